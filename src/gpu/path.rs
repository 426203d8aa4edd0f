//! The path tracer's kernel (shaders/path.wgsl over the tracer's module) on the [`Kernel`]
//! runner, in f32 and (where the device passes the start-up check) f64: the tracer's `Params`
//! and outputs, a second uniform of its own ([`GpuPathParams`], binding 7), and a pipeline per
//! scene [`Variant`] ([`Variant::of_path`]). Each dispatch adds as many samples per pixel as keep its
//! steps within lavapipe's budget ([`path_samples_per_dispatch`]): a path of up to 16 bounces
//! with two shadow rays each may take tens of thousands of steps, and lavapipe stops a loop
//! after 65,535 iterations counted across the loops around it.

use bytemuck::{Pod, Zeroable};

use super::GpuContext;
use super::image::{
    Accumulated, Readback, TRACE_OUTPUTS, TRACE64_OUTPUTS, image_readback, render_image_bands,
};
use super::kernel::{Band, Kernel, KernelSpec, RunTimes, SecondUniform};
use super::params::{GpuParams, GpuParams64};
use super::real::GpuReal;
use super::shaders::{PATH_MODULE, PATH64_MODULE};
use super::variant::Variant;
use crate::algebra::{Real, Vec3};
use crate::cpu::path::PathParams;
use crate::error::Result;
use crate::frame::Frame;
use crate::params::TraceParams;
use crate::uniform::{FieldLayout, Layout};

/// shaders/path_uniform.wgsl's `PathParams` (binding 7; keep in sync). Its CPU twin is
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
    pub sun_one_minus_cos: f32,
    pub sun_irradiance: [f32; 3],
    pub sampler: u32,
    pub light_intensity: [f32; 3],
    pub strategy: u32,
    pub roughness: f32,
    pub metallic: f32,
    pub specular: f32,
    /// `material.multiscatter`: 1 on, 0 off.
    pub multiscatter: u32,
    pub regularize: f32,
    pub seed: u32,
    /// `path.step_scale`: the over-relaxation of shadow and bounce rays.
    pub step_scale: f32,
    pub pad1: u32,
    /// `material.emission`: the radiance emitted, times the albedo (0: none).
    pub emission: [f32; 3],
    pub pad2: u32,
}

impl GpuPathParams {
    /// shaders/path_uniform.wgsl's `struct PathParams` as WGSL lays it out (tests/architecture/shaders.rs holds it
    /// against naga's reflection and against this struct's offsets; `qjulia gpu-params --json`
    /// prints it for the browser's host).
    pub const LAYOUT: Layout = Layout {
        name: "PathParams",
        size: 160,
        align: 16,
        fields: &[
            FieldLayout {
                name: "sky_zenith",
                offset: 0,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sky_intensity",
                offset: 12,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sky_horizon",
                offset: 16,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "bounces",
                offset: 28,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sky_ground",
                offset: 32,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "roulette_start",
                offset: 44,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sky_up",
                offset: 48,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "clamp_contribution",
                offset: 60,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sun_direction",
                offset: 64,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sun_one_minus_cos",
                offset: 76,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sun_irradiance",
                offset: 80,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "sampler",
                offset: 92,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "light_intensity",
                offset: 96,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "strategy",
                offset: 108,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "roughness",
                offset: 112,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "metallic",
                offset: 116,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "specular",
                offset: 120,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "multiscatter",
                offset: 124,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "regularize",
                offset: 128,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "seed",
                offset: 132,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "step_scale",
                offset: 136,
                size: 4,
                ty: "f32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "pad1",
                offset: 140,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
            FieldLayout {
                name: "emission",
                offset: 144,
                size: 12,
                ty: "vec3<f32>",
                per_dispatch: false,
            },
            FieldLayout {
                name: "pad2",
                offset: 156,
                size: 4,
                ty: "u32",
                per_dispatch: false,
            },
        ],
    };

    /// The uniform of `p`, in f32 whatever the precision of the geometry.
    pub fn new<F: Real>(p: &PathParams<F>) -> Self {
        let x = |x: F| x.to_f64() as f32;
        let v = |v: Vec3<F>| [x(v.x), x(v.y), x(v.z)];
        Self {
            sky_zenith: v(p.sky.zenith),
            sky_intensity: x(p.sky.intensity),
            sky_horizon: v(p.sky.horizon),
            bounces: p.bounces,
            sky_ground: v(p.sky.ground),
            roulette_start: p.roulette_start,
            sky_up: v(p.sky.up),
            clamp_contribution: x(p.clamp_contribution),
            sun_direction: v(p.sun.direction),
            sun_one_minus_cos: x(p.sun.one_minus_cos),
            sun_irradiance: v(p.sun.irradiance),
            sampler: p.sampler,
            light_intensity: v(p.light_intensity),
            strategy: p.strategy as u32,
            roughness: x(p.roughness),
            metallic: x(p.metallic),
            specular: x(p.specular),
            multiscatter: p.multiscatter as u32,
            regularize: x(p.regularize),
            seed: p.seed,
            step_scale: x(p.step_scale),
            pad1: 0,
            emission: v(p.emission),
            pad2: 0,
        }
    }
}

/// The path kernel in f32: the tracer's uniform and outputs (colour unused, depth, steps,
/// estimates, and the running mean of the linear radiance in `accumulated`), its own uniform at
/// binding 7 (binding 6 is the AOV output).
///
/// Trusted (no runtime checks injected), as the tracer is: every loop of path.wgsl is bounded
/// by the params (`bounces` of at most 16, the samples of a dispatch, the tracer's
/// `max_steps` and `max_iterations`) or by constants (the sampler's bits), and `path_main`
/// checks the pixel against the band before it writes.
pub const PATH_KERNEL: KernelSpec = KernelSpec {
    name: "path",
    module: PATH_MODULE,
    entry_point: "path_main",
    uniform_bytes: size_of::<GpuParams>() as u64,
    outputs: &TRACE_OUTPUTS,
    band_row_multiple: 1,
    trusted: true,
    second_uniform: Some(SecondUniform {
        binding: 7,
        bytes: size_of::<GpuPathParams>() as u64,
    }),
    input: Some(8),
    bake_keeps: Some(super::kernel::TRACE_BAKE_KEEPS),
};

/// [`PATH_KERNEL`] in f64: the geometry in f64 (uniform [`GpuParams64`], the depth in f64); the
/// material, the light and the radiance stay f32, their trigonometry too.
pub const PATH64_KERNEL: KernelSpec = KernelSpec {
    name: "path64",
    module: PATH64_MODULE,
    uniform_bytes: size_of::<GpuParams64>() as u64,
    outputs: &TRACE64_OUTPUTS,
    ..PATH_KERNEL
};

/// Samples one invocation traces in one dispatch: as many as keep samples x rays x max_steps
/// within 60,000 (each scattering event traces at most three rays, four with an environment
/// map: the bounce's and a shadow ray per light; the last ray is one more), at least 1 and at
/// most 8.
pub fn path_samples_per_dispatch(bounces: u32, max_steps: u32, environment: bool) -> u32 {
    let rays = (3 + u64::from(environment)) * bounces as u64 + 1;
    (60_000 / (rays * max_steps.max(1) as u64)).clamp(1, 8) as u32
}

/// The path tracer's pipelines on one device in precision `F`: one per scene [`Variant`], built
/// on first use and cached (a generic one where specialisation is off).
pub struct GpuPathTracer<F: GpuReal = f32> {
    kernel: Kernel,
    specialise: bool,
    /// Camera rays an invocation traces together, 1 or 2 (the `INTERLEAVE` override).
    interleave: u32,
    /// Adaptive sampling's compaction (the `COMPACT` override).
    compact: bool,
    /// When renders bake the scene's values into their pipeline.
    bake: super::variant::Bake,
    /// Override constants of every pipeline: the f64 check's repairs (none in f32).
    device_constants: Vec<(&'static str, f64)>,
    precision: std::marker::PhantomData<F>,
}

impl GpuPathTracer<f32> {
    /// The f32 path tracer; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl GpuPathTracer<f64> {
    /// The f64 path tracer, where the device passes the start-up check of f64.
    pub fn new_f64(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl<F: GpuReal> GpuPathTracer<F> {
    /// How many pipelines (variants) the path tracer holds: at most
    /// [`super::kernel::MAX_PIPELINES`].
    pub fn pipelines_held(&self) -> usize {
        self.kernel.pipelines_held()
    }

    /// Builds this precision's kernel on `ctx` (`GpuKernels` keeps one of each).
    pub(super) fn build(ctx: GpuContext) -> Result<Self> {
        let device_constants = F::device_constants(&ctx)?;
        Ok(Self {
            kernel: Kernel::new(ctx, F::PATH_KERNEL)?,
            specialise: super::variant::specialise_from_env(),
            interleave: super::variant::interleave_from_env(
                super::variant::DEFAULT_PATH_INTERLEAVE,
            ),
            compact: super::variant::compact_from_env(),
            bake: super::variant::bake_from_env(),
            device_constants,
            precision: std::marker::PhantomData,
        })
    }

    /// When renders bake the scene's values into their pipeline (by default
    /// [`super::variant::bake_from_env`]).
    pub fn set_bake(&mut self, bake: super::variant::Bake) {
        self.bake = bake;
    }

    /// Camera rays an invocation traces together: 1 or 2 (by default
    /// [`super::variant::DEFAULT_PATH_INTERLEAVE`], or `QJULIA_INTERLEAVE`). The paths are the same either way.
    pub fn set_interleave(&mut self, interleave: u32) {
        super::variant::interleave_constant(interleave);
        self.interleave = interleave;
    }

    pub fn context(&self) -> &GpuContext {
        self.kernel.context()
    }

    /// The kernel itself (its buffers, bind groups and passes), for a caller that dispatches
    /// it pass by pass (the explorer's view).
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// The pipeline [`Self::render_bands`] runs `params` on: its path variant's (generic where
    /// specialisation is off), with the device's constants.
    pub fn pipeline(&self, params: &TraceParams<F>) -> Result<wgpu::ComputePipeline> {
        self.pipeline_reading(params, Readback::All)
    }

    /// As [`Self::pipeline`], computing what `readback` reads: with [`Readback::Hdr`] the
    /// AOVs too (the explorer's denoised view).
    pub fn pipeline_reading(
        &self,
        params: &TraceParams<F>,
        readback: Readback,
    ) -> Result<wgpu::ComputePipeline> {
        self.kernel
            .pipeline(&self.constants_reading(params, readback))
    }

    /// As [`Self::pipeline_reading`] where that pipeline is built, else None: nothing is built
    /// (the explorer's frame builds elsewhere).
    pub fn held_pipeline_reading(
        &self,
        params: &TraceParams<F>,
        readback: Readback,
    ) -> Option<wgpu::ComputePipeline> {
        self.kernel
            .held_pipeline(&self.constants_reading(params, readback))
    }

    /// The constants of a scene's pipeline computing what `readback` reads.
    fn constants_reading(
        &self,
        params: &TraceParams<F>,
        readback: Readback,
    ) -> Vec<(&'static str, f64)> {
        let mut constants = self.constants(params);
        constants.extend_from_slice(readback.constants());
        constants
    }

    /// The override constants of a scene's pipeline: its path variant's (none where
    /// specialisation is off), the interleaving and the device's.
    fn constants(&self, params: &TraceParams<F>) -> Vec<(&'static str, f64)> {
        let mut constants = match self.specialise {
            true => Variant::of_path(params).constants(),
            false => Vec::new(),
        };
        constants.push(super::variant::interleave_constant(self.interleave));
        constants.push(super::variant::compact_constant(self.compact));
        constants.extend_from_slice(&self.device_constants);
        constants
    }

    /// Traces `params.samples` paths per pixel band by band (bounded memory and bounded time
    /// per dispatch), handing each band of whole rows, top to bottom, to `sink`: the mean
    /// radiance in [`Frame::radiance`], sample 0's depth and steps (with `Readback::All`), and
    /// the colour left 0 for the display transform.
    pub fn render_bands(
        &self,
        params: &TraceParams<F>,
        path: &PathParams<F>,
        readback: Readback,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        self.render_band_rows(params, path, readback, 0..params.height, sink)
    }

    /// As [`Self::render_bands`], the image's rows `rows` alone (`render --tile`), each pixel
    /// exactly as a render of the whole image makes it (the dispatches cover the same samples).
    pub fn render_band_rows(
        &self,
        params: &TraceParams<F>,
        path: &PathParams<F>,
        readback: Readback,
        rows: std::ops::Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        let samples = params.samples.max(1);
        // Within lavapipe's loop budget, and within `band_pixels()` rays a dispatch as the
        // tracer keeps it, so that a big image's dispatches stay of bounded cost.
        let band_rows = self.kernel.band_rows(params.width, params.height);
        let per_dispatch =
            path_samples_per_dispatch(path.bounces, params.max_steps, params.env_map).min(
                super::GpuTracer::<F>::samples_per_dispatch_in(band_rows, params.width, samples),
            );
        let second = GpuPathParams::new(path);
        let uniform = |band: Band| {
            let start = band.dispatch * per_dispatch;
            let end = (start + per_dispatch).min(samples);
            let trace = F::trace_uniform(params, band, (start, end));
            self.kernel
                .pack_uniforms(&trace, bytemuck::bytes_of(&second))
        };
        // What the tracer reads for `readback` (the colour, 0 here, gives the frame its
        // shape), and the accumulator: the radiance, and with adaptive sampling the samples.
        let read = image_readback(&self.kernel, readback);
        let kept = Accumulated {
            radiance: true,
            samples: params.adaptive(),
        };
        let mut constants = self.constants(params);
        constants.extend_from_slice(readback.constants());
        constants.extend(self.bake.constant(super::variant::camera_rays(params)));
        render_image_bands(
            &self.kernel,
            &constants,
            (
                (params.width, params.height),
                samples.div_ceil(per_dispatch),
            ),
            &read,
            kept,
            &uniform,
            rows,
            params.environment.clone(),
            sink,
        )
    }

    /// As [`Self::render_bands`], the whole image in host memory.
    pub fn render(
        &self,
        params: &TraceParams<F>,
        path: &PathParams<F>,
    ) -> Result<(Frame, RunTimes)> {
        let mut frame = Frame::empty(params.width);
        let times = self.render_bands(params, path, Readback::All, &mut |band| {
            frame.append(&band);
            Ok(())
        })?;
        Ok((frame, times))
    }
}
