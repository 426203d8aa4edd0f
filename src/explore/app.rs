//! The explorer app and its frame loop, after egui's own pattern: what the user edits
//! ([`ExplorerState`], of which `persistence` keeps a part between runs) apart from what runs it
//! ([`Runtime`]: the view's GPU views, the export and render jobs, the dialogs and windows, the
//! status line). Each frame draws the panels, each a small function or type that takes only
//! what it edits: the menu bar (`menu`), the status line (`status`), the timeline's strip and
//! render window (`timeline::panel`), the side panel (`panels`) and the view (`viewport`), the
//! keys first (`input`), then the windows over them. What they ask of the app beyond that they
//! return as [`Command`]s, which [`ExplorerApp::apply`] carries out: the keys' at once, the
//! panels' once they are all drawn, the windows' after the frame.

use std::ops::{Deref, DerefMut};
use std::path::{Path, PathBuf};
use std::time::Instant;

use super::command::Command;
use super::export::Export;
use super::file_dialog::FileDialog;
use super::persistence::{self, load_persisted, load_persisted_timeline};
use super::slice_texture::{Julia2dTexture, SliceTexture};
use super::state::ExplorerState;
use super::status::StatusLine;
use super::timeline::job::RenderJob;
use super::timeline::model::Timeline;
use super::timeline::panel::{RenderWindow, TimelinePanel};
use super::viewport::{ViewOptions, Viewport};
use super::{input, menu, panels};
use crate::heatmap::Legend;
use crate::render::progressive::spans::span;
use crate::render::{Picture, Planner};
use crate::scene::Scene;
use crate::scene::presets::PRESETS;

pub use super::state::{DEFAULT_PREVIEW_SAMPLES, Mode};

/// What runs the explorer and is not saved: the view and its GPU views, the jobs, the dialogs
/// and windows, the status line.
#[derive(Default)]
pub struct Runtime {
    /// The view: the device's kernels and the GPU views on them, where it was drawn.
    pub viewport: Viewport,
    /// The export running.
    pub export: Option<Export>,
    /// The "Render animation…" job running.
    pub render: Option<RenderJob>,
    /// The file dialog open.
    pub dialog: Option<FileDialog>,
    pub show_help: bool,
    /// The status line: its message and the frame clock.
    pub status: StatusLine,
    /// The timeline's strip under the view.
    pub timeline_panel: TimelinePanel,
    /// The "Render animation…" window.
    pub render_window: RenderWindow,
    /// The scene file as the explorer last read or wrote it, to tell when it changed on disk.
    pub file: Option<FileStamp>,
    /// A file that changed on disk and that the user was told about: the next Save to it
    /// overwrites it.
    pub overwrite_told: Option<PathBuf>,
}

/// A file's path, modification time and length, as last read or written.
#[derive(Clone, Debug, PartialEq)]
pub struct FileStamp {
    pub path: PathBuf,
    modified: Option<std::time::SystemTime>,
    len: u64,
}

impl FileStamp {
    /// The file as it is now, where it exists.
    pub fn of(path: &Path) -> Option<Self> {
        let meta = std::fs::metadata(path).ok()?;
        Some(Self {
            path: path.to_path_buf(),
            modified: meta.modified().ok(),
            len: meta.len(),
        })
    }
}

/// The explorer: what the user edits, and what runs it. It dereferences to its
/// [`ExplorerState`], so that `app.scene` or `app.timeline` read as the state's.
pub struct ExplorerApp {
    pub state: ExplorerState,
    pub runtime: Runtime,
}

impl Deref for ExplorerApp {
    type Target = ExplorerState;

    fn deref(&self) -> &ExplorerState {
        &self.state
    }
}

impl DerefMut for ExplorerApp {
    fn deref_mut(&mut self) -> &mut ExplorerState {
        &mut self.state
    }
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
                app.state.timeline = Timeline::new(scene, animation);
                app
            }
            None => {
                let mut app = Self::with_scene(stored_scene.unwrap_or_default());
                if let Some((base, animation)) = load_persisted_timeline(cc.storage) {
                    let state = &mut app.state;
                    state.timeline = Timeline::restored(base, animation, &state.scene);
                }
                app
            }
        };
        app.state.resolution_scale = resolution_scale;
        match &cc.wgpu_render_state {
            Some(rs) => app.attach_gpu(rs),
            None => {
                let why = "eframe started without its wgpu renderer".to_string();
                app.runtime.viewport.no_gpu_because(why);
            }
        }
        app
    }

    /// Puts the tracer on the UI's device and draws the view through its renderer.
    pub fn attach_gpu(&mut self, rs: &egui_wgpu::RenderState) {
        self.runtime.viewport.attach_gpu(rs);
    }

    /// The app's state for a scene, with no GPU attached.
    pub fn with_scene(scene: Scene) -> Self {
        Self {
            state: ExplorerState::with_scene(scene),
            runtime: Runtime::default(),
        }
    }

    /// The planner of what the explorer writes (PNG, animation, mesh): as the command line's
    /// defaults (`--backend auto --precision auto`) decide, on the UI's device where it can,
    /// so an export is the bytes `qjulia render`, `animate` or `mesh` writes of its scene.
    pub fn planner(&self) -> Planner {
        self.runtime.viewport.planner()
    }

    /// The 3D view's renderer, once a GPU is attached.
    pub fn slice_texture(&self) -> Option<&SliceTexture> {
        self.runtime.viewport.slice_texture.as_ref()
    }

    /// The 2D mode's renderer, once a GPU is attached.
    pub fn julia2d_texture(&self) -> Option<&Julia2dTexture> {
        self.runtime.viewport.julia2d_texture.as_ref()
    }

    /// The view's size in pixels last frame.
    pub fn view_pixels(&self) -> [u32; 2] {
        self.runtime.viewport.pixels
    }

    /// Where the view was drawn last frame, in points.
    pub fn view_rect(&self) -> egui::Rect {
        self.runtime.viewport.rect
    }

    /// Where the timeline's strip was drawn last frame, and the x of frame 0 and of the last
    /// frame in it.
    pub fn timeline_strip(&self) -> (egui::Rect, f32, f32) {
        self.runtime.timeline_panel.strip
    }

    /// The scene the view shows: the scene at the view's size.
    pub fn view_scene(&self) -> Scene {
        let state = &self.state;
        self.runtime
            .viewport
            .view_scene(&state.scene, state.preview_samples)
    }

    /// Whether the view shows the full-resolution image of the current scene (in 2D mode: the
    /// 2D view of it), with the heat map of a step view made.
    pub fn view_refined(&self) -> bool {
        let state = &self.state;
        self.runtime
            .viewport
            .is_refined(&state.scene, state.mode, state.preview_samples)
    }

    /// The legend of the step view shown, if one is.
    pub fn heat_legend(&self) -> Option<&Legend> {
        let state = &self.state;
        self.runtime
            .viewport
            .heat_legend(state.scene.image.view, state.mode)
    }

    /// Replaces the scene (a preset, a file): camera home, rotation, c-loop and timeline follow
    /// it (what the view shows, the settings and the last folder stay). Of what runs, the GPU
    /// views, the file dialog and the "Render animation…" window and job stay; the rest starts
    /// afresh, as it always has: the status line's message and clock, the help window, the
    /// heat map, the view's layout until the next frame, the timeline's strip, and a running
    /// export (its thread still writes its file, unannounced).
    pub fn set_scene(&mut self, scene: Scene) {
        self.state = self.state.for_scene(scene);
        let old = std::mem::take(&mut self.runtime);
        // What runs goes on and is still shown: an export, a render job, the dialog.
        self.runtime = Runtime {
            viewport: old.viewport.for_new_scene(),
            export: old.export,
            dialog: old.dialog,
            render: old.render,
            render_window: old.render_window,
            file: old.file,
            overwrite_told: old.overwrite_told,
            ..Runtime::default()
        };
    }

    /// The message shown in the status line, and whether it is an error.
    pub fn message(&self) -> Option<(&str, bool)> {
        let message = self.runtime.status.message.as_ref();
        message.map(|(m, e)| (m.as_str(), *e))
    }

    /// Says `text` in the status line (`error`: as an error).
    fn tell(&mut self, text: String, error: bool) {
        self.runtime.status.message = Some((text, error));
    }

    /// Whether a render job is running.
    pub fn rendering(&self) -> bool {
        self.runtime.render.is_some()
    }

    /// Adds a keyframe at the current frame from the view.
    pub fn add_key(&mut self) {
        let frame = self.state.timeline.add_key(&self.state.scene);
        self.tell(format!("keyframe at frame {frame}"), false);
    }

    /// Loads a scene file, its `[animation]` into the timeline; on error the previous scene
    /// stays and the error is shown. A new timeline starts the "Render animation…" window's
    /// frame range afresh (it was the old animation's); a job running goes on with the
    /// animation it was given, and is still shown.
    pub fn open(&mut self, path: &Path) {
        match persistence::read_scene_file(path) {
            Ok((scene, animation)) => {
                let keys = animation.keys.len();
                self.set_scene(scene.clone());
                self.runtime.file = FileStamp::of(path);
                self.runtime.overwrite_told = None;
                self.state.timeline = Timeline::new(scene, animation);
                let window = std::mem::take(&mut self.runtime.render_window);
                self.runtime.render_window = RenderWindow {
                    open: window.open,
                    dir: window.dir,
                    ..RenderWindow::default()
                };
                self.tell(
                    format!("opened {} ({keys} keyframes)", path.display()),
                    false,
                );
            }
            Err(e) => self.tell(format!("error: {e}"), true),
        }
    }

    /// Saves the scene as TOML with the timeline's `[animation]` (as `qjulia animate --scene`
    /// reads it), after checking that it reads back; a file it would refuse is not written.
    /// Where the file was opened (or last saved) here and has changed on disk since, the first
    /// Save says so and writes nothing (the view keeps the scene it shows); the next overwrites
    /// it.
    pub fn save(&mut self, path: &Path) {
        let now = FileStamp::of(path);
        let changed = self
            .runtime
            .file
            .as_ref()
            .is_some_and(|f| f.path == path && now.is_some() && now.as_ref() != Some(f));
        if changed && self.runtime.overwrite_told.as_deref() != Some(path) {
            self.runtime.overwrite_told = Some(path.to_path_buf());
            let text = format!(
                "{} changed on disk since it was opened: the view keeps its scene; Save again \
                 to overwrite the newer file",
                path.display()
            );
            self.tell(text, true);
            return;
        }
        let state = &mut self.state;
        let (text, error) = persistence::write_scene_file(&mut state.timeline, &state.scene, path);
        if !error {
            self.runtime.file = FileStamp::of(path);
            self.runtime.overwrite_told = None;
        }
        self.tell(text, error);
    }

    /// Exports what the view shows, at the scene's image size through the same kernel, on
    /// another thread: the 3D view (shaded or a step view, as `render`), or in 2D mode the 2D
    /// view (as `render2d`).
    pub fn start_export(&mut self, path: PathBuf) {
        let scene = self.state.scene.clone();
        let picture = match self.state.mode {
            Mode::Slice3d => Picture::Slice {
                shade: scene.image.view.needs_shading(),
            },
            Mode::Julia2d => Picture::Julia2d,
        };
        let export = Export::png(self.planner(), scene, picture, path);
        self.runtime.export = Some(export);
    }

    /// Exports the 3D slice's surface as a mesh at `mesh_resolution` points per axis, as
    /// `qjulia mesh` makes it (the format by the file's extension, the precision by the grid
    /// cell), on the view's GPU where it can, on another thread.
    pub fn start_mesh_export(&mut self, path: PathBuf) {
        let (scene, resolution) = (self.state.scene.clone(), self.state.mesh_resolution);
        let export = Export::mesh(self.planner(), scene, resolution, path);
        self.runtime.export = Some(export);
    }

    /// Renders frames `first..=last` (None: to the last frame) into `dir` as the *Render
    /// animation…* window's Render button does, PNG frames only.
    pub fn start_render_into(&mut self, dir: &Path, first: u32, last: Option<u32>) {
        let r = &mut self.runtime.render_window;
        r.dir = dir.display().to_string();
        r.first = first;
        r.last = last;
        r.resume = false;
        r.video.clear();
        self.start_render();
    }

    /// Starts the render job of the window's choice: the animation as its saved file reads
    /// back (checked as `animate` checks it), each frame decided as `animate` decides it, on
    /// the view's device where it can (as exports).
    fn start_render(&mut self) {
        let state = &mut self.state;
        let (_, base, animation) = match state.timeline.checked_file(&state.scene) {
            Ok(checked) => checked,
            Err(e) => {
                self.runtime.render_window.outcome = Some((format!("error: {e}"), true));
                return;
            }
        };
        let planner = self.planner();
        let window = &mut self.runtime.render_window;
        match RenderJob::start(planner, base, animation, window.request()) {
            Ok(job) => {
                window.outcome = None;
                self.runtime.render = Some(job);
            }
            Err(line) => window.outcome = Some((line, true)),
        }
    }

    /// Ends a finished render job, its outcome in the window and the status line.
    fn poll_render(&mut self) {
        let Some(job) = &self.runtime.render else {
            return;
        };
        if let Some(outcome) = job.finished() {
            let last_dir = &mut self.state.last_dir;
            *last_dir = job
                .dir()
                .parent()
                .map_or(last_dir.clone(), Path::to_path_buf);
            self.runtime.status.message = Some(outcome.clone());
            self.runtime.render_window.outcome = Some(outcome);
            self.runtime.render = None;
        }
    }

    /// Says in the status line how a finished export went.
    fn poll_export(&mut self) {
        let Some(export) = &self.runtime.export else {
            return;
        };
        if let Some(outcome) = export.finished() {
            self.runtime.status.message = Some(outcome);
            self.runtime.export = None;
        }
    }

    /// Carries out a command of the panels, menus or keys.
    pub fn apply(&mut self, command: Command) {
        let (state, runtime) = (&mut self.state, &mut self.runtime);
        match command {
            Command::OpenDialog(purpose) => {
                let name = menu::proposed_name(purpose);
                runtime.dialog = Some(FileDialog::new(purpose, &state.last_dir, name));
            }
            Command::OpenScene(path) => self.open(&path),
            Command::SaveScene(path) => self.save(&path),
            Command::ExportPng(path) => self.start_export(path),
            Command::ExportMesh(path) => self.start_mesh_export(path),
            Command::Preset(k) => {
                let preset = &PRESETS[k];
                self.set_scene(preset.scene());
                self.state.mode = if preset.two_d {
                    Mode::Julia2d
                } else {
                    Mode::Slice3d
                };
                self.tell(format!("preset: {}", preset.name), false);
            }
            Command::ResetCamera => state.scene.camera = state.home_camera.clone(),
            Command::SetAlgebra(algebra) => state.set_algebra(algebra),
            Command::ToggleCLoop => state.toggle_c_loop(),
            Command::ShowFrame(frame) => state.show_frame(frame),
            Command::ToggleTimelinePlay => state.toggle_timeline_play(),
            Command::AddKey => self.add_key(),
            Command::OpenRenderWindow => runtime.render_window.open = true,
            Command::RenderAnimation => self.start_render(),
            Command::ShowHelp => runtime.show_help = true,
            Command::ToggleHelp => runtime.show_help = !runtime.show_help,
            Command::SetEnvironment(file) => match state.set_environment(file) {
                Ok(told) => self.tell(told, false),
                Err(told) => self.tell(told, true),
            },
            Command::Tell(text, error) => self.tell(text, error),
        }
    }

    /// Carries out commands in order; whether there were any.
    fn apply_all(&mut self, commands: Vec<Command>) -> bool {
        let acted = !commands.is_empty();
        for command in commands {
            self.apply(command);
        }
        acted
    }

    /// One frame of the whole UI (eframe's `App::ui`, also driven by the tests): the keys, the
    /// view moved by wall time, the jobs polled, the panels drawn, then the windows over them.
    /// The keys' commands are carried out at once, the panels' before the windows are drawn
    /// (a window a menu opens shows in the frame of the click, as before), the windows' after
    /// the frame.
    pub fn frame(&mut self, ui: &mut egui::Ui) {
        let now = Instant::now();
        let dt = self.runtime.status.tick(now);
        let ctx = ui.ctx().clone();
        let s = &mut self.state;
        let keys = span("keys", || {
            input::shortcuts(&ctx, &mut s.mode, &mut s.scene, &s.home_camera)
        });
        let mut acted = span("commands", || self.apply_all(keys));
        self.state.advance(dt);
        span("jobs", || {
            self.poll_render();
            self.poll_export();
        });
        let panels = self.panels(ui);
        acted |= span("commands", || self.apply_all(panels));
        let windows = span("windows", || self.windows(&ctx));
        acted |= span("commands", || self.apply_all(windows));
        let mode = self.state.mode;
        self.runtime
            .status
            .log(now, &mut self.runtime.viewport, mode);
        if acted || self.state.playing() || self.runtime.export.is_some() || self.rendering() {
            ctx.request_repaint();
        }
    }

    /// The menu bar, the status line, the timeline's strip, the side panel and the view; what
    /// they ask.
    fn panels(&mut self, ui: &mut egui::Ui) -> Vec<Command> {
        let mut commands = Vec::new();
        let (s, r) = (&mut self.state, &mut self.runtime);
        span("menu", || {
            egui::Panel::top("menu").show(ui, |ui| {
                commands.extend(menu::menu_bar(ui, &mut s.mode, &mut s.mesh_resolution));
            })
        });
        span("status line", || {
            egui::Panel::bottom("status").show(ui, |ui| {
                r.status.ui(ui, &r.viewport, s, r.export.as_ref());
            })
        });
        span("timeline", || {
            egui::Panel::bottom("timeline").show(ui, |ui| {
                let panel = &mut r.timeline_panel;
                commands.extend(panel.ui(ui, &mut s.timeline, r.render.as_ref()));
            })
        });
        span("controls", || {
            egui::Panel::left("controls")
                .resizable(true)
                .default_size(320.0)
                .show(ui, |ui| commands.extend(panels::controls(ui, s)))
        });
        let options = ViewOptions {
            mode: s.mode,
            resolution_scale: s.resolution_scale,
            preview_samples: s.preview_samples,
            playing: s.playing(),
        };
        span("view", || {
            egui::CentralPanel::no_frame().show(ui, |ui| r.viewport.ui(ui, &mut s.scene, options))
        });
        commands
    }

    /// The windows over the panels: the file dialog, the help and "Render animation…"; what
    /// they ask.
    fn windows(&mut self, ctx: &egui::Context) -> Vec<Command> {
        let (s, r) = (&mut self.state, &mut self.runtime);
        let mut commands: Vec<Command> = menu::file_dialog(ctx, &mut r.dialog, &mut s.last_dir)
            .into_iter()
            .collect();
        menu::help_window(ctx, &mut r.show_help);
        let last_frame = s.timeline.last_frame();
        let render = r.render.as_ref();
        commands.extend(r.render_window.ui(ctx, last_frame, &s.last_dir, render));
        commands
    }
}

impl eframe::App for ExplorerApp {
    fn ui(&mut self, ui: &mut egui::Ui, _frame: &mut eframe::Frame) {
        self.frame(ui);
    }

    fn save(&mut self, storage: &mut dyn eframe::Storage) {
        persistence::persist(&mut self.state, storage);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::explore::persistence::Memory;

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
    fn scene_files_bring_their_keyframes_and_the_timeline_persists() {
        let mut app = ExplorerApp::with_scene(Scene::default());
        app.state.timeline.show(40, &mut app.state.scene);
        app.scene.camera.eye = [0.5, 1.0, 2.5];
        app.add_key();
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("anim.toml");
        app.save(&path);
        let saved = app.timeline.animation.clone();
        assert_eq!(saved.keys.len(), 1);

        let mut other = ExplorerApp::with_scene(PRESETS[3].scene());
        other.open(&path);
        assert_eq!(other.timeline.animation, saved);
        assert_eq!(other.timeline.base, app.timeline.base);

        let mut storage = Memory::default();
        eframe::App::save(&mut app, &mut storage);
        let (base, animation) = load_persisted_timeline(Some(&storage)).expect("persisted");
        assert_eq!(animation, saved);
        assert_eq!(base, app.timeline.base);
    }
}
