//! A test kernel for the path tracer's BSDF (shaders/bsdf_probe.wgsl over shaders/bsdf.wgsl):
//! one BSDF sample per item from inputs derived from the item's index, so that a test can hold
//! the GPU's BSDF to its CPU twin (src/cpu/bsdf.rs). Not used by any render.

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::kernel::{Kernel, KernelSpec, OutputSpec, Run};
use super::shaders::BSDF_PROBE_MODULE;
use crate::algebra::{Vec2, Vec3};
use crate::cpu::bsdf::{BsdfSample, Material};
use crate::error::Result;

/// The probe's uniform, as shaders/bsdf_probe.wgsl's `Probe` (keep in sync).
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuBsdfProbe {
    pub albedo: [f32; 3],
    pub roughness: f32,
    pub metallic: f32,
    pub specular: f32,
    pub width: u32,
    pub row_offset: u32,
    pub row_count: u32,
    /// The WGSL struct's size is a multiple of its alignment (16).
    pub _pad: [u32; 3],
}

const OUTPUTS: [OutputSpec; 2] = [
    OutputSpec {
        name: "sample",
        bytes_per_item: 16,
    },
    OutputSpec {
        name: "value",
        bytes_per_item: 16,
    },
];

const PROBE_KERNEL: KernelSpec = KernelSpec {
    name: "bsdf_probe",
    module: BSDF_PROBE_MODULE,
    entry_point: "bsdf_probe",
    uniform_bytes: size_of::<GpuBsdfProbe>() as u64,
    outputs: &OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
};

/// The shader's `probe_hash` (Wellons' lowbias32).
pub fn probe_hash(x: u32) -> u32 {
    let mut h = x;
    h ^= h >> 16;
    h = h.wrapping_mul(0x7feb_352d);
    h ^= h >> 15;
    h = h.wrapping_mul(0x846c_a68b);
    h ^= h >> 16;
    h
}

/// Input `k` (0..4) of item `n`, in [0, 1): the hash's top 24 bits, exactly (the shader's
/// `probe_input`).
pub fn probe_input(n: u32, k: u32) -> f32 {
    (probe_hash(n.wrapping_mul(4).wrapping_add(k)) >> 8) as f32 * (1.0 / 16_777_216.0)
}

/// Item `n`'s inputs as the shader forms them: wo's two numbers, the lobe choice, the
/// direction's two numbers.
pub fn probe_inputs(n: u32) -> (Vec2<f32>, f32, Vec2<f32>) {
    (
        Vec2::new(probe_input(n, 0), probe_input(n, 1)),
        probe_input(n, 2),
        Vec2::new(probe_input(n, 3), probe_input(n, 0)),
    )
}

/// One item's result: the sample and the specular probability for its wo.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeResult {
    pub sample: BsdfSample<f32>,
    pub specular_probability: f32,
}

/// Runs the probe for items 0..`count` (rows of 64) with material `m`.
pub fn probe_bsdf(ctx: GpuContext, m: Material<f32>, count: u32) -> Result<Vec<ProbeResult>> {
    let kernel = Kernel::new(ctx, PROBE_KERNEL)?;
    let width = 64;
    let rows = count.div_ceil(width);
    let uniform = |band: super::kernel::Band| {
        let p = GpuBsdfProbe {
            albedo: [m.albedo.x, m.albedo.y, m.albedo.z],
            roughness: m.roughness,
            metallic: m.metallic,
            specular: m.specular,
            width,
            row_offset: band.row,
            row_count: band.rows,
            _pad: [0; 3],
        };
        bytemuck::bytes_of(&p).to_vec()
    };
    let run = Run {
        constants: &[],
        size: (width, rows),
        read: &[true, true],
        dispatches_per_band: 1,
        params: &uniform,
    };
    let mut results = Vec::with_capacity((width * rows) as usize);
    kernel.run(
        &run,
        |out| {
            let s: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[0].expect("read back"));
            let v: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[1].expect("read back"));
            s.iter()
                .zip(v)
                .map(|(s, v)| ProbeResult {
                    sample: BsdfSample {
                        wi: Vec3::new(s[0], s[1], s[2]),
                        f: Vec3::new(v[0], v[1], v[2]),
                        pdf: s[3],
                    },
                    specular_probability: v[3],
                })
                .collect::<Vec<_>>()
        },
        |band| {
            results.extend(band);
            Ok(())
        },
    )?;
    results.truncate(count as usize);
    Ok(results)
}
