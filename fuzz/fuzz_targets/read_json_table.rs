#![no_main]
//! Fuzz target `read_json_table`: see `hullskin_fuzz::read_json_table`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_json_table(data, "fuzz-input");
});
