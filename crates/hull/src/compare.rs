//! The comparison table: skinning interpolation, the plain skinning approximation, and the
//! approximation with its weights optimised by GA, PSO, GSA, Levenberg-Marquardt and GSA then
//! LM, all at the same control points, with their true error, Gaussian curvature range, time
//! and objective evaluations, and the floors of issue 3 checked on the result (on these rows,
//! all with `--fair 0 --envelope free`, the plain objective); then the fair fits of the default
//! `--fair auto --envelope hold` ([`FAIR_ROWS`]: `approx+fair`, `lm+fair`), as `hullskin fit`
//! makes them (at the default count and parameterization `approx+fair` is the default fit, its
//! held-out referee included).
//!
//! The rest of this module's documentation is on [`compare_offsets`], where the library's users read it.

use std::fmt::Write as _;

use nurbs::fit::SkinParameterization;
use serde::Serialize;

use crate::analysis::{Finding, FindingKind};
use crate::curvature_range::{gaussian_curvature_range, CurvatureRange, CURVATURE_GRID};
use crate::fit_error::parametric_residuals;
use crate::optimize::{quiet, Algorithm, Control, OptimSettings, StopReason};
use crate::Offsets;
use crate::{
    fit_offsets, fit_offsets_with, held_out_for_config_with, held_out_refit_config, FitConfig, FitMethod, FitOutcome,
    HeldOutOptions,
};
use crate::{HullError, InputSummary};

/// Relative slack of the "at or below" floor: two solvers reaching the same optimum agree to
/// round-off, not bit for bit.
pub const FLOOR_RELATIVE_TOLERANCE: f64 = 1e-9;

/// The methods of the table, in its order.
pub const COMPARE_METHODS: [FitMethod; 7] = [
    FitMethod::Interp,
    FitMethod::Approx,
    FitMethod::Optimized(Algorithm::Ga),
    FitMethod::Optimized(Algorithm::Pso),
    FitMethod::Optimized(Algorithm::Gsa),
    FitMethod::Optimized(Algorithm::Lm),
    FitMethod::Optimized(Algorithm::GsaLm),
];

/// The rows after [`COMPARE_METHODS`]: the approximation and LM with `--fair auto`
/// ([`Fairing::Auto`](crate::Fairing::Auto)), named so.
pub const FAIR_ROWS: [(&str, FitMethod); 2] =
    [("approx+fair", FitMethod::Approx), ("lm+fair", FitMethod::Optimized(Algorithm::Lm))];

/// Settings of [`compare_offsets`]: those of [`FitConfig`] but the method, shared by all rows.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CompareConfig {
    /// Degrees `(p, q)` along and across the sections.
    pub degree: (usize, usize),
    /// Control points `(NU, NV)` of the approximations; `None` picks [`default_ctrl`](crate::default_ctrl).
    pub ctrl: Option<(usize, usize)>,
    pub param: SkinParameterization,
    pub optim: OptimSettings,
    /// Cross-validate every row with these options (its degrees are the rows'); `None`: no
    /// held-out error.
    pub held_out: Option<HeldOutOptions>,
}

impl Default for CompareConfig {
    fn default() -> Self {
        Self::new()
    }
}

impl CompareConfig {
    /// The settings with the default fit configuration (degrees 3, 3).
    pub fn new() -> Self {
        let d = FitConfig::default();
        CompareConfig { degree: d.degree, ctrl: d.ctrl, param: d.param, optim: d.optim, held_out: None }
    }

    fn fit_config(self, method: FitMethod) -> FitConfig {
        FitConfig {
            method,
            degree: self.degree,
            ctrl: self.ctrl,
            param: self.param,
            optim: self.optim,
            // The methods themselves, not held within the envelope (their findings are in
            // the validity column); the fair rows hold.
            envelope: crate::EnvelopeHold::Free,
            ..FitConfig::default()
        }
    }
}

/// The error columns of a row: true distances, plus the parametric RMS at the fit's parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct RowError {
    pub max: f64,
    pub mean: f64,
    pub rms: f64,
    pub parametric_rms: f64,
}

/// How a row's run ended.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RowStatus {
    Done,
    /// Stopped by the user; the best surface found before is measured.
    Interrupted,
    /// The method failed (see `failure`).
    Failed,
}

/// Whether a row's surface is valid.
#[derive(Clone, Debug, PartialEq, Eq, Serialize)]
pub struct RowValidity {
    /// No finding.
    pub valid: bool,
    /// The number of findings.
    pub findings: usize,
    /// The kinds found, each once, in the order of [`FindingKind`].
    pub kinds: Vec<FindingKind>,
}

impl RowValidity {
    /// The summary of `findings`.
    pub fn of(findings: &[Finding]) -> Self {
        let mut kinds: Vec<FindingKind> = findings.iter().map(|f| f.kind).collect();
        kinds.sort();
        kinds.dedup();
        RowValidity { valid: findings.is_empty(), findings: findings.len(), kinds }
    }

    /// `valid`, or the count and the kinds (`2: fold, below_centre_plane`).
    pub fn label(&self) -> String {
        if self.valid {
            return "valid".into();
        }
        let kinds: Vec<&str> = self.kinds.iter().map(|k| k.name()).collect();
        format!("{}: {}", self.findings, kinds.join(", "))
    }
}

/// One method of the comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareRow {
    pub method: &'static str,
    pub status: RowStatus,
    /// The error message of a failed method.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub failure: Option<String>,
    /// `[NU, NV]` of the surface (asked for, if the method failed).
    pub control_points: [usize; 2],
    /// The parameterization the surface was fitted on (asked for, if the method failed): a
    /// fair row's may be another than the comparison's when the default one was unsound
    /// ([`crate::ALTERNATIVE_PARAMETERIZATIONS`]).
    pub parameterization: &'static str,
    /// What its envelope hold held, `net` or `surface`: a fair row's surface is held when the
    /// net-held one was unsound or less fair for its hold (left out for `net`).
    #[serde(skip_serializing_if = "is_net")]
    pub hold: crate::HoldOn,
    /// `None` if the method failed.
    pub error: Option<RowError>,
    /// `None` if the method failed or the whole surface is degenerate.
    pub gaussian_curvature: Option<CurvatureRange>,
    /// Fit time (skinning and optimisation), seconds.
    pub seconds: f64,
    /// Error measurement time, seconds.
    pub error_seconds: f64,
    pub evaluations: usize,
    pub iterations: usize,
    /// The optimisers' seed (`None` for interp and approx).
    pub seed: Option<u64>,
    /// The optimiser's objective `[start, final]` (parametric RMS with the log-weight penalty).
    pub objective: Option<[f64; 2]>,
    /// RMS of the held-out error (cross-validation), when computed.
    pub held_out_rms: Option<f64>,
    /// Max of the held-out error, when computed.
    pub held_out_max: Option<f64>,
    /// Lower error at the offsets than `approx` but higher held-out error; `None` when not
    /// known (and for `approx`).
    pub overfit: Option<bool>,
    /// Whether the surface is valid (`None` if the method failed).
    pub validity: Option<RowValidity>,
}

impl CompareRow {
    /// The row of a finished fit.
    pub fn from_outcome(offsets: &Offsets, outcome: &FitOutcome) -> Self {
        let s = &outcome.surface;
        let e = &outcome.error.overall;
        let points: Vec<nurbs::Vec3> = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
        let params: Vec<(f64, f64)> = outcome.params.iter().flatten().copied().collect();
        let r = parametric_residuals(s, &points, &params);
        let parametric_rms = (r.iter().map(|d| d * d).sum::<f64>() / r.len().max(1) as f64).sqrt();
        let opt = outcome.optimization.as_ref();
        CompareRow {
            method: outcome.config.method.name(),
            status: match opt.map(|o| o.stop) {
                Some(StopReason::Interrupted) => RowStatus::Interrupted,
                _ => RowStatus::Done,
            },
            failure: None,
            control_points: [s.n_u(), s.n_v()],
            parameterization: outcome.config.param.name(),
            hold: outcome.config.hold_on,
            error: Some(RowError { max: e.max, mean: e.mean, rms: e.rms, parametric_rms }),
            gaussian_curvature: gaussian_curvature_range(s, CURVATURE_GRID),
            seconds: outcome.fit_seconds,
            error_seconds: outcome.error_seconds,
            evaluations: opt.map_or(0, |o| o.evaluations),
            iterations: opt.map_or(0, |o| o.iterations),
            seed: opt.map(|o| o.seed),
            objective: opt.map(|o| [o.start_value, o.final_value]),
            held_out_rms: outcome.error.held_out.as_ref().map(|h| h.rms),
            held_out_max: outcome.error.held_out.as_ref().map(|h| h.max),
            overfit: None,
            validity: Some(RowValidity::of(&outcome.validity)),
        }
    }

    /// The row of a method that failed with `error`.
    pub fn failed(
        method: FitMethod,
        control_points: (usize, usize),
        parameterization: &'static str,
        seed: Option<u64>,
        error: &HullError,
    ) -> Self {
        CompareRow {
            method: method.name(),
            status: RowStatus::Failed,
            failure: Some(error.to_string()),
            control_points: [control_points.0, control_points.1],
            parameterization,
            hold: crate::HoldOn::Net,
            error: None,
            gaussian_curvature: None,
            seconds: 0.0,
            error_seconds: 0.0,
            evaluations: 0,
            iterations: 0,
            seed,
            objective: None,
            held_out_rms: None,
            held_out_max: None,
            overfit: None,
            validity: None,
        }
    }

    fn done_rms(&self) -> Option<f64> {
        match self.status {
            RowStatus::Done => self.error.map(|e| e.rms),
            _ => None,
        }
    }
}

/// One floor of issue 3 on one comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FloorCheck {
    /// What must hold, e.g. `ga < approx`.
    pub floor: String,
    /// `None` when it could not be checked (a method interrupted or not run).
    pub holds: Option<bool>,
    /// The left side (RMS error), when known.
    pub value: Option<f64>,
    /// The right side (RMS error), when known.
    pub bound: Option<f64>,
}

/// The floors of issue 3 on one comparison.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Floors {
    /// The error compared: `"rms"` (true closest-point RMS).
    pub metric: &'static str,
    pub relative_tolerance: f64,
    /// `Some(true)` if every check holds, `Some(false)` if any fails, `None` otherwise.
    pub all_hold: Option<bool>,
    pub checks: Vec<FloorCheck>,
}

/// The state of one method for the floors: its RMS if done, failed, or unknown.
#[derive(Clone, Copy)]
enum Known {
    Rms(f64),
    Failed,
    Unknown,
}

fn known(rows: &[CompareRow], name: &str) -> Known {
    match rows.iter().find(|r| r.method == name) {
        Some(r) if r.status == RowStatus::Failed => Known::Failed,
        Some(r) => r.done_rms().map_or(Known::Unknown, Known::Rms),
        None => Known::Unknown,
    }
}

/// The smallest RMS of the methods `names` that are done (a failed method has no say), unknown
/// if `all_needed` and any is unknown (interrupted or not run); failed if none is done and none
/// unknown.
fn best(rows: &[CompareRow], names: &[&str], all_needed: bool) -> Known {
    let mut best: Option<f64> = None;
    let (mut failed, mut unknown) = (false, false);
    for n in names {
        match known(rows, n) {
            Known::Rms(v) => best = Some(best.map_or(v, |b: f64| b.min(v))),
            Known::Failed => failed = true,
            Known::Unknown => unknown = true,
        }
    }
    match (best, failed, unknown) {
        (_, _, true) if all_needed => Known::Unknown,
        (Some(b), _, _) => Known::Rms(b),
        (None, _, true) => Known::Unknown,
        (None, _, false) => Known::Failed,
    }
}

/// Check the floors of issue 3 on `rows` (see [`compare_offsets`]): `ga`, `pso` and `gsa` each
/// strictly below `approx` in true RMS error; `min(lm, gsa+lm) <= min(ga, pso, gsa)` within
/// [`FLOOR_RELATIVE_TOLERANCE`]. The best of the three is over those done and needs none
/// interrupted or missing; the better of the local two needs one of them done, but an
/// interrupted or missing one leaves a failure unchecked. A failed method fails its floor.
pub fn check_floors(rows: &[CompareRow]) -> Floors {
    fn check(floor: String, a: Known, b: Known, holds: impl Fn(f64, f64) -> bool) -> FloorCheck {
        let (value, bound) =
            (if let Known::Rms(v) = a { Some(v) } else { None }, if let Known::Rms(v) = b { Some(v) } else { None });
        let holds = match (a, b) {
            (Known::Rms(x), Known::Rms(y)) => Some(holds(x, y)),
            (Known::Failed, _) => Some(false),
            _ => None,
        };
        FloorCheck { floor, holds, value, bound }
    }
    let approx = known(rows, "approx");
    let mut checks: Vec<FloorCheck> = ["ga", "pso", "gsa"]
        .into_iter()
        .map(|m| check(format!("{m} < approx"), known(rows, m), approx, |x, y| x < y))
        .collect();
    let evo = best(rows, &["ga", "pso", "gsa"], true);
    let mut local = best(rows, &["lm", "gsa+lm"], false);
    // One local method unknown and the known one above the bound: not checked yet.
    let any_local_unknown =
        matches!(known(rows, "lm"), Known::Unknown) || matches!(known(rows, "gsa+lm"), Known::Unknown);
    if let (Known::Rms(l), Known::Rms(e), true) = (local, evo, any_local_unknown) {
        if l > e * (1.0 + FLOOR_RELATIVE_TOLERANCE) {
            local = Known::Unknown;
        }
    }
    checks.push(check("min(lm, gsa+lm) <= min(ga, pso, gsa)".into(), local, evo, |x, y| {
        x <= y * (1.0 + FLOOR_RELATIVE_TOLERANCE)
    }));
    let all_hold = if checks.iter().any(|c| c.holds == Some(false)) {
        Some(false)
    } else if checks.iter().all(|c| c.holds == Some(true)) {
        Some(true)
    } else {
        None
    };
    Floors { metric: "rms", relative_tolerance: FLOOR_RELATIVE_TOLERANCE, all_hold, checks }
}

/// The optimisation settings shared by the rows, for `compare.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CompareOptimization {
    /// `None`: each algorithm's default.
    pub iterations: Option<usize>,
    pub population: Option<usize>,
    pub control_points: &'static str,
    pub weight_layout: &'static str,
    pub parameter_correction: bool,
    /// Where the offsets' parameters started: `"foot_points"` on the plain approximation, or
    /// `"fitted"` (the skinning's own).
    pub start_parameters: &'static str,
}

/// How the curvature was sampled, for `compare.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurvatureSampling {
    pub grid: usize,
    pub knot_lines: bool,
}

/// `compare.json`: the comparison of all methods on one input.
#[derive(Clone, Debug, Serialize)]
pub struct Comparison {
    pub hullskin: &'static str,
    pub input: InputSummary,
    pub degree: [usize; 2],
    /// `[NU, NV]` of the approximations (interp has its own, in its row).
    pub control_points: [usize; 2],
    pub parameterization: &'static str,
    pub seed: u64,
    pub optimization: CompareOptimization,
    pub curvature_sampling: CurvatureSampling,
    /// False if the comparison was interrupted.
    pub complete: bool,
    /// Methods not run because of an interruption.
    pub not_run: Vec<&'static str>,
    /// K of the rows' held-out errors (`None`: not computed).
    pub held_out_folds: Option<usize>,
    pub methods: Vec<CompareRow>,
    pub floors: Floors,
}

/// Whether a row's hold is the default one (left out of `compare.json`).
fn is_net(hold: &crate::HoldOn) -> bool {
    *hold == crate::HoldOn::Net
}

/// Run every method of [`COMPARE_METHODS`] on `offsets` without progress reports or stops.
///
/// `compare.json` layout (stable; later features add fields):
///
/// ```text
/// {"hullskin": "0.1.0",
///  "input": {"source": "...", "sections": K, "points": N, "units": "m"},
///  "degree": [P, Q], "control_points": [NU, NV], "parameterization": "centripetal,chord",
///  "seed": 1, "optimization": {"iterations": null, "population": null, "control_points": "resolved",
///                              "weight_layout": "full", "parameter_correction": false,
///                              "start_parameters": "foot_points"},
///  "curvature_sampling": {"grid": 41, "knot_lines": true},
///  "complete": true, "not_run": [],
///  "methods": [{"method": "interp", "status": "done", "control_points": [8, 25],
///               "parameterization": "centripetal,chord", ("hold": "surface", for a fair row
///               held on its surface, `CompareRow::hold`)
///               "error": {"max": .., "mean": .., "rms": .., "parametric_rms": ..},
///               "gaussian_curvature": {"max": .., "min": .., "max_at": [u, v], "min_at": [u, v],
///                                      "samples": n, "skipped": n},
///               "seconds": .., "error_seconds": .., "evaluations": 0, "iterations": 0,
///               "seed": null, "objective": null,
///               "held_out_rms": .., "held_out_max": .., "overfit": true,
///               "validity": {"valid": true, "findings": 0, "kinds": []}}, ...],
///  "held_out_folds": 4,
///  "floors": {"metric": "rms", "relative_tolerance": 1e-9, "all_hold": true,
///             "checks": [{"floor": "ga < approx", "holds": true, "value": .., "bound": ..}, ...]}}
/// ```
///
/// * `error`: the true distance of every offset to the surface by closest-point projection, in
///   the input's units ([`measure_fit_error`](crate::measure_fit_error)); `parametric_rms` is the
///   RMS of `|S(u_k, v_k) - Q_k|` at the fit's data parameters (an upper bound of `rms`).
/// * `gaussian_curvature`: `K = (LN - M^2) / (EG - F^2)` (1 / units^2) sampled on a
///   [`CURVATURE_GRID`] x [`CURVATURE_GRID`] uniform parameter grid joined with every distinct
///   interior knot in each direction (the knot lines, where the second derivatives of a
///   surface with repeated knots may jump); see [`gaussian_curvature_range`]. Degenerate points
///   (a pointed stem, where `S_u x S_v` vanishes and K is undefined) are skipped and counted.
/// * `seconds`: the fit itself (skinning, plus the weight optimisation), not the error
///   measurement (`error_seconds`), which costs the same for every method.
/// * `evaluations` and `iterations`: of the objective, 0 for `interp` and `approx`; `seed` and
///   `objective` (`[start, final]`, the optimiser's parametric RMS objective) only for the
///   optimised methods.
/// * `held_out_rms`, `held_out_max`: the error between the offsets by K-fold cross-validation
///   (`held_out_folds` = K; [`crate::held_out_for_config`]), `null` when not asked for, after a
///   stop or when a refit failed. `overfit`: the row is closer to the offsets than the plain
///   approximation but farther from the held-out ones (RMS; [`crate::overfit`]); `null`
///   without both held-out errors, and for `approx` itself.
/// * `validity`: whether the row's surface is valid: the number of findings of
///   [`check_fit_validity`](crate::analysis::check_fit_validity) (folds, leaving the offsets'
///   envelope, bulging through a flat, inward-facing facets) and their kinds, each once;
///   `null` for a failed method.
/// * `status`: `done`, `interrupted` (stopped by the user; the best surface found before the
///   stop is measured) or `failed` (with `failure`, the error message). On an interruption the
///   comparison stops: the methods after it are listed in `not_run` and `complete` is false.
///
/// Floors (issue 3), on the true RMS error: each of GA, PSO and GSA ends strictly below the
/// plain approximation, and the better of LM and GSA+LM ends at or below the best of the three
/// (within [`FLOOR_RELATIVE_TOLERANCE`], for round-off). A failed method fails its floors; an
/// interrupted or missing one leaves them unchecked (`holds: null`).
///
/// # Errors
/// As [`compare_offsets_with`].
pub fn compare_offsets(offsets: &Offsets, config: &CompareConfig) -> Result<Comparison, HullError> {
    compare_offsets_with(offsets, config, &mut |_, fit| quiet(|c| fit(c)))
}

/// A runner of one weight optimisation: called with the algorithm and the fit to run, it
/// calls the fit with a [`Control`] of its choice (a progress bar, a stop flag) and returns
/// its result.
pub type OptimRunner<'r> = dyn FnMut(Algorithm, &mut dyn FnMut(&Control<'_>) -> Result<FitOutcome, HullError>) -> Result<FitOutcome, HullError>
    + 'r;

/// Run every method of [`COMPARE_METHODS`] on `offsets` at the same control points, measure
/// each, and check the floors. Each weight optimisation goes through `run`, which supplies its
/// [`Control`]. When a run sees its stop flag raised, its row is measured from the best surface
/// found before the stop (status `interrupted` if the optimiser was cut short) and the
/// comparison ends there: the later methods are listed in `not_run`.
///
/// A failing interpolation or optimisation is recorded as a `failed` row and the comparison
/// goes on.
///
/// # Errors
/// [`HullError::Input`] if the offsets are invalid for the degrees, an error of the settings
/// ([`HullError::is_setting`]) for unusable settings, and any error of the plain approximation (e.g. [`HullError::Fit`] for
/// control-point counts out of range), on which all the optimised rows depend.
pub fn compare_offsets_with(
    offsets: &Offsets,
    config: &CompareConfig,
    run: &mut OptimRunner<'_>,
) -> Result<Comparison, HullError> {
    // The plain approximation first: it validates the input and the settings, and its failure
    // would fail every optimised row.
    let mut approx = fit_offsets(offsets, &config.fit_config(FitMethod::Approx))?;
    // A row's held-out error, `None` unless asked for, after a stop or if a refit fails (the
    // row itself stands). The refits are those `fit` makes ([`held_out_refit_config`]): a fair
    // row's at the smoothing its search chose, so the figure is that of the surface written, as
    // `fit` reports it, not of a search made again in every refit.
    let held_out = |outcome: &mut FitOutcome, control: &Control<'_>| {
        if let Some(options) = &config.held_out {
            // Not again where the default fit's held-out referee cross-validated it already.
            if crate::held_out_wanted(outcome, options) && !control.stopped() {
                let refits = held_out_refit_config(outcome);
                outcome.error.held_out = held_out_for_config_with(offsets, &refits, options, control).ok().flatten();
            }
        }
    };
    quiet(|control| held_out(&mut approx, control));
    let ctrl = (approx.surface.n_u(), approx.surface.n_v());
    let degree = [approx.surface.degree_u(), approx.surface.degree_v()];
    let mut rows = Vec::with_capacity(COMPARE_METHODS.len());
    let mut not_run = Vec::new();
    let mut stopped = false;
    for method in COMPARE_METHODS {
        if stopped {
            not_run.push(method.name());
            continue;
        }
        let cfg = config.fit_config(method);
        let row = match method {
            FitMethod::Approx => CompareRow::from_outcome(offsets, &approx),
            FitMethod::Interp => match fit_offsets(offsets, &cfg) {
                Ok(mut out) => {
                    quiet(|control| held_out(&mut out, control));
                    CompareRow::from_outcome(offsets, &out)
                }
                Err(e) if matches!(e, HullError::Input { .. }) || e.is_setting() => return Err(e),
                Err(e) => {
                    // What interpolation would have used: one pole per offset of the largest
                    // section, one per section.
                    let n_max = offsets.sections.iter().map(|s| s.points.len()).max().unwrap_or(0);
                    CompareRow::failed(method, (n_max, offsets.sections.len()), config.param.name(), None, &e)
                }
            },
            FitMethod::Optimized(algorithm) => {
                let mut saw_stop = false;
                let result = run(algorithm, &mut |control| {
                    let mut r = fit_offsets_with(offsets, &cfg, control);
                    if let Ok(out) = &mut r {
                        held_out(out, control);
                    }
                    saw_stop = control.stopped();
                    r
                });
                stopped = saw_stop;
                match result {
                    Ok(out) => CompareRow::from_outcome(offsets, &out),
                    Err(e) if e.is_setting() => return Err(e),
                    Err(e) => CompareRow::failed(method, ctrl, config.param.name(), Some(config.optim.seed), &e),
                }
            }
        };
        rows.push(row);
    }
    // The fair fits of the command line's default (`--fair auto`) as rows of their own: the
    // approximation and LM on the fair objective (LM's row is what `--method lm` writes, a sound
    // approximation when LM's surface was rejected).
    for (name, method) in FAIR_ROWS {
        if stopped {
            not_run.push(name);
            continue;
        }
        let cfg = FitConfig {
            fair: crate::Fairing::Auto { tolerance: None },
            envelope: crate::EnvelopeHold::Own,
            ..config.fit_config(method)
        };
        let mut saw_stop = false;
        // As `hullskin fit` makes it: at the default count and parameterization the fair
        // approximation is the default fit, refereed by its held-out error.
        let mut fit = |control: &Control<'_>| {
            let mut r = crate::fit_offsets_within(offsets, &cfg, crate::Goal::Count, control).map(|(out, _)| out);
            if let Ok(out) = &mut r {
                held_out(out, control);
            }
            saw_stop = control.stopped();
            r
        };
        let result = match method.algorithm() {
            Some(algorithm) => run(algorithm, &mut fit),
            None => quiet(|control| fit(control)),
        };
        stopped = saw_stop;
        let mut row = match result {
            Ok(out) => CompareRow::from_outcome(offsets, &out),
            Err(e) if e.is_setting() => return Err(e),
            Err(e) => {
                CompareRow::failed(method, ctrl, config.param.name(), method.algorithm().map(|_| config.optim.seed), &e)
            }
        };
        row.method = name;
        rows.push(row);
    }
    mark_overfitting(&mut rows);
    let o = &config.optim;
    Ok(Comparison {
        hullskin: env!("CARGO_PKG_VERSION"),
        input: InputSummary {
            source: offsets.source.clone(),
            sections: offsets.sections.len(),
            points: offsets.num_points(),
            units: offsets.units.symbol(),
            warnings: Vec::new(),
        },
        degree,
        control_points: [ctrl.0, ctrl.1],
        parameterization: config.param.name(),
        seed: o.seed,
        optimization: CompareOptimization {
            iterations: o.iterations,
            population: o.population,
            control_points: o.weights.mode.name(),
            weight_layout: o.weights.layout.name(),
            parameter_correction: o.parameter_correction,
            start_parameters: if o.foot_point_start && !o.parameter_correction { "foot_points" } else { "fitted" },
        },
        curvature_sampling: CurvatureSampling { grid: CURVATURE_GRID, knot_lines: true },
        complete: not_run.is_empty() && rows.iter().all(|r| r.status != RowStatus::Interrupted),
        not_run,
        held_out_folds: config.held_out.map(|h| h.folds),
        floors: check_floors(&rows),
        methods: rows,
    })
}

/// Mark the rows that over-fit against `approx` ([`crate::overfit`] on the RMS errors at and
/// between the offsets), where both are known.
fn mark_overfitting(rows: &mut [CompareRow]) {
    let base = |r: &CompareRow| Some((r.done_rms()?, r.held_out_rms?));
    let Some((at_b, held_b)) = rows.iter().find(|r| r.method == "approx").and_then(base) else {
        return;
    };
    for r in rows.iter_mut().filter(|r| r.method != "approx") {
        r.overfit = base(r).map(|(at_a, held_a)| crate::overfit(at_a, held_a, at_b, held_b));
    }
}

/// `compare.json`, pretty-printed, with a final newline.
pub fn comparison_json(c: &Comparison) -> String {
    // Serialising plain structs of numbers and strings cannot fail; non-finite numbers become
    // `null` (serde_json's rule).
    let mut s = serde_json::to_string_pretty(c).unwrap_or_else(|e| format!("{{\"error\": \"{e}\"}}"));
    s.push('\n');
    s
}

fn sci(v: f64) -> String {
    format!("{v:.3e}")
}

/// Milliseconds with three significant digits (at least one decimal below 1000).
fn millis(seconds: f64) -> String {
    let ms = 1e3 * seconds;
    match ms {
        m if m >= 100.0 => format!("{m:.0}"),
        m if m >= 10.0 => format!("{m:.1}"),
        m if m >= 1.0 => format!("{m:.2}"),
        m => format!("{m:.3}"),
    }
}

/// The Markdown table of a comparison (one row per method run), without headings.
pub fn comparison_table(c: &Comparison) -> String {
    let u = c.input.units;
    let mut t = String::new();
    let _ = writeln!(
        t,
        "| method | control points | max error ({u}) | mean error ({u}) | RMS error ({u}) | held-out RMS ({u}) | held-out max ({u}) | over-fits | max K (1/{u}²) | min K (1/{u}²) | time (ms) | evaluations | seed | validity |"
    );
    let _ = writeln!(t, "|---|---|--:|--:|--:|--:|--:|:-:|--:|--:|--:|--:|--:|---|");
    for r in &c.methods {
        let mut name = match r.status {
            RowStatus::Done => r.method.to_string(),
            RowStatus::Interrupted => format!("{} (interrupted)", r.method),
            RowStatus::Failed => format!("{} (failed)", r.method),
        };
        // A fair row fitted on another parameterization than the heading's (for validity).
        if r.parameterization != c.parameterization {
            name = format!("{name} on {}", r.parameterization);
        }
        // A fair row held on its surface instead of its net (for validity or fairness).
        if r.hold != crate::HoldOn::Net {
            name = format!("{name} held on the {}", r.hold.name());
        }
        let (max, mean, rms) = match r.error {
            Some(e) => (sci(e.max), sci(e.mean), sci(e.rms)),
            None => ("-".into(), "-".into(), "-".into()),
        };
        let (kmax, kmin) = match r.gaussian_curvature {
            Some(k) => (sci(k.max), sci(k.min)),
            None => ("-".into(), "-".into()),
        };
        let seed = r.seed.map_or_else(|| "-".to_string(), |s| s.to_string());
        let held = |v: Option<f64>| v.map_or_else(|| "-".to_string(), sci);
        let (held_rms, held_max) = (held(r.held_out_rms), held(r.held_out_max));
        let overfit = match r.overfit {
            Some(true) => "**yes**",
            Some(false) => "no",
            None => "-",
        };
        let validity = r.validity.as_ref().map_or_else(|| "-".to_string(), RowValidity::label);
        let _ = writeln!(
            t,
            "| {name} | {}x{} | {max} | {mean} | {rms} | {held_rms} | {held_max} | {overfit} | {kmax} | {kmin} | {} | {} | {seed} | {validity} |",
            r.control_points[0],
            r.control_points[1],
            millis(r.seconds),
            r.evaluations
        );
    }
    t
}

/// The floors as a Markdown list.
pub fn floors_markdown(f: &Floors) -> String {
    let mut t = String::new();
    for c in &f.checks {
        let verdict = match c.holds {
            Some(true) => "holds",
            Some(false) => "**fails**",
            None => "not checked",
        };
        let nums = match (c.value, c.bound) {
            (Some(v), Some(b)) => format!(" ({} vs {})", sci(v), sci(b)),
            _ => String::new(),
        };
        let _ = writeln!(t, "- `{}`: {verdict}{nums}", c.floor);
    }
    t
}

/// `compare.md`: a heading naming the input and settings, the table, the floors and notes.
pub fn comparison_markdown(c: &Comparison) -> String {
    let mut t = String::new();
    let _ = writeln!(t, "## {}\n", c.input.source);
    let o = &c.optimization;
    let budget = |v: Option<usize>| v.map_or_else(|| "default".to_string(), |n| n.to_string());
    let _ = writeln!(
        t,
        "{} sections, {} points ({}); degree {},{}; approximation control points {}x{}; parameterization {}; \
         seed {}; iterations {}, population {}; control points {}, weights {}{}.\n",
        c.input.sections,
        c.input.points,
        c.input.units,
        c.degree[0],
        c.degree[1],
        c.control_points[0],
        c.control_points[1],
        c.parameterization,
        c.seed,
        budget(o.iterations),
        budget(o.population),
        o.control_points,
        o.weight_layout,
        if o.parameter_correction { ", parameter correction" } else { "" },
    );
    t.push_str(&comparison_table(c));
    t.push('\n');
    let verdict = match c.floors.all_hold {
        Some(true) => "all hold",
        Some(false) => "**some fail**",
        None => "not all checked",
    };
    if let Some(k) = c.held_out_folds {
        let _ = writeln!(
            t,
            "Held-out error: {k}-fold cross-validation (refits without every {k}th interior section, then without \
             every {k}th interior point of each section; true distance of what was left out). Over-fits: lower RMS \
             error at the offsets than approx, higher held-out RMS.\n"
        );
    }
    let _ = writeln!(t, "Floors (true RMS error): {verdict}\n");
    t.push_str(&floors_markdown(&c.floors));
    for r in c.methods.iter().filter(|r| r.status == RowStatus::Failed) {
        let _ = writeln!(t, "\n`{}` failed: {}", r.method, r.failure.as_deref().unwrap_or(""));
    }
    if !c.complete {
        let _ = writeln!(
            t,
            "\nInterrupted: the interrupted row holds the best surface found before the stop; not run: {}.",
            if c.not_run.is_empty() { "none".to_string() } else { c.not_run.join(", ") }
        );
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::Progress;
    use crate::series60_sample;
    use std::sync::atomic::AtomicBool;

    fn row(method: &'static str, status: RowStatus, rms: f64) -> CompareRow {
        CompareRow {
            method,
            status,
            failure: None,
            control_points: [4, 4],
            parameterization: "centripetal,chord",
            hold: crate::HoldOn::Net,
            error: (status != RowStatus::Failed).then_some(RowError { max: rms, mean: rms, rms, parametric_rms: rms }),
            gaussian_curvature: None,
            seconds: 0.0,
            error_seconds: 0.0,
            evaluations: 0,
            iterations: 0,
            seed: None,
            objective: None,
            held_out_rms: None,
            held_out_max: None,
            overfit: None,
            validity: None,
        }
    }

    #[test]
    fn floors_hold_fail_or_stay_unchecked() {
        use RowStatus::*;
        let base = |ga: f64, lm: f64, gl: f64| {
            vec![
                row("approx", Done, 1.0),
                row("ga", Done, ga),
                row("pso", Done, 0.8),
                row("gsa", Done, 0.7),
                row("lm", Done, lm),
                row("gsa+lm", Done, gl),
            ]
        };
        let f = check_floors(&base(0.9, 0.6, 0.65));
        assert_eq!(f.all_hold, Some(true));
        assert_eq!(f.checks.len(), 4);
        assert_eq!((f.checks[3].value, f.checks[3].bound), (Some(0.6), Some(0.7)));
        // GA not below approx: fails; equality is not "lower".
        let f = check_floors(&base(1.0, 0.6, 0.65));
        assert_eq!((f.checks[0].holds, f.all_hold), (Some(false), Some(false)));
        // Local solvers above the best evolutionary: fails; equal within round-off: holds.
        assert_eq!(check_floors(&base(0.9, 0.75, 0.71)).checks[3].holds, Some(false));
        assert_eq!(check_floors(&base(0.9, 0.75, 0.7 * (1.0 + 1e-12))).checks[3].holds, Some(true));
        // A failed optimiser fails its floor and has no say in the best of the three; an
        // interrupted one leaves both unchecked.
        let mut rows = base(0.9, 0.6, 0.65);
        rows[3] = row("gsa", Failed, 0.0);
        let f = check_floors(&rows);
        assert_eq!((f.checks[2].holds, f.checks[3].holds, f.all_hold), (Some(false), Some(true), Some(false)));
        assert_eq!(f.checks[3].bound, Some(0.8));
        let mut rows = base(0.9, 0.6, 0.65);
        rows[4] = row("lm", Failed, 0.0);
        rows[5] = row("gsa+lm", Failed, 0.0);
        assert_eq!(check_floors(&rows).checks[3].holds, Some(false));
        let mut rows = base(0.9, 0.6, 0.65);
        rows[3] = row("gsa", Interrupted, 0.5);
        rows.truncate(4);
        let f = check_floors(&rows);
        assert_eq!((f.checks[2].holds, f.checks[3].holds, f.all_hold), (None, None, None));
        // lm done and below, gsa+lm not run: holds already.
        let mut rows = base(0.9, 0.6, 0.65);
        rows.pop();
        assert_eq!(check_floors(&rows).checks[3].holds, Some(true));
        // lm done but above, gsa+lm not run: it might still pass, so not checked.
        let mut rows = base(0.9, 0.75, 0.65);
        rows.pop();
        assert_eq!(check_floors(&rows).checks[3].holds, None);
    }

    fn small_config() -> CompareConfig {
        let mut c = CompareConfig::new();
        c.ctrl = Some((5, 8));
        c.optim.iterations = Some(4);
        c.optim.population = Some(6);
        c
    }

    #[test]
    fn every_method_is_measured_at_the_same_control_points() {
        let offsets = series60_sample();
        let c = compare_offsets(&offsets, &small_config()).expect("sample compares");
        let names: Vec<&str> = c.methods.iter().map(|r| r.method).collect();
        assert_eq!(names, ["interp", "approx", "ga", "pso", "gsa", "lm", "gsa+lm", "approx+fair", "lm+fair"]);
        assert!(c.complete && c.not_run.is_empty());
        // Interpolation has its own count (one pole per offset), the rest the asked one.
        assert_eq!(c.methods[0].control_points, [8, 25]);
        assert!(c.methods[1..].iter().all(|r| r.control_points == [5, 8]));
        let approx = c.methods[1].error.expect("measured");
        // The plain-objective rows (the fair rows' objective carries the fairness terms, and
        // `lm+fair` may be a sound approximation kept for a rejected LM surface).
        for r in &c.methods[..COMPARE_METHODS.len()] {
            let e = r.error.expect("measured");
            // The projection starts at the fit's parameters: the true distance never exceeds the
            // parametric residual (1e-12 relative: round-off of two evaluations).
            assert!(e.rms <= e.parametric_rms * (1.0 + 1e-12), "{}: {e:?}", r.method);
            // max >= RMS >= mean (power means), up to the round-off of the sums.
            assert!(e.max * (1.0 + 1e-12) >= e.rms && e.rms * (1.0 + 1e-12) >= e.mean, "{}: {e:?}", r.method);
            assert!(r.gaussian_curvature.is_some(), "{}", r.method);
            if let Some([start, end]) = r.objective {
                // Never worse than the start, which (re-solved control points, weights 1) is the
                // least-squares optimum at the approximation's parameters, so at most the
                // approximation's own parametric RMS. 1e-9: different round-off of the banded
                // solve and of the kernel's evaluation.
                assert!(end <= start, "{}: {start} -> {end}", r.method);
                assert!(start <= approx.parametric_rms * (1.0 + 1e-9), "{}: {start} vs {approx:?}", r.method);
                assert!(e.parametric_rms <= end * (1.0 + 1e-9), "{}: {e:?} vs {end}", r.method);
                assert!(r.evaluations > 0 && r.seed == Some(1));
            } else {
                assert_eq!(r.evaluations, 0);
            }
        }
        // Interpolation passes through the offsets (round-off on a 122 m hull).
        assert!(c.methods[0].error.expect("measured").max < 1e-9);
        let md = comparison_markdown(&c);
        for n in names {
            assert!(md.lines().any(|l| l.starts_with(&format!("| {n} |"))), "{n}: {md}");
        }
        let json: serde_json::Value = serde_json::from_str(&comparison_json(&c)).expect("valid JSON");
        assert_eq!(json["methods"].as_array().map(Vec::len), Some(COMPARE_METHODS.len() + FAIR_ROWS.len()));
        // Every row says whether its surface is valid, in both files.
        for (r, j) in c.methods.iter().zip(json["methods"].as_array().into_iter().flatten()) {
            let v = r.validity.as_ref().expect("measured rows are checked");
            assert_eq!(j["validity"]["findings"].as_u64(), Some(v.findings as u64), "{}", r.method);
            assert_eq!(j["validity"]["valid"].as_bool(), Some(v.findings == 0), "{}", r.method);
            let row = md.lines().find(|l| l.starts_with(&format!("| {} |", r.method))).expect("row");
            assert!(row.ends_with(&format!("| {} |", v.label())), "{row}");
        }
        assert_eq!(json["floors"]["checks"].as_array().map(Vec::len), Some(4));
        // Counts given: every row is on the comparison's parameterization, and says so.
        for (r, j) in c.methods.iter().zip(json["methods"].as_array().into_iter().flatten()) {
            assert_eq!(r.parameterization, c.parameterization, "{}", r.method);
            assert_eq!(j["parameterization"].as_str(), Some(c.parameterization), "{}", r.method);
        }
        // A fair row made on another parameterization for validity names it in the table.
        let mut other = c.clone();
        other.methods[7].parameterization = "universal,chord";
        let md = comparison_markdown(&other);
        assert!(md.lines().any(|l| l.starts_with("| approx+fair on universal,chord |")), "{md}");
        // One held on its surface says so, and compare.json records it (only then).
        let mut held = c.clone();
        held.methods[7].hold = crate::HoldOn::Surface;
        let md = comparison_markdown(&held);
        assert!(md.lines().any(|l| l.starts_with("| approx+fair held on the surface |")), "{md}");
        let json = serde_json::to_value(&held).expect("serialises");
        let holds: Vec<Option<&str>> =
            json["methods"].as_array().into_iter().flatten().map(|m| m["hold"].as_str()).collect();
        assert_eq!(holds.iter().filter(|h| h.is_some()).count(), 1, "{holds:?}");
        assert_eq!(holds[7], Some("surface"));
        assert!(md.lines().any(|l| l.starts_with("| lm+fair |")), "{md}");
    }

    #[test]
    fn rows_over_fit_when_closer_at_the_offsets_and_farther_between() {
        use RowStatus::*;
        let with = |mut r: CompareRow, held: Option<f64>| {
            r.held_out_rms = held;
            r
        };
        let mut rows = vec![
            with(row("interp", Done, 0.0), Some(2.0)),
            with(row("approx", Done, 1.0), Some(1.5)),
            with(row("ga", Done, 0.9), Some(1.4)),
            with(row("pso", Done, 1.1), Some(2.0)),
            with(row("gsa", Done, 0.9), None),
            with(row("lm", Failed, 0.0), None),
        ];
        mark_overfitting(&mut rows);
        let flags: Vec<Option<bool>> = rows.iter().map(|r| r.overfit).collect();
        // interp: lower at the offsets, higher between; ga better at both; pso worse at the
        // offsets (not over-fitting, just worse); gsa and lm unknown; approx is the baseline.
        assert_eq!(flags, [Some(true), None, Some(false), Some(false), None, None]);
        // Without the baseline's held-out error nothing is marked.
        rows[1].held_out_rms = None;
        rows.iter_mut().for_each(|r| r.overfit = None);
        mark_overfitting(&mut rows);
        assert!(rows.iter().all(|r| r.overfit.is_none()));
    }

    #[test]
    fn held_out_errors_join_the_rows_when_asked_for() {
        let offsets = series60_sample();
        let config = CompareConfig { held_out: Some(HeldOutOptions::default()), ..small_config() };
        let c = compare_offsets(&offsets, &config).expect("sample compares");
        assert_eq!(c.held_out_folds, Some(4));
        for r in &c.methods {
            let (rms, max) = (r.held_out_rms.expect("computed"), r.held_out_max.expect("computed"));
            assert!(0.0 < rms && rms <= max, "{}: {rms} {max}", r.method);
        }
        // The approximation's figure is that of its configuration, computed on its own.
        let approx =
            crate::held_out_for_config(&offsets, &config.fit_config(FitMethod::Approx), &HeldOutOptions::default())
                .expect("cross-validates");
        assert_eq!(c.methods[1].held_out_rms, Some(approx.rms));
        // A fair row's is that `fit` reports of the same surface: the refits at the smoothing
        // its search chose.
        let fair = c.methods.iter().find(|r| r.method == "approx+fair").expect("a fair row");
        let fair_config = FitConfig {
            fair: crate::Fairing::Auto { tolerance: None },
            envelope: crate::EnvelopeHold::Own,
            ..config.fit_config(FitMethod::Approx)
        };
        let fit = fit_offsets(&offsets, &fair_config).expect("fits");
        assert!(fit.fairing.as_ref().is_some_and(|f| f.lambda > 0.0) || fit.envelope_held > 0, "not the plain fit");
        let fit_held =
            crate::held_out_for_config(&offsets, &crate::held_out_refit_config(&fit), &HeldOutOptions::default())
                .expect("cross-validates");
        assert_eq!((fair.held_out_rms, fair.held_out_max), (Some(fit_held.rms), Some(fit_held.max)));
        let (interp, base) = (&c.methods[0], &c.methods[1]);
        let expected = crate::overfit(
            interp.error.expect("done").rms,
            interp.held_out_rms.expect("computed"),
            base.error.expect("done").rms,
            base.held_out_rms.expect("computed"),
        );
        assert_eq!(interp.overfit, Some(expected));
        let json: serde_json::Value = serde_json::from_str(&comparison_json(&c)).expect("valid JSON");
        assert!(json["methods"][0]["held_out_rms"].is_f64() && json["methods"][0]["overfit"].is_boolean());
        assert!(json["methods"][1]["overfit"].is_null(), "approx is the baseline");
        let md = comparison_markdown(&c);
        assert!(md.contains("held-out RMS") && md.contains("4-fold cross-validation"), "{md}");
        // Not asked for: nulls, and no note.
        let plain = compare_offsets(&offsets, &small_config()).expect("compares");
        assert!(plain.methods.iter().all(|r| r.held_out_rms.is_none() && r.overfit.is_none()));
        assert!(!comparison_markdown(&plain).contains("cross-validation"));
    }

    #[test]
    fn a_stop_ends_the_comparison_and_marks_the_row() {
        let offsets = series60_sample();
        let stop = AtomicBool::new(true);
        let progress = |_: Progress| {};
        let c = compare_offsets_with(&offsets, &small_config(), &mut |_, fit| {
            fit(&Control { stop: &stop, progress: &progress })
        })
        .expect("compares");
        let names: Vec<&str> = c.methods.iter().map(|r| r.method).collect();
        assert_eq!(names, ["interp", "approx", "ga"]);
        assert_eq!(c.methods[2].status, RowStatus::Interrupted);
        assert_eq!(c.not_run, ["pso", "gsa", "lm", "gsa+lm", "approx+fair", "lm+fair"]);
        assert!(!c.complete);
        assert_eq!(c.floors.all_hold, None);
        assert!(comparison_markdown(&c).contains("ga (interrupted)"));
    }

    #[test]
    fn row_validity_counts_the_findings_and_names_each_kind_once() {
        let place = crate::analysis::Place { x: 0.0, y: 0.0, z: 0.0, u: 0.0, v: 0.0 };
        let finding =
            |kind| Finding { kind, place, size: 1.0, limit: 0.5, reference: None, x_band: None, flat: None, places: 1 };
        let v = RowValidity::of(&[
            finding(FindingKind::InwardFacing),
            finding(FindingKind::Fold),
            finding(FindingKind::InwardFacing),
        ]);
        assert_eq!((v.valid, v.findings), (false, 3));
        assert_eq!(v.kinds, [FindingKind::Fold, FindingKind::InwardFacing]);
        assert_eq!(v.label(), "3: fold, inward_facing");
        assert_eq!(RowValidity::of(&[]).label(), "valid");
    }

    #[test]
    fn bad_control_points_are_an_error_not_a_table() {
        let offsets = series60_sample();
        let c = CompareConfig { ctrl: Some((9, 10)), ..CompareConfig::new() };
        assert!(matches!(compare_offsets(&offsets, &c), Err(HullError::Fit { .. })));
    }
}
