//! The converged f64 truth of a scene and the errors of a render against it ([`Metrics`]).

use rayon::prelude::*;

use super::setting::Setting;
use crate::TraceParams;
use crate::algebra::{Real, Vec3};
use crate::frame::{Frame, unpack_rgb};
use crate::report::stability::Runner;
use crate::scene::{NormalMethod, Scene};

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
