//! The precisions, commands and views: f64 on the GPU where its check passes (else refused, or on
//! the CPU), help without a display, streamed bands against one band, usage errors, `render2d` and
//! its bad values, and the step views' heat maps.

use std::process::Command;

use super::error_line;
use crate::common::{Capability, files_in, qjulia, stderr};

/// Runs the qjulia binary in `dir` with `args` and extra environment variables.
fn qjulia_env(dir: &std::path::Path, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command.args(args).current_dir(dir);
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().unwrap()
}

/// A case of `--precision f64` refused on the GPU: its name, the environment that makes it and
/// what the error line names.
type Refusal<'a> = (&'a str, &'a [(&'a str, &'a str)], &'a str);

/// f64 runs on the CPU always, and on the GPU where the adapter passes the start-up check of f64
/// (lavapipe does); where it fails (a wrong division injected through the check's test hook),
/// `--backend gpu` exits 1 with one clear line and writes nothing, and `--backend auto` renders
/// on the CPU with a notice. Without SHADER_F64 (GL llvmpipe) the same; on an adapter without
/// f64 that refusal is the adapter's own, and the GPU's f64 render is said skipped.
#[test]
fn f64_on_the_gpu_where_its_check_passes_else_refused_or_on_the_cpu() {
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--width",
        "16",
        "--height",
        "16",
        "--precision",
        "f64",
        "--stats",
        "s.json",
    ];
    let stats = || std::fs::read_to_string(dir.path().join("s.json")).unwrap();
    let out = qjulia(dir.path(), &[&args[..], &["--backend", "cpu"]].concat());
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stats().contains("\"precision\": \"f64\"") && stats().contains("\"backend\": \"cpu\""));
    let test = "f64_on_the_gpu_where_its_check_passes_else_refused_or_on_the_cpu";
    if crate::common::gpu(test).is_none() {
        return;
    }
    let gpu = [&args[..], &["--backend", "gpu", "-o", "g.png"]].concat();
    let wrong_div = [("QJULIA_F64_CHECK_INJECT", "div")];
    let no_f64 = [("WGPU_BACKEND", "gl")];
    let refusals: &[Refusal] =
        if crate::common::gpu_has(Capability::F64, test, "the render in f64 on the GPU") {
            let out = qjulia(dir.path(), &gpu);
            assert!(out.status.success(), "{}", stderr(&out));
            assert!(
                stats().contains("\"precision\": \"f64\"")
                    && stats().contains("\"backend\": \"gpu\"")
            );
            std::fs::remove_file(dir.path().join("g.png")).unwrap();
            &[
                ("a wrong division", &wrong_div, "div of ("),
                ("GL llvmpipe", &no_f64, ""),
            ]
        } else {
            // The adapter's own refusal, as a user without f64 meets it.
            &[("this adapter", &[], "")]
        };
    for &(case, env, reason) in refusals {
        let out = qjulia_env(dir.path(), &gpu, env);
        let err = stderr(&out);
        assert_eq!(out.status.code(), Some(1), "{case}: {err}");
        let lines: Vec<&str> = err.lines().collect();
        assert_eq!(lines.len(), 1, "{case}: {err}");
        // GL llvmpipe has no f64; where wgpu finds no GL adapter at all, that is the error.
        assert!(
            lines[0].starts_with("error: --precision f64 is not available on the GPU")
                && lines[0].contains(reason)
                || lines[0].contains("no GPU adapter"),
            "{case}: {err}"
        );
        assert!(!dir.path().join("g.png").exists(), "{case}");
        let auto = [&args[..], &["--backend", "auto", "-o", "a.png"]].concat();
        let out = qjulia_env(dir.path(), &auto, env);
        let err = stderr(&out);
        assert!(out.status.success(), "{case}: {err}");
        assert!(err.contains("rendering on the CPU"), "{case}: {err}");
        assert!(stats().contains("\"backend\": \"cpu\""), "{case}");
    }
}

#[test]
fn no_subcommand_without_a_display_prints_help() {
    let dir = tempfile::tempdir().unwrap();
    let out = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .current_dir(dir.path())
        .env_remove("DISPLAY")
        .env_remove("WAYLAND_DISPLAY")
        .output()
        .unwrap();
    assert!(out.status.success());
    assert!(String::from_utf8_lossy(&out.stdout).contains("render"));
}

#[test]
fn streamed_bands_make_the_same_files_as_one_band() {
    let dir = tempfile::tempdir().unwrap();
    for backend in ["cpu", "auto"] {
        let args = |png: &str, npy: &str| {
            vec![
                "render".to_string(),
                "--backend".into(),
                backend.into(),
                "--width".into(),
                "64".into(),
                "--height".into(),
                "50".into(),
                "-o".into(),
                png.into(),
                "--steps".into(),
                npy.into(),
            ]
        };
        let whole = Command::new(env!("CARGO_BIN_EXE_qjulia"))
            .args(args("whole.png", "whole.npy"))
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(whole.status.success(), "{}", stderr(&whole));
        // 8 rows a band: 7 bands, the last one short.
        let banded = Command::new(env!("CARGO_BIN_EXE_qjulia"))
            .args(args("banded.png", "banded.npy"))
            .env("QJULIA_BAND_PIXELS", "512")
            .current_dir(dir.path())
            .output()
            .unwrap();
        assert!(banded.status.success(), "{}", stderr(&banded));
        let read = |name: &str| std::fs::read(dir.path().join(name)).unwrap();
        assert_eq!(
            read("whole.npy"),
            read("banded.npy"),
            "{backend}: steps differ"
        );
        let a = image::open(dir.path().join("whole.png")).unwrap().to_rgb8();
        let b = image::open(dir.path().join("banded.png"))
            .unwrap()
            .to_rgb8();
        assert!(a == b, "{backend}: pictures differ");
    }
}

#[test]
fn usage_errors_are_one_line_and_exit_2() {
    let dir = tempfile::tempdir().unwrap();
    for args in [
        &["render", "--width", "abc"][..],
        &["render", "--bogus"],
        &["render", "--backend", "tpu"],
    ] {
        let out = qjulia(dir.path(), args);
        assert_eq!(out.status.code(), Some(2), "{args:?}");
        let text = stderr(&out);
        assert_eq!(text.lines().count(), 1, "{args:?}: {text}");
        assert!(text.starts_with("error: "), "{text}");
        assert_eq!(files_in(dir.path()).len(), 0);
    }
    let help = qjulia(dir.path(), &["render", "--help"]);
    assert!(help.status.success() && String::from_utf8_lossy(&help.stdout).contains("--precision"));
}

#[test]
fn render2d_writes_a_grey_png_that_carries_its_view() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(
        dir.path(),
        &[
            "render2d",
            "--backend",
            "cpu",
            "--width",
            "64",
            "--height",
            "48",
            "--set",
            "fractal.c=[-0.12, 0.75, 0, 0]",
            "--set",
            "view2d.extent=3",
            "--stats",
            "s.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files_in(dir.path()), ["qjulia.png", "s.json"]);
    let img = image::open(dir.path().join("qjulia.png"))
        .unwrap()
        .to_rgb8();
    assert_eq!((img.width(), img.height()), (64, 48));
    assert!(
        img.pixels().all(|p| p[0] == p[1] && p[1] == p[2]),
        "not grey"
    );
    assert!(img.pixels().any(|p| p[0] == 255) && img.pixels().any(|p| p[0] < 64));
    let scene = qjulia::scene::scene_from_png(&dir.path().join("qjulia.png")).unwrap();
    assert!(
        scene.contains("[view2d]") && scene.contains("extent = 3.0"),
        "{scene}"
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert!(stats["hit_fraction"].as_f64().unwrap() > 0.05);
    assert!(stats["steps_max"].as_u64().unwrap() == 256);
    // Rendered again from its PNG, with -o: the same picture.
    let again = qjulia(
        dir.path(),
        &["render2d", "--scene", "qjulia.png", "-o", "again.png"],
    );
    assert!(again.status.success(), "{}", stderr(&again));
    let b = image::open(dir.path().join("again.png")).unwrap().to_rgb8();
    let differ = img
        .pixels()
        .zip(b.pixels())
        .filter(|(p, q)| p[0].abs_diff(q[0]) > 2)
        .count();
    assert!(differ <= 30, "{differ} pixels differ between CPU and auto");
}

#[test]
fn bad_view2d_values_exit_2_naming_the_key() {
    let dir = tempfile::tempdir().unwrap();
    let cases: &[(&str, &str)] = &[
        ("view2d.extent=0", "view2d.extent must be > 0"),
        ("view2d.extent=-1", "view2d.extent must be > 0"),
        ("view2d.extent=nan", "view2d.extent must be finite"),
        (
            "view2d.max_iterations=0",
            "view2d.max_iterations must be in [1, 100000]",
        ),
        (
            "view2d.max_iterations=100001",
            "view2d.max_iterations must be in [1, 100000]",
        ),
        (
            "view2d.center=[0]",
            "view2d.center must be an array of 2 numbers, not 1",
        ),
        ("view2d.center=[inf, 0]", "view2d.center must be finite"),
        ("view2d.zoom=2", "unknown key view2d.zoom"),
        ("image.view=depth", "image.view must be one of"),
    ];
    for (set, expected) in cases {
        for command in ["render2d", "render"] {
            let out = qjulia(
                dir.path(),
                &[command, "--set", set, "-o", "x.png", "--stats", "s.json"],
            );
            assert_eq!(
                out.status.code(),
                Some(2),
                "{command} {set}: {}",
                stderr(&out)
            );
            let line = error_line(&out);
            assert!(
                line.starts_with(&format!("error: --set {set}: ")) && line.contains(expected),
                "{command} {set}: {line}"
            );
            assert!(
                files_in(dir.path()).is_empty(),
                "{command} {set} wrote a file"
            );
        }
    }
    std::fs::write(dir.path().join("v.toml"), "[view2d]\nextent = 0\n").unwrap();
    let out = qjulia(dir.path(), &["render2d", "--scene", "v.toml"]);
    assert_eq!(out.status.code(), Some(2));
    assert!(error_line(&out).contains("v.toml: view2d.extent = 0: must be > 0"));
    assert_eq!(files_in(dir.path()), ["v.toml"]);
}

#[test]
fn step_views_draw_a_heat_map_with_a_legend_and_keep_the_view_in_the_png() {
    let dir = tempfile::tempdir().unwrap();
    for view in ["steps", "divergence"] {
        let png = format!("{view}.png");
        let out = qjulia(
            dir.path(),
            &[
                "render",
                "--backend",
                "cpu",
                "--width",
                "96",
                "--height",
                "40",
                "--view",
                view,
                "-o",
                &png,
                "--stats",
                "s.json",
                "--steps",
                "s.npy",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        let img = image::open(dir.path().join(&png)).unwrap().to_rgb8();
        let legend = qjulia::heatmap::LEGEND_HEIGHT;
        assert_eq!((img.width(), img.height()), (96, 40 + legend));
        // The corners miss the bounding ball: black in the steps view, and in the divergence
        // view, whose corner tiles (8 pixels wide, all missing the ball) do no work.
        assert_eq!(img.get_pixel(0, 0).0, [0, 0, 0], "{view}");
        // Somewhere the colour map's bright end.
        let top = qjulia::heatmap::COLOUR_STOPS[8];
        assert!(
            (0..40).any(|j| (0..96).any(|i| img.get_pixel(i, j).0 == top)),
            "{view}: no pixel at the maximum"
        );
        let scene = qjulia::scene::scene_from_png(&dir.path().join(&png)).unwrap();
        assert!(scene.contains(&format!("view = \"{view}\"")), "{scene}");
        let stats: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap())
                .unwrap();
        let efficiency = stats["tile_efficiency"].as_f64().unwrap();
        assert!(efficiency > 0.0 && efficiency <= 1.0, "{efficiency}");
        assert!(stats["wasted_steps_mean"].as_f64().unwrap() > 0.0);
        // From its PNG, the same picture again.
        let again = qjulia(
            dir.path(),
            &[
                "render",
                "--backend",
                "cpu",
                "--scene",
                &png,
                "-o",
                "again.png",
            ],
        );
        assert!(again.status.success(), "{}", stderr(&again));
        let b = image::open(dir.path().join("again.png")).unwrap().to_rgb8();
        assert!(img == b, "{view}: the re-render differs");
    }
    // --set wins over --view.
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "16",
            "--height",
            "16",
            "--view",
            "steps",
            "--set",
            "image.view=shaded",
            "-o",
            "shaded.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("shaded.png")).unwrap();
    assert_eq!(img.height(), 16);
    let out = qjulia(dir.path(), &["render", "--view", "normals"]);
    assert_eq!(out.status.code(), Some(2));
}
