//! `hullskin.fit` and `hullskin.Fit`: offsets fitted as `hullskin fit` fits them
//! (`crates/cli/src/fit.rs`: [`hull::fit_offsets_within`], the held-out refits of
//! [`hull::held_out_refit_config`], [`hull::overfitting_warning`], [`hull::Report`]), without
//! the GIL and stoppable by Ctrl-C.

use std::path::PathBuf;

use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::errors::{bad_arg, to_py};
use crate::offsets::{read_options, PyOffsets};
use crate::options::FitArgs;
use crate::surface::PySurface;

/// A fitted surface with its report: the same figures as `hullskin fit --json` (report.json).
#[pyclass(module = "hullskin", name = "Fit", frozen)]
pub struct PyFit {
    surface: Py<PySurface>,
    offsets: Py<PyOffsets>,
    /// report.json's text.
    report: String,
    /// What `hullskin fit` prints as warnings (sense checks, validity, over-fitting, no
    /// held-out error).
    warnings: Vec<String>,
}

/// What a fit returns before it becomes Python objects.
struct Outcome {
    surface: nurbs::NurbsSurface,
    report: String,
    warnings: Vec<String>,
}

/// The command line's `fit` on `offsets` (after its reading), with `folds` held-out folds.
fn run_fit(
    offsets: &PyOffsets,
    config: &hull::FitConfig,
    goal: hull::Goal,
    folds: usize,
    control: &hull::Control<'_>,
) -> Result<Outcome, hull::HullError> {
    let o = &offsets.offsets;
    let (mut outcome, search) = hull::fit_offsets_within(o, config, goal, control)?;
    let mut warnings = Vec::new();
    let options = hull::HeldOutOptions::with_folds(folds);
    if hull::held_out_wanted(&mut outcome, &options) && !control.stopped() {
        outcome.error.held_out =
            match hull::held_out_for_config_with(o, &hull::held_out_refit_config(&outcome), &options, control) {
                Ok(h) => h,
                Err(e) => {
                    warnings.push(format!("no held-out error: {e}"));
                    None
                }
            };
    }
    let mut report = hull::Report::new(o, &outcome);
    report.input.warnings = offsets.warnings.clone();
    report.tolerance_search = search;
    let overfit = hull::overfitting_warning(o, &outcome);
    report.overfitting = overfit.as_ref().map(|l| l.trim_start_matches("warning: ").to_string());
    let mut all: Vec<String> = offsets.warnings.iter().map(ToString::to_string).collect();
    all.extend(hull::summary_warnings(o, &outcome));
    all.extend(warnings);
    all.extend(report.overfitting.clone());
    // A report holds numbers, strings and lists only: serde_json cannot refuse it.
    let text = serde_json::to_string_pretty(&report).expect("a report of numbers and strings serializes");
    Ok(Outcome { surface: outcome.surface, report: text, warnings: all })
}

/// Fit one NURBS surface to offsets, as `hullskin fit` does with the same arguments.
///
/// `offsets_or_path`: a `hullskin.Offsets`, a path read as `hullskin fit PATH` reads it (with
/// `units`, `lpp`, `beam`, `design_draft`, `outliers`), or None for the built-in Series 60
/// Cb 0.60 parent. `method`: interp, approx, ga, pso, gsa, lm or gsa+lm. `ctrl`: control
/// points (nu, nv) (default three quarters of the offsets); `tolerance`: the fewest control
/// points whose max error is within it instead, or "default" for 0.5 % of the beam (as
/// `hullskin fit --tolerance default`). `seed`, `iterations`, `population`,
/// `weights` (full, rank1), `control_points` (resolved, fixed), `param_correction`,
/// `fitted_params`: the weight optimisers'. `degree` (p, q), `param`, `fair` ("auto", 0 or
/// a weight; None is "auto"), `knuckles` (auto, auto+flats, off), `corner_angle`, `envelope`
/// (hold, free): the skinning's. `held_out`: folds of the held-out error (0: none).
///
/// Returns a `hullskin.Fit`: `.surface`, `.report` (report.json), `.error`, `.validity`,
/// `.timings`, `.warnings`. Runs without the GIL; Ctrl-C raises KeyboardInterrupt.
#[pyfunction]
#[pyo3(signature = (
    offsets_or_path = None, *, method = "approx", ctrl = None, tolerance = None, seed = 1, iterations = None,
    population = None, degree = (3, 3), param = "centripetal,chord", fair = None, knuckles = "auto",
    corner_angle = 30.0, envelope = "hold", weights = "full", control_points = "resolved", param_correction = false,
    fitted_params = false, held_out = 4, units = "m", lpp = None, beam = None, design_draft = None, outliers = "warn"
))]
pub fn fit(
    py: Python<'_>,
    offsets_or_path: Option<&Bound<'_, PyAny>>,
    method: &str,
    ctrl: Option<(i64, i64)>,
    tolerance: Option<&Bound<'_, PyAny>>,
    seed: u64,
    iterations: Option<usize>,
    population: Option<usize>,
    degree: (i64, i64),
    param: &str,
    fair: Option<&Bound<'_, PyAny>>,
    knuckles: &str,
    corner_angle: f64,
    envelope: &str,
    weights: &str,
    control_points: &str,
    param_correction: bool,
    fitted_params: bool,
    held_out: usize,
    units: &str,
    lpp: Option<f64>,
    beam: Option<f64>,
    design_draft: Option<f64>,
    outliers: &str,
) -> PyResult<PyFit> {
    let auto = pyo3::types::PyString::new(py, "auto").into_any();
    let fair = fair.unwrap_or(&auto);
    let goal = match tolerance {
        None => hull::Goal::Count,
        Some(t) if t.is_instance_of::<pyo3::types::PyString>() => {
            t.extract::<String>()?.parse::<hull::Goal>().map_err(|e| bad_arg(format!("tolerance: {e}")))?
        }
        Some(t) => hull::Goal::Tolerance(t.extract::<f64>().map_err(|_| {
            PyTypeError::new_err("tolerance: expected a number (a max error in the input's units) or \"default\"")
        })?),
    };
    let args = FitArgs {
        method,
        ctrl,
        degree,
        param,
        fair,
        knuckles,
        corner_angle,
        envelope,
        seed,
        iterations,
        population,
        weights,
        control_points,
        param_correction,
        fitted_params,
    };
    let config = args.config()?;
    if held_out == 1 {
        return Err(bad_arg("held_out: 1 fold would hold out every offset (expected 0 to turn it off, or at least 2)"));
    }
    if let hull::Goal::Tolerance(t) = goal {
        if !(t.is_finite() && t > 0.0) {
            return Err(bad_arg(format!("tolerance {t}: expected a positive length")));
        }
    }
    if goal != hull::Goal::Count && ctrl.is_some() {
        return Err(bad_arg("tolerance searches the control-point counts: give tolerance or ctrl, not both"));
    }
    let offsets = match offsets_or_path {
        Some(o) if o.is_instance_of::<PyOffsets>() => o.cast::<PyOffsets>()?.get().clone(),
        Some(o) if o.is_none() => PyOffsets::read(None, &hull::ReadOptions::default())?,
        Some(o) => {
            let path: PathBuf = o.extract().map_err(|_| {
                PyTypeError::new_err("offsets_or_path: expected hullskin.Offsets, a path (str or os.PathLike) or None")
            })?;
            let options = read_options(units, lpp, beam, design_draft, outliers, config.degree.0)?;
            py.detach(|| PyOffsets::read(Some(path), &options))?
        }
        None => PyOffsets::read(None, &hull::ReadOptions::default())?,
    };
    let out =
        crate::interrupt::run(py, |control| run_fit(&offsets, &config, goal, held_out, control))?.map_err(to_py)?;
    let source = format!("{}, fitted by {}", offsets.offsets.source, config.method.name());
    let surface = PySurface {
        surface: out.surface,
        units: offsets.offsets.units,
        source,
        perpendiculars: offsets.offsets.perpendiculars,
    };
    Ok(PyFit {
        surface: Py::new(py, surface)?,
        offsets: Py::new(py, offsets)?,
        report: out.report,
        warnings: out.warnings,
    })
}

fn json_loads<'py>(py: Python<'py>, text: &str) -> PyResult<Bound<'py, PyAny>> {
    py.import("json")?.call_method1("loads", (text,))
}

#[pymethods]
impl PyFit {
    /// The fitted surface.
    #[getter]
    fn surface(&self, py: Python<'_>) -> Py<PySurface> {
        self.surface.clone_ref(py)
    }

    /// The offsets fitted.
    #[getter]
    fn offsets(&self, py: Python<'_>) -> Py<PyOffsets> {
        self.offsets.clone_ref(py)
    }

    /// report.json as a dict (as `hullskin fit --json` prints it).
    #[getter]
    fn report<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        json_loads(py, &self.report)
    }

    /// The true error (closest-point distances, in the offsets' units): `max`, `mean`, `rms`,
    /// `worst`, `per_section`, and `held_out` where computed (report.json's `error`).
    #[getter]
    fn error<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.report(py)?.get_item("error")
    }

    /// The validity findings (folds, leaving the envelope, bulges, inward facets); empty when
    /// the surface is valid.
    #[getter]
    fn validity<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.report(py)?.get_item("validity")
    }

    /// Seconds: `seconds` (fit and error), `fit_seconds`, `error_seconds`, and
    /// `held_out_seconds` where a held-out error was computed.
    #[getter]
    fn timings<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let r = self.report(py)?;
        let out = pyo3::types::PyDict::new(py);
        for key in ["seconds", "fit_seconds", "error_seconds"] {
            out.set_item(key, r.get_item(key)?)?;
        }
        if let Ok(h) = r.get_item("error")?.get_item("held_out") {
            if !h.is_none() {
                out.set_item("held_out_seconds", h.get_item("seconds")?)?;
            }
        }
        Ok(out)
    }

    /// The method's name (report.json's `method`).
    #[getter]
    fn method<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        self.report(py)?.get_item("method")
    }

    /// The warnings `hullskin fit` prints for this fit.
    #[getter]
    fn warnings(&self) -> Vec<String> {
        self.warnings.clone()
    }

    /// report.json's text.
    fn to_json(&self) -> String {
        self.report.clone()
    }

    fn __repr__(&self, py: Python<'_>) -> PyResult<String> {
        let e = self.error(py)?;
        Ok(format!(
            "<hullskin.Fit {} of {}: max error {}, RMS {}>",
            self.method(py)?,
            self.offsets.get().offsets.source,
            e.get_item("max")?,
            e.get_item("rms")?
        ))
    }

    /// Pickled as its surface, offsets, report and warnings.
    fn __reduce__<'py>(slf: &Bound<'py, Self>) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyAny>)> {
        let py = slf.py();
        let me = slf.get();
        let f = py.import("hullskin._hullskin")?.getattr("_fit_from_state")?;
        let state = (me.surface.clone_ref(py), me.offsets.clone_ref(py), me.report.clone(), me.warnings.clone());
        Ok((f, state.into_pyobject(py)?.into_any()))
    }
}

/// Rebuild a pickled fit.
#[pyfunction]
pub fn _fit_from_state(surface: Py<PySurface>, offsets: Py<PyOffsets>, report: String, warnings: Vec<String>) -> PyFit {
    PyFit { surface, offsets, report, warnings }
}
