//! The tracer kernel (shaders/trace.wgsl) on the [`Kernel`] runner: its spec, its pipelines per
//! scene [`Variant`], and renders into host memory band by band, in f32 or (where the adapter
//! passes the start-up check) f64: [`GpuTracer<F>`], one kernel per precision.

use super::GpuContext;
use super::image::{
    Accumulated, Readback, TRACE_OUTPUTS, TRACE64_OUTPUTS, image_readback, render_image_bands,
    stream_frames,
};
use super::kernel::{Band, Kernel, KernelSpec, Run, RunTimes};
use super::params::{GpuParams, GpuParams64};
use super::real::GpuReal;
use super::shaders::{TRACE_MODULE, TRACE64_MODULE};
use super::variant::{Bake, Variant};
use crate::error::Result;
use crate::frame::Frame;
use crate::params::TraceParams;

/// The tracer: uniform [`GpuParams`], outputs colour, depth, steps, estimates and the samples'
/// running sum.
///
/// Trusted (no runtime checks injected): every loop of trace.wgsl is bounded by the params
/// (`max_iterations`, `max_steps`, the cone's fixed counts) and `main` checks the pixel against
/// the band before it writes. Measured on lavapipe (seed's look 512x512, binaries alternating):
/// docs/PERFORMANCE.md.
pub const TRACE_KERNEL: KernelSpec = KernelSpec {
    name: "trace",
    module: TRACE_MODULE,
    entry_point: "main",
    uniform_bytes: size_of::<GpuParams>() as u64,
    outputs: &TRACE_OUTPUTS,
    // Whole workgroup rows, so that every band starts on a cone block's row.
    band_row_multiple: super::WORKGROUP_SIZE.1,
    trusted: true,
    second_uniform: None,
    input: Some(8),
    bake_keeps: Some(super::kernel::TRACE_BAKE_KEEPS),
};

/// [`TRACE_KERNEL`] in f64: uniform [`GpuParams64`], the depth in f64. Trusted for the same
/// reasons (the same WGSL).
pub const TRACE64_KERNEL: KernelSpec = KernelSpec {
    name: "trace64",
    module: TRACE64_MODULE,
    uniform_bytes: size_of::<GpuParams64>() as u64,
    outputs: &TRACE64_OUTPUTS,
    ..TRACE_KERNEL
};

/// Samples one invocation traces in one dispatch at most. lavapipe (Mesa's llvmpipe) stops
/// a loop after 65,535 iterations counted across the loops around it: measured on the unit ball
/// at epsilon 1e-4 (grazing rays of up to 1000 steps), 32 samples in one invocation were right
/// and 48 were not (their last samples never ran). Eight keep well clear of it.
pub const MAX_SAMPLES_PER_DISPATCH: u32 = 8;

/// The tracer's pipelines on one device in precision `F`: a generic one, and one per scene
/// [`Variant`] built on first use and cached.
pub struct GpuTracer<F: GpuReal = f32> {
    kernel: Kernel,
    specialise: bool,
    /// Camera rays an invocation traces together, 1 or 2 (the `INTERLEAVE` override).
    interleave: u32,
    /// Adaptive sampling's compaction (the `COMPACT` override).
    compact: bool,
    /// When renders bake the scene's values into their pipeline.
    bake: Bake,
    /// Override constants of every pipeline: the f64 check's repairs (none in f32).
    device_constants: Vec<(&'static str, f64)>,
    precision: std::marker::PhantomData<F>,
}

/// A GPU render: the frame and how long it took.
pub struct GpuRender {
    pub frame: Frame,
    /// From the first timed dispatch to the image in host memory.
    pub render_seconds: f64,
    /// The dispatches' GPU time by timestamp queries, where the device has them.
    pub gpu_seconds: Option<f64>,
}

impl GpuTracer<f32> {
    /// The f32 tracer: builds the module (and the generic pipeline, where scenes do not get
    /// their own); a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl GpuTracer<f64> {
    /// The f64 tracer, where the device passes the start-up check of f64
    /// ([`GpuContext::f64_support`]; Err saying why not), built with its repairs.
    pub fn new_f64(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl<F: GpuReal> GpuTracer<F> {
    /// Builds this precision's kernel on `ctx` (`GpuKernels` keeps one of each).
    pub(super) fn build(ctx: GpuContext) -> Result<Self> {
        let device_constants = F::device_constants(&ctx)?;
        let tracer = Self {
            kernel: Kernel::new(ctx, F::TRACE_KERNEL)?,
            specialise: super::variant::specialise_from_env(),
            interleave: super::variant::interleave_from_env(super::variant::DEFAULT_INTERLEAVE),
            compact: super::variant::compact_from_env(),
            bake: super::variant::bake_from_env(),
            device_constants,
            precision: std::marker::PhantomData,
        };
        // The generic pipeline is the whole kernel, every branch compiled: built now only where
        // it is what scenes will run (specialisation off). With specialisation, each scene's
        // own is built when it first renders, and costs a fraction (start-up: a 16x16 render on
        // lavapipe spent half its time building a generic pipeline it never ran).
        if !tracer.specialise {
            tracer.kernel.pipeline(&tracer.device_constants)?;
        }
        Ok(tracer)
    }

    /// Whether scenes get their own specialised pipelines.
    pub fn set_specialise(&mut self, on: bool) {
        self.specialise = on;
    }

    /// When renders bake the scene's values into their pipeline (by default
    /// [`super::variant::bake_from_env`]).
    pub fn set_bake(&mut self, bake: Bake) {
        self.bake = bake;
    }

    /// Camera rays an invocation traces together: 1 or 2 (by default
    /// [`super::variant::DEFAULT_INTERLEAVE`], or `QJULIA_INTERLEAVE`). The pixels are the same either way.
    pub fn set_interleave(&mut self, interleave: u32) {
        super::variant::interleave_constant(interleave);
        self.interleave = interleave;
    }

    /// The variant a scene runs on here: its own, or None (the generic pipeline) when
    /// specialisation is off.
    pub fn variant_for(&self, params: &TraceParams<F>, shade: bool) -> Option<Variant> {
        self.specialise.then(|| Variant::of(params, shade))
    }

    /// How many pipelines (variants) the tracer holds: at most [`super::kernel::MAX_PIPELINES`].
    pub fn pipelines_held(&self) -> usize {
        self.kernel.pipelines_held()
    }

    /// The pipeline of a variant (None: generic), built on first use and cached.
    pub fn pipeline(&self, variant: Option<Variant>) -> Result<wgpu::ComputePipeline> {
        self.pipeline_reading(variant, Readback::All)
    }

    /// As [`Self::pipeline`], computing what `readback` reads: with [`Readback::Hdr`] the
    /// AOVs too (the explorer's denoised view).
    pub fn pipeline_reading(
        &self,
        variant: Option<Variant>,
        readback: Readback,
    ) -> Result<wgpu::ComputePipeline> {
        self.kernel
            .pipeline(&self.constants_reading(variant, readback))
    }

    /// As [`Self::pipeline_reading`] where that pipeline is built, else None: nothing is built
    /// (the explorer's frame builds elsewhere).
    pub fn held_pipeline_reading(
        &self,
        variant: Option<Variant>,
        readback: Readback,
    ) -> Option<wgpu::ComputePipeline> {
        self.kernel
            .held_pipeline(&self.constants_reading(variant, readback))
    }

    /// The constants of a variant's pipeline computing what `readback` reads.
    fn constants_reading(
        &self,
        variant: Option<Variant>,
        readback: Readback,
    ) -> Vec<(&'static str, f64)> {
        let mut constants = self.with_device_constants(variant);
        constants.extend_from_slice(readback.constants());
        constants
    }

    /// A variant's constants (None: generic), the interleaving, the compaction and the
    /// device's.
    fn with_device_constants(&self, variant: Option<Variant>) -> Vec<(&'static str, f64)> {
        let mut constants = variant.map(|v| v.constants()).unwrap_or_default();
        constants.push(super::variant::interleave_constant(self.interleave));
        constants.push(super::variant::compact_constant(self.compact));
        constants.extend_from_slice(&self.device_constants);
        constants
    }

    pub fn context(&self) -> &GpuContext {
        self.kernel.context()
    }

    /// The runner underneath: buffers, bind groups and passes for drawing elsewhere (the
    /// explorer's texture).
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// Traces every pixel in host memory.
    pub fn render(&self, params: &TraceParams<F>) -> Result<GpuRender> {
        self.render_outputs(params, true)
    }

    /// As [`Self::render`]; with `shade` false only depth and steps are computed (the colour is
    /// the background), on a pipeline without the shading code.
    pub fn render_outputs(&self, params: &TraceParams<F>, shade: bool) -> Result<GpuRender> {
        let mut frame = Frame::empty(params.width);
        let times = self.render_bands(params, shade, Readback::All, &mut |band| {
            frame.append(&band);
            Ok(())
        })?;
        Ok(GpuRender {
            frame,
            render_seconds: times.seconds,
            gpu_seconds: times.gpu_seconds,
        })
    }

    /// Renders band by band (bounded memory and bounded time per dispatch, whatever the image
    /// size), handing each band of whole rows, top to bottom, to `sink` as a frame of its own.
    pub fn render_bands(
        &self,
        params: &TraceParams<F>,
        shade: bool,
        readback: Readback,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        self.render_band_rows(params, shade, readback, 0..params.height, sink)
    }

    /// As [`Self::render_bands`], the image's rows `rows` alone (`render --tile`), each pixel
    /// exactly as a render of the whole image makes it: the dispatches cover the same samples,
    /// and a band that would start inside a cone block starts on the block's first row, the
    /// rows above `rows` cropped off.
    pub fn render_band_rows(
        &self,
        params: &TraceParams<F>,
        shade: bool,
        readback: Readback,
        rows: std::ops::Range<u32>,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        let mut constants = self.constants(params, shade, readback);
        constants.extend(self.bake.constant(super::variant::camera_rays(params)));
        let size = (params.width, params.height);
        let uniform = self.uniforms(params);
        let shape = (size, self.dispatches(params));
        let read = image_readback(&self.kernel, readback);
        // With adaptive sampling the accumulator comes back for the samples each pixel took.
        let kept = Accumulated {
            radiance: false,
            samples: params.adaptive(),
        };
        render_image_bands(
            &self.kernel,
            &constants,
            shape,
            &read,
            kept,
            &uniform,
            rows,
            params.environment.clone(),
            sink,
        )
    }

    /// Renders many frames one after another, each handed whole to `sink` with its times, in
    /// order: the device runs a frame's first band while the host reads back the frame before
    /// ([`Kernel::run_stream`]).
    pub fn render_frames(
        &self,
        frames: &mut dyn Iterator<Item = (TraceParams<F>, bool)>,
        readback: Readback,
        sink: &mut dyn FnMut(Frame, RunTimes) -> Result<()>,
    ) -> Result<()> {
        let mut steps = frames.flat_map(|(params, shade)| {
            let mut constants = self.constants(&params, shade, readback);
            constants.extend(self.bake.constant(super::variant::camera_rays(&params)));
            let uniform = self.uniforms(&params);
            let read = image_readback(&self.kernel, readback);
            let run = Run {
                constants: &constants,
                size: (params.width, params.height),
                read: &read,
                dispatches_per_band: self.dispatches(&params),
                params: &uniform,
                input: params.environment.clone(),
            };
            self.kernel.steps(&run).collect::<Vec<_>>()
        });
        stream_frames(&self.kernel, &mut steps, sink)
    }

    /// The override constants of a scene's pipeline here, for what `readback` reads (AOVS
    /// where it reads the AOVs, which only a shaded picture has).
    fn constants(
        &self,
        params: &TraceParams<F>,
        shade: bool,
        readback: Readback,
    ) -> Vec<(&'static str, f64)> {
        assert!(
            shade || !readback.aovs(),
            "the AOVs are made of a shaded picture"
        );
        let mut constants = self.with_device_constants(self.variant_for(params, shade));
        constants.extend_from_slice(readback.constants());
        constants
    }

    /// Dispatches per band: the samples, [`Self::samples_per_dispatch`] at a time.
    fn dispatches(&self, params: &TraceParams<F>) -> u32 {
        params
            .samples
            .max(1)
            .div_ceil(self.samples_per_dispatch(params))
    }

    /// The uniform of each dispatch: the band's rows and the samples it adds.
    fn uniforms<'p>(&self, params: &'p TraceParams<F>) -> impl Fn(Band) -> Vec<u8> + 'p {
        let per_dispatch = self.samples_per_dispatch(params);
        move |band: Band| {
            let start = band.dispatch * per_dispatch;
            let end = (start + per_dispatch).min(params.samples.max(1));
            F::trace_uniform(params, band, (start, end))
        }
    }

    /// Samples each dispatch adds: as many as keep a dispatch within `band_pixels()` rays, so
    /// that thousands of samples of a big image never stall the device.
    pub fn samples_per_dispatch(&self, params: &TraceParams<F>) -> u32 {
        let rows = self.kernel.band_rows(params.width, params.height);
        Self::samples_per_dispatch_in(rows, params.width, params.samples)
    }

    /// Samples each dispatch adds to bands of `rows` rows of `width` pixels, of `samples` a
    /// pixel ([`Self::samples_per_dispatch`] for this device's bands).
    pub fn samples_per_dispatch_in(rows: u32, width: u32, samples: u32) -> u32 {
        let band_pixels = rows as u64 * width as u64;
        let fit =
            (crate::memory::band_pixels() / band_pixels.max(1)).clamp(1, u32::MAX as u64) as u32;
        fit.min(MAX_SAMPLES_PER_DISPATCH).min(samples.max(1))
    }
}
