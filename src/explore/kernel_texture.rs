//! A kernel's output drawn into a texture egui shows: the kernel's output arrays with rows
//! padded for texture copies, the texture and its egui id, and the bind group; the 3D slice's
//! and the 2D set's textures both draw through it (the path-traced view writes its texture
//! from the host instead, [`KernelTarget::write_colour`]).

use crate::gpu::Kernel;

/// Texture rows must be 256 bytes apart for buffer-to-texture copies: 64 RGBA8 pixels.
const ROW_ALIGN: u32 = 64;

/// A kernel's outputs for an image of `width` x `height`, rows `row_stride` pixels apart, and
/// the texture its colour (output 0) is copied into.
pub struct KernelTarget {
    pub width: u32,
    pub height: u32,
    pub row_stride: u32,
    /// Whether the AOVs output is whole (else a placeholder): the denoised view reads it.
    pub aovs: bool,
    pub outputs: Vec<wgpu::Buffer>,
    pub texture: wgpu::Texture,
    pub texture_id: egui::TextureId,
    pub bind_group: wgpu::BindGroup,
}

impl KernelTarget {
    /// Output buffers and a texture of `size`, bound with `uniform`; `old` is the id of the
    /// texture this one replaces (kept, so that egui's references stay valid). With `aovs` the
    /// tracer's AOVs output is whole, else a placeholder, as every other on-demand output is.
    pub fn new(
        kernel: &Kernel,
        renderer: &egui::mutex::RwLock<egui_wgpu::Renderer>,
        (label, uniform): (&str, &wgpu::Buffer),
        (size, aovs): ([u32; 2], bool),
        old: Option<egui::TextureId>,
    ) -> Self {
        let row_stride = size[0].next_multiple_of(ROW_ALIGN);
        let mut read = vec![false; kernel.spec().outputs.len()];
        if let Some(slot) = read.get_mut(crate::gpu::AOVS_OUTPUT) {
            *slot = aovs;
        }
        let outputs = kernel.output_buffers(row_stride as u64 * size[1] as u64, label, &read);
        let device = &kernel.context().device;
        let (texture, texture_id) = native_texture(device, renderer, label, size, old);
        let bind_group = kernel.bind_group(uniform, &outputs);
        Self {
            width: size[0],
            height: size[1],
            row_stride,
            aovs,
            outputs,
            texture,
            texture_id,
            bind_group,
        }
    }

    /// Records the copy of the colour rows `[row, row + rows)` into the texture.
    pub fn copy_rows(&self, encoder: &mut wgpu::CommandEncoder, row: u32, rows: u32) {
        encoder.copy_buffer_to_texture(
            wgpu::TexelCopyBufferInfo {
                buffer: &self.outputs[0],
                layout: wgpu::TexelCopyBufferLayout {
                    offset: row as u64 * self.row_stride as u64 * 4,
                    bytes_per_row: Some(self.row_stride * 4),
                    rows_per_image: Some(rows),
                },
            },
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d { x: 0, y: row, z: 0 },
                aspect: wgpu::TextureAspect::All,
            },
            wgpu::Extent3d {
                width: self.width,
                height: rows,
                depth_or_array_layers: 1,
            },
        );
    }
}

impl KernelTarget {
    /// Writes the whole texture from the host: `colour` is `width` x `height` packed RGBA8
    /// (0xAABBGGRR, the frames' colour), row after row.
    pub fn write_colour(&self, queue: &wgpu::Queue, colour: &[u32]) {
        assert_eq!(colour.len(), self.width as usize * self.height as usize);
        queue.write_texture(
            wgpu::TexelCopyTextureInfo {
                texture: &self.texture,
                mip_level: 0,
                origin: wgpu::Origin3d::ZERO,
                aspect: wgpu::TextureAspect::All,
            },
            bytemuck::cast_slice(colour),
            wgpu::TexelCopyBufferLayout {
                offset: 0,
                bytes_per_row: Some(self.width * 4),
                rows_per_image: Some(self.height),
            },
            wgpu::Extent3d {
                width: self.width,
                height: self.height,
                depth_or_array_layers: 1,
            },
        );
    }
}

/// A texture of `size` pixels that egui draws, registered with the renderer (or replacing the
/// texture behind `old`, keeping its id). egui samples textures as gamma-encoded values and
/// writes them to a gamma framebuffer unchanged: a plain (non-sRGB) RGBA8 texture puts the PNG's
/// very bytes on screen.
fn native_texture(
    device: &wgpu::Device,
    renderer: &egui::mutex::RwLock<egui_wgpu::Renderer>,
    label: &str,
    size: [u32; 2],
    old: Option<egui::TextureId>,
) -> (wgpu::Texture, egui::TextureId) {
    let texture = device.create_texture(&wgpu::TextureDescriptor {
        label: Some(label),
        size: wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
        mip_level_count: 1,
        sample_count: 1,
        dimension: wgpu::TextureDimension::D2,
        format: wgpu::TextureFormat::Rgba8Unorm,
        usage: wgpu::TextureUsages::TEXTURE_BINDING | wgpu::TextureUsages::COPY_DST,
        view_formats: &[],
    });
    let view = texture.create_view(&Default::default());
    let mut renderer = renderer.write();
    let id = match old {
        Some(id) => {
            renderer.update_egui_texture_from_wgpu_texture(
                device,
                &view,
                wgpu::FilterMode::Nearest,
                id,
            );
            id
        }
        None => renderer.register_native_texture(device, &view, wgpu::FilterMode::Nearest),
    };
    (texture, id)
}
