//! Where a live view's session shows its images ([`Canvas`]: the caller's textures, one a
//! quality) and the kernel outputs it renders them into ([`Target`]).

use super::Quality;
use crate::gpu::Kernel;

/// Where a session's images are shown: a texture for each [`Quality`], which the caller owns
/// (the explorer's are egui's). The session says when a texture must change size, copies a
/// pass's colour rows into it on the device, or writes it whole from the host.
pub trait Canvas {
    /// Makes the texture of `quality` `size` pixels, replacing the one it had.
    fn resize(&mut self, quality: Quality, size: [u32; 2]);
    /// Records the copy of the colour rows `[row, row + rows)` of `colour` (packed RGBA8,
    /// 0xAABBGGRR, rows `stride` pixels apart; `stride` * 4 bytes is a multiple of 256) into
    /// the texture of `quality`.
    fn copy_rows(
        &self,
        quality: Quality,
        encoder: &mut wgpu::CommandEncoder,
        colour: (&wgpu::Buffer, u32),
        rows: (u32, u32),
    );
    /// Writes the whole texture of `quality`, `size` pixels, from `colour` (packed RGBA8, row
    /// after row).
    fn write(&mut self, quality: Quality, queue: &wgpu::Queue, colour: &[u32], size: [u32; 2]);
    /// Gives back the textures (the session is no longer shown).
    fn release(&mut self);
}

/// Makes the canvas of a new session or view (the caller's: a session is made when a view
/// first needs it).
pub type NewCanvas<C> = std::sync::Arc<dyn Fn() -> C + Send + Sync>;

/// Texture rows must be 256 bytes apart for buffer-to-texture copies: 64 RGBA8 pixels.
const ROW_ALIGN: u32 = 64;

/// A kernel's outputs for an image of `width` x `height`, rows `row_stride` pixels apart (a
/// texture copy's alignment), and their bind group.
pub struct Target {
    pub width: u32,
    pub height: u32,
    pub row_stride: u32,
    /// Whether the AOVs output is whole (else a placeholder): the denoised view reads it.
    pub aovs: bool,
    pub outputs: Vec<wgpu::Buffer>,
    /// The scene's input array bound (the environment map).
    pub input: crate::gpu::kernel::InputData,
    pub bind_group: wgpu::BindGroup,
}

impl Target {
    /// Output buffers of `size`, bound with `uniform` and the scene's `input`. With `aovs` the
    /// tracer's AOVs output is whole, else a placeholder, as every other on-demand output is.
    pub fn new(
        kernel: &Kernel,
        uniform: &wgpu::Buffer,
        size: [u32; 2],
        aovs: bool,
        input: crate::gpu::kernel::InputData,
    ) -> Self {
        let row_stride = size[0].next_multiple_of(ROW_ALIGN);
        let mut read = vec![false; kernel.spec().outputs.len()];
        if let Some(slot) = read.get_mut(crate::gpu::AOVS_OUTPUT) {
            *slot = aovs;
        }
        let outputs = kernel.output_buffers(row_stride as u64 * size[1] as u64, "view", &read);
        let bind_group = kernel.bind_group(uniform, &outputs, &input);
        Self {
            width: size[0],
            height: size[1],
            row_stride,
            aovs,
            outputs,
            input,
            bind_group,
        }
    }
}
