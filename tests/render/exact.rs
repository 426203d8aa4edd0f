//! Checks against exact truth, not against our own output.
//!
//! With c = 0 the set is the unit ball and the seed's estimate is exactly d = r ln(r) / 2
//! (z_n = z^(2^n), z'_n = 2^n z^(2^n - 1)). With c real the slice is the complex Julia set of c
//! revolved about the real axis.

use crate::common;

use qjulia::algebra::{Real, Vec3};
use qjulia::cpu::trace::TINY;

const DERIVATIVE_LIMIT: f64 = <f64 as Real>::DERIVATIVE_LIMIT;
use qjulia::{Frame, Scene, TraceParams, cpu};

fn unit_ball_scene() -> Scene {
    common::scene(&[
        "fractal.c=[0, 0, 0, 0]",
        "image.width=96",
        "image.height=96",
        "camera.eye=[0.4, -0.3, 2.6]",
        "camera.fov_y_degrees=50",
    ])
}

#[test]
fn unit_ball_estimate_is_r_ln_r_over_two() {
    let scene = unit_ball_scene();
    let p = TraceParams::<f64>::new(&scene);
    // Radii whose orbits neither underflow nor overflow in 10 iterations (|z_10| = r^1024).
    for &r in &[0.9, 0.999, 1.0, 1.001, 1.1, 1.5] {
        for dir in [[1.0, 0.0, 0.0], [0.0, 0.6, 0.8], [-0.48, 0.6, -0.64]] {
            let point = Vec3::from_f64(dir) * r;
            let d = p.estimate_distance(point);
            let exact = r * r.ln() / 2.0;
            assert!(
                (d - exact).abs() <= 1e-12 * (1.0 + exact.abs()),
                "r = {r}: d = {d}, exact {exact}"
            );
        }
    }
}

/// Checks a frame of the unit ball: which rays hit, and where.
fn check_unit_ball_frame<F: Real>(name: &str, frame: &Frame, params: &TraceParams<F>) {
    let eps = params.epsilon.to_f64();
    let eye = params.eye.to_f64();
    let (mut through, mut far) = (0, 0);
    for j in 0..frame.height {
        for i in 0..frame.width {
            let k = (j * frame.width + i) as usize;
            let dir = TraceParams::<f64>::camera_ray_of(params, i, j);
            // Distance of the ray's line from the origin (the eye is outside the ball).
            let along = -(eye[0] * dir[0] + eye[1] * dir[1] + eye[2] * dir[2]);
            let closest = [0, 1, 2].map(|c| eye[c] + along * dir[c]);
            let b = closest.iter().map(|v| v * v).sum::<f64>().sqrt();
            let depth = frame.depth[k];
            if b < 1.0 - 1e-6 {
                through += 1;
                assert!(
                    !depth.is_nan(),
                    "{name}: pixel ({i}, {j}) passes {b} from the origin and misses"
                );
            }
            if b > 1.0 + 2.5 * eps {
                far += 1;
                assert!(
                    depth.is_nan(),
                    "{name}: pixel ({i}, {j}) passes {b} from the origin and hits"
                );
            }
            if !depth.is_nan() {
                let hit = [0, 1, 2].map(|c| eye[c] + depth as f64 * dir[c]);
                let r = hit.iter().map(|v| v * v).sum::<f64>().sqrt();
                // f32 depth is rounded: allow its rounding error along the ray.
                let slack = 4.0 * f32::EPSILON as f64 * depth as f64;
                assert!(
                    r >= 1.0 - slack && r <= 1.0 + 2.0 * eps + slack,
                    "{name}: pixel ({i}, {j}) hits at radius {r}, outside [1, 1 + 2 epsilon]"
                );
            }
        }
    }
    assert!(
        through > 1000 && far > 1000,
        "{name}: the view should show the ball and beyond"
    );
}

trait CameraRayOf {
    fn camera_ray_of<F: Real>(params: &TraceParams<F>, i: u32, j: u32) -> [f64; 3];
}

impl CameraRayOf for TraceParams<f64> {
    /// The ray through a pixel, computed in f64 from the same camera (truth, not the tracer's).
    fn camera_ray_of<F: Real>(params: &TraceParams<F>, i: u32, j: u32) -> [f64; 3] {
        let f = params.cam_forward.to_f64();
        let r = params.cam_right.to_f64();
        let u = params.cam_up.to_f64();
        let tan = params.tan_half_fov_y.to_f64();
        let px =
            (2.0 * (i as f64 + 0.5) / params.width as f64 - 1.0) * tan * params.aspect.to_f64();
        let py = (1.0 - 2.0 * (j as f64 + 0.5) / params.height as f64) * tan;
        let d = [0, 1, 2].map(|c| f[c] + px * r[c] + py * u[c]);
        let n = d.iter().map(|v| v * v).sum::<f64>().sqrt();
        d.map(|v| v / n)
    }
}

fn check_unit_ball_normals<F: Real>(name: &str, frame: &Frame, params: &TraceParams<F>) {
    let mut worst = 0f64;
    for j in 0..frame.height {
        for i in 0..frame.width {
            let depth = frame.depth[(j * frame.width + i) as usize];
            if depth.is_nan() {
                continue;
            }
            let dir = params.camera_ray(i, j, 0);
            let p = params.eye + dir * F::lit(depth as f64);
            let n = params.estimate_normal(p, dir).to_f64();
            let radial = p.to_f64();
            let len = radial.iter().map(|v| v * v).sum::<f64>().sqrt();
            let cos = (0..3).map(|c| n[c] * radial[c] / len).sum::<f64>();
            worst = worst.max(cos.clamp(-1.0, 1.0).acos().to_degrees());
        }
    }
    eprintln!("{name}: worst normal error {worst:.4} degrees");
    assert!(
        worst < 1.0,
        "{name}: a normal is {worst} degrees from radial"
    );
}

#[test]
fn unit_ball_on_the_cpu_in_f32_and_f64() {
    let scene = unit_ball_scene();
    let p32 = TraceParams::<f32>::new(&scene);
    let (f32_frame, _) = cpu::render(&p32);
    check_unit_ball_frame("cpu f32", &f32_frame, &p32);
    check_unit_ball_normals("cpu f32", &f32_frame, &p32);
    let p64 = TraceParams::<f64>::new(&scene);
    let (f64_frame, _) = cpu::render(&p64);
    check_unit_ball_frame("cpu f64", &f64_frame, &p64);
    check_unit_ball_normals("cpu f64", &f64_frame, &p64);
}

#[test]
fn unit_ball_normals_by_every_method_and_over_relaxed_hits() {
    // The tetrahedral stencil keeps a second-order term (the third moments of its corners do
    // not vanish) that |z_10| = r^1024 makes large at the seed's delta: it needs a smaller one.
    for (method, delta) in [("tetrahedral", 1e-5), ("analytic", 1e-4)] {
        let mut scene = unit_ball_scene();
        scene.shading.normal_delta = delta;
        scene.shading.normal = qjulia::scene::NormalMethod::ALL
            .into_iter()
            .find(|m| m.name() == method)
            .unwrap();
        let p = TraceParams::<f64>::new(&scene);
        let (frame, _) = cpu::render(&p);
        check_unit_ball_normals(method, &frame, &p);
    }
    // Over-relaxed steps keep every truth about the ball. (pixel_epsilon stays at its default, 0:
    // a pixel-proportional epsilon is held to the CPU twin in gpu_vs_cpu.rs, not checked here.)
    let mut scene = unit_ball_scene();
    scene.fractal.step_scale = 1.8;
    let p = TraceParams::<f32>::new(&scene);
    let (frame, _) = cpu::render(&p);
    check_unit_ball_frame("step_scale 1.8", &frame, &p);
}

#[test]
fn unit_ball_on_the_gpu() {
    let Some(gpu) = common::gpu("unit_ball_on_the_gpu") else {
        return;
    };
    let scene = unit_ball_scene();
    let params = TraceParams::<f32>::new(&scene);
    let frame = gpu.render(&params).unwrap().frame;
    check_unit_ball_frame("gpu", &frame, &params);
}

/// The complex distance estimate, written independently of the quaternion code, with
/// docs/CONTRACT.md's rule that d = 0 where it cannot be formed (and the documented thresholds).
fn complex_estimate(
    x: f64,
    y: f64,
    c: f64,
    max_iterations: u32,
    escape_radius_squared: f64,
) -> f64 {
    let (mut zr, mut zi) = (x, y);
    let (mut dr, mut di) = (1.0, 0.0);
    for _ in 0..max_iterations {
        // z' <- 2 z z', z <- z^2 + c
        let (ndr, ndi) = (2.0 * (zr * dr - zi * di), 2.0 * (zr * di + zi * dr));
        (dr, di) = (ndr, ndi);
        (zr, zi) = (zr * zr - zi * zi + c, 2.0 * zr * zi);
        if zr * zr + zi * zi > escape_radius_squared || dr * dr + di * di > DERIVATIVE_LIMIT {
            break;
        }
    }
    let (zz, dd) = (zr * zr + zi * zi, dr * dr + di * di);
    if zz < f64::MIN_POSITIVE || dd > DERIVATIVE_LIMIT || dd <= zz * TINY {
        return 0.0;
    }
    let z = zr.hypot(zi);
    0.5 * z * z.ln() / dr.hypot(di)
}

#[test]
fn real_c_gives_a_solid_of_revolution() {
    for c in [-1.0, -0.75, -0.4, 0.1, 0.3] {
        let scene = common::scene(&[
            &format!("fractal.c=[{c}, 0, 0, 0]"),
            "fractal.max_iterations=20",
        ]);
        let params = TraceParams::<f64>::new(&scene);
        // A deterministic spread of points through the bounding ball.
        let mut worst = 0f64;
        for k in 0..2000 {
            let t = k as f64;
            let p = [
                (t * 0.7548).fract(),
                (t * 0.5698).fract(),
                (t * 0.3141).fract(),
            ]
            .map(|u| 3.2 * u - 1.6);
            let q = params.estimate_distance(Vec3::from_f64(p));
            let e = complex_estimate(p[0], p[1].hypot(p[2]), c, 20, 10.0);
            let err = (q - e).abs() / (1e-3 + e.abs());
            worst = worst.max(err);
            assert!(
                err < 1e-9,
                "c = {c}, p = {p:?}: quaternion {q}, complex {e}"
            );
        }
        eprintln!("c = {c}: worst relative difference {worst:.2e}");
    }
}
