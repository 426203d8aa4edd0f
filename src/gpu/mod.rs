//! The GPU path: adapter and device choice, and the kernels on the one runner ([`kernel`]).
//! What an image kernel reads back and how its bands become frames is `image.rs`; the float
//! types the kernels run in are `real.rs`'s [`GpuReal`], whose impls are here: they name each
//! kernel's spec, and each kernel is generic over the trait.

pub mod bsdf_probe;
pub mod compose;
mod context;
pub mod denoise;
pub mod f64check;
mod image;
mod julia2d;
pub mod kernel;
mod kernels;
mod params;
pub mod params_json;
pub mod path;
pub mod pipeline_cache;
mod real;
mod sampler;
pub mod scene_kernel;
pub mod shaders;
mod sobol_probe;
mod tracer;
pub mod variant;

pub use context::F64Support;
pub use context::{
    GpuContext, adapter_label, available_adapters, choose_adapter, device_descriptor,
    give_a_runtime_dir, select_adapter,
};
pub use f64check::check_f64;
pub use image::{
    ACCUMULATED_OUTPUT, AOVS_OUTPUT, DEPTH_OUTPUT, IMAGE_OUTPUTS, IMAGE64_OUTPUTS, Readback,
    TRACE_OUTPUTS, TRACE64_OUTPUTS,
};
pub use julia2d::{GpuJulia2d, JULIA2D_KERNEL, JULIA2D64_KERNEL};
pub use kernel::{Kernel, KernelSpec, OutputSpec, SecondUniform, WORKGROUP_SIZE};
pub use kernels::GpuKernels;
pub use params::{GpuJulia2dParams, GpuJulia2dParams64, GpuParams, GpuParams64};
pub use real::GpuReal;
pub use sampler::{GpuSampleGrid, GpuSampler, SAMPLE_KERNEL};
pub use sobol_probe::{SOBOL_PROBE_KERNEL, sobol_probe};
pub use tracer::{GpuRender, GpuTracer, TRACE_KERNEL, TRACE64_KERNEL};
pub use variant::Variant;

use crate::error::Result;

// Each precision's kernels and uniforms (real.rs makes the uniforms of either alike).

impl GpuReal for f32 {
    const TRACE_KERNEL: KernelSpec = TRACE_KERNEL;
    const JULIA2D_KERNEL: KernelSpec = JULIA2D_KERNEL;
    const PATH_KERNEL: KernelSpec = path::PATH_KERNEL;
    type TraceUniform = GpuParams;
    type Julia2dUniform = GpuJulia2dParams;
    fn device_constants(_: &GpuContext) -> Result<Vec<(&'static str, f64)>> {
        Ok(Vec::new())
    }
}

impl GpuReal for f64 {
    const TRACE_KERNEL: KernelSpec = TRACE64_KERNEL;
    const JULIA2D_KERNEL: KernelSpec = JULIA2D64_KERNEL;
    const PATH_KERNEL: KernelSpec = path::PATH64_KERNEL;
    type TraceUniform = GpuParams64;
    type Julia2dUniform = GpuJulia2dParams64;
    fn device_constants(ctx: &GpuContext) -> Result<Vec<(&'static str, f64)>> {
        Ok(ctx.f64_support()?.constants.clone())
    }
}
