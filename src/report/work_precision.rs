//! The work-precision report: for a few fixed scenes, sweep the settings that trade time for
//! accuracy (epsilon fixed and per pixel, iterations, escape radius, over-relaxation, normal
//! method and step, precision and backend), time each, and measure its error against a
//! converged f64 truth. Writes `work_precision.csv`, `work_precision.png` and `report.md`.

use std::fmt::Write as _;
use std::path::Path;
use std::sync::Arc;
use std::time::Instant;

use rayon::prelude::*;

use super::stability::Runner;
use crate::TraceParams;
use crate::algebra::{Real, Vec3};
use crate::frame::{Frame, unpack_rgb};
use crate::gpu::GpuKernels;
use crate::scene::{NormalMethod, Scene};

/// One point of the sweep.
#[derive(Clone, Debug)]
pub struct Setting {
    pub scene_name: &'static str,
    /// The series it belongs to (what is varied).
    pub method: &'static str,
    /// The value varied, for people.
    pub label: String,
    pub runner: Runner,
    pub scene: Scene,
}

/// Errors of one render against the truth.
#[derive(Clone, Copy, Debug, Default)]
pub struct Metrics {
    /// Share of pixels hit by one and not the other.
    pub mask_disagreement: f64,
    /// |depth - true depth| in pixel footprints at that depth, over pixels both hit.
    pub depth_error_p50: f64,
    pub depth_error_p95: f64,
    pub depth_error_max: f64,
    /// Angle between the setting's normal at its hit and the true normal at the true hit.
    pub normal_error_deg_p50: f64,
    pub normal_error_deg_p95: f64,
    /// Colour against the truth's: PSNR and RMSE (in 8-bit steps) over all pixels.
    pub psnr_db: f64,
    pub colour_rmse: f64,
    /// Share of hits that lie inside the true set by more than the setting's epsilon.
    pub overstep_rate: f64,
    /// NaN or Inf values produced (must be 0).
    pub non_finite: u64,
}

/// A measured setting.
#[derive(Clone, Debug)]
pub struct Row {
    pub setting: Setting,
    pub seconds: f64,
    pub steps_mean: f64,
    pub metrics: Metrics,
}

/// Samples per pixel of the truth: its colour is the pixel's mean, so that the colour error of a
/// setting says what its own samples (anti-aliasing) buy.
pub const TRUTH_SAMPLES: u32 = 16;

/// The converged reference for a scene: f64, a large escape radius, a small epsilon, plain
/// steps, the analytic normal. It keeps the scene's iteration count: that chooses which
/// isosurface family is drawn, and twice as many turn the true normals into pixel-scale noise
/// (measured: colour RMSE 39 against the seed's image, normals 68 degrees apart at p95), so the
/// iterations series measures a change of model, not of accuracy.
pub fn truth_scene(base: &Scene) -> Scene {
    let mut t = base.clone();
    t.image.samples = TRUTH_SAMPLES;
    t.fractal.escape_radius_squared = 1e12;
    t.fractal.epsilon = 1e-5;
    t.fractal.max_steps = 200_000;
    t.fractal.step_scale = 1.0;
    t.fractal.pixel_epsilon = 0.0;
    t.shading.normal = NormalMethod::Analytic;
    t
}

/// The sweep around one base scene.
pub fn settings(scene_name: &'static str, base: &Scene, gpu: bool) -> Vec<Setting> {
    let fast = if gpu { Runner::GpuF32 } else { Runner::CpuF32 };
    let mut out = Vec::new();
    let mut add =
        |method: &'static str, label: String, runner: Runner, edit: &dyn Fn(&mut Scene)| {
            let mut scene = base.clone();
            edit(&mut scene);
            out.push(Setting {
                scene_name,
                method,
                label,
                runner,
                scene,
            });
        };
    let runners: &[Runner] = if gpu {
        &[Runner::GpuF32, Runner::CpuF32, Runner::CpuF64]
    } else {
        &[Runner::CpuF32, Runner::CpuF64]
    };
    for &runner in runners {
        for eps in [0.003, 0.001] {
            add(
                "backend",
                format!("{} eps {eps}", runner.name()),
                runner,
                &|s| s.fractal.epsilon = eps,
            );
        }
    }
    for eps in [0.03, 0.01, 0.003, 0.001, 3e-4, 1e-4] {
        add("epsilon fixed", format!("eps {eps}"), fast, &|s| {
            s.fractal.epsilon = eps
        });
    }
    for k in [4.0, 2.0, 1.0, 0.5, 0.25] {
        add("epsilon per pixel", format!("{k} px"), fast, &|s| {
            s.fractal.epsilon = 1e-6;
            s.fractal.pixel_epsilon = k;
        });
    }
    let n = base.fractal.max_iterations as f64;
    for factor in [0.6, 0.8, 1.0, 1.4, 2.0] {
        let iterations = (n * factor).round().max(1.0) as u32;
        add(
            "iterations",
            format!("{iterations} iterations"),
            fast,
            &|s| s.fractal.max_iterations = iterations,
        );
    }
    for r2 in [4.5, 10.0, 100.0, 1e4, 1e8] {
        add("escape radius", format!("|z|^2 > {r2:e}"), fast, &|s| {
            s.fractal.escape_radius_squared = r2
        });
    }
    for (samples, eps) in [(2, 0.003), (4, 0.003), (8, 0.003), (16, 0.003), (4, 0.001)] {
        add(
            "samples",
            format!("{samples} samples eps {eps}"),
            fast,
            &|s| {
                s.image.samples = samples;
                s.fractal.epsilon = eps;
            },
        );
    }
    // Features that change the picture: each is measured against a truth with the same value.
    for radius in [0.1, 0.3] {
        add(
            "soft shadows",
            format!("light radius {radius}"),
            fast,
            &|s| s.light.radius = radius,
        );
    }
    for occlusion in [0.5, 1.0] {
        add(
            "occlusion",
            format!("occlusion {occlusion}, ambient 0.2"),
            fast,
            &|s| {
                s.shading.occlusion = occlusion;
                s.shading.ambient = 0.2;
            },
        );
    }
    add("cone tracing", "cone per 8x8 block".into(), fast, &|s| {
        s.fractal.tracing = crate::scene::Tracing::Cone
    });
    for omega in [1.2, 1.4, 1.6, 1.8] {
        add("over-relaxation", format!("omega {omega}"), fast, &|s| {
            s.fractal.step_scale = omega
        });
    }
    for (method, delta) in [
        (NormalMethod::Central, 1e-3),
        (NormalMethod::Central, 1e-5),
        (NormalMethod::Tetrahedral, 1e-4),
        (NormalMethod::Tetrahedral, 1e-5),
        (NormalMethod::Analytic, 1e-4),
    ] {
        let label = if method == NormalMethod::Analytic {
            "analytic".to_string()
        } else {
            format!("{} {delta:e}", method.name())
        };
        add("normal", label, fast, &|s| {
            s.shading.normal = method;
            s.shading.normal_delta = delta;
        });
    }
    out
}

/// The normal each hit pixel's tracer would shade with, at its own hit point (recomputed by the
/// CPU twin in the setting's precision).
fn normals<F: Real>(scene: &Scene, frame: &Frame) -> Vec<Option<[f64; 3]>> {
    let p = TraceParams::<F>::new(scene);
    (0..frame.pixel_count())
        .into_par_iter()
        .map(|k| {
            let depth = frame.depth[k];
            if depth.is_nan() {
                return None;
            }
            let (i, j) = (
                (k % frame.width as usize) as u32,
                (k / frame.width as usize) as u32,
            );
            let dir = p.camera_ray(i, j, 0);
            let hit = p.eye + dir * F::lit(depth as f64);
            Some(p.estimate_normal(hit, dir).to_f64())
        })
        .collect()
}

fn percentile(values: &mut [f64], q: f64) -> f64 {
    if values.is_empty() {
        return 0.0;
    }
    values.sort_by(|a, b| a.total_cmp(b));
    values[((values.len() - 1) as f64 * q).round() as usize]
}

/// Everything the truth offers for measuring: its frame, normals and f64 parameters.
pub struct Truth {
    pub frame: Frame,
    pub normals: Vec<Option<[f64; 3]>>,
    pub params: TraceParams<f64>,
    pub seconds: f64,
}

impl Truth {
    pub fn new(base: &Scene) -> crate::Result<Self> {
        let scene = truth_scene(base);
        let params = TraceParams::<f64>::new(&scene);
        let (frame, seconds) = Runner::CpuF64.render(&scene, None)?;
        let normals = normals::<f64>(&scene, &frame);
        Ok(Self {
            frame,
            normals,
            params,
            seconds,
        })
    }
}

/// The errors of `frame` (rendered from `setting`) against the truth.
#[allow(clippy::needless_range_loop)] // one index into five per-pixel arrays reads best
pub fn measure(setting: &Setting, frame: &Frame, truth: &Truth) -> Metrics {
    let n = frame.pixel_count();
    let angle = setting.scene.pixel_angle();
    let setting_normals = match setting.runner {
        Runner::CpuF64 | Runner::GpuF64 => normals::<f64>(&setting.scene, frame),
        _ => normals::<f32>(&setting.scene, frame),
    };
    let (mut mask_diff, mut depth_err, mut normal_err) = (0usize, Vec::new(), Vec::new());
    let (mut hits, mut oversteps) = (0usize, 0usize);
    let mut sq_sum = 0f64;
    let tp = &truth.params;
    for k in 0..n {
        let (d, dt) = (frame.depth[k], truth.frame.depth[k]);
        if d.is_nan() != dt.is_nan() {
            mask_diff += 1;
        }
        if !d.is_nan() {
            hits += 1;
            let (i, j) = (
                (k % frame.width as usize) as u32,
                (k / frame.width as usize) as u32,
            );
            let hit = tp.eye + tp.camera_ray(i, j, 0) * d as f64;
            if tp.estimate_distance(hit) < -setting.scene.fractal.epsilon {
                oversteps += 1;
            }
        }
        if !d.is_nan() && !dt.is_nan() {
            depth_err.push((d as f64 - dt as f64).abs() / (dt as f64 * angle).max(1e-12));
            if let (Some(a), Some(b)) = (setting_normals[k], truth.normals[k]) {
                let cos = Vec3::<f64>::from_f64(a)
                    .dot(Vec3::from_f64(b))
                    .clamp(-1.0, 1.0);
                normal_err.push(cos.acos().to_degrees());
            }
        }
        let (a, b) = (
            unpack_rgb(frame.colour[k]),
            unpack_rgb(truth.frame.colour[k]),
        );
        sq_sum += (0..3)
            .map(|c| (a[c] as f64 - b[c] as f64).powi(2))
            .sum::<f64>();
    }
    let mse = sq_sum / (3 * n.max(1)) as f64;
    Metrics {
        mask_disagreement: mask_diff as f64 / n.max(1) as f64,
        depth_error_p50: percentile(&mut depth_err, 0.5),
        depth_error_p95: percentile(&mut depth_err, 0.95),
        depth_error_max: depth_err.iter().copied().fold(0.0, f64::max),
        normal_error_deg_p50: percentile(&mut normal_err, 0.5),
        normal_error_deg_p95: percentile(&mut normal_err, 0.95),
        psnr_db: if mse > 0.0 {
            10.0 * (255.0f64 * 255.0 / mse).log10()
        } else {
            99.0
        },
        colour_rmse: mse.sqrt(),
        overstep_rate: oversteps as f64 / hits.max(1) as f64,
        non_finite: frame.non_finite,
    }
}

/// Seconds each scene's truth took, by scene name.
pub type TruthSeconds = Vec<(&'static str, f64)>;

/// Runs every setting of every scene; `repeats` renders each and keeps the fastest time.
pub fn run(
    scenes: &[(&'static str, Scene)],
    gpu: Option<Arc<GpuKernels>>,
    repeats: u32,
    mut progress: impl FnMut(&str, usize, usize),
) -> crate::Result<(Vec<Row>, TruthSeconds)> {
    let mut rows = Vec::new();
    let mut truth_seconds = Vec::new();
    for (name, base) in scenes {
        progress(&format!("{name}: truth (f64, converged settings)"), 0, 1);
        let seed_truth = Truth::new(base)?;
        truth_seconds.push((*name, seed_truth.seconds));
        // Truths of the picture's features (light radius, occlusion and ambient), made on first
        // use: a feature changes the picture, so its settings are held to a truth that has it.
        let mut feature_truths: Vec<(Scene, Truth)> = Vec::new();
        let all = settings(name, base, gpu.is_some());
        for (k, setting) in all.iter().enumerate() {
            let mut featured = base.clone();
            featured.light.radius = setting.scene.light.radius;
            featured.shading.occlusion = setting.scene.shading.occlusion;
            featured.shading.ambient = setting.scene.shading.ambient;
            let truth = if featured == *base {
                &seed_truth
            } else {
                if !feature_truths.iter().any(|(s, _)| *s == featured) {
                    progress(&format!("{name}: truth of {}", setting.label), k, all.len());
                    let truth = Truth::new(&featured)?;
                    feature_truths.push((featured.clone(), truth));
                }
                let found = feature_truths.iter().find(|(s, _)| *s == featured);
                &found.expect("made above").1
            };
            progress(
                &format!("{name}: {} {}", setting.method, setting.label),
                k,
                all.len(),
            );
            let mut best: Option<(Frame, f64)> = None;
            for _ in 0..repeats.max(1) {
                let start = Instant::now();
                let (frame, seconds) = setting.runner.render(&setting.scene, gpu.as_ref())?;
                let seconds = seconds.min(start.elapsed().as_secs_f64());
                if best.as_ref().is_none_or(|(_, s)| seconds < *s) {
                    best = Some((frame, seconds));
                }
            }
            let (frame, seconds) = best.expect("at least one render");
            let metrics = measure(setting, &frame, truth);
            rows.push(Row {
                setting: setting.clone(),
                seconds,
                steps_mean: crate::Summary::of(&frame).steps_mean,
                metrics,
            });
        }
    }
    Ok((rows, truth_seconds))
}

/// One row per setting, the columns the issue asks for and a few more.
pub fn csv(rows: &[Row]) -> String {
    let mut out = String::from(
        "scene,backend,precision,method,setting,epsilon,pixel_epsilon,max_iterations,escape_radius_squared,\
         step_scale,normal,normal_delta,seconds,steps_mean,mask_disagreement,depth_error_p50,depth_error_p95,\
         depth_error_max,normal_error_deg_p50,normal_error_deg_p95,psnr_db,colour_rmse,overstep_rate,non_finite,\
         samples,light_radius,occlusion\n",
    );
    for r in rows {
        let (s, m) = (&r.setting, &r.metrics);
        let f = &s.scene.fractal;
        let (backend, precision) = r
            .setting
            .runner
            .name()
            .split_once(' ')
            .unwrap_or(("?", "?"));
        let _ = writeln!(
            out,
            "{},{backend},{precision},{},\"{}\",{},{},{},{},{},{},{},{:.6},{:.2},{:.6},{:.4},{:.4},{:.4},{:.4},{:.4},{:.3},{:.4},{:.6},{},{},{},{}",
            s.scene_name,
            s.method,
            s.label,
            f.epsilon,
            f.pixel_epsilon,
            f.max_iterations,
            f.escape_radius_squared,
            f.step_scale,
            s.scene.shading.normal.name(),
            s.scene.shading.normal_delta,
            r.seconds,
            r.steps_mean,
            m.mask_disagreement,
            m.depth_error_p50,
            m.depth_error_p95,
            m.depth_error_max,
            m.normal_error_deg_p50,
            m.normal_error_deg_p95,
            m.psnr_db,
            m.colour_rmse,
            m.overstep_rate,
            m.non_finite,
            s.scene.image.samples,
            s.scene.light.radius,
            s.scene.shading.occlusion
        );
    }
    out
}

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

/// Colour RMSE against seconds, log-log, one series per method, one panel per scene.
pub fn plot(path: &Path, rows: &[Row]) -> Result<(), String> {
    use plotters::prelude::*;
    crate::heatmap::register_plot_font();
    let mut scenes: Vec<&str> = rows.iter().map(|r| r.setting.scene_name).collect();
    scenes.dedup();
    let (w, panel_h) = (1100u32, 620u32);
    let h = panel_h * scenes.len().max(1) as u32;
    let mut buffer = vec![255u8; (w * h * 3) as usize];
    {
        let root = BitMapBackend::with_buffer(&mut buffer, (w, h)).into_drawing_area();
        root.fill(&WHITE).map_err(|e| e.to_string())?;
        let panels = root.split_evenly((scenes.len().max(1), 1));
        let palette = [
            RGBColor(31, 119, 180),
            RGBColor(255, 127, 14),
            RGBColor(44, 160, 44),
            RGBColor(214, 39, 40),
            RGBColor(148, 103, 189),
            RGBColor(140, 86, 75),
            RGBColor(227, 119, 194),
            RGBColor(90, 90, 90),
            RGBColor(188, 189, 34),
            RGBColor(23, 190, 207),
            RGBColor(0, 0, 128),
            RGBColor(255, 187, 120),
        ];
        for (panel, scene) in panels.iter().zip(&scenes) {
            let mine: Vec<&Row> = rows
                .iter()
                .filter(|r| r.setting.scene_name == *scene)
                .collect();
            // Log-log, drawn as log10 values on linear axes labelled with the values themselves.
            let point = |r: &Row| {
                (
                    r.seconds.max(1e-5).log10(),
                    r.metrics.colour_rmse.max(0.01).log10(),
                )
            };
            let (x0, x1) = mine
                .iter()
                .map(|r| point(r).0)
                .fold((f64::MAX, f64::MIN), |(a, b), x| (a.min(x), b.max(x)));
            let (y0, y1) = mine
                .iter()
                .map(|r| point(r).1)
                .fold((f64::MAX, f64::MIN), |(a, b), y| (a.min(y), b.max(y)));
            let mut chart = ChartBuilder::on(panel)
                .caption(
                    format!("{scene}: colour error against render time"),
                    ("sans-serif", 26),
                )
                .margin(16)
                .x_label_area_size(48)
                .y_label_area_size(70)
                .build_cartesian_2d(x0 - 0.1..x1 + 0.1, y0 - 0.1..y1 + 0.1)
                .map_err(|e| e.to_string())?;
            chart
                .configure_mesh()
                .x_labels(10)
                .y_labels(10)
                .x_label_formatter(&|x| format!("{:.3}", 10f64.powf(*x)))
                .y_label_formatter(&|y| format!("{:.1}", 10f64.powf(*y)))
                .x_desc("seconds per image (log)")
                .y_desc("colour RMSE vs truth, 8-bit steps (log)")
                .label_style(("sans-serif", 16))
                .axis_desc_style(("sans-serif", 18))
                .draw()
                .map_err(|e| e.to_string())?;
            let mut methods: Vec<&str> = mine.iter().map(|r| r.setting.method).collect();
            methods.dedup();
            methods.sort();
            methods.dedup();
            for (k, method) in methods.iter().enumerate() {
                let colour = palette[k % palette.len()];
                let mut points: Vec<(f64, f64)> = mine
                    .iter()
                    .filter(|r| r.setting.method == *method)
                    .map(|r| point(r))
                    .collect();
                points.sort_by(|a, b| a.0.total_cmp(&b.0));
                chart
                    .draw_series(LineSeries::new(points.clone(), colour.stroke_width(2)))
                    .map_err(|e| e.to_string())?
                    .label(*method)
                    .legend(move |(x, y)| {
                        PathElement::new(vec![(x, y), (x + 20, y)], colour.stroke_width(3))
                    });
                chart
                    .draw_series(points.iter().map(|&p| Circle::new(p, 4, colour.filled())))
                    .map_err(|e| e.to_string())?;
            }
            chart
                .configure_series_labels()
                .label_font(("sans-serif", 16))
                .background_style(WHITE.mix(0.85))
                .border_style(BLACK)
                .position(SeriesLabelPosition::UpperRight)
                .draw()
                .map_err(|e| e.to_string())?;
        }
        root.present().map_err(|e| e.to_string())?;
    }
    image::save_buffer(path, &buffer, w, h, image::ExtendedColorType::Rgb8)
        .map_err(|e| e.to_string())
}

/// One zoom level of [`zoom_sweep`]: the pixel footprint at the target, and each tracer's time
/// and agreement with the f64 CPU render of the same scene (the reference, timed too).
#[derive(Clone, Debug)]
pub struct ZoomRow {
    pub footprint: f64,
    pub runner: Runner,
    pub seconds: f64,
    /// Against the CPU f64 render at the same settings; None for the reference itself.
    pub versus_f64: Option<crate::compare::Agreement>,
    /// Whether f32's precision warnings fire at this zoom (for f32 runners).
    pub f32_warned: bool,
}

/// The deep-zoom scene at a pixel footprint of `footprint` at the target: the deep-zoom preset's
/// settings (30 iterations, the analytic normal, epsilon one pixel footprint) at `size` pixels.
pub fn zoom_scene(footprint: f64, size: u32) -> Scene {
    let mut scene = crate::scene::presets::find("deep-zoom")
        .expect("the deep-zoom preset")
        .scene();
    scene.image.width = size;
    scene.image.height = size;
    let distance = {
        let [e, t] = [scene.camera.eye, scene.camera.target];
        ((e[0] - t[0]).powi(2) + (e[1] - t[1]).powi(2) + (e[2] - t[2]).powi(2)).sqrt()
    };
    // footprint = 2 distance tan(fov / 2) / height
    scene.camera.fov_y_degrees =
        (2.0 * (footprint * size as f64 / (2.0 * distance)).atan()).to_degrees();
    scene.fractal.epsilon = (footprint * 0.1).max(1e-14);
    scene
}

/// The pixel footprints of the zoom sweep: from where f32 is comfortable to near f64's limit.
pub const ZOOM_FOOTPRINTS: [f64; 8] = [1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-8, 1e-10, 1e-12];

/// f32 against f64 as the zoom deepens: at each of [`ZOOM_FOOTPRINTS`], the CPU in f64 (the
/// reference) and each other tracer (`runners`), timed (best of `repeats`) and held to the
/// reference at the same settings.
pub fn zoom_sweep(
    size: u32,
    runners: &[Runner],
    gpu: Option<Arc<GpuKernels>>,
    repeats: u32,
    mut progress: impl FnMut(&str, usize, usize),
) -> crate::Result<Vec<ZoomRow>> {
    let tolerance = crate::compare::CONTRACT_TOLERANCE;
    let mut rows = Vec::new();
    let total = ZOOM_FOOTPRINTS.len() * (runners.len() + 1);
    for (z, &footprint) in ZOOM_FOOTPRINTS.iter().enumerate() {
        let scene = zoom_scene(footprint, size);
        let f32_warned =
            !crate::precision::slice_warnings(&scene, crate::Precision::F32).is_empty();
        let timed = |runner: Runner| -> crate::Result<(Frame, f64)> {
            let mut best: Option<(Frame, f64)> = None;
            for _ in 0..repeats.max(1) {
                let (frame, seconds) = runner.render(&scene, gpu.as_ref())?;
                if best.as_ref().is_none_or(|(_, s)| seconds < *s) {
                    best = Some((frame, seconds));
                }
            }
            Ok(best.expect("at least one render"))
        };
        progress(
            &format!("zoom {footprint:e}: cpu f64"),
            z * (runners.len() + 1),
            total,
        );
        let (reference, seconds) = timed(Runner::CpuF64)?;
        rows.push(ZoomRow {
            footprint,
            runner: Runner::CpuF64,
            seconds,
            versus_f64: None,
            f32_warned,
        });
        for (r, &runner) in runners.iter().enumerate() {
            progress(
                &format!("zoom {footprint:e}: {}", runner.name()),
                z * (runners.len() + 1) + r + 1,
                total,
            );
            let (frame, seconds) = timed(runner)?;
            rows.push(ZoomRow {
                footprint,
                runner,
                seconds,
                versus_f64: Some(crate::compare::Agreement::measure(
                    &reference, &frame, &tolerance,
                )),
                f32_warned,
            });
        }
    }
    Ok(rows)
}

/// The zoom sweep as a markdown section.
pub fn zoom_markdown(rows: &[ZoomRow], size: u32) -> String {
    let mut out = String::new();
    let _ = writeln!(
        out,
        "## f32 against f64 as the zoom deepens\n\n\
         The deep-zoom preset ({size}x{size}) at pixel footprints from 1e-2 to 1e-12 at the \
         target, each tracer held to the CPU in f64 at the same settings: the share of pixels \
         whose hit mask, and whose colour (within CONTRACT_TOLERANCE), agree; seconds are the \
         best of the repeats. \"warned\": f32's precision warnings fire at this zoom (so \
         `--precision auto` runs f64 there).\n\n\
         | pixel footprint | tracer | seconds | mask agrees | colour agrees | f32 warned |\n\
         |---|---|---|---|---|---|"
    );
    for r in rows {
        let (mask, colour) = match &r.versus_f64 {
            Some(a) => (
                format!("{:.2}%", a.mask * 100.0),
                format!("{:.2}%", a.colour * 100.0),
            ),
            None => ("ref".into(), "ref".into()),
        };
        let _ = writeln!(
            out,
            "| {:e} | {} | {:.4} | {mask} | {colour} | {} |",
            r.footprint,
            r.runner.name(),
            r.seconds,
            if r.f32_warned { "yes" } else { "no" }
        );
    }
    out
}
