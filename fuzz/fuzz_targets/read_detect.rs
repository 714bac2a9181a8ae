#![no_main]
//! Fuzz target `read_detect`: see `hullskin_fuzz::read_detect`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_detect(data, "fuzz-input");
});
