//! Path mode converges: on the path-traced preset the RMSE of the linear image against a
//! converged reference falls with a log-log slope of at most -0.45 over samples, and Sobol' is
//! no worse than the plain hash at 64 samples (the CPU twin in f32; the reference is drawn with
//! the `random` sampler, independent of the Sobol' estimates and shared with the random ones,
//! which favours random).

use qjulia::report::monte_carlo::{
    FIT_FROM, Point, TRIM, case_scene, curve_slope, render, rmse, rmse_trimmed,
};
use qjulia::scene::PathSampler;
use qjulia::scene::presets::find;
use qjulia::{Backend, Planner, PrecisionChoice, Scene};

const SIZE: u32 = 32;
const REFERENCE_SAMPLES: u32 = 4096;
const CURVE: [u32; 5] = [4, 8, 16, 32, 64];

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
            let scene = case_scene(base, sampler, base.path.bounces, samples);
            let (frame, seconds) = render(planner, &scene).expect("a CPU render");
            Point {
                samples,
                taken: samples as f64,
                rmse: rmse(&frame.radiance, reference),
                trimmed: rmse_trimmed(&frame.radiance, reference, TRIM),
                seconds,
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
    let slope = curve_slope(&sobol);
    let figures = |c: &[Point]| {
        c.iter()
            .map(|p| format!("{}: {:.5}", p.samples, p.rmse))
            .collect::<Vec<_>>()
            .join(", ")
    };
    eprintln!(
        "path-traced at {SIZE}x{SIZE}, reference {REFERENCE_SAMPLES} random samples:\n  \
         sobol  {} (slope {slope:.3} from {FIT_FROM} samples)\n  random {} (slope {:.3})",
        figures(&sobol),
        figures(&random),
        curve_slope(&random)
    );
    assert!(
        slope <= -0.45,
        "Sobol' RMSE falls with slope {slope:.3} > -0.45: {}",
        figures(&sobol)
    );
    let (s64, r64) = (sobol[4].rmse, random[4].rmse);
    assert!(
        s64 <= r64,
        "at 64 samples Sobol' has RMSE {s64:.5}, random {r64:.5}"
    );
    // The error is the estimator's, not a bias: it is well above zero at 4 samples and keeps
    // falling.
    assert!(sobol[0].rmse > 2.0 * sobol[4].rmse);
}
