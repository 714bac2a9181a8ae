#![no_main]
//! Fuzz target `mesh_parse_slice`: see `hullskin_fuzz::mesh_parse_slice`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::mesh_parse_slice(data, "fuzz-input");
});
