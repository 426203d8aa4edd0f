//! The library's errors, each knowing the exit code docs/CONTRACT.md gives it.

use std::path::PathBuf;

use crate::scene::SceneError;
pub use crate::scene::one_line;

/// A bad command-line flag that is not a scene key (`--resolution`, `--box`, `--scale`,
/// `--frames`, an output's extension): one line naming the flag as typed and the reason.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", one_line(&format!("{flag}: {message}")))]
pub struct FlagError {
    /// The flag and its value, as typed, e.g. `--resolution 3`.
    pub flag: String,
    pub message: String,
}

impl FlagError {
    pub fn new(flag: impl Into<String>, message: impl Into<String>) -> Self {
        Self {
            flag: flag.into(),
            message: message.into(),
        }
    }
}

/// Bytes as a person reads them: "5.0 GiB", "12.3 MiB", "900 bytes".
pub fn human(bytes: u64) -> String {
    const UNITS: [(&str, f64); 3] = [("GiB", 1073741824.0), ("MiB", 1048576.0), ("KiB", 1024.0)];
    let b = bytes as f64;
    UNITS
        .iter()
        .find(|(_, size)| b >= *size)
        .map_or(format!("{bytes} bytes"), |(unit, size)| {
            format!("{:.1} {unit}", b / size)
        })
}

/// How to get an adapter on a machine without a GPU, for every "no adapter" message.
pub const INSTALL_ADAPTER_HINT: &str = "install Mesa's software Vulkan driver (lavapipe): \
    `sudo apt-get install mesa-vulkan-drivers`";

#[derive(Debug, thiserror::Error)]
pub enum Error {
    /// Bad input: a scene file, `--set`, a shorthand of a scene key. Exit 2.
    #[error(transparent)]
    Scene(#[from] SceneError),
    /// Bad input: a flag that is not a scene key. Exit 2.
    #[error(transparent)]
    Flag(#[from] FlagError),
    /// Bad input: a part given to `merge` (unreadable, not a partial, of another scene,
    /// overlapping another). Exit 2.
    #[error("{}", one_line(&format!("{}: {message}", path.display())))]
    Part { path: PathBuf, message: String },
    /// A whole-image job whose buffers would not fit in the memory available
    /// ([`crate::memory`]), refused before anything is allocated. Exit 2: the input asks for
    /// more than this machine has.
    #[error(
        "{what} would need {needed} bytes ({}) of memory, more than the {available} bytes ({}) available",
        human(*needed),
        human(*available)
    )]
    Memory {
        what: String,
        needed: u64,
        available: u64,
    },
    /// wgpu found no adapter (or none matching WGPU_ADAPTER_NAME). Exit 1.
    #[error("no GPU adapter: {0}; {INSTALL_ADAPTER_HINT}")]
    NoAdapter(String),
    /// The adapter cannot do what was asked (e.g. f64 on the GPU). Exit 1.
    #[error("{0}")]
    Unsupported(String),
    /// Device creation, device loss, mapping failures. Exit 1.
    #[error("GPU: {0}")]
    Gpu(String),
    /// A writer of `animate` (the PNG encoders, the video's thread) stopped: its own error is
    /// the one reported first. Exit 1.
    #[error("{0}")]
    Stopped(String),
    /// ffmpeg missing or failing (`animate --video`). Exit 1.
    #[error("{0}")]
    Video(String),
    /// Reading or writing a file. Exit 1. The I/O error is part of the message and not a
    /// `source`, so that a chain printed in full (`{:#}`) says it once.
    #[error("{}", one_line(&format!("{}: {cause}", path.display())))]
    Io {
        path: PathBuf,
        cause: std::io::Error,
    },
}

impl Error {
    /// The process exit code for this error: 2 for bad input, 1 for anything else.
    pub fn exit_code(&self) -> i32 {
        match self {
            Error::Scene(_) | Error::Flag(_) | Error::Part { .. } | Error::Memory { .. } => 2,
            _ => 1,
        }
    }
}

pub type Result<T, E = Error> = std::result::Result<T, E>;
