//! The 2D Julia view's kernel (shaders/julia2d.wgsl) on the [`Kernel`] runner, for
//! `qjulia render2d` and the explorer's 2D mode, in f32 or (where the adapter passes the
//! start-up check) f64: [`GpuJulia2d<F>`].

use super::GpuContext;
use super::image::{IMAGE_OUTPUTS, IMAGE64_OUTPUTS, Readback, image_readback, render_image_bands};
use super::kernel::{Band, Kernel, KernelSpec, RunTimes};
use super::params::{GpuJulia2dParams, GpuJulia2dParams64};
use super::real::GpuReal;
use super::shaders::{JULIA2D_MODULE, JULIA2D64_MODULE};
use crate::error::Result;
use crate::frame::Frame;
use crate::params::Julia2dParams;

/// The 2D view: uniform [`GpuJulia2dParams`], outputs colour (the grey), the in-set marker
/// (0 in the set, negative outside) and the iterations.
pub const JULIA2D_KERNEL: KernelSpec = KernelSpec {
    name: "julia2d",
    module: JULIA2D_MODULE,
    entry_point: "main",
    uniform_bytes: size_of::<GpuJulia2dParams>() as u64,
    outputs: &IMAGE_OUTPUTS,
    band_row_multiple: 1,
    trusted: false,
    second_uniform: None,
    input: None,
    bake_keeps: Some(super::kernel::JULIA2D_BAKE_KEEPS),
};

/// [`JULIA2D_KERNEL`] in f64: uniform [`GpuJulia2dParams64`], the marker in f64.
pub const JULIA2D64_KERNEL: KernelSpec = KernelSpec {
    name: "julia2d64",
    module: JULIA2D64_MODULE,
    uniform_bytes: size_of::<GpuJulia2dParams64>() as u64,
    outputs: &IMAGE64_OUTPUTS,
    ..JULIA2D_KERNEL
};

/// The 2D Julia pipeline on one device, in precision `F`.
pub struct GpuJulia2d<F: GpuReal = f32> {
    kernel: Kernel,
    /// Override constants of its pipeline: the f64 check's repairs (none in f32).
    device_constants: Vec<(&'static str, f64)>,
    /// When renders bake the view's values into their pipeline (the explorer's live view,
    /// which draws through [`Self::pipeline`], never does).
    bake: super::variant::Bake,
    precision: std::marker::PhantomData<F>,
}

impl GpuJulia2d<f32> {
    /// Builds the module and its pipeline; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl GpuJulia2d<f64> {
    /// The f64 pipeline, where the device passes the start-up check of f64 (Err saying why
    /// not).
    pub fn new_f64(ctx: GpuContext) -> Result<Self> {
        Self::build(ctx)
    }
}

impl<F: GpuReal> GpuJulia2d<F> {
    /// How many pipelines the 2D view holds: at most [`super::kernel::MAX_PIPELINES`].
    pub fn pipelines_held(&self) -> usize {
        self.kernel.pipelines_held()
    }

    /// Builds this precision's kernel on `ctx` (`GpuKernels` keeps one of each).
    pub(super) fn build(ctx: GpuContext) -> Result<Self> {
        let device_constants = F::device_constants(&ctx)?;
        let kernel = Kernel::new(ctx, F::JULIA2D_KERNEL)?;
        let bake = super::variant::bake_from_env();
        kernel.pipeline(&device_constants)?;
        Ok(Self {
            kernel,
            device_constants,
            bake,
            precision: std::marker::PhantomData,
        })
    }

    pub fn context(&self) -> &GpuContext {
        self.kernel.context()
    }

    /// The runner underneath (the explorer draws into a texture with it).
    pub fn kernel(&self) -> &Kernel {
        &self.kernel
    }

    /// The pipeline (the kernel has no specialisations).
    pub fn pipeline(&self) -> Result<wgpu::ComputePipeline> {
        self.kernel.pipeline(&self.device_constants)
    }

    /// The whole image in host memory, and its times.
    pub fn render(&self, params: &Julia2dParams<F>) -> Result<(Frame, RunTimes)> {
        let mut frame = Frame::empty(params.width);
        let times = self.render_bands(params, Readback::All, &mut |band| {
            frame.append(&band);
            Ok(())
        })?;
        Ok((frame, times))
    }

    /// Renders band by band (bounded memory and time per dispatch), handing each band of whole
    /// rows, top to bottom, to `sink`: colour the grey, depth 0 in the set and NaN outside it,
    /// steps the iterations made.
    pub fn render_bands(
        &self,
        params: &Julia2dParams<F>,
        readback: Readback,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        let uniform = |band: Band| F::julia2d_uniform(params, band);
        let size = (params.width, params.height);
        let mut constants = self.device_constants.clone();
        constants.extend(self.bake.constant(size.0 as u64 * size.1 as u64));
        let read = image_readback(&self.kernel, readback);
        render_image_bands(
            &self.kernel,
            &constants,
            (size, 1),
            &read,
            Default::default(),
            &uniform,
            0..size.1,
            None,
            sink,
        )
    }
}
