//! The seed's closing warning in numbers: the distance estimate |z| log|z| / (2 |z'|) with
//! z' <- 2 z z' is exact in spirit only for the complex numbers, and grows less useful as the
//! algebra's dimension rises. For quaternion, octonion and sedenion scenes this measures the
//! steps per pixel, how much of the true remaining distance the first estimate of a ray covers,
//! the time, and the error of f32 (CPU and GPU) against the f64 reference.

use crate::compare::{Agreement, CONTRACT_TOLERANCE};
use std::sync::Arc;

use crate::gpu::GpuKernels;
use crate::params::TraceParams;
use crate::report::stability::Runner;
use crate::scene::{Algebra, Scene};

/// One scene of the table.
pub struct Case {
    pub algebra: Algebra,
    pub label: &'static str,
    pub c: Vec<f64>,
}

/// The seed's c, alone (the same picture in every algebra: its cost only) and reaching into the
/// higher dimensions.
pub fn cases() -> Vec<Case> {
    let seed = [-0.2, 0.6, 0.2, 0.2];
    let padded = |n: usize| {
        let mut c = seed.to_vec();
        c.resize(n, 0.0);
        c
    };
    let mut octonion = padded(8);
    octonion[4..].copy_from_slice(&[0.15, -0.1, 0.1, 0.05]);
    let mut sedenion = padded(16);
    for (k, v) in [(4, 0.1), (7, -0.1), (9, 0.05), (12, 0.1)] {
        sedenion[k] = v;
    }
    let mut wide = octonion.clone();
    wide.resize(16, 0.0);
    for (k, v) in [(8, 0.1), (11, -0.1), (13, 0.1), (15, 0.05)] {
        wide[k] = v;
    }
    // The seed's c turned out of the quaternions: its imaginary part on e4-e6 (e8-e10), which
    // with 1 span no subalgebra.
    let mut turned8 = vec![0.0; 8];
    turned8[0] = seed[0];
    turned8[4..7].copy_from_slice(&seed[1..]);
    let mut turned16 = vec![0.0; 16];
    turned16[0] = seed[0];
    turned16[8..11].copy_from_slice(&seed[1..]);
    vec![
        Case {
            algebra: Algebra::Quaternion,
            label: "seed c",
            c: padded(4),
        },
        Case {
            algebra: Algebra::Octonion,
            label: "seed c, padded",
            c: padded(8),
        },
        Case {
            algebra: Algebra::Octonion,
            label: "c in 8D",
            c: octonion,
        },
        Case {
            algebra: Algebra::Octonion,
            label: "seed c turned onto e4-e6",
            c: turned8,
        },
        Case {
            algebra: Algebra::Sedenion,
            label: "seed c, padded",
            c: padded(16),
        },
        Case {
            algebra: Algebra::Sedenion,
            label: "c in 16D (sparse)",
            c: sedenion,
        },
        Case {
            algebra: Algebra::Sedenion,
            label: "c in 16D (8D c + 4 more)",
            c: wide,
        },
        Case {
            algebra: Algebra::Sedenion,
            label: "seed c turned onto e8-e10",
            c: turned16,
        },
    ]
}

impl Case {
    pub fn scene(&self, size: u32) -> Scene {
        let mut s = Scene::default();
        s.set_algebra(self.algebra);
        s.fractal.c = self.c.clone();
        s.image.width = size;
        s.image.height = size;
        s
    }
}

/// What one case measured.
pub struct Row {
    pub algebra: Algebra,
    pub label: &'static str,
    pub c: Vec<f64>,
    /// Primary-ray steps per pixel (f64 reference).
    pub steps_mean: f64,
    pub steps_max: u32,
    pub hit_fraction: f64,
    /// Mean over hitting rays of the first estimate over the distance really left to the hit
    /// (f64): 1 would be a perfect distance, small values a timid one.
    pub first_step: f64,
    /// Share of the pixels that half steps (step_scale 0.5, f64) hit where full steps miss:
    /// where the estimate overshot and the ray jumped part of the set.
    pub overshoot: f64,
    pub cpu_f64_seconds: f64,
    pub gpu_seconds: Option<f64>,
    pub cpu_f32: Agreement,
    pub gpu_f32: Option<Agreement>,
}

/// Runs every case at `size` x `size`.
pub fn run(size: u32, gpu: Option<&Arc<GpuKernels>>) -> crate::Result<Vec<Row>> {
    let mut rows = Vec::new();
    for case in cases() {
        let scene = case.scene(size);
        let (truth, cpu_f64_seconds) = Runner::CpuF64.render(&scene, None)?;
        let (cpu32, _) = Runner::CpuF32.render(&scene, None)?;
        let mut careful = scene.clone();
        careful.fractal.step_scale = 0.5;
        let (half, _) = Runner::CpuF64.render(&careful, None)?;
        let jumped = (0..truth.pixel_count())
            .filter(|&k| truth.depth[k].is_nan() && !half.depth[k].is_nan())
            .count();
        let (gpu_f32, gpu_seconds) = match gpu {
            Some(g) => {
                // Fastest of three: the first dispatch of a new variant includes compiling it.
                let mut best = f64::INFINITY;
                let mut frame = None;
                for _ in 0..3 {
                    let (f, s) = Runner::GpuF32.render(&scene, Some(g))?;
                    best = best.min(s);
                    frame = Some(f);
                }
                let f = frame.expect("three renders");
                (
                    Some(Agreement::measure(&truth, &f, &CONTRACT_TOLERANCE)),
                    Some(best),
                )
            }
            None => (None, None),
        };
        let steps: Vec<u32> = truth.steps.clone();
        rows.push(Row {
            algebra: case.algebra,
            label: case.label,
            c: case.c.clone(),
            steps_mean: steps.iter().map(|&s| s as f64).sum::<f64>() / steps.len().max(1) as f64,
            steps_max: steps.iter().copied().max().unwrap_or(0),
            hit_fraction: truth.hit_mask().iter().filter(|&&h| h).count() as f64
                / truth.pixel_count().max(1) as f64,
            first_step: first_step_efficiency(&scene, &truth.depth),
            overshoot: jumped as f64 / truth.pixel_count().max(1) as f64,
            cpu_f64_seconds,
            gpu_seconds,
            cpu_f32: Agreement::measure(&truth, &cpu32, &CONTRACT_TOLERANCE),
            gpu_f32,
        });
    }
    Ok(rows)
}

/// Mean of d(t_enter) / (t_hit - t_enter) over the rays that hit (f64).
fn first_step_efficiency(scene: &Scene, depth: &[f32]) -> f64 {
    let p = TraceParams::<f64>::new(scene);
    let (mut sum, mut n) = (0.0, 0usize);
    for j in 0..p.height {
        for i in 0..p.width {
            let t_hit = depth[(j * p.width + i) as usize] as f64;
            if t_hit.is_nan() {
                continue;
            }
            let dir = p.camera_ray(i, j, 0);
            let bounds = p.intersect_bounds(p.eye, dir);
            let left = t_hit - bounds.t_enter;
            if !bounds.hit || left <= 10.0 * p.epsilon {
                continue;
            }
            let d = p.estimate_distance(p.eye + dir * bounds.t_enter).max(0.0);
            sum += d / left;
            n += 1;
        }
    }
    if n == 0 { f64::NAN } else { sum / n as f64 }
}

/// The table, one row per case.
pub fn markdown(rows: &[Row]) -> String {
    let mut out = String::from(
        "| algebra | c | steps/pixel | max steps | hits | first estimate / distance left | \
         missed by full steps | cpu f64 s | gpu f32 s | cpu f32 vs f64: mask, depth, colour | \
         gpu f32 vs f64: mask, depth, colour |\n\
         |---|---|---|---|---|---|---|---|---|---|---|\n",
    );
    let agreement = |a: &Agreement| {
        format!(
            "{:.2}%, {:.2}%, {:.2}%",
            100.0 * a.mask,
            100.0 * a.depth,
            100.0 * a.colour
        )
    };
    for r in rows {
        let nonzero = r.c.iter().filter(|&&v| v != 0.0).count();
        out += &format!(
            "| {} | {} ({} of {} nonzero) | {:.2} | {} | {:.1}% | {:.3} | {:.3}% | {:.3} | {} | {} | {} |\n",
            r.algebra.name(),
            r.label,
            nonzero,
            r.c.len(),
            r.steps_mean,
            r.steps_max,
            100.0 * r.hit_fraction,
            r.first_step,
            100.0 * r.overshoot,
            r.cpu_f64_seconds,
            r.gpu_seconds.map_or("-".into(), |s| format!("{s:.3}")),
            agreement(&r.cpu_f32),
            r.gpu_f32.as_ref().map_or("-".into(), agreement),
        );
    }
    out
}

/// The report page (docs/dimensions/dimensions.md) around the rows' table.
pub fn page(size: u32, machine: &str, table: &str) -> String {
    format!(
        "# The distance estimate as the dimension grows\n\n`qjulia report --dimensions --size {size}` on \
         {machine}. The seed's look (eye, light, shadows) with c in each algebra; the slice is the first \
         three axes. Steps and hits from the f64 CPU reference; agreement of f32 with it as shares of \
         pixels within CONTRACT_TOLERANCE.\n\n{table}"
    )
}
