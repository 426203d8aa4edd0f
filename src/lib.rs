//! qjulia: ray tracing quaternion Julia sets after Keenan Crane (2005), on the GPU with wgpu
//! compute and on the CPU with a pure-Rust twin of the shader that the GPU is held to.
//!
//! The flow: a [`Scene`] (plain data) becomes [`TraceParams`]; the [`gpu`] or [`cpu`] tracer
//! turns those into a [`Frame`]; [`output`] writes it.

pub mod algebra;
pub mod compare;
pub mod cpu;
pub mod error;
pub mod explore;
pub mod frame;
pub mod gpu;
pub mod output;
pub mod params;
pub mod report;
pub mod scene;
pub mod views;

pub use error::{Error, Result};
pub use frame::{Frame, RenderStats};
pub use params::{Julia2dParams, TraceParams};
pub use scene::Scene;

use algebra::Real;
use gpu::{GpuContext, GpuJulia2d, GpuTracer};

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
}

/// Why f64 is refused on the GPU (CONTRACT.md: only where results are right).
pub const GPU_F64_UNSUPPORTED: &str = "--precision f64 is not available on the GPU: WGSL's f64 \
    has no trustworthy log/sqrt on common drivers (lavapipe returns wrong values without an error); \
    use --backend cpu";

/// What the user should know before a render in this precision: settings the floats cannot
/// resolve (and what is done about it), each with the remedy.
pub fn precision_warnings(scene: &Scene, precision: Precision) -> Vec<String> {
    let (relative, escape_limit, name) = match precision {
        Precision::F32 => (f32::RELATIVE_EPSILON, f32::ESCAPE_LIMIT, "f32"),
        Precision::F64 => (f64::RELATIVE_EPSILON, f64::ESCAPE_LIMIT, "f64"),
    };
    let remedy = match precision {
        Precision::F32 => "use --precision f64 (on the CPU)",
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

/// Renders a validated scene. `shade` false asks for depth and steps only (the GPU then runs a
/// pipeline without the shading code; the colour is the background). `notice` hears what the
/// user should know (which backend was used and why).
pub fn render(
    scene: &Scene,
    backend: Backend,
    precision: Precision,
    shade: bool,
    notice: &mut dyn FnMut(&str),
) -> Result<(Frame, RenderStats)> {
    let mut frame = Frame {
        width: scene.image.width,
        height: 0,
        colour: Vec::new(),
        depth: Vec::new(),
        steps: Vec::new(),
        non_finite: 0,
    };
    let stats = render_streaming(scene, backend, precision, shade, notice, &mut |band| {
        frame.append(band);
        Ok(())
    })?;
    Ok((frame, stats))
}

/// As [`render`], handing the image to `sink` in bands of whole rows, top to bottom, as they
/// are done: any image size renders in bounded memory.
pub fn render_streaming(
    scene: &Scene,
    backend: Backend,
    precision: Precision,
    shade: bool,
    notice: &mut dyn FnMut(&str),
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    match (backend, precision) {
        (Backend::Cpu, _) => render_cpu_streaming(scene, precision, sink),
        (Backend::Gpu, Precision::F64) => Err(Error::Unsupported(GPU_F64_UNSUPPORTED.into())),
        (Backend::Gpu, Precision::F32) => {
            render_gpu_streaming(&GpuTracer::new(GpuContext::new()?)?, scene, shade, sink)
        }
        (Backend::Auto, Precision::F64) => {
            notice("f64 is not available on the GPU; rendering on the CPU");
            render_cpu_streaming(scene, precision, sink)
        }
        (Backend::Auto, Precision::F32) => match GpuContext::new().and_then(GpuTracer::new) {
            Ok(tracer) => {
                notice(&format!(
                    "rendering on the GPU: {}",
                    tracer.context().adapter_label()
                ));
                render_gpu_streaming(&tracer, scene, shade, sink)
            }
            Err(e) => {
                notice(&format!("{e}; rendering on the CPU"));
                render_cpu_streaming(scene, precision, sink)
            }
        },
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

/// Rows per CPU band.
fn cpu_band_rows(width: u32) -> u32 {
    (band_pixels() / width.max(1) as u64).clamp(1, u32::MAX as u64) as u32
}

/// Renders an image of `width` x `height` on the CPU band by band with `render_rows`, handing
/// each band to `sink`; returns the seconds spent rendering (the sink's time left out).
fn cpu_bands(
    (width, height): (u32, u32),
    render_rows: &dyn Fn(std::ops::Range<u32>) -> Frame,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
    summary: &mut SummaryBuilder,
) -> Result<f64> {
    let mut seconds = 0.0;
    let mut row = 0;
    while row < height {
        let rows = cpu_band_rows(width).min(height - row);
        let start = std::time::Instant::now();
        let band = render_rows(row..row + rows);
        seconds += start.elapsed().as_secs_f64();
        summary.add(&band);
        sink(&band)?;
        row += rows;
    }
    Ok(seconds)
}

fn render_cpu_streaming(
    scene: &Scene,
    precision: Precision,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    fn run<F: Real>(
        p: &TraceParams<F>,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
        summary: &mut SummaryBuilder,
    ) -> Result<f64> {
        cpu_bands(
            (p.width, p.height),
            &|rows| cpu::render_rows(p, rows),
            sink,
            summary,
        )
    }
    let mut summary = SummaryBuilder::new(scene.image.width);
    let seconds = match precision {
        Precision::F32 => run(&TraceParams::<f32>::new(scene), sink, &mut summary)?,
        Precision::F64 => run(&TraceParams::<f64>::new(scene), sink, &mut summary)?,
    };
    Ok(make_stats(
        scene,
        &summary,
        "cpu",
        "cpu".into(),
        precision,
        seconds,
        None,
    ))
}

fn render_gpu_streaming(
    tracer: &GpuTracer,
    scene: &Scene,
    shade: bool,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    let mut summary = SummaryBuilder::new(scene.image.width);
    let (seconds, gpu_seconds) =
        tracer.render_bands(&TraceParams::<f32>::new(scene), shade, &mut |band| {
            summary.add(&band);
            sink(&band)
        })?;
    let label = tracer.context().adapter_label();
    Ok(make_stats(
        scene,
        &summary,
        "gpu",
        label,
        Precision::F32,
        seconds,
        gpu_seconds,
    ))
}

/// Renders on a GPU tracer (f32); `shade` false computes depth and steps only.
pub fn render_gpu(tracer: &GpuTracer, scene: &Scene, shade: bool) -> Result<(Frame, RenderStats)> {
    let out = tracer.render_outputs(&TraceParams::<f32>::new(scene), shade)?;
    let label = tracer.context().adapter_label();
    let mut summary = SummaryBuilder::new(scene.image.width);
    summary.add(&out.frame);
    let stats = make_stats(
        scene,
        &summary,
        "gpu",
        label,
        Precision::F32,
        out.render_seconds,
        out.gpu_seconds,
    );
    Ok((out.frame, stats))
}

/// The 2D Julia view of a validated scene (`qjulia render2d`), handed to `sink` in bands of
/// whole rows, top to bottom: colour the grey, depth 0 in the set and NaN outside it, steps the
/// iterations made. Backends and precisions as for [`render_streaming`]; the stats count points
/// in the set as hits and iterations as steps.
pub fn render2d_streaming(
    scene: &Scene,
    backend: Backend,
    precision: Precision,
    notice: &mut dyn FnMut(&str),
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    match (backend, precision) {
        (Backend::Cpu, _) => render2d_cpu(scene, precision, sink),
        (Backend::Gpu, Precision::F64) => Err(Error::Unsupported(GPU_F64_UNSUPPORTED.into())),
        (Backend::Gpu, Precision::F32) => {
            render2d_gpu(&GpuJulia2d::new(GpuContext::new()?)?, scene, sink)
        }
        (Backend::Auto, Precision::F64) => {
            notice("f64 is not available on the GPU; rendering on the CPU");
            render2d_cpu(scene, precision, sink)
        }
        (Backend::Auto, Precision::F32) => match GpuContext::new().and_then(GpuJulia2d::new) {
            Ok(julia) => {
                notice(&format!(
                    "rendering on the GPU: {}",
                    gpu::adapter_label(&julia.context().info)
                ));
                render2d_gpu(&julia, scene, sink)
            }
            Err(e) => {
                notice(&format!("{e}; rendering on the CPU"));
                render2d_cpu(scene, precision, sink)
            }
        },
    }
}

fn render2d_cpu(
    scene: &Scene,
    precision: Precision,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    fn run<F: Real>(
        p: &Julia2dParams<F>,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
        summary: &mut SummaryBuilder,
    ) -> Result<f64> {
        let rows = |rows| cpu::julia2d::render_rows(p, rows);
        cpu_bands((p.width, p.height), &rows, sink, summary)
    }
    let mut summary = SummaryBuilder::new(scene.image.width);
    let seconds = match precision {
        Precision::F32 => run(&Julia2dParams::<f32>::new(scene), sink, &mut summary)?,
        Precision::F64 => run(&Julia2dParams::<f64>::new(scene), sink, &mut summary)?,
    };
    Ok(make_stats(
        scene,
        &summary,
        "cpu",
        "cpu".into(),
        precision,
        seconds,
        None,
    ))
}

fn render2d_gpu(
    julia: &GpuJulia2d,
    scene: &Scene,
    sink: &mut dyn FnMut(&Frame) -> Result<()>,
) -> Result<RenderStats> {
    let mut summary = SummaryBuilder::new(scene.image.width);
    let seconds = julia.render_bands(&Julia2dParams::<f32>::new(scene), &mut |band| {
        summary.add(&band);
        sink(&band)
    })?;
    let label = gpu::adapter_label(&julia.context().info);
    Ok(make_stats(
        scene,
        &summary,
        "gpu",
        label,
        Precision::F32,
        seconds,
        None,
    ))
}

/// The 2D Julia view on a given GPU pipeline, in host memory (the explorer's export).
pub fn render2d_gpu_frame(julia: &GpuJulia2d, scene: &Scene) -> Result<(Frame, RenderStats)> {
    let mut frame = Frame {
        width: scene.image.width,
        height: 0,
        colour: Vec::new(),
        depth: Vec::new(),
        steps: Vec::new(),
        non_finite: 0,
    };
    let stats = render2d_gpu(julia, scene, &mut |band| {
        frame.append(band);
        Ok(())
    })?;
    Ok((frame, stats))
}

/// The 2D Julia view in host memory; see [`render2d_streaming`].
pub fn render2d(
    scene: &Scene,
    backend: Backend,
    precision: Precision,
    notice: &mut dyn FnMut(&str),
) -> Result<(Frame, RenderStats)> {
    let mut frame = Frame {
        width: scene.image.width,
        height: 0,
        colour: Vec::new(),
        depth: Vec::new(),
        steps: Vec::new(),
        non_finite: 0,
    };
    let stats = render2d_streaming(scene, backend, precision, notice, &mut |band| {
        frame.append(band);
        Ok(())
    })?;
    Ok((frame, stats))
}

/// Hit, step and divergence figures accumulated over bands.
struct SummaryBuilder {
    pixels: u64,
    hits: u64,
    steps: u64,
    steps_max: u32,
    tiles: views::TileWork,
}

impl SummaryBuilder {
    fn new(width: u32) -> Self {
        Self {
            pixels: 0,
            hits: 0,
            steps: 0,
            steps_max: 0,
            tiles: views::TileWork::new(width, views::TILE),
        }
    }

    fn add(&mut self, band: &Frame) {
        self.tiles.add_rows(&band.steps);
        self.pixels += band.pixel_count() as u64;
        self.hits += band.depth.iter().filter(|d| !d.is_nan()).count() as u64;
        self.steps += band.steps.iter().map(|&s| s as u64).sum::<u64>();
        self.steps_max = self
            .steps_max
            .max(band.steps.iter().copied().max().unwrap_or(0));
    }
}

fn make_stats(
    scene: &Scene,
    summary: &SummaryBuilder,
    backend: &str,
    adapter: String,
    precision: Precision,
    render_seconds: f64,
    gpu_seconds: Option<f64>,
) -> RenderStats {
    let n = summary.pixels.max(1) as f64;
    let tiles = summary.tiles.clone().finish();
    RenderStats {
        backend: backend.into(),
        adapter,
        precision: precision.name().into(),
        width: scene.image.width,
        height: scene.image.height,
        render_seconds,
        gpu_seconds,
        hit_fraction: summary.hits as f64 / n,
        steps_mean: summary.steps as f64 / n,
        steps_max: summary.steps_max,
        tile_efficiency: tiles.efficiency,
        wasted_steps_mean: tiles.wasted_steps_mean,
    }
}
