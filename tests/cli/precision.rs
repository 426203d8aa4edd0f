//! `--precision auto` (the default): f32 wherever f32 resolves the picture, f64 otherwise, and
//! `--stats` says which ran (`precision`) and why (`precision_reason`); for `render`,
//! `render2d` and each frame of `animate`. On the CPU, where f64 always runs.

use crate::common;

use crate::common::{qjulia, stderr};

fn stats(dir: &std::path::Path, name: &str) -> serde_json::Value {
    serde_json::from_str(&std::fs::read_to_string(dir.join(name)).unwrap()).unwrap()
}

const SMALL: [&str; 4] = ["--width", "48", "--height", "32"];

#[test]
fn render_auto_runs_f32_where_it_resolves_and_f64_where_it_does_not() {
    let dir = tempfile::tempdir().unwrap();
    let run = |extra: &[&str], name: &str| {
        let args = [
            &["render", "--backend", "cpu", "--stats", name][..],
            &SMALL,
            extra,
        ]
        .concat();
        let out = qjulia(dir.path(), &args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        (stats(dir.path(), name), stderr(&out))
    };
    let (s, err) = run(&[], "plain.json");
    assert_eq!(s["precision"], "f32", "{s}");
    assert_eq!(s["precision_reason"], "auto: f32 resolves the scene");
    assert!(!err.contains("warning"), "{err}");

    let (s, err) = run(&["--set", "fractal.epsilon=1e-9"], "deep.json");
    assert_eq!(s["precision"], "f64", "{s}");
    let reason = s["precision_reason"].as_str().unwrap();
    assert!(
        reason.starts_with("auto: fractal.epsilon = 1e-9 is below"),
        "{reason}"
    );
    assert!(
        err.contains("rendering in f64: auto: fractal.epsilon"),
        "{err}"
    );
    assert!(!err.contains("warning"), "f64 resolves it: {err}");

    // Asked for f32: f32, with f32's warning, as before.
    let (s, err) = run(
        &["--set", "fractal.epsilon=1e-9", "--precision", "f32"],
        "f32.json",
    );
    assert_eq!(s["precision"], "f32");
    assert_eq!(s["precision_reason"], "asked for (--precision f32)");
    assert!(err.contains("warning: fractal.epsilon"), "{err}");
}

#[test]
fn render2d_auto_holds_the_pixel_to_f32s_spacing() {
    let dir = tempfile::tempdir().unwrap();
    let run = |extent: &str, name: &str| {
        let set = format!("view2d.extent={extent}");
        let args = [
            &[
                "render2d",
                "--backend",
                "cpu",
                "--stats",
                name,
                "--set",
                &set,
            ][..],
            &SMALL,
        ]
        .concat();
        let out = qjulia(dir.path(), &args);
        assert!(out.status.success(), "{args:?}: {}", stderr(&out));
        stats(dir.path(), name)
    };
    assert_eq!(run("4", "wide.json")["precision"], "f32");
    let deep = run("1e-9", "deep.json");
    assert_eq!(deep["precision"], "f64", "{deep}");
    assert!(
        deep["precision_reason"]
            .as_str()
            .unwrap()
            .contains("a pixel spans"),
        "{deep}"
    );
}

#[test]
fn animate_decides_each_frame_by_its_own_scene() {
    // epsilon from 1e-3 (f32 resolves it) at frame 0 to 1e-9 (it does not) at frame 3.
    let dir = tempfile::tempdir().unwrap();
    let scene = "[image]\nwidth = 40\nheight = 30\n\n[animation]\nframes = 4\n\n\
        [[animation.keys]]\nframe = 0\nfractal.epsilon = 1e-3\n\n\
        [[animation.keys]]\nframe = 3\nfractal.epsilon = 1e-9\n";
    std::fs::write(dir.path().join("a.toml"), scene).unwrap();
    let args = ["animate", "--scene", "a.toml", "--backend", "cpu"];
    let out = qjulia(dir.path(), &[&args[..], &["--stats", "s.json"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    let s = stats(dir.path(), "s.json");
    assert_eq!(s["precision"], "f32, f64", "{s}");
    // Each frame renders again to the same bytes under the same rule, and a split gives the
    // same frames: a frame's precision is its own scene's, not its range's.
    let out = qjulia(
        dir.path(),
        &[&args[..], &["--frames", "3..3", "--out", "alone"]].concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let whole = std::fs::read(dir.path().join("qjulia-frames/frame-00003.png")).unwrap();
    assert!(whole == std::fs::read(dir.path().join("alone/frame-00003.png")).unwrap());
    for k in [0, 3] {
        let frame = format!("qjulia-frames/frame-{k:05}.png");
        let again = format!("again-{k}.png");
        let out = qjulia(
            dir.path(),
            &[
                "render",
                "--scene",
                &frame,
                "--backend",
                "cpu",
                "-o",
                &again,
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(
            std::fs::read(dir.path().join(&frame)).unwrap()
                == std::fs::read(dir.path().join(&again)).unwrap(),
            "frame {k} renders again to the same bytes"
        );
    }
}

#[test]
fn depth_is_float64_when_the_render_ran_in_f64() {
    // A pixel footprint of about 2e-9 at the hit: f32's spacing there (2.4e-7 near t = 2) is a
    // hundred pixels, so float32 depths collapse to a few values while float64 keeps them apart.
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(
        dir.path(),
        &[
            &[
                "render",
                "--backend",
                "cpu",
                "--depth",
                "d.npy",
                "--stats",
                "s.json",
            ][..],
            &SMALL,
            &["--set", "camera.fov_y_degrees=1e-6"],
        ]
        .concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(stats(dir.path(), "s.json")["precision"], "f64");
    let bytes = std::fs::read(dir.path().join("d.npy")).unwrap();
    let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
    let header = String::from_utf8_lossy(&bytes[10..10 + header_len]);
    assert!(header.contains("'descr': '<f8'"), "{header}");
    let depth: Vec<f64> = bytes[10 + header_len..]
        .chunks_exact(8)
        .map(|b| f64::from_le_bytes(b.try_into().unwrap()))
        .collect();
    assert_eq!(depth.len(), 48 * 32);
    let hits: Vec<f64> = depth.iter().copied().filter(|d| !d.is_nan()).collect();
    assert!(
        hits.len() > 48 * 32 / 2,
        "the zoom is on the set: {} hits",
        hits.len()
    );
    let distinct = |values: Vec<u64>| {
        let mut v = values;
        v.sort_unstable();
        v.dedup();
        v.len()
    };
    let as_f64 = distinct(hits.iter().map(|d| d.to_bits()).collect());
    let as_f32 = distinct(hits.iter().map(|&d| (d as f32).to_bits() as u64).collect());
    assert!(
        as_f64 > 10 * as_f32,
        "float64 keeps {as_f64} distinct depths where float32 keeps {as_f32}"
    );
}

/// The kinds of a work's warnings in a precision, through the one decision's plan.
fn kinds(
    sets: &[&str],
    work: qjulia::Work,
    precision: qjulia::Precision,
) -> Vec<qjulia::precision::WarningKind> {
    let choice = match precision {
        qjulia::Precision::F32 => qjulia::PrecisionChoice::F32,
        qjulia::Precision::F64 => qjulia::PrecisionChoice::F64,
    };
    let scene = common::scene(sets);
    let plan = qjulia::Planner::new(qjulia::Backend::Cpu, choice)
        .plan(&scene, work, &mut |_| {})
        .expect("a CPU plan");
    assert_eq!(plan.decision.precision, precision);
    for w in &plan.warnings {
        // The line is the shortfall, then what is done about it.
        assert!(w.text.starts_with(&format!("{}: ", w.shortfall)), "{w}");
    }
    plan.warnings.iter().map(|w| w.kind).collect()
}

#[test]
fn each_warning_kind_fires_where_its_precision_falls_short() {
    use qjulia::Precision::{F32, F64};
    use qjulia::precision::WarningKind::*;
    let slice = qjulia::Picture::SHADED.into();
    let plane = qjulia::Picture::Julia2d.into();
    // Nothing in the default scene, in either precision.
    for p in [F32, F64] {
        assert!(kinds(&[], slice, p).is_empty());
        assert!(kinds(&[], plane, p).is_empty());
    }
    // Each kind fires in f32 where f64 still resolves it, and in f64 further on.
    let cases: [(
        &[&str],
        &[&str],
        qjulia::Work,
        qjulia::precision::WarningKind,
    ); 4] = [
        (
            &["fractal.epsilon=1e-9"],
            &["fractal.epsilon=1e-300"],
            slice,
            Epsilon,
        ),
        (
            &["camera.fov_y_degrees=1e-5"],
            &["camera.fov_y_degrees=1e-13"],
            slice,
            Pixel,
        ),
        (
            &["fractal.escape_radius_squared=1e9"],
            &["fractal.escape_radius_squared=1e101"],
            slice,
            EscapeRadius,
        ),
        (
            &["view2d.extent=1e-4"],
            &["view2d.extent=1e-13"],
            plane,
            Pixel2d,
        ),
    ];
    for (f32_sets, f64_sets, work, kind) in cases {
        assert_eq!(kinds(f32_sets, work, F32), [kind], "{f32_sets:?} in f32");
        assert!(kinds(f32_sets, work, F64).is_empty(), "{f32_sets:?} in f64");
        assert_eq!(kinds(f64_sets, work, F64), [kind], "{f64_sets:?} in f64");
    }
    // A mesh: its grid cell plays the pixel's part (a tiny pixel says nothing of it), and the
    // scene's other shortfalls stay.
    let grid = |step: f64| {
        qjulia::Work::Mesh(Some(qjulia::grid::GridSpec {
            origin: [0.5; 3],
            step: [step; 3],
            size: [8; 3],
        }))
    };
    let tiny_pixel: &[&str] = &["camera.fov_y_degrees=1e-5"];
    assert!(kinds(tiny_pixel, grid(0.1), F32).is_empty());
    assert_eq!(kinds(&[], grid(1e-8), F32), [GridCell]);
    assert!(kinds(&[], grid(1e-8), F64).is_empty());
    assert_eq!(kinds(&[], grid(1e-17), F64), [GridCell]);
    assert_eq!(
        kinds(&["fractal.epsilon=1e-9"], grid(1e-8), F32),
        [Epsilon, GridCell]
    );
    // No grid (an empty bounding region): the scene's own.
    assert_eq!(
        kinds(&["fractal.epsilon=1e-9"], qjulia::Work::Mesh(None), F32),
        [Epsilon]
    );
}
