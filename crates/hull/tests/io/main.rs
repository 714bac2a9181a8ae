//! Reading and writing, one test binary: the offsets readers on the real files of `testdata/`
//! and their sense checks, the fuzz findings replayed, CAD surfaces read back, meshes read and
//! sliced, and every export read back by a real reader (Open CASCADE, trimesh, pygltflib).
//!
//! `cargo test -p hullskin-hull --test io`; one module with a filter, e.g. `--test io mesh::`.
//! The helpers shared with the crate's other test binaries are in `tests/common/`.

#[path = "../common/mod.rs"]
mod common;

mod cad_read;
mod exports;
mod fuzz_regressions;
mod mesh;
mod occt_iges;
mod readers;
mod sense;
