//! The fuzz target `merge_part`: its body and its doc are qjulia_fuzz::merge_part (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::merge_part(data));
