//! The kernel against independent implementations, one test binary: evaluation, derivatives,
//! normals and curvature against Open CASCADE's values (`oracle`), closest points against its
//! projections (`projection_oracle`), and random curves and surfaces against the `curvo` crate
//! (`curvo_crosscheck`, proptest).
//!
//! `cargo test -p hullskin-nurbs --test oracles`. proptest keeps the failures it finds in
//! `tests/proptest-regressions/<module>.txt` (its default place, beside the folder that holds
//! the `main.rs`) and replays them first.

mod curvo_crosscheck;
mod oracle;
mod projection_oracle;
