#![no_main]
//! Fuzz target `drawing_dxf`: see `hullskin_fuzz::drawing_dxf`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::drawing_dxf(data, "fuzz-input");
});
