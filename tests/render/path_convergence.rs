//! Path mode converges: on the path-traced preset the RMSE of the linear image against a
//! converged reference, the worst 0.5% of pixels left out (`TRIM`: a rare glint's pixels), falls
//! with a log-log slope of at most -0.45 over samples, and Sobol' is no worse than the plain
//! hash at 64 samples (the CPU twin in f32; the reference is drawn with
//! the `random` sampler, independent of the Sobol' estimates and shared with the random ones,
//! which favours random). Each point's RMSE is the root of the mean squared error over
//! [`SEEDS`] seeds (`path.seed`): one render's error turns on whether a rare glint lands in it,
//! and so does a single curve's shape.

use qjulia::report::monte_carlo::{
    FIT_FROM, Point, TRIM, case_scene, curve_slope, render, rmse, rmse_trimmed,
};
use qjulia::scene::PathSampler;
use qjulia::scene::presets::find;
use qjulia::{Backend, Planner, PrecisionChoice, Scene};

const SIZE: u32 = 32;
const REFERENCE_SAMPLES: u32 = 4096;
const CURVE: [u32; 5] = [4, 8, 16, 32, 64];
/// Independent renders (`path.seed` 0..SEEDS) averaged at each point.
const SEEDS: u32 = 4;

fn preset(size: u32) -> Scene {
    let mut scene = find("path-traced").expect("the path-traced preset").scene();
    scene.image.width = size;
    scene.image.height = size;
    scene
}

fn curve(
    planner: &mut Planner,
    base: &Scene,
    sampler: PathSampler,
    reference: &[[f32; 3]],
) -> Vec<Point> {
    CURVE
        .iter()
        .map(|&samples| {
            // Squared errors and seconds summed over the seeds.
            let (mut squared, mut trimmed, mut seconds) = (0.0, 0.0, 0.0);
            for seed in 0..SEEDS {
                let mut scene = case_scene(base, sampler, base.path.bounces, samples);
                scene.path.seed = seed;
                let (frame, s) = render(planner, &scene).expect("a CPU render");
                squared += rmse(&frame.radiance, reference).powi(2);
                trimmed += rmse_trimmed(&frame.radiance, reference, TRIM).powi(2);
                seconds += s;
            }
            let n = SEEDS as f64;
            Point {
                samples,
                taken: samples as f64,
                rmse: (squared / n).sqrt(),
                trimmed: (trimmed / n).sqrt(),
                seconds: seconds / n,
                estimated: None,
            }
        })
        .collect()
}

#[test]
fn the_path_traced_preset_converges_and_sobol_is_no_worse_than_random() {
    let mut planner = Planner::new(Backend::Cpu, PrecisionChoice::F32);
    let base = preset(SIZE);
    let reference_scene = case_scene(
        &base,
        PathSampler::Random,
        base.path.bounces,
        REFERENCE_SAMPLES,
    );
    let reference = render(&mut planner, &reference_scene)
        .expect("the reference")
        .0
        .radiance;
    let sobol = curve(&mut planner, &base, PathSampler::Sobol, &reference);
    let random = curve(&mut planner, &base, PathSampler::Random, &reference);
    // The curves the test holds: the trimmed RMSE (the worst TRIM of the pixels left out: a
    // rare glint's pixels, whose error a render's luck decides).
    let trimmed = |c: &[Point]| -> Vec<Point> {
        c.iter()
            .map(|p| Point {
                rmse: p.trimmed,
                ..*p
            })
            .collect()
    };
    let (sobol_t, random_t) = (trimmed(&sobol), trimmed(&random));
    let slope = curve_slope(&sobol_t);
    let figures = |c: &[Point]| {
        c.iter()
            .map(|p| format!("{}: {:.5}", p.samples, p.rmse))
            .collect::<Vec<_>>()
            .join(", ")
    };
    eprintln!(
        "path-traced at {SIZE}x{SIZE}, reference {REFERENCE_SAMPLES} random samples, {SEEDS} \
         seeds:\n  sobol  {} (slope {:.3})\n  random {} (slope {:.3})\n  trimmed: sobol {} (slope \
         {slope:.3} from {FIT_FROM} samples)\n  trimmed: random {} (slope {:.3})",
        figures(&sobol),
        curve_slope(&sobol),
        figures(&random),
        curve_slope(&random),
        figures(&sobol_t),
        figures(&random_t),
        curve_slope(&random_t)
    );
    assert!(
        slope <= -0.45,
        "Sobol' trimmed RMSE falls with slope {slope:.3} > -0.45: {}",
        figures(&sobol_t)
    );
    let (s64, r64) = (sobol_t[4].rmse, random_t[4].rmse);
    assert!(
        s64 <= r64,
        "at 64 samples Sobol' has trimmed RMSE {s64:.5}, random {r64:.5}"
    );
    // The error is the estimator's, not a bias: it is well above zero at 4 samples and keeps
    // falling.
    assert!(sobol_t[0].rmse > 2.0 * sobol_t[4].rmse);
}
