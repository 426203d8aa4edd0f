//! `qjulia animate` through the binary (docs/CONTRACT.md's additions): frames in any split are
//! byte-identical, `--resume` completes an interrupted run with the same bytes, bad ranges exit 2
//! with nothing written, each frame's PNG renders again to the same bytes, complete frames stay
//! when a later one fails, and `--stats` has its fields. Small frames (48x32) of a six-frame
//! animation, on the CPU except for one GPU test.

use crate::common;

use std::path::Path;
use std::process::Output;

/// The test animation: six frames of 48x32 (c on its closed loop: no keyframe sets it).
const SCENE: &str = "[image]\nwidth = 48\nheight = 32\n\n[animation]\nframes = 6\n";

use crate::common::{files_in, qjulia, qjulia_env, stderr};

/// A temporary folder holding the test animation as `anim.toml`.
fn with_scene() -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("anim.toml"), SCENE).unwrap();
    dir
}

/// Runs `animate --scene anim.toml --backend cpu` with `args`; panics when it fails.
fn animate_cpu(dir: &Path, args: &[&str]) -> Output {
    let out = qjulia(
        dir,
        &[
            &["animate", "--scene", "anim.toml", "--backend", "cpu"],
            args,
        ]
        .concat(),
    );
    assert!(out.status.success(), "animate {args:?}: {}", stderr(&out));
    out
}

fn frame_names(frames: std::ops::RangeInclusive<u32>) -> Vec<String> {
    frames.map(|k| format!("frame-{k:05}.png")).collect()
}

/// Asserts that two folders hold the same files with the same bytes.
fn assert_same_files(a: &Path, b: &Path) {
    assert_eq!(files_in(a), files_in(b));
    for name in files_in(a) {
        assert!(
            std::fs::read(a.join(&name)).unwrap() == std::fs::read(b.join(&name)).unwrap(),
            "{name} differs between {} and {}",
            a.display(),
            b.display()
        );
    }
}

#[test]
fn frames_rendered_in_any_split_are_byte_identical() {
    let dir = with_scene();
    // One whole run into the default folder, qjulia-frames.
    animate_cpu(dir.path(), &[]);
    let whole = dir.path().join("qjulia-frames");
    assert_eq!(files_in(&whole), frame_names(0..=5));
    // The same frames in three pieces, out of order.
    for range in ["3..5", "0..0", "1..2"] {
        animate_cpu(dir.path(), &["--frames", range, "--out", "split"]);
    }
    assert_same_files(&whole, &dir.path().join("split"));
    // The animation moves: c goes round its loop, so the frames are not all the same picture.
    let first = std::fs::read(whole.join("frame-00000.png")).unwrap();
    let middle = std::fs::read(whole.join("frame-00003.png")).unwrap();
    assert_ne!(first, middle, "frames 0 and 3 of the loop are the same");
}

#[test]
fn resume_completes_an_interrupted_run_with_the_same_bytes() {
    let dir = with_scene();
    animate_cpu(dir.path(), &["--out", "whole"]);
    let (whole, resumed) = (dir.path().join("whole"), dir.path().join("resumed"));
    // An interrupted run: frames 0, 1 and 3 complete, a staged temporary file of the frame it
    // was on, and frame 4 left by another scene (stale: it must be rendered again).
    std::fs::create_dir(&resumed).unwrap();
    for name in frame_names(0..=1).into_iter().chain(frame_names(3..=3)) {
        std::fs::copy(whole.join(&name), resumed.join(&name)).unwrap();
    }
    // Staged temporaries a killed run left: one of the frame it was on (2, to be rendered
    // again: the resumed run removes it), and one of an output of another name, which it
    // leaves alone.
    std::fs::write(
        resumed.join(".frame-00002.png.qjulia-abc123.tmp"),
        b"half a frame",
    )
    .unwrap();
    std::fs::write(resumed.join(".other.png.qjulia-abc123.tmp"), b"not ours").unwrap();
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "48",
            "--height",
            "32",
            "-o",
            "resumed/frame-00004.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let kept = std::fs::metadata(resumed.join("frame-00001.png"))
        .unwrap()
        .modified()
        .unwrap();
    animate_cpu(
        dir.path(),
        &["--out", "resumed", "--resume", "--stats", "s.json"],
    );
    assert!(!resumed.join(".frame-00002.png.qjulia-abc123.tmp").exists());
    std::fs::remove_file(resumed.join(".other.png.qjulia-abc123.tmp")).unwrap();
    assert_same_files(&whole, &resumed);
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["frames"], 3, "frames 2, 4 and 5 rendered: {stats}");
    assert_eq!(stats["skipped"], 3, "frames 0, 1 and 3 kept: {stats}");
    let after = std::fs::metadata(resumed.join("frame-00001.png"))
        .unwrap()
        .modified()
        .unwrap();
    assert_eq!(kept, after, "a complete frame was written again");
    // Resuming a complete run renders nothing.
    animate_cpu(
        dir.path(),
        &["--out", "resumed", "--resume", "--stats", "s.json"],
    );
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(
        (&stats["frames"], &stats["skipped"]),
        (&0.into(), &6.into())
    );
}

#[test]
fn bad_ranges_exit_2_naming_frames_and_write_nothing() {
    let dir = with_scene();
    for range in [
        "5..2", "0..6", "6..6", "x", "3", "..3", "2..", "-1..2", "0...3", "0..=3", "",
    ] {
        let out = qjulia(
            dir.path(),
            &[
                "animate",
                "--scene",
                "anim.toml",
                "--backend",
                "cpu",
                &format!("--frames={range}"),
                "--stats",
                "s.json",
            ],
        );
        assert_eq!(
            out.status.code(),
            Some(2),
            "--frames {range}: {}",
            stderr(&out)
        );
        let text = stderr(&out);
        let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("error: ")).collect();
        assert_eq!(errors.len(), 1, "--frames {range}: {text}");
        assert!(
            errors[0].starts_with(&format!("error: --frames {range}: ")),
            "{}",
            errors[0]
        );
        assert_eq!(files_in(dir.path()), ["anim.toml"], "--frames {range}");
    }
    // A bad scene key is today's one-line error, and nothing is written either.
    let out = qjulia(
        dir.path(),
        &[
            "animate",
            "--scene",
            "anim.toml",
            "--set",
            "fractal.colour=1",
        ],
    );
    assert_eq!(out.status.code(), Some(2), "{}", stderr(&out));
    assert!(stderr(&out).contains("fractal.colour"), "{}", stderr(&out));
    assert_eq!(files_in(dir.path()), ["anim.toml"]);
}

#[test]
fn each_frame_renders_again_to_the_same_bytes() {
    let dir = with_scene();
    animate_cpu(dir.path(), &["--frames", "0..5"]);
    for k in 0..=5 {
        let name = format!("qjulia-frames/frame-{k:05}.png");
        let text = qjulia::scene::scene_from_png(&dir.path().join(&name)).unwrap();
        assert!(!text.contains("animation"), "{name} carries [animation]");
        let out = qjulia(
            dir.path(),
            &[
                "render",
                "--scene",
                &name,
                "--backend",
                "cpu",
                "-o",
                "again.png",
            ],
        );
        assert!(out.status.success(), "{}", stderr(&out));
        assert!(
            std::fs::read(dir.path().join(&name)).unwrap()
                == std::fs::read(dir.path().join("again.png")).unwrap(),
            "render --scene {name} gives other bytes"
        );
    }
    // A heat-map view too (rendered whole, with its legend strip).
    animate_cpu(
        dir.path(),
        &["--frames", "2..2", "--view", "steps", "--out", "v"],
    );
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--scene",
            "v/frame-00002.png",
            "--backend",
            "cpu",
            "-o",
            "again.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let img = image::open(dir.path().join("v/frame-00002.png")).unwrap();
    assert!(img.height() > 32, "the steps view has its legend strip");
    assert!(
        std::fs::read(dir.path().join("v/frame-00002.png")).unwrap()
            == std::fs::read(dir.path().join("again.png")).unwrap()
    );
}

#[test]
fn complete_frames_stay_when_a_later_one_fails() {
    let dir = with_scene();
    // Frame 2 cannot be renamed into place: a folder holds its name.
    std::fs::create_dir_all(dir.path().join("qjulia-frames/frame-00002.png")).unwrap();
    let out = qjulia(
        dir.path(),
        &["animate", "--scene", "anim.toml", "--backend", "cpu"],
    );
    assert_eq!(out.status.code(), Some(1), "{}", stderr(&out));
    assert!(stderr(&out).contains("frame-00002.png"), "{}", stderr(&out));
    // The error is the writer's own (the file it could not write), not a queue found closed.
    assert!(!stderr(&out).contains("stopped"), "{}", stderr(&out));
    // Frames 0 and 1 are there, whole; no temporary file is left behind. Later frames, which
    // the pipeline may have rendered while frame 2 was being written, are whole where present.
    let names = files_in(&dir.path().join("qjulia-frames"));
    assert!(names.starts_with(&frame_names(0..=2)), "{names:?}");
    for name in names.iter().filter(|n| *n != "frame-00002.png") {
        assert!(frame_names(0..=5).contains(name), "{names:?}");
        let img = image::open(dir.path().join("qjulia-frames").join(name)).unwrap();
        assert_eq!((img.width(), img.height()), (48, 32), "{name}");
    }
}

#[test]
fn stats_record_frames_seconds_rate_and_backend() {
    let dir = with_scene();
    animate_cpu(dir.path(), &["--frames", "1..4", "--stats", "s.json"]);
    let stats: serde_json::Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("s.json")).unwrap()).unwrap();
    assert_eq!(stats["frames"], 4);
    assert_eq!(stats["skipped"], 0);
    assert_eq!((&stats["first"], &stats["last"]), (&1.into(), &4.into()));
    let seconds = stats["seconds"].as_f64().unwrap();
    let fps = stats["frames_per_second"].as_f64().unwrap();
    assert!(seconds > 0.0, "{stats}");
    assert!(
        (fps - 4.0 / seconds).abs() <= 1e-9 * fps,
        "frames_per_second is frames / seconds: {stats}"
    );
    let render_seconds = stats["render_seconds"].as_f64().unwrap();
    assert!(render_seconds > 0.0 && render_seconds <= seconds, "{stats}");
    assert_eq!(stats["backend"], "cpu");
    assert_eq!(stats["adapter"], "cpu");
    assert_eq!(stats["precision"], "f32");
    assert_eq!(
        (&stats["width"], &stats["height"]),
        (&48.into(), &32.into())
    );
    // The stats file is the only other thing written.
    assert_eq!(
        files_in(dir.path()),
        ["anim.toml", "qjulia-frames", "s.json"]
    );
}

#[test]
fn gpu_frames_are_the_same_in_any_split_and_render_again() {
    if common::gpu("gpu_frames_are_the_same_in_any_split_and_render_again").is_none() {
        return;
    }
    let dir = with_scene();
    let gpu = |args: &[&str]| {
        let out = qjulia(
            dir.path(),
            &[
                &["animate", "--scene", "anim.toml", "--backend", "gpu"],
                args,
            ]
            .concat(),
        );
        assert!(out.status.success(), "animate {args:?}: {}", stderr(&out));
    };
    gpu(&["--frames", "0..2", "--out", "whole", "--stats", "s.json"]);
    gpu(&["--frames", "2..2", "--out", "split"]);
    gpu(&["--frames", "0..1", "--out", "split"]);
    assert_same_files(&dir.path().join("whole"), &dir.path().join("split"));
    // Frames of four bands each (8 rows of 48 pixels): the stream keeps two bands on the
    // device, across frames, and must put each back in its own frame.
    let out = qjulia_env(
        dir.path(),
        &[
            "animate",
            "--scene",
            "anim.toml",
            "--backend",
            "gpu",
            "--frames",
            "0..2",
            "--out",
            "banded",
        ],
        &[("QJULIA_BAND_PIXELS", "400")],
    );
    assert!(out.status.success(), "banded: {}", stderr(&out));
    assert_same_files(&dir.path().join("whole"), &dir.path().join("banded"));
    let stats = std::fs::read_to_string(dir.path().join("s.json")).unwrap();
    assert!(stats.contains("\"backend\": \"gpu\""), "{stats}");
    let out = qjulia(
        dir.path(),
        &[
            "render",
            "--scene",
            "whole/frame-00001.png",
            "--backend",
            "gpu",
            "-o",
            "again.png",
        ],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        std::fs::read(dir.path().join("whole/frame-00001.png")).unwrap()
            == std::fs::read(dir.path().join("again.png")).unwrap()
    );
}

#[test]
fn the_default_animation_starts_at_the_default_render() {
    let dir = tempfile::tempdir().unwrap();
    let size = ["--width", "48", "--height", "32", "--backend", "cpu"];
    let out = qjulia(
        dir.path(),
        &[&["animate", "--frames", "0..1"], &size[..]].concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let out = qjulia(
        dir.path(),
        &[&["render", "-o", "r.png"], &size[..]].concat(),
    );
    assert!(out.status.success(), "{}", stderr(&out));
    let render = std::fs::read(dir.path().join("r.png")).unwrap();
    // c's loop starts exactly at the scene's c: frame 0 is the scene itself, and then c moves.
    assert!(std::fs::read(dir.path().join("qjulia-frames/frame-00000.png")).unwrap() == render);
    assert!(std::fs::read(dir.path().join("qjulia-frames/frame-00001.png")).unwrap() != render);
}

#[test]
fn frame_count_prints_the_count_and_writes_nothing() {
    let dir = with_scene();
    let out = animate_cpu(dir.path(), &["--frame-count"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "6\n");
    let out = animate_cpu(
        dir.path(),
        &["--frame-count", "--set", "animation.frames=250"],
    );
    assert_eq!(String::from_utf8_lossy(&out.stdout), "250\n");
    // The default animation: 120 frames.
    let out = qjulia(dir.path(), &["animate", "--frame-count"]);
    assert_eq!(String::from_utf8_lossy(&out.stdout), "120\n");
    assert_eq!(files_in(dir.path()), ["anim.toml"]);
}

#[test]
fn a_stopped_run_keeps_its_frames_and_writes_no_video() {
    use std::sync::atomic::{AtomicBool, Ordering};
    let dir = with_scene();
    let mut loader = qjulia::scene::SceneLoader::new();
    loader.file(&dir.path().join("anim.toml")).unwrap();
    let (base, animation) = loader.build_animated().unwrap();
    let mut planner = qjulia::Planner::new(qjulia::Backend::Cpu, qjulia::PrecisionChoice::F32);
    let stop = AtomicBool::new(false);
    let (out, video) = (dir.path().join("f"), dir.path().join("v.mp4"));
    let job = qjulia::animate::Job {
        base: &base,
        animation: &animation,
        range: qjulia::animate::FrameRange::all(animation.frames),
        out: Some(&out),
        resume: false,
        hdr: false,
        // Without ffmpeg the video never starts; the frames are what is checked then.
        video: qjulia::video::find_ffmpeg()
            .is_ok()
            .then_some(video.as_path()),
        stop: Some(&stop),
    };
    // Stop as soon as the first frame is written.
    let stats = qjulia::animate::run(&mut planner, &mut |_| {}, &job, &mut |p| {
        if let qjulia::animate::Progress::Frame { .. } = p {
            stop.store(true, Ordering::Relaxed);
        }
    })
    .expect("a stopped run is not an error");
    assert!(stats.stopped && stats.frames < 6, "{stats:?}");
    let names = files_in(&out);
    assert_eq!(names, frame_names(0..=(names.len() as u32 - 1)));
    assert_eq!(names.len() as u32, stats.frames);
    assert!(!video.exists(), "an incomplete video is not written");
    assert_eq!(files_in(dir.path()), ["anim.toml", "f"]);
}

/// Issue 35, item 8: `path.animated_seed` renders frame k with seed `path.seed + k`, so the
/// noise moves between the frames of a still scene (c held, `path_radius = 0`), its PNG's scene
/// says the seed, and the frames are the same bytes in any split.
#[test]
fn an_animated_seed_moves_the_noise_and_keeps_any_split() {
    let dir = tempfile::tempdir().unwrap();
    let scene = "[shading]\nmodel = \"path\"\n\n[image]\nwidth = 24\nheight = 16\nsamples = 2\n\n\
                 [path]\nseed = 7\nanimated_seed = true\n\n[animation]\nframes = 3\n\
                 path_radius = 0.0\n";
    std::fs::write(dir.path().join("anim.toml"), scene).unwrap();
    animate_cpu(dir.path(), &[]);
    let whole = dir.path().join("qjulia-frames");
    for range in ["2..2", "0..1"] {
        animate_cpu(dir.path(), &["--frames", range, "--out", "split"]);
    }
    assert_same_files(&whole, &dir.path().join("split"));
    let frame = |k: u32| std::fs::read(whole.join(format!("frame-{k:05}.png"))).unwrap();
    assert_ne!(
        frame(0),
        frame(1),
        "the noise did not move between frames 0 and 1"
    );
    let scene_of = |k: u32| {
        let mut loader = qjulia::scene::SceneLoader::new();
        let path = whole.join(format!("frame-{k:05}.png"));
        loader.file(&path).unwrap_or_else(|e| panic!("{e}"));
        loader.build().unwrap_or_else(|e| panic!("{e}"))
    };
    assert_eq!(scene_of(0).path.seed, 7);
    assert_eq!(scene_of(2).path.seed, 9);
}
