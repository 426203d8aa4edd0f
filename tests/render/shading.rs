//! The picture's shading features (issue 11): soft shadows (`light.radius`), ambient light and
//! occlusion (`shading.ambient`, `shading.occlusion`) and orbit-trap colour
//! (`shading.colouring`). Each is held to the CPU twin on the GPU, to the seed where it is off,
//! and to its formula in the book (docs/book/scene-file.md, "Shading features (exact)")
//! computed here from the definitions.

use crate::common;

use qjulia::algebra::Vec3;
use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::cpu::trace::{OCCLUSION_SAMPLES, OCCLUSION_STEP};
use qjulia::frame::unpack_rgb;
use qjulia::{Frame, Scene, TraceParams, cpu};

const SMALL: [&str; 2] = ["image.width=128", "image.height=128"];

fn with(extra: &[&str]) -> Scene {
    let all: Vec<&str> = SMALL.iter().chain(extra).copied().collect();
    common::scene(&all)
}

fn cpu_f32(scene: &Scene) -> Frame {
    cpu::render(&TraceParams::<f32>::new(scene)).0
}

/// The GPU against the CPU twin in f32, within CONTRACT_TOLERANCE.
fn gpu_agrees(name: &str, scene: Scene) {
    let expected = cpu_f32(&scene);
    assert!(
        expected.hit_mask().iter().any(|&h| h),
        "{name}: the test scene shows nothing"
    );
    let Some(gpu) = common::gpu(name) else { return };
    let actual = gpu
        .render(&TraceParams::<f32>::new(&scene))
        .expect("GPU render")
        .frame;
    common::assert_agree(name, &expected, &actual, &CONTRACT_TOLERANCE);
}

#[test]
fn soft_shadows_gpu_agrees_with_cpu() {
    gpu_agrees("soft_shadows", with(&["light.radius=0.3"]));
}

/// A radius of 0 is the seed's point light: the same frame, bit for bit, as a scene without the
/// key, on both tracers.
#[test]
fn radius_zero_is_the_hard_shadow_bit_for_bit() {
    let seed = with(&[]);
    let zero = with(&["light.radius=0"]);
    assert_identical("cpu", &cpu_f32(&seed), &cpu_f32(&zero));
    let Some(gpu) = common::gpu("radius_zero") else {
        return;
    };
    let a = gpu.render(&TraceParams::<f32>::new(&seed)).unwrap().frame;
    let b = gpu.render(&TraceParams::<f32>::new(&zero)).unwrap().frame;
    assert_identical("gpu", &a, &b);
}

/// The primary hits of every `step`-th pixel of a 128x128 scene, each with its pixel, the hit
/// point and the shading normal there (the CPU twin's own functions, in its precision).
fn hits_every<F: qjulia::algebra::Real>(
    p: &TraceParams<F>,
    step: usize,
) -> Vec<(u32, u32, Vec3<F>, Vec3<F>)> {
    let mut out = Vec::new();
    for j in (0..128).step_by(step) {
        for i in (0..128).step_by(step) {
            let dir = p.camera_ray(i, j, 0);
            let bounds = p.intersect_bounds(p.eye, dir);
            if !bounds.hit {
                continue;
            }
            let trace = p.sphere_trace(p.eye, dir, bounds.t_enter, bounds.t_exit, F::zero());
            if trace.hit {
                let x = p.eye + dir * trace.t;
                out.push((i, j, x, p.estimate_normal(x, dir)));
            }
        }
    }
    out
}

/// Colour, steps and depth (its bits: a miss is NaN) the same at every pixel.
fn assert_identical(name: &str, a: &Frame, b: &Frame) {
    let bits = |f: &Frame| f.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    let differ = (0..a.pixel_count())
        .filter(|&k| a.colour[k] != b.colour[k] || a.steps[k] != b.steps[k])
        .count();
    assert_eq!(differ, 0, "{name}: {differ} pixels differ");
    assert!(bits(a) == bits(b), "{name}: depths differ");
}

/// The soft march takes the hard shadow ray's steps (step_scale 1): it reports 0 exactly where
/// `in_shadow` reports a hit, and otherwise a visibility in (0, 1].
#[test]
fn soft_shadow_is_zero_exactly_where_the_hard_ray_hits() {
    let scene = with(&["light.radius=0.2"]);
    let p = TraceParams::<f32>::new(&scene);
    let (mut hidden, mut seen) = (0, 0);
    for (i, j, x, n) in hits_every(&p, 3) {
        let v = p.soft_shadow(x, n);
        if p.in_shadow(x, n) {
            hidden += 1;
            assert_eq!(v, 0.0, "pixel ({i}, {j})");
        } else {
            seen += 1;
            assert!(v > 0.0 && v <= 1.0, "pixel ({i}, {j}): visibility {v}");
        }
    }
    assert!(hidden > 20 && seen > 20, "{hidden} hidden, {seen} seen");
}

/// The penumbra lies outside the hard shadow (the soft march hits exactly where the hard ray
/// does, so the umbra is the hard shadow). The edge: hit pixels of the radius-0 render that are
/// lit and not in shadow (a hit, not black, the same colour as the render without shadows) with
/// a 4-neighbour in shadow (a hit whose colour differs from the render without shadows). With
/// radius 0.2 more than 5% of the edge pixels are strictly between the shadowed and the full
/// colour in the soft render: in the brightest channel c of the full colour,
/// shadow_factor * full[c] + 1 < soft[c] < full[c] (the 1 allows for rounding to 8 bits).
#[test]
fn a_radius_gives_a_penumbra_at_the_shadow_edge() {
    let hard = cpu_f32(&with(&[]));
    let open = cpu_f32(&with(&["shading.shadows=false"]));
    let soft = cpu_f32(&with(&["light.radius=0.2"]));
    let shadow_factor = with(&[]).shading.shadow_factor;
    let (w, h) = (hard.width as i64, hard.height as i64);
    let at = |i: i64, j: i64| (j * w + i) as usize;
    let hit = hard.hit_mask();
    let shadowed = |k: usize| hit[k] && hard.colour[k] != open.colour[k];
    let lit_open =
        |k: usize| hit[k] && hard.colour[k] == open.colour[k] && open.colour[k] & 0xff_ffff != 0;
    let (mut edge, mut penumbra) = (0, 0);
    for j in 0..h {
        for i in 0..w {
            let k = at(i, j);
            if !lit_open(k) {
                continue;
            }
            let next_to_shadow = [(1, 0), (-1, 0), (0, 1), (0, -1)].iter().any(|(di, dj)| {
                let (a, b) = (i + di, j + dj);
                a >= 0 && b >= 0 && a < w && b < h && shadowed(at(a, b))
            });
            if !next_to_shadow {
                continue;
            }
            edge += 1;
            let full = unpack_rgb(open.colour[k]);
            let got = unpack_rgb(soft.colour[k]);
            let c = (0..3).max_by_key(|&c| full[c]).unwrap();
            if shadow_factor * full[c] as f64 + 1.0 < got[c] as f64 && got[c] < full[c] {
                penumbra += 1;
            }
        }
    }
    eprintln!("shadow edge: {edge} pixels, {penumbra} in a penumbra");
    assert!(
        edge > 20,
        "the test scene has only {edge} shadow-edge pixels"
    );
    assert!(
        penumbra * 20 > edge,
        "only {penumbra} of {edge} edge pixels are in a penumbra"
    );
}

#[test]
fn occlusion_and_ambient_gpu_agrees_with_cpu() {
    gpu_agrees(
        "occlusion",
        with(&["shading.ambient=0.3", "shading.occlusion=1"]),
    );
    gpu_agrees("ambient_only", with(&["shading.ambient=0.5"]));
}

/// The unit ball (c = 0) with the light at its centre: every hit has N.l = -1, so only the
/// ambient term is left, ambient A B = A for ambient 1 and a white base. An open convex
/// surface occludes nothing: 2 d(1 + h) = (1 + h) ln(1 + h) >= h, so A = 1 at every hit, and
/// every hit is white within 1/255, on both tracers.
#[test]
fn the_unit_ball_is_not_occluded() {
    let scene = common::scene(&[
        "fractal.c=[0, 0, 0, 0]",
        "image.width=96",
        "image.height=96",
        "camera.eye=[0.4, -0.3, 2.6]",
        "camera.fov_y_degrees=50",
        "light.position=[0, 0, 0]",
        "shading.diffuse=[1, 1, 1]",
        "shading.ambient=1",
        "shading.occlusion=1",
    ]);
    let check = |name: &str, frame: &Frame| {
        let hits = frame.hit_mask();
        let n = hits.iter().filter(|&&h| h).count();
        assert!(n > 1000, "{name}: {n} hits");
        for (k, _) in hits.iter().enumerate().filter(|(_, h)| **h) {
            let rgb = unpack_rgb(frame.colour[k]);
            assert!(
                rgb.iter().all(|&c| c >= 254),
                "{name}: pixel {k} is {rgb:?}"
            );
        }
    };
    check("cpu", &cpu_f32(&scene));
    if let Some(gpu) = common::gpu("unit_ball_occlusion") {
        check(
            "gpu",
            &gpu.render(&TraceParams::<f32>::new(&scene)).unwrap().frame,
        );
    }
}

/// The occlusion factor by the book's formula, from the tracer's distance estimate:
/// A = 1 - occlusion (1/K) sum_{k=1..K} clamp(1 - 2 d(p + k h n) / (k h), 0, 1).
fn occlusion_formula(p: &TraceParams<f64>, x: Vec3<f64>, n: Vec3<f64>) -> f64 {
    let k_max = OCCLUSION_SAMPLES;
    let sum: f64 = (1..=k_max)
        .map(|k| {
            let h = k as f64 * OCCLUSION_STEP;
            let d = p.estimate_distance(x + n * h);
            (1.0 - 2.0 * d / h).clamp(0.0, 1.0)
        })
        .sum();
    1.0 - p.occlusion * sum / k_max as f64
}

/// On the seed's set (f64): the factor is the formula at every sampled hit, in
/// [1 - occlusion, 1], and well below 1 in its folds (some hit below 0.8).
#[test]
fn occlusion_follows_the_formula_and_darkens_folds() {
    let scene = with(&["shading.occlusion=1"]);
    let p = TraceParams::<f64>::new(&scene);
    let (mut hits, mut lowest) = (0, 1.0f64);
    for (i, j, x, n) in hits_every(&p, 4) {
        hits += 1;
        let a = p.occlusion(x, n);
        let expected = occlusion_formula(&p, x, n);
        assert!(
            (a - expected).abs() < 1e-12,
            "({i}, {j}): {a} vs {expected}"
        );
        assert!((0.0..=1.0).contains(&a), "({i}, {j}): {a}");
        lowest = lowest.min(a);
    }
    assert!(hits > 100, "{hits} hits");
    assert!(lowest < 0.8, "no fold: the lowest factor is {lowest}");
}

#[test]
fn orbit_trap_gpu_agrees_with_cpu() {
    gpu_agrees("orbit_trap", with(&["shading.colouring=\"orbit_trap\""]));
}

#[test]
fn all_three_features_gpu_agrees_with_cpu() {
    gpu_agrees(
        "all_features",
        with(&[
            "light.radius=0.5",
            "shading.ambient=0.25",
            "shading.occlusion=1",
            "shading.colouring=\"orbit_trap\"",
        ]),
    );
}

/// The trap distance at c = 0 from the definition: z_n = z_0^(2^n), so |z_n| = r^(2^n) for
/// |z_0| = r; t = min over n = 0..N of |r^(2^n) - R|, N the first n with |z_n|^2 above the
/// escape radius squared, or max_iterations.
fn trap_at_c0(r: f64, trap_radius: f64, max_iterations: u32, escape_radius_squared: f64) -> f64 {
    let mut t = (r - trap_radius).abs();
    for n in 1..=max_iterations {
        let z = r.powf(2f64.powi(n as i32));
        t = t.min((z - trap_radius).abs());
        if z * z > escape_radius_squared {
            break;
        }
    }
    t
}

/// The palette from the definition: 0.5 + 0.5 cos(2 pi (scale t + phase)) per channel.
fn palette(t: f64, scale: f64, phase: [f64; 3]) -> [f64; 3] {
    phase.map(|ph| 0.5 + 0.5 * (2.0 * std::f64::consts::PI * (scale * t + ph)).cos())
}

const UNIT_BALL_TRAP: [&str; 11] = [
    "fractal.c=[0, 0, 0, 0]",
    "image.width=96",
    "image.height=96",
    "camera.eye=[0.4, -0.3, 2.6]",
    "camera.fov_y_degrees=50",
    "light.position=[0, 0, 0]",
    "shading.ambient=1",
    "shading.colouring=\"orbit_trap\"",
    "shading.trap_radius=1.5",
    "shading.trap_scale=2.5",
    "shading.palette_phase=[0.0, 0.3, 0.6]",
];

#[test]
fn orbit_trap_at_c0_follows_the_formula() {
    let scene = common::scene(&UNIT_BALL_TRAP);
    let p = TraceParams::<f64>::new(&scene);
    let (iterations, escape) = (p.max_iterations, p.escape_radius_squared);
    // The function, at radii whose orbits escape at different n.
    for &r in &[0.3, 0.9, 0.999, 1.0, 1.0005, 1.002, 1.01, 1.1, 1.4, 2.0] {
        for dir in [[1.0, 0.0, 0.0], [0.0, 0.6, 0.8], [-0.48, 0.6, -0.64]] {
            let q = p.slice_point(Vec3::from_f64(dir) * r);
            let got = p.orbit_trap(q);
            let expected = trap_at_c0(r, 1.5, iterations, escape);
            assert!(
                (got - expected).abs() < 1e-9 * (1.0 + expected),
                "r = {r}: trap {got}, expected {expected}"
            );
        }
    }
    // The pictures: with the light at the centre only ambient B is left, B the palette colour
    // of the hit's trap distance, from the hit's radius (computed in f64 from the depth).
    let check = |name: &str, frame: &Frame| {
        let mut worst = 0f64;
        let mut spread = (f64::MAX, f64::MIN);
        for j in 0..frame.height {
            for i in 0..frame.width {
                let k = (j * frame.width + i) as usize;
                let depth = frame.depth[k];
                if depth.is_nan() {
                    continue;
                }
                let dir = p.camera_ray(i, j, 0);
                let r = (p.eye + dir * depth as f64).length();
                let t = trap_at_c0(r, 1.5, iterations, escape);
                spread = (spread.0.min(t), spread.1.max(t));
                let expected = palette(t, 2.5, [0.0, 0.3, 0.6]);
                let got = unpack_rgb(frame.colour[k]);
                for c in 0..3 {
                    worst = worst.max((got[c] as f64 / 255.0 - expected[c]).abs());
                }
            }
        }
        eprintln!("{name}: worst channel error {worst:.4}, t in {spread:?}");
        assert!(worst <= 2.0 / 255.0, "{name}: a channel is {worst} off");
        assert!(spread.1 - spread.0 > 0.1, "{name}: the trap barely varies");
    };
    check("cpu", &cpu_f32(&scene));
    if let Some(gpu) = common::gpu("orbit_trap_at_c0") {
        check(
            "gpu",
            &gpu.render(&TraceParams::<f32>::new(&scene)).unwrap().frame,
        );
    }
}
