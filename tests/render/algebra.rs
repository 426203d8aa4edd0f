//! Octonion and sedenion Julia sets (`fractal.algebra`): with c and the slice inside the
//! quaternion subalgebra their renders equal the quaternion render (octonions bit for bit, since
//! both take |z'| by the norm; sedenions, which carry z' whole, to rounding), on every tracer; with
//! c reaching into the higher dimensions the GPU agrees with its CPU twin; the scene file checks
//! vector lengths against the algebra after all overrides.

use crate::common;

use qjulia::compare::{Agreement, CONTRACT_TOLERANCE, Tolerance};
use qjulia::scene::{Algebra, SceneLoader};
use qjulia::{Frame, Scene, TraceParams, cpu};

const SMALL: [&str; 2] = ["image.width=96", "image.height=96"];

fn with(extra: &[&str]) -> Scene {
    let all: Vec<&str> = SMALL.iter().chain(extra).copied().collect();
    common::scene(&all)
}

/// The scene in another algebra, c and the slice padded with zeros.
fn embedded(scene: &Scene, algebra: Algebra) -> Scene {
    let mut s = scene.clone();
    s.set_algebra(algebra);
    assert_eq!(s.fractal.c.len(), algebra.dim());
    s
}

/// Sedenions against quaternions: the same picture but for rounding (z' carried whole rather
/// than |z'| by the norm): the same hit mask, depth within 1e-5 and colour within 1/255 on all
/// but a few pixels.
const ROUNDING: Tolerance = Tolerance {
    mask_agreement: 0.999,
    depth_abs: 1e-5,
    depth_agreement: 0.999,
    colour_abs: 1,
    colour_agreement: 0.999,
};

fn assert_same_algebra(name: &str, algebra: Algebra, expected: &Frame, actual: &Frame) {
    if algebra == Algebra::Sedenion {
        common::assert_agree(name, expected, actual, &ROUNDING);
        let a = Agreement::measure(expected, actual, &ROUNDING);
        assert!(a.colour_max_error <= 2, "{name}: {a}");
    } else {
        assert_identical(name, expected, actual);
    }
}

fn assert_identical(name: &str, expected: &Frame, actual: &Frame) {
    assert!(
        expected.hit_mask().iter().any(|&h| h),
        "{name}: the scene shows nothing"
    );
    assert_eq!(expected.colour, actual.colour, "{name}: colour differs");
    assert_eq!(expected.steps, actual.steps, "{name}: steps differ");
    let bits = |f: &Frame| f.depth.iter().map(|d| d.to_bits()).collect::<Vec<_>>();
    assert_eq!(bits(expected), bits(actual), "{name}: depth differs");
}

/// Quaternion scenes with different paths through the tracer: the seed's look, a slice turned
/// within 4D with an offset, the analytic and tetrahedral normals.
fn quaternion_scenes() -> Vec<(&'static str, Scene)> {
    let (a, b) = (0.6f64, 0.4f64);
    let x = format!("slice.x=[{:?}, 0, 0, {:?}]", a.cos(), a.sin());
    let y = format!("slice.y=[0, {:?}, {:?}, 0]", b.cos(), b.sin());
    let z = format!("slice.z=[0, {:?}, {:?}, 0]", -b.sin(), b.cos());
    vec![
        ("seed_look", with(&[])),
        (
            "rotated",
            with(&[&x, &y, &z, "slice.offset=[0.1, 0, 0, -0.2]"]),
        ),
        ("analytic", with(&["shading.normal=\"analytic\""])),
        ("tetrahedral", with(&["shading.normal=\"tetrahedral\""])),
    ]
}

#[test]
fn embedded_quaternion_scenes_render_identically_on_the_cpu() {
    for (name, scene) in quaternion_scenes() {
        let (q32, _) = cpu::render(&TraceParams::<f32>::new(&scene));
        let (q64, _) = cpu::render(&TraceParams::<f64>::new(&scene));
        for algebra in [Algebra::Octonion, Algebra::Sedenion] {
            let s = embedded(&scene, algebra);
            let (f32_frame, _) = cpu::render(&TraceParams::<f32>::new(&s));
            assert_same_algebra(
                &format!("{name} {algebra:?} f32"),
                algebra,
                &q32,
                &f32_frame,
            );
            let (f64_frame, _) = cpu::render(&TraceParams::<f64>::new(&s));
            assert_same_algebra(
                &format!("{name} {algebra:?} f64"),
                algebra,
                &q64,
                &f64_frame,
            );
        }
    }
}

#[test]
fn embedded_quaternion_scenes_render_identically_on_the_gpu() {
    let Some(gpu) = common::gpu("embedded_quaternion_scenes_render_identically_on_the_gpu") else {
        return;
    };
    let render = |s: &Scene| gpu.render(&TraceParams::<f32>::new(s)).unwrap().frame;
    for (name, scene) in quaternion_scenes() {
        let q = render(&scene);
        for algebra in [Algebra::Octonion, Algebra::Sedenion] {
            let s = embedded(&scene, algebra);
            assert_same_algebra(&format!("{name} {algebra:?} gpu"), algebra, &q, &render(&s));
        }
    }
}

/// Scenes that use the higher dimensions: c off the quaternions, and a slice turned into them.
fn higher_scenes() -> Vec<(&'static str, Scene)> {
    let (a, b) = (0.5f64, 0.3f64);
    vec![
        (
            "octonion_c",
            with(&[
                "fractal.algebra=\"octonion\"",
                "fractal.c=[-0.2, 0.6, 0.2, 0.2, 0.15, -0.1, 0.1, 0.05]",
            ]),
        ),
        (
            "octonion_turned_slice",
            with(&[
                "fractal.algebra=\"octonion\"",
                "fractal.c=[-0.2, 0.6, 0.2, 0.2, 0.1, 0, 0, 0]",
                &format!("slice.x=[{:?}, 0, 0, 0, 0, {:?}, 0, 0]", a.cos(), a.sin()),
                &format!("slice.z=[0, 0, {:?}, 0, 0, 0, 0, {:?}]", b.cos(), b.sin()),
                "shading.normal=\"analytic\"",
            ]),
        ),
        (
            "sedenion_c",
            with(&[
                "fractal.algebra=\"sedenion\"",
                "fractal.c=[-0.2, 0.6, 0.2, 0.2, 0.1, 0, 0, -0.1, 0, 0.05, 0, 0, 0.1, 0, 0, 0]",
            ]),
        ),
    ]
}

#[test]
fn higher_dimensional_scenes_differ_from_the_quaternion_one() {
    let quaternion = cpu::render(&TraceParams::<f32>::new(&with(&[]))).0;
    for (name, scene) in higher_scenes() {
        let (frame, _) = cpu::render(&TraceParams::<f32>::new(&scene));
        assert!(frame.hit_mask().iter().any(|&h| h), "{name} shows nothing");
        assert_ne!(frame.colour, quaternion.colour, "{name}");
    }
}

#[test]
fn gpu_agrees_with_the_cpu_in_higher_dimensions() {
    let Some(gpu) = common::gpu("gpu_agrees_with_the_cpu_in_higher_dimensions") else {
        return;
    };
    for (name, scene) in higher_scenes() {
        let (expected, _) = cpu::render(&TraceParams::<f32>::new(&scene));
        let actual = gpu.render(&TraceParams::<f32>::new(&scene)).unwrap().frame;
        common::assert_agree(name, &expected, &actual, &CONTRACT_TOLERANCE);
    }
}

#[test]
fn vectors_must_have_the_algebra_length_after_all_overrides() {
    let build = |sets: &[&str]| {
        let mut l = SceneLoader::new();
        for s in sets {
            l.set(s).unwrap();
        }
        l.build()
    };
    // Defaults follow the algebra.
    let s = build(&["fractal.algebra=\"sedenion\""]).unwrap();
    assert_eq!(s.fractal.c.len(), 16);
    assert_eq!(&s.fractal.c[..4], &[-0.2, 0.6, 0.2, 0.2]);
    assert!(s.fractal.c[4..].iter().all(|&v| v == 0.0));
    assert_eq!(s.slice.z[2], 1.0);
    assert_eq!(s.slice.offset, vec![0.0; 16]);
    // A quaternion c with an octonion algebra names the key and the expected length.
    let e = build(&["fractal.c=[1, 0, 0, 0]", "fractal.algebra=\"octonion\""]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("fractal.c"));
    assert!(e.to_string().contains("8 numbers"), "{e}");
    let e = build(&[
        "fractal.algebra=\"octonion\"",
        "slice.offset=[0, 0, 0, 0, 0, 0, 0, 0, 0]",
    ])
    .unwrap_err();
    assert_eq!(e.key.as_deref(), Some("slice.offset"));
    // A later layer may fix an earlier one: only the final scene is checked.
    let s = build(&[
        "fractal.c=[1, 0, 0, 0]",
        "fractal.algebra=\"octonion\"",
        "fractal.c=[0.1, 0, 0, 0, 0, 0, 0, 0.2]",
    ])
    .unwrap();
    assert_eq!(s.fractal.c[7], 0.2);
    let e = build(&["fractal.algebra=\"trigintaduonion\""]).unwrap_err();
    assert_eq!(e.key.as_deref(), Some("fractal.algebra"));
}
