#![no_main]
//! Fuzz target `read_freeship_offsets`: see `hullskin_fuzz::read_freeship_offsets`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_freeship_offsets(data, "fuzz-input");
});
