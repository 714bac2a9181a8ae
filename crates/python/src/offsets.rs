//! `hullskin.Offsets` and `hullskin.read_offsets`: a ship's offsets as NumPy sections, with
//! what the reader noted and warned of.

use std::path::PathBuf;

use hull::{Offsets, Perpendiculars, Section, SenseKind, SenseWarning};
use numpy::PyArrayDyn;
use pyo3::prelude::*;

use crate::arrays;
use crate::errors::{bad_arg, to_py};
use crate::options;

/// A ship's offsets: sections in order along the length (x forward, y half-breadth >= 0, z up),
/// in `units`, with the notes and warnings of their reading.
#[pyclass(module = "hullskin", name = "Offsets", frozen)]
#[derive(Clone)]
pub struct PyOffsets {
    pub offsets: Offsets,
    /// The reader's notes (format, axes, what was left out or assumed), one line each.
    pub notes: Vec<String>,
    /// The sense checks' warnings (units, size, outlier cells).
    pub warnings: Vec<SenseWarning>,
}

impl PyOffsets {
    /// The offsets of a path, or the built-in sample without one: read as `hullskin fit`
    /// reads them (`SkinArgs::read_options`: sections shorter than `degree_u + 1` points left
    /// out where the format allows).
    pub fn read(path: Option<PathBuf>, options: &hull::ReadOptions) -> PyResult<Self> {
        let Some(path) = path else {
            return Ok(PyOffsets { offsets: hull::series60_sample(), notes: Vec::new(), warnings: Vec::new() });
        };
        if hull::is_mesh_path(&path) {
            return Err(bad_arg(format!(
                "{}: a mesh; hullskin.read_offsets reads offsets (slice a mesh with the command line: hullskin fit \
                 MESH --stations N)",
                path.display()
            )));
        }
        let outcome = hull::read_offsets_with(&path, options).map_err(to_py)?;
        let notes = outcome.messages();
        Ok(PyOffsets { offsets: outcome.offsets, notes, warnings: outcome.warnings })
    }
}

/// The reading options of the command line for these arguments.
pub fn read_options(
    units: &str,
    lpp: Option<f64>,
    beam: Option<f64>,
    design_draft: Option<f64>,
    outliers: &str,
    degree_u: usize,
) -> PyResult<hull::ReadOptions> {
    let outliers: hull::OutlierPolicy = outliers.parse().map_err(|e: String| bad_arg(format!("outliers: {e}")))?;
    if (beam.is_some() || design_draft.is_some()) && !(lpp.is_some() && beam.is_some() && design_draft.is_some()) {
        return Err(bad_arg("beam and design_draft scale a Series 60 table with lpp: give all three"));
    }
    for (name, v) in [("lpp", lpp), ("beam", beam), ("design_draft", design_draft)] {
        if let Some(x) = v.filter(|x| !(x.is_finite() && *x > 0.0)) {
            return Err(bad_arg(format!("{name}: {x} is not a length (expected a positive number)")));
        }
    }
    let dimensions = lpp.map(|lpp| hull::MainDimensions {
        lpp,
        beam: beam.unwrap_or(f64::NAN),
        draft: design_draft.unwrap_or(f64::NAN),
    });
    Ok(hull::ReadOptions {
        units: options::units(units)?,
        dimensions,
        min_points: degree_u + 1,
        outliers,
        ..hull::ReadOptions::default()
    })
}

#[pymethods]
impl PyOffsets {
    /// Offsets from sections given as arrays of shape (n, 3) (x, y, z per point, in order
    /// along each section), in `units`; `labels` name the sections (default "1", "2", ...);
    /// `perpendiculars` is `(x of AP, x of FP)` where known.
    #[staticmethod]
    #[pyo3(signature = (sections, units = "m", labels = None, source = "python", perpendiculars = None))]
    fn from_sections(
        sections: Vec<Bound<'_, PyAny>>,
        units: &str,
        labels: Option<Vec<String>>,
        source: &str,
        perpendiculars: Option<(f64, f64)>,
    ) -> PyResult<Self> {
        if let Some(l) = labels.as_ref().filter(|l| l.len() != sections.len()) {
            return Err(bad_arg(format!("labels: {} names for {} sections", l.len(), sections.len())));
        }
        let mut out = Vec::with_capacity(sections.len());
        for (k, s) in sections.iter().enumerate() {
            let points = arrays::points(s, &format!("sections[{k}]"))?;
            let label = labels.as_ref().map_or_else(|| (k + 1).to_string(), |l| l[k].clone());
            out.push(Section::new(label, points));
        }
        let mut offsets = Offsets::new(source, options::units(units)?, out);
        offsets.perpendiculars = perpendiculars.map(perpendiculars_of).transpose()?;
        Ok(PyOffsets { offsets, notes: Vec::new(), warnings: Vec::new() })
    }

    /// The sections as arrays of shape (n, 3).
    #[getter]
    fn sections<'py>(&self, py: Python<'py>) -> PyResult<Vec<Bound<'py, PyArrayDyn<f64>>>> {
        self.offsets.sections.iter().map(|s| arrays::vec3s(py, &[s.points.len()], &s.points)).collect()
    }

    /// The sections' labels (station numbers or names of the input).
    #[getter]
    fn labels(&self) -> Vec<String> {
        self.offsets.sections.iter().map(|s| s.label.clone()).collect()
    }

    /// Where the offsets came from: the path, or the built-in sample's description.
    #[getter]
    fn source(&self) -> String {
        self.offsets.source.clone()
    }

    /// The length unit: m, mm, ft or in.
    #[getter]
    fn units(&self) -> &'static str {
        self.offsets.units.symbol()
    }

    /// `(x of the aft perpendicular, x of the forward one)` where the data give them, else None.
    #[getter]
    fn perpendiculars(&self) -> Option<(f64, f64)> {
        self.offsets.perpendiculars.map(|p| (p.aft, p.fore))
    }

    /// The reader's notes, one line each (as `hullskin fit` prints them with `note:`).
    #[getter]
    fn notes(&self) -> Vec<String> {
        self.notes.clone()
    }

    /// The sense checks' warnings (as `hullskin fit` prints them with `warning:`).
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.iter().map(ToString::to_string).collect()
    }

    /// These offsets with x, y and z multiplied by `x`, `y` and `z` (a hull stretched in
    /// length, breadth and depth; the perpendiculars follow x).
    #[pyo3(signature = (x = 1.0, y = 1.0, z = 1.0))]
    fn scaled(&self, x: f64, y: f64, z: f64) -> PyResult<Self> {
        for (name, k) in [("x", x), ("y", y), ("z", z)] {
            if !(k.is_finite() && k > 0.0) {
                return Err(bad_arg(format!("{name}: {k} is not a scale factor (expected a positive number)")));
            }
        }
        let mut out = self.clone();
        for s in &mut out.offsets.sections {
            for p in &mut s.points {
                *p = nurbs::Vec3::new(p.x * x, p.y * y, p.z * z);
            }
        }
        out.offsets.perpendiculars = self
            .offsets
            .perpendiculars
            .map(|p| Perpendiculars::try_new(p.aft * x, p.lpp() * x))
            .transpose()
            .map_err(to_py)?;
        out.offsets.source = format!("{} scaled by ({x}, {y}, {z})", self.offsets.source);
        out.warnings.clear();
        Ok(out)
    }

    fn __len__(&self) -> usize {
        self.offsets.sections.len()
    }

    fn __repr__(&self) -> String {
        format!(
            "<hullskin.Offsets {}: {} sections, {} points, {}>",
            self.offsets.source,
            self.offsets.sections.len(),
            self.offsets.num_points(),
            self.offsets.units.symbol()
        )
    }

    /// Pickled as its sections (the notes and warnings of the reading are kept).
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = slf.py();
        let me = slf.get();
        let sections: Vec<Vec<[f64; 3]>> =
            me.offsets.sections.iter().map(|s| s.points.iter().map(|p| [p.x, p.y, p.z]).collect()).collect();
        let state = (
            sections,
            me.offsets.units.symbol(),
            me.labels(),
            me.offsets.source.clone(),
            me.perpendiculars(),
            me.notes.clone(),
            me.warnings.iter().map(warning_state).collect::<Vec<_>>(),
        );
        let f = py.import("hullskin._hullskin")?.getattr("_offsets_from_state")?;
        Ok((f, state.into_pyobject(py)?.into_any()))
    }
}

/// The perpendiculars at x = `aft` and `fore` (exactly those values).
pub fn perpendiculars_of((aft, fore): (f64, f64)) -> PyResult<Perpendiculars> {
    Perpendiculars::try_new(aft, fore - aft)
        .map(|_| Perpendiculars { aft, fore })
        .map_err(|_| bad_arg(format!("perpendiculars ({aft}, {fore}): expected finite (AP x, FP x) with FP > AP")))
}

/// A sense warning as plain values: file, line, column, kind, value, message.
type WarningState = (String, Option<usize>, Option<usize>, usize, f64, String);

/// Every kind of sense warning, in a fixed order (their pickled index).
const SENSE_KINDS: [SenseKind; 5] =
    [SenseKind::UnitsInHeader, SenseKind::Size, SenseKind::Transposed, SenseKind::Outlier, SenseKind::Spacing];

fn warning_state(w: &SenseWarning) -> WarningState {
    let kind = SENSE_KINDS.iter().position(|k| *k == w.kind).unwrap_or(0);
    (w.at.file.clone(), w.at.line, w.at.column, kind, w.value, w.message.clone())
}

fn warning_from_state((file, line, column, kind, value, message): WarningState) -> PyResult<SenseWarning> {
    let kind =
        *SENSE_KINDS.get(kind).ok_or_else(|| bad_arg(format!("pickled offsets: unknown warning kind {kind}")))?;
    Ok(SenseWarning { at: hull::Location { file, line, column }, kind, value, message })
}

/// Rebuild pickled offsets.
#[pyfunction]
pub fn _offsets_from_state(
    sections: Vec<Vec<[f64; 3]>>,
    units: &str,
    labels: Vec<String>,
    source: String,
    perpendiculars: Option<(f64, f64)>,
    notes: Vec<String>,
    warnings: Vec<WarningState>,
) -> PyResult<PyOffsets> {
    let secs = sections
        .into_iter()
        .zip(labels)
        .map(|(pts, label)| Section::new(label, pts.into_iter().map(|[x, y, z]| nurbs::Vec3::new(x, y, z)).collect()))
        .collect();
    let mut offsets = Offsets::new(source, options::units(units)?, secs);
    offsets.perpendiculars = perpendiculars.map(perpendiculars_of).transpose()?;
    let warnings = warnings.into_iter().map(warning_from_state).collect::<PyResult<_>>()?;
    Ok(PyOffsets { offsets, notes, warnings })
}

/// Read offsets: a sections CSV, an offset table, a Series 60 table, a long CSV, a JSON table,
/// a point cloud or a FREE!ship text, recognised by content (as `hullskin fit FILE`); without a
/// path, the built-in Series 60 Cb 0.60 parent.
#[pyfunction]
#[pyo3(signature = (path = None, units = "m", lpp = None, beam = None, design_draft = None, outliers = "warn", degree_u = 3))]
pub fn read_offsets(
    py: Python<'_>,
    path: Option<PathBuf>,
    units: &str,
    lpp: Option<f64>,
    beam: Option<f64>,
    design_draft: Option<f64>,
    outliers: &str,
    degree_u: usize,
) -> PyResult<PyOffsets> {
    let options = read_options(units, lpp, beam, design_draft, outliers, degree_u)?;
    py.detach(|| PyOffsets::read(path, &options))
}
