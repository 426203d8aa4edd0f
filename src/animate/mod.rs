//! `qjulia animate`: the frames of a scene's animation, each a full qjulia PNG
//! (`DIR/frame-NNNNN.png`) carrying its own frame's resolved scene, written whole or not at all,
//! with `--hdr` an OpenEXR beside each (`DIR/frame-NNNNN.exr`, [`crate::hdr`]), and optionally
//! a video of them through ffmpeg ([`crate::video`]).
//!
//! Frame k's bytes depend only on the scene options and k (on one backend and adapter): each
//! frame's renderer is decided by its own scene ([`Planner::plan`], as `qjulia render` decides
//! it: with `--precision auto` deep frames run in f64), runs of frames of one renderer stream
//! on the same path as `qjulia render`, so any split of the frames (`--frames A..B`) gives
//! byte-identical files and `render --scene DIR/frame-NNNNN.png` writes that frame again, byte
//! for byte.
//!
//! The frames are pipelined: this thread renders them one after another, reading back only the
//! colour; the writers (`writers.rs`: a pool of threads that encodes and writes the PNGs, and
//! one more that feeds ffmpeg in order) take them as they come. At most [`frames_in_flight`]
//! rendered frames wait for them, so memory stays bounded.

mod job;
mod writers;

pub use job::{FramePlan, FrameRange, Job, Progress};
pub use writers::frames_in_flight;

use std::path::{Path, PathBuf};
use std::sync::atomic::Ordering;
use std::time::Instant;

use serde::Serialize;

use crate::error::{Error, Result};
use crate::frame::Frame;
use crate::render::{Picture, Planner, Readback, Renderer};
use crate::scene::{Scene, View};
use writers::Writers;

/// The folder frames go to when none is given.
pub const DEFAULT_DIR: &str = "qjulia-frames";

/// The PNG of frame `k` in `dir`: `frame-NNNNN.png`, five digits (frames are below 100000).
pub fn frame_path(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame-{k:05}.png"))
}

/// The OpenEXR of frame `k` in `dir` (`animate --hdr`): `frame-NNNNN.exr`, beside its PNG.
pub fn frame_exr_path(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame-{k:05}.exr"))
}

/// Whether frame `k`'s PNG is already there and complete: it exists under its final name (the
/// writer renames only complete files into place) and carries exactly `scene`. A frame left by
/// another scene, or a file that is not a qjulia PNG, is not complete.
pub fn frame_complete(path: &Path, scene: &Scene) -> bool {
    path.is_file() && crate::scene::scene_from_png(path).is_ok_and(|text| text == scene.to_toml())
}

/// As [`frame_complete`], for a frame's OpenEXR: there under its final name, carrying exactly
/// `scene`.
pub fn frame_exr_complete(path: &Path, scene: &Scene) -> bool {
    path.is_file() && crate::scene::scene_from_exr(path).is_ok_and(|text| text == scene.to_toml())
}

/// What one animate run did, for `--stats` (JSON).
#[derive(Clone, Debug, Serialize)]
pub struct AnimateStats {
    /// The frames rendered and written in this run.
    pub frames: u32,
    /// Whether the run was stopped early ([`Job::stop`]): then no video was written.
    #[serde(skip)]
    pub stopped: bool,
    /// The video written, if any, and the frames it holds (those rendered and those skipped).
    pub video: Option<PathBuf>,
    pub video_frames: u32,
    /// Frames of the range skipped as already complete (`--resume`).
    pub skipped: u32,
    /// The range asked for, inclusive.
    pub first: u32,
    pub last: u32,
    /// Wall-clock seconds from the first frame to the last one written (the device's start-up
    /// left out), rendering and writing included.
    pub seconds: f64,
    /// `frames / seconds` (0 when nothing was rendered).
    pub frames_per_second: f64,
    /// The renderers' own seconds, summed over the frames (`render_seconds` of each).
    pub render_seconds: f64,
    pub backend: String,
    pub adapter: String,
    pub precision: String,
    pub width: u32,
    pub height: u32,
}

/// The first step of a run: every frame of the range with its scene, its PNG (and EXR) and
/// whether the frame is complete.
pub fn plan_frames(job: &Job) -> Vec<FramePlan> {
    job.range
        .iter()
        .map(|frame| {
            let scene = job.animation.scene_at(job.base, frame);
            let png = job.out.map(|dir| frame_path(dir, frame));
            let exr = job
                .out
                .filter(|_| job.hdr)
                .map(|dir| frame_exr_path(dir, frame));
            let complete = job.resume
                && png.as_deref().is_some_and(|p| frame_complete(p, &scene))
                && exr.as_deref().is_none_or(|p| frame_exr_complete(p, &scene));
            FramePlan {
                frame,
                scene,
                png,
                exr,
                complete,
            }
        })
        .collect()
}

/// Renders frames `job.range` of `job.animation` over `job.base`: PNGs into `job.out`,
/// skipping complete frames when `job.resume` is set, and the video. In steps: the frames are
/// planned ([`plan_frames`]); each frame to render gets the renderer `planner` decides for its
/// own scene (its precision may depend on the frame; `notice` hears what the planner says the
/// first time it makes each renderer), all before the first renders; the writers start (PNG
/// encoders, the video); the frames render in runs of one renderer, each run one stream, each
/// frame handed to the writers as it comes. Frames already written stay when a later one
/// fails; the video is written whole or not at all.
pub fn run(
    planner: &mut Planner,
    notice: &mut dyn FnMut(&str),
    job: &Job,
    progress: &mut dyn FnMut(Progress),
) -> Result<AnimateStats> {
    if let Some(dir) = job.out {
        std::fs::create_dir_all(dir).map_err(|cause| Error::Io {
            path: dir.to_path_buf(),
            cause,
        })?;
    }
    let frames = plan_frames(job);
    let to_render: Vec<&FramePlan> = frames.iter().filter(|f| !f.complete).collect();
    let skipped = (frames.len() - to_render.len()) as u32;
    progress(Progress::Start {
        to_render: to_render.len() as u32,
        skipped,
    });
    // The EXR needs the shaded picture and its AOVs whatever the PNG shows (a heat map's
    // depth and steps are the same either way).
    let (picture, readback) = match (job.base.image.view, job.hdr) {
        (_, true) => (Picture::SHADED, Readback::Hdr),
        (View::Shaded, false) => (Picture::SHADED, Readback::Colour),
        (View::Samples, false) => (Picture::SHADED, Readback::All),
        _ => (Picture::Slice { shade: false }, Readback::All),
    };
    let renderers: Vec<Renderer> = to_render
        .iter()
        .map(|f| Ok(planner.plan(&f.scene, picture.into(), notice)?.renderer))
        .collect::<Result<_>>()?;
    let start = Instant::now();
    let mut runs = Runs::default();
    let video_frames = std::thread::scope(|s| -> Result<u32> {
        let mut writers = Writers::start(s, job, &frames);
        let handed_out = runs.render(
            &to_render,
            &renderers,
            picture,
            readback,
            job,
            &mut |plan, frame, seconds| writers.frame(plan, frame, seconds, progress),
        );
        let finished = handed_out.and_then(|()| match runs.rendered < to_render.len() as u32 {
            // Stopped before this frame: the rest stays undone.
            true => Ok(()),
            false => writers.feed_rest_from_disk(),
        });
        writers.finish(finished, runs.rendered == to_render.len() as u32, progress)
    })?;
    let rendered = runs.rendered;
    let seconds = start.elapsed().as_secs_f64();
    Ok(AnimateStats {
        frames: rendered,
        stopped: rendered < to_render.len() as u32,
        video: job.video.map(Path::to_path_buf),
        video_frames,
        skipped,
        first: job.range.first,
        last: job.range.last,
        seconds,
        frames_per_second: if rendered > 0 {
            rendered as f64 / seconds
        } else {
            0.0
        },
        render_seconds: runs.render_seconds,
        backend: joined(&runs.used, |r| r.backend_name().into()),
        adapter: joined(&runs.used, Renderer::adapter),
        precision: joined(&runs.used, |r| r.precision().name().into()),
        width: job.base.image.width,
        height: job.base.image.height,
    })
}

/// The render step's tally: frames rendered, their renderers' seconds, and the renderers used
/// (one per run).
#[derive(Default)]
struct Runs {
    rendered: u32,
    render_seconds: f64,
    used: Vec<Renderer>,
}

impl Runs {
    /// Renders `frames` (each with its renderer) in runs of one renderer, each run one stream,
    /// handing each frame in order to `sink` with its render seconds; stops early when
    /// `job.stop` is set.
    fn render(
        &mut self,
        frames: &[&FramePlan],
        renderers: &[Renderer],
        picture: Picture,
        readback: Readback,
        job: &Job,
        sink: &mut dyn FnMut(&FramePlan, &Frame, f64) -> Result<()>,
    ) -> Result<()> {
        let stop = || job.stop.is_some_and(|s| s.load(Ordering::Relaxed));
        let mut first = 0;
        for run in renderers.chunk_by(Renderer::same_tracer) {
            if stop() {
                break;
            }
            let plans = &frames[first..first + run.len()];
            first += run.len();
            self.used.push(run[0].clone());
            let mut scenes = plans
                .iter()
                .map(|f| f.scene.clone())
                .take_while(|_| !stop());
            let mut next = plans.iter();
            run[0].render_frames(&mut scenes, picture, readback, &mut |frame, stats| {
                let plan = next.next().expect("one plan per frame rendered");
                self.rendered += 1;
                self.render_seconds += stats.render_seconds;
                sink(plan, &frame, stats.render_seconds)
            })?;
        }
        Ok(())
    }
}

/// What the renderers used say of themselves, each once, in order of use, joined by ", "
/// (one value when all frames had one renderer; "" when none rendered).
fn joined(used: &[Renderer], say: impl Fn(&Renderer) -> String) -> String {
    let mut said: Vec<String> = Vec::new();
    for r in used {
        let s = say(r);
        if !said.contains(&s) {
            said.push(s);
        }
    }
    said.join(", ")
}
