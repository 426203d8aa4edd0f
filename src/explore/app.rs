//! The explorer's state and UI: a side panel editing every scene value, the view with mouse and
//! keyboard camera control, presets, open/save/export, the animation of c, and the status line.
//! The view shows the 3D slice (shaded, or a heat map of its steps) or, in 2D mode, the 2D
//! Julia set of c's first two components, panned and zoomed by mouse.

use std::path::{Path, PathBuf};
use std::sync::Arc;
use std::sync::mpsc::{Receiver, channel};
use std::time::Instant;

use egui::{Key, Modifiers};

use super::camera;
use super::file_dialog::{FileDialog, Outcome, Purpose};
use super::view::ViewRenderer;
use super::view2d::View2dRenderer;
use crate::gpu::{GpuContext, GpuJulia2d, GpuTracer};
use crate::output::{OutputPaths, write_outputs, write_view_outputs};
use crate::render::GpuKernels;
use crate::scene::presets::PRESETS;
use crate::scene::rotation::{axis_name, plane_name, planes, rotate_basis};
use crate::scene::{Camera, Scene, SceneLoader, SceneSource, View, View2d};
use crate::views::{HeatMap, Legend};

/// Storage keys for what persists between runs (eframe also keeps the window size).
const STORAGE_SCENE: &str = "qjulia-scene";
const STORAGE_RESOLUTION: &str = "qjulia-resolution-scale";

/// Radians of orbit per point dragged, and zoom per point scrolled.
const ORBIT_PER_POINT: f64 = 0.01;
const ZOOM_PER_POINT: f64 = 0.002;

/// The keyboard shortcuts, as the help window lists them.
pub const SHORTCUTS: &[(&str, &str)] = &[
    ("Left drag", "orbit the camera about its target"),
    ("Right or middle drag", "pan"),
    ("Wheel", "zoom"),
    ("Arrow keys", "orbit in steps (in 2D: pan)"),
    ("+ / -", "zoom in / out"),
    ("R", "reset the camera (in 2D: the 2D view)"),
    ("M", "switch between the 3D view and the 2D Julia set"),
    ("Space", "play / pause the animation of c"),
    ("Ctrl+O", "open a scene (TOML or a qjulia PNG)"),
    ("Ctrl+S", "save the scene as TOML"),
    ("Ctrl+E", "export a PNG"),
    ("F1", "this help"),
    (
        "Ctrl+Q",
        "quit (the scene and window size are kept for next time)",
    ),
];

/// The animation of c: a smooth closed path through 4D around a centre.
#[derive(Clone, Debug)]
pub struct Animation {
    pub playing: bool,
    /// Radians of the path per second.
    pub speed: f64,
    /// The path's size.
    pub radius: f64,
    pub phase: f64,
    pub center: Vec<f64>,
}

impl Animation {
    /// The point of the closed path at `phase`: every component moves, with different
    /// frequencies, and the path returns to its start after 2 pi.
    pub fn point(&self, phase: f64) -> Vec<f64> {
        let r = self.radius;
        self.center
            .iter()
            .enumerate()
            .map(|(k, &c)| match k {
                0 => c + r * (phase.cos() - 1.0),
                1 => c + r * phase.sin(),
                2 => c + 0.6 * r * (2.0 * phase).sin(),
                3 => c + 0.6 * r * ((3.0 * phase).cos() - 1.0),
                // Octonion and sedenion components: smaller, each at its own frequency.
                _ => c + 0.3 * r * ((k as f64 - 2.0) * phase).sin(),
            })
            .collect()
    }
}

/// What the view shows.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Mode {
    /// The quaternion Julia set's 3D slice, as `qjulia render` draws it (any `image.view`).
    #[default]
    Slice3d,
    /// The 2D Julia set of c = c[0] + c[1] i, as `qjulia render2d` draws it.
    Julia2d,
}

/// The heat map of a step view, uploaded for egui.
struct HeatTexture {
    handle: egui::TextureHandle,
    /// The view's steps generation and the view it was made for.
    generation: u64,
    view: View,
    legend: Legend,
}

/// An export running on its own thread.
struct Export {
    path: PathBuf,
    done: Receiver<Result<(), String>>,
}

pub struct ExplorerApp {
    pub scene: Scene,
    /// The camera that "reset" returns to.
    home_camera: Camera,
    /// The slice basis the rotation angles turn, and the angles.
    base_basis: [Vec<f64>; 3],
    /// One per plane of `rotation::planes(dim)`.
    pub angles: Vec<f64>,
    pub view: Option<ViewRenderer>,
    /// The 2D mode's renderer (the render2d kernel).
    pub view2d: Option<View2dRenderer>,
    /// 3D view or 2D Julia set.
    pub mode: Mode,
    heat: Option<HeatTexture>,
    gpu_error: Option<String>,
    adapter_label: String,
    pub animation: Animation,
    /// Resolution of the view relative to the panel's pixels.
    pub resolution_scale: f32,
    dialog: Option<FileDialog>,
    last_dir: PathBuf,
    message: Option<(String, bool)>,
    show_help: bool,
    export: Option<Export>,
    last_frame: Option<Instant>,
    frame_seconds: f64,
    /// The view's size in pixels last frame, and where it was drawn (in points).
    pub view_pixels: [u32; 2],
    pub view_rect: egui::Rect,
    log_frames: u32,
    log_since: Option<Instant>,
}

impl ExplorerApp {
    /// The app on eframe's wgpu device; `initial` is the scene given on the command line,
    /// else the one persisted from the last run, else the default.
    pub fn new(cc: &eframe::CreationContext<'_>, initial: Option<Scene>) -> Self {
        let (stored_scene, resolution_scale) = load_persisted(cc.storage);
        let scene = initial.or(stored_scene).unwrap_or_default();
        let mut app = Self::with_scene(scene);
        app.resolution_scale = resolution_scale;
        match &cc.wgpu_render_state {
            Some(rs) => app.attach_gpu(rs),
            None => app.gpu_error = Some("eframe started without its wgpu renderer".into()),
        }
        app
    }

    /// Puts the tracer on the UI's device and draws the view through its renderer.
    pub fn attach_gpu(&mut self, rs: &egui_wgpu::RenderState) {
        let ctx = GpuContext {
            adapter: rs.adapter.clone(),
            device: rs.device.clone(),
            queue: rs.queue.clone(),
            info: rs.adapter.get_info(),
        };
        self.adapter_label = ctx.adapter_label();
        match GpuJulia2d::new(ctx.clone()) {
            Ok(julia) => {
                self.view2d = Some(View2dRenderer::new(Arc::new(julia), rs.renderer.clone()))
            }
            Err(e) => self.gpu_error = Some(e.to_string()),
        }
        match GpuTracer::new(ctx) {
            Ok(tracer) => {
                self.view = Some(ViewRenderer::new(Arc::new(tracer), rs.renderer.clone()))
            }
            Err(e) => self.gpu_error = Some(e.to_string()),
        }
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
            scene,
            view: None,
            view2d: None,
            mode: Mode::Slice3d,
            heat: None,
            gpu_error: None,
            adapter_label: String::new(),
            resolution_scale: 1.0,
            dialog: None,
            last_dir: std::env::current_dir().unwrap_or_else(|_| PathBuf::from(".")),
            message: None,
            show_help: false,
            export: None,
            last_frame: None,
            frame_seconds: 0.0,
            view_pixels: [0, 0],
            view_rect: egui::Rect::NOTHING,
            log_frames: 0,
            log_since: None,
        }
    }

    /// The scene the view shows: the scene at the view's size.
    pub fn view_scene(&self) -> Scene {
        let mut scene = self.scene.clone();
        scene.image.width = self.view_pixels[0];
        scene.image.height = self.view_pixels[1];
        scene
    }

    /// Whether the view shows the full-resolution image of the current scene (in 2D mode: the
    /// 2D view of it), with the heat map of a step view made.
    pub fn view_refined(&self) -> bool {
        if self.mode == Mode::Julia2d {
            return self
                .view2d
                .as_ref()
                .is_some_and(|v| v.is_refined(&self.view_scene()));
        }
        let Some(view) = &self.view else { return false };
        let refined = view.is_refined(&self.view_scene(), self.view_pixels);
        let heat_made = self.scene.image.view == View::Shaded
            || self.heat.as_ref().is_some_and(|h| {
                h.view == self.scene.image.view && h.generation == view.stats().steps_generation
            });
        refined && !view.busy() && heat_made
    }

    /// The legend of the step view shown, if one is.
    pub fn heat_legend(&self) -> Option<&Legend> {
        self.heat
            .as_ref()
            .filter(|h| self.mode == Mode::Slice3d && h.view == self.scene.image.view)
            .map(|h| &h.legend)
    }

    /// Replaces the scene (a preset, a file): camera home, rotation and animation follow it.
    pub fn set_scene(&mut self, scene: Scene) {
        let resolution = self.resolution_scale;
        let (view, view2d, mode) = (self.view.take(), self.view2d.take(), self.mode);
        let (gpu_error, adapter) = (
            self.gpu_error.take(),
            std::mem::take(&mut self.adapter_label),
        );
        let (dir, dialog) = (self.last_dir.clone(), self.dialog.take());
        *self = Self {
            view,
            view2d,
            mode,
            gpu_error,
            adapter_label: adapter,
            resolution_scale: resolution,
            last_dir: dir,
            dialog,
            ..Self::with_scene(scene)
        };
    }

    /// The message shown in the status line, and whether it is an error.
    pub fn message(&self) -> Option<(&str, bool)> {
        self.message.as_ref().map(|(m, e)| (m.as_str(), *e))
    }

    /// Loads a scene file; on error the previous scene stays and the error is shown.
    pub fn open(&mut self, path: &Path) {
        let mut loader = SceneLoader::new();
        match loader.file(path).and_then(|()| loader.build()) {
            Ok(scene) => {
                self.set_scene(scene);
                self.message = Some((format!("opened {}", path.display()), false));
            }
            Err(e) => self.message = Some((format!("error: {e}"), true)),
        }
    }

    fn save(&mut self, path: &Path) {
        let result = std::fs::write(path, self.scene.to_toml());
        self.message = Some(match result {
            Ok(()) => (format!("saved {}", path.display()), false),
            Err(e) => (format!("error: {}: {e}", path.display()), true),
        });
    }

    /// Exports the scene at its image size through the same tracer, on another thread.
    /// Exports what the view shows, at the scene's image size through the same kernel: the 3D
    /// view (shaded or a step view, as `render`), or in 2D mode the 2D view (as `render2d`).
    fn start_export(&mut self, path: PathBuf) {
        let scene = self.scene.clone();
        let (send, done) = channel();
        let paths = OutputPaths {
            png: Some(path.clone()),
            ..Default::default()
        };
        let job: Box<dyn FnOnce() -> crate::Result<()> + Send> = match self.mode {
            Mode::Slice3d => {
                let Some(view) = &self.view else { return };
                let renderer = crate::Renderer::on_tracer(view.tracer().clone());
                Box::new(move || {
                    let shade = scene.image.view == View::Shaded;
                    let picture = crate::Picture::Slice { shade };
                    let (frame, stats) = renderer.render_frame(&scene, picture)?;
                    write_view_outputs(&paths, &frame, &stats, &scene)
                })
            }
            Mode::Julia2d => {
                let Some(view2d) = &self.view2d else { return };
                let kernels = GpuKernels::with(None, Some(view2d.julia().clone()));
                let renderer = crate::Renderer::gpu(Arc::new(kernels));
                Box::new(move || {
                    let (frame, stats) = renderer.render_frame(&scene, crate::Picture::Julia2d)?;
                    write_outputs(&paths, &frame, &stats, &scene)
                })
            }
        };
        std::thread::spawn(move || {
            send.send(job().map_err(|e| e.to_string())).ok();
        });
        self.export = Some(Export { path, done });
    }

    fn poll_export(&mut self) {
        let Some(export) = &self.export else { return };
        if let Ok(result) = export.done.try_recv() {
            self.message = Some(match result {
                Ok(()) => (format!("exported {}", export.path.display()), false),
                Err(e) => (format!("error: export failed: {e}"), true),
            });
            self.export = None;
        }
    }

    fn open_dialog(&mut self, purpose: Purpose) {
        let name = match purpose {
            Purpose::OpenScene => "",
            Purpose::SaveScene => "scene.toml",
            Purpose::ExportPng => "qjulia.png",
        };
        self.dialog = Some(FileDialog::new(purpose, &self.last_dir, name));
    }

    /// Switches the algebra (c, slice and offset cut or padded), the rotation starting afresh.
    fn set_algebra(&mut self, algebra: crate::scene::Algebra) {
        self.scene.set_algebra(algebra);
        self.base_basis = [
            self.scene.slice.x.clone(),
            self.scene.slice.y.clone(),
            self.scene.slice.z.clone(),
        ];
        self.angles = vec![0.0; planes(algebra.dim()).len()];
        self.animation.center = self.scene.fractal.c.clone();
    }

    fn apply_rotation(&mut self) {
        let [x, y, z] = rotate_basis(&self.base_basis, &self.angles);
        self.scene.slice.x = x;
        self.scene.slice.y = y;
        self.scene.slice.z = z;
    }

    fn shortcuts(&mut self, ctx: &egui::Context) {
        if ctx.egui_wants_keyboard_input() {
            return;
        }
        let cmd = Modifiers::COMMAND;
        let (open, save, export) = ctx.input_mut(|i| {
            (
                i.consume_key(cmd, Key::O),
                i.consume_key(cmd, Key::S),
                i.consume_key(cmd, Key::E),
            )
        });
        if open {
            self.open_dialog(Purpose::OpenScene);
        }
        if save {
            self.open_dialog(Purpose::SaveScene);
        }
        if export {
            self.open_dialog(Purpose::ExportPng);
        }
        ctx.input(|i| {
            if i.key_pressed(Key::M) {
                self.mode = match self.mode {
                    Mode::Slice3d => Mode::Julia2d,
                    Mode::Julia2d => Mode::Slice3d,
                };
            }
            if i.key_pressed(Key::F1) {
                self.show_help = !self.show_help;
            }
            if i.key_pressed(Key::Space) {
                self.animation.playing = !self.animation.playing;
                if self.animation.playing {
                    self.animation.center = self.scene.fractal.c.clone();
                    self.animation.phase = 0.0;
                }
            }
            if self.mode == Mode::Julia2d {
                let v = &mut self.scene.view2d;
                let step = 0.1 * v.extent;
                for (key, dx, dy) in [
                    (Key::ArrowLeft, -step, 0.0),
                    (Key::ArrowRight, step, 0.0),
                    (Key::ArrowUp, 0.0, step),
                    (Key::ArrowDown, 0.0, -step),
                ] {
                    if i.key_pressed(key) {
                        v.center[0] += dx;
                        v.center[1] += dy;
                    }
                }
                if i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals) {
                    v.extent = clamp_extent(v.extent * 0.8);
                }
                if i.key_pressed(Key::Minus) {
                    v.extent = clamp_extent(v.extent / 0.8);
                }
                if i.key_pressed(Key::R) {
                    *v = View2d::default();
                }
                return;
            }
            let cam = &mut self.scene.camera;
            let step = 0.1;
            if i.key_pressed(Key::ArrowLeft) {
                camera::orbit(cam, -step, 0.0);
            }
            if i.key_pressed(Key::ArrowRight) {
                camera::orbit(cam, step, 0.0);
            }
            if i.key_pressed(Key::ArrowUp) {
                camera::orbit(cam, 0.0, step);
            }
            if i.key_pressed(Key::ArrowDown) {
                camera::orbit(cam, 0.0, -step);
            }
            if i.key_pressed(Key::Plus) || i.key_pressed(Key::Equals) {
                camera::zoom(cam, 0.9);
            }
            if i.key_pressed(Key::Minus) {
                camera::zoom(cam, 1.0 / 0.9);
            }
            if i.key_pressed(Key::R) {
                *cam = self.home_camera.clone();
            }
        });
    }

    fn menu_bar(&mut self, ui: &mut egui::Ui) {
        egui::MenuBar::new().ui(ui, |ui| {
            ui.menu_button("File", |ui| {
                if ui.button("Open scene…  (Ctrl+O)").clicked() {
                    self.open_dialog(Purpose::OpenScene);
                }
                if ui.button("Save scene…  (Ctrl+S)").clicked() {
                    self.open_dialog(Purpose::SaveScene);
                }
                if ui.button("Export PNG…  (Ctrl+E)").clicked() {
                    self.open_dialog(Purpose::ExportPng);
                }
            });
            ui.menu_button("Presets", |ui| {
                for preset in PRESETS {
                    if ui.button(preset.name).on_hover_text(preset.about).clicked() {
                        self.set_scene(preset.scene());
                        self.mode = if preset.two_d {
                            Mode::Julia2d
                        } else {
                            Mode::Slice3d
                        };
                        self.message = Some((format!("preset: {}", preset.name), false));
                    }
                }
            });
            ui.menu_button("View", |ui| {
                ui.radio_value(&mut self.mode, Mode::Slice3d, "3D slice");
                ui.radio_value(&mut self.mode, Mode::Julia2d, "2D Julia set  (M)");
                ui.separator();
                if ui.button("Reset camera  (R)").clicked() {
                    self.scene.camera = self.home_camera.clone();
                }
                if ui.button("Help  (F1)").clicked() {
                    self.show_help = true;
                }
            });
        });
    }

    fn controls(&mut self, ui: &mut egui::Ui) {
        egui::ScrollArea::vertical().show(ui, |ui| {
            ui.horizontal(|ui| {
                ui.label("Show");
                ui.selectable_value(&mut self.mode, Mode::Slice3d, "3D slice");
                ui.selectable_value(&mut self.mode, Mode::Julia2d, "2D Julia set");
            });
            match self.mode {
                Mode::Slice3d => {
                    egui::ComboBox::from_label("view")
                        .selected_text(self.scene.image.view.name())
                        .show_ui(ui, |ui| {
                            for view in View::ALL {
                                ui.selectable_value(&mut self.scene.image.view, view, view.name());
                            }
                        });
                }
                Mode::Julia2d => {
                    egui::CollapsingHeader::new("2D view")
                        .default_open(true)
                        .show(ui, |ui| self.view2d_controls(ui));
                }
            }
            egui::CollapsingHeader::new("Fractal")
                .default_open(true)
                .show(ui, |ui| self.fractal_controls(ui));
            egui::CollapsingHeader::new("Slice (4D)")
                .default_open(true)
                .show(ui, |ui| self.slice_controls(ui));
            egui::CollapsingHeader::new("Animation")
                .default_open(true)
                .show(ui, |ui| self.animation_controls(ui));
            egui::CollapsingHeader::new("Camera").show(ui, |ui| self.camera_controls(ui));
            egui::CollapsingHeader::new("Light and shading")
                .show(ui, |ui| self.shading_controls(ui));
            egui::CollapsingHeader::new("Image").show(ui, |ui| self.image_controls(ui));
        });
    }

    fn fractal_controls(&mut self, ui: &mut egui::Ui) {
        let mut algebra = self.scene.fractal.algebra;
        egui::ComboBox::from_label("algebra")
            .selected_text(algebra.name())
            .show_ui(ui, |ui| {
                for a in crate::scene::Algebra::ALL {
                    ui.selectable_value(&mut algebra, a, a.name());
                }
            });
        if algebra != self.scene.fractal.algebra {
            self.set_algebra(algebra);
        }
        let f = &mut self.scene.fractal;
        for k in 0..f.c.len() {
            let name = format!("c {}", axis_name(k));
            ui.add(egui::Slider::new(&mut f.c[k], -1.5..=1.5).text(name));
        }
        // c as a direction on the unit sphere of the algebra and a magnitude.
        let magnitude = f.c.iter().map(|v| v * v).sum::<f64>().sqrt();
        let direction: Vec<f64> = if magnitude > 0.0 {
            f.c.iter().map(|v| v / magnitude).collect()
        } else {
            (0..f.c.len())
                .map(|k| if k == 0 { 1.0 } else { 0.0 })
                .collect()
        };
        let mut angles = hyperspherical(&direction);
        let mut new_magnitude = magnitude;
        let mut turned = false;
        ui.add(egui::Slider::new(&mut new_magnitude, 0.0..=2.0).text("|c|"));
        let last = angles.len() - 1;
        for (k, angle) in angles.iter_mut().enumerate() {
            let range = if k == last {
                -std::f64::consts::PI..=std::f64::consts::PI
            } else {
                0.0..=std::f64::consts::PI
            };
            turned |= ui
                .add(egui::Slider::new(angle, range).text(format!("c angle {}", k + 1)))
                .changed();
        }
        if turned || new_magnitude != magnitude {
            let dir = if turned {
                from_hyperspherical(&angles)
            } else {
                direction
            };
            f.c = dir.iter().map(|v| v * new_magnitude).collect();
        }
        ui.add(
            egui::Slider::new(&mut f.max_iterations, 1..=200)
                .logarithmic(true)
                .text("max iterations"),
        );
        ui.add(
            egui::Slider::new(&mut f.epsilon, 1e-5..=0.1)
                .logarithmic(true)
                .text("epsilon"),
        );
        ui.add(
            egui::Slider::new(&mut f.escape_radius_squared, 4.0..=1e6)
                .logarithmic(true)
                .text("escape radius²"),
        );
        ui.add(
            egui::Slider::new(&mut f.bounding_radius_squared, 0.5..=16.0).text("bounding radius²"),
        );
        ui.add(
            egui::Slider::new(&mut f.max_steps, 1..=5000)
                .logarithmic(true)
                .text("max steps"),
        );
        ui.add(
            egui::Slider::new(&mut f.step_scale, 0.5..=2.0).text("step scale (over-relaxation)"),
        );
        ui.add(
            egui::Slider::new(&mut f.pixel_epsilon, 0.0..=4.0).text("epsilon in pixels (0 = off)"),
        );
        egui::ComboBox::from_label("tracing")
            .selected_text(f.tracing.name())
            .show_ui(ui, |ui| {
                for tracing in crate::scene::Tracing::ALL {
                    ui.selectable_value(&mut f.tracing, tracing, tracing.name());
                }
            });
    }

    fn view2d_controls(&mut self, ui: &mut egui::Ui) {
        let c = &self.scene.fractal.c;
        ui.label(format!("c = {:.4} {:+.4} i (c real, c i)", c[0], c[1]));
        let v = &mut self.scene.view2d;
        let speed = 0.002 * v.extent;
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut v.center[0]).speed(speed));
            ui.label("centre real");
        });
        ui.horizontal(|ui| {
            ui.add(egui::DragValue::new(&mut v.center[1]).speed(speed));
            ui.label("centre imaginary");
        });
        ui.add(
            egui::Slider::new(&mut v.extent, MIN_EXTENT..=MAX_EXTENT)
                .logarithmic(true)
                .text("extent (width)"),
        );
        ui.add(
            egui::Slider::new(&mut v.max_iterations, 1..=5000)
                .logarithmic(true)
                .text("2D iterations"),
        );
        ui.label("Drag to pan, wheel to zoom about the pointer.");
        if ui.button("Reset 2D view (R)").clicked() {
            *v = View2d::default();
        }
    }

    fn slice_controls(&mut self, ui: &mut egui::Ui) {
        let mut turned = false;
        let dim = self.scene.fractal.algebra.dim();
        let angles = &mut self.angles;
        egui::ScrollArea::vertical()
            .id_salt("rotation planes")
            .max_height(260.0)
            .show(ui, |ui| {
                for (angle, plane) in angles.iter_mut().zip(planes(dim)) {
                    let slider =
                        egui::Slider::new(angle, -std::f64::consts::PI..=std::f64::consts::PI);
                    turned |= ui
                        .add(slider.text(format!("turn {}", plane_name(plane))))
                        .changed();
                }
            });
        if ui.button("Reset rotation").clicked() {
            self.angles.iter_mut().for_each(|a| *a = 0.0);
            turned = true;
        }
        if turned {
            self.apply_rotation();
        }
        for k in 0..self.scene.slice.offset.len() {
            let name = format!("offset {}", axis_name(k));
            ui.add(egui::Slider::new(&mut self.scene.slice.offset[k], -1.5..=1.5).text(name));
        }
    }

    fn animation_controls(&mut self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let label = if self.animation.playing {
                "Pause"
            } else {
                "Play"
            };
            if ui.button(label).clicked() {
                self.animation.playing = !self.animation.playing;
                if self.animation.playing {
                    self.animation.center = self.scene.fractal.c.clone();
                    self.animation.phase = 0.0;
                }
            }
            ui.label("c moves on a closed 4D path");
        });
        ui.add(
            egui::Slider::new(&mut self.animation.speed, 0.02..=3.0)
                .logarithmic(true)
                .text("speed (rad/s)"),
        );
        ui.add(
            egui::Slider::new(&mut self.animation.radius, 0.005..=0.5)
                .logarithmic(true)
                .text("path size"),
        );
    }

    fn camera_controls(&mut self, ui: &mut egui::Ui) {
        let cam = &mut self.scene.camera;
        ui.add(egui::Slider::new(&mut cam.fov_y_degrees, 1.0..=170.0).text("field of view (°)"));
        ui.label(format!(
            "eye    {:.3} {:.3} {:.3}",
            cam.eye[0], cam.eye[1], cam.eye[2]
        ));
        ui.label(format!(
            "target {:.3} {:.3} {:.3}",
            cam.target[0], cam.target[1], cam.target[2]
        ));
        if ui.button("Reset camera (R)").clicked() {
            *cam = self.home_camera.clone();
        }
    }

    fn shading_controls(&mut self, ui: &mut egui::Ui) {
        for (k, name) in ["light x", "light y", "light z"].iter().enumerate() {
            ui.add(egui::Slider::new(&mut self.scene.light.position[k], -6.0..=6.0).text(*name));
        }
        let sh = &mut self.scene.shading;
        ui.checkbox(&mut sh.shadows, "shadows");
        ui.add(egui::Slider::new(&mut sh.shadow_factor, 0.0..=1.0).text("shadow factor"));
        ui.horizontal(|ui| {
            colour_edit(ui, &mut sh.diffuse);
            ui.label("diffuse");
            colour_edit(ui, &mut sh.background);
            ui.label("background");
        });
        ui.add(egui::Slider::new(&mut sh.normal_tint, 0.0..=1.0).text("normal tint"));
        ui.add(egui::Slider::new(&mut sh.specular, 0.0..=2.0).text("specular"));
        ui.add(
            egui::Slider::new(&mut sh.shininess, 0.0..=200.0)
                .logarithmic(true)
                .text("shininess"),
        );
        egui::ComboBox::from_label("normal")
            .selected_text(sh.normal.name())
            .show_ui(ui, |ui| {
                for method in crate::scene::NormalMethod::ALL {
                    ui.selectable_value(&mut sh.normal, method, method.name());
                }
            });
        ui.add(
            egui::Slider::new(&mut sh.normal_delta, 1e-6..=1e-2)
                .logarithmic(true)
                .text("normal delta"),
        );
    }

    fn image_controls(&mut self, ui: &mut egui::Ui) {
        ui.label("Exported image size:");
        ui.add(
            egui::Slider::new(&mut self.scene.image.width, 1..=8192)
                .logarithmic(true)
                .text("width"),
        );
        ui.add(
            egui::Slider::new(&mut self.scene.image.height, 1..=8192)
                .logarithmic(true)
                .text("height"),
        );
        ui.add(
            egui::Slider::new(&mut self.resolution_scale, 0.25..=2.0).text("view resolution scale"),
        );
    }

    /// One line of fixed height (a status bar that changed height would resize the view).
    fn status(&self, ui: &mut egui::Ui) {
        ui.horizontal(|ui| {
            let fps = if self.frame_seconds > 0.0 {
                1.0 / self.frame_seconds
            } else {
                0.0
            };
            ui.label(format!(
                "{:.1} ms/frame ({fps:.0} fps)",
                self.frame_seconds * 1e3
            ));
            if self.mode == Mode::Julia2d {
                if let Some(view2d) = &self.view2d {
                    let v = &self.scene.view2d;
                    ui.separator();
                    ui.label(format!(
                        "2D at {:.6} {:+.6} i, extent {:.3e}",
                        v.center[0], v.center[1], v.extent
                    ));
                    ui.label(format!("render {:.0} ms", view2d.render_seconds * 1e3));
                }
            } else if let Some(view) = &self.view {
                let s = view.stats();
                ui.separator();
                ui.label(format!(
                    "{}x{} at scale {:.2}{}",
                    s.size[0],
                    s.size[1],
                    s.scale,
                    if s.refined { "" } else { " (preview)" }
                ));
                ui.label(format!("render {:.0} ms", s.render_seconds * 1e3));
                match s.summary {
                    Some(sum) => ui.label(format!(
                        "steps mean {:.1} max {}",
                        sum.steps_mean, sum.steps_max
                    )),
                    _ => ui.label("steps …"),
                };
            }
            ui.separator();
            ui.label(&self.adapter_label);
            if self.export.is_some() {
                ui.separator();
                ui.spinner();
                ui.label("exporting…");
            }
            if let Some((text, is_error)) = &self.message {
                ui.separator();
                if *is_error {
                    ui.colored_label(ui.visuals().error_fg_color, text);
                } else {
                    ui.label(text);
                }
            }
        });
    }

    /// The view: the tracer's texture (or a step view's heat map, or in 2D mode the 2D Julia
    /// set), filling the panel, with mouse control of the camera (of the 2D view in 2D mode).
    fn view(&mut self, ui: &mut egui::Ui) {
        // Whole physical pixels, so that each texel lands on one screen pixel.
        let ppp_screen = ui.ctx().pixels_per_point();
        let snap = |p: egui::Pos2| {
            egui::pos2((p.x * ppp_screen).round(), (p.y * ppp_screen).round()) / ppp_screen
        };
        let available = ui.available_rect_before_wrap();
        let rect = egui::Rect::from_min_max(snap(available.min), snap(available.max));
        self.view_rect = rect;
        let response = ui.allocate_rect(rect, egui::Sense::click_and_drag());
        let ppp = ui.ctx().pixels_per_point() * self.resolution_scale;
        self.view_pixels = [
            (rect.width() * ppp).round().max(1.0) as u32,
            (rect.height() * ppp).round().max(1.0) as u32,
        ];
        if self.mode == Mode::Julia2d {
            self.view_2d(ui, rect, &response);
            return;
        }
        let cam = &mut self.scene.camera;
        if response.dragged_by(egui::PointerButton::Primary) {
            let d = response.drag_delta();
            camera::orbit(
                cam,
                d.x as f64 * ORBIT_PER_POINT,
                d.y as f64 * ORBIT_PER_POINT,
            );
        }
        if response.dragged_by(egui::PointerButton::Secondary)
            || response.dragged_by(egui::PointerButton::Middle)
        {
            let d = response.drag_delta();
            let h = rect.height().max(1.0) as f64;
            camera::pan(cam, -d.x as f64 / h, d.y as f64 / h);
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y) as f64;
            if scroll != 0.0 {
                camera::zoom(cam, (-scroll * ZOOM_PER_POINT).exp());
            }
        }
        let interacting =
            response.dragged() || self.animation.playing || ui.input(|i| i.pointer.any_down());
        let view_scene = self.view_scene();
        let Some(view) = &mut self.view else {
            self.no_gpu(ui, rect);
            return;
        };
        view.update(&view_scene, self.view_pixels, interacting);
        let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
        let shown = self.scene.image.view;
        if shown == View::Shaded {
            if let Some((texture, _)) = view.texture() {
                ui.painter().image(texture, rect, uv, egui::Color32::WHITE);
            }
        } else {
            // Step views: a heat map of the steps read back from the image shown.
            let stats = view.stats();
            if let Some((steps, size)) = &stats.steps {
                let fresh = self
                    .heat
                    .as_ref()
                    .is_some_and(|h| h.generation == stats.steps_generation && h.view == shown);
                if let (false, Some(map)) = (
                    fresh,
                    crate::views::heat_map_of(shown, steps, size[0], size[1]),
                ) {
                    let HeatMap { rgb, legend, .. } = map;
                    let image =
                        egui::ColorImage::from_rgb([size[0] as usize, size[1] as usize], &rgb);
                    let options = egui::TextureOptions::NEAREST;
                    let handle = match self.heat.take() {
                        Some(mut h) => {
                            h.handle.set(image, options);
                            h.handle
                        }
                        None => ui.ctx().load_texture("qjulia-heat-map", image, options),
                    };
                    self.heat = Some(HeatTexture {
                        handle,
                        generation: stats.steps_generation,
                        view: shown,
                        legend,
                    });
                }
            }
            if let Some(heat) = self.heat.as_ref().filter(|h| h.view == shown) {
                ui.painter()
                    .image(heat.handle.id(), rect, uv, egui::Color32::WHITE);
                draw_legend(ui.painter(), rect, &heat.legend);
            }
        }
        if view.busy() {
            ui.ctx().request_repaint();
        }
    }

    /// The 2D mode: the 2D Julia set of c, drag to pan, wheel to zoom about the pointer.
    fn view_2d(&mut self, ui: &mut egui::Ui, rect: egui::Rect, response: &egui::Response) {
        let v = &mut self.scene.view2d;
        // Complex units per point: the texture fills the rect, extent across its width.
        let per_point = v.extent / rect.width().max(1.0) as f64;
        if response.dragged() {
            let d = response.drag_delta();
            v.center[0] -= d.x as f64 * per_point;
            v.center[1] += d.y as f64 * per_point;
        }
        if response.hovered() {
            let scroll = ui.input(|i| i.smooth_scroll_delta.y) as f64;
            if scroll != 0.0 {
                let extent = clamp_extent(v.extent * (-scroll * ZOOM_PER_POINT).exp());
                let factor = extent / v.extent;
                if let Some(p) = response.hover_pos() {
                    // The point under the pointer stays there.
                    let under = [
                        v.center[0] + (p.x - rect.center().x) as f64 * per_point,
                        v.center[1] - (p.y - rect.center().y) as f64 * per_point,
                    ];
                    for (centre, under) in v.center.iter_mut().zip(under) {
                        *centre = under - (under - *centre) * factor;
                    }
                }
                v.extent = extent;
            }
        }
        let scene = self.view_scene();
        let Some(view2d) = &mut self.view2d else {
            self.no_gpu(ui, rect);
            return;
        };
        view2d.update(&scene);
        if let Some((texture, _)) = view2d.texture() {
            let uv = egui::Rect::from_min_max(egui::pos2(0.0, 0.0), egui::pos2(1.0, 1.0));
            ui.painter().image(texture, rect, uv, egui::Color32::WHITE);
        }
        if view2d.busy() || !view2d.is_refined(&scene) {
            ui.ctx().request_repaint();
        }
    }

    fn no_gpu(&self, ui: &mut egui::Ui, rect: egui::Rect) {
        let text = format!(
            "No GPU renderer: {}\n{}",
            self.gpu_error.as_deref().unwrap_or("unknown error"),
            crate::error::INSTALL_ADAPTER_HINT
        );
        ui.put(rect, egui::Label::new(text));
    }

    fn dialogs(&mut self, ctx: &egui::Context) {
        if let Some(dialog) = &mut self.dialog {
            match dialog.show(ctx) {
                Outcome::Open => {}
                Outcome::Cancelled => self.dialog = None,
                Outcome::Chosen(path) => {
                    let purpose = dialog.purpose;
                    self.last_dir = dialog.dir().to_path_buf();
                    self.dialog = None;
                    match purpose {
                        Purpose::OpenScene => self.open(&path),
                        Purpose::SaveScene => self.save(&path),
                        Purpose::ExportPng => self.start_export(path),
                    }
                }
            }
        }
        if self.show_help {
            egui::Window::new("Help")
                .open(&mut self.show_help)
                .show(ctx, |ui| {
                    egui::Grid::new("shortcuts").striped(true).show(ui, |ui| {
                        for (keys, what) in SHORTCUTS {
                            ui.strong(*keys);
                            ui.label(*what);
                            ui.end_row();
                        }
                    });
                });
        }
    }

    /// With `QJULIA_EXPLORE_LOG=1`, one line a second on stderr: frame rate and what the view
    /// shows (for measuring the explorer where no one watches it).
    fn log(&mut self, now: Instant) {
        if std::env::var_os("QJULIA_EXPLORE_LOG").is_none_or(|v| v != "1") {
            return;
        }
        self.log_frames += 1;
        let since = self.log_since.get_or_insert(now);
        let elapsed = now.duration_since(*since).as_secs_f64();
        if elapsed >= 1.0 {
            let s = self
                .view
                .as_ref()
                .map(|v| v.stats().clone())
                .unwrap_or_default();
            eprintln!(
                "explore: {:.1} fps; view {}x{}; shown {}x{} (scale {:.2}, {}) rendered in {:.0} ms, {:.0} ms after the last change",
                self.log_frames as f64 / elapsed,
                self.view_pixels[0],
                self.view_pixels[1],
                s.size[0],
                s.size[1],
                s.scale,
                if s.refined { "full" } else { "preview" },
                s.render_seconds * 1e3,
                s.since_change_seconds * 1e3,
            );
            self.log_frames = 0;
            self.log_since = Some(now);
        }
    }

    fn animate(&mut self, dt: f64) {
        if self.animation.playing {
            self.animation.phase =
                (self.animation.phase + dt * self.animation.speed) % std::f64::consts::TAU;
            self.scene.fractal.c = self.animation.point(self.animation.phase);
        }
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
        self.poll_export();
        egui::Panel::top("menu").show(ui, |ui| self.menu_bar(ui));
        egui::Panel::bottom("status").show(ui, |ui| self.status(ui));
        egui::Panel::left("controls")
            .resizable(true)
            .default_size(320.0)
            .show(ui, |ui| self.controls(ui));
        egui::CentralPanel::no_frame().show(ui, |ui| self.view(ui));
        self.dialogs(&ctx);
        self.log(now);
        if self.animation.playing || self.export.is_some() {
            ctx.request_repaint();
        }
    }
}

impl eframe::App for ExplorerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        eframe::set_value(storage, STORAGE_SCENE, &self.scene.to_toml());
        eframe::set_value(storage, STORAGE_RESOLUTION, &self.resolution_scale);
    }
}

/// What the last run left: its scene (when it still loads) and the view's resolution scale.
pub fn load_persisted(storage: Option<&dyn eframe::Storage>) -> (Option<Scene>, f32) {
    let scene = storage
        .and_then(|s| eframe::get_value::<String>(s, STORAGE_SCENE))
        .and_then(|text| {
            let mut loader = SceneLoader::new();
            loader.toml_str(&text, SceneSource::Default).ok()?;
            loader.build().ok()
        });
    let resolution = storage
        .and_then(|s| eframe::get_value::<f32>(s, STORAGE_RESOLUTION))
        .unwrap_or(1.0)
        .clamp(0.25, 2.0);
    (scene, resolution)
}

/// The 2D view's extent range in the explorer (f32 on the GPU resolves no finer).
const MIN_EXTENT: f64 = 1e-6;
const MAX_EXTENT: f64 = 64.0;

fn clamp_extent(extent: f64) -> f64 {
    extent.clamp(MIN_EXTENT, MAX_EXTENT)
}

/// A step view's legend over the bottom of the view: the colour bar from min to max, the values
/// at its ends and middle and what it counts (as the PNG's legend strip shows them).
fn draw_legend(painter: &egui::Painter, rect: egui::Rect, legend: &Legend) {
    let height = crate::views::LEGEND_HEIGHT as f32;
    let strip = egui::Rect::from_min_max(egui::pos2(rect.min.x, rect.max.y - height), rect.max);
    let [r, g, b] = crate::views::LEGEND_BACKGROUND;
    painter.rect_filled(strip, 0.0, egui::Color32::from_rgb(r, g, b));
    let (left, right) = (strip.min.x + 6.0, strip.max.x - 6.0);
    let (top, bottom) = (strip.min.y + 5.0, strip.min.y + 15.0);
    let segments = 96;
    for k in 0..segments {
        let x0 = left + (right - left) * k as f32 / segments as f32;
        let x1 = left + (right - left) * (k + 1) as f32 / segments as f32;
        let [r, g, b] = crate::views::colour_map(k as f64 / (segments - 1) as f64);
        painter.rect_filled(
            egui::Rect::from_min_max(egui::pos2(x0, top), egui::pos2(x1 + 0.5, bottom)),
            0.0,
            egui::Color32::from_rgb(r, g, b),
        );
    }
    let font = egui::FontId::proportional(12.0);
    let colour = egui::Color32::from_gray(235);
    let middle = strip.center().x;
    for (x, align, value) in [
        (left, egui::Align2::LEFT_TOP, legend.min),
        (middle, egui::Align2::CENTER_TOP, legend.mid),
        (right, egui::Align2::RIGHT_TOP, legend.max),
    ] {
        painter.line_segment(
            [egui::pos2(x, bottom), egui::pos2(x, bottom + 3.0)],
            egui::Stroke::new(1.0, colour),
        );
        painter.text(
            egui::pos2(x, bottom + 5.0),
            align,
            value.to_string(),
            font.clone(),
            colour,
        );
    }
    painter.text(
        egui::pos2(middle, bottom + 21.0),
        egui::Align2::CENTER_TOP,
        legend.title,
        font,
        colour,
    );
}

/// A colour picker for an `[f64; 3]` in [0, 1].
fn colour_edit(ui: &mut egui::Ui, colour: &mut [f64; 3]) {
    let mut rgb = colour.map(|c| c as f32);
    if ui.color_edit_button_rgb(&mut rgb).changed() {
        *colour = rgb.map(|c| (c as f64).clamp(0.0, 1.0));
    }
}

/// The n - 1 hyperspherical angles of a unit n-vector: d = (cos a1, sin a1 cos a2,
/// sin a1 sin a2 cos a3, ..., sin a1 ... sin a(n-1)), the last angle in (-pi, pi].
fn hyperspherical(d: &[f64]) -> Vec<f64> {
    let n = d.len();
    let mut angles = Vec::with_capacity(n - 1);
    for k in 0..n - 2 {
        let rest = d[k..].iter().map(|v| v * v).sum::<f64>().sqrt();
        angles.push(if rest > 0.0 {
            (d[k] / rest).clamp(-1.0, 1.0).acos()
        } else {
            0.0
        });
    }
    angles.push(d[n - 1].atan2(d[n - 2]));
    angles
}

fn from_hyperspherical(angles: &[f64]) -> Vec<f64> {
    let mut d = Vec::with_capacity(angles.len() + 1);
    let mut sines = 1.0;
    for &a in angles {
        d.push(sines * a.cos());
        sines *= a.sin();
    }
    d.push(sines);
    d
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A storage in memory, like eframe's file storage.
    #[derive(Default)]
    struct Memory(std::collections::HashMap<String, String>);

    impl eframe::Storage for Memory {
        fn get_string(&self, key: &str) -> Option<String> {
            self.0.get(key).cloned()
        }
        fn set_string(&mut self, key: &str, value: String) {
            self.0.insert(key.to_string(), value);
        }
        fn remove_string(&mut self, key: &str) {
            self.0.remove(key);
        }
        fn flush(&mut self) {}
    }

    #[test]
    fn the_scene_and_resolution_persist_between_runs() {
        let mut scene = PRESETS[3].scene();
        scene.camera.eye = [0.25, 1.5, 2.0];
        let mut app = ExplorerApp::with_scene(scene.clone());
        app.resolution_scale = 0.5;
        let mut storage = Memory::default();
        eframe::App::save(&mut app, &mut storage);
        let (restored, resolution) = load_persisted(Some(&storage));
        assert_eq!(restored, Some(scene));
        assert_eq!(resolution, 0.5);
        assert_eq!(load_persisted(None), (None, 1.0));
    }

    #[test]
    fn hyperspherical_angles_round_trip() {
        for d in [
            vec![0.5, 0.5, 0.5, 0.5],
            vec![-0.2, 0.6, 0.2, 0.2],
            vec![0.0, 0.0, -1.0, 0.0],
            vec![0.1, -0.3, 0.2, 0.0, 0.5, -0.1, 0.0, 0.7],
        ] {
            let n = d.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
            let u: Vec<f64> = d.iter().map(|v| v / n).collect();
            let back = from_hyperspherical(&hyperspherical(&u));
            for k in 0..u.len() {
                assert!((back[k] - u[k]).abs() < 1e-12, "{u:?} -> {back:?}");
            }
        }
    }

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

    #[test]
    fn the_animation_path_is_closed_and_starts_at_c() {
        let a = Animation {
            playing: true,
            speed: 1.0,
            radius: 0.1,
            phase: 0.0,
            center: vec![-0.2, 0.6, 0.2, 0.2, 0.1, 0.0, 0.0, -0.1],
        };
        assert_eq!(a.point(0.0), a.center);
        let end = a.point(std::f64::consts::TAU);
        assert!((0..8).all(|k| (end[k] - a.center[k]).abs() < 1e-12));
    }
}
