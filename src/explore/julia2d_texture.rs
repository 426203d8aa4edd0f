//! The 2D Julia set's texture, which the explorer's viewport shows in 2D mode: the render
//! module's live 2D view ([`Live2d`]) draws into it, and egui shows it directly.

use std::sync::Arc;

use super::slice_texture::{EguiRenderer, ViewTextures};
use crate::gpu::GpuKernels;
use crate::render::progressive::Quality;
use crate::render::progressive::julia2d::Live2d;

/// The explorer's 2D view: the live 2D view, drawing into a texture egui shows.
pub type Julia2dTexture = Live2d<ViewTextures>;

impl Live2d<ViewTextures> {
    /// The view on the 2D kernels of `kernels` ([`Live2d::new`]), drawing through `renderer`.
    pub fn on_textures(kernels: Arc<GpuKernels>, renderer: EguiRenderer) -> crate::Result<Self> {
        let new_canvas = ViewTextures::maker(&kernels, renderer);
        Live2d::new(kernels, new_canvas)
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let (canvas, size) = self.shown_image()?;
        Some((canvas.texture_id(Quality::Full)?, size))
    }
}
