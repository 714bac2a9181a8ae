#![no_main]
//! Fuzz target `read_series60_table`: see `hullskin_fuzz::read_series60_table`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_series60_table(data, "fuzz-input");
});
