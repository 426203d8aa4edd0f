//! `render` as a user meets it: the default output, bad input (exit 2, nothing written), outputs
//! that survive a failed run, a PNG that carries its scene, and the depth, steps and stats outputs.

use super::error_line;
use crate::common::{files_in, qjulia, stderr};

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

/// The tEXt chunks of the PNG at `path`, keyword and text.
fn png_texts(path: &std::path::Path) -> Vec<(String, String)> {
    let decoder = png::Decoder::new(std::io::BufReader::new(std::fs::File::open(path).unwrap()));
    let mut reader = decoder.read_info().unwrap();
    let mut rgb = vec![0; reader.output_buffer_size().unwrap()];
    reader.next_frame(&mut rgb).unwrap();
    reader.finish().unwrap();
    let info = reader.info();
    info.uncompressed_latin1_text
        .iter()
        .map(|t| (t.keyword.clone(), t.text.clone()))
        .collect()
}

/// Issue 49, item 3: a path-traced PNG records its estimated error (`qjulia-error`, the stats'
/// figures to the last digit), a render to `image.target_error` also what stopped it; a phong
/// PNG, which has no estimate, records none.
#[test]
fn a_path_traced_png_records_its_estimated_error() {
    let dir = tempfile::tempdir().unwrap();
    let d = dir.path();
    let path = [
        "render",
        "--preset",
        "path-traced",
        "--width",
        "24",
        "--height",
        "24",
        "--backend",
        "cpu",
        "--set",
        "image.samples=64",
        "--set",
        "image.target_error=0.06",
        "-o",
        "path.png",
        "--stats",
        "path.json",
    ];
    let out = qjulia(d, &path);
    assert!(out.status.success(), "{}", stderr(&out));
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(d.join("path.json")).unwrap()).unwrap();
    let texts = png_texts(&d.join("path.png"));
    let (_, text) = texts
        .iter()
        .find(|(k, _)| k == qjulia::output::ERROR_PNG_KEYWORD)
        .expect("the error recorded");
    let recorded: toml::Table = text.parse().unwrap();
    for key in ["estimated_rmse", "estimated_relative_rmse"] {
        assert_eq!(recorded[key].as_float(), stats[key].as_f64(), "{key}");
    }
    assert_eq!(
        recorded["stopped_by"].as_str(),
        stats["stopped_by"].as_str()
    );
    let last = stats["target_passes"].as_array().unwrap().last().unwrap();
    assert_eq!(
        recorded["samples"].as_integer(),
        last["samples"].as_i64(),
        "{text}"
    );
    let out = qjulia(
        d,
        &[
            "render",
            "--width",
            "24",
            "--height",
            "24",
            "-o",
            "phong.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(png_texts(&d.join("phong.png")).is_empty());
}
