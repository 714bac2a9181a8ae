#![no_main]
//! Fuzz target `read_long_csv`: see `hullskin_fuzz::read_long_csv`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_long_csv(data, "fuzz-input");
});
