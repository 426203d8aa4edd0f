//! The path tracer's kernel (shaders/path.wgsl over the tracer's module) on the [`Kernel`]
//! runner: the tracer's `Params` and outputs, and a second uniform of its own
//! ([`GpuPathParams`], binding 6). Each dispatch adds as many samples per pixel as keep its
//! steps within lavapipe's budget ([`path_samples_per_dispatch`]): a path of up to 16 bounces
//! with two shadow rays each may take tens of thousands of steps, and lavapipe stops a loop
//! after 65,535 iterations counted across the loops around it.

use bytemuck::{Pod, Zeroable};

use super::kernel::{Band, Kernel, KernelSpec, Run, RunTimes, SecondUniform};
use super::params::GpuParams;
use super::shaders::PATH_MODULE;
use super::{GpuContext, TRACE_OUTPUTS};
use crate::algebra::Vec3;
use crate::cpu::path::PathParams;
use crate::error::Result;
use crate::params::TraceParams;

/// shaders/path.wgsl's `PathParams` (binding 6; keep in sync). Its CPU twin is
/// [`PathParams`].
#[repr(C)]
#[derive(Clone, Copy, Debug, Default, PartialEq, Pod, Zeroable)]
pub struct GpuPathParams {
    pub sky_zenith: [f32; 3],
    pub sky_intensity: f32,
    pub sky_horizon: [f32; 3],
    pub bounces: u32,
    pub sky_ground: [f32; 3],
    pub roulette_start: u32,
    pub sky_up: [f32; 3],
    pub clamp_contribution: f32,
    pub sun_direction: [f32; 3],
    pub sun_cos_radius: f32,
    pub sun_irradiance: [f32; 3],
    pub sampler: u32,
    pub light_intensity: [f32; 3],
    pub strategy: u32,
    pub roughness: f32,
    pub metallic: f32,
    pub specular: f32,
    pub pad: u32,
}

impl GpuPathParams {
    pub fn new(p: &PathParams<f32>) -> Self {
        let v = |v: Vec3<f32>| [v.x, v.y, v.z];
        Self {
            sky_zenith: v(p.sky.zenith),
            sky_intensity: p.sky.intensity,
            sky_horizon: v(p.sky.horizon),
            bounces: p.bounces,
            sky_ground: v(p.sky.ground),
            roulette_start: p.roulette_start,
            sky_up: v(p.sky.up),
            clamp_contribution: p.clamp_contribution,
            sun_direction: v(p.sun.direction),
            sun_cos_radius: p.sun.cos_radius,
            sun_irradiance: v(p.sun.irradiance),
            sampler: p.sampler,
            light_intensity: v(p.light_intensity),
            strategy: p.strategy as u32,
            roughness: p.roughness,
            metallic: p.metallic,
            specular: p.specular,
            pad: 0,
        }
    }
}

/// The path kernel in f32: the tracer's uniform and outputs (colour unused, depth, steps,
/// estimates, and the running mean of the linear radiance in `accumulated`), its own uniform at
/// binding 6. Not trusted: wgpu's loop bounding and index checks stay in.
pub const PATH_KERNEL: KernelSpec = KernelSpec {
    name: "path",
    module: PATH_MODULE,
    entry_point: "path_main",
    uniform_bytes: size_of::<GpuParams>() as u64,
    outputs: &TRACE_OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: Some(SecondUniform {
        binding: 6,
        bytes: size_of::<GpuPathParams>() as u64,
    }),
};

/// Samples one invocation traces in one dispatch: as many as keep samples x rays x max_steps
/// within 60,000 (each scattering event traces at most three rays: the bounce's and two shadow
/// rays; the last ray is one more), at least 1 and at most 8.
pub fn path_samples_per_dispatch(bounces: u32, max_steps: u32) -> u32 {
    let rays = 3 * bounces as u64 + 1;
    (60_000 / (rays * max_steps.max(1) as u64)).clamp(1, 8) as u32
}

/// A path-traced image in host memory: per pixel the mean linear radiance, sample 0's depth
/// (NaN on a miss) and steps.
#[derive(Clone, Debug, PartialEq)]
pub struct PathImage {
    pub width: u32,
    pub height: u32,
    pub radiance: Vec<[f32; 3]>,
    pub depth: Vec<f32>,
    pub steps: Vec<u32>,
}

/// The path tracer's pipeline on one device (f32).
pub struct GpuPathTracer {
    kernel: Kernel,
}

impl GpuPathTracer {
    /// Builds the module; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Ok(Self {
            kernel: Kernel::new(ctx, PATH_KERNEL)?,
        })
    }

    /// Traces `params.samples` paths per pixel.
    pub fn render(
        &self,
        params: &TraceParams<f32>,
        path: &PathParams<f32>,
    ) -> Result<(PathImage, RunTimes)> {
        let samples = params.samples.max(1);
        let per_dispatch = path_samples_per_dispatch(path.bounces, params.max_steps);
        let second = GpuPathParams::new(path);
        let uniform = |band: Band| {
            let start = band.dispatch * per_dispatch;
            let end = (start + per_dispatch).min(samples);
            let trace = GpuParams::new(params, band.row, band.rows).with_samples(start, end);
            self.kernel
                .pack_uniforms(bytemuck::bytes_of(&trace), bytemuck::bytes_of(&second))
        };
        let run = Run {
            constants: &[],
            size: (params.width, params.height),
            read: &[false, true, true, false, true],
            dispatches_per_band: samples.div_ceil(per_dispatch),
            params: &uniform,
        };
        let mut image = PathImage {
            width: params.width,
            height: params.height,
            radiance: Vec::new(),
            depth: Vec::new(),
            steps: Vec::new(),
        };
        let times = self.kernel.run(
            &run,
            |out| {
                let depth: &[f32] = bytemuck::cast_slice(out.outputs[1].expect("depth"));
                let steps: &[u32] = bytemuck::cast_slice(out.outputs[2].expect("steps"));
                let acc: &[[f32; 4]] = bytemuck::cast_slice(out.outputs[4].expect("radiance"));
                (depth.to_vec(), steps.to_vec(), acc.to_vec())
            },
            |(depth, steps, acc)| {
                image
                    .depth
                    .extend(depth.iter().map(|&d| if d < 0.0 { f32::NAN } else { d }));
                image.steps.extend(steps);
                image
                    .radiance
                    .extend(acc.iter().map(|a| [a[0], a[1], a[2]]));
                Ok(())
            },
        )?;
        Ok((image, times))
    }
}
