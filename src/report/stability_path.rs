//! Path mode's stiff and extreme cases (issue 35): on every tracer each case finishes, holds no
//! NaN or Inf, gives the same bytes twice, and its image's mean luminance lies within 3 standard
//! errors of the f64 CPU render's, the error taken from an independent run of the `random`
//! sampler. Used by the tests and by `qjulia report --stability` (its second table).

use std::sync::Arc;
use std::time::Duration;

use super::stability::{Case, Runner, render_twice, runners, with_time_limit};
use crate::algebra::Vec3;
use crate::cpu::bsdf::luminance;
use crate::gpu::{GpuKernels, Readback};
use crate::scene::Scene;
use crate::{Frame, Picture};

/// The path-mode cases: each adds its keys to path mode at `PATH_SAMPLES` samples with the
/// default sky.
pub const PATH_CASES: &[Case] = &[
    Case {
        name: "sun 0.001°",
        why: "cos(radius) is 1 in f32",
        sets: &["sun.intensity=3", "sun.angular_radius_degrees=0.001"],
    },
    Case {
        name: "sun 0.01°",
        why: "cos(radius) is 1 in f32 (NaN in 44% of pixels before)",
        sets: &["sun.intensity=3", "sun.angular_radius_degrees=0.01"],
    },
    Case {
        name: "sun 0.53°",
        why: "the real sun",
        sets: &["sun.intensity=3", "sun.angular_radius_degrees=0.53"],
    },
    Case {
        name: "sun 45°",
        why: "a wide disc",
        sets: &["sun.intensity=3", "sun.angular_radius_degrees=45"],
    },
    Case {
        name: "sun 90°",
        why: "a hemisphere",
        sets: &["sun.intensity=3", "sun.angular_radius_degrees=90"],
    },
    Case {
        name: "sphere light r = 1e-4",
        why: "its cone's cosine is 1 in f32 (black before)",
        sets: &["sky.intensity=0", "light.radius=1e-4", "light.intensity=20"],
    },
    Case {
        name: "sphere light r = 1 at 2",
        why: "a large light near the set",
        sets: &[
            "sky.intensity=0",
            "light.radius=1",
            "light.position=[0,2,0]",
            "light.intensity=5",
        ],
    },
    Case {
        name: "intensity 1e-6",
        why: "radiance near f32's small numbers",
        sets: &["sun.intensity=1e-6", "sky.intensity=1e-6"],
    },
    Case {
        name: "intensity 1e6",
        why: "radiance near f32's large numbers",
        sets: &["sun.intensity=1e6", "sky.intensity=1e6"],
    },
    Case {
        name: "roughness 0, metallic 0",
        why: "the sharpest dielectric lobe",
        sets: &[
            "sun.intensity=3",
            "material.roughness=0",
            "material.metallic=0",
        ],
    },
    Case {
        name: "roughness 0, metallic 1",
        why: "a mirror",
        sets: &[
            "sun.intensity=3",
            "material.roughness=0",
            "material.metallic=1",
        ],
    },
    Case {
        name: "roughness 1, metallic 0",
        why: "the widest lobe",
        sets: &[
            "sun.intensity=3",
            "material.roughness=1",
            "material.metallic=0",
        ],
    },
    Case {
        name: "roughness 1, metallic 1",
        why: "a rough metal",
        sets: &[
            "sun.intensity=3",
            "material.roughness=1",
            "material.metallic=1",
        ],
    },
    Case {
        name: "16 bounces",
        why: "the longest paths, roulette",
        sets: &["sun.intensity=3", "path.bounces=16"],
    },
    Case {
        name: "crevice (30 steps)",
        why: "rays run out of steps",
        sets: &["sun.intensity=3", "fractal.max_steps=30"],
    },
    Case {
        name: "eye inside the set",
        why: "the first estimate is negative",
        sets: &[
            "sun.intensity=3",
            "camera.eye=[0.05,0.02,0.0]",
            "camera.target=[0,0,-1]",
        ],
    },
    Case {
        name: "deep zoom (f64 only)",
        why: "pixels below the f32 spacing",
        sets: &[
            "sun.intensity=3",
            "camera.fov_y_degrees=0.0002",
            "fractal.epsilon=1e-7",
            "camera.target=[-0.1,0.05,0.3]",
        ],
    },
    Case {
        name: "clamp 1",
        why: "the clamp on",
        sets: &["sun.intensity=3", "path.clamp=1"],
    },
];

/// Samples a pixel in every case.
pub const PATH_SAMPLES: u32 = 16;

/// A path case's scene: path mode, `PATH_SAMPLES` samples, the case's keys, `size` square.
pub fn path_scene(case: &Case, size: u32) -> Scene {
    let mut scene = case.scene(size);
    scene.shading.model = crate::scene::ShadingModel::Path;
    scene.image.samples = PATH_SAMPLES;
    scene
}

/// What one path case did on one tracer.
#[derive(Clone, Debug)]
pub struct PathOutcome {
    pub case: &'static str,
    pub runner: Runner,
    /// None when it did not finish within the limit (or failed).
    pub seconds: Option<f64>,
    pub error: Option<String>,
    /// NaN or Inf values in the frame (radiance, depth but its miss marker).
    pub non_finite: u64,
    /// Samples the renderer dropped as not finite (`--stats`' `nonfinite_samples`).
    pub dropped: u64,
    /// Rays that ran out of steps (`--stats`' `exhausted_rays`).
    pub exhausted: u64,
    /// The same radiance, depth and steps, bit for bit, twice.
    pub deterministic: bool,
    /// The image's mean luminance.
    pub mean: f64,
    /// The reference's standard error, and how many of them this mean lies from the f64 CPU's
    /// (None for the reference itself, and where the case is compared in f64 only).
    pub versus_f64: Option<(f64, f64)>,
}

impl PathOutcome {
    /// Finished, finite, repeatable, and within 3 standard errors of the reference.
    pub fn passed(&self) -> bool {
        self.seconds.is_some()
            && self.error.is_none()
            && self.non_finite == 0
            && self.deterministic
            && self.versus_f64.is_none_or(|(_, z)| z <= 3.0)
    }
}

/// The mean over pixels of the frame's luminance (the path tracer's own `luminance`, in f64).
fn mean_luminance(frame: &Frame) -> f64 {
    let n = frame.radiance.len().max(1) as f64;
    frame
        .radiance
        .iter()
        .map(|c| luminance(Vec3::<f64>::from_f64(c.map(f64::from))))
        .sum::<f64>()
        / n
}

/// The standard error of the image's mean luminance, from a render whose samples are
/// independent (the `random` sampler): each pixel's M2 of its samples' luminances gives its
/// mean's variance M2 / (n (n - 1)), and the image's mean has the sum of them over P^2.
fn standard_error(frame: &Frame, samples: u32) -> f64 {
    let n = samples as f64;
    let p = frame.luminance_m2.len().max(1) as f64;
    let variance: f64 = frame
        .luminance_m2
        .iter()
        .map(|&m2| m2 as f64 / (n * (n - 1.0)))
        .sum();
    variance.sqrt() / p
}

fn same(a: &Frame, b: &Frame) -> bool {
    let bits = |f: &Frame| -> Vec<u32> {
        let radiance = f.radiance.iter().flatten().map(|v| v.to_bits());
        radiance
            .chain(f.depth.iter().map(|d| d.to_bits()))
            .collect()
    };
    bits(a) == bits(b) && a.steps == b.steps
}

/// Renders `scene` on `runner`, reading back `readback`.
fn render(
    runner: Runner,
    scene: &Scene,
    gpu: Option<&Arc<GpuKernels>>,
    readback: Readback,
) -> crate::Result<Frame> {
    let plan = runner.plan(scene, gpu)?;
    let mut frame = Frame::empty(scene.image.width);
    plan.renderer
        .render_with(scene, Picture::SHADED, readback, &mut |band| {
            frame.append(band);
            Ok(())
        })?;
    Ok(frame)
}

/// The reference of a case: the f64 CPU's mean luminance, and the standard error of a mean of
/// that many samples from its independent (`random` sampler) render.
pub fn reference(case: &Case, size: u32) -> crate::Result<(f64, f64)> {
    let scene = path_scene(case, size);
    let sobol = render(Runner::CpuF64, &scene, None, Readback::All)?;
    let mut random = scene.clone();
    random.path.sampler = crate::scene::PathSampler::Random;
    let independent = render(Runner::CpuF64, &random, None, Readback::Hdr)?;
    Ok((
        mean_luminance(&sobol),
        standard_error(&independent, scene.image.samples),
    ))
}

/// Runs one path case on one tracer twice, under the time limit, against `reference` (the f64
/// CPU's mean and standard error).
pub fn run_path_case(
    case: &'static Case,
    size: u32,
    runner: Runner,
    gpu: Option<Arc<GpuKernels>>,
    reference: Option<(f64, f64)>,
    limit: Duration,
) -> PathOutcome {
    let scene = path_scene(case, size);
    let mut outcome = PathOutcome {
        case: case.name,
        runner,
        seconds: None,
        error: None,
        non_finite: 0,
        dropped: 0,
        exhausted: 0,
        deterministic: false,
        mean: 0.0,
        versus_f64: None,
    };
    let run = render_twice(limit, move || {
        render(runner, &scene, gpu.as_ref(), Readback::All)
    });
    match run {
        None => outcome.error = Some(format!("did not finish within {} s", limit.as_secs())),
        Some(Err(e)) => outcome.error = Some(e.to_string()),
        Some(Ok((first, second, seconds))) => {
            outcome.seconds = Some(seconds);
            let radiance = |f: &Frame| {
                let values = f.radiance.iter().flatten();
                values.filter(|v| !v.is_finite()).count() as u64
            };
            outcome.non_finite =
                first.non_finite + second.non_finite + radiance(&first) + radiance(&second);
            outcome.dropped = first.nonfinite_samples;
            outcome.exhausted = first.exhausted_rays;
            outcome.deterministic = same(&first, &second);
            outcome.mean = mean_luminance(&first);
            let compared = runner.precision() == crate::Precision::F64 || !f64_only(case.name);
            outcome.versus_f64 = reference.filter(|_| compared).map(|(mean, se)| {
                // A floor of 1e-5 of the mean: f32's rounding where the estimate has no noise.
                let se = se.max(1e-5 * mean.abs());
                let off = (outcome.mean - mean).abs();
                // An image with no noise and no error (all black: the eye inside the set).
                (se, if off == 0.0 { 0.0 } else { off / se })
            });
        }
    }
    outcome
}

/// Every path case on every runner given, the f64 CPU first as the reference for the others.
pub fn run_all_path(
    size: u32,
    gpu: Option<Arc<GpuKernels>>,
    limit: Duration,
    mut progress: impl FnMut(&PathOutcome),
) -> Vec<PathOutcome> {
    let mut outcomes = Vec::new();
    for case in PATH_CASES {
        let reference = with_time_limit(limit, move || reference(case, size).ok()).flatten();
        for runner in runners(gpu.as_ref()) {
            let against = match runner {
                Runner::CpuF64 => None,
                _ => reference,
            };
            let outcome = run_path_case(case, size, runner, gpu.clone(), against, limit);
            progress(&outcome);
            outcomes.push(outcome);
        }
    }
    outcomes
}

/// The path outcomes as a Markdown section: its heading, what it holds, the table and a totals
/// line.
pub fn path_markdown(size: u32, outcomes: &[PathOutcome]) -> String {
    let mut out = format!(
        "\n## Path mode\n\nEach case is path mode at {size}x{size}, {PATH_SAMPLES} samples, with \
         the default sky unless it says otherwise, run twice per tracer. `mean` is the image's \
         mean luminance; `SE` the standard error of the f64 CPU's, from an independent render \
         with the `random` sampler (each pixel's variance of its samples' luminances), at least \
         1e-5 of the mean; `vs f64` how many of them the tracer's mean lies from the f64 CPU's \
         (at most 3 passes). `dropped` counts samples left out as not finite, `ran out` the \
         rays that ran out of steps.\n\n\
         | case | tracer | seconds | NaN/Inf | dropped | ran out | repeatable | mean | SE | vs f64 | notes |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n"
    );
    for o in outcomes {
        let seconds = o.seconds.map_or("—".into(), |s| format!("{s:.3}"));
        let (se, z) = o
            .versus_f64
            .map_or(("ref".into(), "ref".into()), |(se, z)| {
                (format!("{se:.2e}"), format!("{z:.2}"))
            });
        let (se, z) = match (o.runner, f64_only(o.case)) {
            (Runner::CpuF32 | Runner::GpuF32, true) => ("—".into(), "not compared".into()),
            _ => (se, z),
        };
        out += &format!(
            "| {} | {} | {seconds} | {} | {} | {} | {} | {:.4e} | {se} | {z} | {} |\n",
            o.case,
            o.runner.name(),
            o.non_finite,
            o.dropped,
            o.exhausted,
            if o.deterministic { "yes" } else { "NO" },
            o.mean,
            o.error.clone().unwrap_or_default()
        );
    }
    let failed = outcomes.iter().filter(|o| !o.passed()).count();
    let nan: u64 = outcomes.iter().map(|o| o.non_finite).sum();
    out += &format!(
        "\n{} runs: {} passed, {failed} failed; {nan} NaN/Inf values.\n",
        outcomes.len(),
        outcomes.len() - failed
    );
    out
}

/// Whether the case of this name is compared in f64 only (f32 cannot resolve it).
fn f64_only(name: &str) -> bool {
    name.contains("f64 only")
}
