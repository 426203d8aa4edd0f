//! The uniform blocks the kernels read, as `#[repr(C)]` bytemuck structs.

use bytemuck::{Pod, Zeroable};

use crate::params::{Julia2dParams, TraceParams};

/// The tracer's uniform in one precision: `$name` with floats `$real`, made from
/// `TraceParams<$real>`, `$pad` u32s of padding at the end (WGSL's size is a multiple of the
/// struct's alignment: 16 bytes in f32, 32 in f64).
macro_rules! gpu_params {
    ($(#[$doc:meta])* $name:ident, $real:ty, $pad:literal) => {
        $(#[$doc])*
        #[repr(C)]
        #[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
        pub struct $name {
            pub c: [[$real; 4]; 4],
            pub slice_x: [[$real; 4]; 4],
            pub slice_y: [[$real; 4]; 4],
            pub slice_z: [[$real; 4]; 4],
            pub slice_offset: [[$real; 4]; 4],
            pub eye: [$real; 3],
            pub epsilon: $real,
            pub cam_forward: [$real; 3],
            pub tan_half_fov_y: $real,
            pub cam_right: [$real; 3],
            pub aspect: $real,
            pub cam_up: [$real; 3],
            pub escape_radius_squared: $real,
            pub light: [$real; 3],
            pub bounds_radius_squared: $real,
            pub bounds_center: [$real; 3],
            pub normal_tint: $real,
            pub diffuse: [$real; 3],
            pub specular: $real,
            pub background: [$real; 3],
            pub shininess: $real,
            pub palette_phase: [$real; 3],
            pub trap_scale: $real,
            pub cut_normal: [$real; 3],
            pub cut_offset: $real,
            pub shadow_factor: $real,
            pub normal_delta: $real,
            pub step_scale: $real,
            pub pixel_epsilon: $real,
            pub pixel_angle: $real,
            pub light_radius: $real,
            pub ambient: $real,
            pub occlusion: $real,
            pub trap_radius: $real,
            pub max_iterations: u32,
            pub max_steps: u32,
            pub width: u32,
            pub height: u32,
            pub shadows: u32,
            /// The band of rows this dispatch traces: [row_offset, row_offset + row_count).
            pub row_offset: u32,
            pub row_count: u32,
            /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows
            /// are copied into a texture).
            pub row_stride: u32,
            /// The output row that the band's first row lands in.
            pub out_row: u32,
            pub normal_method: u32,
            pub tracing: u32,
            pub algebra_parts: u32,
            pub samples: u32,
            /// The samples this dispatch adds: [sample_start, sample_end) of `samples`.
            pub sample_start: u32,
            pub sample_end: u32,
            pub colouring: u32,
            pub cut: u32,
            /// The WGSL struct's size is a multiple of its alignment.
            pub _pad: [u32; $pad],
        }

        impl $name {
            /// The tracer parameters for a band of rows, written at the start of a band-sized
            /// output (row_stride = width, out_row = 0); see [`Self::with_output`].
            pub fn new(p: &TraceParams<$real>, row_offset: u32, row_count: u32) -> Self {
                let v3 = |v: crate::algebra::Vec3<$real>| [v.x, v.y, v.z];
                let v4 = |v: crate::algebra::Hyper<$real>| v.map(|q| [q.x, q.y, q.z, q.w]);
                Self {
                    c: v4(p.c),
                    slice_x: v4(p.slice_x),
                    slice_y: v4(p.slice_y),
                    slice_z: v4(p.slice_z),
                    slice_offset: v4(p.slice_offset),
                    eye: v3(p.eye),
                    epsilon: p.epsilon,
                    cam_forward: v3(p.cam_forward),
                    tan_half_fov_y: p.tan_half_fov_y,
                    cam_right: v3(p.cam_right),
                    aspect: p.aspect,
                    cam_up: v3(p.cam_up),
                    escape_radius_squared: p.escape_radius_squared,
                    light: v3(p.light),
                    bounds_radius_squared: p.bounds_radius_squared,
                    bounds_center: v3(p.bounds_center),
                    normal_tint: p.normal_tint,
                    diffuse: v3(p.diffuse),
                    specular: p.specular,
                    background: v3(p.background),
                    shininess: p.shininess,
                    palette_phase: v3(p.palette_phase),
                    trap_scale: p.trap_scale,
                    cut_normal: v3(p.cut_normal),
                    cut_offset: p.cut_offset,
                    shadow_factor: p.shadow_factor,
                    normal_delta: p.normal_delta,
                    step_scale: p.step_scale,
                    pixel_epsilon: p.pixel_epsilon,
                    pixel_angle: p.pixel_angle,
                    light_radius: p.light_radius,
                    ambient: p.ambient,
                    occlusion: p.occlusion,
                    trap_radius: p.trap_radius,
                    max_iterations: p.max_iterations,
                    max_steps: p.max_steps,
                    width: p.width,
                    height: p.height,
                    shadows: p.shadows as u32,
                    row_offset,
                    row_count,
                    row_stride: p.width,
                    out_row: 0,
                    normal_method: p.normal_method.code(),
                    tracing: p.tracing.code(),
                    algebra_parts: p.algebra_parts,
                    samples: p.samples,
                    sample_start: 0,
                    sample_end: p.samples,
                    colouring: p.colouring.code(),
                    cut: p.cut as u32,
                    _pad: [0; $pad],
                }
            }

            /// The same band written into a larger output: rows `row_stride` pixels apart, the
            /// band's first row at output row `out_row`.
            pub fn with_output(self, row_stride: u32, out_row: u32) -> Self {
                Self {
                    row_stride,
                    out_row,
                    ..self
                }
            }

            /// The same band, adding only the samples [start, end) in this dispatch.
            pub fn with_samples(self, start: u32, end: u32) -> Self {
                Self {
                    sample_start: start,
                    sample_end: end,
                    ..self
                }
            }
        }
    };
}

gpu_params!(
    /// Keep in sync with `struct Params` in shaders/trace.wgsl: same fields, same order; every
    /// `vec3<Real>` is followed by a scalar filling its slot. The f32 image of
    /// [`TraceParams`]; the tests compare this layout with the one naga computes for the
    /// shader's f32 module.
    GpuParams,
    f32,
    2
);

gpu_params!(
    /// [`GpuParams`] in f64, for the f64 module of the same shaders/trace.wgsl (keep in sync
    /// with `struct Params` there); the tests compare its layout with naga's for that module.
    GpuParams64,
    f64,
    5
);

/// Keep in sync with `struct Julia2dParams` in shaders/julia2d.wgsl: same fields, same order.
/// The tests compare this layout with the one naga computes for the shader.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuJulia2dParams {
    pub c: [f32; 2],
    pub center: [f32; 2],
    pub half_extent: [f32; 2],
    pub max_iterations: u32,
    pub width: u32,
    pub height: u32,
    /// The band of rows this dispatch computes: [row_offset, row_offset + row_count).
    pub row_offset: u32,
    pub row_count: u32,
    /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows are
    /// copied into a texture).
    pub row_stride: u32,
    /// The output row that the band's first row lands in.
    pub out_row: u32,
    /// Fills the struct to WGSL's size (a multiple of its 8-byte alignment).
    pub pad: u32,
}

impl GpuJulia2dParams {
    /// The f32 parameters for a band of rows, written at the start of a band-sized output.
    pub fn new(p: &Julia2dParams<f32>, row_offset: u32, row_count: u32) -> Self {
        Self {
            c: [p.c.x, p.c.y],
            center: [p.center.x, p.center.y],
            half_extent: [p.half_extent.x, p.half_extent.y],
            max_iterations: p.max_iterations,
            width: p.width,
            height: p.height,
            row_offset,
            row_count,
            row_stride: p.width,
            out_row: 0,
            pad: 0,
        }
    }

    /// The same band written into a larger output: rows `row_stride` pixels apart, the band's
    /// first row at output row `out_row`.
    pub fn with_output(self, row_stride: u32, out_row: u32) -> Self {
        Self {
            row_stride,
            out_row,
            ..self
        }
    }
}

/// [`GpuJulia2dParams`] in f64, for the f64 module of shaders/julia2d.wgsl (keep in sync with
/// `struct Julia2dParams` there); the tests compare its layout with naga's for that module.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuJulia2dParams64 {
    pub c: [f64; 2],
    pub center: [f64; 2],
    pub half_extent: [f64; 2],
    pub max_iterations: u32,
    pub width: u32,
    pub height: u32,
    /// The band of rows this dispatch computes: [row_offset, row_offset + row_count).
    pub row_offset: u32,
    pub row_count: u32,
    /// Pixels per row of the output arrays (>= width; a multiple of 64 where the rows are
    /// copied into a texture).
    pub row_stride: u32,
    /// The output row that the band's first row lands in.
    pub out_row: u32,
    /// Fills the struct to WGSL's size (a multiple of its 16-byte alignment).
    pub pad: u32,
}

impl GpuJulia2dParams64 {
    /// The f64 parameters for a band of rows, written at the start of a band-sized output.
    pub fn new(p: &Julia2dParams<f64>, row_offset: u32, row_count: u32) -> Self {
        Self {
            c: [p.c.x, p.c.y],
            center: [p.center.x, p.center.y],
            half_extent: [p.half_extent.x, p.half_extent.y],
            max_iterations: p.max_iterations,
            width: p.width,
            height: p.height,
            row_offset,
            row_count,
            row_stride: p.width,
            out_row: 0,
            pad: 0,
        }
    }

    /// The same band written into a larger output: rows `row_stride` pixels apart, the band's
    /// first row at output row `out_row`.
    pub fn with_output(self, row_stride: u32, out_row: u32) -> Self {
        Self {
            row_stride,
            out_row,
            ..self
        }
    }
}
