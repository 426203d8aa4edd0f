//! Video: frames piped to `ffmpeg` as raw RGB, H.264 (yuv420p) in `.mp4` or VP9 in `.webm`,
//! odd sizes padded to even, written to a temporary file beside the target and renamed into
//! place only when ffmpeg has finished without error (whole or not at all).

use std::io::{Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::thread::JoinHandle;

use crate::error::{Error, FlagError, Result};

/// How to get ffmpeg, for the error when it is not on PATH.
pub const INSTALL_FFMPEG_HINT: &str = "install it (Debian/Ubuntu: `sudo apt-get install ffmpeg`; \
    macOS: `brew install ffmpeg`) or leave out --video";

/// The container and codec, chosen by the file's extension.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Codec {
    /// `.mp4`: H.264 (libx264), yuv420p, quality 18 (visually lossless), `+faststart`.
    H264,
    /// `.webm`: VP9 (libvpx-vp9), yuv420p, constant quality 30.
    Vp9,
}

impl Codec {
    /// The codec of `--video FILE` by its extension (case-insensitive); any other is bad input
    /// (exit 2) naming the flag.
    pub fn for_path(path: &Path) -> Result<Self, FlagError> {
        let extension = path
            .extension()
            .and_then(|e| e.to_str())
            .map(str::to_ascii_lowercase);
        match extension.as_deref() {
            Some("mp4") => Ok(Codec::H264),
            Some("webm") => Ok(Codec::Vp9),
            _ => Err(FlagError::new(
                format!("--video {}", path.display()),
                "the video must end in .mp4 (H.264) or .webm (VP9)",
            )),
        }
    }

    /// ffmpeg's muxer and encoder options for this codec.
    fn arguments(self) -> &'static [&'static str] {
        match self {
            Codec::H264 => &[
                "-c:v",
                "libx264",
                "-preset",
                "medium",
                "-crf",
                "18",
                "-movflags",
                "+faststart",
                "-f",
                "mp4",
            ],
            Codec::Vp9 => &[
                "-c:v",
                "libvpx-vp9",
                "-crf",
                "30",
                "-b:v",
                "0",
                "-row-mt",
                "1",
                "-deadline",
                "good",
                "-cpu-used",
                "4",
                "-f",
                "webm",
            ],
        }
    }
}

/// The `ffmpeg` on PATH, or the error (exit 1) that says how to get it.
pub fn find_ffmpeg() -> Result<PathBuf> {
    let found = std::env::var_os("PATH").and_then(|paths| {
        std::env::split_paths(&paths)
            .map(|dir| dir.join("ffmpeg"))
            .find(|candidate| candidate.is_file())
    });
    found.ok_or_else(|| {
        Error::Video(format!(
            "--video needs ffmpeg, which is not on PATH: {INSTALL_FFMPEG_HINT}"
        ))
    })
}

/// The size a video of `[width, height]` frames has: each rounded up to even (yuv420p halves
/// both for its colour planes), the padding black at the right and bottom.
pub fn padded_size([width, height]: [u32; 2]) -> [u32; 2] {
    [width.next_multiple_of(2), height.next_multiple_of(2)]
}

/// A video being written: ffmpeg reading raw RGB frames on its stdin and writing a temporary
/// file beside the target. Dropped before [`Self::finish`], it stops ffmpeg and leaves nothing.
pub struct VideoWriter {
    child: Child,
    stdin: Option<ChildStdin>,
    /// ffmpeg's stderr, collected on a thread so that ffmpeg never blocks on it.
    log: Option<JoinHandle<String>>,
    /// Taken when the video is renamed into place; dropped, it removes the temporary file.
    temp: Option<tempfile::TempPath>,
    path: PathBuf,
    frame_bytes: usize,
    frames: u64,
}

impl VideoWriter {
    /// Starts ffmpeg for frames of `[width, height]` RGB8 pixels at `fps` frames per second.
    pub fn start(path: &Path, [width, height]: [u32; 2], fps: f64) -> Result<Self> {
        let codec = Codec::for_path(path)?;
        let ffmpeg = find_ffmpeg()?;
        let io = |cause| Error::Io {
            path: path.to_path_buf(),
            cause,
        };
        let dir = match path.parent() {
            Some(p) if !p.as_os_str().is_empty() => p,
            _ => Path::new("."),
        };
        crate::output::remove_stale_staging(path);
        let (prefix, suffix) = crate::output::staging_name(path);
        let temp = tempfile::Builder::new()
            .prefix(&prefix)
            .suffix(suffix)
            .tempfile_in(dir)
            .map_err(io)?
            .into_temp_path();
        let [even_width, even_height] = padded_size([width, height]);
        let mut child = Command::new(ffmpeg)
            .args(["-hide_banner", "-loglevel", "error", "-y"])
            .args(["-f", "rawvideo", "-pix_fmt", "rgb24"])
            .args(["-video_size", &format!("{width}x{height}")])
            .args(["-framerate", &fps.to_string()])
            .args(["-i", "pipe:0"])
            .args(["-vf", &format!("pad={even_width}:{even_height}:0:0:black")])
            .args(["-pix_fmt", "yuv420p"])
            .args(codec.arguments())
            .arg(&*temp)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Error::Video(format!("cannot start ffmpeg: {e}")))?;
        let stdin = child.stdin.take();
        let log = child.stderr.take().map(|mut stderr| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = stderr.read_to_string(&mut text);
                text
            })
        });
        Ok(Self {
            child,
            stdin,
            log,
            temp: Some(temp),
            path: path.to_path_buf(),
            frame_bytes: width as usize * height as usize * 3,
            frames: 0,
        })
    }

    /// Appends one frame: `[width, height]` RGB8 pixels, row by row, top first.
    pub fn push(&mut self, rgb: &[u8]) -> Result<()> {
        assert_eq!(
            rgb.len(),
            self.frame_bytes,
            "a video frame of the video's size"
        );
        let stdin = self.stdin.as_mut().expect("open until finish");
        if stdin.write_all(rgb).is_err() {
            // ffmpeg stopped reading: it failed, and says why; how it ended too, where it has
            // (killed, crashed, failed).
            let what = match self.ended() {
                Some(status) => format!("stopped reading frames ({status})"),
                None => "stopped reading frames".to_string(),
            };
            return Err(self.failure(&what));
        }
        self.frames += 1;
        Ok(())
    }

    /// How ffmpeg ended, once it has, waiting up to 2 s: a dying process's pipe closes a
    /// moment before its exit status is there (the kernel closes its files first), and a
    /// `try_wait` at once could miss a SIGKILL that had already struck.
    fn ended(&mut self) -> Option<std::process::ExitStatus> {
        let deadline = std::time::Instant::now() + std::time::Duration::from_secs(2);
        loop {
            match self.child.try_wait() {
                Ok(Some(status)) => return Some(status),
                Ok(None) if std::time::Instant::now() < deadline => {
                    std::thread::sleep(std::time::Duration::from_millis(5))
                }
                _ => return None,
            }
        }
    }

    /// Frames pushed so far.
    pub fn frames(&self) -> u64 {
        self.frames
    }

    /// Closes ffmpeg's input, waits for it and renames the video into place.
    pub fn finish(mut self) -> Result<()> {
        drop(self.stdin.take());
        let status = self.child.wait().map_err(|e| Error::Io {
            path: self.path.clone(),
            cause: e,
        })?;
        if !status.success() {
            return Err(self.failure(&format!("exited with {status}")));
        }
        let temp = self.temp.take().expect("finished once");
        temp.persist(&self.path).map_err(|e| Error::Io {
            path: self.path.clone(),
            cause: e.error,
        })?;
        Ok(())
    }

    /// The error of a failed ffmpeg: what it did and the last line it wrote.
    fn failure(&mut self, what: &str) -> Error {
        drop(self.stdin.take());
        let _ = self.child.kill();
        let _ = self.child.wait();
        let log = self
            .log
            .take()
            .and_then(|h| h.join().ok())
            .unwrap_or_default();
        let last = log.lines().rev().find(|l| !l.trim().is_empty());
        Error::Video(format!(
            "ffmpeg {what} writing {}{}",
            self.path.display(),
            last.map(|l| format!(": {}", l.trim())).unwrap_or_default()
        ))
    }
}

impl Drop for VideoWriter {
    fn drop(&mut self) {
        if self.stdin.is_some() {
            // Not finished: stop ffmpeg; the temporary file goes with `temp`.
            drop(self.stdin.take());
            let _ = self.child.kill();
            let _ = self.child.wait();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_codec_follows_the_extension() {
        assert_eq!(Codec::for_path(Path::new("a.mp4")).unwrap(), Codec::H264);
        assert_eq!(
            Codec::for_path(Path::new("dir/a.WEBM")).unwrap(),
            Codec::Vp9
        );
        let e = Codec::for_path(Path::new("a.gif")).unwrap_err().to_string();
        assert!(e.contains("--video a.gif") && e.contains(".mp4"), "{e}");
        assert!(Codec::for_path(Path::new("mp4")).is_err());
    }

    #[test]
    fn odd_sizes_are_padded_to_even() {
        assert_eq!(padded_size([65, 47]), [66, 48]);
        assert_eq!(padded_size([64, 48]), [64, 48]);
    }
}
