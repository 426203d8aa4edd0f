//! The command line as a user meets it (docs/CONTRACT.md): default output, bad input, atomic writes,
//! re-rendering from a PNG, the .npy and JSON outputs.

mod common;

use std::path::Path;
use std::process::{Command, Output};

use common::{files_in, qjulia, stderr};

/// The one `error:` line of a failed run.
fn error_line(out: &Output) -> String {
    let text = stderr(out);
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "expected one error line, got:\n{text}");
    errors[0].to_string()
}

#[test]
fn render_with_no_options_writes_a_512_square_png() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(dir.path(), &["render"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(files_in(dir.path()), ["qjulia.png"]);
    let img = image::open(dir.path().join("qjulia.png")).unwrap();
    assert_eq!((img.width(), img.height()), (512, 512));
    assert_eq!(img.color(), image::ColorType::Rgb8);
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        let mode = std::fs::metadata(dir.path().join("qjulia.png"))
            .unwrap()
            .permissions()
            .mode();
        assert_eq!(
            mode & 0o644,
            0o644,
            "outputs are ordinary readable files, not private temporaries"
        );
    }
    // It said which backend it used.
    assert!(
        stderr(&out).contains("rendering on the"),
        "{}",
        stderr(&out)
    );
}

#[test]
fn bad_input_exits_2_naming_the_key_and_writes_nothing() {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("bad.toml"),
        "[camera]\nfov_y_degrees = 190\n",
    )
    .unwrap();
    std::fs::write(dir.path().join("typo.toml"), "[fractal]\nepsilom = 0.01\n").unwrap();
    std::fs::write(dir.path().join("broken.toml"), "[fractal\nc = 1\n").unwrap();
    let cases: &[(&[&str], &str)] = &[
        (&["--set", "fractal.colour=1"], "unknown key fractal.colour"),
        (
            &["--set", "image.width=wide"],
            "image.width must be an integer",
        ),
        (
            &["--set", "fractal.c=[1, 2]"],
            "fractal.c must be an array of 4 numbers, not 2",
        ),
        (
            &["--set", "fractal.max_iterations=0"],
            "fractal.max_iterations must be in [1, 100000]",
        ),
        (
            &["--set", "fractal.epsilon=nan"],
            "--set fractal.epsilon=nan: fractal.epsilon must be finite",
        ),
        (
            &["--set", "fractal.epsilon=-1"],
            "fractal.epsilon must be > 0",
        ),
        (
            &["--set", "camera.target=[0, 0, 3]"],
            "camera.target must differ",
        ),
        (
            &["--set", "camera.up=[0, 0, -1]"],
            "camera.up makes camera.up parallel",
        ),
        (
            &["--width", "0"],
            "--width 0: image.width must be in [1, 65536]",
        ),
        (
            &["--scene", "bad.toml"],
            "bad.toml: camera.fov_y_degrees = 190: must be in (0, 180)",
        ),
        (
            &["--scene", "typo.toml"],
            "typo.toml: unknown key fractal.epsilom",
        ),
        (
            &["--scene", "broken.toml"],
            "broken.toml: invalid TOML at line 1",
        ),
        (&["--scene", "missing.toml"], "missing.toml: cannot read"),
    ];
    for (args, expected) in cases {
        let mut all = vec!["render"];
        all.extend_from_slice(args);
        all.extend_from_slice(&["--depth", "d.npy", "--stats", "s.json", "-o", "x.png"]);
        let out = qjulia(dir.path(), &all);
        assert_eq!(out.status.code(), Some(2), "{args:?}: {}", stderr(&out));
        let line = error_line(&out);
        assert!(
            line.contains(expected),
            "{args:?}: expected {expected:?} in {line:?}"
        );
        assert!(!stderr(&out).contains("panicked"), "{args:?} panicked");
        assert_eq!(
            files_in(dir.path()),
            ["bad.toml", "broken.toml", "typo.toml"],
            "{args:?} wrote a file"
        );
    }
}

#[test]
fn existing_outputs_survive_a_failed_run() {
    let dir = tempfile::tempdir().unwrap();
    let png = dir.path().join("keep.png");
    std::fs::write(&png, b"precious").unwrap();
    // Bad input: nothing is rendered.
    let out = qjulia(
        dir.path(),
        &["render", "-o", "keep.png", "--set", "image.width=-3"],
    );
    assert_eq!(out.status.code(), Some(2));
    // An output that cannot be written fails the run after rendering: the others stay untouched.
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
            "-o",
            "keep.png",
            "--stats",
            "no/such/dir/s.json",
        ],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(error_line(&out).contains("no/such/dir/s.json"));
    assert_eq!(std::fs::read(&png).unwrap(), b"precious");
    assert_eq!(
        files_in(dir.path()),
        ["keep.png"],
        "temporary files were left behind"
    );
}

#[test]
fn a_png_carries_its_scene_and_renders_again_identically() {
    let dir = tempfile::tempdir().unwrap();
    let first = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "48",
            "--height",
            "40",
            "--set",
            "fractal.c=[-0.4, 0.6, 0.1, 0.0]",
            "-o",
            "a.png",
        ],
    );
    assert!(first.status.success(), "{}", stderr(&first));
    let again = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--scene",
            "a.png",
            "-o",
            "b.png",
        ],
    );
    assert!(again.status.success(), "{}", stderr(&again));
    let a = image::open(dir.path().join("a.png")).unwrap().to_rgb8();
    let b = image::open(dir.path().join("b.png")).unwrap().to_rgb8();
    assert_eq!((b.width(), b.height()), (48, 40));
    assert!(a == b, "the re-render differs");
    let scene = qjulia::scene::scene_from_png(&dir.path().join("b.png")).unwrap();
    assert!(scene.contains("c = [-0.4, 0.6, 0.1, 0.0]"), "{scene}");
}

#[test]
fn depth_steps_and_stats_outputs() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "20",
            "--height",
            "10",
            "--depth",
            "d.npy",
            "--steps",
            "s.npy",
            "--stats",
            "stats.json",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // --depth or --steps without -o: no PNG.
    assert_eq!(files_in(dir.path()), ["d.npy", "s.npy", "stats.json"]);
    for (name, descr) in [("d.npy", "'<f4'"), ("s.npy", "'<u4'")] {
        let bytes = std::fs::read(dir.path().join(name)).unwrap();
        assert_eq!(&bytes[..8], b"\x93NUMPY\x01\x00");
        let header_len = u16::from_le_bytes([bytes[8], bytes[9]]) as usize;
        assert_eq!((10 + header_len) % 64, 0);
        let header = std::str::from_utf8(&bytes[10..10 + header_len]).unwrap();
        assert!(
            header.contains(descr) && header.contains("'shape': (10, 20)"),
            "{header}"
        );
        assert_eq!(bytes.len(), 10 + header_len + 20 * 10 * 4);
    }
    let depth = std::fs::read(dir.path().join("d.npy")).unwrap();
    let values: Vec<f32> = depth[depth.len() - 800..]
        .chunks(4)
        .map(|c| f32::from_le_bytes([c[0], c[1], c[2], c[3]]))
        .collect();
    assert!(values.iter().any(|v| v.is_nan()) && values.iter().any(|v| v.is_finite()));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("stats.json")).unwrap())
            .unwrap();
    assert_eq!(stats["backend"], "cpu");
    assert_eq!(stats["adapter"], "cpu");
    assert_eq!(stats["precision"], "f32");
    assert_eq!(
        (stats["width"].as_u64(), stats["height"].as_u64()),
        (Some(20), Some(10))
    );
    assert!(stats["gpu_seconds"].is_null());
    for key in ["render_seconds", "hit_fraction", "steps_mean"] {
        assert!(stats[key].as_f64().is_some_and(f64::is_finite), "{key}");
    }
    assert!(stats["steps_max"].as_u64().is_some());
}

/// Runs the qjulia binary in `dir` with `args` and extra environment variables.
fn qjulia_env(dir: &std::path::Path, args: &[&str], env: &[(&str, &str)]) -> std::process::Output {
    let mut command = Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command.args(args).current_dir(dir);
    for (key, value) in env {
        command.env(key, value);
    }
    command.output().unwrap()
}

/// f64 runs on the CPU always, and on the GPU where the adapter passes the start-up check of f64
/// (lavapipe does); where it fails (a wrong division injected through the check's test hook),
/// `--backend gpu` exits 1 with one clear line and writes nothing, and `--backend auto` renders
/// on the CPU with a notice. Without SHADER_F64 (GL llvmpipe) the same.
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
    if std::env::var("QJULIA_SKIP_GPU_TESTS").is_ok_and(|v| v == "1") {
        eprintln!("f64 on the GPU: skipped because QJULIA_SKIP_GPU_TESTS=1");
        return;
    }
    let gpu = [&args[..], &["--backend", "gpu", "-o", "g.png"]].concat();
    let out = qjulia(dir.path(), &gpu);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(stats().contains("\"precision\": \"f64\"") && stats().contains("\"backend\": \"gpu\""));
    std::fs::remove_file(dir.path().join("g.png")).unwrap();
    let wrong_div = [("QJULIA_F64_CHECK_INJECT", "div")];
    let no_f64 = [("WGPU_BACKEND", "gl")];
    for (case, env, reason) in [
        ("a wrong division", &wrong_div, "div of ("),
        ("GL llvmpipe", &no_f64, ""),
    ] {
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

/// The scene a PNG written by qjulia carries, built.
fn scene_of(png: &Path) -> qjulia::Scene {
    let mut loader = qjulia::scene::SceneLoader::new();
    loader.file(png).unwrap();
    loader.build().unwrap()
}

#[test]
fn a_preset_is_layered_after_the_defaults_and_before_everything_else() {
    let dir = tempfile::tempdir().unwrap();
    // The basilica preset: c = -1, 16 iterations, eye (0.4, 2.2, 2.2), light (1, 3, 2).
    std::fs::write(
        dir.path().join("s.toml"),
        "[fractal]\nmax_iterations = 12\n[image]\nwidth = 8\n",
    )
    .unwrap();
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--preset",
            "basilica",
            "--scene",
            "s.toml",
            "--height",
            "6",
            "--set",
            "light.position=[0, 0, 4]",
            "-o",
            "a.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let scene = scene_of(&dir.path().join("a.png"));
    assert_eq!(scene.fractal.c, [-1.0, 0.0, 0.0, 0.0], "from the preset");
    assert_eq!(scene.camera.eye, [0.4, 2.2, 2.2], "from the preset");
    assert_eq!(scene.fractal.max_iterations, 12, "the file over the preset");
    assert_eq!((scene.image.width, scene.image.height), (8, 6));
    assert_eq!(
        scene.light.position,
        [0.0, 0.0, 4.0],
        "--set over the preset"
    );
    assert_eq!(
        scene.fractal.epsilon, 0.003,
        "the default where no layer sets it"
    );
    // Every preset renders from the command line, each to its own scene.
    for p in qjulia::scene::presets::PRESETS {
        let name = format!("{}.png", p.slug);
        let out = qjulia(
            dir.path(),
            &[
                "render",
                "--backend",
                "cpu",
                "--preset",
                p.slug,
                "--width",
                "4",
                "--height",
                "4",
                "-o",
                &name,
            ],
        );
        assert!(out.status.success(), "{}: {}", p.slug, stderr(&out));
        let mut scene = scene_of(&dir.path().join(&name));
        let mut want = p.scene();
        (want.image.width, want.image.height) = (4, 4);
        scene.image = want.image.clone();
        assert_eq!(scene, want, "{}", p.slug);
    }
}

#[test]
fn an_unknown_preset_exits_2_listing_the_names() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(dir.path(), &["render", "--preset", "Seed", "-o", "x.png"]);
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let line = error_line(&out);
    assert!(line.starts_with("error: --preset Seed: "), "{line}");
    for p in qjulia::scene::presets::PRESETS {
        assert!(line.contains(p.slug), "{line} does not list {}", p.slug);
    }
    assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
    assert!(files_in(dir.path()).is_empty());
}

#[test]
fn info_lists_the_presets() {
    let dir = tempfile::tempdir().unwrap();
    let out = qjulia(dir.path(), &["info"]);
    let text = String::from_utf8_lossy(&out.stdout);
    for p in qjulia::scene::presets::PRESETS {
        assert!(
            text.lines()
                .any(|l| l.trim_start().starts_with(&format!("{} ", p.slug))
                    && l.trim_end().ends_with(p.about)),
            "{} missing from:\n{text}",
            p.slug
        );
    }
}

#[test]
fn overlong_scene_text_is_refused_before_it_is_read_whole() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // A scene file of 2 MiB (comments), a --set of 100 KB, and a PNG whose compressed scene
    // chunk inflates to 16 MiB (a few KB on disk).
    let mut long = String::from("[fractal]\nepsilon = 0.01\n");
    while long.len() < 2 << 20 {
        long.push_str("# a comment to make the file long, long, long, long, long, long\n");
    }
    std::fs::write(d.join("long.toml"), &long).unwrap();
    let bomb = {
        use png::text_metadata::EncodableTextChunk;
        let mut bytes = Vec::new();
        let mut encoder = png::Encoder::new(&mut bytes, 1, 1);
        encoder.set_color(png::ColorType::Rgb);
        let mut writer = encoder.write_header().unwrap();
        // The compressed chunk, written by hand before the image data.
        let mut chunk = png::text_metadata::ITXtChunk::new(
            qjulia::scene::SCENE_PNG_KEYWORD,
            " ".repeat(16 << 20),
        );
        chunk.compressed = true;
        let mut encoded = Vec::new();
        chunk.encode(&mut encoded).unwrap();
        writer
            .write_chunk(
                png::chunk::ChunkType(*b"iTXt"),
                &encoded[8..encoded.len() - 4],
            )
            .unwrap();
        writer.write_image_data(&[0, 0, 0]).unwrap();
        writer.finish().unwrap();
        bytes
    };
    assert!(bomb.len() < 100_000, "{} bytes", bomb.len());
    std::fs::write(d.join("bomb.png"), &bomb).unwrap();
    let big_set = format!("fractal.c=[{}]", "0.0, ".repeat(20_000));
    let cases: [(&[&str], &str); 3] = [
        (
            &["--scene", "long.toml"],
            "long.toml: the scene is longer than a scene may be (1048576 bytes)",
        ),
        (&["--set", &big_set], "more than a --set may be (65536)"),
        (
            &["--scene", "bomb.png"],
            "bomb.png: its qjulia-scene chunk inflates to more than a scene may be (1048576 bytes)",
        ),
    ];
    for (args, expected) in cases {
        let mut all = vec!["render", "-o", "x.png"];
        all.extend_from_slice(args);
        let out = qjulia(d, &all);
        assert_eq!(out.status.code(), Some(2), "{expected}: {}", stderr(&out));
        let line = error_line(&out);
        assert!(line.contains(expected), "expected {expected:?} in {line:?}");
        assert!(line.len() < 300, "a long line: {line}");
        assert!(!d.join("x.png").exists());
    }
}

/// Runs qjulia in `dir` with `QJULIA_MEMORY_LIMIT` (bytes) set.
fn qjulia_with_memory(dir: &Path, limit: u64, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(args)
        .current_dir(dir)
        .env("QJULIA_MEMORY_LIMIT", limit.to_string())
        .output()
        .expect("run qjulia")
}

#[test]
fn a_whole_image_job_that_would_not_fit_is_refused_before_it_starts() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    // 64x64 pixels: the EXR alone holds 52 bytes a pixel (212,992 bytes); 100,000 are allowed.
    let size = ["--width", "64", "--height", "64"];
    let cases: [(&[&str], &str); 4] = [
        (
            &["--hdr", "x.exr"],
            "--hdr's 64x64 image would need 212992 bytes (208.0 KiB) of memory, more than the \
             100000 bytes (97.7 KiB) available",
        ),
        (
            &["-o", "x.png", "--set", "image.denoise=\"atrous\""],
            "the denoised 64x64 image would need 589824 bytes",
        ),
        (
            &["-o", "x.png", "--view", "steps"],
            "the 64x64 heat map would need 278528 bytes",
        ),
        (
            &["--tile", "0/2", "--hdr", "x.exr"],
            "tile 0/2's 64x32 rows would need 245760 bytes",
        ),
    ];
    for (args, expected) in cases {
        let mut all = vec!["render", "--backend", "cpu"];
        all.extend_from_slice(&size);
        all.extend_from_slice(args);
        let out = qjulia_with_memory(d, 100_000, &all);
        assert_eq!(out.status.code(), Some(2), "{expected}: {}", stderr(&out));
        let line = error_line(&out);
        assert!(line.contains(expected), "expected {expected:?} in {line:?}");
        assert!(files_in(d).is_empty(), "{args:?} wrote {:?}", files_in(d));
    }
    // A streamed PNG holds a band at a time: never refused.
    let out = qjulia_with_memory(
        d,
        100_000,
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "64",
            "--height",
            "64",
            "-o",
            "x.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    // merge: the whole image of its parts.
    for k in 0..2 {
        let tile = format!("{k}/2");
        let part = format!("part{k}.exr");
        let out = qjulia(
            d,
            &[
                "render",
                "--backend",
                "cpu",
                "--width",
                "64",
                "--height",
                "64",
                "--tile",
                &tile,
                "--hdr",
                &part,
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
    }
    let out = qjulia_with_memory(
        d,
        100_000,
        &["merge", "part0.exr", "part1.exr", "-o", "merged.png"],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    let line = error_line(&out);
    assert!(
        line.contains("would need") && line.contains("bytes"),
        "{line}"
    );
    assert!(!d.join("merged.png").exists());
}

#[test]
fn an_error_quoting_what_was_typed_is_one_line() {
    let dir = tempfile::tempdir().unwrap();
    // A newline and an escape character typed into the arguments (fuzz/regressions/).
    let cases: [(&[&str], &str); 2] = [
        (
            &["render", "--set", "fractal.c\nx=1"],
            "--set fractal.c\\nx=1",
        ),
        (
            &["mesh", "--box", "0,0,0\n\u{1b},1,1,1"],
            "--box 0,0,0\\n\\u{1b},1,1,1",
        ),
    ];
    for (args, expected) in cases {
        let out = qjulia(dir.path(), args);
        assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
        assert_eq!(stderr(&out).lines().count(), 1, "{}", stderr(&out));
        assert!(error_line(&out).contains(expected), "{}", stderr(&out));
    }
}
