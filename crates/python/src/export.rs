//! Meshes and CAD files of a surface, as `hullskin export` writes them
//! (`crates/cli/src/export.rs`): the same metadata, tolerances and writers, written
//! atomically.

use std::path::Path;

use hull::{
    mesh_name, mirrored_full_hull, stl_header, tessellate, write_iges, write_step, write_stl_ascii, write_stl_binary,
    IgesMeta, StepMeta, TessellationOptions, TriMesh,
};
use pyo3::prelude::*;

use crate::errors::{bad_arg, io_error, to_py};
use crate::surface::PySurface;

/// What to write.
#[derive(Clone, Copy, PartialEq, Eq)]
pub enum Format {
    Iges,
    Step,
    Stl,
    StlAscii,
}

/// The mesh of `s` within `tolerance` (default: the command line's, 1e-4 of the control net's
/// diagonal), with the port half when `mirror`.
pub fn mesh(py: Python<'_>, s: &PySurface, tolerance: Option<f64>, mirror: bool) -> PyResult<TriMesh> {
    let mut options = TessellationOptions::for_surface(&s.surface);
    options.mirror = mirror;
    if let Some(t) = tolerance {
        if !(t.is_finite() && t > 0.0) {
            return Err(bad_arg(format!("tolerance {t}: expected a positive length")));
        }
        options.tolerance = t;
    }
    py.detach(|| tessellate(&s.surface, &options)).map(|t| t.mesh).map_err(|e| to_py(e.into()))
}

/// The header date: `timestamp`, else SOURCE_DATE_EPOCH, else now (the command line's rule).
fn unix_time(timestamp: Option<i64>) -> i64 {
    timestamp.or_else(|| std::env::var("SOURCE_DATE_EPOCH").ok().and_then(|s| s.trim().parse().ok())).unwrap_or_else(
        || {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map_or(0, |d| i64::try_from(d.as_secs()).unwrap_or(i64::MAX))
        },
    )
}

/// Write `s` to `path` in `format`.
pub fn write(
    py: Python<'_>,
    s: &PySurface,
    path: &Path,
    format: Format,
    mirror: bool,
    tolerance: Option<f64>,
    timestamp: Option<i64>,
) -> PyResult<()> {
    let file_name = path.file_name().map_or_else(|| "hull".into(), |n| n.to_string_lossy().into_owned());
    let time = unix_time(timestamp);
    let units = s.units;
    let source = &s.source;
    let fill: Box<dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()> + Send + Sync> = match format {
        Format::Iges | Format::Step => {
            let surface = if mirror { mirrored_full_hull(&s.surface).map_err(to_py)? } else { s.surface.clone() };
            hull::check_finite(&surface).map_err(to_py)?;
            if format == Format::Iges {
                let mut meta = IgesMeta::new(units.into(), &file_name, &hull::iges_timestamp(time));
                meta.product_id = format!("hull surface ({source})");
                Box::new(move |mut w| write_iges(&mut w, &surface, &meta))
            } else {
                let mut meta = StepMeta::new(units, &file_name, &hull::step_timestamp(time));
                meta.description = format!("hull surface ({source})");
                Box::new(move |mut w| write_step(&mut w, &surface, &meta))
            }
        }
        Format::Stl | Format::StlAscii => {
            hull::check_finite(&s.surface).map_err(to_py)?;
            let mesh = mesh(py, s, tolerance, mirror)?;
            if format == Format::Stl {
                Box::new(move |mut w| write_stl_binary(&mut w, &mesh, &stl_header("hull", units)))
            } else {
                Box::new(move |mut w| write_stl_ascii(&mut w, &mesh, &mesh_name("hull")))
            }
        }
    };
    py.detach(|| hull::write_atomic(path, |w| fill(w))).map_err(|e| io_error(path, &e))
}
