//! The central panel: the view, on whole physical pixels, showing the tracer's texture (or a
//! step view's heat map, or in 2D mode the 2D Julia set), with the mouse on it (`input`). The
//! [`Viewport`] owns what draws it: the device's kernels and the GPU views on them.

use std::sync::Arc;

use super::heat_texture::HeatTexture;
use super::input;
use super::slice_texture::{Julia2dTexture, SliceTexture, Slot, ThreadView, presenter};
use super::state::Mode;
use crate::heatmap::Legend;
use crate::precision::PrecisionChoice;
use crate::render::progressive::spans::span;
use crate::render::progressive::view_thread::ViewThread;
use crate::render::{Backend, Planner};
use crate::scene::{Scene, View};

/// The whole texture.
const FULL_UV: egui::Rect = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));

/// How often the UI draws while the view works and publishes nothing new (a new image is
/// drawn at once: the view thread wakes the UI): a safety net, should a wake be missed.
const HEARTBEAT: std::time::Duration = std::time::Duration::from_millis(500);

/// How the view is drawn, besides the scene.
#[derive(Clone, Copy, Debug)]
pub struct ViewOptions {
    pub mode: Mode,
    /// Resolution of the view relative to the panel's pixels.
    pub resolution_scale: f32,
    /// Samples the idle view accumulates.
    pub preview_samples: u32,
    /// The scene changes by itself (c's loop or the timeline playing): the view renders as
    /// while the user drags.
    pub playing: bool,
}

/// The view: the GPU views on the UI's device, and where it was drawn.
pub struct Viewport {
    pub slice_texture: Option<SliceTexture>,
    /// The 2D mode's renderer (the render2d kernel).
    pub julia2d_texture: Option<Julia2dTexture>,
    heat: Option<HeatTexture>,
    /// The views' thread, whose device's kernels the exports run on (None without a GPU).
    thread: Option<Arc<ViewThread>>,
    gpu_error: Option<String>,
    pub adapter_label: String,
    /// The view's size in pixels last frame, and where it was drawn (in points).
    pub pixels: [u32; 2],
    pub rect: egui::Rect,
    /// What the view was last asked to show, and when this frame asked for something new
    /// because of the user's input (the input latency's start, `QJULIA_EXPLORE_LOG=frames`).
    asked: Option<(Mode, Scene, [u32; 2])>,
    pub input_asked: Option<std::time::Instant>,
}

impl Default for Viewport {
    fn default() -> Self {
        Self {
            slice_texture: None,
            julia2d_texture: None,
            heat: None,
            thread: None,
            gpu_error: None,
            adapter_label: String::new(),
            pixels: [0, 0],
            rect: egui::Rect::NOTHING,
            asked: None,
            input_asked: None,
        }
    }
}

impl Viewport {
    /// Puts the views on the view thread ([`ViewThread`]: a device of their own on the
    /// window's adapter, made on the thread; the UI's thread runs no tile, and the window's
    /// submissions never wait behind the views' nor theirs behind the window's); their images
    /// are drawn through the window's renderer. The exports run on the views' device too.
    pub fn attach_gpu(&mut self, rs: &egui_wgpu::RenderState) {
        let info = rs.adapter.get_info();
        self.adapter_label = crate::gpu::adapter_label(&info);
        let thread = Arc::new(ViewThread::start(info));
        let slots: [Arc<std::sync::Mutex<Slot>>; 2] = Default::default();
        thread.set_presenter(presenter(rs.queue.clone(), slots.clone()));
        let window = (rs.device.clone(), rs.queue.clone());
        let renderer = rs.renderer.clone();
        let [slice, julia2d] = slots;
        self.slice_texture = Some(SliceTexture::new(
            thread.clone(),
            (false, slice),
            window.clone(),
            renderer.clone(),
        ));
        self.julia2d_texture = Some(Julia2dTexture::new(
            thread.clone(),
            (true, julia2d),
            window,
            renderer,
        ));
        self.thread = Some(thread);
    }

    /// Why there is no GPU view (shown in its place).
    pub fn no_gpu_because(&mut self, why: String) {
        self.gpu_error = Some(why);
    }

    /// The same GPU views, for a new scene: the heat map and the view's layout start afresh.
    pub fn for_new_scene(self) -> Self {
        Self {
            slice_texture: self.slice_texture,
            julia2d_texture: self.julia2d_texture,
            thread: self.thread,
            gpu_error: self.gpu_error,
            adapter_label: self.adapter_label,
            ..Self::default()
        }
    }

    /// The planner of what the explorer writes (PNG, animation, mesh): as the command line's
    /// defaults (`--backend auto --precision auto`) decide, on the UI's device where it can,
    /// so an export is the bytes `qjulia render`, `animate` or `mesh` writes of its scene.
    pub fn planner(&self) -> Planner {
        let (backend, choice) = (Backend::Auto, PrecisionChoice::Auto);
        match self.thread.as_ref().and_then(|t| t.kernels()) {
            Some(kernels) => Planner::on_device(kernels, backend, choice),
            None => Planner::new(backend, choice),
        }
    }

    /// The scene the view shows: `scene` at the view's size, with the preview's samples.
    pub fn view_scene(&self, scene: &Scene, preview_samples: u32) -> Scene {
        let mut scene = scene.clone();
        scene.image.width = self.pixels[0];
        scene.image.height = self.pixels[1];
        scene.image.samples = preview_samples;
        scene
    }

    /// Whether the view shows the full-resolution image of `scene` (in 2D mode: the 2D view
    /// of it), with the heat map of a step view made.
    pub fn is_refined(&self, scene: &Scene, mode: Mode, preview_samples: u32) -> bool {
        let view_scene = self.view_scene(scene, preview_samples);
        if mode == Mode::Julia2d {
            return self
                .julia2d_texture
                .as_ref()
                .is_some_and(|v| v.is_refined(&view_scene, self.pixels) && !v.busy());
        }
        let Some(view) = &self.slice_texture else {
            return false;
        };
        let refined = view.is_refined(&view_scene, self.pixels);
        let stats = view.stats();
        let generation = match scene.image.view {
            View::Samples => stats.counts_generation,
            _ => stats.steps_generation,
        };
        let heat_made = scene.image.view == View::Shaded
            || self
                .heat
                .as_ref()
                .is_some_and(|h| h.is_for(scene.image.view, generation));
        refined && !view.busy() && heat_made
    }

    /// When the render of the image shown in `mode` began.
    pub fn shown_began(&self, mode: Mode) -> Option<std::time::Instant> {
        match mode {
            Mode::Slice3d => self.slice_texture.as_ref()?.shown_began(),
            Mode::Julia2d => self.julia2d_texture.as_ref()?.shown_began(),
        }
    }

    /// The legend of the step view `view` shown, if one is.
    pub fn heat_legend(&self, view: View, mode: Mode) -> Option<&Legend> {
        self.heat
            .as_ref()
            .filter(|h| mode == Mode::Slice3d && h.shows(view))
            .map(HeatTexture::legend)
    }

    /// The view, filling the panel, with mouse control of the camera (of the 2D view in 2D
    /// mode) of `scene`.
    pub fn ui(&mut self, ui: &mut egui::Ui, scene: &mut Scene, options: ViewOptions) {
        // Whole physical pixels, so that each texel lands on one screen pixel.
        let ppp_screen = ui.ctx().pixels_per_point();
        let snap = |p: egui::Pos2| {
            egui::pos2((p.x * ppp_screen).round(), (p.y * ppp_screen).round()) / ppp_screen
        };
        let available = ui.available_rect_before_wrap();
        let rect = egui::Rect::from_min_max(snap(available.min), snap(available.max));
        self.rect = rect;
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point() * options.resolution_scale;
        self.pixels = [
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ];
        // The mode not shown gives its views' memory back. The mouse moves the camera (the
        // 2D view) first, so that the view is asked for this frame's picture.
        match options.mode {
            Mode::Slice3d => input::mouse_3d(ui, rect, &response, &mut scene.camera),
            Mode::Julia2d => input::mouse_2d(ui, rect, &response, &mut scene.view2d),
        }
        let view_scene = &self.view_scene(scene, options.preview_samples);
        let same = |(mode, scene, pixels): &(Mode, Scene, [u32; 2])| {
            *mode == options.mode && scene == view_scene && *pixels == self.pixels
        };
        if !self.asked.as_ref().is_some_and(same) {
            if ui.input(|i| !i.events.is_empty()) {
                self.input_asked = Some(std::time::Instant::now());
            }
            self.asked = Some((options.mode, view_scene.clone(), self.pixels));
        }
        match options.mode {
            Mode::Slice3d => {
                self.view_3d(ui, rect, &response, view_scene, options);
                if let Some(view2d) = &mut self.julia2d_texture {
                    view2d.release();
                }
            }
            Mode::Julia2d => {
                self.view_2d(ui, rect, view_scene);
                if let Some(view) = &mut self.slice_texture {
                    view.release();
                }
            }
        }
    }

    /// The 3D view of `view_scene` (the scene at the view's size and samples): the shaded
    /// picture, or a step view's heat map with its legend.
    fn view_3d(
        &mut self,
        ui: &mut egui::Ui,
        rect: egui::Rect,
        response: &egui::Response,
        view_scene: &Scene,
        options: ViewOptions,
    ) {
        let interacting =
            response.dragged() || options.playing || ui.input(|i| i.pointer.any_down());
        let Some(view) = self.slice_texture.as_mut().filter(|v| v.error().is_none()) else {
            self.no_gpu(ui, rect);
            return;
        };
        view.update(ui.ctx(), view_scene, self.pixels, interacting);
        let shown = view_scene.image.view;
        if shown == View::Shaded {
            if let Some((texture, _)) = view.texture() {
                ui.painter()
                    .image(texture, rect, FULL_UV, egui::Color32::WHITE);
            }
        } else {
            // Step views: a heat map of the steps read back from the image shown; the samples
            // view, of the samples each pixel took.
            let stats = view.stats();
            let values = match shown {
                View::Samples => stats.counts.as_ref().map(|c| (c, stats.counts_generation)),
                _ => stats.steps.as_ref().map(|s| (s, stats.steps_generation)),
            };
            if let Some(((values, size), generation)) = values {
                span("heat map", || {
                    HeatTexture::refresh(&mut self.heat, ui.ctx(), shown, values, *size, generation)
                });
            }
            if let Some(heat) = self.heat.as_ref().filter(|h| h.shows(shown)) {
                heat.paint(ui.painter(), rect);
            }
        }
        // The view thread wakes the UI when it publishes something new; until then the UI
        // draws nothing more for it (on a CPU adapter a frame of the window costs the view's
        // tracer the cores it paints on).
        if view.busy() {
            ui.ctx().request_repaint_after(HEARTBEAT);
        }
    }

    /// The 2D mode: the 2D Julia set of c in `view_scene` (the scene at the view's size).
    fn view_2d(&mut self, ui: &mut egui::Ui, rect: egui::Rect, view_scene: &Scene) {
        let Some(view2d) = self
            .julia2d_texture
            .as_mut()
            .filter(|v| v.error().is_none())
        else {
            self.no_gpu(ui, rect);
            return;
        };
        view2d.update_2d(ui.ctx(), view_scene);
        if let Some((texture, _)) = view2d.texture() {
            ui.painter()
                .image(texture, rect, FULL_UV, egui::Color32::WHITE);
        }
        if view2d.busy() {
            ui.ctx().request_repaint_after(HEARTBEAT);
        }
    }

    /// In place of the view when there is no GPU renderer: why, and what to install.
    fn no_gpu(&self, ui: &mut egui::Ui, rect: egui::Rect) {
        let thread_error = self.slice_texture.as_ref().and_then(ThreadView::error);
        let text = format!(
            "No GPU renderer: {}\n{}",
            self.gpu_error
                .as_deref()
                .or(thread_error)
                .unwrap_or("unknown error"),
            crate::error::INSTALL_ADAPTER_HINT
        );
        ui.put(rect, egui::Label::new(text));
    }
}
