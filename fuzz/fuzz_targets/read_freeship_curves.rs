#![no_main]
//! Fuzz target `read_freeship_curves`: see `hullskin_fuzz::read_freeship_curves`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_freeship_curves(data, "fuzz-input");
});
