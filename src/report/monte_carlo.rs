//! The work-precision report's Monte Carlo page (`qjulia report --monte-carlo`): how fast path
//! mode's linear image converges. For each case (a scene, a sampler, a number of bounces) the
//! RMSE of the linear image against a converged reference of the same scene and bounces,
//! against samples per pixel and against seconds, log-log, with the fitted slope. Writes
//! `monte_carlo.csv`, `monte_carlo.png` and `monte_carlo.md`.
//!
//! The reference is rendered with the `random` sampler (the plain hash), so that the Sobol'
//! curves are measured against an independent estimate. A `random` curve's first samples are
//! the reference's own first samples: its RMSE is biased low by at most the share
//! `n / reference_samples` of the reference they make, which favours `random` in the
//! comparison, not Sobol'.

use std::path::Path;

use crate::error::Result;
use crate::frame::Frame;
use crate::render::{Picture, Planner};
use crate::scene::presets::find;
use crate::scene::{PathSampler, Scene};

/// Samples per pixel of each point of a curve.
pub const SAMPLES: [u32; 9] = [1, 2, 4, 8, 16, 32, 64, 128, 256];

/// The slope is fitted over the points with at least this many samples (the first few are
/// dominated by sample 0, the pixel centre, which every sampler shares).
pub const FIT_FROM: u32 = 4;

/// One curve: what is varied.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    pub scene_name: &'static str,
    pub sampler: PathSampler,
    pub bounces: u32,
}

/// One measured point of a curve.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Point {
    pub samples: u32,
    /// Root mean square error of the linear RGB (every channel of every pixel) against the
    /// reference.
    pub rmse: f64,
    /// The RMSE over all but the [`TRIM`] share of pixels with the largest errors: the
    /// error of the bulk of the image, without the rare glints (a small bright sun seen in a
    /// glossy lobe) that dominate the RMSE of a few pixels.
    pub trimmed: f64,
    /// The render's GPU seconds where the device times it, else its render seconds.
    pub seconds: f64,
}

/// A measured curve, its fitted log-log slope (RMSE against samples) and its reference's mean
/// linear radiance.
#[derive(Clone, Debug)]
pub struct Curve {
    pub case: Case,
    pub points: Vec<Point>,
    pub slope: f64,
    pub reference_mean: f64,
}

/// The page's scenes at `size` x `size`: the two path presets, and the path-traced preset as a
/// rough metal.
pub fn scenes(size: u32) -> Vec<(&'static str, Scene)> {
    let preset = |slug: &str| find(slug).expect("a path preset").scene();
    let mut metal = preset("path-traced");
    metal.material.metallic = 1.0;
    metal.material.roughness = 0.6;
    let mut out = vec![
        ("path-traced", preset("path-traced")),
        ("path-gallery", preset("path-gallery")),
        ("rough metal", metal),
    ];
    for (_, scene) in &mut out {
        scene.image.width = size;
        scene.image.height = size;
    }
    out
}

/// The cases: every scene with both samplers at 3 bounces, and the path-traced preset with
/// Sobol' at 1 and 5 bounces.
pub fn cases() -> Vec<Case> {
    let mut out = Vec::new();
    for scene_name in ["path-traced", "path-gallery", "rough metal"] {
        for sampler in PathSampler::ALL {
            out.push(Case {
                scene_name,
                sampler,
                bounces: 3,
            });
        }
    }
    for bounces in [1, 5] {
        out.push(Case {
            scene_name: "path-traced",
            sampler: PathSampler::Sobol,
            bounces,
        });
    }
    out
}

/// The RMSE of two linear images over every channel of every pixel.
pub fn rmse(a: &[[f32; 3]], b: &[[f32; 3]]) -> f64 {
    assert_eq!(a.len(), b.len(), "images of one size");
    let sum: f64 = a
        .iter()
        .zip(b)
        .flat_map(|(p, q)| (0..3).map(move |c| (p[c] as f64 - q[c] as f64).powi(2)))
        .sum();
    (sum / (3 * a.len().max(1)) as f64).sqrt()
}

/// The share of pixels with the largest errors that [`rmse_trimmed`] leaves out.
pub const TRIM: f64 = 0.005;

/// The RMSE of two linear images over every channel of all but the `trim` share of pixels
/// with the largest errors.
pub fn rmse_trimmed(a: &[[f32; 3]], b: &[[f32; 3]], trim: f64) -> f64 {
    assert_eq!(a.len(), b.len(), "images of one size");
    let mut errors: Vec<f64> = a
        .iter()
        .zip(b)
        .map(|(p, q)| {
            (0..3)
                .map(|c| (p[c] as f64 - q[c] as f64).powi(2))
                .sum::<f64>()
        })
        .collect();
    errors.sort_by(f64::total_cmp);
    let keep = ((1.0 - trim) * errors.len() as f64).ceil() as usize;
    let kept = &errors[..keep.min(errors.len())];
    (kept.iter().sum::<f64>() / (3 * kept.len().max(1)) as f64).sqrt()
}

/// The least-squares slope of log y against log x.
pub fn fit_slope(points: &[(f64, f64)]) -> f64 {
    let logs: Vec<(f64, f64)> = points.iter().map(|&(x, y)| (x.ln(), y.ln())).collect();
    let n = logs.len() as f64;
    let (mx, my) = logs
        .iter()
        .fold((0.0, 0.0), |(a, b), &(x, y)| (a + x / n, b + y / n));
    let (sxy, sxx) = logs.iter().fold((0.0, 0.0), |(a, b), &(x, y)| {
        (a + (x - mx) * (y - my), b + (x - mx) * (x - mx))
    });
    sxy / sxx
}

/// The slope of a curve's RMSE against samples, over its points from [`FIT_FROM`] samples on.
pub fn curve_slope(points: &[Point]) -> f64 {
    let fit: Vec<(f64, f64)> = points
        .iter()
        .filter(|p| p.samples >= FIT_FROM)
        .map(|p| (p.samples as f64, p.rmse))
        .collect();
    fit_slope(&fit)
}

/// A path-traced render of `scene` through `planner`: the frame and its seconds.
pub fn render(planner: &mut Planner, scene: &Scene) -> Result<(Frame, f64)> {
    let plan = planner.plan(scene, Picture::SHADED.into(), &mut |_| {})?;
    let (frame, stats) = plan.renderer.render_frame(scene, Picture::SHADED)?;
    Ok((frame, stats.gpu_seconds.unwrap_or(stats.render_seconds)))
}

/// `scene` with this case's sampler, bounces and samples.
pub fn case_scene(scene: &Scene, sampler: PathSampler, bounces: u32, samples: u32) -> Scene {
    let mut s = scene.clone();
    s.path.sampler = sampler;
    s.path.bounces = bounces;
    s.image.samples = samples;
    s
}

/// A reference's scene and bounces.
type ReferenceKey = (&'static str, u32);

/// Measures every case at `size` x `size` against references of `reference_samples` (at least
/// 4 times the most samples of a point, so that no `random` point is most of its reference),
/// telling `progress` (what, done, of) as it goes.
pub fn run(
    planner: &mut Planner,
    size: u32,
    reference_samples: u32,
    progress: &mut dyn FnMut(&str, usize, usize),
) -> Result<Vec<Curve>> {
    let most = SAMPLES[SAMPLES.len() - 1];
    assert!(
        reference_samples >= 4 * most,
        "a reference of {reference_samples} samples, at least {}",
        4 * most
    );
    let scenes = scenes(size);
    let cases = cases();
    let total = cases.len() * (SAMPLES.len() + 1);
    let mut done = 0;
    let mut references: Vec<(ReferenceKey, Vec<[f32; 3]>)> = Vec::new();
    let mut curves = Vec::new();
    for case in cases {
        let base = &scenes
            .iter()
            .find(|(name, _)| *name == case.scene_name)
            .expect("a scene of the page")
            .1;
        let key = (case.scene_name, case.bounces);
        if !references.iter().any(|(k, _)| *k == key) {
            progress(
                &format!("{} reference, {} bounces", case.scene_name, case.bounces),
                done,
                total,
            );
            let scene = case_scene(base, PathSampler::Random, case.bounces, reference_samples);
            references.push((key, render(planner, &scene)?.0.radiance));
        }
        done += 1;
        let reference = &references
            .iter()
            .find(|(k, _)| *k == key)
            .expect("made above")
            .1;
        let mut points = Vec::new();
        for samples in SAMPLES {
            progress(
                &format!(
                    "{} {} {} bounces, {samples} samples",
                    case.scene_name,
                    case.sampler.name(),
                    case.bounces
                ),
                done,
                total,
            );
            let scene = case_scene(base, case.sampler, case.bounces, samples);
            let (frame, seconds) = render(planner, &scene)?;
            points.push(Point {
                samples,
                rmse: rmse(&frame.radiance, reference),
                trimmed: rmse_trimmed(&frame.radiance, reference, TRIM),
                seconds,
            });
            done += 1;
        }
        let reference_mean = reference
            .iter()
            .map(|p| (p[0] + p[1] + p[2]) as f64 / 3.0)
            .sum::<f64>()
            / reference.len().max(1) as f64;
        curves.push(Curve {
            slope: curve_slope(&points),
            case,
            points,
            reference_mean,
        });
    }
    Ok(curves)
}

/// The curves as CSV: one row per point.
pub fn csv(curves: &[Curve]) -> String {
    let mut out = String::from("scene,sampler,bounces,samples,rmse,rmse_trimmed,seconds\n");
    for c in curves {
        for p in &c.points {
            out.push_str(&format!(
                "{},{},{},{},{:.6e},{:.6e},{:.6}\n",
                c.case.scene_name,
                c.case.sampler.name(),
                c.case.bounces,
                p.samples,
                p.rmse,
                p.trimmed,
                p.seconds
            ));
        }
    }
    out
}

/// A curve's label: scene, sampler and bounces.
fn label(c: &Case) -> String {
    format!("{} {} {}b", c.scene_name, c.sampler.name(), c.bounces)
}

/// The point of a curve at `samples`.
fn at(curve: &Curve, samples: u32) -> Option<&Point> {
    curve.points.iter().find(|p| p.samples == samples)
}

/// The page: the table of slopes, the verdicts and what each choice buys.
pub fn markdown(curves: &[Curve], size: u32, reference_samples: u32, machine: &str) -> String {
    let mut md = format!(
        "# Monte Carlo convergence (path mode)\n\n\
         `qjulia report --monte-carlo --size {size}` on {machine}. Each curve is the RMSE of the \
         linear image (every channel of every pixel, {size}x{size}) against a reference of \
         {reference_samples} samples per pixel of the same scene and bounces, drawn with the \
         `random` sampler. A `random` curve shares its first samples with the reference, which \
         biases its RMSE low by up to n/{reference_samples}: in `random`'s favour. The slope is \
         the least-squares fit of log RMSE against log samples from {FIT_FROM} samples on \
         (-0.5 is plain Monte Carlo). Seconds are the render's GPU seconds where the device \
         times them. \"Trimmed\" leaves out the {trim}% of pixels with the largest errors: a \
         small bright sun seen in a glossy lobe makes rare glints, a sample or two worth \
         hundreds of times a pixel's mean, and those few pixels can rule the RMSE, one sampler \
         meeting a glint that the other misses.\n\n\
         ![RMSE against samples and seconds](monte_carlo.png)\n\n\
         | curve | slope | RMSE at 16 | RMSE at 64 | RMSE at 256 | trimmed at 64 | seconds at 64 | reference mean |\n\
         |---|---|---|---|---|---|---|---|\n",
        trim = 100.0 * TRIM
    );
    let cell = |c: &Curve, n: u32| at(c, n).map_or("-".into(), |p| format!("{:.4}", p.rmse));
    for c in curves {
        md.push_str(&format!(
            "| {} | {:.3} | {} | {} | {} | {} | {} | {:.4} |\n",
            label(&c.case),
            c.slope,
            cell(c, 16),
            cell(c, 64),
            cell(c, 256),
            at(c, 64).map_or("-".into(), |p| format!("{:.4}", p.trimmed)),
            at(c, 64).map_or("-".into(), |p| format!("{:.3}", p.seconds)),
            c.reference_mean
        ));
    }
    md.push_str("\n## Verdicts\n\n");
    let find = |scene: &str, sampler: PathSampler, bounces: u32| {
        curves.iter().find(|c| {
            c.case.scene_name == scene && c.case.sampler == sampler && c.case.bounces == bounces
        })
    };
    for scene in ["path-traced", "path-gallery", "rough metal"] {
        let (Some(s), Some(r)) = (
            find(scene, PathSampler::Sobol, 3),
            find(scene, PathSampler::Random, 3),
        ) else {
            continue;
        };
        let (Some(s64), Some(r64)) = (at(s, 64), at(r, 64)) else {
            continue;
        };
        md.push_str(&format!(
            "- **{scene}, Sobol' against random** (3 bounces, 64 samples): RMSE {:.4} against \
             {:.4}, so Sobol' has {:.2}x random's error ({:.4} against {:.4} trimmed: {:.2}x); \
             at equal error plain Monte Carlo needs {:.2}x Sobol's samples ({:.2}x trimmed); \
             slopes {:.3} and {:.3}.\n",
            s64.rmse,
            r64.rmse,
            s64.rmse / r64.rmse,
            s64.trimmed,
            r64.trimmed,
            s64.trimmed / r64.trimmed,
            (r64.rmse / s64.rmse).powi(2),
            (r64.trimmed / s64.trimmed).powi(2),
            s.slope,
            r.slope
        ));
    }
    let bounce_curves: Vec<&Curve> = [1, 3, 5]
        .iter()
        .filter_map(|&b| find("path-traced", PathSampler::Sobol, b))
        .collect();
    if bounce_curves.len() == 3 {
        let (one, three, five) = (bounce_curves[0], bounce_curves[1], bounce_curves[2]);
        let cost = |c: &Curve| at(c, 64).map_or(f64::NAN, |p| p.seconds);
        md.push_str(&format!(
            "- **Bounces** (path-traced, Sobol'): the reference's mean radiance is {:.4} at 1 \
             bounce, {:.4} at 3 and {:.4} at 5: 3 bounces add {:.1}% light over direct light \
             alone, 5 add {:.2}% more over 3. 64 samples take {:.3} s, {:.3} s and {:.3} s. \
             RMSE at 64 samples: {:.4}, {:.4}, {:.4}.\n",
            one.reference_mean,
            three.reference_mean,
            five.reference_mean,
            100.0 * (three.reference_mean / one.reference_mean - 1.0),
            100.0 * (five.reference_mean / three.reference_mean - 1.0),
            cost(one),
            cost(three),
            cost(five),
            at(one, 64).map_or(f64::NAN, |p| p.rmse),
            at(three, 64).map_or(f64::NAN, |p| p.rmse),
            at(five, 64).map_or(f64::NAN, |p| p.rmse),
        ));
    }
    md
}

/// `monte_carlo.png`: RMSE against samples (left) and against seconds (right), log-log, one
/// series per curve.
pub fn plot(path: &Path, curves: &[Curve]) -> std::result::Result<(), String> {
    use plotters::prelude::*;
    crate::heatmap::register_plot_font();
    let (w, h) = (1400u32, 640u32);
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let panels = root.split_evenly((1, 2));
        type Axis = (&'static str, fn(&Point) -> f64);
        let x_of: [Axis; 2] = [
            ("samples per pixel (log)", |p| p.samples as f64),
            ("seconds per image (log)", |p| p.seconds.max(1e-5)),
        ];
        for (panel, (x_desc, x)) in panels.iter().zip(x_of) {
            let all: Vec<(f64, f64)> = curves
                .iter()
                .flat_map(|c| c.points.iter())
                .map(|p| (x(p).log10(), p.rmse.max(1e-6).log10()))
                .collect();
            let (x0, x1) = all
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
            let (y0, y1) = all
                .iter()
                .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!(
                        "linear RMSE against {}",
                        x_desc.split(' ').next().unwrap_or("")
                    ),
                    ("sans-serif", 24),
                )
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(70)
                .build_cartesian_2d(x0 - 0.1..x1 + 0.1, y0 - 0.1..y1 + 0.1)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_labels(8)
                .y_labels(8)
                .x_label_formatter(&|v| format!("{:.3}", 10f64.powf(*v)))
                .y_label_formatter(&|v| format!("{:.4}", 10f64.powf(*v)))
                .x_desc(x_desc)
                .y_desc("RMSE vs reference (log)")
                .label_style(("sans-serif", 15))
                .axis_desc_style(("sans-serif", 17))
                .draw()
                .map_err(|e| e.to_string())?;
            for (k, c) in curves.iter().enumerate() {
                let points: Vec<(f64, f64)> = c
                    .points
                    .iter()
                    .map(|p| (x(p).log10(), p.rmse.max(1e-6).log10()))
                    .collect();
                super::plot::draw_series(&mut chart, &points, k, &label(&c.case), 3)?;
            }
            super::plot::draw_legend(&mut chart, 14)?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    image::save_buffer(path, &buffer, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_slope_of_a_power_law_is_its_exponent() {
        let points: Vec<(f64, f64)> = [4.0, 8.0, 16.0, 64.0]
            .iter()
            .map(|&x: &f64| (x, 3.0 * x.powf(-0.5)))
            .collect();
        assert!((fit_slope(&points) + 0.5).abs() < 1e-12);
    }

    #[test]
    fn the_trimmed_rmse_leaves_out_the_worst_pixels() {
        let mut a = vec![[0.0f32; 3]; 1000];
        let b = vec![[0.0f32; 3]; 1000];
        for (k, p) in a.iter_mut().enumerate() {
            *p = [0.1; 3];
            if k < 5 {
                *p = [100.0; 3];
            }
        }
        assert!(rmse(&a, &b) > 3.0);
        assert!((rmse_trimmed(&a, &b, 0.005) - 0.1).abs() < 1e-6);
        assert!((rmse_trimmed(&a, &b, 0.0) - rmse(&a, &b)).abs() < 1e-9);
    }

    #[test]
    fn rmse_of_a_constant_offset_is_the_offset() {
        let a = vec![[1.0f32, 2.0, 3.0]; 10];
        let b = vec![[1.5f32, 2.5, 3.5]; 10];
        assert!((rmse(&a, &b) - 0.5).abs() < 1e-12);
        assert_eq!(rmse(&a, &a), 0.0);
    }
}
