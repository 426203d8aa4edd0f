//! Faults, each a test: a full disk (a 64 KiB tmpfs) under `render` and `animate`: one line
//! naming the file and the reason once, exit 1, nothing under a final name that is not whole,
//! the complete frames kept, no staged file left. Mounting needs root: elsewhere the tests say
//! they skipped, except under CI (`QJULIA_CI=1`), where they fail.

use std::path::{Path, PathBuf};

use crate::common;
use std::process::{Command, Output};

/// A small tmpfs, unmounted when dropped.
struct FullDisk {
    dir: tempfile::TempDir,
}

impl FullDisk {
    fn mount(name: &str) -> Option<Self> {
        let dir = tempfile::tempdir().unwrap();
        let ok = Command::new("mount")
            .args(["-t", "tmpfs", "-o", "size=64k", "tmpfs"])
            .arg(dir.path())
            .output()
            .is_ok_and(|o| o.status.success());
        if !ok {
            common::skip_outside_ci(name, "a full disk", "cannot mount a tmpfs: needs root");
            return None;
        }
        Some(Self { dir })
    }

    fn path(&self) -> &Path {
        self.dir.path()
    }
}

impl Drop for FullDisk {
    fn drop(&mut self) {
        let _ = Command::new("umount").arg(self.dir.path()).status();
    }
}

fn qjulia(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(args)
        .current_dir(dir)
        .output()
        .unwrap()
}

/// Every file under `dir`, by name.
fn names(dir: &Path) -> Vec<String> {
    let mut v: Vec<String> = std::fs::read_dir(dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    v.sort();
    v
}

/// The one line of a failure for lack of space, naming `file`.
fn assert_one_line_of_no_space(out: &Output, file: &str) {
    assert_eq!(out.status.code(), Some(1));
    let stderr = String::from_utf8_lossy(&out.stderr);
    let lines: Vec<&str> = stderr
        .lines()
        .filter(|l| !l.starts_with("qjulia: "))
        .collect();
    assert_eq!(lines.len(), 1, "{stderr}");
    assert!(
        lines[0].starts_with("error: ") && lines[0].contains(file),
        "{stderr}"
    );
    assert_eq!(
        lines[0].matches("No space left on device").count(),
        1,
        "the reason once: {stderr}"
    );
}

#[test]
fn a_full_disk_under_render_writes_nothing() {
    let Some(disk) = FullDisk::mount("render on a full disk") else {
        return;
    };
    let out = qjulia(
        disk.path(),
        &[
            "render",
            "--backend",
            "cpu",
            "--width",
            "640",
            "--height",
            "640",
            "-o",
            "a.png",
        ],
    );
    assert_one_line_of_no_space(&out, "a.png");
    assert_eq!(names(disk.path()), Vec::<String>::new());
}

/// 24 frames of about 7 KB each into `frames`.
const ANIMATE: &[&str] = &[
    "animate",
    "--preset",
    "rabbit",
    "--set",
    "animation.frames=24",
    "--backend",
    "cpu",
    "--width",
    "64",
    "--height",
    "64",
    "--out",
    "frames",
];

#[test]
fn a_full_disk_under_animate_keeps_the_complete_frames() {
    let Some(disk) = FullDisk::mount("animate on a full disk") else {
        return;
    };
    // Frames of about 7 KB: the disk holds some, not all.
    let frames = disk.path().join("frames");
    let out = qjulia(disk.path(), ANIMATE);
    assert_one_line_of_no_space(&out, "frame-");
    let kept = names(&frames);
    assert!(!kept.is_empty() && kept.len() < 24, "{kept:?}");
    // Each frame kept is whole: the same bytes a render of it elsewhere writes.
    let elsewhere = tempfile::tempdir().unwrap();
    let whole = qjulia(elsewhere.path(), ANIMATE);
    assert!(whole.status.success());
    for name in &kept {
        assert!(
            name.starts_with("frame-") && name.ends_with(".png"),
            "{name} left"
        );
        let a: PathBuf = frames.join(name);
        let b = elsewhere.path().join("frames").join(name);
        assert!(
            std::fs::read(a).unwrap() == std::fs::read(b).unwrap(),
            "{name} is not whole"
        );
    }
}
