//! The 2D Julia view's kernel (shaders/julia2d.wgsl) on the [`Kernel`] runner, for
//! `qjulia render2d` and the explorer's 2D mode.

use super::kernel::{Band, Kernel, KernelSpec, RunTimes};
use super::params::GpuJulia2dParams;
use super::shaders::JULIA2D_MODULE;
use super::{GpuContext, IMAGE_OUTPUTS, render_image_bands};
use crate::error::Result;
use crate::frame::Frame;
use crate::params::Julia2dParams;
use crate::render::Readback;

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
};

/// The 2D Julia pipeline on one device.
pub struct GpuJulia2d {
    kernel: Kernel,
}

impl GpuJulia2d {
    /// Builds the module and its pipeline; a shader the device rejects is an error.
    pub fn new(ctx: GpuContext) -> Result<Self> {
        let kernel = Kernel::new(ctx, JULIA2D_KERNEL)?;
        kernel.pipeline(&[])?;
        Ok(Self { kernel })
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
        self.kernel.pipeline(&[])
    }

    /// The whole image in host memory, and its times.
    pub fn render(&self, params: &Julia2dParams<f32>) -> Result<(Frame, RunTimes)> {
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
        params: &Julia2dParams<f32>,
        readback: Readback,
        sink: &mut dyn FnMut(Frame) -> Result<()>,
    ) -> Result<RunTimes> {
        let uniform = |band: Band| {
            bytemuck::bytes_of(&GpuJulia2dParams::new(params, band.row, band.rows)).to_vec()
        };
        let size = (params.width, params.height);
        render_image_bands(&self.kernel, &[], (size, 1), readback, &uniform, sink)
    }
}
