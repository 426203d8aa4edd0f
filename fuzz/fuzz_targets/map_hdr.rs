//! The fuzz target `map_hdr`: its body and its doc are qjulia_fuzz::map_hdr (src/lib.rs).
#![no_main]

libfuzzer_sys::fuzz_target!(|data: &[u8]| qjulia_fuzz::map_hdr(data));
