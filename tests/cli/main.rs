//! The command line as a user meets it (docs/CONTRACT.md): default output, bad input, atomic writes,
//! re-rendering from a PNG, the .npy and JSON outputs.
//!
//! The tests are in `render.rs` (render's outputs, bad input, atomic writes, a PNG's scene),
//! `modes.rs` (f64 on either backend, help, streamed bands, usage errors, render2d, the step
//! views) and `scenes.rs` (presets, info, overlong scene text, memory limits, quoted input).

#[path = "../common/mod.rs"]
mod common;
mod modes;
mod render;
mod scenes;

use std::process::Output;

use common::stderr;

/// The one `error:` line of a failed run.
fn error_line(out: &Output) -> String {
    let text = stderr(out);
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "expected one error line, got:\n{text}");
    errors[0].to_string()
}
