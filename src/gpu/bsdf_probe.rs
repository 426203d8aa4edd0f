//! A test kernel for the path tracer's BSDF and light (shaders/bsdf_probe.wgsl over
//! shaders/bsdf.wgsl and shaders/light.wgsl): one BSDF sample and one sample of each light per
//! item, from inputs derived from the item's index, so that a test can hold the GPU's functions
//! to their CPU twins (src/cpu/bsdf.rs, src/cpu/light.rs). Not used by any render.

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::kernel::{Kernel, KernelSpec, OutputSpec, Run};
use super::shaders::BSDF_PROBE_MODULE;
use crate::algebra::{Vec2, Vec3};
use crate::cpu::bsdf::{BsdfSample, Material};
use crate::cpu::light::{Sky, SphereLight, Sun};
use crate::cpu::sobol::{random_sample, to_unit};
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
    /// The material's multiscatter: 1 on, 0 off.
    pub multiscatter: u32,
    /// The WGSL struct's size is a multiple of its alignment (16).
    pub _pad: [u32; 2],
}

const OUTPUTS: [OutputSpec; 5] = [
    OutputSpec {
        name: "sample",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "value",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "sun",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "light",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
    OutputSpec {
        name: "light_value",
        bytes_per_item: 16,
        on_demand: false,
        planes: 1,
        planes_back: 1,
    },
];

/// The probe's sky, sun and sphere light, as the shader's `probe_sky`, `probe_sun` and
/// `probe_sphere_light` (keep in sync).
pub fn probe_lights() -> (Sky<f32>, Sun<f32>, SphereLight<f32>) {
    (
        Sky {
            zenith: Vec3::new(0.2, 0.4, 0.9),
            horizon: Vec3::new(0.8, 0.85, 0.9),
            ground: Vec3::new(0.3, 0.25, 0.2),
            up: Vec3::new(0.0, 1.0, 0.0),
            intensity: 1.5,
        },
        Sun {
            direction: Vec3::new(0.3, 0.8, 0.52).normalize(),
            one_minus_cos: 0.01,
            irradiance: Vec3::new(3.0, 2.0, 1.0),
        },
        SphereLight {
            center: Vec3::new(1.0, 2.0, 3.0),
            radius: 0.5,
            intensity: Vec3::new(2.0, 2.0, 2.0),
        },
    )
}

/// Item `n`'s point for the lights, in [-1, 1]^3 (the shader's `p`).
pub fn probe_point(n: u32) -> Vec3<f32> {
    Vec3::new(probe_input(n, 0), probe_input(n, 1), probe_input(n, 2)) * 2.0 - Vec3::splat(1.0)
}

const PROBE_KERNEL: KernelSpec = KernelSpec {
    name: "bsdf_probe",
    module: BSDF_PROBE_MODULE,
    entry_point: "bsdf_probe",
    uniform_bytes: size_of::<GpuBsdfProbe>() as u64,
    outputs: &OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: None,
};

/// Input `k` (0..4) of item `n`, in [0, 1): the random sampler's number for (n, 0, k), as the
/// shader's `probe_input`.
pub fn probe_input(n: u32, k: u32) -> f32 {
    to_unit(random_sample(n, 0, k))
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

/// One item's result: the BSDF sample and the specular probability for its wo; the sun's and
/// the sphere light's samples (wi, pdf); the sphere light's radiance.x and distance, the sky's
/// radiance.x along the sun's wi and the sphere light's pdf of it.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProbeResult {
    pub sample: BsdfSample<f32>,
    pub specular_probability: f32,
    pub sun: [f32; 4],
    pub light: [f32; 4],
    pub light_value: [f32; 4],
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
            multiscatter: m.multiscatter as u32,
            _pad: [0; 2],
        };
        bytemuck::bytes_of(&p).to_vec()
    };
    let run = Run {
        constants: &[],
        size: (width, rows),
        read: &[true; 5],
        dispatches_per_band: 1,
        params: &uniform,
        input: None,
    };
    let mut results = Vec::with_capacity((width * rows) as usize);
    kernel.run(
        &run,
        |out| {
            let s: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[0].expect("read back"));
            let v: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[1].expect("read back"));
            let sun: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[2].expect("read back"));
            let light: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[3].expect("read back"));
            let lv: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[4].expect("read back"));
            (0..s.len())
                .map(|k| (s[k], v[k], sun[k], light[k], lv[k]))
                .map(|(s, v, sun, light, light_value)| ProbeResult {
                    sample: BsdfSample {
                        wi: Vec3::new(s[0], s[1], s[2]),
                        f: Vec3::new(v[0], v[1], v[2]),
                        pdf: s[3],
                    },
                    specular_probability: v[3],
                    sun,
                    light,
                    light_value,
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
