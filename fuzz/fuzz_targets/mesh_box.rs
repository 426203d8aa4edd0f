//! The fuzz target `mesh_box`: its body and its doc are qjulia_fuzz::mesh_box (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::mesh_box(data));
