//! Path mode at the extremes (issue 35): tiny suns and sphere lights render finite and lit on
//! the GPU and on the CPU in both precisions; a sample that is not finite is dropped and
//! counted; rays that run out of steps are dark and counted (`--stats`' `nonfinite_samples` and
//! `exhausted_rays`).

use crate::common;

use std::process::Command;

use qjulia::algebra::Vec3;
use qjulia::cpu::path::sample_valid;
use qjulia::params::TraceParams;
use qjulia::{Frame, Picture, Precision, Scene};

fn path_scene(extra: &[&str]) -> Scene {
    let mut sets = vec![
        "shading.model=\"path\"",
        "image.width=48",
        "image.height=48",
    ];
    sets.extend_from_slice(extra);
    common::scene(&sets)
}

fn cpu_frame(scene: &Scene, precision: Precision) -> Frame {
    common::cpu_renderer(scene, precision)
        .render_frame(scene, Picture::SHADED)
        .expect("CPU render")
        .0
}

/// The mean over pixels and channels of a frame's linear radiance, and the share of hit pixels
/// that are black.
fn mean_and_black_hits(frame: &Frame) -> (f64, f64) {
    let r = &frame.radiance;
    assert_eq!(r.len(), frame.pixel_count());
    for (k, c) in r.iter().enumerate() {
        assert!(
            c.iter().all(|v| v.is_finite() && *v >= 0.0),
            "pixel {k}: {c:?}"
        );
    }
    let mean = r.iter().flatten().map(|&v| v as f64).sum::<f64>() / (3 * r.len()) as f64;
    let hits: Vec<_> = frame
        .depth
        .iter()
        .zip(r)
        .filter(|(d, _)| !d.is_nan())
        .collect();
    let black = hits
        .iter()
        .filter(|(_, c)| c.iter().all(|&v| v == 0.0))
        .count();
    (mean, black as f64 / hits.len().max(1) as f64)
}

/// The cases: a sun of 0.01 and 0.001 degrees (cos rounds to 1 in f32: NaN in 1,788 of
/// 4,096 pixels before) and a sphere light of radius 1e-4 with the sky off (every pixel it lit
/// was black before). Each renders finite on the GPU and the CPU in f32 and f64, no sample is
/// dropped, no more of the hits are black than with the larger light, and the image's mean
/// radiance is the same light's at a size where f32 was always
/// right (a sun of 0.5 degrees, a sphere of radius 1e-2), within 3% in f32 and f64 alike:
/// the far field of a light does not depend on its size, only the penumbrae move.
#[test]
fn tiny_suns_and_sphere_lights_render_finite_and_lit() {
    let cases: [(&[&str], &[&str]); 3] = [
        (
            &["sun.intensity=3", "sun.angular_radius_degrees=0.01"],
            &["sun.intensity=3", "sun.angular_radius_degrees=0.5"],
        ),
        (
            &["sun.intensity=3", "sun.angular_radius_degrees=0.001"],
            &["sun.intensity=3", "sun.angular_radius_degrees=0.5"],
        ),
        (
            &["sky.intensity=0", "light.radius=1e-4", "light.intensity=20"],
            &["sky.intensity=0", "light.radius=1e-2", "light.intensity=20"],
        ),
    ];
    for (tiny, large) in cases {
        let samples = ["image.samples=8"];
        let scene = path_scene(&[tiny, &samples[..]].concat());
        let reference = path_scene(&[large, &samples[..]].concat());
        let (want, want_black) = mean_and_black_hits(&cpu_frame(&reference, Precision::F64));
        let mut frames = vec![
            ("cpu f32", cpu_frame(&scene, Precision::F32)),
            ("cpu f64", cpu_frame(&scene, Precision::F64)),
        ];
        let test = "tiny_suns_and_sphere_lights_render_finite_and_lit";
        if let Some(f) = common::gpu_render_frame(test, &scene) {
            frames.push(("gpu f32", f));
        }
        for (name, frame) in frames {
            let (mean, black) = mean_and_black_hits(&frame);
            assert_eq!(frame.nonfinite_samples, 0, "{name} {tiny:?}");
            assert!(
                (mean - want).abs() < 0.03 * want,
                "{name} {tiny:?}: mean radiance {mean}, the larger light's {want}"
            );
            // Hits in shadow or facing away are black with either light; no more than that.
            assert!(
                black <= want_black + 0.02,
                "{name} {tiny:?}: {black} of the hits black, {want_black} with the larger light"
            );
        }
    }
}

#[test]
fn only_finite_non_negative_radiance_is_valid() {
    let v = |x: f64, y: f64, z: f64| Vec3::new(x, y, z);
    assert!(sample_valid(v(0.0, 1.0, 1e30)));
    assert!(sample_valid(v(-0.0, 0.0, 0.0)));
    assert!(!sample_valid(v(f64::NAN, 0.0, 0.0)));
    assert!(!sample_valid(v(0.0, f64::INFINITY, 0.0)));
    assert!(!sample_valid(v(0.0, 0.0, -1e-30)));
    assert!(!sample_valid(Vec3::new(1.0f32, f32::NEG_INFINITY, 1.0)));
}

/// A shadow ray that runs out of steps is occluded: on the unit ball (c = 0), from just above
/// its pole along the tangent, the ray leaves the bounding ball unoccluded with the default
/// steps, and with one step it runs out before it leaves (before issue 35 it counted as
/// unoccluded, lighting crevices through their walls).
#[test]
fn a_shadow_ray_that_runs_out_of_steps_is_occluded() {
    for (steps, expected) in [(1000, true), (1, false)] {
        let scene = common::scene(&["fractal.c=[0,0,0,0]", &format!("fractal.max_steps={steps}")]);
        let p = TraceParams::<f64>::new(&scene);
        let path = qjulia::cpu::path::PathParams::<f64>::new(&scene);
        let origin = Vec3::new(0.0, 0.0, 1.0 + 4.0 * p.epsilon);
        let dir = Vec3::new(1.0, 0.0, 0.0);
        assert_eq!(
            p.unoccluded(&path, origin, dir, 1e30),
            expected,
            "{steps} steps"
        );
    }
}

fn stats_of(backend: &str, sets: &[&str]) -> serde_json::Value {
    let dir = tempfile::tempdir().unwrap();
    let stats = dir.path().join("s.json");
    let mut cmd = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    cmd.args([
        "render",
        "--width",
        "48",
        "--height",
        "48",
        "--backend",
        backend,
    ]);
    for s in sets {
        cmd.args(["--set", s]);
    }
    cmd.arg("--stats")
        .arg(&stats)
        .arg("-o")
        .arg(dir.path().join("a.png"));
    let out = cmd.output().unwrap();
    assert!(
        out.status.success(),
        "{}",
        String::from_utf8_lossy(&out.stderr)
    );
    serde_json::from_str(&std::fs::read_to_string(stats).unwrap()).unwrap()
}

/// `--stats` counts the rays that ran out of steps in path mode: a crevice scene (the seed's
/// set with 30 steps a ray, where rays into its folds run out) has thousands, on the CPU and the
/// GPU alike (within 10%: a ray on the edge of running out can fall either way by one
/// rounding), and the default's far fewer; phong mode counts neither (null).
#[test]
fn stats_count_the_rays_that_run_out_in_path_mode() {
    let crevice = [
        "shading.model=\"path\"",
        "sun.intensity=3",
        "image.samples=8",
        "fractal.max_steps=30",
    ];
    let mut backends = vec!["cpu"];
    if !common::gpu_skipped("stats_count_the_rays_that_run_out_in_path_mode") {
        backends.push("gpu");
    }
    let mut counts = Vec::new();
    for backend in backends {
        let s = stats_of(backend, &crevice);
        assert_eq!(s["nonfinite_samples"], 0, "{backend}");
        let n = s["exhausted_rays"].as_u64().expect("a count");
        assert!(n > 1000, "{backend}: {n}");
        let default = stats_of(backend, &crevice[..3]);
        let d = default["exhausted_rays"].as_u64().expect("a count");
        assert!(
            d * 10 < n,
            "{backend}: {d} with the default steps, {n} with 30"
        );
        counts.push(n as f64);
    }
    if let [cpu, gpu] = counts[..] {
        assert!((cpu - gpu).abs() < 0.1 * cpu, "cpu {cpu}, gpu {gpu}");
    }
    let phong = stats_of("cpu", &["fractal.max_steps=30"]);
    assert!(phong["exhausted_rays"].is_null() && phong["nonfinite_samples"].is_null());
}
