//! Samples per pixel (`image.samples`): the GPU against the CPU, and exact truths. A view of
//! background alone is unchanged; on the unit ball (c = 0), black on white, a pixel's grey is the
//! share of its samples that miss, which is compared with the analytic share of the pixel that
//! the ball covers.

use crate::common;

use qjulia::compare::CONTRACT_TOLERANCE;
use qjulia::{Picture, Precision, Scene, TraceParams, cpu};

fn render(scene: &Scene, precision: Precision) -> qjulia::Frame {
    common::cpu_renderer(scene, precision)
        .render_frame(scene, Picture::SHADED)
        .expect("CPU render")
        .0
}

#[test]
fn gpu_and_cpu_agree_with_several_samples() {
    let scene = common::scene(&["image.width=96", "image.height=96", "image.samples=5"]);
    let Some(gpu) = common::gpu("samples gpu vs cpu") else {
        return;
    };
    let expected = render(&scene, Precision::F32);
    let actual = common::gpu_frame(gpu, &scene);
    common::assert_agree("samples-5", &expected, &actual, &CONTRACT_TOLERANCE);
    // Estimates and iterations are counted the same way on both: every ray of every sample.
    assert_counts_agree("samples-5", &expected, &actual);
}

/// The work counts of a CPU and a GPU frame of one scene agree up to rounding (a ray that ends
/// a step earlier or later on one backend): within 1e-3 of the CPU's.
fn assert_counts_agree(what: &str, cpu: &qjulia::Frame, gpu: &qjulia::Frame) {
    for (name, c, g) in [
        ("estimates", cpu.estimates, gpu.estimates),
        ("iterations", cpu.iterations, gpu.iterations),
    ] {
        let (c, g) = (c as f64, g as f64);
        assert!(
            c > 0.0 && (c - g).abs() <= 1e-3 * c,
            "{what}: {name}: cpu {c}, gpu {g}"
        );
    }
}

/// Path mode counts the iterations of every ray (camera, shadow, bounce), of the normals and of
/// the orbit trap, the same on both backends; the normals and the trap add iterations that no
/// estimate makes, so there are more than the estimates' own.
#[test]
fn path_mode_counts_the_same_iterations_on_both_backends() {
    let scene = common::scene(&[
        "image.width=40",
        "image.height=40",
        "image.samples=6",
        "shading.model=\"path\"",
        "shading.colouring=\"orbit_trap\"",
        "sun.intensity=3",
    ]);
    let Some(actual) = common::gpu_render_frame("path iterations gpu vs cpu", &scene) else {
        return;
    };
    let expected = render(&scene, Precision::F32);
    assert_counts_agree("path", &expected, &actual);
    assert!(expected.iterations > expected.estimates);
}

#[test]
fn depth_steps_and_hits_are_sample_zeros_and_estimates_count_every_sample() {
    let one = common::scene(&["image.width=48", "image.height=40"]);
    let mut four = one.clone();
    four.image.samples = 4;
    let (a, b) = (render(&one, Precision::F32), render(&four, Precision::F32));
    assert_eq!(a.steps, b.steps);
    assert_eq!(
        a.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>(),
        b.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>()
    );
    // One sample: the estimates are exactly the work counter's (primary and shadow rays).
    let work = cpu::count_work(&TraceParams::<f32>::new(&one));
    assert_eq!(a.estimates, work.estimates);
    assert_eq!(a.iterations, work.iterations);
    assert!(
        b.estimates > 3 * a.estimates,
        "{} vs {}",
        b.estimates,
        a.estimates
    );
    assert_ne!(a.colour, b.colour, "four samples change the edges");
}

#[test]
fn a_view_of_background_alone_is_unchanged_by_samples() {
    // Looking away from the set: every ray misses the bounding ball.
    let scene = common::scene(&[
        "image.width=40",
        "image.height=24",
        "image.samples=9",
        "camera.eye=[0, 0, 3]",
        "camera.target=[0, 0, 6]",
        "shading.background=[0.2, 0.5, 0.7]",
    ]);
    let mut one = scene.clone();
    one.image.samples = 1;
    let mut frames = vec![
        (
            "cpu f32",
            render(&one, Precision::F32),
            render(&scene, Precision::F32),
        ),
        (
            "cpu f64",
            render(&one, Precision::F64),
            render(&scene, Precision::F64),
        ),
    ];
    if let Some(gpu) = common::gpu("background with samples") {
        let on_gpu = |s: &Scene| {
            gpu.render(&TraceParams::<f32>::new(s))
                .expect("GPU render")
                .frame
        };
        frames.push(("gpu", on_gpu(&one), on_gpu(&scene)));
    }
    for (name, single, several) in frames {
        // The background as one sample packs it (0.7 * 255 rounds to 178 in f32, 179 in f64).
        let background = single.colour[0];
        assert!(single.colour.iter().all(|&c| c == background), "{name}");
        assert!(
            several.colour.iter().all(|&c| c == background),
            "{name}: a background pixel changed"
        );
        assert!(several.depth.iter().all(|d| d.is_nan()), "{name}");
    }
}
/// The CONTRACT's camera in f64, independently of the tracer: the ray through the point (x, y)
/// of the image plane in pixel units.
fn camera_ray(scene: &Scene, x: f64, y: f64) -> [f64; 3] {
    let sub = |a: [f64; 3], b: [f64; 3]| [a[0] - b[0], a[1] - b[1], a[2] - b[2]];
    let cross = |a: [f64; 3], b: [f64; 3]| {
        [
            a[1] * b[2] - a[2] * b[1],
            a[2] * b[0] - a[0] * b[2],
            a[0] * b[1] - a[1] * b[0],
        ]
    };
    let norm = |a: [f64; 3]| {
        let l = (a[0] * a[0] + a[1] * a[1] + a[2] * a[2]).sqrt();
        a.map(|v| v / l)
    };
    let (w, h) = (scene.image.width as f64, scene.image.height as f64);
    let f = norm(sub(scene.camera.target, scene.camera.eye));
    let r = norm(cross(f, scene.camera.up));
    let u = cross(r, f);
    let tan = (scene.camera.fov_y_degrees.to_radians() / 2.0).tan();
    let px = (2.0 * x / w - 1.0) * tan * w / h;
    let py = (1.0 - 2.0 * y / h) * tan;
    norm([0, 1, 2].map(|k| f[k] + px * r[k] + py * u[k]))
}

#[test]
fn on_the_unit_ball_a_pixels_grey_is_the_share_of_samples_that_hit() {
    const SAMPLES: u32 = 64;
    let scene = common::scene(&[
        "fractal.c=[0, 0, 0, 0]",
        "fractal.epsilon=1e-4",
        "image.width=64",
        "image.height=64",
        "image.samples=64",
        "camera.eye=[0, 0, 3]",
        "camera.fov_y_degrees=50",
        "shading.diffuse=[0, 0, 0]",
        "shading.normal_tint=0",
        "shading.specular=0",
        "shading.shadows=false",
        "shading.background=[1, 1, 1]",
    ]);
    // Rays stop where the estimate r ln(r) / 2 drops below epsilon: the ball they see has the
    // radius solving r ln(r) / 2 = epsilon (Newton from 1).
    let eps = scene.fractal.epsilon;
    let mut radius = 1.0f64;
    for _ in 0..50 {
        radius -= (radius * radius.ln() / 2.0 - eps) / ((radius.ln() + 1.0) / 2.0);
    }
    let eye = scene.camera.eye;
    let covers = |x: f64, y: f64| {
        let d = camera_ray(&scene, x, y);
        let along = -(eye[0] * d[0] + eye[1] * d[1] + eye[2] * d[2]);
        let closest = [0, 1, 2].map(|k| eye[k] + along * d[k]);
        closest.iter().map(|v| v * v).sum::<f64>() < radius * radius
    };
    // The analytic share: the pixel's area whose ray meets the ball, on a 128 x 128 grid of
    // the pixel (an error below 1/128 on a straight edge, far below the samples').
    const GRID: u32 = 128;
    let share = |i: u32, j: u32| {
        let inside = (0..GRID * GRID)
            .filter(|k| {
                let (a, b) = ((k % GRID) as f64 + 0.5, (k / GRID) as f64 + 0.5);
                covers(i as f64 + a / GRID as f64, j as f64 + b / GRID as f64)
            })
            .count();
        inside as f64 / (GRID * GRID) as f64
    };
    let mut frames = vec![
        ("cpu f64", render(&scene, Precision::F64)),
        ("cpu f32", render(&scene, Precision::F32)),
    ];
    if let Some(gpu) = common::gpu("unit ball coverage") {
        let frame = common::gpu_frame(gpu, &scene);
        frames.push(("gpu f32", frame));
    }
    for (name, frame) in frames {
        let (mut count, mut error_sum, mut worst) = (0u32, 0.0f64, 0.0f64);
        for j in 0..64 {
            for i in 0..64 {
                let truth = share(i, j);
                if truth <= 0.0 || truth >= 1.0 {
                    continue;
                }
                let grey = (frame.colour[(j * 64 + i) as usize] & 0xff) as f64 / 255.0;
                let error = ((1.0 - grey) - truth).abs();
                count += 1;
                error_sum += error;
                worst = worst.max(error);
            }
        }
        let mean = error_sum / count as f64;
        eprintln!("{name}: {count} silhouette pixels, mean error {mean:.4}, worst {worst:.4}");
        assert!(count > 100, "{name}: only {count} silhouette pixels");
        // The bound: N low-discrepancy points estimate the area of a pixel cut by a nearly
        // straight edge within about their discrepancy, of order (ln N)^2 / N for Halton points
        // (0.27 at N = 64, a loose worst case); on average over edge pixels it is several times
        // smaller. Allowed: a mean of 1.5 / N plus the grey's rounding (0.5 / 255), and a worst
        // pixel of 8 / N. (One sample, through the centre, measures a mean error of 0.175 and a worst of 0.456 here:
        // seven times this bound.)
        let n = SAMPLES as f64;
        assert!(
            mean <= 1.5 / n + 0.5 / 255.0,
            "{name}: mean coverage error {mean} above 1.5/N"
        );
        assert!(worst <= 8.0 / n, "{name}: worst coverage error {worst}");
    }
}

#[test]
fn every_feature_at_once_agrees_on_gpu_and_cpu() {
    // The gallery preset turns on samples, soft shadows, ambient and occlusion, orbit-trap
    // colour and the cut together.
    let mut scene = qjulia::scene::presets::find("gallery")
        .expect("the gallery preset")
        .scene();
    scene.image.width = 96;
    scene.image.height = 96;
    scene.image.samples = 4;
    let Some(gpu) = common::gpu("every feature at once") else {
        return;
    };
    let expected = render(&scene, Precision::F32);
    let actual = common::gpu_frame(gpu, &scene);
    assert!(expected.hit_mask().iter().any(|&h| h));
    common::assert_agree("all-features", &expected, &actual, &CONTRACT_TOLERANCE);
}
