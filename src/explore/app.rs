//! The explorer's state and its frame loop. What the UI does with the state lives beside it, in
//! `impl ExplorerApp` blocks of their own: the side panel's controls (`panels`), the menu bar and
//! its windows (`menu`), keys and mouse (`input`), the view's drawing (`viewport`, with the step
//! views' heat map in `heat_texture`), the animation of c (`animation`), the keyframed
//! animation's timeline and its render (`timeline`), the status line (`status`), export
//! (`export`) and what persists (`persistence`).

use std::path::PathBuf;
use std::sync::Arc;
use std::time::Instant;

use super::animation::Animation;
use super::export::Export;
use super::file_dialog::FileDialog;
use super::heat_texture::HeatTexture;
use super::julia2d_texture::Julia2dTexture;
use super::persistence::{load_persisted, load_persisted_timeline};
use super::slice_texture::SliceTexture;
use super::timeline::Timeline;
use crate::gpu::{GpuContext, GpuKernels};
use crate::heatmap::Legend;
use crate::precision::PrecisionChoice;
use crate::render::{Backend, Planner};
use crate::scene::rotation::{planes, rotate_basis};
use crate::scene::{Camera, Scene, View};

/// Samples the idle view accumulates unless the panel says otherwise.
pub const DEFAULT_PREVIEW_SAMPLES: u32 = 64;

/// What the view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// The quaternion Julia set's 3D slice, as `qjulia render` draws it (any `image.view`).
    #[default]
    Slice3d,
    /// The 2D Julia set of c = c[0] + c[1] i, as `qjulia render2d` draws it.
    Julia2d,
}

/// The explorer: the scene being edited and what the UI keeps from frame to frame.
pub struct ExplorerApp {
    pub scene: Scene,
    /// The camera that "reset" returns to.
    pub(super) home_camera: Camera,
    /// The slice basis the rotation angles turn, and the angles.
    pub(super) base_basis: [Vec<f64>; 3],
    /// One per plane of `rotation::planes(dim)`.
    pub angles: Vec<f64>,
    pub slice_texture: Option<SliceTexture>,
    /// The 2D mode's renderer (the render2d kernel).
    pub julia2d_texture: Option<Julia2dTexture>,
    /// 3D view or 2D Julia set.
    pub mode: Mode,
    pub(super) heat: Option<HeatTexture>,
    /// The UI device's kernels: the views' and the exports' (None without a GPU).
    pub(super) kernels: Option<Arc<GpuKernels>>,
    pub(super) gpu_error: Option<String>,
    pub(super) adapter_label: String,
    pub animation: Animation,
    /// The scene's `[animation]`: keyframes, scrubbing, playing, rendering.
    pub timeline: Timeline,
    /// Resolution of the view relative to the panel's pixels.
    pub resolution_scale: f32,
    /// Samples the idle view accumulates (independent of `image.samples`, which exports use).
    pub preview_samples: u32,
    pub(super) dialog: Option<FileDialog>,
    pub(super) last_dir: PathBuf,
    pub(super) message: Option<(String, bool)>,
    pub(super) show_help: bool,
    pub(super) export: Option<Export>,
    /// Grid points per axis of "Export mesh…" (`qjulia mesh --resolution`).
    pub mesh_resolution: u32,
    last_frame: Option<Instant>,
    pub(super) frame_seconds: f64,
    /// The view's size in pixels last frame, and where it was drawn (in points).
    pub view_pixels: [u32; 2],
    pub view_rect: egui::Rect,
    pub(super) log_frames: u32,
    pub(super) log_since: Option<Instant>,
}

impl ExplorerApp {
    /// The app on eframe's wgpu device; `initial` is the scene given on the command line,
    /// else the one persisted from the last run, else the default.
    pub fn new(
        cc: &eframe::CreationContext<'_>,
        initial: Option<(Scene, crate::animation::Animation)>,
    ) -> Self {
        let (stored_scene, resolution_scale) = load_persisted(cc.storage);
        let mut app = match initial {
            Some((scene, animation)) => {
                let mut app = Self::with_scene(scene.clone());
                app.timeline = Timeline::new(scene, animation);
                app
            }
            None => {
                let mut app = Self::with_scene(stored_scene.unwrap_or_default());
                if let Some((base, animation)) = load_persisted_timeline(cc.storage) {
                    app.timeline = Timeline::restored(base, animation, &app.scene);
                }
                app
            }
        };
        app.resolution_scale = resolution_scale;
        match &cc.wgpu_render_state {
            Some(rs) => app.attach_gpu(rs),
            None => app.gpu_error = Some("eframe started without its wgpu renderer".into()),
        }
        app
    }

    /// Puts the tracer on the UI's device and draws the view through its renderer.
    pub fn attach_gpu(&mut self, rs: &egui_wgpu::RenderState) {
        let ctx = GpuContext::from_device(rs.adapter.clone(), rs.device.clone(), rs.queue.clone());
        self.adapter_label = ctx.adapter_label();
        let kernels = Arc::new(GpuKernels::new(ctx));
        match Julia2dTexture::new(kernels.clone(), rs.renderer.clone()) {
            Ok(view) => self.julia2d_texture = Some(view),
            Err(e) => self.gpu_error = Some(e.to_string()),
        }
        match SliceTexture::new(kernels.clone(), rs.renderer.clone()) {
            Ok(view) => self.slice_texture = Some(view),
            Err(e) => self.gpu_error = Some(e.to_string()),
        }
        self.kernels = Some(kernels);
    }

    /// The app's state for a scene, with no GPU attached.
    pub fn with_scene(scene: Scene) -> Self {
        Self {
            home_camera: scene.camera.clone(),
            base_basis: [
                scene.slice.x.clone(),
                scene.slice.y.clone(),
                scene.slice.z.clone(),
            ],
            angles: vec![0.0; planes(scene.fractal.algebra.dim()).len()],
            animation: Animation {
                playing: false,
                speed: 0.4,
                radius: 0.08,
                phase: 0.0,
                center: scene.fractal.c.clone(),
            },
            timeline: Timeline::new(scene.clone(), Default::default()),
            scene,
            slice_texture: None,
            julia2d_texture: None,
            mode: Mode::Slice3d,
            heat: None,
            kernels: None,
            gpu_error: None,
            adapter_label: String::new(),
            resolution_scale: 1.0,
            preview_samples: DEFAULT_PREVIEW_SAMPLES,
            dialog: None,
            last_dir: std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
            message: None,
            show_help: false,
            export: None,
            mesh_resolution: crate::mesh::DEFAULT_RESOLUTION,
            last_frame: None,
            frame_seconds: 0.0,
            view_pixels: [0, 0],
            view_rect: egui::Rect::NOTHING,
            log_frames: 0,
            log_since: None,
        }
    }

    /// The planner of what the explorer writes (PNG, animation, mesh): as the command line's
    /// defaults (`--backend auto --precision auto`) decide, on the UI's device where it can,
    /// so an export is the bytes `qjulia render`, `animate` or `mesh` writes of its scene.
    pub fn planner(&self) -> Planner {
        let (backend, choice) = (Backend::Auto, PrecisionChoice::Auto);
        match &self.kernels {
            Some(kernels) => Planner::on_device(kernels.clone(), backend, choice),
            None => Planner::new(backend, choice),
        }
    }

    /// The scene the view shows: the scene at the view's size.
    pub fn view_scene(&self) -> Scene {
        let mut scene = self.scene.clone();
        scene.image.width = self.view_pixels[0];
        scene.image.height = self.view_pixels[1];
        scene.image.samples = self.preview_samples;
        scene
    }

    /// Whether the view shows the full-resolution image of the current scene (in 2D mode: the
    /// 2D view of it), with the heat map of a step view made.
    pub fn view_refined(&self) -> bool {
        if self.mode == Mode::Julia2d {
            return self
                .julia2d_texture
                .as_ref()
                .is_some_and(|v| v.is_refined(&self.view_scene()));
        }
        let Some(view) = &self.slice_texture else {
            return false;
        };
        let refined = view.is_refined(&self.view_scene(), self.view_pixels);
        let heat_made = self.scene.image.view == View::Shaded
            || self
                .heat
                .as_ref()
                .is_some_and(|h| h.is_for(self.scene.image.view, view.stats().steps_generation));
        refined && !view.busy() && heat_made
    }

    /// The legend of the step view shown, if one is.
    pub fn heat_legend(&self) -> Option<&Legend> {
        self.heat
            .as_ref()
            .filter(|h| self.mode == Mode::Slice3d && h.shows(self.scene.image.view))
            .map(HeatTexture::legend)
    }

    /// Replaces the scene (a preset, a file): camera home, rotation and animation follow it.
    pub fn set_scene(&mut self, scene: Scene) {
        let resolution = self.resolution_scale;
        let (slice_texture, julia2d_texture, mode) = (
            self.slice_texture.take(),
            self.julia2d_texture.take(),
            self.mode,
        );
        let (kernels, gpu_error, adapter) = (
            self.kernels.take(),
            self.gpu_error.take(),
            std::mem::take(&mut self.adapter_label),
        );
        let (dir, dialog) = (self.last_dir.clone(), self.dialog.take());
        let render = std::mem::take(&mut self.timeline.render);
        *self = Self {
            slice_texture,
            julia2d_texture,
            mode,
            kernels,
            gpu_error,
            adapter_label: adapter,
            resolution_scale: resolution,
            preview_samples: self.preview_samples,
            mesh_resolution: self.mesh_resolution,
            last_dir: dir,
            dialog,
            ..Self::with_scene(scene)
        };
        self.timeline.render = render;
    }

    /// The message shown in the status line, and whether it is an error.
    pub fn message(&self) -> Option<(&str, bool)> {
        self.message.as_ref().map(|(m, e)| (m.as_str(), *e))
    }

    /// Switches the algebra (c, slice and offset cut or padded), the rotation starting afresh.
    pub(super) fn set_algebra(&mut self, algebra: crate::scene::Algebra) {
        self.scene.set_algebra(algebra);
        self.base_basis = [
            self.scene.slice.x.clone(),
            self.scene.slice.y.clone(),
            self.scene.slice.z.clone(),
        ];
        self.angles = vec![0.0; planes(algebra.dim()).len()];
        self.animation.center = self.scene.fractal.c.clone();
    }

    /// Turns the slice basis by the rotation angles.
    pub(super) fn apply_rotation(&mut self) {
        let [x, y, z] = rotate_basis(&self.base_basis, &self.angles);
        self.scene.slice.x = x;
        self.scene.slice.y = y;
        self.scene.slice.z = z;
    }

    /// One frame of the whole UI (eframe's `App::ui`, also driven by the tests).
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let now = Instant::now();
        let dt = self
            .last_frame
            .map_or(0.0, |t| now.duration_since(t).as_secs_f64())
            .min(0.25);
        self.last_frame = Some(now);
        self.frame_seconds = if self.frame_seconds == 0.0 {
            dt
        } else {
            0.9 * self.frame_seconds + 0.1 * dt
        };
        let ctx = ui.ctx().clone();
        self.shortcuts(&ctx);
        self.animate(dt);
        self.play_timeline(dt);
        self.poll_export();
        egui::Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status(ui));
        egui::Panel::bottom("timeline").show(ui, |ui| self.timeline_panel(ui));
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(320.0)
            .show(ui, |ui| self.controls(ui));
        egui::CentralPanel::no_frame().show(ui, |ui| self.view_panel(ui));
        self.dialogs(&ctx);
        self.render_window(&ctx);
        self.log(now);
        if self.animation.playing
            || self.timeline.playing
            || self.export.is_some()
            || self.rendering()
        {
            ctx.request_repaint();
        }
    }
}

impl eframe::App for ExplorerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        self.persist(storage);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn switching_the_algebra_pads_c_and_the_slice_and_rotates_in_every_plane() {
        let mut app = ExplorerApp::with_scene(Scene::default());
        app.set_algebra(crate::scene::Algebra::Octonion);
        assert_eq!(
            app.scene.fractal.c,
            vec![-0.2, 0.6, 0.2, 0.2, 0.0, 0.0, 0.0, 0.0]
        );
        assert_eq!(app.angles.len(), 28);
        // Turn i into e7: the slice's y axis leaves the quaternions.
        let p = planes(8).iter().position(|&p| p == (1, 7)).unwrap();
        app.angles[p] = std::f64::consts::FRAC_PI_2;
        app.apply_rotation();
        assert!((app.scene.slice.y[7] - 1.0).abs() < 1e-12);
        assert!(
            crate::scene::rotation::orthonormality_error(&[
                app.scene.slice.x.clone(),
                app.scene.slice.y.clone(),
                app.scene.slice.z.clone(),
            ]) < 1e-12
        );
        // Back to quaternions: cut to 4D, the basis still orthonormal.
        app.set_algebra(crate::scene::Algebra::Quaternion);
        assert_eq!(app.scene.fractal.c.len(), 4);
        assert_eq!(app.angles.len(), 6);
        assert_eq!(app.scene.slice.x.len(), 4);
    }
}
