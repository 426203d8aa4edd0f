//! `qjulia animate --video`: H.264 in .mp4 and VP9 in .webm through ffmpeg, checked with
//! ffprobe (frame count, size, codec, pixel format); odd sizes padded to even; PNG frames only
//! with `--out`; `--resume` encodes the frames already on disk; without ffmpeg, exit 1 before
//! anything is rendered or written; a failing ffmpeg leaves no file. Where ffmpeg is missing the
//! tests skip, except under CI (`QJULIA_CI=1`, set by .ci/run), where they fail.

use crate::common;

use std::path::Path;
use std::process::Command;

use crate::common::{assert_refused, files_in, qjulia, stderr};

/// Six frames of 48x32 on the CPU (c on its closed loop).
const SCENE: &str = "[image]\nwidth = 48\nheight = 32\n\n[animation]\nframes = 6\n";

/// Whether ffmpeg and ffprobe are here; under CI their absence fails the test.
fn have_ffmpeg(test: &str) -> bool {
    let found = ["ffmpeg", "ffprobe"].iter().all(|tool| {
        Command::new(tool)
            .arg("-version")
            .output()
            .is_ok_and(|o| o.status.success())
    });
    if !found {
        common::skip_outside_ci(
            test,
            "the video",
            "ffmpeg/ffprobe not on PATH: apt-get install ffmpeg (.ci/run installs it)",
        );
    }
    found
}

fn with_scene(scene: &str) -> tempfile::TempDir {
    let dir = tempfile::tempdir().unwrap();
    std::fs::write(dir.path().join("anim.toml"), scene).unwrap();
    dir
}

fn animate(dir: &Path, args: &[&str]) -> std::process::Output {
    let base = ["animate", "--scene", "anim.toml", "--backend", "cpu"];
    qjulia(dir, &[&base[..], args].concat())
}

/// What ffprobe says of the video's first stream: codec, pixel format, width, height, and the
/// frames it decodes.
fn probe(path: &Path) -> (String, String, u32, u32, u32) {
    let out = Command::new("ffprobe")
        .args(["-v", "error", "-count_frames", "-select_streams", "v:0"])
        .args([
            "-show_entries",
            "stream=codec_name,pix_fmt,width,height,nb_read_frames",
        ])
        .args(["-of", "default=noprint_wrappers=1"])
        .arg(path)
        .output()
        .expect("run ffprobe");
    assert!(
        out.status.success(),
        "ffprobe {}: {}",
        path.display(),
        stderr(&out)
    );
    let text = String::from_utf8_lossy(&out.stdout).into_owned();
    let field = |name: &str| {
        text.lines()
            .find_map(|l| l.strip_prefix(&format!("{name}=")))
            .unwrap_or_else(|| panic!("ffprobe gave no {name}: {text}"))
            .to_string()
    };
    let number = |name: &str| field(name).parse::<u32>().expect("a number");
    (
        field("codec_name"),
        field("pix_fmt"),
        number("width"),
        number("height"),
        number("nb_read_frames"),
    )
}

#[test]
fn an_mp4_holds_every_frame_in_h264_yuv420p_and_no_pngs_without_out() {
    if !have_ffmpeg("mp4") {
        return;
    }
    let dir = with_scene(SCENE);
    let out = animate(dir.path(), &["--video", "a.mp4"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        probe(&dir.path().join("a.mp4")),
        ("h264".into(), "yuv420p".into(), 48, 32, 6)
    );
    // PNG frames only with --out; no temporary file left.
    assert_eq!(files_in(dir.path()), ["a.mp4", "anim.toml"]);
}

#[test]
fn a_webm_of_an_odd_size_is_padded_to_even_and_pngs_come_with_out() {
    if !have_ffmpeg("webm") {
        return;
    }
    let scene = SCENE
        .replace("width = 48", "width = 47")
        .replace("height = 32", "height = 33");
    let dir = with_scene(&scene);
    let out = animate(
        dir.path(),
        &["--frames", "1..4", "--video", "a.webm", "--out", "frames"],
    );
    assert!(out.status.success(), "{}", stderr(&out));
    assert_eq!(
        probe(&dir.path().join("a.webm")),
        ("vp9".into(), "yuv420p".into(), 48, 34, 4)
    );
    assert_eq!(
        files_in(&dir.path().join("frames")),
        [
            "frame-00001.png",
            "frame-00002.png",
            "frame-00003.png",
            "frame-00004.png"
        ]
    );
}

#[test]
fn resume_with_video_encodes_the_frames_on_disk() {
    if !have_ffmpeg("resume") {
        return;
    }
    let dir = with_scene(SCENE);
    let out = animate(dir.path(), &["--out", "f"]);
    assert!(out.status.success(), "{}", stderr(&out));
    let before: Vec<Vec<u8>> = files_in(&dir.path().join("f"))
        .iter()
        .map(|n| std::fs::read(dir.path().join("f").join(n)).unwrap())
        .collect();
    let out = animate(dir.path(), &["--out", "f", "--resume", "--video", "v.mp4"]);
    assert!(out.status.success(), "{}", stderr(&out));
    assert!(
        stderr(&out).contains("6 frames already complete, 0 to render"),
        "{}",
        stderr(&out)
    );
    assert_eq!(probe(&dir.path().join("v.mp4")).4, 6);
    let after: Vec<Vec<u8>> = files_in(&dir.path().join("f"))
        .iter()
        .map(|n| std::fs::read(dir.path().join("f").join(n)).unwrap())
        .collect();
    assert!(before == after, "the frames on disk are left as they were");
}

/// Runs `animate --video a.mp4` with `args` in `dir`, PATH set to `path` (where ffmpeg is
/// looked for).
fn animate_on_path(dir: &Path, path: &str, args: &[&str]) -> std::process::Output {
    Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(["animate", "--scene", "anim.toml", "--backend", "cpu"])
        .args(["--video", "a.mp4"])
        .args(args)
        .env("PATH", path)
        .current_dir(dir)
        .output()
        .unwrap()
}

#[test]
fn without_ffmpeg_it_exits_1_at_once_and_writes_nothing() {
    let dir = with_scene(SCENE);
    let empty = tempfile::tempdir().unwrap();
    let out = animate_on_path(
        dir.path(),
        &empty.path().display().to_string(),
        &["--out", "frames"],
    );
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    let lines: Vec<&str> = text.lines().collect();
    assert_eq!(lines.len(), 1, "one line: {text}");
    assert!(
        lines[0].contains("ffmpeg") && lines[0].contains("apt-get install ffmpeg"),
        "{text}"
    );
    assert_eq!(
        files_in(dir.path()),
        ["anim.toml"],
        "nothing rendered or written"
    );
}

#[test]
fn a_failing_ffmpeg_leaves_no_video() {
    // An "ffmpeg" that reads a little and fails: the run exits 1 and leaves no file, no
    // temporary file, while complete PNG frames stay.
    let dir = with_scene(SCENE);
    let bin = tempfile::tempdir().unwrap();
    let fake = bin.path().join("ffmpeg");
    std::fs::write(
        &fake,
        "#!/bin/sh\nhead -c 100 >/dev/null\necho 'fake ffmpeg: broken encoder' >&2\nexit 1\n",
    )
    .unwrap();
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        std::fs::set_permissions(&fake, std::fs::Permissions::from_mode(0o755)).unwrap();
    }
    let path = format!(
        "{}:{}",
        bin.path().display(),
        std::env::var("PATH").unwrap_or_default()
    );
    let out = animate_on_path(dir.path(), &path, &[]);
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    assert!(
        text.contains("broken encoder"),
        "ffmpeg's own reason: {text}"
    );
    assert_eq!(
        files_in(dir.path()),
        ["anim.toml"],
        "no video, no temporary file"
    );
}

#[test]
fn a_video_of_another_kind_is_refused() {
    let dir = with_scene(SCENE);
    assert_refused(
        dir.path(),
        &["animate", "--scene", "anim.toml", "--video", "a.gif"],
        "error: --video a.gif",
        ".mp4",
    );
}
