//! The voxel sampler (shaders/sample.wgsl) on the [`Kernel`] runner, for `qjulia mesh`: the
//! level of the mesh's surface at every point of a grid, streamed to the host in bands of whole
//! rows (bounded memory for any grid), through the tracer's own estimate. The tracer's `Params`
//! are the scene's, as a render's; the grid has a uniform of its own ([`GpuSampleGrid`]).

use bytemuck::{Pod, Zeroable};

use super::kernel::{Band, Kernel, KernelSpec, OutputSpec, Run, RunTimes, SecondUniform};
use super::params::GpuParams;
use super::shaders::SAMPLE_MODULE;
use super::{GpuContext, Variant};
use crate::error::Result;
use crate::grid::SampleGrid;
use crate::params::TraceParams;

/// The sampler's one output: each grid point's level (f32, written as its bits).
pub const SAMPLE_OUTPUTS: [OutputSpec; 1] = [OutputSpec {
    name: "level",
    bytes_per_item: 4,
    on_demand: false,
    planes: 1,
    planes_back: 1,
}];

/// The sampled grid, as shaders/sample.wgsl's `SampleGrid` (binding 7; keep in sync): its first
/// point, the spacing of its points, its points per row and rows per layer, and the band of
/// rows (of rows of rows) this dispatch samples.
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuSampleGrid {
    pub origin: [f32; 3],
    pub width: u32,
    pub step: [f32; 3],
    pub rows: u32,
    pub row_offset: u32,
    pub row_count: u32,
    /// The WGSL struct's size is a multiple of its alignment (16).
    pub _pad: [u32; 2],
}

/// The sampler: uniforms [`GpuParams`] (the tracer's, for its estimate) and [`GpuSampleGrid`]
/// (binding 7), one output, the levels. Trusted (no runtime checks injected): its only
/// loop is the estimate's, bounded by `max_iterations`, and `sample` checks the point against
/// the band before it writes.
pub const SAMPLE_KERNEL: KernelSpec = KernelSpec {
    name: "sample",
    module: SAMPLE_MODULE,
    entry_point: "sample",
    uniform_bytes: size_of::<GpuParams>() as u64,
    outputs: &SAMPLE_OUTPUTS,
    band_row_multiple: 1,
    trusted: true,
    second_uniform: Some(SecondUniform {
        binding: 7,
        bytes: size_of::<GpuSampleGrid>() as u64,
    }),
    input: None,
    // The grid's band (row_offset, row_count) shares its names with the tracer's.
    bake_keeps: Some(super::kernel::TRACE_BAKE_KEEPS),
};

/// The sampler's pipelines on one device, one per scene [`Variant`] (built on first use).
pub struct GpuSampler {
    kernel: Kernel,
}

impl GpuSampler {
    /// Builds the module; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: Kernel::new(ctx, SAMPLE_KERNEL)?,
        })
    }

    pub fn context(&self) -> &GpuContext {
        self.kernel.context()
    }

    /// The grid's uniform for its rows [row, row + rows).
    pub fn grid_uniform(grid: &SampleGrid<f32>, row: u32, rows: u32) -> GpuSampleGrid {
        let v3 = |v: crate::algebra::Vec3<f32>| [v.x, v.y, v.z];
        GpuSampleGrid {
            origin: v3(grid.origin),
            width: grid.width,
            step: v3(grid.step),
            rows: grid.rows,
            row_offset: row,
            row_count: rows,
            _pad: [0; 2],
        }
    }

    /// Samples the first `total_rows` rows of the grid (its layers times its rows per layer),
    /// band by band, top to bottom, handing each band's first row and its levels (row after
    /// row) to `sink`. The sampling's time leaves the sink's out.
    pub fn sample(
        &self,
        params: &TraceParams<f32>,
        grid: &SampleGrid<f32>,
        total_rows: u32,
        sink: &mut dyn FnMut(u32, &[f32]) -> Result<()>,
    ) -> Result<RunTimes> {
        let mut constants = Variant::of(params, false).constants();
        let points = grid.width as u64 * total_rows as u64;
        constants.extend(super::variant::bake_from_env().constant(points));
        let trace = GpuParams::new(params, 0, grid.rows);
        let uniform = |band: Band| {
            let grid = Self::grid_uniform(grid, band.row, band.rows);
            self.kernel
                .pack_uniforms(bytemuck::bytes_of(&trace), bytemuck::bytes_of(&grid))
        };
        let run = Run {
            constants: &constants,
            size: (grid.width, total_rows),
            read: &[true],
            dispatches_per_band: 1,
            params: &uniform,
            input: None,
        };
        self.kernel.run(
            &run,
            |out| {
                let bytes = out.outputs[0].expect("the levels are read back");
                (out.row, bytemuck::cast_slice::<u8, f32>(bytes).to_vec())
            },
            |(row, levels)| sink(row, &levels),
        )
    }
}
