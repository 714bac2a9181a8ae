//! Helpers of the view crate's integration test binaries: the workspace's one copy of each,
//! kept with `hull`'s tests (which use them too) and included from there.
#![allow(dead_code)]

#[path = "../../../hull/tests/common/browser.rs"]
pub mod browser;
#[path = "../../../hull/tests/common/python.rs"]
pub mod python;
#[path = "../../../hull/tests/common/tables.rs"]
pub mod tables;
