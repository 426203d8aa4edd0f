//! The float types the GPU kernels run in ([`GpuReal`]): each precision's kernels and
//! uniforms. The trait is here, apart from its impls for f32 and f64 (in gpu/mod.rs), because
//! each kernel is generic over it while the impls name each kernel's spec.

use super::GpuContext;
use super::kernel::{Band, KernelSpec};
use super::params::{BandUniform, SampledUniform};
use crate::algebra::Real;
use crate::error::Result;
use crate::params::{Julia2dParams, TraceParams};

/// The float types the GPU kernels run in: f32 on every adapter, f64 where the adapter passes
/// the start-up check ([`GpuContext::f64_support`]). Each has its own modules of the same WGSL
/// (src/gpu/shaders.rs) and its own uniform layouts; the uniforms are made alike, from the
/// layouts' types ([`Self::TraceUniform`], [`Self::Julia2dUniform`]).
pub trait GpuReal: Real {
    /// The tracer kernel in this precision.
    const TRACE_KERNEL: KernelSpec;
    /// The 2D view's kernel in this precision.
    const JULIA2D_KERNEL: KernelSpec;
    /// The path tracer's kernel in this precision.
    const PATH_KERNEL: KernelSpec;
    /// The tracer's uniform block in this precision.
    type TraceUniform: SampledUniform<TraceParams<Self>>;
    /// The 2D view's uniform block in this precision.
    type Julia2dUniform: BandUniform<Julia2dParams<Self>>;
    /// Override constants every pipeline of this precision on `ctx` is built with (f64: the
    /// start-up check's repairs); Err where this precision cannot run on `ctx`.
    fn device_constants(ctx: &GpuContext) -> Result<Vec<(&'static str, f64)>>;

    /// The tracer's uniform for one dispatch: a band, adding the samples [start, end).
    fn trace_uniform(p: &TraceParams<Self>, band: Band, (start, end): (u32, u32)) -> Vec<u8> {
        let gpu = Self::TraceUniform::band(p, band.row, band.rows).sampled(start, end);
        bytemuck::bytes_of(&gpu).to_vec()
    }
    /// The tracer's uniform for one dispatch into an image whose rows are `row_stride` items
    /// apart, the band's rows written from its own row on (the explorer's texture).
    fn view_uniform(
        p: &TraceParams<Self>,
        band: Band,
        row_stride: u32,
        (start, end): (u32, u32),
    ) -> Vec<u8> {
        let gpu = Self::TraceUniform::band(p, band.row, band.rows)
            .placed(row_stride, band.row)
            .sampled(start, end);
        bytemuck::bytes_of(&gpu).to_vec()
    }
    /// The 2D view's uniform for one band.
    fn julia2d_uniform(p: &Julia2dParams<Self>, band: Band) -> Vec<u8> {
        bytemuck::bytes_of(&Self::Julia2dUniform::band(p, band.row, band.rows)).to_vec()
    }
    /// The 2D view's uniform for the whole image into rows `row_stride` items apart (the
    /// explorer's texture).
    fn julia2d_view_uniform(p: &Julia2dParams<Self>, row_stride: u32) -> Vec<u8> {
        let gpu = Self::Julia2dUniform::band(p, 0, p.height).placed(row_stride, 0);
        bytemuck::bytes_of(&gpu).to_vec()
    }
}
