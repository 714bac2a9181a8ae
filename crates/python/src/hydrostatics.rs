//! The hydrostatic table of a surface, as `hullskin hydrostatics --format json` computes it
//! (`crates/cli/src/hydrostatics.rs`): the same checks of the drafts and density, the same
//! options and [`hull::HydrostaticsTable::json`].

use hull::{Hydrostatics, HydrostaticsOptions, HydrostaticsTable};
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
    for (name, value) in [("draft", Some(draft)), ("to", to)] {
        if let Some(t) = value.filter(|t| !(t.is_finite() && *t > 0.0)) {
            return Err(bad_arg(format!("{name} {t}: expected a draft greater than 0")));
        }
    }
    if !(density.is_finite() && density > 0.0) {
        return Err(bad_arg(format!("density {density}: expected a positive density in t/m³")));
    }
    let drafts = match (to, step) {
        (Some(to), Some(step)) => hull::draft_range(draft, to, step).map_err(to_py)?,
        (None, None) => vec![draft],
        _ => return Err(bad_arg("to and step go together (a range of drafts from draft to `to` by `step`)")),
    };
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
