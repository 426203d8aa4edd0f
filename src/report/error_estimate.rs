//! The error estimate held to the measured error (`--stats`' `estimated_rmse`, src/estimate.rs):
//! a scene rendered over several seeds, raw and denoised, each render's estimate against its
//! RMSE from a reference of independent `random` samples, with the reference's own variance
//! taken out. tests/render/error_estimate.rs and `examples/error_estimate.rs` both measure here.

use super::monte_carlo::{image_mean, render_stats};
use crate::error::Result;
use crate::frame::Frame;
use crate::render::Planner;
use crate::scene::{PathSampler, Scene};

/// A reference: the mean of two renders of `random` samples, each of half its samples and its
/// own seed, and its variance per value, E[(r1 - r2)^2] / 4 over the image (measured from the
/// two renders, not from the code under test's estimate).
pub struct Reference {
    pub image: Vec<[f32; 3]>,
    /// The mean over the image's values of the reference's variance.
    pub variance: f64,
}

/// `scene`'s reference of `samples` `random` samples (two renders of half as many, seeds
/// 1,000,001 and 1,000,002).
pub fn reference(planner: &mut Planner, scene: &Scene, samples: u32) -> Result<Reference> {
    let mut renders = Vec::new();
    for seed in [1_000_001, 1_000_002] {
        let mut s = scene.clone();
        s.path.sampler = PathSampler::Random;
        s.path.seed = seed;
        s.path.noise_target = 0.0;
        s.image.samples = samples / 2;
        s.image.denoise = crate::denoise::Denoiser::None;
        renders.push(super::monte_carlo::render(planner, &s)?.0.radiance);
    }
    let (one, two) = (&renders[0], &renders[1]);
    let image = one
        .iter()
        .zip(two)
        .map(|(a, b)| [0, 1, 2].map(|c| (a[c] + b[c]) / 2.0))
        .collect();
    let squared: f64 = one
        .iter()
        .zip(two)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).powi(2) / 4.0))
        .sum();
    Ok(Reference {
        image,
        variance: squared / (3 * one.len().max(1)) as f64,
    })
}

/// One render's estimate and its measured error.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Check {
    /// `estimated_rmse` of the render.
    pub estimated: f64,
    /// Its RMSE against the reference, the reference's variance taken out: sqrt(max(MSE -
    /// variance, 0)).
    pub measured: f64,
}

/// The mean over the image's values of the squared error of `image` against `reference`, its
/// variance taken out.
pub fn measured_mse(image: &[[f32; 3]], reference: &Reference) -> f64 {
    let squared: f64 = image
        .iter()
        .zip(&reference.image)
        .flat_map(|(a, b)| (0..3).map(move |c| (a[c] as f64 - b[c] as f64).powi(2)))
        .sum();
    (squared / (3 * image.len().max(1)) as f64 - reference.variance).max(0.0)
}

/// Renders `scene` (its sampler, samples and denoiser as they are) at each of `seeds`, and holds
/// each render's estimate against its error: the root of the mean over the seeds of each.
pub fn check(
    planner: &mut Planner,
    scene: &Scene,
    seeds: &[u32],
    reference: &Reference,
) -> Result<Check> {
    let (mut estimated, mut measured) = (0.0, 0.0);
    for &seed in seeds {
        let mut s = scene.clone();
        s.path.seed = seed;
        let (frame, estimate) = render_estimated(planner, &s)?;
        let e = estimate.ok_or_else(|| {
            crate::error::Error::Unsupported("the render gave no error estimate".into())
        })?;
        estimated += e * e;
        measured += measured_mse(frame.linear(), reference);
    }
    let n = seeds.len().max(1) as f64;
    Ok(Check {
        estimated: (estimated / n).sqrt(),
        measured: (measured / n).sqrt(),
    })
}

/// A render of `scene` with its stats' `estimated_rmse`.
pub fn render_estimated(planner: &mut Planner, scene: &Scene) -> Result<(Frame, Option<f64>)> {
    let (frame, stats) = render_stats(planner, scene)?;
    Ok((frame, stats.summary.estimated_rmse))
}

/// Renders to `image.target_error` and what came of it.
#[derive(Clone, Debug, PartialEq)]
pub struct TargetCheck {
    /// Per seed: the samples of the last pass, whether the target stopped it, its estimated
    /// and its measured relative RMSE (the measured one over the reference's mean).
    pub renders: Vec<(u32, bool, f64, f64)>,
}

impl TargetCheck {
    /// The root mean square over the seeds of the measured relative RMSE.
    pub fn measured(&self) -> f64 {
        let n = self.renders.len().max(1) as f64;
        (self.renders.iter().map(|r| r.3 * r.3).sum::<f64>() / n).sqrt()
    }

    /// The mean over the seeds of the samples of the last pass.
    pub fn mean_samples(&self) -> f64 {
        let n = self.renders.len().max(1) as f64;
        self.renders.iter().map(|r| r.0 as f64).sum::<f64>() / n
    }
}

/// Renders `scene` (with its `image.target_error`) at each of `seeds` against `reference`.
pub fn check_target(
    planner: &mut Planner,
    scene: &Scene,
    seeds: &[u32],
    reference: &Reference,
) -> Result<TargetCheck> {
    let mean = image_mean(&reference.image);
    let mut renders = Vec::new();
    for &seed in seeds {
        let mut s = scene.clone();
        s.path.seed = seed;
        let (frame, stats) = render_stats(planner, &s)?;
        let target = stats
            .target
            .ok_or_else(|| crate::error::Error::Unsupported("no target passes".into()))?;
        renders.push((
            target.samples(),
            target.stopped_by == "target_error",
            stats.summary.estimated_relative_rmse.unwrap_or(f64::NAN),
            measured_mse(frame.linear(), reference).sqrt() / mean,
        ));
    }
    Ok(TargetCheck { renders })
}
