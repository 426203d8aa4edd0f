//! The uniform blocks the kernels read: the `#[repr(C)]` bytemuck images of the host parameters
//! (declared once, with them, in src/params.rs), and how a dispatch sets its own fields.

pub use crate::params::{GpuJulia2dParams, GpuJulia2dParams64, GpuParams, GpuParams64};

/// `with_output` for the uniforms with an output placement (row_stride, out_row).
macro_rules! with_output {
    ($($gpu:ident),*) => {$(
        impl $gpu {
            /// The same band written into a larger output: rows `row_stride` pixels apart, the
            /// band's first row at output row `out_row`.
            pub fn with_output(self, row_stride: u32, out_row: u32) -> Self {
                Self {
                    row_stride,
                    out_row,
                    ..self
                }
            }
        }
    )*};
}
with_output!(GpuParams, GpuParams64, GpuJulia2dParams, GpuJulia2dParams64);

/// `with_samples` for the tracer's uniforms.
macro_rules! with_samples {
    ($($gpu:ident),*) => {$(
        impl $gpu {
            /// The same band, adding only the samples [start, end) in this dispatch.
            pub fn with_samples(self, start: u32, end: u32) -> Self {
                Self {
                    sample_start: start,
                    sample_end: end,
                    ..self
                }
            }
        }
    )*};
}
with_samples!(GpuParams, GpuParams64);

/// A uniform of one band of rows of a kernel, made of its host parameters `P`: what lets the
/// precisions' [`super::GpuReal`] impls share their uniforms' making ([`GpuParams`] and
/// [`GpuParams64`] of [`crate::params::TraceParams`], [`GpuJulia2dParams`] and
/// [`GpuJulia2dParams64`] of [`crate::params::Julia2dParams`]).
pub trait BandUniform<P>: bytemuck::Pod {
    /// The uniform of the band of rows [row, row + rows), written into a band-sized output.
    fn band(p: &P, row: u32, rows: u32) -> Self;
    /// The same band written into a larger output (`with_output`).
    fn placed(self, row_stride: u32, out_row: u32) -> Self;
}

/// A tracer's uniform: a band that adds some of its samples in one dispatch.
pub trait SampledUniform<P>: BandUniform<P> {
    /// The same band, adding only the samples [start, end) (`with_samples`).
    fn sampled(self, start: u32, end: u32) -> Self;
}

macro_rules! band_uniform {
    ($($gpu:ident of $host:ident<$r:ty>),*) => {$(
        impl BandUniform<crate::params::$host<$r>> for $gpu {
            fn band(p: &crate::params::$host<$r>, row: u32, rows: u32) -> Self {
                Self::new(p, row, rows)
            }
            fn placed(self, row_stride: u32, out_row: u32) -> Self {
                self.with_output(row_stride, out_row)
            }
        }
    )*};
}
band_uniform!(
    GpuParams of TraceParams<f32>,
    GpuParams64 of TraceParams<f64>,
    GpuJulia2dParams of Julia2dParams<f32>,
    GpuJulia2dParams64 of Julia2dParams<f64>
);

impl SampledUniform<crate::params::TraceParams<f32>> for GpuParams {
    fn sampled(self, start: u32, end: u32) -> Self {
        self.with_samples(start, end)
    }
}

impl SampledUniform<crate::params::TraceParams<f64>> for GpuParams64 {
    fn sampled(self, start: u32, end: u32) -> Self {
        self.with_samples(start, end)
    }
}
