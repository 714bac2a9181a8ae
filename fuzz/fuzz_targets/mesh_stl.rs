#![no_main]
//! Fuzz target `mesh_stl`: see `hullskin_fuzz::mesh_stl`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::mesh_stl(data, "fuzz-input");
});
