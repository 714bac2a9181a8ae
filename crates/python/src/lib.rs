//! hullskin from Python: the `hullskin._hullskin` extension module, a thin layer over the
//! `hull` crate (built by maturin, `pyproject.toml`; `python/hullskin` is the package).
//!
//! Every figure comes from the library functions the command line calls, with its defaults,
//! so that `hullskin.fit(path).report` equals `hullskin fit path --json` and
//! `surface.hydrostatics(draft=T)` equals `hullskin hydrostatics --draft T --format json`.
//! Arguments are checked before any library call (`ValueError`, `TypeError`); library errors
//! become `hullskin.HullskinError` (a `ValueError`) with the library's message.

// Python functions take their keyword arguments one by one, and return tuples of arrays.
#![allow(clippy::too_many_arguments, clippy::type_complexity)]

mod arrays;
mod errors;
mod export;
mod fit;
mod hydrostatics;
mod interrupt;
mod offsets;
mod options;
mod surface;

use pyo3::prelude::*;

/// The native module; `python/hullskin/__init__.py` re-exports it with the Dask helpers.
#[pymodule]
fn _hullskin(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("HullskinError", m.py().get_type::<errors::HullskinError>())?;
    m.add("SEA_WATER_DENSITY", hull::SEA_WATER_DENSITY)?;
    m.add("DEFAULT_HELD_OUT_FOLDS", hull::HeldOutOptions::DEFAULT_FOLDS)?;
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<offsets::PyOffsets>()?;
    m.add_class::<surface::PySurface>()?;
    m.add_class::<fit::PyFit>()?;
    m.add_function(wrap_pyfunction!(offsets::read_offsets, m)?)?;
    m.add_function(wrap_pyfunction!(fit::fit, m)?)?;
    m.add_function(wrap_pyfunction!(offsets::_offsets_from_state, m)?)?;
    m.add_function(wrap_pyfunction!(surface::_surface_from_state, m)?)?;
    m.add_function(wrap_pyfunction!(fit::_fit_from_state, m)?)?;
    Ok(())
}
