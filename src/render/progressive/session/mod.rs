//! A progressive session: the live view's render of one kernel in one precision, the same GPU
//! tracer as `qjulia render`, drawing into the caller's [`Canvas`] (for the explorer, textures
//! that egui shows directly, with no trip through host memory). A render is cut into tiles of rows, each its own submission of bounded cost, so the
//! UI never waits behind a long dispatch; tiles of a stale render are dropped before
//! submission. While the scene changes it renders at a reduced resolution chosen to keep the
//! frame rate up, then refines to full resolution, and the idle view adds samples to a running
//! mean pass by pass.
//!
//! The schedule's rules are [`super`]'s ([`Pace`]: the tile's and the frame's budgets, the
//! preview's scale, the cost learned from the tiles' device time), and the decoding of what a
//! pass reads back [`super::readback`]'s.
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
//! keeps that frame, hands it to a
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

mod collect;
mod passes;

use super::canvas::{Canvas, Target};
use super::denoise_worker::DenoiseWorker;
use super::pipeline_builder;
use super::readback::MeanLayout;
use super::{Pace, Quality, TileTimer};
use crate::denoise::Denoiser;
use crate::display::{Display, ToneMap};
use crate::frame::Frame;
use crate::gpu::kernel::input_source;
use crate::gpu::path::GpuPathTracer;
use crate::gpu::{GpuContext, GpuKernels, GpuReal, GpuTracer, Kernel, Readback};
use crate::params::TraceParams;
use crate::scene::{Denoise, Scene, View};
use crate::stats::Summary;

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
    /// Path mode: the estimated relative RMSE of the last running mean read back
    /// ([`crate::estimate::raw`], `--stats`' `estimated_relative_rmse`), None below 2 samples.
    pub noise: Option<f64>,
    /// With a denoiser in path mode: that of the denoised image shown
    /// ([`crate::estimate::denoised`]).
    pub denoised_noise: Option<f64>,
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
    /// When this pass started, and when the render's first pass did (the scene it shows was
    /// asked for before then).
    started: Instant,
    began: Instant,
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
    /// When its render began.
    began: Instant,
    mapped: Arc<Mutex<Option<Result<(), wgpu::BufferAsyncError>>>>,
}

/// The running mean of the image shown (path mode, or with a denoiser), kept to encode again
/// when the display transform changes and to denoise again when the `[denoise]` keys do.
#[derive(Clone)]
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
    /// When its render began.
    began: Instant,
    /// Counts the means read back: the denoiser's results say which they are of.
    generation: u64,
    /// How the texture holds it (None: not written yet).
    encoded: Option<Encoding>,
}

impl KeptRadiance {
    /// Whether `other` is this mean as it was: the same read back, denoised and shown alike.
    pub fn same_as(&self, other: &KeptRadiance) -> bool {
        let keys = |k: &KeptRadiance| k.denoised.as_ref().map(|(d, _)| d.clone());
        self.generation == other.generation
            && self.quality == other.quality
            && self.encoded == other.encoded
            && keys(self) == keys(other)
    }
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
pub struct Session<F: GpuReal, C: Canvas> {
    kernel: ViewKernel<F>,
    /// Where its images are shown: a texture per quality, the caller's.
    canvas: C,
    uniform: wgpu::Buffer,
    targets: [Option<Target>; 2],
    job: Option<Job<F>>,
    /// The target shown now, and when its render began.
    shown: Option<Quality>,
    shown_began: Option<Instant>,
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

impl<F: GpuReal + bytemuck::Pod, C: Canvas> Session<F, C> {
    /// The session on `kernel`, showing its images on `canvas`, denoising on `kernels`' device.
    pub fn new(kernel: ViewKernel<F>, canvas: C, kernels: Arc<GpuKernels>) -> Self {
        let uniform = kernel.kernel().uniform_buffer("view params");
        let pace = Pace::new(kernel.is_path());
        let timer = TileTimer::new(kernel.context().device.clone());
        Self {
            kernel,
            canvas,
            uniform,
            targets: [None, None],
            job: None,
            shown: None,
            shown_began: None,
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
        self.targets = [None, None];
        self.canvas.release();
        self.worker.drop_queued();
        self.job = None;
        self.shown = None;
        self.shown_began = None;
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

    /// The image shown, once there is one: its quality (which of the canvas's textures) and
    /// its size in pixels.
    pub fn shown(&self) -> Option<(Quality, [u32; 2])> {
        let quality = self.shown?;
        let target = self.targets[quality as usize].as_ref()?;
        Some((quality, [target.width, target.height]))
    }

    /// When the render of the image shown began: a scene asked for before then is in it (the
    /// explorer's input latency, `QJULIA_EXPLORE_LOG=frames`).
    pub fn shown_began(&self) -> Option<Instant> {
        self.shown.and(self.shown_began)
    }

    /// The canvas the session shows its images on.
    pub fn canvas(&self) -> &C {
        &self.canvas
    }

    pub fn canvas_mut(&mut self) -> &mut C {
        &mut self.canvas
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

    /// Makes sure the target for `quality` has this size, re-creating it if not.
    /// (`aovs`: with the AOVs output whole).
    fn ensure_target(
        &mut self,
        quality: Quality,
        size: [u32; 2],
        aovs: bool,
        input: crate::gpu::kernel::InputData,
    ) {
        let slot = quality as usize;
        let same_input = |t: &Target| input_source(&t.input) == input_source(&input);
        if self.targets[slot]
            .as_ref()
            .is_some_and(|t| [t.width, t.height] == size && t.aovs == aovs && same_input(t))
        {
            return;
        }
        if self.shown == Some(quality) {
            self.shown = None;
        }
        if self.kept.as_ref().is_some_and(|k| k.quality == quality) {
            self.kept = None;
        }
        self.targets[slot] = Some(Target::new(
            self.kernel.kernel(),
            &self.uniform,
            size,
            aovs,
            input,
        ));
        self.canvas.resize(quality, size);
    }
}
