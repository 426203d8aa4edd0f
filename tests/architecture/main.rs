//! The code and its documents held to each other: the contract's keys and the schema, the book's
//! links and commands, the WGSL and its host-side tables, each kernel and its CPU twin function
//! by function, the browser's fixtures against the binary, CI's GL pass against the tests that
//! depend on a capability, file lengths and import cycles.
//!
//! One test crate: each file a module, tests/common compiled once.

mod book;
mod ci;
#[path = "../common/mod.rs"]
mod common;
mod contract;
mod file_lengths;
mod import_cycles;
mod shaders;
mod twins;
mod web;
mod web_estimate;
mod web_kernels;

use std::path::{Path, PathBuf};

/// Every file under `dir`, recursively, whose extension is one of `extensions`, sorted (the
/// book's pages, the sources whose lengths are held, the test files CI's GL pass is held to).
fn files_under(dir: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut out = Vec::new();
    let mut todo = vec![dir.to_path_buf()];
    while let Some(dir) = todo.pop() {
        for entry in std::fs::read_dir(&dir).unwrap_or_else(|e| panic!("{}: {e}", dir.display())) {
            let path = entry.expect("a directory entry").path();
            if path.is_dir() {
                todo.push(path);
            } else if path
                .extension()
                .is_some_and(|e| extensions.iter().any(|x| e == *x))
            {
                out.push(path);
            }
        }
    }
    out.sort();
    out
}
