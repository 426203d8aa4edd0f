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
