#![no_main]
//! Fuzz target `drawing_digitize`: see `hullskin_fuzz::drawing_digitize`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::drawing_digitize(data, "fuzz-input");
});
