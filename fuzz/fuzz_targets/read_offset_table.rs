#![no_main]
//! Fuzz target `read_offset_table`: see `hullskin_fuzz::read_offset_table`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_offset_table(data, "fuzz-input");
});
