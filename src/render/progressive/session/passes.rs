//! A session's passes: what each UI frame asks for and moves on (`update`), a render started
//! at a quality once its pipeline is built (on the builder's thread), its tiles submitted within
//! the frame's budget, and a finished pass shown, its cost learned and the next pass begun.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::super::pipeline_builder;
use super::super::readback::{self, MeanLayout};
use super::super::spans::span;
use super::super::{FRAME_SECONDS, IDLE_DELAY, MAX_IN_FLIGHT, Quality};
use super::{
    Canvas, Job, PipelineBuild, PipelineRequest, RadianceReadback, Session, TextureStats,
    ViewKernel, denoises, traced_scene,
};
use crate::cpu::path::PathParams;
use crate::display::Display;
use crate::gpu::GpuReal;
use crate::gpu::Readback;
use crate::gpu::kernel::Band;
use crate::gpu::path::GpuPathParams;
use crate::params::TraceParams;
use crate::scene::{Scene, View};

impl<F: GpuReal + bytemuck::Pod, C: Canvas> Session<F, C> {
    /// Asks for `scene` at `size` pixels (the view's full resolution) and moves rendering on:
    /// call once per UI frame. `interacting` says the user is dragging or animating.
    pub fn update(&mut self, scene: &Scene, size: [u32; 2], interacting: bool) {
        let size = [size[0].clamp(1, 8192), size[1].clamp(1, 8192)];
        span("poll", || {
            self.kernel.context().device.poll(wgpu::PollType::Poll).ok()
        });
        self.pace.learn(self.timer.take());
        self.reap_build();
        self.asked = scene.clone();
        self.display = Display::of(scene);
        span("collect mean", || self.collect_radiance());
        span("collect denoised", || self.collect_denoised());
        span("finish job", || self.finish_job());
        span("collect steps", || self.collect_readback());
        // Path mode: a new display transform encodes the radiance shown again, at once; with a
        // denoiser, new keys denoise the mean shown again (and it is shown once denoised).
        if self.kept.as_ref().is_some_and(|k| self.to_encode(k)) {
            span("show mean", || self.show_kept());
        }
        let scene = &traced_scene(scene);

        let wanted = (scene.clone(), size);
        if self.wanted.as_ref() != Some(&wanted) {
            self.wanted = Some(wanted);
            self.changed_at = Instant::now();
            // Tiles of a stale render not yet submitted are dropped; a fully submitted one is
            // let finish, so that a continuous drag still shows a new image every frame. A
            // preview always finishes: on a device so slow that even the smallest preview
            // takes more than a frame's budget, a scene that changes every frame (Play) would
            // otherwise never show one.
            self.worker.drop_queued();
            if let Some(job) = self.job.as_ref().filter(|j| j.quality == Quality::Full) {
                let rows = self.targets[job.quality as usize]
                    .as_ref()
                    .map_or(0, |t| t.height);
                if job.next_row < rows {
                    self.job = None;
                }
            }
        }

        if self.job.is_none() {
            let current = self
                .last_start
                .as_ref()
                .is_some_and(|(s, z, _)| s == scene && *z == size);
            let preview_shown = self
                .last_start
                .as_ref()
                .is_some_and(|(.., q)| *q == Quality::Preview);
            let idle = !interacting && self.changed_at.elapsed() >= IDLE_DELAY;
            if !current && !self.pace.interactive(size) && !idle {
                let preview = self.pace.preview_size(size);
                self.start(Quality::Preview, scene, preview, size);
            } else if !current || (preview_shown && idle) {
                self.start(Quality::Full, scene, size, size);
            }
        }
        span("submit", || self.submit_tiles(FRAME_SECONDS));
    }

    /// Starts a render of `scene` at `size` (the view's full size `full`) once its pipeline is
    /// built; until then the view shows what it showed, and the next frame asks again.
    pub(super) fn start(
        &mut self,
        quality: Quality,
        scene: &Scene,
        size: [u32; 2],
        full: [u32; 2],
    ) {
        let asked = scene;
        let mut scene = scene.clone();
        scene.image.width = size[0];
        scene.image.height = size[1];
        if quality == Quality::Preview {
            // A preview is one sample; the full image adds its samples pass by pass.
            scene.image.samples = 1;
        }
        // The idle view's passes make the AOVs where a denoiser is on.
        let aovs = quality == Quality::Full && denoises(&scene);
        let readback = match aovs {
            true => Readback::Hdr,
            false => Readback::All,
        };
        let params = TraceParams::<F>::new(&scene);
        // The step views show the steps alone: no shading needed.
        let shade = scene.image.view.needs_shading();
        let Some((pipeline, (params, ..))) = self.pipeline_for((params, shade, readback)) else {
            return;
        };
        self.last_start = Some((asked.clone(), full, quality));
        if !self.kernel.is_path() && !aovs {
            // Phong mode's mean goes straight to the texture: nothing kept to show.
            self.kept = None;
        }
        let input = scene.loaded.environment.clone();
        span("target", || self.ensure_target(quality, size, aovs, input));
        let path_uniform = match &self.kernel {
            ViewKernel::Phong(_) => Vec::new(),
            ViewKernel::Path(_) => {
                let path = GpuPathParams::new(&PathParams::<F>::new(&scene));
                bytemuck::bytes_of(&path).to_vec()
            }
        };
        let adaptive = params.adaptive();
        self.job = Some(Job {
            quality,
            pipeline,
            params,
            path_uniform,
            sample: 0,
            aovs,
            adaptive,
            next_row: 0,
            started: Instant::now(),
            began: Instant::now(),
            pending: Arc::new(AtomicU32::new(0)),
            last_done: Arc::new(Mutex::new(None)),
        });
    }

    /// The pipeline of `request` where it is built, with the request back; else None, and it
    /// is built on the builder's thread, one build of the view's at a time ([`PipelineBuild`]).
    /// A request whose build failed is not built again.
    pub(super) fn pipeline_for(
        &mut self,
        request: PipelineRequest<F>,
    ) -> Option<(wgpu::ComputePipeline, PipelineRequest<F>)> {
        if let Some(pipeline) = span("pipeline", || self.kernel.held(&request)) {
            return Some((pipeline, request));
        }
        if self.build.is_some() || self.failed_build.as_ref() == Some(&request) {
            return None;
        }
        let kernel = self.kernel.clone();
        let asked = request.clone();
        let pending = pipeline_builder::build(move || kernel.build(&asked));
        self.build = Some(PipelineBuild { request, pending });
        None
    }

    /// Ends a finished pipeline build: its pipeline is held by the kernel; a failure is kept,
    /// so that its request is not built again, and said on stderr once.
    pub(super) fn reap_build(&mut self) {
        if !self.build.as_ref().is_some_and(|b| b.pending.is_finished()) {
            return;
        }
        let PipelineBuild { request, pending } = self.build.take().expect("checked above");
        let failure = match pending.take() {
            Some(Ok(Ok(_))) => return,
            Some(Ok(Err(e))) => e.to_string(),
            _ => "the build panicked".to_string(),
        };
        eprintln!("qjulia explore: the view's pipeline was not built: {failure}");
        self.failed_build = Some(request);
    }

    /// Submits tiles of the current job: at most `budget` seconds of GPU work by the cost
    /// learned, and at least one tile.
    pub(super) fn submit_tiles(&mut self, budget: f64) {
        let Some(job) = &mut self.job else { return };
        let Some(target) = self.targets[job.quality as usize].as_ref() else {
            return;
        };
        let kernel = self.kernel.kernel();
        let (device, queue) = (&kernel.context().device, &kernel.context().queue);
        let width = target.width;
        let row_seconds = self.pace.seconds(width as f64);
        let tile_rows = self.pace.tile_rows(width);
        let mut budget = budget;
        let mut first = true;
        while job.next_row < target.height && self.in_flight.load(Ordering::Acquire) < MAX_IN_FLIGHT
        {
            let rows = tile_rows.min(target.height - job.next_row);
            if !first && rows as f64 * row_seconds > budget {
                break;
            }
            first = false;
            let band = Band {
                row: job.next_row,
                rows,
                dispatch: 0,
            };
            let mut uniform = F::view_uniform(
                &job.params,
                band,
                target.row_stride,
                (job.sample, job.sample + 1),
            );
            if !job.path_uniform.is_empty() {
                uniform = kernel.pack_uniforms(&uniform, &job.path_uniform);
            }
            queue.write_buffer(&self.uniform, 0, &uniform);
            let mut encoder = device.create_command_encoder(&Default::default());
            kernel.encode(
                &mut encoder,
                &job.pipeline,
                &target.bind_group,
                (width, rows),
                None,
            );
            let last_tile = job.next_row + rows == target.height;
            // The tracer's colour goes straight into the texture; the path tracer's radiance,
            // and with a denoiser the mean and its AOVs, come back to the host after the pass's
            // last tile.
            // The samples view reads the accumulator back for its counts (the heat map stands
            // in the texture's place, so phong mode's colour need not reach the texture).
            let counts = self.asked.image.view == View::Samples;
            let path = self.kernel.is_path();
            let depth = size_of::<F>() as u64;
            let layout = MeanLayout::of(path, job.aovs, job.adaptive, counts, depth);
            let radiance = match layout.reads() {
                false => {
                    let colour = &target.outputs[0];
                    let (stride, row) = (target.row_stride, job.next_row);
                    let rows_at = (row, rows);
                    self.canvas
                        .copy_rows(job.quality, &mut encoder, (colour, stride), rows_at);
                    None
                }
                true if last_tile => {
                    let spare = self.spare_readback.take();
                    let items = target.row_stride as u64 * target.height as u64;
                    let outputs = &target.outputs;
                    let copy =
                        readback::copy_mean(device, &mut encoder, outputs, items, spare, layout);
                    Some(copy)
                }
                true => None,
            };
            self.in_flight.fetch_add(1, Ordering::AcqRel);
            job.pending.fetch_add(1, Ordering::AcqRel);
            let submitted = Instant::now();
            let index = queue.submit([encoder.finish()]);
            self.timer
                .time(index, submitted, rows as u64 * width as u64);
            self.dispatches += 1;
            if let Some(buffer) = radiance {
                let mapped = Arc::new(Mutex::new(None));
                let slot = mapped.clone();
                buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
                    *slot.lock().unwrap() = Some(r)
                });
                self.radiance_readback = Some(RadianceReadback {
                    buffer,
                    layout,
                    quality: job.quality,
                    size: [target.width, target.height],
                    row_stride: target.row_stride,
                    samples: job.sample + 1,
                    adaptive: job.adaptive,
                    began: job.began,
                    mapped,
                });
            }
            let (in_flight, pending, last_done) = (
                self.in_flight.clone(),
                job.pending.clone(),
                job.last_done.clone(),
            );
            queue.on_submitted_work_done(move || {
                *last_done.lock().unwrap() = Some(Instant::now());
                pending.fetch_sub(1, Ordering::AcqRel);
                in_flight.fetch_sub(1, Ordering::AcqRel);
            });
            job.next_row += rows;
            budget -= rows as f64 * row_seconds;
        }
    }

    /// Once every tile of the job has run (in path mode: and its radiance is shown): show its
    /// image, learn its cost, read its steps.
    pub(super) fn finish_job(&mut self) {
        let Some(job) = &self.job else { return };
        let Some(target) = self.targets[job.quality as usize].as_ref() else {
            return;
        };
        if job.next_row < target.height
            || job.pending.load(Ordering::Acquire) > 0
            || self.radiance_readback.is_some()
        {
            return;
        }
        let job = self.job.take().expect("checked above");
        let done = job.last_done.lock().unwrap().unwrap_or_else(Instant::now);
        let seconds = done.duration_since(job.started).as_secs_f64();
        // A denoised pass is shown once the denoiser has it (show_kept).
        if !job.aovs {
            self.shown = Some(job.quality);
            self.shown_began = Some(job.began);
        }
        self.stats.samples = job.sample + 1;
        // More samples for the same scene: the next pass adds one to the running mean.
        let current = match (&self.wanted, &self.last_start) {
            (Some((scene, size)), Some((started, full, _))) => scene == started && size == full,
            _ => false,
        };
        if job.quality == Quality::Full && job.sample + 1 < job.params.samples && current {
            self.job = Some(Job {
                sample: job.sample + 1,
                next_row: 0,
                started: Instant::now(),
                pending: Arc::new(AtomicU32::new(0)),
                last_done: Arc::new(Mutex::new(None)),
                ..job
            });
        }
        if job.sample > 0 {
            return;
        }
        let full = self.wanted.as_ref().map_or([1, 1], |(_, s)| *s);
        self.stats = TextureStats {
            size: [target.width, target.height],
            scale: target.width as f64 / full[0].max(1) as f64,
            render_seconds: seconds,
            summary: None,
            steps: None,
            steps_generation: self.stats.steps_generation,
            refined: job.quality == Quality::Full,
            since_change_seconds: done.duration_since(self.changed_at).as_secs_f64(),
            samples: 1,
            // Said again once this scene's mean is read back and denoised.
            noise: None,
            denoised_noise: None,
            samples_taken: None,
            counts: None,
            denoised_samples: None,
            ..std::mem::take(&mut self.stats)
        };
        self.start_readback(job.quality);
    }
}
