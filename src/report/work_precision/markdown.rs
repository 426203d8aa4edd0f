//! `report.md`'s work-precision sections: per scene the seed's row, the settings that beat it,
//! the Pareto front, what samples buy and what the picture's features cost.

use std::fmt::Write as _;

use super::{Row, TRUTH_SAMPLES};
use crate::report::stability::Runner;
use crate::scene::NormalMethod;

/// Rows no faster row beats on colour error, fastest first.
pub fn pareto_front<'a>(rows: &[&'a Row]) -> Vec<&'a Row> {
    let mut sorted: Vec<&Row> = rows.to_vec();
    sorted.sort_by(|a, b| a.seconds.total_cmp(&b.seconds));
    let mut front = Vec::new();
    let mut best = f64::INFINITY;
    for r in sorted {
        if r.metrics.colour_rmse < best {
            best = r.metrics.colour_rmse;
            front.push(r);
        }
    }
    front
}

/// The seed's settings on the fast tracer: the row to beat.
pub fn seed_row<'a>(rows: &[&'a Row]) -> Option<&'a Row> {
    let fast = if rows.iter().any(|r| r.setting.runner == Runner::GpuF32) {
        Runner::GpuF32
    } else {
        Runner::CpuF32
    };
    rows.iter()
        .find(|r| {
            r.setting.method == "backend"
                && r.setting.runner == fast
                && r.setting.scene.fractal.epsilon == 0.003
        })
        .copied()
}

/// Series that change the picture (measured against truths of their own).
const FEATURE_SERIES: [&str; 2] = ["soft shadows", "occlusion"];

/// What anti-aliasing buys: 4 samples at the seed's epsilon against 1 sample at a third of it,
/// the question the report answers in words.
fn samples_verdict(rows: &[&Row]) -> String {
    let find = |samples: u32, eps: f64, method: &str| {
        rows.iter().find(|r| {
            r.setting.method == method
                && r.setting.scene.image.samples == samples
                && r.setting.scene.fractal.epsilon == eps
        })
    };
    let (Some(four), Some(fine)) = (find(4, 0.003, "samples"), find(1, 0.001, "epsilon fixed"))
    else {
        return String::new();
    };
    let verdict = if four.metrics.colour_rmse < fine.metrics.colour_rmse {
        if four.seconds <= fine.seconds {
            "4 samples at epsilon 0.003 beat 1 sample at epsilon 0.001: lower colour error in less time"
        } else {
            "4 samples at epsilon 0.003 have the lower colour error, but take longer than 1 sample at epsilon 0.001"
        }
    } else if four.seconds <= fine.seconds {
        "1 sample at epsilon 0.001 has the lower colour error, and 4 samples at epsilon 0.003 are faster"
    } else {
        "1 sample at epsilon 0.001 beats 4 samples at epsilon 0.003: lower colour error in less time"
    };
    format!(
        "What samples buy: {verdict} ({:.4} s, colour RMSE {:.2} against {:.4} s, {:.2}; the truth \
         averages {TRUTH_SAMPLES} samples).\n\n",
        four.seconds, four.metrics.colour_rmse, fine.seconds, fine.metrics.colour_rmse
    )
}

/// The report: the method, per scene the seed's row, the settings that beat it, and the Pareto
/// front.
pub fn markdown(
    rows: &[Row],
    truth_seconds: &[(&str, f64)],
    machine: &str,
    command: &str,
) -> String {
    let mut out = format!(
        "# Work-precision report\n\n`{command}` on {machine}.\n\n\
         Each setting renders its scene once per repeat (the fastest of the repeats is kept: `seconds` is the \
         render alone, from the first dispatch to the image in host memory after a warm-up, as \
         `--stats` reports it). Errors are against a converged f64 CPU render of the same scene: escape \
         |z|^2 > 1e12, epsilon 1e-5, plain steps, the analytic normal, {TRUTH_SAMPLES} samples per pixel, and the \
         scene's own iteration count (iterations choose the surface drawn; the iterations series measures that change \
         of model). Depth errors are in \
         pixel footprints at the true depth; normal errors compare the normal the setting shades with \
         (recomputed at its own hit point by the CPU twin in its precision) with the true one; colour \
         error is the RMSE in 8-bit steps over all pixels (and PSNR). An overstep is a hit inside the \
         true set by more than the setting's epsilon. The plot is work_precision.png, every number \
         work_precision.csv.\n\n"
    );
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.setting.scene_name).collect();
    scenes.dedup();
    for scene in scenes {
        let all_mine: Vec<&Row> = rows
            .iter()
            .filter(|r| r.setting.scene_name == scene)
            .collect();
        // Settings of the same picture; the features (another picture, another truth) apart.
        let (features, mine): (Vec<&Row>, Vec<&Row>) = all_mine
            .iter()
            .partition(|r| FEATURE_SERIES.contains(&r.setting.method));
        let truth = truth_seconds
            .iter()
            .find(|(n, _)| *n == scene)
            .map_or(0.0, |t| t.1);
        let _ = writeln!(
            out,
            "## {scene}\n\nThe truth took {truth:.2} s on the CPU in f64.\n"
        );
        let twins: Vec<f64> = mine
            .iter()
            .filter(|r| {
                let (f, n) = (&r.setting.scene.fractal, &r.setting.scene.shading);
                r.setting.runner == seed_row(&mine).map_or(r.setting.runner, |s| s.setting.runner)
                    && f.epsilon == 0.003
                    && f.pixel_epsilon == 0.0
                    && f.step_scale == 1.0
                    && n.normal == NormalMethod::Central
                    && n.normal_delta == 1e-4
                    && f.escape_radius_squared == 10.0
                    && r.setting.scene.image.samples == 1
                    && r.setting.scene.light.radius == 0.0
                    && r.setting.scene.shading.occlusion == 0.0
                    && seed_row(&mine)
                        .is_some_and(|s| s.setting.scene.fractal.max_iterations == f.max_iterations)
            })
            .map(|r| r.seconds)
            .collect();
        if twins.len() > 1 {
            let (lo, hi) = twins
                .iter()
                .fold((f64::MAX, 0f64), |(a, b), &t| (a.min(t), b.max(t)));
            let _ = writeln!(
                out,
                "Timing noise: the seed's settings, rendered as {} separate rows, took {lo:.4} to {hi:.4} s \
                 ({:.0}% spread).\n",
                twins.len(),
                100.0 * (hi - lo) / lo
            );
        }
        if let Some(seed) = seed_row(&mine) {
            let _ = writeln!(
                out,
                "The seed's settings ({}): {:.4} s, colour RMSE {:.2}, PSNR {:.1} dB, mask disagreement {:.3}%, \
                 depth p95 {:.2} px, normal p95 {:.2}°.\n",
                seed.setting.runner.name(),
                seed.seconds,
                seed.metrics.colour_rmse,
                seed.metrics.psnr_db,
                seed.metrics.mask_disagreement * 100.0,
                seed.metrics.depth_error_p95,
                seed.metrics.normal_error_deg_p95
            );
            // To count as faster, beat every render of the seed's settings (the noise above).
            let fastest_seed = twins.iter().copied().fold(seed.seconds, f64::min);
            let better: Vec<&&Row> = mine
                .iter()
                .filter(|r| {
                    r.seconds < fastest_seed && r.metrics.colour_rmse <= seed.metrics.colour_rmse
                })
                .collect();
            if better.is_empty() {
                out += "No setting is both faster than every render of the seed's settings and at least as accurate.\n\n";
            } else {
                out += "Faster than every render of the seed's settings, at equal or lower colour error \
                        (time saved against the fastest of them):\n\n| series | setting | seconds | time saved | colour RMSE |\n|---|---|---|---|---|\n";
                for r in better {
                    let _ = writeln!(
                        out,
                        "| {} | {} | {:.4} | {:.0}% | {:.2} |",
                        r.setting.method,
                        r.setting.label,
                        r.seconds,
                        100.0 * (1.0 - r.seconds / fastest_seed),
                        r.metrics.colour_rmse
                    );
                }
                out += "\n";
            }
        }
        out += "Pareto front (no faster setting has a lower colour error):\n\n\
                | series | setting | seconds | colour RMSE | PSNR dB | mask % | depth p95 px | normal p95 ° | overstep % |\n\
                |---|---|---|---|---|---|---|---|---|\n";
        for r in pareto_front(&mine) {
            let m = &r.metrics;
            let _ = writeln!(
                out,
                "| {} | {} | {:.4} | {:.2} | {:.1} | {:.3} | {:.2} | {:.2} | {:.3} |",
                r.setting.method,
                r.setting.label,
                r.seconds,
                m.colour_rmse,
                m.psnr_db,
                m.mask_disagreement * 100.0,
                m.depth_error_p95,
                m.normal_error_deg_p95,
                m.overstep_rate * 100.0
            );
        }
        out += "\n";
        out += &samples_verdict(&mine);
        if let Some(seed) = seed_row(&mine) {
            out += "What the picture's features cost (each against a truth with the same feature; \
                    time against the seed's settings):\n\n\
                    | series | setting | seconds | x seed's time | colour RMSE | PSNR dB |\n|---|---|---|---|---|---|\n";
            for r in &features {
                let _ = writeln!(
                    out,
                    "| {} | {} | {:.4} | {:.2} | {:.2} | {:.1} |",
                    r.setting.method,
                    r.setting.label,
                    r.seconds,
                    r.seconds / seed.seconds,
                    r.metrics.colour_rmse,
                    r.metrics.psnr_db
                );
            }
            out += "\n";
        }
    }
    out += "How much of a difference in time is noise: the seed's own settings appear in several series \
            (backend eps 0.003, epsilon fixed 0.003, iterations x1, escape radius 10); the spread of their \
            times is the measurement's noise, and a setting that beats the seed's by less than that spread \
            does not really beat it.\n\n";
    let nan: u64 = rows.iter().map(|r| r.metrics.non_finite).sum();
    let _ = writeln!(
        out,
        "NaN or Inf values over all {} renders: {nan}.",
        rows.len()
    );
    out
}
