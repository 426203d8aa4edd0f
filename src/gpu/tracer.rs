//! The tracer kernel (shaders/trace.wgsl) on the [`Kernel`] runner: its spec, its pipelines per
//! scene [`Variant`], and renders into host memory band by band.

use super::kernel::{Band, Kernel, KernelSpec, RunTimes};
use super::params::GpuParams;
use super::shaders::TRACE_MODULE;
use super::variant::Variant;
use super::{GpuContext, TRACE_OUTPUTS, render_image_bands};
use crate::error::Result;
use crate::frame::Frame;
use crate::params::TraceParams;
use crate::render::Readback;

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
};

/// Samples one invocation traces in one dispatch at most. lavapipe (Mesa's llvmpipe) stops
/// a loop after 65,535 iterations counted across the loops around it: measured on the unit ball
/// at epsilon 1e-4 (grazing rays of up to 1000 steps), 32 samples in one invocation were right
/// and 48 were not (their last samples never ran). Eight keep well clear of it.
pub const MAX_SAMPLES_PER_DISPATCH: u32 = 8;

/// The tracer's pipelines on one device: a generic one, and one per scene [`Variant`] built on
/// first use and cached.
pub struct GpuTracer {
    kernel: Kernel,
    specialise: bool,
}

/// A GPU render: the frame and how long it took.
pub struct GpuRender {
    pub frame: Frame,
    /// From the first timed dispatch to the image in host memory.
    pub render_seconds: f64,
    /// The dispatches' GPU time by timestamp queries, where the device has them.
    pub gpu_seconds: Option<f64>,
}

impl GpuTracer {
    /// Builds the module and the generic pipeline; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        let tracer = Self {
            kernel: Kernel::new(ctx, TRACE_KERNEL)?,
            // QJULIA_SPECIALISE=0 runs every scene on the generic pipeline (to measure the gain).
            specialise: std::env::var_os("QJULIA_SPECIALISE").is_none_or(|v| v != "0"),
        };
        tracer.kernel.pipeline(&[])?;
        Ok(tracer)
    }

    /// Whether scenes get their own specialised pipelines.
    pub fn set_specialise(&mut self, on: bool) {
        self.specialise = on;
    }

    /// The variant a scene runs on here: its own, or None (the generic pipeline) when
    /// specialisation is off.
    pub fn variant_for(&self, params: &TraceParams<f32>, shade: bool) -> Option<Variant> {
        self.specialise.then(|| Variant::of(params, shade))
    }

    /// The pipeline of a variant (None: generic), built on first use and cached.
    pub fn pipeline(&self, variant: Option<Variant>) -> Result<wgpu::ComputePipeline> {
        self.kernel
            .pipeline(&variant.map(|v| v.constants()).unwrap_or_default())
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
    pub fn render(&self, params: &TraceParams<f32>) -> Result<GpuRender> {
        self.render_outputs(params, true)
    }

    /// As [`Self::render`]; with `shade` false only depth and steps are computed (the colour is
    /// the background), on a pipeline without the shading code.
    pub fn render_outputs(&self, params: &TraceParams<f32>, shade: bool) -> Result<GpuRender> {
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
        params: &TraceParams<f32>,
        shade: bool,
        readback: Readback,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        let constants = self
            .variant_for(params, shade)
            .map(|v| v.constants())
            .unwrap_or_default();
        let size = (params.width, params.height);
        let per_dispatch = self.samples_per_dispatch(params);
        let uniform = |band: Band| {
            let start = band.dispatch * per_dispatch;
            let end = (start + per_dispatch).min(params.samples.max(1));
            let gpu = GpuParams::new(params, band.row, band.rows).with_samples(start, end);
            bytemuck::bytes_of(&gpu).to_vec()
        };
        let dispatches = params.samples.max(1).div_ceil(per_dispatch);
        let shape = (size, dispatches);
        render_image_bands(&self.kernel, &constants, shape, readback, &uniform, sink)
    }

    /// Samples each dispatch adds: as many as keep a dispatch within `band_pixels()` rays, so
    /// that thousands of samples of a big image never stall the device.
    pub fn samples_per_dispatch(&self, params: &TraceParams<f32>) -> u32 {
        let rows = self.kernel.band_rows(params.width, params.height);
        let band_pixels = rows as u64 * params.width as u64;
        let fit = (crate::band_pixels() / band_pixels.max(1)).clamp(1, u32::MAX as u64) as u32;
        fit.min(MAX_SAMPLES_PER_DISPATCH).min(params.samples.max(1))
    }
}
