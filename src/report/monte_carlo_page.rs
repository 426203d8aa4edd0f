//! The Monte Carlo page's text, table and plot (`monte_carlo.md`, `.csv` and `.png`) from the
//! curves [`super::monte_carlo::run`] measures: the curves' table, the verdicts (Sobol' against
//! random, what the denoiser, adaptive sampling and regularisation buy and what they cost in
//! bias), and the bounces.

use std::path::Path;

use super::monte_carlo::{
    ADAPTIVE_TARGET, Case, Curve, FIT_FROM, Point, REGULARIZE, SAMPLES, TRIM, seconds_to,
};
use crate::scene::PathSampler;

/// The curves as CSV: one row per point.
pub fn csv(curves: &[Curve]) -> String {
    let mut out = String::from(
        "scene,sampler,bounces,denoise,noise_target,regularize,samples,taken,rmse,rmse_trimmed,\
         seconds,estimated_rmse\n",
    );
    for c in curves {
        for p in &c.points {
            out.push_str(&format!(
                "{},{},{},{},{},{},{},{:.3},{:.6e},{:.6e},{:.6},{}\n",
                c.case.scene_name,
                c.case.sampler.name(),
                c.case.bounces,
                if c.case.denoise { "atrous" } else { "none" },
                if c.case.adaptive {
                    ADAPTIVE_TARGET
                } else {
                    0.0
                },
                if c.case.regularize { REGULARIZE } else { 0.0 },
                p.samples,
                p.taken,
                p.rmse,
                p.trimmed,
                p.seconds,
                p.estimated.map_or(String::new(), |e| format!("{e:.6e}")),
            ));
        }
    }
    out
}

/// A curve's label: scene, sampler, bounces, adaptive sampling, regularisation and the
/// denoiser.
fn label(c: &Case) -> String {
    let adaptive = if c.adaptive { " adaptive" } else { "" };
    let regularized = if c.regularize { " regularized" } else { "" };
    let denoised = if c.denoise { " denoised" } else { "" };
    format!(
        "{} {} {}b{adaptive}{regularized}{denoised}",
        c.scene_name,
        c.sampler.name(),
        c.bounces
    )
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
         Each render also estimates its own RMSE, without the reference (`--stats`' \
         `estimated_rmse`: from its pixels' two halves, of the denoised image where the \
         denoiser runs; [The error on request](../book/error.md)). The right-hand plots draw it \
         against run time, dashed, beside the measured error of the same curve; the table \
         gives it at 64 samples over the measured RMSE. The measured RMSE also holds the \
         reference's own noise (it is the root of the render's MSE plus the reference's \
         variance), so where a curve's error comes near the reference's the estimate falls \
         below the measure by that much, as it should. Each point is one render (seed 0), and \
         its estimate is one draw as its measured error is: where a few glints rule the error \
         the two can part by a third in one render, in either direction. Over seeds they agree \
         within 20% (`tests/render/error_estimate.rs`; `cargo run --release --example \
         error_estimate`).\n\n\
         ![RMSE against samples and seconds](monte_carlo.png)\n\n\
         | curve | slope | RMSE at 16 | RMSE at 64 | RMSE at 256 | trimmed at 64 | seconds at 64 | estimate / measured at 64 | reference mean |\n\
         |---|---|---|---|---|---|---|---|---|\n",
        trim = 100.0 * TRIM
    );
    let cell = |c: &Curve, n: u32| at(c, n).map_or("-".into(), |p| format!("{:.4}", p.rmse));
    for c in curves {
        md.push_str(&format!(
            "| {} | {:.3} | {} | {} | {} | {} | {} | {} | {:.4} |\n",
            label(&c.case),
            c.slope,
            cell(c, 16),
            cell(c, 64),
            cell(c, 256),
            at(c, 64).map_or("-".into(), |p| format!("{:.4}", p.trimmed)),
            at(c, 64).map_or("-".into(), |p| format!("{:.3}", p.seconds)),
            at(c, 64)
                .and_then(|p| p.estimated.map(|e| format!("{e:.4} ({:.2}x)", e / p.rmse)))
                .unwrap_or_else(|| "-".into()),
            c.reference_mean
        ));
    }
    md.push_str("\n## Verdicts\n\n");
    let find = |scene: &str, sampler: PathSampler, bounces: u32| {
        curves.iter().find(|c| {
            c.case.scene_name == scene
                && c.case.sampler == sampler
                && c.case.bounces == bounces
                && !c.case.denoise
                && !c.case.adaptive
                && !c.case.regularize
        })
    };
    // The Sobol' curve of `scene` with the denoiser, adaptive sampling and regularisation as
    // asked.
    let kind = |scene: &str, (denoise, adaptive, regularize): (bool, bool, bool)| {
        curves.iter().find(|c| {
            c.case.scene_name == scene
                && c.case.denoise == denoise
                && c.case.adaptive == adaptive
                && c.case.regularize == regularize
        })
    };
    let denoised = |scene: &str| kind(scene, (true, false, false));
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
    let most = SAMPLES[SAMPLES.len() - 1];
    for scene in ["path-traced", "path-gallery", "rough metal"] {
        let (Some(plain), Some(random), Some(d), Some(a), Some(ad), Some(g), Some(gd)) = (
            find(scene, PathSampler::Sobol, 3),
            find(scene, PathSampler::Random, 3),
            denoised(scene),
            kind(scene, (false, true, false)),
            kind(scene, (true, true, false)),
            kind(scene, (false, false, true)),
            kind(scene, (true, false, true)),
        ) else {
            continue;
        };
        let (Some(p16), Some(d16), Some(p64)) = (at(plain, 16), at(d, 16), at(plain, 64)) else {
            continue;
        };
        // The target: plain Sobol's error at 64 samples, plain and trimmed. Who reaches it
        // (and stays there) first?
        let race = |target: f64, error: fn(&Point) -> f64| {
            let ways = [
                ("Sobol'", seconds_to(plain, target, error)),
                ("random", seconds_to(random, target, error)),
                ("Sobol' denoised", seconds_to(d, target, error)),
                ("Sobol' adaptive", seconds_to(a, target, error)),
                ("Sobol' adaptive denoised", seconds_to(ad, target, error)),
                ("Sobol' regularized", seconds_to(g, target, error)),
                ("Sobol' regularized denoised", seconds_to(gd, target, error)),
            ];
            let seconds = |s: Option<f64>| s.map_or("never".into(), |s| format!("{s:.3} s"));
            let cheapest = ways
                .iter()
                .filter_map(|(name, s)| s.map(|s| (name, s)))
                .min_by(|a, b| a.1.total_cmp(&b.1))
                .map_or("none of them".to_string(), |(name, _)| name.to_string());
            let each: Vec<String> = ways
                .iter()
                .map(|(name, s)| format!("{name} {}", seconds(*s)))
                .collect();
            format!("{}: the cheapest is {cheapest}", each.join(", "))
        };
        md.push_str(&format!(
            "- **{scene}, the denoiser** (Sobol', 3 bounces): at 16 samples RMSE {:.4} against \
             {:.4} plain ({:.2}x; trimmed {:.4} against {:.4}). To plain Sobol's RMSE at 64 \
             samples ({:.4}): {}. To its trimmed RMSE ({:.4}): {}. Its bias, at {most} samples: \
             RMSE {:.4} on edge pixels ({:.1}% of them) and {:.4} on flat ones, where plain \
             averaging has {:.4} and {:.4}.\n",
            d16.rmse,
            p16.rmse,
            d16.rmse / p16.rmse,
            d16.trimmed,
            p16.trimmed,
            p64.rmse,
            race(p64.rmse, |p| p.rmse),
            p64.trimmed,
            race(p64.trimmed, |p| p.trimmed),
            d.split.edge,
            100.0 * d.split.edge_share,
            d.split.flat,
            plain.split.edge,
            plain.split.flat,
        ));
        let (Some(g16), Some(g256), Some(gd16), Some(gd256)) =
            (at(g, 16), at(g, most), at(gd, 16), at(gd, most))
        else {
            continue;
        };
        let (Some(p256), Some(a256), Some(a64)) = (at(plain, most), at(a, most), at(a, 64)) else {
            continue;
        };
        let bias = |c: &Curve| 100.0 * (c.last_mean / c.reference_mean - 1.0);
        md.push_str(&format!(
            "- **{scene}, regularisation** (`path.regularize = {REGULARIZE}`, Sobol', 3 \
             bounces): at 16 samples RMSE {:.4} against {:.4} plain (trimmed {:.4} against \
             {:.4}), denoised {:.4}; at {most} samples {:.4} against {:.4}, denoised {:.4}. \
             Its bias: the image's mean radiance at {most} samples is {:+.2}% off the \
             reference's ({:+.2}% denoised), where plain Sobol's is {:+.2}% off.\n",
            g16.rmse,
            p16.rmse,
            g16.trimmed,
            p16.trimmed,
            gd16.rmse,
            g256.rmse,
            p256.rmse,
            gd256.rmse,
            bias(g),
            bias(gd),
            bias(plain),
        ));
        md.push_str(&format!(
            "- **{scene}, adaptive sampling** (Sobol', 3 bounces, noise target \
             {ADAPTIVE_TARGET}): allowed {most} samples a pixel, its pixels took {:.1} on \
             average ({:.0}%), in {:.3} s against plain's {:.3} s, for RMSE {:.4} against {:.4} \
             (trimmed {:.4} against {:.4}); allowed 64, they took {:.1}, RMSE {:.4} against \
             {:.4}.\n",
            a256.taken,
            100.0 * a256.taken / most as f64,
            a256.seconds,
            p256.seconds,
            a256.rmse,
            p256.rmse,
            a256.trimmed,
            p256.trimmed,
            a64.taken,
            a64.rmse,
            p64.rmse,
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

/// `monte_carlo.png`: a row a scene, its curves' RMSE against samples (left) and against
/// seconds (right), log-log, one series per curve; on the right each curve's own estimate of
/// its RMSE too ([`Point::estimated`]), dashed in the curve's colour.
pub fn plot(path: &Path, curves: &[Curve]) -> std::result::Result<(), String> {
    use plotters::prelude::*;
    crate::heatmap::register_plot_font();
    // One row of panels a scene, in the order the curves first name them: each row's few
    // curves keep colours of their own and a legend that hides none of them.
    let mut scenes: Vec<&str> = Vec::new();
    for c in curves {
        if !scenes.contains(&c.case.scene_name) {
            scenes.push(c.case.scene_name);
        }
    }
    let (w, row_h) = (1400u32, 520u32);
    let h = row_h * scenes.len().max(1) as u32;
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let rows = root.split_evenly((scenes.len().max(1), 1));
        type Axis = (&'static str, fn(&Point) -> f64);
        let x_of: [Axis; 2] = [
            ("samples per pixel (log)", |p| p.taken),
            ("seconds per image (log)", |p| p.seconds.max(1e-5)),
        ];
        for (row, scene) in rows.iter().zip(&scenes) {
            let mine: Vec<&Curve> = curves
                .iter()
                .filter(|c| c.case.scene_name == *scene)
                .collect();
            for (panel, (x_desc, x)) in row.split_evenly((1, 2)).iter().zip(x_of) {
                let estimates = x_desc.starts_with("seconds");
                let all: Vec<(f64, f64)> = mine
                    .iter()
                    .flat_map(|c| c.points.iter())
                    .flat_map(|p| {
                        let estimate = p.estimated.filter(|_| estimates);
                        [Some(p.rmse), estimate]
                            .into_iter()
                            .flatten()
                            .map(|e| (x(p).log10(), e.max(1e-6).log10()))
                    })
                    .collect();
                let (x0, x1) = all
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.0), b.max(p.0)));
                let (y0, y1) = all
                    .iter()
                    .fold((f64::MAX, f64::MIN), |(a, b), p| (a.min(p.1), b.max(p.1)));
                let against = x_desc.split(' ').next().unwrap_or("");
                let mut chart = ChartBuilder::on(panel)
                    .caption(
                        format!("{scene}: linear RMSE against {against}"),
                        ("sans-serif", 22),
                    )
                    .margin(14)
                    .x_label_area_size(44)
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
                    .label_style(("sans-serif", 14))
                    .axis_desc_style(("sans-serif", 16))
                    .draw()
                    .map_err(|e| e.to_string())?;
                for (k, c) in mine.iter().enumerate() {
                    let points: Vec<(f64, f64)> = c
                        .points
                        .iter()
                        .map(|p| (x(p).log10(), p.rmse.max(1e-6).log10()))
                        .collect();
                    let name = label(&c.case);
                    let name = name.strip_prefix(scene).unwrap_or(&name).trim_start();
                    super::plot::draw_series(&mut chart, &points, k, name, 3)?;
                    let estimated: Vec<(f64, f64)> = c
                        .points
                        .iter()
                        .filter(|_| estimates)
                        .filter_map(|p| p.estimated.map(|e| (x(p).log10(), e.max(1e-6).log10())))
                        .collect();
                    super::plot::draw_dashed(&mut chart, &estimated, k)?;
                }
                if estimates {
                    super::plot::draw_dashed_legend(&mut chart, "its estimate (dashed)")?;
                }
                super::plot::draw_legend(&mut chart, 14)?;
            }
        }
        root.present().map_err(|e| e.to_string())?;
    }
    image::save_buffer(path, &buffer, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())
}
