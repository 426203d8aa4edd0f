//! What a session collects once the device is done: a pass's running mean read back (kept,
//! shown through the display transform, handed to the denoiser's thread), the denoised image,
//! and the depth and steps of a finished render for the status line's figures.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::super::Quality;
use super::super::denoise_worker::{DenoiseKey, Request};
use super::super::readback;
use super::{Canvas, KeptRadiance, Session, StepsReadback, encoding_of};
use crate::gpu::GpuReal;
use crate::stats::SummaryBuilder;

impl<F: GpuReal + bytemuck::Pod, C: Canvas> Session<F, C> {
    /// Once the mean of a pass is in host memory (path mode's radiance; with a denoiser the
    /// mean with its AOVs and depth, and its noise figure), keeps it and shows it (with a
    /// denoiser: asks for it to be denoised).
    pub(super) fn collect_radiance(&mut self) {
        let Some(rb) = &self.radiance_readback else {
            return;
        };
        let Some(result) = rb.mapped.lock().unwrap().take() else {
            return;
        };
        let rb = self.radiance_readback.take().expect("checked above");
        if result.is_ok()
            && let Ok(view) = rb.buffer.slice(..).get_mapped_range()
        {
            let shape = readback::shape(rb.size, rb.row_stride);
            let flags = (rb.adaptive, self.kernel.is_path());
            let mean = readback::decode_mean::<F>(&view, rb.layout, shape, rb.samples, flags);
            self.stats.samples_taken = mean.samples_taken;
            if !mean.counts.is_empty() {
                self.stats.counts = Some((Arc::new(mean.counts), rb.size));
                self.stats.counts_generation += 1;
            }
            let (radiance, frame) = (mean.radiance, mean.frame);
            drop(view);
            rb.buffer.unmap();
            self.spare_readback = Some(rb.buffer);
            self.stats.noise = mean.estimate.map(|e| e.relative);
            self.generation += 1;
            self.kept = Some(KeptRadiance {
                radiance,
                frame,
                denoised: None,
                size: rb.size,
                samples: rb.samples,
                quality: rb.quality,
                began: rb.began,
                generation: self.generation,
                encoded: None,
            });
            self.show_kept();
        }
    }

    /// With a denoiser: takes what the denoiser's thread finished, for the kept mean if it is
    /// of it.
    pub(super) fn collect_denoised(&mut self) {
        while let Some(done) = self.worker.poll() {
            let Some(kept) = self
                .kept
                .as_mut()
                .filter(|k| k.generation == done.key.generation)
            else {
                continue;
            };
            let linear = match done.linear {
                Ok(linear) => {
                    self.stats.denoise_error = None;
                    self.stats.denoised_noise = done.estimate;
                    self.stats.denoise_seconds = done.seconds;
                    self.stats.denoise_backend = done.backend;
                    linear
                }
                Err(e) => {
                    // Shown as the mean itself, and the error said in the status line.
                    self.stats.denoise_error = Some(e);
                    kept.frame
                        .as_ref()
                        .map_or_else(Vec::new, |f| f.linear().to_vec())
                }
            };
            kept.denoised = Some((done.key.params, linear));
        }
    }

    /// The kept mean into its target's texture (dropped if that target has since changed
    /// size), and shown: path mode's radiance through the display transform; with a denoiser
    /// its denoised image (path mode: through the display transform; phong mode: packed as the
    /// tracer packs its mean), or, until the denoiser has it, a request for it.
    pub(super) fn show_kept(&mut self) {
        let Some(kept) = &mut self.kept else { return };
        let sized = self.targets[kept.quality as usize]
            .as_ref()
            .is_some_and(|t| [t.width, t.height] == kept.size);
        if !sized {
            self.kept = None;
            return;
        }
        let path = self.kernel.is_path();
        let encoding = encoding_of(&self.asked, kept.frame.is_some());
        let start = Instant::now();
        let colour = match (&encoding.denoise, &kept.frame) {
            (Some(params), Some(frame)) => match &kept.denoised {
                Some((made, linear)) if made == params => match path {
                    true => self.display.pack_all(linear),
                    false => crate::denoise::pack_phong(linear),
                },
                _ => {
                    let mut scene = self.asked.clone();
                    scene.image.samples = kept.samples;
                    self.worker.request(Request {
                        key: DenoiseKey {
                            generation: kept.generation,
                            params: params.clone(),
                        },
                        frame: frame.clone(),
                        scene,
                    });
                    return;
                }
            },
            _ if path => self.display.pack_all(&kept.radiance),
            // Phong mode's mean without the denoiser is the tracer's own, in the texture.
            _ => return,
        };
        self.stats.encode_seconds = start.elapsed().as_secs_f64();
        let queue = &self.kernel.context().queue;
        self.canvas.write(kept.quality, queue, &colour, kept.size);
        self.stats.denoised_samples = encoding.denoise.is_some().then_some(kept.samples);
        kept.encoded = Some(encoding);
        self.encodes += 1;
        self.shown = Some(kept.quality);
        self.shown_began = Some(kept.began);
        self.stats.samples = self.stats.samples.max(kept.samples);
    }

    pub(super) fn start_readback(&mut self, quality: Quality) {
        let Some(target) = self.targets[quality as usize].as_ref() else {
            return;
        };
        let device = &self.kernel.context().device;
        let items = target.row_stride as u64 * target.height as u64;
        // Depth in the tracer's precision, then the steps (u32).
        let depth_bytes = items * size_of::<F>() as u64;
        let buffer = device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("depth and steps readback"),
            size: depth_bytes + items * 4,
            usage: wgpu::BufferUsages::MAP_READ | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let mut encoder = device.create_command_encoder(&Default::default());
        encoder.copy_buffer_to_buffer(&target.outputs[1], 0, &buffer, 0, depth_bytes);
        encoder.copy_buffer_to_buffer(&target.outputs[2], 0, &buffer, depth_bytes, items * 4);
        self.kernel.context().queue.submit([encoder.finish()]);
        let mapped = Arc::new(Mutex::new(None));
        let slot = mapped.clone();
        buffer.slice(..).map_async(wgpu::MapMode::Read, move |r| {
            *slot.lock().unwrap() = Some(r)
        });
        self.readback = Some(StepsReadback {
            buffer,
            size: [target.width, target.height],
            row_stride: target.row_stride,
            mapped,
        });
    }

    pub(super) fn collect_readback(&mut self) {
        let Some(rb) = &self.readback else { return };
        let Some(result) = rb.mapped.lock().unwrap().take() else {
            return;
        };
        if result.is_ok()
            && let Ok(view) = rb.buffer.slice(..).get_mapped_range()
        {
            let shape = readback::shape(rb.size, rb.row_stride);
            let (depth, steps) = readback::decode_steps::<F>(&view, shape);
            let mut summary = SummaryBuilder::new(rb.size[0]);
            summary.add_arrays(&depth, &steps);
            self.stats.summary = Some(summary.finish());
            self.stats.steps = Some((Arc::new(steps), rb.size));
            self.stats.steps_generation += 1;
        }
        self.readback = None;
    }
}
