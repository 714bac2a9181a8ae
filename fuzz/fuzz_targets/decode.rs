#![no_main]
//! Fuzz target `decode`: see `hullskin_fuzz::decode`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::decode(data, "fuzz-input");
});
