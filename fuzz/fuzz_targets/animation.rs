//! The fuzz target `animation`: its body and its doc are qjulia_fuzz::animation (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::animation(data));
