//! Python arguments turned into the library's settings, with the command line's defaults
//! (`crates/cli/src/skin_args.rs`, `optim_args.rs`), so that `hullskin.fit(...)` and
//! `hullskin fit ...` with the same values fit the same surface. Every bad value is a
//! `ValueError` naming the argument and what was expected.

use hull::{Fairing, FitConfig, FitMethod, OptimSettings, Units, WeightLayout, WeightMode, WeightOptions};
use nurbs::fit::{CornerOptions, SkinParameterization};
use pyo3::exceptions::PyTypeError;
use pyo3::prelude::*;

use crate::errors::bad_arg;

/// `units`: `m`, `mm`, `ft` or `in`.
pub fn units(s: &str) -> PyResult<Units> {
    s.parse().map_err(|e: hull::HullError| bad_arg(format!("units: {e}")))
}

/// `method`: interp, approx, ga, pso, gsa, lm or gsa+lm.
pub fn method(s: &str) -> PyResult<FitMethod> {
    s.parse().map_err(|e: String| bad_arg(format!("method: {e}")))
}

/// `fair`: `"auto"`, 0 (the plain least squares) or a weight `λ > 0`.
pub fn fairing(fair: &Bound<'_, PyAny>) -> PyResult<Fairing> {
    if let Ok(s) = fair.extract::<String>() {
        if s.trim().eq_ignore_ascii_case("auto") {
            return Ok(Fairing::Auto { tolerance: None });
        }
        return Err(bad_arg(format!(
            "fair: `{s}` is not a fairness setting (expected \"auto\", 0 or a number > 0 such as 1e-3)"
        )));
    }
    let l: f64 = fair
        .extract()
        .map_err(|_| PyTypeError::new_err("fair: expected \"auto\" or a number (0: the plain least squares)"))?;
    match l {
        0.0 => Ok(Fairing::Off),
        l if l > 0.0 && l.is_finite() => Ok(Fairing::Lambda(l)),
        _ => Err(bad_arg(format!("fair: {l} is not a fairness weight (expected \"auto\", 0, or a finite number > 0)"))),
    }
}

/// A pair of counts (`ctrl`, `degree`).
pub fn pair(name: &str, v: (i64, i64)) -> PyResult<(usize, usize)> {
    let c = |x: i64| {
        usize::try_from(x).map_err(|_| bad_arg(format!("{name}: {x} is negative (expected ({name}_u, {name}_v) >= 0)")))
    };
    Ok((c(v.0)?, c(v.1)?))
}

/// The skinning and optimisation arguments of `fit`, as the command line takes them.
pub struct FitArgs<'a> {
    pub method: &'a str,
    pub ctrl: Option<(i64, i64)>,
    pub degree: (i64, i64),
    pub param: &'a str,
    pub fair: &'a Bound<'a, PyAny>,
    pub knuckles: &'a str,
    pub corner_angle: f64,
    pub envelope: &'a str,
    pub seed: u64,
    pub iterations: Option<usize>,
    pub population: Option<usize>,
    pub weights: &'a str,
    pub control_points: &'a str,
    pub param_correction: bool,
    pub fitted_params: bool,
}

impl FitArgs<'_> {
    /// The library's settings (`SkinArgs::fit_config` of the command line).
    pub fn config(&self) -> PyResult<FitConfig> {
        let param: SkinParameterization = self.param.parse().map_err(|e| bad_arg(format!("param: {e}")))?;
        if !(self.corner_angle > 0.0 && self.corner_angle < 180.0) {
            return Err(bad_arg(format!(
                "corner_angle: {} is out of range (expected degrees between 0 and 180, exclusive)",
                self.corner_angle
            )));
        }
        let corner = CornerOptions { min_angle_deg: self.corner_angle, ..CornerOptions::default() };
        let knuckles = self
            .knuckles
            .parse::<hull::KnuckleChoice>()
            .map_err(|e| bad_arg(format!("knuckles: {e}")))?
            .knuckles(corner);
        let (envelope, hold_on) =
            self.envelope.parse::<hull::EnvelopeChoice>().map_err(|e| bad_arg(format!("envelope: {e}")))?.settings();
        let layout: WeightLayout = self.weights.parse().map_err(|e| bad_arg(format!("weights: {e}")))?;
        let mode: WeightMode = self.control_points.parse().map_err(|e| bad_arg(format!("control_points: {e}")))?;
        let optim = OptimSettings {
            seed: self.seed,
            iterations: self.iterations,
            population: self.population,
            weights: WeightOptions { mode, layout, ..WeightOptions::default() },
            parameter_correction: self.param_correction,
            foot_point_start: !self.fitted_params,
        };
        Ok(FitConfig {
            method: method(self.method)?,
            degree: pair("degree", self.degree)?,
            ctrl: self.ctrl.map(|c| pair("ctrl", c)).transpose()?,
            param,
            optim,
            knuckles,
            fair: fairing(self.fair)?,
            smoothing: 0.0,
            envelope,
            hold_on,
            ..FitConfig::default()
        })
    }
}
