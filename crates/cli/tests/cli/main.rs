//! The `hullskin` command line end to end: one test binary (ripgrep's `tests/` layout), one
//! module per subcommand or concern, the shared helpers in `common` (run the binary, find
//! `testdata/`, a scratch directory per test).
//!
//! `cargo test -p hullskin --test cli` runs them all; a module or a test by name with a filter,
//! e.g. `cargo test -p hullskin --test cli bad_input::`.

mod common;
/// Reading the report's page (base64, URLs): view's test helper, one for the workspace.
#[path = "../../../view/tests/common/page.rs"]
mod page;
/// The Python of `tools/requirements.txt` for the export checks: the helper of hull's tests,
/// one for the workspace.
#[path = "../../../hull/tests/common/python.rs"]
mod python;

mod bad_input;
mod compare;
mod digitize;
mod export;
mod fit;
mod hydrostatics;
mod limits;
mod nothing_lost;
mod optimize;
mod report;
mod slice;
