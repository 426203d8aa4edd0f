//! The work-precision report: for a few fixed scenes, sweep the settings that trade time for
//! accuracy (epsilon fixed and per pixel, iterations, escape radius, over-relaxation, normal
//! method and step, precision and backend), time each, and measure its error against a
//! converged f64 truth. Writes `work_precision.csv`, `work_precision.png` and `report.md`.
//!
//! This module owns the sweep: its settings and running them ([`run`]). The truth and the
//! errors against it are in `truth.rs`, the writers in `csv.rs`, `markdown.rs` and `plot.rs`,
//! and the f32-against-f64 zoom sweep in `zoom.rs`.

mod csv;
mod markdown;
mod plot;
mod setting;
mod truth;
mod zoom;

pub use csv::csv;
pub use markdown::{markdown, pareto_front, seed_row};
pub use plot::plot;
pub use setting::Setting;
pub use truth::{Metrics, TRUTH_SAMPLES, Truth, measure, truth_scene};
pub use zoom::{ZOOM_FOOTPRINTS, ZoomRow, zoom_markdown, zoom_scene, zoom_sweep};

use std::sync::Arc;
use std::time::Instant;

use super::stability::Runner;
use crate::frame::Frame;
use crate::gpu::GpuKernels;
use crate::scene::{NormalMethod, Scene};

/// A measured setting.
#[derive(Clone, Debug)]
pub struct Row {
    pub setting: Setting,
    pub seconds: f64,
    pub steps_mean: f64,
    pub metrics: Metrics,
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
