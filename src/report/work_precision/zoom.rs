//! The zoom sweep: f32 against f64 as the pixel footprint shrinks, and its markdown section.

use std::fmt::Write as _;
use std::sync::Arc;

use crate::frame::Frame;
use crate::gpu::GpuKernels;
use crate::report::stability::Runner;
use crate::scene::Scene;

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
