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
