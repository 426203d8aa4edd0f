//! The fuzz target `map_exr`: its body and its doc are qjulia_fuzz::map_exr (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::map_exr(data));
