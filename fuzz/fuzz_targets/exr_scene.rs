//! The fuzz target `exr_scene`: its body and its doc are qjulia_fuzz::exr_scene (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::exr_scene(data));
