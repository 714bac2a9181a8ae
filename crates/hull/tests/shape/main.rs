//! The shape measured, one test binary: planar cuts, curvature and fairness against closed
//! forms (`analysis`), and hydrostatics against closed forms and published figures.
//!
//! `cargo test -p hullskin-hull --test shape`; one module with a filter, e.g.
//! `--test shape hydrostatics::`.

#[path = "../common/mod.rs"]
mod common;

mod analysis;
mod hydrostatics;
