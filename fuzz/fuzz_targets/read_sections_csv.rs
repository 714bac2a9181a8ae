#![no_main]
//! Fuzz target `read_sections_csv`: see `hullskin_fuzz::read_sections_csv`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_sections_csv(data, "fuzz-input");
});
