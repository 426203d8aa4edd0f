//! Faults, each a test: `kill -9` at spread-out moments of `render`, `animate`, `mesh` and
//! `merge` (56 kills in all), and ffmpeg killed in the middle of a video. After every kill no
//! file under a final name is partial: each is absent or byte for byte the uninterrupted run's.
//! A rerun (`animate --resume` for animate) then completes with the same bytes and leaves no
//! staged `.qjulia-*.tmp` file. The CPU backend keeps the runs short and their bytes fixed.

use std::path::{Path, PathBuf};

use crate::common;
use std::process::{Command, Output};
use std::time::{Duration, Instant};

fn qjulia(dir: &Path, args: &[&str]) -> Output {
    Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args(args)
        .current_dir(dir)
        .output()
        .expect("run qjulia")
}

fn stderr(out: &Output) -> String {
    String::from_utf8_lossy(&out.stderr).into_owned()
}

/// Every file under `dir` (recursively), by its path relative to `dir`, sorted.
fn files(dir: &Path) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut stack = vec![dir.to_path_buf()];
    while let Some(d) = stack.pop() {
        for entry in std::fs::read_dir(&d).unwrap() {
            let path = entry.unwrap().path();
            if path.is_dir() {
                stack.push(path);
            } else {
                out.push(path.strip_prefix(dir).unwrap().to_path_buf());
            }
        }
    }
    out.sort();
    out
}

/// A staged file: `.NAME.qjulia-XXXXXX.tmp`.
fn is_staged(path: &Path) -> bool {
    let name = path.file_name().unwrap().to_string_lossy();
    name.starts_with('.') && name.contains(".qjulia-") && name.ends_with(".tmp")
}

/// A command to kill, the files it writes that must be whole (by their final names), and how
/// it is completed after a kill.
struct Job {
    name: &'static str,
    args: Vec<String>,
    /// The final names compared with the uninterrupted run's bytes (the stats, which hold times,
    /// are left out).
    outputs: Vec<&'static str>,
    /// Arguments added to the rerun after a kill (`--resume`).
    rerun_extra: Vec<String>,
    /// Files the job reads, copied into each run's folder first.
    inputs: Vec<(String, Vec<u8>)>,
}

impl Job {
    fn args(&self) -> Vec<&str> {
        self.args.iter().map(String::as_str).collect()
    }

    fn prepare(&self) -> tempfile::TempDir {
        let dir = tempfile::tempdir().unwrap();
        for (name, bytes) in &self.inputs {
            std::fs::write(dir.path().join(name), bytes).unwrap();
        }
        dir
    }

    /// The uninterrupted run: its outputs' bytes and how long it took.
    fn reference(&self) -> (Vec<(PathBuf, Vec<u8>)>, Duration) {
        let dir = self.prepare();
        let start = Instant::now();
        let out = qjulia(dir.path(), &self.args());
        let took = start.elapsed();
        assert!(out.status.success(), "{}: {}", self.name, stderr(&out));
        let bytes = self.outputs_in(dir.path());
        assert!(!bytes.is_empty(), "{}: no outputs", self.name);
        (bytes, took)
    }

    /// The outputs present in `dir` (frames by their pattern), with their bytes.
    fn outputs_in(&self, dir: &Path) -> Vec<(PathBuf, Vec<u8>)> {
        files(dir)
            .into_iter()
            .filter(|p| !is_staged(p))
            .filter(|p| {
                let name = p.to_string_lossy();
                self.outputs.iter().any(|o| match o.strip_suffix('*') {
                    Some(prefix) => name.starts_with(prefix),
                    None => name == *o,
                })
            })
            .map(|p| {
                let bytes = std::fs::read(dir.join(&p)).unwrap();
                (p, bytes)
            })
            .collect()
    }
}

/// What a sweep saw: kills, and those that left a staged file (killed while writing) or some
/// but not all outputs.
#[derive(Default, Debug)]
struct Sweep {
    kills: u32,
    staged_left: u32,
    partial_runs: u32,
}

/// Kills `job` `kills` times, at moments spread evenly over its uninterrupted run's duration
/// (and a little jitter), checking each time what is left and that a rerun completes it.
fn sweep(job: &Job, kills: u32) -> Sweep {
    let (reference, took) = job.reference();
    let mut seen = Sweep::default();
    let mut jitter: u64 = 0x9e37_79b9_7f4a_7c15;
    for k in 0..kills {
        jitter = jitter
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        let fraction =
            (f64::from(k) + (jitter >> 11) as f64 / (1u64 << 53) as f64) / f64::from(kills);
        let delay = took.mul_f64(fraction);
        let dir = job.prepare();
        let mut child = Command::new(env!("CARGO_BIN_EXE_qjulia"))
            .args(job.args())
            .current_dir(dir.path())
            .stdout(std::process::Stdio::null())
            .stderr(std::process::Stdio::null())
            .spawn()
            .unwrap();
        std::thread::sleep(delay);
        let _ = child.kill(); // SIGKILL
        let _ = child.wait();
        seen.kills += 1;
        let context = format!("{} killed after {delay:?} (of {took:?})", job.name);
        // Whatever is under a final name is the uninterrupted run's, byte for byte.
        let left = job.outputs_in(dir.path());
        for (path, bytes) in &left {
            let expected = reference.iter().find(|(p, _)| p == path);
            let (_, expected) = expected.unwrap_or_else(|| panic!("{context}: {path:?}?"));
            assert!(
                bytes == expected,
                "{context}: {path:?} is partial or different"
            );
        }
        if files(dir.path()).iter().any(|p| is_staged(p)) {
            seen.staged_left += 1;
        }
        if !left.is_empty() && left.len() < reference.len() {
            seen.partial_runs += 1;
        }
        // The rerun completes it, to the same bytes, and removes the staged files.
        let mut args = job.args();
        args.extend(job.rerun_extra.iter().map(String::as_str));
        let out = qjulia(dir.path(), &args);
        assert!(out.status.success(), "{context}: rerun: {}", stderr(&out));
        assert!(
            job.outputs_in(dir.path()) == reference,
            "{context}: the rerun's bytes differ"
        );
        let staged: Vec<PathBuf> = files(dir.path())
            .into_iter()
            .filter(|p| is_staged(p))
            .collect();
        assert!(staged.is_empty(), "{context}: the rerun left {staged:?}");
    }
    eprintln!("{}: {seen:?}", job.name);
    seen
}

fn strings(args: &[&str]) -> Vec<String> {
    args.iter().map(|s| s.to_string()).collect()
}

#[test]
fn kill_9_at_any_moment_leaves_nothing_partial_and_a_rerun_completes_it() {
    let cpu = ["--backend", "cpu"];
    let render = Job {
        name: "render",
        args: strings(
            &[
                &["render"],
                &cpu[..],
                &["--width", "320", "--height", "320"],
            ]
            .concat(),
        )
        .into_iter()
        .chain(strings(&[
            "-o",
            "out.png",
            "--hdr",
            "out.exr",
            "--steps",
            "steps.npy",
        ]))
        .collect(),
        outputs: vec!["out.png", "out.exr", "steps.npy"],
        rerun_extra: vec![],
        inputs: vec![],
    };
    let animate = Job {
        name: "animate",
        args: strings(&[&["animate"], &cpu[..], &["--width", "64", "--height", "64"]].concat())
            .into_iter()
            .chain(strings(&[
                "--set",
                "animation.frames=16",
                "--out",
                "frames",
                "--hdr",
            ]))
            .collect(),
        outputs: vec!["frames/frame-*"],
        rerun_extra: strings(&["--resume"]),
        inputs: vec![],
    };
    let mesh = Job {
        name: "mesh",
        args: strings(&[&["mesh"], &cpu[..], &["--resolution", "128"]].concat())
            .into_iter()
            .chain(strings(&["-o", "set.ply"]))
            .collect(),
        outputs: vec!["set.ply"],
        rerun_extra: vec![],
        inputs: vec![],
    };
    // merge's parts, rendered once.
    let parts = tempfile::tempdir().unwrap();
    let mut inputs = Vec::new();
    for k in 0..2 {
        let tile = format!("{k}/2");
        let part = format!("part{k}.exr");
        let out = qjulia(
            parts.path(),
            &[
                &["render"],
                &cpu[..],
                &["--width", "512", "--height", "512"],
            ]
            .concat()
            .into_iter()
            .chain(["--tile", &tile, "--hdr", &part])
            .collect::<Vec<_>>(),
        );
        assert!(out.status.success(), "{}", stderr(&out));
        inputs.push((
            part.clone(),
            std::fs::read(parts.path().join(&part)).unwrap(),
        ));
    }
    let merge = Job {
        name: "merge",
        args: strings(&[
            "merge",
            "part0.exr",
            "part1.exr",
            "-o",
            "whole.png",
            "--hdr",
            "whole.exr",
        ]),
        outputs: vec!["whole.png", "whole.exr"],
        rerun_extra: vec![],
        inputs,
    };
    let mut total = Sweep::default();
    for (job, kills) in [(&render, 14), (&animate, 14), (&mesh, 14), (&merge, 14)] {
        let seen = sweep(job, kills);
        total.kills += seen.kills;
        total.staged_left += seen.staged_left;
        total.partial_runs += seen.partial_runs;
    }
    eprintln!("all: {total:?}");
    assert!(total.kills >= 50);
    // The sweep reached the writes: some kills left a staged file behind.
    assert!(
        total.staged_left > 0,
        "no kill landed while a file was being written: {total:?}"
    );
}

/// ffmpeg, found on PATH, or None (skipped outside CI; under CI a failure).
fn real_ffmpeg() -> Option<PathBuf> {
    let found = std::env::var_os("PATH").and_then(|path| {
        std::env::split_paths(&path)
            .map(|d| d.join("ffmpeg"))
            .find(|p| p.is_file())
    });
    if found.is_none() {
        common::skip_outside_ci("kills: ffmpeg", "killing ffmpeg", "no ffmpeg on PATH");
    }
    found
}

#[test]
fn ffmpeg_killed_mid_video_is_one_line_and_leaves_no_video() {
    let Some(ffmpeg) = real_ffmpeg() else {
        return;
    };
    let dir = tempfile::tempdir().unwrap();
    let bin = tempfile::tempdir().unwrap();
    // An ffmpeg that is the real one (exec), telling its pid first.
    let pid_file = bin.path().join("pid");
    let shim = bin.path().join("ffmpeg");
    std::fs::write(
        &shim,
        format!(
            "#!/bin/sh\necho $$ > '{}'\nexec '{}' \"$@\"\n",
            pid_file.display(),
            ffmpeg.display()
        ),
    )
    .unwrap();
    use std::os::unix::fs::PermissionsExt;
    std::fs::set_permissions(&shim, std::fs::Permissions::from_mode(0o755)).unwrap();
    let path = format!(
        "{}:{}",
        bin.path().display(),
        std::env::var("PATH").unwrap()
    );
    let child = Command::new(env!("CARGO_BIN_EXE_qjulia"))
        .args([
            "animate",
            "--backend",
            "cpu",
            "--width",
            "96",
            "--height",
            "96",
        ])
        .args(["--set", "animation.frames=400", "--video", "a.mp4"])
        .env("PATH", path)
        .current_dir(dir.path())
        .stdout(std::process::Stdio::null())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .unwrap();
    let start = Instant::now();
    let pid = loop {
        if let Ok(text) = std::fs::read_to_string(&pid_file)
            && let Ok(pid) = text.trim().parse::<u32>()
        {
            break pid;
        }
        assert!(
            start.elapsed() < Duration::from_secs(30),
            "ffmpeg never started"
        );
        std::thread::sleep(Duration::from_millis(10));
    };
    // Let it encode a while, then kill it.
    std::thread::sleep(Duration::from_millis(500));
    let killed = Command::new("kill")
        .args(["-9", &pid.to_string()])
        .status()
        .unwrap();
    assert!(killed.success(), "kill -9 {pid}");
    let out = child.wait_with_output().unwrap();
    let text = stderr(&out);
    assert_eq!(out.status.code(), Some(1), "{text}");
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("error:")).collect();
    assert_eq!(errors.len(), 1, "one error line: {text}");
    assert!(errors[0].contains("ffmpeg"), "{text}");
    assert!(errors[0].contains("SIGKILL"), "how it ended: {text}");
    eprintln!("ffmpeg killed: {}", errors[0]);
    assert!(
        !text
            .lines()
            .any(|l| !l.starts_with("error:") && !l.starts_with("qjulia:")),
        "nothing but the run's own lines: {text}"
    );
    assert!(
        files(dir.path()).is_empty(),
        "no video and no staged file: {:?}",
        files(dir.path())
    );
}
