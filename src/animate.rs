//! `qjulia animate`: the frames of a scene's animation, each a full qjulia PNG
//! (`DIR/frame-NNNNN.png`) carrying its own frame's resolved scene, written whole or not at all,
//! and optionally a video of them through ffmpeg ([`crate::video`]).
//!
//! Frame k's bytes depend only on the scene options and k (on one backend and adapter): each
//! frame's renderer is decided by its own scene ([`Planner::plan`], as `qjulia render` decides
//! it: with `--precision auto` deep frames run in f64), runs of frames of one renderer stream
//! on the same path as `qjulia render`, so any split of the frames (`--frames A..B`) gives
//! byte-identical files and `render --scene DIR/frame-NNNNN.png` writes that frame again, byte
//! for byte.
//!
//! The frames are pipelined: this thread renders them one after another, reading back only the
//! colour; a pool of threads encodes and writes the PNGs, and one more feeds ffmpeg in order.
//! At most [`frames_in_flight`] rendered frames wait for them, so memory stays bounded.

use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc::{Receiver, channel, sync_channel};
use std::sync::{Arc, Mutex};
use std::time::Instant;

use serde::Serialize;

use crate::animation::Animation;
use crate::error::{Error, FlagError, Result};
use crate::gpu::Readback;
use crate::output::{read_png_rgb, write_png};
use crate::render::{Picture, Planner, Renderer};
use crate::scene::{Scene, View};
use crate::video::VideoWriter;

/// The folder frames go to when none is given.
pub const DEFAULT_DIR: &str = "qjulia-frames";

/// An inclusive range of 0-based frame numbers, `first <= last`.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FrameRange {
    pub first: u32,
    pub last: u32,
}

impl FrameRange {
    /// Every frame of an animation of `frames` frames (at least 1).
    pub fn all(frames: u32) -> Self {
        Self {
            first: 0,
            last: frames.saturating_sub(1),
        }
    }

    /// Parses `--frames A..B`: 0-based, inclusive, `A <= B < frames`. The error names the flag
    /// as typed (exit 2 as bad input).
    pub fn parse(text: &str, frames: u32) -> Result<Self, FlagError> {
        let bad = |message: String| FlagError::new(format!("--frames {text}"), message);
        let expected = || {
            bad(format!(
                "expected A..B, the first and last frame (0-based, inclusive; the animation has {frames} frames, 0..{})",
                frames.saturating_sub(1)
            ))
        };
        let (a, b) = text.split_once("..").ok_or_else(expected)?;
        let number = |s: &str| {
            (!s.is_empty() && s.bytes().all(|c| c.is_ascii_digit()))
                .then(|| s.parse::<u32>().ok())
                .flatten()
        };
        let (Some(first), Some(last)) = (number(a), number(b)) else {
            return Err(expected());
        };
        if first > last {
            return Err(bad(format!(
                "the first frame {first} is after the last {last}"
            )));
        }
        if last >= frames {
            return Err(bad(format!(
                "frame {last} is past the last frame {} (the animation has {frames} frames, numbered from 0)",
                frames.saturating_sub(1)
            )));
        }
        Ok(Self { first, last })
    }

    /// How many frames the range holds.
    pub fn len(&self) -> u32 {
        self.last - self.first + 1
    }

    /// Never empty (`first <= last`); here for the lint's sake.
    pub fn is_empty(&self) -> bool {
        false
    }

    pub fn iter(&self) -> std::ops::RangeInclusive<u32> {
        self.first..=self.last
    }
}

/// The PNG of frame `k` in `dir`: `frame-NNNNN.png`, five digits (frames are below 100000).
pub fn frame_path(dir: &Path, k: u32) -> PathBuf {
    dir.join(format!("frame-{k:05}.png"))
}

/// Whether frame `k`'s PNG is already there and complete: it exists under its final name (the
/// writer renames only complete files into place) and carries exactly `scene`. A frame left by
/// another scene, or a file that is not a qjulia PNG, is not complete.
pub fn frame_complete(path: &Path, scene: &Scene) -> bool {
    path.is_file() && crate::scene::scene_from_png(path).is_ok_and(|text| text == scene.to_toml())
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

/// What the caller hears as the frames go.
pub enum Progress<'a> {
    /// The frames to render, after those already complete were counted out.
    Start { to_render: u32, skipped: u32 },
    /// Frame `frame` was rendered and written: its PNG at `path` where PNGs are written (else
    /// it went to the video alone), in `render_seconds`.
    Frame {
        frame: u32,
        path: Option<&'a Path>,
        render_seconds: f64,
    },
}

/// One `animate` run: which frames of which animation go where.
#[derive(Clone, Copy, Debug)]
pub struct Job<'a> {
    pub base: &'a Scene,
    pub animation: &'a Animation,
    pub range: FrameRange,
    /// The folder of the PNG frames (created if missing); None writes none (a video alone).
    pub out: Option<&'a Path>,
    /// Skip frames whose PNG in `out` is complete (a video then reads them from there).
    pub resume: bool,
    /// The video to write (`.mp4` or `.webm`), of every frame of the range.
    pub video: Option<&'a Path>,
    /// Set (by another thread) to stop after the frames in hand: frames written stay, and the
    /// video, incomplete, is not written. The explorer's Cancel.
    pub stop: Option<&'a AtomicBool>,
}

/// How many rendered frames may wait for the encoders at once: one per encoder thread, and as
/// many again in the queue, so that the renderer never waits on one slow frame.
pub fn frames_in_flight() -> usize {
    2 * encoder_threads()
}

/// The threads that encode and write PNG frames: the machine's cores, at most 8.
fn encoder_threads() -> usize {
    std::thread::available_parallelism().map_or(2, |n| n.get().clamp(1, 8))
}

/// A rendered frame's image, as written: `[width, height]` RGB8 pixels.
struct Picture8 {
    size: [u32; 2],
    rgb: Vec<u8>,
}

/// A frame for the PNG encoders.
struct PngJob {
    frame: u32,
    scene: Scene,
    path: PathBuf,
    picture: Arc<Picture8>,
    render_seconds: f64,
}

/// What an encoder reports of a frame.
type Written = (u32, PathBuf, f64, Result<()>);

/// Renders frames `job.range` of `job.animation` over `job.base`, each with the renderer
/// `planner` decides for its scene (its precision may depend on the frame; `notice` hears what
/// the planner says the first time it makes each renderer): PNGs into
/// `job.out`, skipping complete frames when `job.resume` is set, and the video. Frames already
/// written stay when a later one fails; the video is written whole or not at all.
pub fn run(
    planner: &mut Planner,
    notice: &mut dyn FnMut(&str),
    job: &Job,
    progress: &mut dyn FnMut(Progress),
) -> Result<AnimateStats> {
    let mut used: Vec<Renderer> = Vec::new();
    if let Some(dir) = job.out {
        std::fs::create_dir_all(dir).map_err(|source| Error::Io {
            path: dir.to_path_buf(),
            source,
        })?;
    }
    // Every frame of the range, and whether it is complete already (then not rendered).
    let frames: Vec<(u32, Scene, Option<PathBuf>, bool)> = job
        .range
        .iter()
        .map(|k| {
            let scene = job.animation.scene_at(job.base, k);
            let path = job.out.map(|dir| frame_path(dir, k));
            let complete = job.resume && path.as_deref().is_some_and(|p| frame_complete(p, &scene));
            (k, scene, path, complete)
        })
        .collect();
    let skipped = frames.iter().filter(|f| f.3).count() as u32;
    progress(Progress::Start {
        to_render: job.range.len() - skipped,
        skipped,
    });
    let start = Instant::now();
    let mut render_seconds = 0.0;
    let mut rendered = 0;
    let fps = job.animation.fps;

    let outcome = std::thread::scope(|s| -> Result<u32> {
        let (to_encoders, jobs) = sync_channel::<PngJob>(encoder_threads());
        let (report, written) = channel::<Written>();
        // The encoders hold the only handles on the queue's end and on the reports' start: when
        // all have stopped, sending fails, and the reports end when all are done.
        let jobs = Arc::new(Mutex::new(jobs));
        for _ in 0..encoder_threads() {
            let (jobs, report) = (jobs.clone(), report.clone());
            s.spawn(move || encode_pngs(&jobs, &report));
        }
        drop((jobs, report));
        let (to_video, pictures) = sync_channel::<Arc<Picture8>>(encoder_threads());
        let video = job
            .video
            .map(|path| s.spawn(move || feed_video(path, fps, pictures)));

        // Renders the frames to render as one stream and hands each out in order, the complete
        // frames a video needs read back from disk between them; stops at the first error (its
        // own, or an encoder's or the video's: then a queue is closed).
        let mut hand_out = || -> Result<()> {
            let to_video = |picture: Arc<Picture8>| match job.video {
                Some(_) => to_video.send(picture).map_err(|_| stopped()),
                None => Ok(()),
            };
            let mut complete = frames
                .iter()
                .filter(|f| f.3 && job.video.is_some())
                .peekable();
            let mut from_disk = |until: u32| -> Result<()> {
                while let Some((_, _, path, _)) = complete.next_if(|f| f.0 < until) {
                    let (size, rgb) = read_png_rgb(path.as_deref().expect("complete in out"))?;
                    to_video(Arc::new(Picture8 { size, rgb }))?;
                }
                Ok(())
            };
            let to_render: Vec<_> = frames.iter().filter(|f| !f.3).collect();
            let stop = || job.stop.is_some_and(|s| s.load(Ordering::Relaxed));
            let (picture, readback) = match job.base.image.view {
                View::Shaded => (Picture::SHADED, Readback::Colour),
                _ => (Picture::Slice { shade: false }, Readback::All),
            };
            let mut next = 0;
            let mut sink = |frame: crate::frame::Frame, stats: crate::stats::RenderStats| {
                let (k, scene, path, _) = to_render[next];
                next += 1;
                from_disk(*k)?;
                let seconds = stats.render_seconds;
                render_seconds += seconds;
                rendered += 1;
                let picture = Arc::new(picture_of(scene, &frame));
                match path {
                    Some(path) => {
                        let job = PngJob {
                            frame: *k,
                            scene: scene.clone(),
                            path: path.clone(),
                            picture: picture.clone(),
                            render_seconds: seconds,
                        };
                        to_encoders.send(job).map_err(|_| stopped())?;
                    }
                    None => progress(Progress::Frame {
                        frame: *k,
                        path: None,
                        render_seconds: seconds,
                    }),
                }
                to_video(picture)?;
                report_written(&written, false, progress)
            };
            // Each frame's renderer, chosen before the first renders; then the frames in runs of
            // one renderer (frames may differ in precision), each run one stream.
            let chosen: Vec<Renderer> = to_render
                .iter()
                .map(|f| Ok(planner.plan(&f.1, picture.into(), notice)?.renderer))
                .collect::<Result<_>>()?;
            let mut first = 0;
            for run in chosen.chunk_by(Renderer::same_tracer) {
                if stop() {
                    break;
                }
                let frames = &to_render[first..first + run.len()];
                first += run.len();
                used.push(run[0].clone());
                let mut scenes = frames.iter().map(|f| f.1.clone()).take_while(|_| !stop());
                run[0].render_frames(&mut scenes, picture, readback, &mut sink)?;
            }
            match next < to_render.len() {
                // Stopped before this frame: the rest stays undone.
                true => Ok(()),
                false => from_disk(u32::MAX),
            }
        };
        let handed_out = hand_out();
        drop(to_encoders);
        drop(to_video);
        // Every PNG finishes (or fails) before the video is kept; an encoder's or the video's
        // error is the reason a queue closed, so it comes out first.
        let encoded = report_written(&written, true, progress);
        let video = video.map(|thread| thread.join().expect("the video thread"));
        encoded?;
        let writer = video.transpose()?.flatten();
        handed_out?;
        if rendered < job.range.len() - skipped {
            // Stopped: an incomplete video is not written (dropped, it leaves nothing).
            return Ok(0);
        }
        let video_frames = writer.as_ref().map_or(0, |w| w.frames() as u32);
        if let Some(writer) = writer {
            writer.finish()?;
        }
        Ok(video_frames)
    });
    let video_frames = outcome?;
    let stopped = rendered < job.range.len() - skipped;
    let seconds = start.elapsed().as_secs_f64();
    Ok(AnimateStats {
        frames: rendered,
        stopped,
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
        render_seconds,
        backend: joined(&used, |r| r.backend_name().into()),
        adapter: joined(&used, Renderer::adapter),
        precision: joined(&used, |r| r.precision().name().into()),
        width: job.base.image.width,
        height: job.base.image.height,
    })
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

/// Hands the encoders' reports to `progress`: those in already, or (`all`) every one until the
/// encoders are done. The first failed frame's error comes out after the others are reported.
fn report_written(
    written: &Receiver<Written>,
    all: bool,
    progress: &mut dyn FnMut(Progress),
) -> Result<()> {
    let mut first_error = None;
    let mut take = |(frame, path, render_seconds, result): Written| match result {
        Ok(()) => progress(Progress::Frame {
            frame,
            path: Some(&path),
            render_seconds,
        }),
        Err(e) => {
            first_error.get_or_insert(e);
        }
    };
    if all {
        written.iter().for_each(&mut take);
    } else {
        written.try_iter().for_each(&mut take);
    }
    first_error.map_or(Ok(()), Err)
}

/// An encoder thread: writes the PNG of each frame it takes from the queue until the queue
/// closes, or until a frame fails (then it stops, and with it, once all have, the queue).
fn encode_pngs(jobs: &Mutex<Receiver<PngJob>>, report: &std::sync::mpsc::Sender<Written>) {
    loop {
        let next = jobs.lock().expect("the frame queue").recv();
        let Ok(job) = next else { return };
        let result = write_png(&job.path, &job.scene, job.picture.size, &job.picture.rgb);
        let failed = result.is_err();
        let _ = report.send((job.frame, job.path, job.render_seconds, result));
        if failed {
            return;
        }
    }
}

/// The video thread: starts ffmpeg at the first frame (its size is the video's) and feeds it
/// every frame in order; returns the writer, unfinished, for the caller to keep or drop.
fn feed_video(
    path: &Path,
    fps: f64,
    pictures: Receiver<Arc<Picture8>>,
) -> Result<Option<VideoWriter>> {
    let mut writer: Option<VideoWriter> = None;
    for picture in pictures {
        let w = match &mut writer {
            Some(w) => w,
            None => writer.insert(VideoWriter::start(path, picture.size, fps)?),
        };
        w.push(&picture.rgb)?;
    }
    Ok(writer)
}

/// The error of a queue found closed: the thread at its end stopped on an error of its own,
/// which is the one reported.
fn stopped() -> Error {
    Error::Video("a frame writer stopped".into())
}

/// The picture a frame's PNG shows: the shaded image, or a heat map of `image.view` with its
/// legend.
fn picture_of(scene: &Scene, frame: &crate::frame::Frame) -> Picture8 {
    match scene.image.view {
        View::Shaded => Picture8 {
            size: [frame.width, frame.height],
            rgb: frame.rgb8(),
        },
        view => {
            let (w, h, rgb) = crate::heatmap::view_image(frame, view);
            Picture8 { size: [w, h], rgb }
        }
    }
}
