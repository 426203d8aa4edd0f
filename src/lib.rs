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

pub use error::{Error, Result};
pub use frame::{Frame, RenderStats};
pub use params::TraceParams;
pub use scene::Scene;

use algebra::Real;
use gpu::{GpuContext, GpuTracer};

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
    match (backend, precision) {
        (Backend::Cpu, _) => Ok(render_cpu(scene, precision)),
        (Backend::Gpu, Precision::F64) => Err(Error::Unsupported(GPU_F64_UNSUPPORTED.into())),
        (Backend::Gpu, Precision::F32) => {
            render_gpu(&GpuTracer::new(GpuContext::new()?)?, scene, shade)
        }
        (Backend::Auto, Precision::F64) => {
            notice("f64 is not available on the GPU; rendering on the CPU");
            Ok(render_cpu(scene, precision))
        }
        (Backend::Auto, Precision::F32) => match GpuContext::new().and_then(GpuTracer::new) {
            Ok(tracer) => {
                notice(&format!(
                    "rendering on the GPU: {}",
                    tracer.context().adapter_label()
                ));
                render_gpu(&tracer, scene, shade)
            }
            Err(e) => {
                notice(&format!("{e}; rendering on the CPU"));
                Ok(render_cpu(scene, precision))
            }
        },
    }
}

/// Renders on the CPU reference tracer.
pub fn render_cpu(scene: &Scene, precision: Precision) -> (Frame, RenderStats) {
    let (frame, seconds) = match precision {
        Precision::F32 => cpu::render(&TraceParams::<f32>::new(scene)),
        Precision::F64 => cpu::render(&TraceParams::<f64>::new(scene)),
    };
    let stats = make_stats(&frame, "cpu", "cpu".into(), precision, seconds, None);
    (frame, stats)
}

/// Renders on a GPU tracer (f32); `shade` false computes depth and steps only.
pub fn render_gpu(tracer: &GpuTracer, scene: &Scene, shade: bool) -> Result<(Frame, RenderStats)> {
    let out = tracer.render_outputs(&TraceParams::<f32>::new(scene), shade)?;
    let label = tracer.context().adapter_label();
    let stats = make_stats(
        &out.frame,
        "gpu",
        label,
        Precision::F32,
        out.render_seconds,
        out.gpu_seconds,
    );
    Ok((out.frame, stats))
}

fn make_stats(
    frame: &Frame,
    backend: &str,
    adapter: String,
    precision: Precision,
    render_seconds: f64,
    gpu_seconds: Option<f64>,
) -> RenderStats {
    let summary = frame.summary();
    RenderStats {
        backend: backend.into(),
        adapter,
        precision: precision.name().into(),
        width: frame.width,
        height: frame.height,
        render_seconds,
        gpu_seconds,
        hit_fraction: summary.hit_fraction,
        steps_mean: summary.steps_mean,
        steps_max: summary.steps_max,
    }
}
