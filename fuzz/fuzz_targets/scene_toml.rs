//! The fuzz target `scene_toml`: its body and its doc are qjulia_fuzz::scene_toml (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::scene_toml(data));
