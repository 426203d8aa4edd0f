//! The cut plane (`[cut]`): the set intersected with the half-space n . p <= offset.
//!
//! Truth from the definitions: with c = 0 the set is the unit ball, so a cut through its centre
//! seen along -n shows a flat disk: every hit lies on the plane (within epsilon), its normal is
//! the plane's, and its colour is the Phong shading of that normal (computed here in f64). The
//! GPU is held to its CPU twin in f32 with cuts on the seed's set, and a zero normal is refused.

use crate::common;

use qjulia::algebra::{Real, Vec3};
use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::frame::unpack_rgb;
use qjulia::{Frame, Scene, TraceParams, cpu};

/// GPU against CPU f32, as tests/render/gpu_vs_cpu.rs does, plus: the cut must show (some hit lies on
/// the plane).
fn check(name: &str, scene: Scene) {
    let params = TraceParams::<f32>::new(&scene);
    let (expected, _) = cpu::render(&params);
    let on_plane = on_plane_hits(&expected, &params);
    assert!(
        on_plane > expected.pixel_count() / 20,
        "{name}: only {on_plane} hits on the cut face"
    );
    let Some(gpu) = common::gpu(name) else { return };
    let actual = gpu.render(&params).expect("GPU render").frame;
    common::assert_agree(name, &expected, &actual, &CONTRACT_TOLERANCE);
    common::assert_steps_mostly_agree(name, &expected, &actual);
}

/// Hits within 2 epsilon of the cut plane.
fn on_plane_hits<F: Real>(frame: &Frame, params: &TraceParams<F>) -> usize {
    let (n, offset, eps) = (
        params.cut_normal.to_f64(),
        params.cut_offset.to_f64(),
        params.epsilon.to_f64(),
    );
    let mut count = 0;
    for j in 0..frame.height {
        for i in 0..frame.width {
            let depth = frame.depth[(j * frame.width + i) as usize];
            if depth.is_nan() {
                continue;
            }
            let p = hit_point(params, i, j, depth as f64);
            if (dot(n, p) - offset).abs() <= 2.0 * eps {
                count += 1;
            }
        }
    }
    count
}

fn small(extra: &[&str]) -> Scene {
    let all: Vec<&str> = ["image.width=128", "image.height=128"]
        .iter()
        .chain(extra)
        .copied()
        .collect();
    common::scene(&all)
}

#[test]
fn seed_look_cut_at_z_0_agrees_with_the_cpu() {
    check("cut_z0", small(&["cut.enabled=true"]));
}

#[test]
fn oblique_cut_agrees_with_the_cpu() {
    check(
        "cut_oblique",
        small(&[
            "cut.enabled=true",
            "cut.normal=[1, 1, 1]",
            "cut.offset=0.1",
            "camera.eye=[2, 1.5, 2]",
        ]),
    );
    check(
        "cut_oblique_cone_analytic",
        small(&[
            "cut.enabled=true",
            "cut.normal=[-0.3, 1, 0.5]",
            "cut.offset=-0.05",
            "camera.eye=[-0.5, 2.5, 1.5]",
            "fractal.tracing=cone",
            "shading.normal=analytic",
        ]),
    );
}

#[test]
fn the_generic_pipeline_cuts_too() {
    let Some(_) = common::gpu("cut_generic") else {
        return;
    };
    let mut generic = qjulia::gpu::GpuTracer::new(qjulia::gpu::GpuContext::new().unwrap()).unwrap();
    generic.set_specialise(false);
    let scene = small(&["cut.enabled=true", "cut.normal=[0, 1, 1]"]);
    let params = TraceParams::<f32>::new(&scene);
    let (expected, _) = cpu::render(&params);
    let actual = generic.render(&params).unwrap().frame;
    common::assert_agree("cut_generic", &expected, &actual, &CONTRACT_TOLERANCE);
}

// ----- the unit ball cut through its centre -----

/// The cut's normal (not of unit length: the loader normalises it) and the eye on it.
const N: [f64; 3] = [1.0, 2.0, 2.0];

fn cut_ball_scene() -> Scene {
    common::scene(&[
        "fractal.c=[0, 0, 0, 0]",
        "image.width=96",
        "image.height=96",
        "cut.enabled=true",
        "cut.normal=[1, 2, 2]",
        "cut.offset=0",
        // On the normal's line, 3 from the centre, looking at it: along -n onto the cut face.
        "camera.eye=[1, 2, 2]",
        "camera.up=[0, 0, 1]",
        "camera.fov_y_degrees=50",
        "light.position=[2, 2, 3]",
    ])
}

fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

fn normalise(v: [f64; 3]) -> [f64; 3] {
    let l = dot(v, v).sqrt();
    v.map(|x| x / l)
}

/// The ray through pixel (i, j)'s centre, in f64 from the camera frame (truth, not the tracer's).
fn ray<F: Real>(params: &TraceParams<F>, i: u32, j: u32) -> [f64; 3] {
    let (f, r, u) = (
        params.cam_forward.to_f64(),
        params.cam_right.to_f64(),
        params.cam_up.to_f64(),
    );
    let tan = params.tan_half_fov_y.to_f64();
    let px = (2.0 * (i as f64 + 0.5) / params.width as f64 - 1.0) * tan * params.aspect.to_f64();
    let py = (1.0 - 2.0 * (j as f64 + 0.5) / params.height as f64) * tan;
    normalise([0, 1, 2].map(|c| f[c] + px * r[c] + py * u[c]))
}

fn hit_point<F: Real>(params: &TraceParams<F>, i: u32, j: u32, t: f64) -> [f64; 3] {
    let (eye, dir) = (params.eye.to_f64(), ray(params, i, j));
    [0, 1, 2].map(|c| eye[c] + t * dir[c])
}

/// The seed's Phong (docs/CONTRACT.md) of the plane's normal at p, in f64, as 8-bit channels.
fn plane_phong(scene: &Scene, p: [f64; 3]) -> [f64; 3] {
    let n = normalise(N);
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let l = normalise(sub(scene.light.position, p));
    let e = normalise(sub(scene.camera.eye, p));
    let n_dot_l = dot(n, l);
    assert!(n_dot_l > 0.0, "the test wants the cut face lit");
    let r = [0, 1, 2].map(|c| 2.0 * n_dot_l * n[c] - l[c]);
    let highlight = scene.shading.specular * dot(e, r).max(0.0).powf(scene.shading.shininess);
    let sh = &scene.shading;
    [0, 1, 2].map(|c| {
        let v = (sh.diffuse[c] + sh.normal_tint * n[c].abs()) * n_dot_l + highlight;
        v.clamp(0.0, 1.0) * 255.0
    })
}

/// Every ray that meets the plane inside the unit disk hits there, with the plane's normal and
/// its Phong colour; every ray that meets it outside misses.
fn check_cut_ball<F: Real>(name: &str, frame: &Frame, params: &TraceParams<F>, scene: &Scene) {
    let n = normalise(N);
    let eps = params.epsilon.to_f64();
    let eye = params.eye.to_f64();
    let (mut disk, mut outside, mut worst_colour) = (0, 0, 0f64);
    for j in 0..frame.height {
        for i in 0..frame.width {
            let k = (j * frame.width + i) as usize;
            let dir = ray(params, i, j);
            // Where the ray meets the plane n . p = 0, and how far that is from the centre.
            let t_plane = -dot(n, eye) / dot(n, dir);
            let q = [0, 1, 2].map(|c| eye[c] + t_plane * dir[c]);
            let r = dot(q, q).sqrt();
            let depth = frame.depth[k];
            if r > 1.0 + 2.5 * eps {
                outside += 1;
                assert!(
                    depth.is_nan(),
                    "{name}: ({i}, {j}) meets the plane at r = {r} and hits"
                );
                continue;
            }
            if r >= 0.99 {
                continue;
            }
            disk += 1;
            assert!(
                !depth.is_nan(),
                "{name}: ({i}, {j}) meets the disk at r = {r} and misses"
            );
            let p = hit_point(params, i, j, depth as f64);
            let height = dot(n, p);
            let slack = 4.0 * f32::EPSILON as f64 * depth as f64;
            assert!(
                height >= -slack && height <= eps + slack,
                "{name}: ({i}, {j}) hits {height} from the plane, outside [0, epsilon]"
            );
            // The tracer's own normal at its hit is the plane's.
            let tracer_dir = params.camera_ray(i, j, 0);
            let hit = params.eye + tracer_dir * F::lit(depth as f64);
            let normal = params.estimate_normal(hit, tracer_dir).to_f64();
            let off = (0..3).map(|c| (normal[c] - n[c]).abs()).fold(0.0, f64::max);
            assert!(
                off < 1e-6,
                "{name}: ({i}, {j}) has normal {normal:?}, not {n:?}"
            );
            let want = plane_phong(scene, p);
            let got = unpack_rgb(frame.colour[k]);
            for c in 0..3 {
                worst_colour = worst_colour.max((got[c] as f64 - want[c]).abs());
            }
        }
    }
    eprintln!("{name}: {disk} disk pixels, {outside} outside, worst colour {worst_colour:.3}/255");
    assert!(
        disk > 2000 && outside > 1000,
        "{name}: the view should show the disk and beyond"
    );
    assert!(
        worst_colour <= 1.0,
        "{name}: a disk pixel is {worst_colour}/255 from the plane's Phong colour"
    );
}

#[test]
fn a_cut_through_the_unit_ball_is_a_flat_disk_on_the_cpu() {
    let scene = cut_ball_scene();
    let p32 = TraceParams::<f32>::new(&scene);
    check_cut_ball("cpu f32", &cpu::render(&p32).0, &p32, &scene);
    let p64 = TraceParams::<f64>::new(&scene);
    check_cut_ball("cpu f64", &cpu::render(&p64).0, &p64, &scene);
}

#[test]
fn a_cut_through_the_unit_ball_is_a_flat_disk_on_the_gpu() {
    let Some(gpu) = common::gpu("cut_ball_gpu") else {
        return;
    };
    let scene = cut_ball_scene();
    let params = TraceParams::<f32>::new(&scene);
    let frame = gpu.render(&params).unwrap().frame;
    check_cut_ball("gpu", &frame, &params, &scene);
}

#[test]
fn the_uncut_half_of_the_ball_is_untouched() {
    // The estimate is max(d, n . p - offset): the set's own where the plane's term is lower.
    let scene = cut_ball_scene();
    let p = TraceParams::<f64>::new(&scene);
    let n = normalise(N);
    for (point, want) in [
        // Behind the plane, the ball's exact r ln r / 2 (the plane's term is lower).
        ([0.0, 0.0, -1.2], 1.2 * 1.2f64.ln() / 2.0),
        (n.map(|x| -0.9 * x), 0.9 * 0.9f64.ln() / 2.0),
        // In front, the distance to the plane (larger than the ball's estimate).
        (n.map(|x| 0.5 * x), 0.5),
        (n.map(|x| 2.0 * x), 2.0),
    ] {
        let d = p.estimate_distance(Vec3::from_f64(point));
        assert!((d - want).abs() < 1e-12, "at {point:?}: {d}, want {want}");
    }
}

#[test]
fn a_zero_cut_normal_is_refused() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--backend",
        "cpu",
        "--set",
        "cut.normal=[0,0,0]",
        "-o",
        "x.png",
    ];
    common::assert_refused(dir.path(), &args, "error: --set ", "cut.normal");
}
