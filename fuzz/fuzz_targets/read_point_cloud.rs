#![no_main]
//! Fuzz target `read_point_cloud`: see `hullskin_fuzz::read_point_cloud`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::read_point_cloud(data, "fuzz-input");
});
