#![no_main]
//! Fuzz target `mesh_vrml`: see `hullskin_fuzz::mesh_vrml`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::mesh_vrml(data, "fuzz-input");
});
