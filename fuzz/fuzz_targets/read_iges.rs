#![no_main]
//! Fuzz target `read_iges`: see `hullskin_fuzz::read_iges`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_iges(data, "fuzz-input");
});
