//! The animation timeline: the scene's `[animation]` table (frame count, frames per second, c's
//! path radius, keyframes) edited in the explorer. Keyframes are added at the current frame from
//! the view, moved (by dragging their marker or by number) and deleted; the scrub strip and Play
//! show [`Animation::scene_at`] in the view; File > Save writes the scene with its animation, so
//! that `qjulia animate --scene FILE` renders exactly it; and "Render animation..." runs the
//! frames through `qjulia animate`'s own code on a thread, with progress and cancel.
//!
//! The timeline keeps the animation's base scene (the scene file's tables). The view shows the
//! base at a frame; what the user changes in the view goes back into the base when the timeline
//! next moves, saves or renders ([`Timeline::absorb`]), except the values the keyframes set,
//! which the tracks give, and c while no keyframe sets it and the user left it where the
//! timeline put it (c's closed loop is around the base's c).

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use super::app::ExplorerApp;
use crate::animate::{FrameRange, Progress};
use crate::animation::{Animation, FRAMES_MAX, FRAMES_MIN, Keyframe, get_value, scene_file};
use crate::render::Planner;
use crate::scene::schema::{self, Kind};
use crate::scene::{Scene, SceneLoader, SceneSource, Slice};

/// The values a keyframe can take from the view: what the mouse and the panel's c and slice
/// controls change.
const VIEW_PATHS: [&str; 7] = [
    "camera.eye",
    "camera.target",
    "fractal.c",
    "slice.x",
    "slice.y",
    "slice.z",
    "slice.offset",
];

/// The slice's axes, which keyframes set together.
const AXES: [&str; 3] = ["slice.x", "slice.y", "slice.z"];

/// The folder "Render animation..." proposes, in the explorer's last folder.
const DEFAULT_DIR: &str = crate::animate::DEFAULT_DIR;

/// The animation being edited, the frame shown, and the render running.
pub struct Timeline {
    /// The animation: keys sorted by frame, frame numbers unique and below `frames`.
    pub animation: Animation,
    /// The scene the animation animates (the scene file's tables, `animate`'s base).
    pub base: Scene,
    /// The frame the timeline is at.
    pub frame: u32,
    /// The scene the timeline last put in the view, to tell the user's changes from its own.
    shown: Option<Scene>,
    /// Playing the animation in the view at its frames per second.
    pub playing: bool,
    /// While playing: the frame position, fractional, advanced by wall time.
    position: f64,
    /// The selected keyframe, by frame number.
    pub selected: Option<u32>,
    /// The key whose marker is being dragged.
    dragging: Option<u32>,
    /// Where the strip was drawn last frame, and the x of frame 0 and of the last frame in it.
    pub strip: (egui::Rect, f32, f32),
    /// The "Render animation..." window and its job.
    pub(super) render: RenderWindow,
}

impl Timeline {
    /// The timeline of `animation` over `base`, at frame 0.
    pub fn new(base: Scene, animation: Animation) -> Self {
        let mut timeline = Self {
            animation,
            base,
            frame: 0,
            shown: None,
            playing: false,
            position: 0.0,
            selected: None,
            dragging: None,
            strip: (egui::Rect::NOTHING, 0.0, 0.0),
            render: RenderWindow::default(),
        };
        timeline.animation.keys.sort_by_key(|k| k.frame);
        timeline
    }

    /// A timeline restored over a view that already shows `view` (the timeline's own frame 0
    /// or a frame of it): c on its loop stays the loop's, not a new centre.
    pub fn restored(base: Scene, animation: Animation, view: &Scene) -> Self {
        let mut timeline = Self::new(base, animation);
        timeline.shown = Some(view.clone());
        timeline
    }

    /// The last frame's number.
    pub fn last_frame(&self) -> u32 {
        self.animation.frames.max(1) - 1
    }

    /// The keyframes' frame numbers, in order.
    pub fn key_frames(&self) -> Vec<u32> {
        self.animation.keys.iter().map(|k| k.frame).collect()
    }

    /// The keyframe at `frame`, if there is one.
    pub fn key(&self, frame: u32) -> Option<&Keyframe> {
        self.animation.keys.iter().find(|k| k.frame == frame)
    }

    /// Frame `frame`'s scene, as `qjulia animate` renders it.
    pub fn scene_at(&self, frame: u32) -> Scene {
        self.animation.scene_at(&self.base, frame)
    }

    /// Takes what the user changed in `view` into the base: every value of the view, except c
    /// when no keyframe sets it and the view's c is the one the timeline put there (so c's loop
    /// keeps its centre). The values keyframes set are the tracks' whatever the base holds.
    /// After a change of algebra the keys' numbers of the algebra are cut or padded to fit.
    pub fn absorb(&mut self, view: &Scene) {
        let mut base = view.clone();
        let c_keyed = self.animation.animated_paths().contains(&"fractal.c");
        let c_untouched = self
            .shown
            .as_ref()
            .is_some_and(|s| s.fractal.c == view.fractal.c);
        if !c_keyed && c_untouched && self.base.fractal.c.len() == view.fractal.c.len() {
            base.fractal.c = self.base.fractal.c.clone();
        }
        self.base = base;
        self.fit_keys();
    }

    /// Cuts or pads the keys' numbers of the algebra (c, the slice) to the base's algebra, the
    /// slice axes re-orthonormalised (the standard axes where they degenerate).
    fn fit_keys(&mut self) {
        let dim = self.base.fractal.algebra.dim();
        for key in &mut self.animation.keys {
            let mut resized = false;
            for (path, value) in &mut key.values {
                let hyper = matches!(schema::key(path).map(|k| k.kind), Some(Kind::Hyper { .. }));
                if hyper && value.len() != dim {
                    value.resize(dim, 0.0);
                    resized = true;
                }
            }
            let axes: Vec<usize> = AXES
                .iter()
                .filter_map(|a| key.values.iter().position(|(p, _)| p == a))
                .collect();
            if resized && axes.len() == 3 {
                let [x, y, z] = [0, 1, 2].map(|a| key.values[axes[a]].1.as_slice());
                let fitted = crate::scene::orthonormalise([x, y, z])
                    .unwrap_or_else(|| Slice::default().axes(dim));
                for (a, axis) in fitted.into_iter().enumerate() {
                    key.values[axes[a]].1 = axis;
                }
            }
        }
    }

    /// The paths a keyframe at the current frame takes from `view`: those other keyframes set,
    /// the camera's eye and target, c where the view's c is not the animation's at this frame,
    /// the slice's axes where the algebra has more than 4 dimensions or they are not the
    /// standard ones (or not the animation's here), and the slice offset where it is not zero
    /// (or not the animation's here). The axes go together.
    fn paths_for(&self, view: &Scene) -> Vec<String> {
        let current = self.scene_at(self.frame);
        let changed = |path: &str| get_value(view, path) != get_value(&current, path);
        let dim = view.fractal.algebra.dim();
        let standard = Slice::default().axes(dim);
        let s = &view.slice;
        let turned = dim > 4 || [&s.x, &s.y, &s.z].into_iter().ne(standard.iter());
        let mut paths: Vec<String> = self
            .animation
            .animated_paths()
            .into_iter()
            .map(String::from)
            .collect();
        for path in VIEW_PATHS {
            let wanted = match path {
                "camera.eye" | "camera.target" => true,
                "fractal.c" => changed(path),
                "slice.offset" => changed(path) || s.offset.iter().any(|&x| x != 0.0),
                _ => turned || AXES.iter().any(|a| changed(a)),
            };
            if wanted && !paths.iter().any(|p| p == path) {
                paths.push(path.to_string());
            }
        }
        if AXES.iter().any(|a| paths.iter().any(|p| p == a)) {
            for axis in AXES {
                if !paths.iter().any(|p| p == axis) {
                    paths.push(axis.to_string());
                }
            }
        }
        paths
    }

    /// Adds a keyframe at the current frame from the view (replacing one there): the values of
    /// [`Self::paths_for`]. Keys that did not set a path the new key sets take the value they
    /// showed, so every key still looks as it did. A key's values are in the order of their
    /// paths, as a scene file reads back. Returns the key's frame.
    pub fn add_key(&mut self, view: &Scene) -> u32 {
        // A c moved from the loop is the key's, not a new centre of the loop.
        let centre = self.base.fractal.c.clone();
        self.absorb(view);
        if self.base.fractal.c.len() == centre.len() {
            self.base.fractal.c = centre;
        }
        let paths = self.paths_for(view);
        let before = self.animation.clone();
        for key in &mut self.animation.keys {
            let showed = before.scene_at(&self.base, key.frame);
            for path in &paths {
                if !key.values.iter().any(|(p, _)| p == path) {
                    let value = get_value(&showed, path).expect("keyed paths are animatable");
                    key.values.push((path.clone(), value));
                }
            }
            key.values.sort_by(|a, b| a.0.cmp(&b.0));
        }
        let mut values: Vec<(String, Vec<f64>)> = paths
            .iter()
            .map(|p| (p.clone(), get_value(view, p).expect("animatable")))
            .collect();
        values.sort_by(|a, b| a.0.cmp(&b.0));
        let frame = self.frame;
        self.animation.keys.retain(|k| k.frame != frame);
        self.animation.keys.push(Keyframe { frame, values });
        self.animation.keys.sort_by_key(|k| k.frame);
        self.selected = Some(frame);
        self.shown = Some(view.clone());
        frame
    }

    /// Moves the keyframe at `from` to frame `to`. Refused (false, nothing changed) when there
    /// is no key at `from`, `to` is past the last frame or another key is there.
    pub fn move_key(&mut self, from: u32, to: u32) -> bool {
        if to > self.last_frame() || (from != to && self.key(to).is_some()) {
            return false;
        }
        let Some(key) = self.animation.keys.iter_mut().find(|k| k.frame == from) else {
            return false;
        };
        key.frame = to;
        self.animation.keys.sort_by_key(|k| k.frame);
        if self.selected == Some(from) {
            self.selected = Some(to);
        }
        true
    }

    /// Deletes the keyframe at `frame`; false where there is none.
    pub fn delete_key(&mut self, frame: u32) -> bool {
        let count = self.animation.keys.len();
        self.animation.keys.retain(|k| k.frame != frame);
        if self.selected == Some(frame) {
            self.selected = None;
        }
        self.animation.keys.len() != count
    }

    /// Sets the frame count, within [`FRAMES_MIN`, `FRAMES_MAX`] and never below the last
    /// keyframe (move or delete it first); the current frame stays within.
    pub fn set_frames(&mut self, frames: u32) {
        let least = self
            .animation
            .keys
            .last()
            .map_or(FRAMES_MIN, |k| k.frame + 1);
        self.animation.frames = frames.clamp(least.max(FRAMES_MIN), FRAMES_MAX);
        self.frame = self.frame.min(self.last_frame());
    }

    /// Shows frame `frame` (within the animation) in `view`, the view's changes taken into the
    /// base first.
    pub fn show(&mut self, frame: u32, view: &mut Scene) {
        self.absorb(view);
        self.frame = frame.min(self.last_frame());
        *view = self.scene_at(self.frame);
        self.shown = Some(view.clone());
    }

    /// Play or pause; playing starts at the current frame, shown at once.
    pub fn toggle_play(&mut self, view: &mut Scene) {
        self.playing = !self.playing;
        if self.playing {
            self.position = f64::from(self.frame);
            self.show(self.frame, view);
        }
    }

    /// While playing, advances by `dt` seconds at the animation's frames per second, looping at
    /// the end, and shows the frame reached.
    pub fn advance(&mut self, dt: f64, view: &mut Scene) {
        if !self.playing {
            return;
        }
        let frames = f64::from(self.animation.frames);
        self.position = (self.position + dt * self.animation.fps).rem_euclid(frames);
        let frame = (self.position.floor() as u32).min(self.last_frame());
        if frame != self.frame {
            self.show(frame, view);
        }
    }

    /// The scene file of the animation, the view's changes taken into the base: the scene's
    /// tables and `[animation]`.
    pub fn file_text(&mut self, view: &Scene) -> String {
        self.absorb(view);
        scene_file(&self.base, &self.animation)
    }

    /// The scene file as `qjulia animate --scene FILE` reads it: its text, and the base and
    /// animation read back from it; the loader's one-line error where it would refuse it (a
    /// track that leaves a range between its keys, a degenerate camera on the way).
    pub fn checked_file(&mut self, view: &Scene) -> Result<(String, Scene, Animation), String> {
        let text = self.file_text(view);
        let mut loader = SceneLoader::new();
        loader
            .toml_str(&text, SceneSource::Default)
            .and_then(|()| loader.build_animated())
            .map(|(scene, animation)| (text, scene, animation))
            .map_err(|e| e.message)
    }
}

/// The "Render animation..." window: where and which frames, and the job running.
#[derive(Default)]
pub(super) struct RenderWindow {
    pub open: bool,
    /// The output folder, as typed.
    pub dir: String,
    pub first: u32,
    pub last: Option<u32>,
    pub resume: bool,
    /// A video of the frames as typed (`.mp4` or `.webm`); empty for none.
    pub video: String,
    pub job: Option<RenderJob>,
    /// How the last job ended.
    pub outcome: Option<(String, bool)>,
}

/// What a render job has done so far, shared with its thread.
#[derive(Default)]
struct JobProgress {
    /// Frames complete: rendered, or skipped as complete already (resume).
    done: u32,
    /// Frames rendered in this job.
    rendered: u32,
    /// When the job ended: a line for the status, and whether it is an error.
    finished: Option<(String, bool)>,
}

/// A "Render animation..." job on its own thread.
pub(super) struct RenderJob {
    total: u32,
    dir: PathBuf,
    started: Instant,
    shared: Arc<Shared>,
}

/// What a job and its thread share: the progress, and the request to stop.
#[derive(Default)]
struct Shared {
    progress: Mutex<JobProgress>,
    cancel: AtomicBool,
}

impl RenderJob {
    /// Frames done and the total.
    pub fn counts(&self) -> (u32, u32) {
        (self.shared.progress.lock().unwrap().done, self.total)
    }

    /// Frames rendered per second so far.
    pub fn frames_per_second(&self) -> f64 {
        let rendered = self.shared.progress.lock().unwrap().rendered;
        f64::from(rendered) / self.started.elapsed().as_secs_f64().max(1e-9)
    }
}

/// What a render job does: which frames, into which folder, and the video if one is asked for.
struct JobSpec {
    base: Scene,
    animation: Animation,
    range: FrameRange,
    dir: PathBuf,
    resume: bool,
    video: Option<PathBuf>,
}

/// The job's thread: the frames as `qjulia animate` renders them (the one call of
/// [`crate::animate::run`] in the explorer), counted into the shared progress; Cancel stops it
/// after the frames in hand, the frames written staying and an incomplete video not written.
fn run_job(mut planner: Planner, spec: JobSpec, shared: Arc<Shared>) -> (String, bool) {
    let (progress, cancel) = (&shared.progress, &shared.cancel);
    let job = crate::animate::Job {
        base: &spec.base,
        animation: &spec.animation,
        range: spec.range,
        out: Some(&spec.dir),
        resume: spec.resume,
        video: spec.video.as_deref(),
        stop: Some(cancel),
    };
    let result = crate::animate::run(&mut planner, &mut |_| {}, &job, &mut |p| {
        let mut p_ = progress.lock().unwrap();
        match p {
            Progress::Start { skipped, .. } => p_.done += skipped,
            Progress::Frame { .. } => {
                p_.done += 1;
                p_.rendered += 1;
            }
        }
    });
    let dir = spec.dir.display();
    match result {
        Err(e) => (format!("error: render animation: {e}"), true),
        Ok(stats) if stats.stopped => {
            let done = progress.lock().unwrap().done;
            let total = spec.range.len();
            (
                format!("render cancelled: {done} of {total} frames in {dir}"),
                false,
            )
        }
        Ok(stats) => {
            let video = spec
                .video
                .map(|v| format!(" and {}", v.display()))
                .unwrap_or_default();
            let line = format!(
                "rendered {} frames ({} already complete) to {dir}{video}",
                stats.frames, stats.skipped
            );
            (line, false)
        }
    }
}

impl ExplorerApp {
    /// Moves the timeline by wall time while it plays; run once a frame.
    pub(super) fn play_timeline(&mut self, dt: f64) {
        self.timeline.advance(dt, &mut self.scene);
        self.poll_render();
    }

    /// Shows frame `frame` of the animation in the view (c's own Play stops).
    pub fn show_frame(&mut self, frame: u32) {
        self.animation.playing = false;
        self.timeline.show(frame, &mut self.scene);
        self.follow_slice();
    }

    /// Play or pause the animation in the view (c's own Play stops).
    pub fn toggle_timeline_play(&mut self) {
        self.animation.playing = false;
        self.timeline.toggle_play(&mut self.scene);
    }

    /// Adds a keyframe at the current frame from the view.
    pub fn add_key(&mut self) {
        let frame = self.timeline.add_key(&self.scene);
        self.message = Some((format!("keyframe at frame {frame}"), false));
    }

    /// When the keys set the slice, the rotation controls turn the slice shown.
    fn follow_slice(&mut self) {
        let keyed = self.timeline.animation.animated_paths();
        if AXES.iter().any(|a| keyed.contains(a)) {
            let s = &self.scene.slice;
            self.base_basis = [s.x.clone(), s.y.clone(), s.z.clone()];
            self.angles.iter_mut().for_each(|a| *a = 0.0);
        }
    }

    /// The timeline: play, frame, frame count, fps, path radius, the keys' buttons, then the
    /// strip (scrub, key markers).
    pub(super) fn timeline_panel(&mut self, ui: &mut egui::Ui) {
        let last = self.timeline.last_frame();
        ui.horizontal_wrapped(|ui| {
            let label = if self.timeline.playing {
                "Pause"
            } else {
                "Play"
            };
            if ui
                .button(label)
                .on_hover_text("play the animation at its fps")
                .clicked()
            {
                self.toggle_timeline_play();
            }
            let mut frame = self.timeline.frame;
            ui.label("frame");
            if ui
                .add(egui::DragValue::new(&mut frame).range(0..=last))
                .changed()
            {
                self.show_frame(frame);
            }
            ui.label(format!("/ {last}"));
            ui.separator();
            let mut frames = self.timeline.animation.frames;
            ui.label("frames");
            if ui
                .add(egui::DragValue::new(&mut frames).range(FRAMES_MIN..=FRAMES_MAX))
                .on_hover_text("frame count (not below the last keyframe)")
                .changed()
            {
                self.timeline.set_frames(frames);
            }
            ui.label("fps");
            ui.add(
                egui::DragValue::new(&mut self.timeline.animation.fps)
                    .range(0.1..=1000.0)
                    .speed(0.1),
            );
            ui.label("c path radius");
            ui.add(
                egui::DragValue::new(&mut self.timeline.animation.path_radius)
                    .range(0.0..=10.0)
                    .speed(0.001),
            )
            .on_hover_text("c's closed loop when no keyframe sets c");
            ui.separator();
            if ui
                .button("Add key")
                .on_hover_text("a keyframe at this frame from the view")
                .clicked()
            {
                self.add_key();
            }
            if let Some(selected) = self.timeline.selected {
                let mut to = selected;
                ui.label("key at");
                if ui
                    .add(egui::DragValue::new(&mut to).range(0..=last))
                    .on_hover_text("move the selected keyframe")
                    .changed()
                    && !self.timeline.move_key(selected, to)
                {
                    self.message = Some((format!("frame {to} has a keyframe already"), true));
                }
                if ui.button("Delete key").clicked() {
                    self.timeline.delete_key(selected);
                }
            }
            ui.label(format!("{} keys", self.timeline.animation.keys.len()));
            ui.separator();
            if ui.button("Render animation…").clicked() {
                self.timeline.render.open = true;
            }
            if let Some(job) = &self.timeline.render.job {
                let (done, total) = job.counts();
                ui.add(
                    egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                        .desired_width(120.0)
                        .text(format!("{done}/{total}")),
                );
            }
        });
        self.timeline_strip(ui);
    }

    /// The strip: frames left to right, ticks, the keyframes' diamonds (the selected one
    /// highlighted) and the current frame. Click or drag on it to scrub; drag a diamond to move
    /// its key (to a free frame); click a diamond to select its key.
    fn timeline_strip(&mut self, ui: &mut egui::Ui) {
        let width = ui.available_width().max(100.0);
        let (rect, response) =
            ui.allocate_exact_size(egui::vec2(width, 34.0), egui::Sense::click_and_drag());
        let inner = rect.shrink2(egui::vec2(10.0, 0.0));
        self.timeline.strip = (rect, inner.left(), inner.right());
        let last = self.timeline.last_frame();
        let x_of = |frame: u32| {
            let t = if last == 0 {
                0.0
            } else {
                frame as f32 / last as f32
            };
            inner.left() + t * inner.width()
        };
        let frame_at = |x: f32| {
            let t = ((x - inner.left()) / inner.width().max(1.0)).clamp(0.0, 1.0);
            (t * last as f32).round() as u32
        };
        let key_near = |timeline: &Timeline, x: f32| {
            timeline
                .key_frames()
                .into_iter()
                .filter(|&k| (x_of(k) - x).abs() <= 7.0)
                .min_by(|&a, &b| (x_of(a) - x).abs().total_cmp(&(x_of(b) - x).abs()))
        };
        if response.drag_started() {
            let origin = ui.input(|i| i.pointer.press_origin());
            self.timeline.dragging = origin.and_then(|p| key_near(&self.timeline, p.x));
            if let Some(k) = self.timeline.dragging {
                self.timeline.selected = Some(k);
            }
        }
        if let Some(pos) = response.interact_pointer_pos() {
            let frame = frame_at(pos.x);
            if response.dragged() {
                match self.timeline.dragging {
                    Some(from) => {
                        if from != frame && self.timeline.move_key(from, frame) {
                            self.timeline.dragging = Some(frame);
                        }
                        let shown = self.timeline.dragging.unwrap_or(frame);
                        if shown != self.timeline.frame {
                            self.show_frame(shown);
                        }
                    }
                    None if frame != self.timeline.frame => self.show_frame(frame),
                    None => {}
                }
            } else if response.clicked() {
                let key = key_near(&self.timeline, pos.x);
                self.timeline.selected = key;
                self.show_frame(key.unwrap_or(frame));
            }
        }
        if response.drag_stopped() {
            self.timeline.dragging = None;
        }

        let painter = ui.painter_at(rect);
        let visuals = ui.visuals();
        painter.rect_filled(rect, 3.0, visuals.extreme_bg_color);
        let mid = rect.center().y;
        let faint = visuals.weak_text_color();
        painter.line_segment(
            [
                egui::pos2(inner.left(), mid),
                egui::pos2(inner.right(), mid),
            ],
            egui::Stroke::new(1.0, faint),
        );
        // Ticks at a round step at least 50 points apart, numbered.
        let per_frame = inner.width() / last.max(1) as f32;
        let step = [
            1, 2, 5, 10, 20, 25, 50, 100, 200, 250, 500, 1000, 2000, 5000, 10_000,
        ]
        .into_iter()
        .find(|&s| s as f32 * per_frame >= 50.0)
        .unwrap_or(20_000);
        let font = egui::FontId::proportional(10.0);
        for k in (0..=last).step_by(step as usize) {
            let x = x_of(k);
            painter.line_segment(
                [
                    egui::pos2(x, rect.bottom() - 8.0),
                    egui::pos2(x, rect.bottom()),
                ],
                egui::Stroke::new(1.0, faint),
            );
            painter.text(
                egui::pos2(x + 2.0, rect.bottom() - 1.0),
                egui::Align2::LEFT_BOTTOM,
                k.to_string(),
                font.clone(),
                faint,
            );
        }
        // The current frame.
        let x = x_of(self.timeline.frame);
        let accent = visuals.selection.bg_fill;
        painter.line_segment(
            [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
            egui::Stroke::new(2.0, accent),
        );
        painter.text(
            egui::pos2(x + 3.0, rect.top() + 1.0),
            egui::Align2::LEFT_TOP,
            self.timeline.frame.to_string(),
            font,
            visuals.strong_text_color(),
        );
        // The keys.
        for k in self.timeline.key_frames() {
            let centre = egui::pos2(x_of(k), mid);
            let r = 6.0;
            let selected = self.timeline.selected == Some(k);
            let fill = if selected {
                egui::Color32::from_rgb(255, 220, 80)
            } else {
                egui::Color32::from_rgb(235, 140, 50)
            };
            painter.add(egui::Shape::convex_polygon(
                vec![
                    centre + egui::vec2(0.0, -r),
                    centre + egui::vec2(r, 0.0),
                    centre + egui::vec2(0.0, r),
                    centre + egui::vec2(-r, 0.0),
                ],
                fill,
                egui::Stroke::new(1.0, egui::Color32::BLACK),
            ));
        }
        response.on_hover_text("click or drag to scrub; drag a key marker to move its key");
    }

    /// The "Render animation..." window: folder, frame range, resume; while a job runs, its
    /// progress and Cancel.
    pub(super) fn render_window(&mut self, ctx: &egui::Context) {
        if !self.timeline.render.open {
            return;
        }
        let last_frame = self.timeline.last_frame();
        let mut open = true;
        let mut start = false;
        egui::Window::new("Render animation")
            .open(&mut open)
            .resizable(false)
            .show(ctx, |ui| {
                let r = &mut self.timeline.render;
                if r.dir.is_empty() {
                    r.dir = self.last_dir.join(DEFAULT_DIR).display().to_string();
                }
                ui.label("As `qjulia animate`: frame-NNNNN.png in the folder.");
                ui.horizontal(|ui| {
                    ui.label("folder");
                    ui.add(egui::TextEdit::singleline(&mut r.dir).desired_width(320.0));
                });
                let mut last = r.last.unwrap_or(last_frame).min(last_frame);
                r.first = r.first.min(last_frame);
                ui.horizontal(|ui| {
                    ui.label("frames");
                    ui.add(egui::DragValue::new(&mut r.first).range(0..=last_frame));
                    ui.label("to");
                    ui.add(egui::DragValue::new(&mut last).range(0..=last_frame));
                    ui.label(format!("(of 0 to {last_frame})"));
                });
                r.last = (last != last_frame).then_some(last);
                ui.checkbox(&mut r.resume, "resume: skip frames already complete");
                ui.horizontal(|ui| {
                    ui.label("video");
                    ui.add(
                        egui::TextEdit::singleline(&mut r.video)
                            .desired_width(320.0)
                            .hint_text("none, or FILE.mp4 / FILE.webm (needs ffmpeg)"),
                    );
                });
                match &r.job {
                    Some(job) => {
                        let (done, total) = job.counts();
                        ui.add(
                            egui::ProgressBar::new(done as f32 / total.max(1) as f32).text(
                                format!(
                                    "{done} / {total} frames, {:.1} fps",
                                    job.frames_per_second()
                                ),
                            ),
                        );
                        ui.horizontal(|ui| {
                            if job.shared.cancel.load(Ordering::Relaxed) {
                                ui.label("cancelling after the frames in hand…");
                            } else if ui.button("Cancel").clicked() {
                                job.shared.cancel.store(true, Ordering::Relaxed);
                            }
                        });
                    }
                    None => {
                        if let Some((line, error)) = &r.outcome {
                            let colour = if *error {
                                ui.visuals().error_fg_color
                            } else {
                                ui.visuals().text_color()
                            };
                            ui.colored_label(colour, line);
                        }
                        start = ui.button("Render").clicked();
                    }
                }
            });
        self.timeline.render.open = open;
        if start {
            self.start_render();
        }
    }

    /// Renders frames `first..=last` (None: to the last frame) into `dir` as the *Render
    /// animation…* window's Render button does, PNG frames only.
    pub fn start_render_into(&mut self, dir: &Path, first: u32, last: Option<u32>) {
        let r = &mut self.timeline.render;
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
        let (_, base, animation) = match self.timeline.checked_file(&self.scene) {
            Ok(checked) => checked,
            Err(e) => {
                self.timeline.render.outcome = Some((format!("error: {e}"), true));
                return;
            }
        };
        let planner = self.planner();
        let r = &mut self.timeline.render;
        let last = r.last.unwrap_or(animation.frames - 1);
        if r.first > last {
            r.outcome = Some((
                format!(
                    "error: the first frame {} is after the last {last}",
                    r.first
                ),
                true,
            ));
            return;
        }
        let range = FrameRange {
            first: r.first,
            last,
        };
        let dir = PathBuf::from(r.dir.trim());
        let resume = r.resume;
        let video = Some(r.video.trim())
            .filter(|v| !v.is_empty())
            .map(PathBuf::from);
        if let Some(video) = &video {
            // As `animate` checks it: the kind, then ffmpeg, before anything is rendered.
            let checked = crate::video::Codec::for_path(video)
                .map_err(crate::Error::from)
                .and_then(|_| crate::video::find_ffmpeg());
            if let Err(e) = checked {
                r.outcome = Some((format!("error: {e}"), true));
                return;
            }
        }
        let shared = Arc::new(Shared::default());
        let job = RenderJob {
            total: range.len(),
            dir: dir.clone(),
            started: Instant::now(),
            shared: shared.clone(),
        };
        let spec = JobSpec {
            base,
            animation,
            range,
            dir,
            resume,
            video,
        };
        std::thread::spawn(move || {
            let finished = run_job(planner, spec, shared.clone());
            shared.progress.lock().unwrap().finished = Some(finished);
        });
        r.outcome = None;
        r.job = Some(job);
    }

    /// Ends a finished render job, its outcome in the window and the status line.
    fn poll_render(&mut self) {
        let r = &mut self.timeline.render;
        let Some(job) = &r.job else { return };
        let finished = job.shared.progress.lock().unwrap().finished.take();
        if let Some(outcome) = finished {
            self.last_dir = job
                .dir
                .parent()
                .map_or(self.last_dir.clone(), Path::to_path_buf);
            self.message = Some(outcome.clone());
            r.outcome = Some(outcome);
            r.job = None;
        }
    }

    /// Whether a render job is running.
    pub fn rendering(&self) -> bool {
        self.timeline.render.job.is_some()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene::Algebra;

    fn values(t: &Timeline, frame: u32) -> Vec<(String, Vec<f64>)> {
        t.key(frame).expect("a key").values.clone()
    }

    fn path_of(key: &[(String, Vec<f64>)], path: &str) -> Option<Vec<f64>> {
        key.iter().find(|(p, _)| p == path).map(|(_, v)| v.clone())
    }

    #[test]
    fn a_key_takes_the_camera_from_the_view_and_c_only_when_moved() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        assert_eq!(t.add_key(&view), 0);
        let key = values(&t, 0);
        let paths: Vec<&str> = key.iter().map(|(p, _)| p.as_str()).collect();
        assert_eq!(paths, ["camera.eye", "camera.target"]);
        // At frame 60 with the camera moved and c changed: c is keyed, and the key at 0 takes
        // the c it showed (the loop's start, the scene's c).
        t.show(60, &mut view);
        view.camera.eye = [1.0, 0.5, 2.0];
        view.fractal.c = vec![0.1, 0.2, 0.3, 0.4];
        t.add_key(&view);
        assert_eq!(t.key_frames(), [0, 60]);
        assert_eq!(
            path_of(&values(&t, 60), "fractal.c"),
            Some(view.fractal.c.clone())
        );
        assert_eq!(
            path_of(&values(&t, 0), "fractal.c"),
            Some(Scene::default().fractal.c)
        );
        // Each key is what the animation shows at its frame.
        assert_eq!(t.scene_at(60).camera.eye, [1.0, 0.5, 2.0]);
        assert_eq!(t.scene_at(0).camera.eye, Scene::default().camera.eye);
        assert_eq!(t.scene_at(0).fractal.c, Scene::default().fractal.c);
        assert_eq!(t.selected, Some(60));
    }

    #[test]
    fn the_slice_is_keyed_beyond_four_dimensions_or_when_turned() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        view.slice.offset = vec![0.0, 0.0, 0.0, 0.2];
        t.add_key(&view);
        let key = values(&t, 0);
        assert!(path_of(&key, "slice.offset").is_some());
        assert!(path_of(&key, "slice.x").is_none());
        // Octonions: the axes are keyed, all three, and fitted to eight dimensions.
        view.set_algebra(Algebra::Octonion);
        t.show(10, &mut view);
        t.add_key(&view);
        let key = values(&t, 10);
        for axis in AXES {
            assert_eq!(path_of(&key, axis).map(|v| v.len()), Some(8), "{axis}");
        }
        assert_eq!(
            path_of(&values(&t, 0), "slice.offset").map(|v| v.len()),
            Some(8)
        );
    }

    #[test]
    fn keys_move_within_range_to_free_frames_and_delete() {
        let mut view = Scene::default();
        let mut t = Timeline::new(
            view.clone(),
            Animation {
                frames: 50,
                ..Animation::default()
            },
        );
        for frame in [0, 10, 30] {
            t.show(frame, &mut view);
            view.camera.eye[0] = f64::from(frame) / 100.0;
            t.add_key(&view);
        }
        assert_eq!(t.key_frames(), [0, 10, 30]);
        // Onto another key, past the end, or from where no key is: refused.
        assert!(!t.move_key(10, 30));
        assert!(!t.move_key(10, 50));
        assert!(!t.move_key(11, 12));
        assert_eq!(t.key_frames(), [0, 10, 30]);
        // Past a neighbour: the keys stay sorted, the selection follows.
        t.selected = Some(10);
        assert!(t.move_key(10, 40));
        assert_eq!(t.key_frames(), [0, 30, 40]);
        assert_eq!(t.selected, Some(40));
        assert_eq!(t.scene_at(40).camera.eye[0], 0.1);
        // Adding where a key is replaces it.
        t.show(30, &mut view);
        view.camera.eye[0] = 0.9;
        t.add_key(&view);
        assert_eq!(t.key_frames(), [0, 30, 40]);
        assert_eq!(t.scene_at(30).camera.eye[0], 0.9);
        // The frame count stays above the last key.
        t.set_frames(20);
        assert_eq!(t.animation.frames, 41);
        t.set_frames(0);
        assert_eq!(t.animation.frames, 41);
        t.selected = Some(40);
        assert!(t.delete_key(40));
        assert!(!t.delete_key(40));
        assert_eq!(t.selected, None);
        t.set_frames(5);
        assert_eq!(t.animation.frames, 31);
        assert!(t.delete_key(30) && t.delete_key(0));
        t.set_frames(0);
        assert_eq!(t.animation.frames, FRAMES_MIN);
        assert_eq!(t.frame, 0);
    }

    #[test]
    fn scrubbing_and_playing_show_the_animation_frames() {
        let mut view = Scene::default();
        let mut t = Timeline::new(view.clone(), Animation::default());
        t.show(30, &mut view);
        view.camera.eye = [0.5, 0.5, 2.5];
        t.add_key(&view);
        t.show(90, &mut view);
        view.camera.eye = [-0.5, 0.2, 2.8];
        view.shading.ambient = 0.1; // not keyed: goes into the base
        t.add_key(&view);
        let base = t.base.clone();
        assert_eq!(base.shading.ambient, 0.1);
        assert_eq!(
            base.fractal.c,
            Scene::default().fractal.c,
            "c's loop centre"
        );
        for k in [0, 45, 60, 119] {
            t.show(k, &mut view);
            assert_eq!(view, t.animation.scene_at(&base, k), "frame {k}");
        }
        // Play: 30 fps, a tenth of a second is three frames, looping after the last.
        t.show(118, &mut view);
        t.toggle_play(&mut view);
        t.advance(0.1, &mut view);
        assert_eq!(t.frame, 1);
        assert_eq!(view, t.animation.scene_at(&base, 1));
        t.toggle_play(&mut view);
        t.advance(1.0, &mut view);
        assert_eq!(t.frame, 1, "paused");
    }

    #[test]
    fn the_saved_file_reads_back_as_the_animation() {
        let mut view = Scene::default();
        view.set_algebra(Algebra::Octonion);
        let mut t = Timeline::new(
            view.clone(),
            Animation {
                frames: 48,
                fps: 24.0,
                path_radius: 0.05,
                keys: vec![],
            },
        );
        for (frame, x) in [(0, 0.1), (20, -0.3), (47, 1.0 / 3.0)] {
            t.show(frame, &mut view);
            view.camera.eye[0] = x;
            view.fractal.c[5] = x / 7.0;
            t.add_key(&view);
        }
        let (text, base, animation) = t.checked_file(&view).expect("a valid file");
        assert_eq!(animation, t.animation, "{text}");
        assert_eq!(base, t.base);
        for k in 0..48 {
            assert_eq!(animation.scene_at(&base, k), t.scene_at(k), "frame {k}");
        }
    }
}
