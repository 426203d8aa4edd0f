//! What a bad scene says: where the value came from ([`SceneSource`]) and the one-line
//! [`SceneError`] that names it, the key and the reason.

use std::fmt;
use std::path::PathBuf;

use toml::Value;

/// `text` as one line: each control character (a newline, a NUL, ...) written as its Rust
/// escape (`\n`, `\0`, `\u{1b}`), so that a message quoting what the user typed, or a file's
/// name, stays the one line an error is. Other characters are kept as they are.
pub fn one_line(text: &str) -> String {
    text.chars()
        .map(|c| match c.is_control() {
            true => c.escape_debug().to_string(),
            false => c.to_string(),
        })
        .collect()
}

/// Where a scene value came from, so that an error can name it.
#[derive(Clone, Debug, PartialEq)]
pub enum SceneSource {
    /// The built-in defaults.
    Default,
    /// A preset (src/scene/presets.rs), by its slug.
    Preset(String),
    /// A scene file (TOML, or a PNG carrying its scene).
    File(PathBuf),
    /// A shorthand flag, as typed, e.g. `--width 0`.
    Flag(String),
    /// One `--set`, its `KEY=VALUE` as typed.
    Set(String),
}

impl fmt::Display for SceneSource {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            SceneSource::Default => write!(f, "default scene"),
            SceneSource::Preset(slug) => write!(f, "preset {slug}"),
            SceneSource::File(p) => write!(f, "{}", p.display()),
            SceneSource::Flag(s) => write!(f, "{s}"),
            SceneSource::Set(s) => write!(f, "--set {s}"),
        }
    }
}

/// A bad scene: one line naming the source (file or flag), the key and the reason.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{}", one_line(&format!("{origin}: {message}")))]
pub struct SceneError {
    /// Where the bad value came from.
    pub origin: SceneSource,
    /// The dotted key at fault, where there is one.
    pub key: Option<String>,
    pub message: String,
}

impl SceneError {
    pub(super) fn general(source: &SceneSource, message: impl Into<String>) -> Self {
        Self {
            origin: source.clone(),
            key: None,
            message: message.into(),
        }
    }

    /// A value of `key` is wrong: in a file, `key = value: reason`; on the command line, where
    /// the value is already in view, `key reason`.
    pub(super) fn value(source: &SceneSource, key: &str, value: &Value, reason: &str) -> Self {
        let message = match source {
            SceneSource::File(_) | SceneSource::Default | SceneSource::Preset(_) => {
                format!("{key} = {value}: {reason}")
            }
            SceneSource::Flag(_) | SceneSource::Set(_) => format!("{key} {reason}"),
        };
        Self {
            origin: source.clone(),
            key: Some(key.to_string()),
            message,
        }
    }

    pub(super) fn key(source: &SceneSource, key: &str, message: String) -> Self {
        Self {
            origin: source.clone(),
            key: Some(key.to_string()),
            message,
        }
    }
}
