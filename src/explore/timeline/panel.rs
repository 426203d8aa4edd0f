//! The timeline's panels: the strip under the view (play, frame, frame count, fps, the keys'
//! buttons; the scrub strip with the key markers) and the "Render animation…" window. Each edits
//! what it owns (the strip its drag, the window its form) and the timeline's model; what reaches
//! further (showing a frame in the view, adding a key from it, starting the render) it returns
//! as [`Command`]s, which the app applies after the frame.

use std::path::{Path, PathBuf};

use super::job::{RenderJob, RenderRequest};
use super::model::Timeline;
use crate::animation::{FRAMES_MAX, FRAMES_MIN};
use crate::explore::command::Command;

/// The folder "Render animation..." proposes, in the explorer's last folder.
const DEFAULT_DIR: &str = crate::animate::DEFAULT_DIR;

/// The strip under the view: what it keeps from frame to frame.
pub struct TimelinePanel {
    /// Where the strip was drawn last frame, and the x of frame 0 and of the last frame in it.
    pub strip: (egui::Rect, f32, f32),
    /// The key whose marker is being dragged.
    dragging: Option<u32>,
}

impl Default for TimelinePanel {
    fn default() -> Self {
        Self {
            strip: (egui::Rect::NOTHING, 0.0, 0.0),
            dragging: None,
        }
    }
}

impl TimelinePanel {
    /// The timeline: play, frame, frame count, fps, path radius, the keys' buttons, then the
    /// strip (scrub, key markers).
    pub fn ui(
        &mut self,
        ui: &mut egui::Ui,
        timeline: &mut Timeline,
        job: Option<&RenderJob>,
    ) -> Vec<Command> {
        let mut commands = Vec::new();
        let last = timeline.last_frame();
        ui.horizontal_wrapped(|ui| {
            let label = if timeline.playing { "Pause" } else { "Play" };
            if ui
                .button(label)
                .on_hover_text("play the animation at its fps")
                .clicked()
            {
                commands.push(Command::ToggleTimelinePlay);
            }
            let mut frame = timeline.frame;
            let label = ui.label("frame").id;
            if ui
                .add(egui::DragValue::new(&mut frame).range(0..=last))
                .labelled_by(label)
                .changed()
            {
                commands.push(Command::ShowFrame(frame));
            }
            ui.label(format!("/ {last}"));
            ui.separator();
            let mut frames = timeline.animation.frames;
            let label = ui.label("frames").id;
            if ui
                .add(egui::DragValue::new(&mut frames).range(FRAMES_MIN..=FRAMES_MAX))
                .labelled_by(label)
                .on_hover_text("frame count (not below the last keyframe)")
                .changed()
            {
                timeline.set_frames(frames);
            }
            let label = ui.label("fps").id;
            ui.add(
                egui::DragValue::new(&mut timeline.animation.fps)
                    .range(0.1..=1000.0)
                    .speed(0.1),
            )
            .labelled_by(label);
            let label = ui.label("c path radius").id;
            ui.add(
                egui::DragValue::new(&mut timeline.animation.path_radius)
                    .range(0.0..=10.0)
                    .speed(0.001),
            )
            .labelled_by(label)
            .on_hover_text("c's closed loop when no keyframe sets c");
            ui.separator();
            if ui
                .button("Add key")
                .on_hover_text("a keyframe at this frame from the view")
                .clicked()
            {
                commands.push(Command::AddKey);
            }
            if let Some(selected) = timeline.selected {
                let mut to = selected;
                let label = ui.label("key at").id;
                if ui
                    .add(egui::DragValue::new(&mut to).range(0..=last))
                    .labelled_by(label)
                    .on_hover_text("move the selected keyframe")
                    .changed()
                    && !timeline.move_key(selected, to)
                {
                    commands.push(Command::Tell(
                        format!("frame {to} has a keyframe already"),
                        true,
                    ));
                }
                if ui.button("Delete key").clicked() {
                    timeline.delete_key(selected);
                }
            }
            ui.label(format!("{} keys", timeline.animation.keys.len()));
            ui.separator();
            if ui.button("Render animation…").clicked() {
                commands.push(Command::OpenRenderWindow);
            }
            if let Some(job) = job {
                let (done, total) = job.counts();
                ui.add(
                    egui::ProgressBar::new(done as f32 / total.max(1) as f32)
                        .desired_width(120.0)
                        .text(format!("{done}/{total}")),
                );
            }
        });
        self.strip(ui, timeline, &mut commands);
        commands
    }

    /// The strip: frames left to right, ticks, the keyframes' diamonds (the selected one
    /// highlighted) and the current frame. Click or drag on it to scrub; drag a diamond to move
    /// its key (to a free frame); click a diamond to select its key.
    fn strip(&mut self, ui: &mut egui::Ui, timeline: &mut Timeline, commands: &mut Vec<Command>) {
        let width = ui.available_width().max(100.0);
        let (rect, response) =
            ui.allocate_exact_size(egui::vec2(width, 34.0), egui::Sense::click_and_drag());
        let inner = rect.shrink2(egui::vec2(10.0, 0.0));
        self.strip = (rect, inner.left(), inner.right());
        let last = timeline.last_frame();
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
            self.dragging = origin.and_then(|p| key_near(timeline, p.x));
            if let Some(k) = self.dragging {
                timeline.selected = Some(k);
            }
        }
        if let Some(pos) = response.interact_pointer_pos() {
            let frame = frame_at(pos.x);
            if response.dragged() {
                match self.dragging {
                    Some(from) => {
                        if from != frame && timeline.move_key(from, frame) {
                            self.dragging = Some(frame);
                        }
                        let shown = self.dragging.unwrap_or(frame);
                        if shown != timeline.frame {
                            commands.push(Command::ShowFrame(shown));
                        }
                    }
                    None if frame != timeline.frame => commands.push(Command::ShowFrame(frame)),
                    None => {}
                }
            } else if response.clicked() {
                let key = key_near(timeline, pos.x);
                timeline.selected = key;
                commands.push(Command::ShowFrame(key.unwrap_or(frame)));
            }
        }
        if response.drag_stopped() {
            self.dragging = None;
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
        let x = x_of(timeline.frame);
        let accent = visuals.selection.bg_fill;
        painter.line_segment(
            [egui::pos2(x, rect.top()), egui::pos2(x, rect.bottom())],
            egui::Stroke::new(2.0, accent),
        );
        painter.text(
            egui::pos2(x + 3.0, rect.top() + 1.0),
            egui::Align2::LEFT_TOP,
            timeline.frame.to_string(),
            font,
            visuals.strong_text_color(),
        );
        // The keys.
        for k in timeline.key_frames() {
            let centre = egui::pos2(x_of(k), mid);
            let r = 6.0;
            let selected = timeline.selected == Some(k);
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
}

/// The "Render animation..." window: where and which frames, and how the last job ended.
#[derive(Default)]
pub struct RenderWindow {
    pub open: bool,
    /// The output folder, as typed.
    pub dir: String,
    pub first: u32,
    pub last: Option<u32>,
    pub resume: bool,
    /// A video of the frames as typed (`.mp4` or `.webm`); empty for none.
    pub video: String,
    /// How the last job ended.
    pub outcome: Option<(String, bool)>,
}

impl RenderWindow {
    /// What the window asks to render, as typed.
    pub fn request(&self) -> RenderRequest {
        RenderRequest {
            first: self.first,
            last: self.last,
            dir: PathBuf::from(self.dir.trim()),
            resume: self.resume,
            video: Some(self.video.trim())
                .filter(|v| !v.is_empty())
                .map(PathBuf::from),
        }
    }

    /// The "Render animation..." window: folder, frame range, resume; while a job runs, its
    /// progress and Cancel.
    pub fn ui(
        &mut self,
        ctx: &egui::Context,
        last_frame: u32,
        last_dir: &Path,
        job: Option<&RenderJob>,
    ) -> Option<Command> {
        if !self.open {
            return None;
        }
        let mut open = true;
        let mut start = false;
        egui::Window::new("Render animation")
            .open(&mut open)
            .resizable(false)
            .show(ctx, |ui| {
                let r = &mut *self;
                if r.dir.is_empty() {
                    r.dir = last_dir.join(DEFAULT_DIR).display().to_string();
                }
                ui.label("As `qjulia animate`: frame-NNNNN.png in the folder.");
                ui.horizontal(|ui| {
                    ui.label("folder");
                    ui.add(egui::TextEdit::singleline(&mut r.dir).desired_width(320.0));
                });
                let mut last = r.last.unwrap_or(last_frame).min(last_frame);
                r.first = r.first.min(last_frame);
                ui.horizontal(|ui| {
                    let label = ui.label("frames").id;
                    ui.add(egui::DragValue::new(&mut r.first).range(0..=last_frame))
                        .labelled_by(label);
                    let label = ui.label("to").id;
                    ui.add(egui::DragValue::new(&mut last).range(0..=last_frame))
                        .labelled_by(label);
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
                match job {
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
                            if job.cancelling() {
                                ui.label("cancelling after the frames in hand…");
                            } else if ui.button("Cancel").clicked() {
                                job.cancel();
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
        self.open = open;
        start.then_some(Command::RenderAnimation)
    }
}
