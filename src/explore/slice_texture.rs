//! The view's textures, which the explorer's viewport shows: the images the view thread
//! ([`ViewThread`]: the render module's live 3D and 2D views on a thread and a device of their
//! own) publishes in host memory, written into textures on the window's device that egui draws
//! ([`ViewTextures`]), and the view's figures as of that image ([`ThreadView`]: the 3D view,
//! [`SliceTexture`], and the 2D view, [`Julia2dTexture`]). The UI's thread never runs a tile:
//! it asks for a picture, and draws what has arrived.

use std::sync::Arc;
use std::time::Instant;

use crate::precision::Precision;
use crate::render::progressive::Quality;
use crate::render::progressive::canvas::Canvas;
use crate::render::progressive::session::{KeptRadiance, TextureStats};
use crate::render::progressive::view_thread::{Ask, Shown, ViewThread};
use crate::scene::Scene;

pub use crate::render::progressive::INTERACTIVE_FPS;

/// The renderer egui draws with, shared by the explorer's textures.
pub type EguiRenderer = Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>;

/// A view's two textures (the preview's and the full image's) that egui shows.
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

    fn write(&mut self, quality: Quality, queue: &wgpu::Queue, colour: &[u32], size: [u32; 2]) {
        if let Some((texture, _)) = &self.textures[quality as usize] {
            super::kernel_texture::write_colour(queue, texture, colour, size);
        }
    }

    fn release(&mut self) {
        if self.textures.iter().all(Option::is_none) {
            return;
        }
        let mut renderer = self.renderer.write();
        for (_, id) in self.textures.iter_mut().filter_map(Option::take) {
            renderer.free_texture(&id);
        }
    }
}

/// One of the thread's views as the UI sees it: what it asked last, what the thread published
/// as of then, and that image in a texture egui draws.
pub struct ThreadView {
    thread: Arc<ViewThread>,
    /// Whether this is the 2D view.
    julia2d: bool,
    textures: ViewTextures,
    queue: wgpu::Queue,
    /// The number and size of the image in the texture.
    uploaded: Option<(u64, [u32; 2])>,
    /// What the thread published, as of the image in the texture.
    shown: Arc<Shown>,
    /// The last ask: its number and picture.
    asked: Option<(u64, Ask)>,
    waker_set: bool,
}

/// The explorer's 3D view.
pub type SliceTexture = ThreadView;
/// The explorer's 2D view.
pub type Julia2dTexture = ThreadView;

impl ThreadView {
    /// The 3D view (`julia2d`: the 2D view) of `thread`, drawn on the window's `device` and
    /// `queue` through `renderer`.
    pub fn new(
        thread: Arc<ViewThread>,
        julia2d: bool,
        (device, queue): (wgpu::Device, wgpu::Queue),
        renderer: EguiRenderer,
    ) -> Self {
        Self {
            thread,
            julia2d,
            textures: ViewTextures::new(device, renderer),
            queue,
            uploaded: None,
            shown: Arc::default(),
            asked: None,
            waker_set: false,
        }
    }

    /// Asks for the 3D slice of `scene` at `size` (`interacting`: the user drags or the scene
    /// plays), and takes what the thread published since the last frame.
    pub fn update(
        &mut self,
        ctx: &egui::Context,
        scene: &Scene,
        size: [u32; 2],
        interacting: bool,
    ) {
        let ask = Ask::Slice {
            scene: scene.clone(),
            size,
            interacting,
        };
        self.ask(ctx, ask);
    }

    /// Asks for the 2D view of `scene` at its image's size, and takes what the thread
    /// published since the last frame.
    pub fn update_2d(&mut self, ctx: &egui::Context, scene: &Scene) {
        self.ask(
            ctx,
            Ask::Julia2d {
                scene: scene.clone(),
            },
        );
    }

    fn ask(&mut self, ctx: &egui::Context, ask: Ask) {
        if !self.waker_set {
            let ctx = ctx.clone();
            self.thread
                .set_waker(Box::new(move || ctx.request_repaint()));
            self.waker_set = true;
        }
        let number = self.thread.ask(ask.clone());
        self.asked = Some((number, ask));
        self.refresh();
    }

    /// Takes what the thread published last, if it is this view's: its image into the texture.
    fn refresh(&mut self) {
        let shown = self.thread.shown();
        if shown.julia2d != self.julia2d {
            return;
        }
        if let Some(image) = &shown.image
            && self.uploaded != Some((image.generation, image.size))
        {
            if self.uploaded.is_none_or(|(_, size)| size != image.size) {
                self.textures.resize(Quality::Full, image.size);
            }
            let queue = &self.queue;
            self.textures
                .write(Quality::Full, queue, &image.colour, image.size);
            self.uploaded = Some((image.generation, image.size));
        }
        self.shown = shown;
    }

    /// Gives back the texture (the view is not shown).
    pub fn release(&mut self) {
        self.textures.release();
        self.uploaded = None;
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let (_, size) = self.uploaded?;
        Some((self.textures.texture_id(Quality::Full)?, size))
    }

    /// Whether what the thread published is of the last ask.
    fn current(&self) -> bool {
        self.asked
            .as_ref()
            .is_some_and(|(n, _)| *n == self.shown.ask)
    }

    /// Whether the view still has work to do (the last ask not yet done).
    pub fn busy(&self) -> bool {
        !self.current() || self.shown.busy
    }

    /// Whether the view shows the full-resolution image of exactly `scene` at `size` (the 2D
    /// view: `scene` at its image's size).
    pub fn is_refined(&self, scene: &Scene, size: [u32; 2]) -> bool {
        let asked = match &self.asked {
            Some((
                _,
                Ask::Slice {
                    scene: s, size: z, ..
                },
            )) => s == scene && *z == size,
            Some((_, Ask::Julia2d { scene: s })) => s == scene,
            None => false,
        };
        let uploaded =
            self.shown.image.as_ref().map(|i| i.generation) == self.uploaded.map(|(g, _)| g);
        asked && self.current() && self.shown.refined && uploaded
    }

    /// Why the view cannot run here, where it cannot.
    pub fn error(&self) -> Option<&str> {
        self.shown.error.as_deref()
    }

    pub fn stats(&self) -> &TextureStats {
        &self.shown.stats
    }

    /// Whether the view waits for its pipeline to be built.
    pub fn building_pipeline(&self) -> bool {
        self.shown.building_pipeline
    }

    /// The precision of the view shown, and why (the status line's hover text).
    pub fn precision(&self) -> Precision {
        self.shown.precision
    }

    pub fn precision_note(&self) -> &str {
        &self.shown.precision_note
    }

    /// Whether the 3D view shown is path traced, and why path mode cannot run here if it was
    /// asked for and cannot.
    pub fn path_traced(&self) -> bool {
        self.shown.path_traced
    }

    pub fn path_unavailable(&self) -> Option<&str> {
        self.shown.path_unavailable.as_deref()
    }

    /// Tiles dispatched by the 3D views since they were made, and images they encoded on the
    /// host (path mode).
    pub fn dispatches(&self) -> u64 {
        self.shown.dispatches
    }

    pub fn encodes(&self) -> u64 {
        self.shown.encodes
    }

    /// Path mode, or with a denoiser: the mean of the image shown.
    pub fn kept_radiance(&self) -> Option<&KeptRadiance> {
        self.shown.kept.as_deref()
    }

    /// When the render of the image shown began.
    pub fn shown_began(&self) -> Option<Instant> {
        self.shown.began
    }

    /// The 2D view: seconds its last render took.
    pub fn render_seconds(&self) -> f64 {
        self.shown.render_seconds
    }
}
