//! Faults, each a test: a GPU device lost in the middle of the work (the test hook
//! `QJULIA_FAULT_LOSE_DEVICE=N` destroys it once the Nth band is submitted, as a GPU reset or a
//! driver crash would). `render` exits 1 with one line and writes nothing; `animate` exits 1
//! with one line, its complete frames kept byte for byte, and `--resume` finishes the rest with
//! the bytes of an uninterrupted run. Both run on the GPU (`--backend gpu`): without an adapter
//! they fail, unless `QJULIA_SKIP_GPU_TESTS=1`.

use crate::common;

use std::path::Path;
use std::process::Output;

use crate::common::{files_in, gpu_skipped, stderr};

const LOST: &str = "error: GPU: the GPU device was lost (destroyed)";

/// qjulia in `dir`, with the device lost after `lose_after` bands (None: never), bands of 32x32
/// pixels.
fn qjulia(dir: &Path, lose_after: Option<u32>, args: &[&str]) -> Output {
    let mut command = std::process::Command::new(env!("CARGO_BIN_EXE_qjulia"));
    command
        .args(args)
        .current_dir(dir)
        .env("QJULIA_BAND_PIXELS", "1024")
        .env_remove("QJULIA_FAULT_LOSE_DEVICE");
    if let Some(n) = lose_after {
        command.env("QJULIA_FAULT_LOSE_DEVICE", n.to_string());
    }
    command.output().expect("run qjulia")
}

/// The run failed with exit 1 and one error line, the lost device's.
fn assert_lost(name: &str, out: &Output) {
    let err = stderr(out);
    assert_eq!(out.status.code(), Some(1), "{name}: {err}");
    let errors: Vec<&str> = err.lines().filter(|l| l.starts_with("error")).collect();
    assert_eq!(errors, [LOST], "{name}: {err}");
    assert!(!err.contains("panicked"), "{name}: {err}");
}

#[test]
fn a_lost_device_ends_render_with_one_line_and_no_file() {
    if gpu_skipped("a_lost_device_ends_render_with_one_line_and_no_file") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    let args = [
        "render",
        "--backend",
        "gpu",
        "--width",
        "64",
        "--height",
        "64",
        "--hdr",
        "a.exr",
        "-o",
        "a.png",
    ];
    // Uninterrupted, the render takes four bands: the device goes at the second.
    let whole = qjulia(dir.path(), None, &args);
    assert!(whole.status.success(), "{}", stderr(&whole));
    for f in ["a.png", "a.exr"] {
        std::fs::remove_file(dir.path().join(f)).unwrap();
    }
    let lost = qjulia(dir.path(), Some(2), &args);
    assert_lost("render", &lost);
    assert!(
        files_in(dir.path()).is_empty(),
        "{:?}",
        files_in(dir.path())
    );
}

#[test]
fn a_lost_device_ends_animate_with_its_complete_frames_kept() {
    if gpu_skipped("a_lost_device_ends_animate_with_its_complete_frames_kept") {
        return;
    }
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(
        dir.path().join("anim.toml"),
        "[image]\nwidth = 32\nheight = 32\n\n[animation]\nframes = 6\n",
    )
    .unwrap();
    let args = |out: &str| {
        [
            "animate",
            "--backend",
            "gpu",
            "--scene",
            "anim.toml",
            "--out",
            out,
        ]
        .map(str::to_string)
    };
    let run = |lose: Option<u32>, out: &str, extra: &[&str]| {
        let mut a: Vec<String> = args(out).to_vec();
        a.extend(extra.iter().map(|s| s.to_string()));
        let a: Vec<&str> = a.iter().map(String::as_str).collect();
        qjulia(dir.path(), lose, &a)
    };
    let whole = run(None, "whole", &[]);
    assert!(whole.status.success(), "{}", stderr(&whole));
    let frames = files_in(&dir.path().join("whole"));
    assert_eq!(frames.len(), 6, "{frames:?}");
    // One band a frame: the device goes while frame 3 renders, after frames 0-2 are written.
    let lost = run(Some(4), "lost", &[]);
    assert_lost("animate", &lost);
    let kept = files_in(&dir.path().join("lost"));
    assert_eq!(kept, frames[..3], "the complete frames, and nothing else");
    for f in &kept {
        common::assert_same_file(
            f,
            &dir.path().join("whole").join(f),
            &dir.path().join("lost").join(f),
        );
    }
    let resumed = run(None, "lost", &["--resume"]);
    assert!(resumed.status.success(), "{}", stderr(&resumed));
    assert_eq!(files_in(&dir.path().join("lost")), frames);
    for f in &frames {
        common::assert_same_file(
            f,
            &dir.path().join("whole").join(f),
            &dir.path().join("lost").join(f),
        );
    }
}
