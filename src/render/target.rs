//! `image.target_error`: a path-traced render that stops at an error rather than a sample
//! count. It renders the whole image in passes of more and more samples, each from the first
//! sample (so each pass is exactly a render of its samples, and tiles of one are not needed),
//! estimates each pass's error ([`crate::estimate`]; of the denoised image where a denoiser
//! runs), and stops at the first pass whose `estimated_relative_rmse` is at most the target, or
//! at `image.samples`. The schedule is docs/CONTRACT.md's; docs/book/error.md says what it
//! costs and how close it lands.

use super::Renderer;
use crate::denoise::Denoiser;
use crate::error::Result;
use crate::frame::Frame;
use crate::picture::Picture;
use crate::render::Readback;
use crate::scene::Scene;
use crate::stats::{RenderStats, TargetPass, TargetStats};

/// The first pass's samples (or `image.samples`, where fewer).
pub const FIRST_PASS: u32 = 16;
/// A pass after the first takes the samples that its predecessor's estimate asks for, times
/// this margin (so that the next pass's estimate lands under the target rather than on it).
pub const MARGIN: f64 = 1.2;
/// ... and at least this many times its predecessor's, so that the passes grow geometrically.
pub const LEAST_GROWTH: f64 = 1.5;

/// The samples of the pass after one of `samples` whose estimate was `estimate` (relative), to
/// reach `target` with at most `most`: `samples (estimate / target)^2` (the error of a mean
/// falls as one over the root of its samples) times [`MARGIN`], at least [`LEAST_GROWTH`] times
/// `samples`, rounded up to an even count (two halves of equal size), at most `most`. Without
/// an estimate, `most`.
pub fn next_samples(samples: u32, estimate: Option<f64>, target: f64, most: u32) -> u32 {
    let Some(e) = estimate else {
        return most;
    };
    let asked = samples as f64 * (e / target).powi(2) * MARGIN;
    let n = asked
        .max(samples as f64 * LEAST_GROWTH)
        .ceil()
        .min(most as f64) as u32;
    (n + n % 2).min(most)
}

impl Renderer {
    /// [`Self::render_with`] of a scene that targets an error ([`Scene::targets_error`]): the
    /// passes, the last one's frame handed to `sink` whole, with its stats (the passes' seconds
    /// summed) and [`TargetStats`].
    pub(super) fn render_to_target(
        &self,
        scene: &Scene,
        readback: Readback,
        sink: &mut dyn FnMut(&Frame) -> Result<()>,
    ) -> Result<RenderStats> {
        let (width, height) = (scene.image.width, scene.image.height);
        crate::memory::check(
            &format!("the {width}x{height} image rendered to image.target_error"),
            u64::from(width)
                * u64::from(height)
                * (crate::memory::FRAME_BYTES_PER_PIXEL + crate::memory::DENOISE_BYTES_PER_PIXEL),
        )?;
        let (target, most) = (scene.image.target_error, scene.image.samples);
        let denoise = scene.image.denoise != Denoiser::None;
        let readback = if denoise { Readback::Hdr } else { readback };
        let mut samples = most.min(FIRST_PASS);
        let mut passes = Vec::new();
        let (mut seconds, mut gpu_seconds, mut denoise_seconds) = (0.0, Some(0.0), 0.0);
        loop {
            let mut pass = scene.clone();
            pass.image.samples = samples;
            let mut frame = Frame::empty(width);
            let mut stats =
                self.render_rows(&pass, Picture::SHADED, readback, 0..height, &mut |b| {
                    frame.append(b);
                    Ok(())
                })?;
            if denoise {
                self.denoise(&pass, &mut frame, &mut stats)?;
            }
            seconds += stats.render_seconds;
            gpu_seconds = gpu_seconds.zip(stats.gpu_seconds).map(|(a, b)| a + b);
            denoise_seconds += stats.denoise.as_ref().map_or(0.0, |d| d.seconds);
            let estimate = stats.summary.estimated_relative_rmse;
            passes.push(TargetPass {
                samples,
                estimated_relative_rmse: estimate,
            });
            let met = estimate.is_some_and(|e| e <= target);
            if met || samples >= most {
                stats.render_seconds = seconds;
                stats.gpu_seconds = gpu_seconds;
                if let Some(d) = &mut stats.denoise {
                    d.seconds = denoise_seconds;
                    d.gpu_seconds = None;
                }
                stats.target = Some(TargetStats {
                    stopped_by: if met { "target_error" } else { "samples" },
                    target_passes: passes,
                });
                sink(&frame)?;
                return Ok(stats);
            }
            samples = next_samples(samples, estimate, target, most);
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_next_pass_asks_for_the_samples_the_estimate_predicts() {
        // 16 samples at twice the target: 4x the samples, times the margin: 76.8, so 78.
        assert_eq!(next_samples(16, Some(0.04), 0.02, 4096), 78);
        // Just over the target: at least 1.5x, even.
        assert_eq!(next_samples(16, Some(0.0201), 0.02, 4096), 24);
        assert_eq!(next_samples(15, Some(0.0201), 0.02, 4096), 24);
        // Never past image.samples, even where that is odd.
        assert_eq!(next_samples(16, Some(1.0), 0.02, 4095), 4095);
        // No estimate: straight to image.samples.
        assert_eq!(next_samples(16, None, 0.02, 1000), 1000);
    }
}
