//! The status line under the view (frame time, what the view shows and how long it took, the
//! adapter, a running export, the last message), and its twin on stderr for measuring the
//! explorer where no one watches it (`QJULIA_EXPLORE_LOG=1` once a second, `=frames` for every
//! frame).

use std::time::Instant;

use super::export::Export;
use super::state::{ExplorerState, Mode};
use super::viewport::Viewport;

/// The status line's own: the last message, and the frame clock it shows.
#[derive(Default)]
pub struct StatusLine {
    /// The message shown, and whether it is an error.
    pub message: Option<(String, bool)>,
    last_frame: Option<Instant>,
    /// Seconds per frame, smoothed.
    frame_seconds: f64,
    log_frames: u32,
    log_since: Option<Instant>,
    /// Frames logged with `QJULIA_EXPLORE_LOG=frames`.
    frames_logged: u64,
    /// The start of the last frame logged, for the interval to the next.
    last_logged: Option<Instant>,
}

impl StatusLine {
    /// A new frame at `now`: the seconds since the last one (0 for the first, at most a
    /// quarter of a second), into the frame time shown.
    pub fn tick(&mut self, now: Instant) -> f64 {
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
        dt
    }

    /// One line of fixed height (a status bar that changed height would resize the view): the
    /// view's, the state's and a running export's figures, and the message.
    pub fn ui(
        &self,
        ui: &mut egui::Ui,
        viewport: &Viewport,
        state: &ExplorerState,
        export: Option<&Export>,
    ) {
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
            if state.mode == Mode::Julia2d {
                if let Some(view2d) = &viewport.julia2d_texture {
                    let v = &state.scene.view2d;
                    ui.separator();
                    ui.label(format!(
                        "2D at {:.6} {:+.6} i, extent {:.3e}",
                        v.center[0], v.center[1], v.extent
                    ));
                    ui.label(format!("render {:.0} ms", view2d.render_seconds() * 1e3));
                    let precision = match view2d.precision() {
                        crate::precision::Precision::F64 => "f64 (deep zoom)",
                        crate::precision::Precision::F32 => "f32",
                    };
                    ui.label(precision).on_hover_text(view2d.precision_note());
                }
            } else if let Some(view) = &viewport.slice_texture {
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
                if view.building_pipeline() {
                    ui.label("building the pipeline…").on_hover_text(
                        "a new variant of the kernel is compiled off the UI's thread; the view \
                         shows the last image meanwhile",
                    );
                }
                // The precision the view runs in: f64 by itself where f32 cannot resolve it.
                let precision = match view.precision() {
                    crate::precision::Precision::F64 => "f64 (deep zoom)",
                    crate::precision::Precision::F32 => "f32",
                };
                ui.label(precision).on_hover_text(view.precision_note());
                if view.path_traced() {
                    ui.label("path traced");
                } else if state.scene.shading.model == crate::scene::ShadingModel::Path
                    && let Some(why) = view.path_unavailable()
                {
                    let colour = ui.visuals().error_fg_color;
                    ui.colored_label(colour, "Phong (path tracer unavailable)")
                        .on_hover_text(why);
                }
                if s.refined {
                    let mut samples = format!("samples {}/{}", s.samples, state.preview_samples);
                    if let Some(mean) = s.samples_taken {
                        samples.push_str(&format!(" ({mean:.1} a pixel)"));
                    }
                    ui.label(samples).on_hover_text(
                        "with adaptive sampling, a pixel stops once each of its two streams' \
                         noise is at most path.noise_target: the mean of what each has taken",
                    );
                }
                if let Some(noise) = s.noise.filter(|_| s.refined) {
                    ui.label(format!("error {:.1}%", 100.0 * noise))
                        .on_hover_text(
                            "the image's estimated RMSE relative to its mean, from the \
                             disagreement of each pixel's two halves (--stats' \
                             estimated_relative_rmse; the book's \"The error on request\")",
                        );
                }
                if let Some(error) = &s.denoise_error {
                    let colour = ui.visuals().error_fg_color;
                    ui.colored_label(colour, "not denoised")
                        .on_hover_text(error);
                } else if let Some(samples) = s.denoised_samples {
                    let error = s
                        .denoised_noise
                        .map_or(String::new(), |e| format!(", error {:.1}%", 100.0 * e));
                    ui.label(format!(
                        "denoised {samples} ({:.0} ms {}{error})",
                        s.denoise_seconds * 1e3,
                        s.denoise_backend
                    ))
                    .on_hover_text(
                        "the denoiser's time includes denoising each half alone, which gives \
                         the denoised image's estimated error",
                    );
                }
                match s.summary {
                    Some(sum) => ui.label(format!(
                        "steps mean {:.1} max {}",
                        sum.steps_mean, sum.steps_max
                    )),
                    _ => ui.label("steps …"),
                };
            }
            ui.separator();
            ui.label(&viewport.adapter_label);
            if let Some(export) = export {
                ui.separator();
                ui.spinner();
                match export.progress() {
                    Some((done, total)) if total > 0 => {
                        ui.label(format!("exporting… {done}/{total} grid layers"))
                    }
                    _ => ui.label("exporting…"),
                };
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

    /// With `QJULIA_EXPLORE_LOG=1`, one line a second on stderr: frame rate and what the view
    /// shows (for measuring the explorer where no one watches it). With
    /// `QJULIA_EXPLORE_LOG=frames`, one line a frame instead: its number, the time the frame's
    /// own work took (from `now`, its start, to this call at its end: input, jobs polled,
    /// panels and view), the time since the last frame began (idle waits included), when it
    /// began (`at`, milliseconds since the Unix epoch), when the render of the image it shows
    /// began (`shows`, the same clock, `-` for none), `input` where the user's input asked the
    /// view for something new in it, then the frame's spans of a millisecond or more
    /// ([`crate::render::progressive::spans`]), as `explore frame 12: 3.41 ms work, 16.70 ms
    /// since the last, at 1796601600123.4, shows 1796601600080.1, input; controls 1.20, view
    /// 2.05`. A frame that shows a render begun after an input frame began shows that input:
    /// the soak's input latency.
    pub fn log(&mut self, now: Instant, viewport: &mut Viewport, mode: Mode) {
        let mode_log = std::env::var_os("QJULIA_EXPLORE_LOG");
        let input = viewport.input_asked.take();
        if mode_log.as_ref().is_some_and(|v| v == "frames") {
            use crate::render::progressive::spans::{epoch_ms, keep, take};
            let work = now.elapsed().as_secs_f64() * 1e3;
            let since = self
                .last_logged
                .map_or(0.0, |t| now.duration_since(t).as_secs_f64() * 1e3);
            // The first frame logged turns the spans on; each frame's of a millisecond or
            // more follow its figures.
            keep(true);
            let spans = take(1.0);
            let shows = viewport
                .shown_began(mode)
                .map_or_else(|| "-".to_string(), |t| format!("{:.1}", epoch_ms(t)));
            eprintln!(
                "explore frame {}: {work:.2} ms work, {since:.2} ms since the last, at {:.1}, shows {shows}{}{}{spans}",
                self.frames_logged,
                epoch_ms(now),
                if input.is_some() { ", input" } else { "" },
                if spans.is_empty() { "" } else { "; " }
            );
            self.frames_logged += 1;
            self.last_logged = Some(now);
            return;
        }
        if mode_log.is_none_or(|v| v != "1") {
            return;
        }
        self.log_frames += 1;
        let since = self.log_since.get_or_insert(now);
        let elapsed = now.duration_since(*since).as_secs_f64();
        if elapsed >= 1.0 {
            let s = viewport
                .slice_texture
                .as_ref()
                .map(|v| v.stats().clone())
                .unwrap_or_default();
            eprintln!(
                "explore: {:.1} fps; view {}x{}; shown {}x{} (scale {:.2}, {}, {} samples) rendered in {:.0} ms, {:.0} ms after the last change{}",
                self.log_frames as f64 / elapsed,
                viewport.pixels[0],
                viewport.pixels[1],
                s.size[0],
                s.size[1],
                s.scale,
                if s.refined { "full" } else { "preview" },
                s.samples,
                s.render_seconds * 1e3,
                s.since_change_seconds * 1e3,
                match viewport
                    .slice_texture
                    .as_ref()
                    .is_some_and(|v| v.path_traced())
                {
                    true => format!("; path traced, encoded in {:.1} ms", s.encode_seconds * 1e3),
                    false => String::new(),
                },
            );
            self.log_frames = 0;
            self.log_since = Some(now);
        }
    }
}
