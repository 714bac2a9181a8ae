#![no_main]
//! Fuzz target `drawing_svg`: see `hullskin_fuzz::drawing_svg`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::drawing_svg(data, "fuzz-input");
});
