//! What an `animate` run is: the range of frames, the job, each frame's plan and the progress
//! it reports; what the run (`mod.rs`) and its writers (`writers.rs`) both use, in a module of
//! its own so that neither imports the other.

use std::path::{Path, PathBuf};
use std::sync::atomic::AtomicBool;

use crate::animation::Animation;
use crate::error::FlagError;
use crate::scene::Scene;

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
    /// Skip frames whose PNG in `out` is complete (a video then reads them from there), and
    /// with `hdr` their EXR too.
    pub resume: bool,
    /// Write each frame's OpenEXR beside its PNG in `out` (which must be given).
    pub hdr: bool,
    /// The video to write (`.mp4` or `.webm`), of every frame of the range.
    pub video: Option<&'a Path>,
    /// Set (by another thread) to stop after the frames in hand: frames written stay, and the
    /// video, incomplete, is not written. The explorer's Cancel.
    pub stop: Option<&'a AtomicBool>,
}

/// One frame of a run: its number, its scene, where its PNG goes (None: no PNGs are
/// written, a video alone), where its EXR goes (`hdr` only), and whether the frame is complete
/// already (`--resume`: its PNG, and its EXR where one is written; then it is not rendered
/// again, and a video reads its PNG back).
#[derive(Clone, Debug)]
pub struct FramePlan {
    pub frame: u32,
    pub scene: Scene,
    pub png: Option<PathBuf>,
    pub exr: Option<PathBuf>,
    pub complete: bool,
}
