//! Test support: the path tracer's sampler (shaders/sobol.wgsl) evaluated on the GPU over a grid
//! of (pixel, sample, dimension), so that the tests can hold its bits to the CPU twin's
//! (src/cpu/sobol.rs). Nothing renders through it.

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::kernel::{Band, Kernel, KernelSpec, OutputSpec, Run};
use super::shaders::SOBOL_PROBE_MODULE;
use crate::error::Result;

/// The probe's uniform, as shaders/sobol_probe.wgsl's `ProbeParams` (keep in sync).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
struct ProbeParams {
    row_offset: u32,
    rows: u32,
    width: u32,
    dims: u32,
    pixel_base: u32,
    sampler: u32,
    _pad: [u32; 2],
}

/// The probe's one output: each item's bits.
const PROBE_OUTPUTS: [OutputSpec; 1] = [OutputSpec {
    name: "bits",
    bytes_per_item: 4,
    on_demand: false,
    planes: 1,
    planes_back: 1,
}];

/// The probe kernel: uniform `ProbeParams`, one output. Untrusted (wgpu's checks kept): it is
/// test support, and its only loop (`sobol`'s) ends after at most 32 turns.
pub const SOBOL_PROBE_KERNEL: KernelSpec = KernelSpec {
    name: "sobol_probe",
    module: SOBOL_PROBE_MODULE,
    entry_point: "sobol_probe",
    uniform_bytes: size_of::<ProbeParams>() as u64,
    outputs: &PROBE_OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: None,
};

/// Test support: the bits of `sampler` (`cpu::sobol::SAMPLER_SOBOL` or `SAMPLER_RANDOM`) drawn
/// on the GPU for pixels `pixels`, samples 0 to `samples - 1` and dimensions 0 to `dims - 1`,
/// pixel by pixel, then sample by sample, then dimension by dimension: the draw for (pixel,
/// sample, dim) at `((pixel - pixels.start) * samples + sample) * dims + dim`.
pub fn sobol_probe(
    ctx: &GpuContext,
    sampler: u32,
    pixels: std::ops::Range<u32>,
    samples: u32,
    dims: u32,
) -> Result<Vec<u32>> {
    let kernel = Kernel::new(ctx.clone(), SOBOL_PROBE_KERNEL)?;
    let width = samples * dims;
    let params = |band: Band| {
        let p = ProbeParams {
            row_offset: band.row,
            rows: band.rows,
            width,
            dims,
            pixel_base: pixels.start,
            sampler,
            _pad: [0; 2],
        };
        bytemuck::bytes_of(&p).to_vec()
    };
    let run = Run {
        constants: &[],
        size: (width, pixels.len() as u32),
        read: &[true],
        dispatches_per_band: 1,
        params: &params,
        input: None,
    };
    let mut bits = vec![0u32; (width as usize) * pixels.len()];
    kernel.run(
        &run,
        |out| {
            let band = bytemuck::cast_slice::<u8, u32>(out.outputs[0].expect("the bits"));
            (out.row, band.to_vec())
        },
        |(row, band)| {
            let at = row as usize * width as usize;
            bits[at..at + band.len()].copy_from_slice(&band);
            Ok(())
        },
    )?;
    Ok(bits)
}
