//! The hydrostatic table of a surface, as `hullskin hydrostatics --format json` computes it
//! (`crates/cli/src/hydrostatics.rs`): the same checks of the drafts and density
//! ([`hull::table_drafts`]), the same options and [`hull::HydrostaticsTable::json`].

use hull::{Hydrostatics, HydrostaticsOptions, HydrostaticsTable, InputNames};
use pyo3::prelude::*;

use crate::errors::{bad_arg, to_py};
use crate::surface::PySurface;

/// The table's JSON text.
pub fn table_json(
    s: &PySurface,
    draft: f64,
    to: Option<f64>,
    step: Option<f64>,
    density: f64,
    lpp: Option<f64>,
    ap: Option<f64>,
) -> PyResult<String> {
    let drafts = hull::table_drafts(Some(draft), to, step, density, InputNames::Keywords).map_err(to_py)?;
    let perpendiculars = match (lpp, ap) {
        (Some(lpp), ap) => Some(hull::Perpendiculars::try_new(ap.unwrap_or(0.0), lpp).map_err(|_| {
            bad_arg(format!("lpp {lpp}, ap {}: expected a positive Lpp and a finite AP", ap.unwrap_or(0.0)))
        })?),
        (None, Some(_)) => return Err(bad_arg("ap places the perpendiculars with lpp: give lpp too")),
        (None, None) => s.perpendiculars,
    };
    let options = HydrostaticsOptions { density, units: s.units, perpendiculars, ..HydrostaticsOptions::default() };
    let surfaces = std::slice::from_ref(&s.surface);
    let hydro = Hydrostatics::patches(surfaces, &options).map_err(to_py)?;
    let rows = hydro.rows(&drafts).map_err(to_py)?;
    let table = HydrostaticsTable { source: s.source.clone(), units: s.units, density, perpendiculars, rows };
    Ok(table.json())
}
