#![no_main]
//! Fuzz target `read_step`: see `hullskin_fuzz::read_step`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_step(data, "fuzz-input");
});
