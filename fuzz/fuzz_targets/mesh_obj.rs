#![no_main]
//! Fuzz target `mesh_obj`: see `hullskin_fuzz::mesh_obj`.

libfuzzer_sys::fuzz_target!(|data: &[u8]| {
    let _ = hullskin_fuzz::mesh_obj(data, "fuzz-input");
});
