//! The command line as a user meets it (docs/CONTRACT.md): every command through the binary,
//! its outputs, exit codes and one-line errors, and the faults it survives.
//!
//! One test crate (as Cargo's own testsuite is): each file a module, tests/common compiled once.
//! `render.rs` (render's outputs, bad input, atomic writes, a PNG's scene), `modes.rs` (f64 on
//! either backend, help, streamed bands, usage errors, render2d, the step views) and `scenes.rs`
//! (presets, info, overlong scene text, memory limits, quoted input) were this crate before;
//! the rest are a command or a concern each: `animate`, `animation` (the table through the
//! loader), `video`, `tiles` (and merge), `mesh/`, `hdr`, `precision`, `report`, `web_command`,
//! `pipeline_cache`, `bad_input` and `fuzz_findings` (bad input everywhere), and the faults
//! (`faults`, `kills`, `lost_device`).

mod animate;
mod animation;
mod bad_input;
#[path = "../common/mod.rs"]
mod common;
mod faults;
mod fuzz_findings;
mod hdr;
mod kernel;
mod kills;
mod lost_device;
mod mesh;
mod modes;
mod pipeline_cache;
mod precision;
mod render;
mod report;
mod scenes;
mod tiles;
mod video;
mod web_command;

use std::process::Output;

use common::stderr;

/// The one `error:` line of a failed run.
fn error_line(out: &Output) -> String {
    let text = stderr(out);
    let errors: Vec<&str> = text.lines().filter(|l| l.starts_with("error: ")).collect();
    assert_eq!(errors.len(), 1, "expected one error line, got:\n{text}");
    errors[0].to_string()
}
