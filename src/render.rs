//! One render path. [`Renderer::choose`] makes the backend x precision decision, the one place
//! it is made; [`Renderer::render`] then renders any [`Picture`] of a scene on that tracer, in
//! bands of whole rows handed to a sink, and returns its [`RenderStats`]. `render`, `render2d`,
//! the reports, the stability suite, the bench and the explorer's export all go through it.

use std::sync::{Arc, Mutex};

use crate::algebra::Real;
use crate::cpu;
use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::gpu::{GpuContext, GpuJulia2d, GpuSampler, GpuTracer};
use crate::params::{Julia2dParams, TraceParams};
use crate::scene::Scene;
use crate::stats::{RenderStats, SummaryBuilder};

/// Which tracer renders.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Backend {
    /// The GPU when wgpu finds an adapter that can do what is asked, else the CPU.
    Auto,
    Gpu,
    Cpu,
}

/// The float type the tracer runs in.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Precision {
    F32,
    F64,
}

impl Precision {
    pub fn name(self) -> &'static str {
        match self {
            Precision::F32 => "f32",
            Precision::F64 => "f64",
        }
    }

    /// The relative spacing of its values that the precision warnings hold settings to
    /// ([`Real::RELATIVE_EPSILON`]: 8 ulps).
    pub fn relative_spacing(self) -> f64 {
        match self {
            Precision::F32 => f32::RELATIVE_EPSILON,
            Precision::F64 => f64::RELATIVE_EPSILON,
        }
    }
}

/// What is rendered of a scene.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Picture {
    /// The 3D slice (`qjulia render`). `shade` false asks for depth and steps only: the GPU then
    /// runs a pipeline without the shading code, and the colour is the background.
    Slice { shade: bool },
    /// The 2D Julia set of c[0] + c[1] i (`qjulia render2d`): colour the grey, depth 0 in the
    /// set and NaN outside it, steps the iterations made. Its stats count points in the set as
    /// hits and iterations as steps.
    Julia2d,
    /// No picture: the levels of `qjulia mesh`'s grid ([`crate::mesh`]), which
    /// [`Renderer::sampler`] samples; [`Renderer::render`] refuses it.
    Mesh,
}

impl Picture {
    /// The shaded 3D slice.
    pub const SHADED: Picture = Picture::Slice { shade: true };
}

/// Which outputs of a render come back to the host.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Readback {
    /// Colour, depth and steps, and the stats' [`Summary`](crate::stats::Summary) of them.
    All,
    /// The colour only (a picture that is only written as an image: an animation's frames):
    /// the bands' depth and steps are empty and the stats' summary is left at zero. The GPU
    /// reads back a quarter of the bytes.
    Colour,
}

/// Why f64 is refused on a GPU (CONTRACT.md: only where the adapter has SHADER_F64 and the
/// start-up check passes); the check's reason follows it.
pub const GPU_F64_UNSUPPORTED: &str = "--precision f64 is not available on the GPU";

/// The GPU kernels of one device, each built on first use.
pub struct GpuKernels {
    ctx: GpuContext,
    tracer: Mutex<Option<Arc<GpuTracer>>>,
    julia2d: Mutex<Option<Arc<GpuJulia2d>>>,
    tracer64: Mutex<Option<Arc<GpuTracer<f64>>>>,
    julia2d64: Mutex<Option<Arc<GpuJulia2d<f64>>>>,
    sampler: Mutex<Option<Arc<GpuSampler>>>,
}

impl GpuKernels {
    /// No kernel built yet.
    pub fn new(ctx: GpuContext) -> Self {
        Self {
            ctx,
            tracer: Mutex::new(None),
            julia2d: Mutex::new(None),
            tracer64: Mutex::new(None),
            julia2d64: Mutex::new(None),
            sampler: Mutex::new(None),
        }
    }

    /// Kernels already built (the explorer's, the report's); the others are built on use.
    pub fn with(tracer: Option<Arc<GpuTracer>>, julia2d: Option<Arc<GpuJulia2d>>) -> Self {
        let ctx = match (&tracer, &julia2d) {
            (Some(t), _) => t.context().clone(),
            (None, Some(j)) => j.context().clone(),
            (None, None) => panic!("GpuKernels::with needs a kernel"),
        };
        Self {
            ctx,
            tracer: Mutex::new(tracer),
            julia2d: Mutex::new(julia2d),
            tracer64: Mutex::new(None),
            julia2d64: Mutex::new(None),
            sampler: Mutex::new(None),
        }
    }

    pub fn context(&self) -> &GpuContext {
        &self.ctx
    }

    pub fn tracer(&self) -> Result<Arc<GpuTracer>> {
        built(&self.tracer, || GpuTracer::new(self.ctx.clone()))
    }

    pub fn julia2d(&self) -> Result<Arc<GpuJulia2d>> {
        built(&self.julia2d, || GpuJulia2d::new(self.ctx.clone()))
    }

    pub fn sampler(&self) -> Result<Arc<GpuSampler>> {
        built(&self.sampler, || GpuSampler::new(self.ctx.clone()))
    }

    /// The f64 tracer, where the device passes the start-up check of f64.
    pub fn tracer64(&self) -> Result<Arc<GpuTracer<f64>>> {
        built(&self.tracer64, || GpuTracer::new_f64(self.ctx.clone()))
    }

    /// The f64 2D view, where the device passes the start-up check of f64.
    pub fn julia2d64(&self) -> Result<Arc<GpuJulia2d<f64>>> {
        built(&self.julia2d64, || GpuJulia2d::new_f64(self.ctx.clone()))
    }

    /// Whether f64 runs on this device: SHADER_F64 and the start-up check
    /// ([`GpuContext::f64_support`], run once per device).
    pub fn has_f64(&self) -> bool {
        self.ctx.f64_support().is_ok()
    }

    /// Builds the kernel a picture needs in `precision` (so that a shader the device rejects,
    /// or f64 failing its check, shows up now).
    fn prepare(&self, picture: Picture, precision: Precision) -> Result<()> {
        match (picture, precision) {
            (Picture::Slice { .. }, Precision::F32) => self.tracer().map(drop),
            (Picture::Julia2d, Precision::F32) => self.julia2d().map(drop),
            (Picture::Slice { .. }, Precision::F64) => self.tracer64().map(drop),
            (Picture::Julia2d, Precision::F64) => self.julia2d64().map(drop),
            (Picture::Mesh, Precision::F32) => self.sampler().map(drop),
            (Picture::Mesh, Precision::F64) => Err(Error::Unsupported(
                "the mesh sampler runs in f32 on the GPU".into(),
            )),
        }
    }
}

fn built<T>(slot: &Mutex<Option<Arc<T>>>, make: impl FnOnce() -> Result<T>) -> Result<Arc<T>> {
    let mut slot = slot.lock().expect("kernel slot");
    if let Some(k) = slot.as_ref() {
        return Ok(k.clone());
    }
    let k = Arc::new(make()?);
    *slot = Some(k.clone());
    Ok(k)
}

/// Where renders run: the GPU or the CPU, in a precision (f64 on the GPU only where the device
/// passed the start-up check).
#[derive(Clone)]
pub struct Renderer {
    gpu: Option<Arc<GpuKernels>>,
    precision: Precision,
}

impl Renderer {
    /// The one backend x precision decision. `picture` says which kernel to build (a shader the
    /// device rejects sends `Auto` to the CPU); `notice` hears what the user should know: which
    /// backend was chosen and why.
    pub fn choose(
        backend: Backend,
        precision: Precision,
        picture: Picture,
        notice: &mut dyn FnMut(&str),
    ) -> Result<Self> {
        // f64 on the GPU needs the device to pass the start-up check of f64 (prepare runs it).
        let on_gpu = || -> Result<Self> {
            let kernels = GpuKernels::new(GpuContext::new()?);
            kernels
                .prepare(picture, precision)
                .map_err(|e| match precision {
                    Precision::F64 => Error::Unsupported(format!("{GPU_F64_UNSUPPORTED}: {e}")),
                    Precision::F32 => e,
                })?;
            Ok(Self::gpu_in(Arc::new(kernels), precision))
        };
        match backend {
            Backend::Cpu => Ok(Self::cpu(precision)),
            Backend::Gpu => on_gpu(),
            Backend::Auto => match on_gpu() {
                Ok(renderer) => {
                    let f64_note = match precision {
                        Precision::F64 => " in f64",
                        Precision::F32 => "",
                    };
                    notice(&format!(
                        "rendering on the GPU{f64_note}: {}",
                        renderer.adapter()
                    ));
                    Ok(renderer)
                }
                Err(e) => {
                    notice(&format!("{e}; rendering on the CPU"));
                    Ok(Self::cpu(precision))
                }
            },
        }
    }

    /// The CPU tracer in `precision`.
    pub fn cpu(precision: Precision) -> Self {
        Self {
            gpu: None,
            precision,
        }
    }

    /// The GPU kernels of a device (f32).
    pub fn gpu(kernels: Arc<GpuKernels>) -> Self {
        Self::gpu_in(kernels, Precision::F32)
    }

    /// The GPU kernels of a device in `precision` (f64: renders fail where the device does not
    /// pass the start-up check; see [`Self::gpu_has_f64`]).
    pub fn gpu_in(kernels: Arc<GpuKernels>, precision: Precision) -> Self {
        Self {
            gpu: Some(kernels),
            precision,
        }
    }

    /// Whether this renderer's GPU runs f64 (SHADER_F64 and the start-up check of f64, run
    /// once per device on the first call); false on the CPU. For `--precision auto`: a GPU
    /// renderer in f32 can ask before it switches a scene to f64 ([`Self::with_precision`]).
    pub fn gpu_has_f64(&self) -> bool {
        self.gpu.as_ref().is_some_and(|k| k.has_f64())
    }

    /// The same backend (and device) in another precision.
    pub fn with_precision(&self, precision: Precision) -> Self {
        Self {
            gpu: self.gpu.clone(),
            precision,
        }
    }

    /// A GPU tracer already built (f32).
    pub fn on_tracer(tracer: Arc<GpuTracer>) -> Self {
        Self::gpu(Arc::new(GpuKernels::with(Some(tracer), None)))
    }

    pub fn precision(&self) -> Precision {
        self.precision
    }

    /// "gpu" or "cpu".
    pub fn backend_name(&self) -> &'static str {
        if self.gpu.is_some() { "gpu" } else { "cpu" }
    }

    /// The adapter, "name / Backend", or "cpu".
    pub fn adapter(&self) -> String {
        match &self.gpu {
            Some(k) => k.context().adapter_label(),
            None => "cpu".into(),
        }
    }

    /// The GPU's voxel sampler (built on first use), or None on the CPU.
    pub fn sampler(&self) -> Option<Result<Arc<GpuSampler>>> {
        self.gpu.as_ref().map(|k| k.sampler())
    }

    /// Renders a validated scene, handing the image to `sink` in bands of whole rows, top to
    /// bottom, as they are done: any image size renders in bounded memory.
    pub fn render(
        &self,
        scene: &Scene,
        picture: Picture,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        self.render_with(scene, picture, Readback::All, sink)
    }

    /// As [`Self::render`], reading back only `readback`'s outputs.
    pub fn render_with(
        &self,
        scene: &Scene,
        picture: Picture,
        readback: Readback,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        if picture == Picture::Mesh {
            return Err(Error::Unsupported(
                "a mesh is not rendered: qjulia::mesh::make_mesh makes it".into(),
            ));
        }
        let mut summary = SummaryBuilder::new(scene.image.width);
        let mut counted = |band: &Frame| {
            if readback == Readback::All {
                summary.add(band);
            }
            sink(band)
        };
        let (render_seconds, gpu_seconds) = match &self.gpu {
            Some(kernels) => {
                let mut owned = |band: Frame| counted(&band);
                let times = match (picture, self.precision) {
                    (Picture::Slice { shade }, Precision::F32) => kernels.tracer()?.render_bands(
                        &TraceParams::<f32>::new(scene),
                        shade,
                        readback,
                        &mut owned,
                    )?,
                    (Picture::Slice { shade }, Precision::F64) => {
                        kernels.tracer64()?.render_bands(
                            &TraceParams::<f64>::new(scene),
                            shade,
                            readback,
                            &mut owned,
                        )?
                    }
                    (Picture::Julia2d, Precision::F32) => kernels.julia2d()?.render_bands(
                        &Julia2dParams::<f32>::new(scene),
                        readback,
                        &mut owned,
                    )?,
                    (Picture::Julia2d, Precision::F64) => kernels.julia2d64()?.render_bands(
                        &Julia2dParams::<f64>::new(scene),
                        readback,
                        &mut owned,
                    )?,
                    (Picture::Mesh, _) => unreachable!("refused above"),
                };
                (times.seconds, times.gpu_seconds)
            }
            None => {
                let seconds = match self.precision {
                    Precision::F32 => render_cpu::<f32>(scene, picture, &mut counted)?,
                    Precision::F64 => render_cpu::<f64>(scene, picture, &mut counted)?,
                };
                (seconds, None)
            }
        };
        Ok(RenderStats {
            backend: self.backend_name().into(),
            adapter: self.adapter(),
            precision: self.precision.name().into(),
            precision_reason: format!("asked for (--precision {})", self.precision.name()),
            width: scene.image.width,
            height: scene.image.height,
            render_seconds,
            gpu_seconds,
            summary: summary.finish(),
        })
    }

    /// Renders a picture of each of `scenes` (validated, of one size) one after another and
    /// hands each whole to `sink` with its stats, in order. On the GPU the frames stream: the
    /// device renders the next while the host reads back and hands out this one
    /// ([`crate::gpu::Kernel::run_stream`]); a frame's `render_seconds` then runs from its
    /// submission to its decoding, and may overlap the one before.
    pub fn render_frames(
        &self,
        scenes: &mut dyn Iterator<Item = Scene>,
        picture: Picture,
        readback: Readback,
        sink: &mut dyn FnMut(Frame, RenderStats) -> Result<()>,
    ) -> Result<()> {
        let (Some(kernels), Picture::Slice { shade }) = (&self.gpu, picture) else {
            for scene in scenes {
                let mut frame = Frame::empty(scene.image.width);
                let stats = self.render_with(&scene, picture, readback, &mut |band| {
                    frame.append(band);
                    Ok(())
                })?;
                sink(frame, stats)?;
            }
            return Ok(());
        };
        let mut sink = |frame: Frame, times: crate::gpu::kernel::RunTimes| {
            let summary = match readback {
                Readback::All => crate::stats::Summary::of(&frame),
                Readback::Colour => SummaryBuilder::new(frame.width).finish(),
            };
            let stats = RenderStats {
                backend: self.backend_name().into(),
                adapter: self.adapter(),
                precision: self.precision.name().into(),
                precision_reason: format!("asked for (--precision {})", self.precision.name()),
                width: frame.width,
                height: frame.height,
                render_seconds: times.seconds,
                gpu_seconds: times.gpu_seconds,
                summary,
            };
            sink(frame, stats)
        };
        match self.precision {
            Precision::F32 => {
                let mut params = scenes.map(|scene| (TraceParams::<f32>::new(&scene), shade));
                kernels
                    .tracer()?
                    .render_frames(&mut params, readback, &mut sink)
            }
            Precision::F64 => {
                let mut params = scenes.map(|scene| (TraceParams::<f64>::new(&scene), shade));
                kernels
                    .tracer64()?
                    .render_frames(&mut params, readback, &mut sink)
            }
        }
    }

    /// As [`Self::render`], the whole image in host memory.
    pub fn render_frame(&self, scene: &Scene, picture: Picture) -> Result<(Frame, RenderStats)> {
        let mut frame = Frame::empty(scene.image.width);
        let stats = self.render(scene, picture, &mut |band| {
            frame.append(band);
            Ok(())
        })?;
        Ok((frame, stats))
    }
}

/// A picture on the CPU in `F`, band by band; returns the seconds spent rendering (the sink's
/// time left out).
fn render_cpu<F: Real>(
    scene: &Scene,
    picture: Picture,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<f64> {
    match picture {
        Picture::Slice { .. } => {
            let p = TraceParams::<F>::new(scene);
            cpu_bands(
                (p.width, p.height),
                &|rows| cpu::render_rows(&p, rows),
                sink,
            )
        }
        Picture::Julia2d => {
            let p = Julia2dParams::<F>::new(scene);
            let rows = |rows| cpu::julia2d::render_rows(&p, rows);
            cpu_bands((p.width, p.height), &rows, sink)
        }
        Picture::Mesh => unreachable!("Renderer::render_with refuses a mesh"),
    }
}

/// Pixels per band of a streamed render: 4 Mpixel (16 MiB per output array), or
/// `QJULIA_BAND_PIXELS` (at least 64) to trade memory for dispatch count.
pub fn band_pixels() -> u64 {
    std::env::var("QJULIA_BAND_PIXELS")
        .ok()
        .and_then(|v| v.parse::<u64>().ok())
        .map_or(1 << 22, |n| n.max(64))
}

/// Renders an image of `width` x `height` on the CPU band by band with `render_rows`, handing
/// each band to `sink`; returns the seconds spent rendering (the sink's time left out).
fn cpu_bands(
    (width, height): (u32, u32),
    render_rows: &dyn Fn(std::ops::Range<u32>) -> Frame,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<f64> {
    let band_rows = (band_pixels() / width.max(1) as u64).clamp(1, u32::MAX as u64) as u32;
    let mut seconds = 0.0;
    let mut row = 0;
    while row < height {
        let rows = band_rows.min(height - row);
        let start = std::time::Instant::now();
        let band = render_rows(row..row + rows);
        seconds += start.elapsed().as_secs_f64();
        sink(&band)?;
        row += rows;
    }
    Ok(seconds)
}

/// What the user should know before a render in this precision: settings the floats cannot
/// resolve (and what is done about it), each with the remedy.
pub fn precision_warnings(scene: &Scene, precision: Precision) -> Vec<String> {
    let (relative, escape_limit, name) = match precision {
        Precision::F32 => (f32::RELATIVE_EPSILON, f32::ESCAPE_LIMIT, "f32"),
        Precision::F64 => (f64::RELATIVE_EPSILON, f64::ESCAPE_LIMIT, "f64"),
    };
    let remedy = match precision {
        Precision::F32 => "use --precision f64 (or auto)",
        Precision::F64 => "this is beyond f64 too",
    };
    let f = &scene.fractal;
    let eye = glam::DVec3::from_array(scene.camera.eye);
    let target = glam::DVec3::from_array(scene.camera.target);
    // The largest coordinate the rays work with, and the float spacing there.
    let reach = eye.length().max(f.bounding_radius_squared.sqrt()).max(1.0);
    let spacing = reach * relative;
    let mut warnings = Vec::new();
    if f.epsilon < spacing {
        warnings.push(format!(
            "fractal.epsilon = {:e} is below the spacing of {name} values at distance {reach:.3} ({spacing:.1e}): hits are taken there instead; {remedy}",
            f.epsilon
        ));
    }
    let footprint =
        2.0 * (target - eye).length() * (scene.camera.fov_y_degrees.to_radians() * 0.5).tan()
            / scene.image.height as f64;
    if footprint < spacing {
        warnings.push(format!(
            "a pixel spans {footprint:.1e} at the target, below the spacing of {name} values ({spacing:.1e}): neighbouring pixels trace the same points; {remedy}"
        ));
    }
    if f.escape_radius_squared > escape_limit {
        warnings.push(format!(
            "fractal.escape_radius_squared = {:e} would overflow {name} iterations: {escape_limit:e} is used; {remedy}",
            f.escape_radius_squared
        ));
    }
    warnings
}
