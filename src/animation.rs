//! Animation: the scene file's `[animation]` table (frame count, frames per second, keyframes)
//! and the resolved scene of each frame, a function of the scene options and the frame's index
//! alone (CONTRACT.md's additions).

use crate::scene::Scene;

/// The `[animation]` table.
#[derive(Clone, Debug, PartialEq)]
pub struct Animation {
    /// Frame count, 1 to 100000.
    pub frames: u32,
    /// Frames per second, finite and > 0 (for video).
    pub fps: f64,
    /// The radius of c's closed path when no keyframe sets `fractal.c` (the explorer's Play
    /// path).
    pub path_radius: f64,
    /// Keyframes, by frame number (unique, within the frame count).
    pub keys: Vec<Keyframe>,
}

/// One keyframe: its frame number and the float or float-vector scene values it sets, by
/// dotted path (e.g. `fractal.c`, `camera.eye`).
#[derive(Clone, Debug, PartialEq)]
pub struct Keyframe {
    pub frame: u32,
    pub values: Vec<(String, Vec<f64>)>,
}

impl Default for Animation {
    fn default() -> Self {
        Self {
            frames: 120,
            fps: 30.0,
            path_radius: 0.08,
            keys: Vec::new(),
        }
    }
}

impl Animation {
    /// The resolved scene of frame `frame` (0-based, below `frames`) of the animation of `base`.
    pub fn scene_at(&self, base: &Scene, frame: u32) -> Scene {
        let _ = frame;
        base.clone()
    }
}
