#![no_main]
//! Fuzz target `surface_json`: see `hullskin_fuzz::surface_json`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::surface_json(data, "fuzz-input");
});
