//! The fuzz target `set`: its body and its doc are qjulia_fuzz::set (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::set(data));
