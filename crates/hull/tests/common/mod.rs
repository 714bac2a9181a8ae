//! Helpers shared by the integration test binaries of `hull` (each uses a subset of them).
#![allow(dead_code)]

pub mod browser;
pub mod python;
pub mod surfaces;
pub mod tables;
