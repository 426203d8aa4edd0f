//! The view's textures, which the explorer's viewport shows: the images the view thread
//! ([`ViewThread`]: the render module's live 3D and 2D views on a thread and a device of their
//! own) makes in host memory, written by its presenter into textures on the window's device that
//! egui draws ([`Slot`], [`presenter`]), and the view's figures as of that image
//! ([`ThreadView`]: the 3D view, [`SliceTexture`], and the 2D view, [`Julia2dTexture`]). The
//! UI's thread never runs a tile nor copies an image: it asks for a picture, and draws what has
//! arrived.

use std::sync::{Arc, Mutex};
use std::time::Instant;

use crate::precision::Precision;
use crate::render::progressive::host_canvas::HostFrame;
use crate::render::progressive::session::{KeptRadiance, TextureStats};
use crate::render::progressive::spans::span;
use crate::render::progressive::view_thread::{Ask, Presenter, Shown, ViewThread};
use crate::scene::Scene;

pub use crate::render::progressive::INTERACTIVE_FPS;

/// The renderer egui draws with, shared by the explorer's textures.
pub type EguiRenderer = Arc<egui::mutex::RwLock<egui_wgpu::Renderer>>;

/// A view's texture on the window's device, which egui draws, shared with the view thread's
/// presenter ([`presenter`]): the presenter writes each new image into it on the view thread,
/// and the UI's thread makes it anew only when the size changes (egui's renderer registers it).
#[derive(Default)]
pub struct Slot {
    texture: Option<(wgpu::Texture, egui::TextureId, [u32; 2])>,
    /// The number of the image in the texture.
    generation: Option<u64>,
    /// An image of another size than the texture's, for the UI's thread to make the texture.
    pending: Option<HostFrame>,
}

/// The presenter of the view thread ([`ViewThread::set_presenter`]): each new image written
/// into its view's texture (`slots`: the 3D view's, the 2D view's) on the window's `queue`, or
/// left for the UI's thread where the size changed.
pub fn presenter(queue: wgpu::Queue, slots: [Arc<Mutex<Slot>>; 2]) -> Presenter {
    Box::new(move |julia2d, image: &HostFrame| {
        let mut slot = slots[julia2d as usize].lock().unwrap();
        match &slot.texture {
            Some((texture, _, size)) if *size == image.size => {
                super::kernel_texture::write_colour(&queue, texture, &image.colour, image.size);
                slot.generation = Some(image.generation);
                slot.pending = None;
            }
            _ => slot.pending = Some(image.clone()),
        }
    })
}

/// One of the thread's views as the UI sees it: what it asked last, what the thread published
/// as of then, and that image in a texture egui draws.
pub struct ThreadView {
    thread: Arc<ViewThread>,
    /// Whether this is the 2D view.
    julia2d: bool,
    /// Its texture, and what makes one on the window's device.
    slot: Arc<Mutex<Slot>>,
    device: wgpu::Device,
    queue: wgpu::Queue,
    renderer: EguiRenderer,
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
    /// The 3D view (`julia2d`: the 2D view) of `thread`, its images in `slot`'s texture on the
    /// window's `device` and `queue`, drawn through `renderer`.
    pub fn new(
        thread: Arc<ViewThread>,
        (julia2d, slot): (bool, Arc<Mutex<Slot>>),
        (device, queue): (wgpu::Device, wgpu::Queue),
        renderer: EguiRenderer,
    ) -> Self {
        Self {
            thread,
            julia2d,
            slot,
            device,
            queue,
            renderer,
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

    /// Takes what the thread published last, if it is this view's, and makes the texture
    /// anew for an image of a new size (the presenter writes the rest on the view thread).
    fn refresh(&mut self) {
        let shown = self.thread.shown();
        if shown.julia2d != self.julia2d {
            return;
        }
        let mut slot = self.slot.lock().unwrap();
        if let Some(image) = slot.pending.take() {
            let old = slot.texture.take().map(|(_, id, _)| id);
            let renderer = &self.renderer;
            let (texture, id) = span("view texture", || {
                super::kernel_texture::native_texture(
                    &self.device,
                    renderer,
                    "view",
                    image.size,
                    old,
                )
            });
            super::kernel_texture::write_colour(&self.queue, &texture, &image.colour, image.size);
            slot.texture = Some((texture, id, image.size));
            slot.generation = Some(image.generation);
        }
        drop(slot);
        self.shown = shown;
    }

    /// Gives back the texture (the view is not shown).
    pub fn release(&mut self) {
        let mut slot = self.slot.lock().unwrap();
        slot.pending = None;
        slot.generation = None;
        if let Some((_, id, _)) = slot.texture.take() {
            self.renderer.write().free_texture(&id);
        }
    }

    /// The texture to draw and its size in pixels, once there is one.
    pub fn texture(&self) -> Option<(egui::TextureId, [u32; 2])> {
        let slot = self.slot.lock().unwrap();
        slot.generation?;
        slot.texture.as_ref().map(|(_, id, size)| (*id, *size))
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
        let generation = self.slot.lock().unwrap().generation;
        let uploaded = self.shown.image.as_ref().map(|i| i.generation) == generation;
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
