//! `qjulia animate`: the frames of a scene's animation, each a full qjulia PNG
//! (`DIR/frame-NNNNN.png`) carrying its own frame's resolved scene, written whole or not at all.
//!
//! Frame k's bytes depend only on the scene options and k (on one backend and adapter): every
//! frame is rendered alone by the same [`Renderer`], chosen once by the caller, on the same path
//! as `qjulia render`, so any split of the frames (`--frames A..B`) gives byte-identical files and
//! `render --scene DIR/frame-NNNNN.png` writes that frame again, byte for byte.

use std::path::{Path, PathBuf};
use std::time::Instant;

use serde::Serialize;

use crate::animation::Animation;
use crate::error::{Error, Result};
use crate::output::{OutputPaths, StreamingOutputs, write_view_outputs};
use crate::render::{Picture, Renderer};
use crate::scene::{Scene, SceneError, SceneSource, View};
use crate::stats::RenderStats;

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
    pub fn parse(text: &str, frames: u32) -> Result<Self, SceneError> {
        let bad = |message: String| SceneError {
            origin: SceneSource::Flag(format!("--frames {text}")),
            key: None,
            message,
        };
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
    /// Frame `frame` was written to `path`.
    Frame {
        frame: u32,
        path: &'a Path,
        stats: &'a RenderStats,
    },
}

/// Renders frames `range` of `animation` over `base` into `dir` (created if missing), each with
/// `renderer`, skipping complete frames when `resume` is set. Frames already written stay when a
/// later one fails.
pub fn run(
    renderer: &Renderer,
    base: &Scene,
    animation: &Animation,
    range: FrameRange,
    dir: &Path,
    resume: bool,
    progress: &mut dyn FnMut(Progress),
) -> Result<AnimateStats> {
    std::fs::create_dir_all(dir).map_err(|source| Error::Io {
        path: dir.to_path_buf(),
        source,
    })?;
    let mut todo = Vec::new();
    for k in range.iter() {
        let scene = animation.scene_at(base, k);
        let path = frame_path(dir, k);
        if !(resume && frame_complete(&path, &scene)) {
            todo.push((k, scene, path));
        }
    }
    let skipped = range.len() - todo.len() as u32;
    progress(Progress::Start {
        to_render: todo.len() as u32,
        skipped,
    });
    let start = Instant::now();
    let mut render_seconds = 0.0;
    for (k, scene, path) in &todo {
        let stats = render_frame(renderer, scene, path)?;
        render_seconds += stats.render_seconds;
        progress(Progress::Frame {
            frame: *k,
            path,
            stats: &stats,
        });
    }
    let seconds = start.elapsed().as_secs_f64();
    let frames = todo.len() as u32;
    Ok(AnimateStats {
        frames,
        skipped,
        first: range.first,
        last: range.last,
        seconds,
        frames_per_second: if frames > 0 {
            frames as f64 / seconds
        } else {
            0.0
        },
        render_seconds,
        backend: renderer.backend_name().into(),
        adapter: renderer.adapter(),
        precision: renderer.precision().name().into(),
        width: base.image.width,
        height: base.image.height,
    })
}

/// Renders one frame's scene to its PNG as `qjulia render -o PATH` does (so that rendering the
/// PNG's scene again gives the same bytes): the shaded picture streamed band by band, or a heat
/// map of `image.view` rendered whole; written to a temporary file and renamed into place.
pub fn render_frame(renderer: &Renderer, scene: &Scene, path: &Path) -> Result<RenderStats> {
    let paths = OutputPaths {
        png: Some(path.to_path_buf()),
        ..Default::default()
    };
    if scene.image.view != View::Shaded {
        let picture = Picture::Slice { shade: false };
        let (frame, stats) = renderer.render_frame(scene, picture)?;
        write_view_outputs(&paths, &frame, &stats, scene)?;
        return Ok(stats);
    }
    let mut outputs = StreamingOutputs::create(&paths, scene)?;
    let stats = renderer.render(scene, Picture::SHADED, &mut |band| outputs.write_band(band))?;
    outputs.finish(&stats)?;
    Ok(stats)
}
