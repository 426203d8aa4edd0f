//! The 3D slice's texture, which the explorer's viewport shows: the same GPU tracer as
//! `qjulia render`, drawing into a texture that egui shows directly (no trip through host
//! memory). A render is cut into tiles of rows, each its own submission of bounded cost, so the
//! UI never waits behind a long dispatch; tiles of a stale render are dropped before
//! submission. While the scene changes it renders at a reduced resolution chosen to keep the
//! frame rate up, then refines to full resolution, and the idle view adds samples to a running
//! mean pass by pass.
//!
//! The schedule's rules (the tile's and the frame's budgets, the preview's scale, the cost
//! learned from the tiles' device time) and the decoding of what a pass reads back are the
//! render module's ([`crate::render::progressive`]).
//!
//! Why it passes 600 lines: it still drives the kernels on that schedule itself (jobs, passes,
//! pipeline builds, readbacks, the running mean, the denoiser's hand-off), which issue 36 item
//! 2 moves into a progressive session in the render module; what stays here is the texture and
//! its wiring.
//!
//! Path mode (`shading.model = "path"`, the shaded view) runs the path tracer
//! ([`GpuPathTracer`]) on the same schedule, tiles and passes: each pass adds one sample to its
//! `accumulated` output, the running mean of the linear radiance, as `qjulia render` does. Its
//! colour is not made on the GPU: the shown bytes must be [`Display`]'s, the f64 host function
//! that makes the PNG's, so that the view and `qjulia render` give the same bytes of the same
//! scene and samples. So the last tile of each pass also copies the accumulator into a buffer
//! the host maps; the view keeps that radiance, encodes it with `Display` (in parallel) and
//! writes the texture. An exposure or tone-map change only encodes the kept radiance again: no
//! trace (the scenes the view compares leave the display transform out). The readback is one
//! pass's (16 bytes a pixel), at most one in flight; the next pass starts once it is collected,
//! which costs a frame per sample and keeps every pass's image, and no more, in memory. The
//! simpler alternative, a GPU display pass, would make f32 bytes that could differ from the
//! PNG's in the last bit of rounding.
//!
//! With a denoiser (`image.denoise`, either model) the idle view's passes also compute the AOVs
//! (the tracers' AOVS override) and the last tile of each pass copies them and the depth back
//! with the mean (phong mode's colour then goes through the host as path mode's does): the view
//! keeps that frame and its noise figure ([`crate::denoise::frame_noise`]), hands it to a
//! thread of its own ([`DenoiseWorker`], the same [`crate::denoise::denoise`] on the same device
//! as `qjulia render`) and shows the denoised running mean once it is back, so that the view
//! and `qjulia render` give the same bytes of the same scene and samples. The passes do not
//! wait for the denoiser: it takes the newest mean whenever it is free. A change of the
//! `[denoise]` keys denoises the kept mean again, without a trace; the switch itself traces
//! again (the AOVs and M2 start at sample 0). The preview (one sample, while things move) is
//! not denoised.
//!
//! With adaptive sampling (`path.noise_target`) the passes are the same kernels', so a done
//! pixel stops as in `qjulia render`; the mean read back (path mode's, or with a denoiser)
//! brings the accumulator, whose fourth float gives the samples each pixel took: the status
//! line's mean, and the denoiser's per-pixel counts.

use std::sync::atomic::{AtomicU32, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::denoise_worker::{DenoiseKey, DenoiseWorker, Request};
use super::frame_spans::span;
use super::kernel_texture::KernelTarget;
use super::pipeline_builder;
use super::precision_switch::{Either, PrecisionSwitch};
use crate::cpu::path::PathParams;
use crate::denoise::Denoiser;
use crate::display::{Display, ToneMap};
use crate::frame::Frame;
use crate::gpu::kernel::Band;
use crate::gpu::path::{GpuPathParams, GpuPathTracer};
use crate::gpu::{GpuContext, GpuKernels, GpuReal, GpuTracer, Kernel, Readback};
use crate::params::TraceParams;
use crate::precision::Precision;
use crate::render::progressive::{
    self, FRAME_SECONDS, IDLE_DELAY, MAX_IN_FLIGHT, MeanLayout, Pace, Quality, TileTimer,
};
use crate::render::{Picture, Planner};
use crate::scene::{Denoise, Scene, View};
use crate::stats::{Summary, SummaryBuilder};

pub use crate::render::progressive::INTERACTIVE_FPS;

/// What the view shows now, for the status line.
#[derive(Clone, Debug, Default)]
pub struct TextureStats {
    /// Size of the image shown, in pixels.
    pub size: [u32; 2],
    /// Its resolution relative to the full view (1 = full).
    pub scale: f64,
    /// Seconds from the first tile's submission to the last tile's completion.
    pub render_seconds: f64,
    /// The shown image's figures, once its depth and steps are read back.
    pub summary: Option<Summary>,
    /// The shown image's steps per pixel, row by row, and its size (for the step views), once
    /// read back.
    pub steps: Option<(Arc<Vec<u32>>, [u32; 2])>,
    /// Counts the images whose steps were read back: a new value means new steps.
    pub steps_generation: u64,
    /// The samples each pixel of the last running mean read back has taken, row by row, and
    /// its size (the samples view), where the mean came back with the accumulator (path mode,
    /// a denoiser, or the samples view itself).
    pub counts: Option<(Arc<Vec<u32>>, [u32; 2])>,
    /// Counts the means whose counts were read back.
    pub counts_generation: u64,
    /// Whether the full-resolution image is shown.
    pub refined: bool,
    /// Seconds from the last change of scene or size to this image.
    pub since_change_seconds: f64,
    /// Samples in the running mean shown (with adaptive sampling: the most a pixel has taken).
    pub samples: u32,
    /// With adaptive sampling (path mode, or with a denoiser): the mean samples a pixel of the
    /// last running mean read back has taken.
    pub samples_taken: Option<f64>,
    /// Path mode: seconds the host took to encode the radiance shown (the display transform).
    pub encode_seconds: f64,
    /// With a denoiser: the estimated noise of the last running mean read back
    /// ([`crate::denoise::frame_noise`]), None below 2 samples.
    pub noise: Option<f64>,
    /// With a denoiser: the samples in the denoised mean shown, its wall seconds and where it
    /// ran, or why it failed.
    pub denoised_samples: Option<u32>,
    pub denoise_seconds: f64,
    pub denoise_backend: &'static str,
    pub denoise_error: Option<String>,
}

/// The kernel a view runs: the tracer (Phong shading, and the step views' depth and steps) or
/// the path tracer (path mode's shaded view).
#[derive(Clone)]
pub enum ViewKernel<F: GpuReal> {
    Phong(Arc<GpuTracer<F>>),
    Path(Arc<GpuPathTracer<F>>),
}

impl<F: GpuReal> ViewKernel<F> {
    fn kernel(&self) -> &Kernel {
        match self {
            ViewKernel::Phong(tracer) => tracer.kernel(),
            ViewKernel::Path(tracer) => tracer.kernel(),
        }
    }

    fn context(&self) -> &GpuContext {
        self.kernel().context()
    }

    fn is_path(&self) -> bool {
        matches!(self, ViewKernel::Path(_))
    }

    /// The pipeline of a job's pipeline request where it is built, else None (nothing is
    /// built).
    fn held(&self, request: &PipelineRequest<F>) -> Option<wgpu::ComputePipeline> {
        let (params, shade, readback) = request;
        match self {
            ViewKernel::Phong(tracer) => {
                tracer.held_pipeline_reading(tracer.variant_for(params, *shade), *readback)
            }
            ViewKernel::Path(tracer) => tracer.held_pipeline_reading(params, *readback),
        }
    }

    /// Builds the pipeline of a request (and holds it), or says why it cannot.
    fn build(&self, request: &PipelineRequest<F>) -> crate::Result<wgpu::ComputePipeline> {
        let (params, shade, readback) = request;
        match self {
            ViewKernel::Phong(tracer) => {
                tracer.pipeline_reading(tracer.variant_for(params, *shade), *readback)
            }
            ViewKernel::Path(tracer) => tracer.pipeline_reading(params, *readback),
        }
    }
}

/// What a job's pipeline is made for: its params (their variant), whether it shades (the
/// tracer's step views do not) and what it reads back.
type PipelineRequest<F> = (TraceParams<F>, bool, Readback);

/// A pipeline being built on the builder's thread ([`pipeline_builder`]): a new variant costs
/// a compile (on lavapipe about half a second, more for the path tracer) that the UI's frame
/// must not wait for. The view shows what it showed until the build is done.
struct PipelineBuild<F: GpuReal> {
    request: PipelineRequest<F>,
    pending: pipeline_builder::Pending<crate::Result<wgpu::ComputePipeline>>,
}

/// A render in progress: which target, what, and how far.
struct Job<F: GpuReal> {
    quality: Quality,
    pipeline: wgpu::ComputePipeline,
    params: TraceParams<F>,
    /// The path tracer's own uniform (binding 6), empty for the tracer.
    path_uniform: Vec<u8>,
    /// The sample this pass adds to the running mean (0: the first image).
    sample: u32,
    /// Whether its passes compute the AOVs and read them back with the mean (the denoised
    /// view).
    aovs: bool,
    /// Whether its pixels sample adaptively: the accumulator comes back with the mean (path
    /// mode's always does) for the samples each pixel took.
    adaptive: bool,
    next_row: u32,
    started: Instant,
    /// Completion times of its tiles, filled in by the queue's callbacks.
    pending: Arc<AtomicU32>,
    last_done: Arc<Mutex<Option<Instant>>>,
}

/// An asynchronous readback of a finished render's depth and steps, for the statistics.
struct StepsReadback {
    /// Depth rows, then steps rows, each `row_stride` pixels apart.
    buffer: wgpu::Buffer,
    size: [u32; 2],
    row_stride: u32,
    mapped: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>>,
}

/// An asynchronous readback of the running mean after a pass: in path mode the accumulator,
/// with a denoiser the AOVs and the depth.
struct RadianceReadback {
    /// What [`copy_mean`] copies, each rows `row_stride` pixels apart: `accumulated` (path mode,
    /// vec4<f32> a pixel), then with `aovs` the AOVs (three vec4<f32>) and the depth (an `F`).
    buffer: wgpu::Buffer,
    layout: MeanLayout,
    quality: Quality,
    size: [u32; 2],
    row_stride: u32,
    /// Samples in its running mean.
    samples: u32,
    /// Whether its pixels sample adaptively (the accumulator's fourth float says which are
    /// done, after how many samples).
    adaptive: bool,
    mapped: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>>,
}

/// The running mean of the image shown (path mode, or with a denoiser), kept to encode again
/// when the display transform changes and to denoise again when the `[denoise]` keys do.
pub struct KeptRadiance {
    /// Path mode: the mean linear radiance, row after row (empty in phong mode).
    pub radiance: Vec<[f32; 3]>,
    /// With a denoiser: the mean with its AOVs and depth, as the denoiser reads it.
    pub frame: Option<Arc<Frame>>,
    /// With a denoiser: its denoised linear image, and the keys it was made with.
    pub denoised: Option<(Denoise, Vec<[f32; 3]>)>,
    pub size: [u32; 2],
    /// Samples in the mean.
    pub samples: u32,
    quality: Quality,
    /// Counts the means read back: the denoiser's results say which they are of.
    generation: u64,
    /// How the texture holds it (None: not written yet).
    encoded: Option<Encoding>,
}

/// How a kept mean is in the texture: through which display transform, denoised with which
/// keys (None: not denoised).
#[derive(Clone, Debug, PartialEq)]
struct Encoding {
    display: Display,
    denoise: Option<Denoise>,
}

/// The scene as the tracers see it: the display transform (`image.exposure`, `image.tone_map`)
/// left out, since only the host's encoding of path mode's radiance uses it.
/// The `[denoise]` table is left out too (the host runs the denoiser); the switch,
/// `image.denoise`, stays: it decides whether the tracers compute the AOVs.
fn traced_scene(scene: &Scene) -> Scene {
    let mut scene = scene.clone();
    scene.image.exposure = 0.0;
    scene.image.tone_map = ToneMap::None;
    scene.denoise = Denoise::default();
    scene
}

/// Whether the view denoises `scene`: a denoiser is on and the view is the shaded picture.
fn denoises(scene: &Scene) -> bool {
    scene.image.denoise != Denoiser::None && scene.image.view == View::Shaded
}

/// How the view is to show a mean of `scene` (`frame`: whether it has the AOVs).
fn encoding_of(scene: &Scene, frame: bool) -> Encoding {
    Encoding {
        display: Display::of(scene),
        denoise: (frame && denoises(scene)).then(|| scene.denoise.clone()),
    }
}

/// The view in one precision: its tracer, targets and render in progress.
pub struct SliceView<F: GpuReal = f32> {
    kernel: ViewKernel<F>,
    renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    uniform: wgpu::Buffer,
    targets: [Option<KernelTarget>; 2],
    job: Option<Job<F>>,
    /// The target shown now.
    shown: Option<Quality>,
    /// The scene (display transform left out: [`traced_scene`]) and full size last asked for,
    /// and when it last changed.
    wanted: Option<(Scene, [u32; 2])>,
    /// The scene, full size and quality of the last render started.
    last_start: Option<(Scene, [u32; 2], Quality)>,
    changed_at: Instant,
    /// The device's estimated cost per pixel, learned frame by frame from `timer`.
    pace: Pace,
    in_flight: Arc<AtomicU32>,
    /// The device's time on the tiles, as a thread of its own sees them finish.
    timer: TileTimer,
    stats: TextureStats,
    readback: Option<StepsReadback>,
    /// Path mode: the display transform asked for, the accumulator's readback in flight and
    /// the radiance shown; with a denoiser, the scene asked for (its display transform and
    /// `[denoise]` keys) and the denoiser's thread.
    display: Display,
    asked: Scene,
    worker: DenoiseWorker,
    generation: u64,
    radiance_readback: Option<RadianceReadback>,
    /// The last readback's buffer, unmapped, for the next.
    spare_readback: Option<wgpu::Buffer>,
    kept: Option<KeptRadiance>,
    /// The pipeline being built, and the last request whose build failed (not asked again).
    build: Option<PipelineBuild<F>>,
    failed_build: Option<PipelineRequest<F>>,
    /// Tiles dispatched, and images encoded on the host (path mode), since the view was made.
    dispatches: u64,
    encodes: u64,
}

impl<F: GpuReal + bytemuck::Pod> SliceView<F> {
    /// The view on `kernel`, drawing through `renderer`, denoising on `kernels`' device.
    pub fn new(
        kernel: ViewKernel<F>,
        renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
        kernels: Arc<GpuKernels>,
    ) -> Self {
        let uniform = kernel.kernel().uniform_buffer("view params");
        let pace = Pace::new(kernel.is_path());
        let timer = TileTimer::new(kernel.context().device.clone());
        Self {
            kernel,
            renderer,
            uniform,
            targets: [None, None],
            job: None,
            shown: None,
            wanted: None,
            last_start: None,
            changed_at: Instant::now(),
            pace,
            in_flight: Arc::new(AtomicU32::new(0)),
            timer,
            stats: TextureStats::default(),
            readback: None,
            display: Display::default(),
            asked: Scene::default(),
            worker: DenoiseWorker::new(kernels),
            generation: 0,
            radiance_readback: None,
            spare_readback: None,
            kept: None,
            build: None,
            failed_build: None,
            dispatches: 0,
            encodes: 0,
        }
    }

    pub fn kernel(&self) -> &ViewKernel<F> {
        &self.kernel
    }

    pub fn stats(&self) -> &TextureStats {
        &self.stats
    }

    /// Whether a pipeline is being built for the scene asked for (the view shows the last
    /// image meanwhile).
    pub fn building_pipeline(&self) -> bool {
        self.build.is_some()
    }

    /// Gives back the memory of a view no longer shown (the other precision, the other
    /// tracer, or the 3D view in 2D mode): its targets (their egui textures freed), its
    /// readbacks and its kept mean. The kernel, its pipelines and the cost learned stay; shown
    /// again, the view renders afresh. Without it each view kept its buffers at the last size
    /// it was shown at, and the explorer's memory rose with every new pairing of a view and a
    /// window size (the soak's working set).
    pub fn release(&mut self) {
        if self.targets.iter().all(Option::is_none)
            && self.spare_readback.is_none()
            && self.kept.is_none()
            && self.radiance_readback.is_none()
        {
            return;
        }
        {
            let mut renderer = self.renderer.write();
            for target in self.targets.iter_mut().filter_map(Option::take) {
                renderer.free_texture(&target.texture_id);
            }
        }
        self.worker.drop_queued();
        self.job = None;
        self.shown = None;
        self.wanted = None;
        self.last_start = None;
        self.readback = None;
        self.radiance_readback = None;
        self.spare_readback = None;
        self.kept = None;
    }

    /// Tiles dispatched since the view was made: a trace, however small, adds to it.
    pub fn dispatches(&self) -> u64 {
        self.dispatches
    }

    /// Path mode: images encoded from radiance on the host since the view was made.
    pub fn encodes(&self) -> u64 {
        self.encodes
    }

    /// Path mode: the radiance of the image shown.
    pub fn kept_radiance(&self) -> Option<&KeptRadiance> {
        self.kept.as_ref()
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let target = self.targets[self.shown? as usize].as_ref()?;
        Some((target.texture_id, [target.width, target.height]))
    }

    /// Whether the view still has work to do (the caller should keep repainting).
    pub fn busy(&self) -> bool {
        let preview_last = self
            .last_start
            .as_ref()
            .is_some_and(|(.., q)| *q == Quality::Preview);
        self.job.is_some()
            || self.build.is_some()
            || self.in_flight.load(Ordering::Acquire) > 0
            || self.readback.is_some()
            || self.radiance_readback.is_some()
            || self.worker.busy()
            || self.kept.as_ref().is_some_and(|k| self.to_encode(k))
            || preview_last
    }

    /// Whether `kept` is still to be written as asked (and can be: phong mode's mean needs the
    /// denoiser).
    fn to_encode(&self, kept: &KeptRadiance) -> bool {
        let wanted = encoding_of(&self.asked, kept.frame.is_some());
        let can = self.kernel.is_path() || wanted.denoise.is_some();
        can && kept.encoded.as_ref() != Some(&wanted)
    }

    /// Whether the shown image is the full-resolution render of exactly this scene and size
    /// (in path mode: in its display transform).
    pub fn is_refined(&self, scene: &Scene, size: [u32; 2]) -> bool {
        let displayed = !(self.kernel.is_path() || denoises(scene))
            || self
                .kept
                .as_ref()
                .is_some_and(|k| k.encoded == Some(encoding_of(scene, k.frame.is_some())));
        let scene = traced_scene(scene);
        displayed
            && self.job.is_none()
            && self.radiance_readback.is_none()
            && self.shown == Some(Quality::Full)
            && self
                .last_start
                .as_ref()
                .is_some_and(|(s, z, q)| *s == scene && *z == size && *q == Quality::Full)
    }

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
    fn start(&mut self, quality: Quality, scene: &Scene, size: [u32; 2], full: [u32; 2]) {
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
        span("target", || self.ensure_target(quality, size, aovs));
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
            pending: Arc::new(AtomicU32::new(0)),
            last_done: Arc::new(Mutex::new(None)),
        });
    }

    /// The pipeline of `request` where it is built, with the request back; else None, and it
    /// is built on the builder's thread, one build of the view's at a time ([`PipelineBuild`]).
    /// A request whose build failed is not built again.
    fn pipeline_for(
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
    fn reap_build(&mut self) {
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
    fn submit_tiles(&mut self, budget: f64) {
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
                    target.copy_rows(&mut encoder, job.next_row, rows);
                    None
                }
                true if last_tile => {
                    let spare = self.spare_readback.take();
                    let items = target.row_stride as u64 * target.height as u64;
                    let outputs = &target.outputs;
                    let copy =
                        progressive::copy_mean(device, &mut encoder, outputs, items, spare, layout);
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
    fn finish_job(&mut self) {
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
            samples_taken: None,
            counts: None,
            denoised_samples: None,
            ..std::mem::take(&mut self.stats)
        };
        self.start_readback(job.quality);
    }

    /// Once the mean of a pass is in host memory (path mode's radiance; with a denoiser the
    /// mean with its AOVs and depth, and its noise figure), keeps it and shows it (with a
    /// denoiser: asks for it to be denoised).
    fn collect_radiance(&mut self) {
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
            let shape = (
                rb.size[0] as usize,
                rb.size[1] as usize,
                rb.row_stride as usize,
            );
            let flags = (rb.adaptive, self.kernel.is_path());
            let mean = progressive::decode_mean::<F>(&view, rb.layout, shape, rb.samples, flags);
            self.stats.samples_taken = mean.samples_taken;
            if !mean.counts.is_empty() {
                self.stats.counts = Some((Arc::new(mean.counts), rb.size));
                self.stats.counts_generation += 1;
            }
            let (radiance, frame) = (mean.radiance, mean.frame);
            drop(view);
            rb.buffer.unmap();
            self.spare_readback = Some(rb.buffer);
            self.stats.noise = frame
                .as_ref()
                .and_then(|f| crate::denoise::frame_noise(f, rb.samples, rb.adaptive));
            self.generation += 1;
            self.kept = Some(KeptRadiance {
                radiance,
                frame,
                denoised: None,
                size: rb.size,
                samples: rb.samples,
                quality: rb.quality,
                generation: self.generation,
                encoded: None,
            });
            self.show_kept();
        }
    }

    /// With a denoiser: takes what the denoiser's thread finished, for the kept mean if it is
    /// of it.
    fn collect_denoised(&mut self) {
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
    fn show_kept(&mut self) {
        let Some(kept) = &mut self.kept else { return };
        let target = self.targets[kept.quality as usize]
            .as_ref()
            .filter(|t| [t.width, t.height] == kept.size);
        let Some(target) = target else {
            self.kept = None;
            return;
        };
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
        target.write_colour(&self.kernel.context().queue, &colour);
        self.stats.denoised_samples = encoding.denoise.is_some().then_some(kept.samples);
        kept.encoded = Some(encoding);
        self.encodes += 1;
        self.shown = Some(kept.quality);
        self.stats.samples = self.stats.samples.max(kept.samples);
    }

    fn start_readback(&mut self, quality: Quality) {
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

    fn collect_readback(&mut self) {
        let Some(rb) = &self.readback else { return };
        let Some(result) = rb.mapped.lock().unwrap().take() else {
            return;
        };
        if result.is_ok()
            && let Ok(view) = rb.buffer.slice(..).get_mapped_range()
        {
            let shape = (
                rb.size[0] as usize,
                rb.size[1] as usize,
                rb.row_stride as usize,
            );
            let (depth, steps) = progressive::decode_steps::<F>(&view, shape);
            let mut summary = SummaryBuilder::new(rb.size[0]);
            summary.add_arrays(&depth, &steps);
            self.stats.summary = Some(summary.finish());
            self.stats.steps = Some((Arc::new(steps), rb.size));
            self.stats.steps_generation += 1;
        }
        self.readback = None;
    }

    /// Makes sure the target for `quality` has this size, re-creating it if not.
    /// (`aovs`: with the AOVs output whole).
    fn ensure_target(&mut self, quality: Quality, size: [u32; 2], aovs: bool) {
        let slot = quality as usize;
        if self.targets[slot]
            .as_ref()
            .is_some_and(|t| [t.width, t.height] == size && t.aovs == aovs)
        {
            return;
        }
        if self.shown == Some(quality) {
            self.shown = None;
        }
        if self.kept.as_ref().is_some_and(|k| k.quality == quality) {
            self.kept = None;
        }
        let old = self.targets[slot].take();
        self.targets[slot] = Some(KernelTarget::new(
            self.kernel.kernel(),
            &self.renderer,
            ("view", &self.uniform),
            (size, aovs),
            old.map(|t| t.texture_id),
        ));
    }
}

/// A view in f32 and, by itself, f64.
type Views = PrecisionSwitch<SliceView<f32>, SliceView<f64>>;

/// Calls `$body` with `$view` bound to the shown view of `$views`, in its precision.
macro_rules! on_shown {
    ($views:expr, $view:ident => $body:expr) => {
        match $views.shown() {
            Either::F32($view) => $body,
            Either::F64($view) => $body,
        }
    };
}

/// The explorer's 3D view, in f32 or (deep) f64 by itself ([`PrecisionSwitch`]): the tracer's
/// (Phong, and the step views), or in path mode the path tracer's.
pub struct SliceTexture {
    /// The device's kernels, shared with the explorer's exports.
    kernels: Arc<GpuKernels>,
    /// Decides the views' precision ([`Planner::for_view`]).
    planner: Planner,
    views: Views,
    /// The path tracer's views, built at the first path-traced view; Err: it cannot run here,
    /// and why (the tracer's view stands in).
    path_views: Option<Result<Views, String>>,
    /// Whether the path tracer's view is the one shown.
    path_shown: bool,
}

impl SliceTexture {
    /// The view on the f32 tracer of `kernels` (built now: a shader the device rejects is an
    /// error); the f64 one is taken from them at the first deep view, the path tracer's at the
    /// first path-traced view.
    pub fn new(
        kernels: Arc<GpuKernels>,
        renderer: Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>,
    ) -> crate::Result<Self> {
        let view = SliceView::new(
            ViewKernel::Phong(kernels.tracer()?),
            renderer,
            kernels.clone(),
        );
        Ok(Self {
            planner: Planner::for_view(kernels.clone()),
            kernels,
            views: PrecisionSwitch::new(view),
            path_views: None,
            path_shown: false,
        })
    }

    /// Renders `scene` at `size` in the precision it needs, with the path tracer where it is
    /// path traced (`shading.model = "path"`, the shaded view), as [`SliceView::update`].
    pub fn update(&mut self, scene: &Scene, size: [u32; 2], interacting: bool) {
        let kernels = &self.kernels;
        let picture = Picture::Slice {
            shade: scene.image.view.needs_shading(),
        };
        self.path_shown = false;
        if picture.path_traced(scene) {
            let renderer = self.views.f32_view().renderer.clone();
            let slot = self.path_views.get_or_insert_with(|| {
                let tracer = kernels.path().map_err(|e| e.to_string())?;
                let view = SliceView::new(ViewKernel::Path(tracer), renderer, kernels.clone());
                Ok(PrecisionSwitch::new(view))
            });
            if let Ok(views) = slot {
                self.path_shown = true;
                let build = |view: &SliceView<f32>| {
                    let path64 = ViewKernel::Path(kernels.path_in::<f64>()?);
                    Ok(SliceView::new(
                        path64,
                        view.renderer.clone(),
                        kernels.clone(),
                    ))
                };
                match views.pick(&self.planner, scene, Picture::SHADED, build) {
                    Either::F32(view) => view.update(scene, size, interacting),
                    Either::F64(view) => view.update(scene, size, interacting),
                }
                self.release_hidden();
                return;
            }
        }
        let build = |view: &SliceView<f32>| {
            let tracer64 = ViewKernel::Phong(kernels.tracer_in::<f64>()?);
            Ok(SliceView::new(
                tracer64,
                view.renderer.clone(),
                kernels.clone(),
            ))
        };
        match self
            .views
            .pick(&self.planner, scene, Picture::SHADED, build)
        {
            Either::F32(view) => view.update(scene, size, interacting),
            Either::F64(view) => view.update(scene, size, interacting),
        }
        self.release_hidden();
    }

    /// Gives back the memory of every view but the one shown ([`SliceView::release`]).
    fn release_hidden(&mut self) {
        let path = self.path_shown;
        self.views
            .release_hidden(path, SliceView::release, SliceView::release);
        if let Some(Ok(views)) = &mut self.path_views {
            views.release_hidden(!path, SliceView::release, SliceView::release);
        }
    }

    /// Gives back the memory of every view (2D mode shows none of them).
    pub fn release(&mut self) {
        self.views
            .release_hidden(true, SliceView::release, SliceView::release);
        if let Some(Ok(views)) = &mut self.path_views {
            views.release_hidden(true, SliceView::release, SliceView::release);
        }
    }

    /// The views shown: the path tracer's or the tracer's.
    fn shown(&self) -> &Views {
        match (&self.path_views, self.path_shown) {
            (Some(Ok(views)), true) => views,
            _ => &self.views,
        }
    }

    /// Whether the view shown is path traced.
    pub fn path_traced(&self) -> bool {
        self.path_shown
    }

    /// Why path mode cannot run here, if it was asked for and cannot.
    pub fn path_unavailable(&self) -> Option<&str> {
        self.path_views.as_ref()?.as_ref().err().map(String::as_str)
    }

    /// The precision of the view shown.
    pub fn precision(&self) -> Precision {
        self.shown().precision()
    }

    /// Why the view runs in its precision (the status line's hover text).
    pub fn precision_note(&self) -> &str {
        self.shown().reason()
    }

    pub fn stats(&self) -> &TextureStats {
        on_shown!(self.shown(), view => view.stats())
    }

    /// Whether the view shown waits for its pipeline to be built.
    pub fn building_pipeline(&self) -> bool {
        on_shown!(self.shown(), view => view.building_pipeline())
    }

    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        on_shown!(self.shown(), view => view.texture())
    }

    pub fn busy(&self) -> bool {
        on_shown!(self.shown(), view => view.busy())
    }

    pub fn is_refined(&self, scene: &Scene, size: [u32; 2]) -> bool {
        on_shown!(self.shown(), view => view.is_refined(scene, size))
    }

    /// Tiles dispatched by every view since they were made (a trace of any of them adds to it).
    pub fn dispatches(&self) -> u64 {
        let mut all = vec![&self.views];
        all.extend(self.path_views.as_ref().and_then(|v| v.as_ref().ok()));
        all.iter()
            .map(|v| {
                on_both(
                    v,
                    |d, e| d + e,
                    SliceView::dispatches,
                    SliceView::dispatches,
                )
            })
            .sum()
    }

    /// Path mode: images the shown view encoded on the host from radiance.
    pub fn encodes(&self) -> u64 {
        on_shown!(self.shown(), view => view.encodes())
    }

    /// Path mode: the radiance of the image shown, its size and its samples.
    pub fn kept_radiance(&self) -> Option<&KeptRadiance> {
        on_shown!(self.shown(), view => view.kept_radiance())
    }
}

/// `f32(view)` and, where the f64 view was built, `f64(view)`, joined by `join`.
fn on_both<R: Default>(
    views: &Views,
    join: impl Fn(R, R) -> R,
    f32: impl Fn(&SliceView<f32>) -> R,
    f64: impl Fn(&SliceView<f64>) -> R,
) -> R {
    let deep = views.f64_view().map_or_else(R::default, f64);
    join(f32(views.f32_view()), deep)
}
