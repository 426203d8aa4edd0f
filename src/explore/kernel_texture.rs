//! The textures egui draws that the explorer's views show: made (or remade behind the same egui
//! id), or written whole from the host. The 3D view's and the 2D view's
//! ([`super::slice_texture::Slot`]) are.

/// Writes the whole of `texture`, `size` pixels, from the host: `colour` is packed RGBA8
/// (0xAABBGGRR, the frames' colour), row after row.
pub fn write_colour(queue: &wgpu::Queue, texture: &wgpu::Texture, colour: &[u32], size: [u32; 2]) {
    assert_eq!(colour.len(), size[0] as usize * size[1] as usize);
    queue.write_texture(
        wgpu::TexelCopyTextureInfo {
            texture,
            mip_level: 0,
            origin: wgpu::Origin3d::ZERO,
            aspect: wgpu::TextureAspect::All,
        },
        bytemuck::cast_slice(colour),
        wgpu::TexelCopyBufferLayout {
            offset: 0,
            bytes_per_row: Some(size[0] * 4),
            rows_per_image: Some(size[1]),
        },
        wgpu::Extent3d {
            width: size[0],
            height: size[1],
            depth_or_array_layers: 1,
        },
    );
}

/// A texture of `size` pixels that egui draws, registered with the renderer (or replacing the
/// texture behind `old`, keeping its id). egui samples textures as gamma-encoded values and
/// writes them to a gamma framebuffer unchanged: a plain (non-sRGB) RGBA8 texture puts the PNG's
/// very bytes on screen.
pub fn native_texture(
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
