//! Helpers shared by the integration test binaries of `hull` (each uses a subset of them).
#![allow(dead_code)]

pub mod python;
mod root;
pub mod surfaces;
pub mod tables;

#[allow(unused_imports)] // each test binary uses a subset of the helpers
pub use root::{testdata, workspace_root};
