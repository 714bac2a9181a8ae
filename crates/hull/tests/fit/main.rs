//! Fitting, one test binary: random sections fitted by every method (proptest), the held-out
//! error, the validity of the fitted surfaces of real hulls, and hull features (chines, flats,
//! transoms, bulbs) inside one surface.
//!
//! `cargo test -p hullskin-hull --test fit`; one module with a filter, e.g. `--test fit held_out::`.
//! proptest keeps the failures it finds in `tests/proptest-regressions/<module>.txt` and
//! replays them first (its default place: beside the folder that holds the `main.rs`, here
//! `tests/proptest-regressions/pipeline_props.txt`).

#[path = "../common/mod.rs"]
mod common;

mod fairness_alternative;
mod features;
mod held_out;
mod held_out_referee;
mod pipeline_props;
mod real_hull_features;
mod round_off;
mod tolerance_referee;
mod validity;
