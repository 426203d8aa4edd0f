//! Where a scene comes from and what it may cost: presets layered after the defaults, `info`'s
//! list, scene text too long, whole-image jobs that would not fit in memory, and errors that quote
//! what was typed.

use std::path::Path;
use std::process::{Command, Output};

use super::error_line;
use crate::common::{files_in, qjulia, stderr};

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
            "--hdr's 64x64 image would need 327680 bytes (320.0 KiB) of memory, more than the \
             100000 bytes (97.7 KiB) available",
        ),
        (
            &["-o", "x.png", "--set", "image.denoise=\"atrous\""],
            "the denoised 64x64 image would need 655360 bytes",
        ),
        (
            &["-o", "x.png", "--view", "steps"],
            "the 64x64 heat map would need 344064 bytes",
        ),
        (
            &["--tile", "0/2", "--hdr", "x.exr"],
            "tile 0/2's 64x32 rows would need 335872 bytes",
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
