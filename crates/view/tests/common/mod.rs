//! Helpers of the view crate's integration test binaries: the browser runner (view's own), and
//! the workspace's one copy of the others, kept with `hull`'s tests (which use them too) and
//! included from there.
#![allow(dead_code)]

pub mod browser;
#[path = "../../../hull/tests/common/python.rs"]
pub mod python;
#[path = "../../../hull/tests/common/root.rs"]
mod root;
#[path = "../../../hull/tests/common/surfaces.rs"]
pub mod surfaces;
#[path = "../../../hull/tests/common/tables.rs"]
pub mod tables;

#[allow(unused_imports)] // each test binary uses a subset of the helpers
pub use root::workspace_root;
