//! The 3D slice's textures, which the explorer's viewport shows: the render module's live view
//! ([`LiveView`]: its progressive sessions, the tracer's and the path tracer's, in f32 or f64)
//! draws into them, and egui shows them directly, with no trip through host memory. Here are
//! the textures ([`ViewTextures`], each session's [`Canvas`]) and the view the viewport holds;
//! the schedule, the kernels and the readbacks are the render module's
//! ([`crate::render::progressive`]).

use std::sync::Arc;

use crate::gpu::GpuKernels;
use crate::render::progressive::Quality;
use crate::render::progressive::canvas::{Canvas, NewCanvas};
use crate::render::progressive::live::LiveView;

pub use crate::render::progressive::INTERACTIVE_FPS;

/// The renderer egui draws with, shared by the explorer's textures.
pub type EguiRenderer = Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>;

/// A session's two textures (the preview's and the full image's) that egui shows.
pub struct ViewTextures {
    device: wgpu::Device,
    renderer: EguiRenderer,
    textures: [Option<(wgpu::Texture, egui::TextureId)>; 2],
}

impl ViewTextures {
    pub fn new(device: wgpu::Device, renderer: EguiRenderer) -> Self {
        Self {
            device,
            renderer,
            textures: [None, None],
        }
    }

    /// What makes each view's textures on `kernels`' device, drawn through `renderer`.
    pub fn maker(kernels: &GpuKernels, renderer: EguiRenderer) -> NewCanvas<Self> {
        let device = kernels.context().device.clone();
        Arc::new(move || Self::new(device.clone(), renderer.clone()))
    }

    /// The egui texture of `quality`, once made.
    pub fn texture_id(&self, quality: Quality) -> Option<egui::TextureId> {
        self.textures[quality as usize].as_ref().map(|(_, id)| *id)
    }
}

impl Canvas for ViewTextures {
    fn resize(&mut self, quality: Quality, size: [u32; 2]) {
        let slot = &mut self.textures[quality as usize];
        let old = slot.take().map(|(_, id)| id);
        let made =
            super::kernel_texture::native_texture(&self.device, &self.renderer, "view", size, old);
        *slot = Some(made);
    }

    fn copy_rows(
        &self,
        quality: Quality,
        encoder: &mut wgpu::CommandEncoder,
        (colour, stride): (&wgpu::Buffer, u32),
        (row, rows): (u32, u32),
    ) {
        if let Some((texture, _)) = &self.textures[quality as usize] {
            super::kernel_texture::copy_rows(encoder, (colour, stride), texture, (row, rows));
        }
    }

    fn write(&self, quality: Quality, queue: &wgpu::Queue, colour: &[u32], size: [u32; 2]) {
        if let Some((texture, _)) = &self.textures[quality as usize] {
            super::kernel_texture::write_colour(queue, texture, colour, size);
        }
    }

    fn release(&mut self) {
        let mut renderer = self.renderer.write();
        for (_, id) in self.textures.iter_mut().filter_map(Option::take) {
            renderer.free_texture(&id);
        }
    }
}

/// The explorer's 3D view: the live view, drawing into textures egui shows.
pub type SliceTexture = LiveView<ViewTextures>;

impl LiveView<ViewTextures> {
    /// The view on the kernels of `kernels` ([`LiveView::new`]), drawing through `renderer`.
    pub fn on_textures(kernels: Arc<GpuKernels>, renderer: EguiRenderer) -> crate::Result<Self> {
        let new_canvas = ViewTextures::maker(&kernels, renderer);
        LiveView::new(kernels, new_canvas)
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let (canvas, quality, size) = self.shown_image()?;
        Some((canvas.texture_id(quality)?, size))
    }
}
