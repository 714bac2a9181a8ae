//! What a fit run writes: `surface.igs`, `surface.json` and `report.json` (all or nothing),
//! and the summary table printed to the terminal.
//!
//! The layout of `report.json` is documented on [`Report`], where the library's users read it.

use std::fmt::Write as _;
use std::io;
use std::path::Path;

use serde::Serialize;

use crate::export::{iges_timestamp, write_iges, write_surface_json, IgesMeta};
use crate::optimize::OptimReport;
use crate::{check_finite, FitError, FitOutcome, HullError, Offsets, OutputDir, ToleranceSearch};
use nurbs::NurbsSurface;

/// The `input` block of `report.json`.
#[derive(Clone, Debug, Serialize)]
pub struct InputSummary {
    pub source: String,
    pub sections: usize,
    pub points: usize,
    pub units: &'static str,
    /// The sense checks' warnings on the input (the suspect cells, units, size; empty when
    /// none), set by the caller that read the offsets.
    pub warnings: Vec<crate::read::SenseWarning>,
}

/// The `surface` block of `report.json`.
#[derive(Clone, Debug, Serialize)]
pub struct SurfaceSummary {
    pub degree: [usize; 2],
    pub control_points: [usize; 2],
    pub rational: bool,
}

/// `report.json`.
///
/// `report.json` layout (stable; later features add fields):
///
/// ```text
/// {"hullskin": "0.1.0", "method": "approx",
///  "input": {"source": "...", "sections": K, "points": N, "units": "m"},
///  "surface": {"degree": [P, Q], "control_points": [NU, NV], "rational": false},
///  "parameterization": "centripetal",
///  "error": {"max": .., "mean": .., "rms": .., "points": N, "worst": {...},
///            "per_section": [{"section": "..", "max": .., "mean": .., "rms": .., "points": n}],
///            "unconverged_projections": 0,
///            "held_out": {"rms": .., "max": .., "sections": {"max": .., "mean": .., "rms": .., "points": n},
///                         "points": {...}, "folds": 4, "refits": 8, "seconds": ..}},
///  "seconds": .., "fit_seconds": .., "error_seconds": ..,
///  "optimization": {"algorithm": "gsa", "seed": 1, "control_points": "resolved",
///                   "weight_layout": "full", "weight_bounds": [0.1, 10], "weight_range": [..],
///                   "weights_at_bounds": n, "iterations": .., "evaluations": .., "stop": "iterations",
///                   "start_value": .., "final_value": .., "history": [..],
///                   "parameter_correction": false, "settings": {..}, "seconds": ..},
///  "fairness": {"thin_plate": .., "gaussian": [min, max], "station_inflections": n,
///               "waterline_inflections": n},
///  "held_out_referee": {"folds": 4, "plain_max": .., "default_max": .., "limit": ..,
///                       "tried": [{"param": "chord", "hold": "surface", "control_points": [NU, NV],
///                                  "max": .., "findings": 0, "no_less_fair": true,
///                                  "accepted": true, "smoothing": 0, "held_out_max": ..}],
///                       "default_fit_seconds": .., "default_held_out_seconds": .., "seconds": ..},
///  "folds": [{"x": [x0, x1], "v": [v0, v1], "samples": n, "of": n}],
///  "validity": [{"kind": "below_centre_plane", "place": {"x": .., "y": .., "z": .., "u": .., "v": ..},
///                "size": .., "limit": .., "reference": .., "x_band": [x0, x1], "flat": "bottom"}]}
/// ```
///
/// `optimization` is present for the weight-optimised methods only (also where the optimised
/// surface gave way to an approximation, which `rejected` says: the record of the run); its
/// `history` is the best objective (parametric RMS of the offsets) after each iteration. `fairness` is the final
/// surface's ([`crate::fairing::FairnessFigures`]), always present. `fairing` is present when the fit was faired ([`crate::FairReport`]: `setting`, `lambda`
/// (0: the plain fit was kept), `tolerance`, `tried` (`lambda`, `max`, `folds`, `accepted`),
/// `before` and `after`, each as `fairness`); `rejected`
/// lists results not taken as the answer, and why; `overfitting` (from `hullskin fit` with an
/// optimised method) says when its held-out error shows over-fitting. `tolerance_search` is
/// present with `--tolerance` only ([`ToleranceSearch`]: `tolerance`, `control_points`,
/// `interp_control_points`, `ratio`, `fits`, `complete`, `valid`, `tried`). `held_out_referee`
/// is present for the default fit ([`crate::HeldOutReferee`]: its held-out max error against the
/// plain approximation's, and the alternatives tried where it was the farther), whatever
/// `--held-out` says: it chose the surface written.
///
/// A surface measured as it is (`hullskin fit SURFACE --offsets FILE`, [`Report::measured`])
/// has `"method": "given"`, `"parameterization": "closest points"`, `fit_seconds` 0 and
/// `surface_source`, the surface's file (left out for a fit).
///
/// `envelope_held` (left out when 0) counts the control-point coordinates held on the offsets'
/// envelope by `--envelope hold` (with the surface samples held, when the surface hold was the
/// alternative used: [`crate::HoldOn::Surface`]).
///
/// `folds` is left out when the surface does not fold. `validity` is always there: one finding
/// per defect ([`crate::analysis::Finding`]; kinds `fold`, `below_centre_plane`,
/// `beyond_half_breadth`, `below_lowest_offset`, `above_highest_offset`, `past_aft_end`,
/// `past_fore_end`, `flat_bulge`, `inward_facing`), empty for a valid surface. `size` is how far
/// past `reference` (model units; an area in units² for `inward_facing`), `limit` the allowance
/// it exceeded; `reference`, `x_band` and `flat` only where they apply.
///
/// Errors are distances in the input's units, measured by closest-point projection of every
/// input point onto the surface. `error.held_out`, when asked for (`hullskin fit --held-out K`,
/// on by default), is the error between the offsets by K-fold cross-validation
/// ([`crate::held_out_for_config`]): the true distance of held-out sections and of held-out
/// points within sections to the surface refitted without them.
#[derive(Clone, Debug, Serialize)]
pub struct Report {
    pub hullskin: &'static str,
    pub method: &'static str,
    pub input: InputSummary,
    pub surface: SurfaceSummary,
    pub parameterization: &'static str,
    pub error: FitError,
    /// Fit plus error measurement, seconds.
    pub seconds: f64,
    pub fit_seconds: f64,
    pub error_seconds: f64,
    /// What the weight optimisation did (optimised methods only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub optimization: Option<OptimReport>,
    /// The search for the fewest control points within a tolerance (`--tolerance` only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance_search: Option<ToleranceSearch>,
    /// Where the surface folds back across its sections (left out when there is none).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub folds: Vec<crate::analysis::Fold>,
    /// What fairing did ([`crate::fairing::FairReport`]; left out when the fit was not faired).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub fairing: Option<crate::FairReport>,
    /// Results not taken as the answer, and why.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub rejected: Vec<String>,
    /// An optimised method's over-fitting, when its held-out error shows it (lower RMS at the
    /// offsets than the approximation at the same control points, higher held out): the
    /// command line's warning, set by the caller that cross-validated both.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub overfitting: Option<String>,
    /// The default fit's held-out error against the plain approximation's, and the
    /// alternatives tried where it was the farther ([`crate::HeldOutReferee`]; left out for any
    /// other fit, or where the default fit could not be cross-validated).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_out_referee: Option<crate::HeldOutReferee>,
    /// Every defect of the surface (always present; empty when valid).
    pub validity: Vec<crate::analysis::Finding>,
    /// The surface's fairness: thin-plate energy, Gaussian-curvature range, inflections of its
    /// stations and waterlines (always present).
    pub fairness: crate::fairing::FairnessFigures,
    /// Control-point coordinates (and surface samples, [`crate::HoldOn::Surface`]) held on the
    /// offsets' envelope by `--envelope hold` ([`FitOutcome::envelope_held`]; left out when
    /// none was).
    #[serde(skip_serializing_if = "is_zero")]
    pub envelope_held: usize,
    /// The file of a surface measured as it is ([`Report::measured`], method `given`); left
    /// out for a fit.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub surface_source: Option<String>,
}

/// A surface given as it is (read from a surface.json, IGES or STEP file, not fitted here),
/// measured against offsets as a fit is: the error of every offset by closest-point projection
/// and the validity checks.
#[derive(Clone, Debug)]
pub struct Measured<'a> {
    pub surface: &'a NurbsSurface,
    /// The surface's file.
    pub source: &'a str,
    pub error: FitError,
    pub validity: Vec<crate::analysis::Finding>,
    /// Seconds spent measuring.
    pub seconds: f64,
}

impl<'a> Measured<'a> {
    /// Measure `surface` (from the file `source`) against `offsets`, in the offsets' units
    /// (which must be the surface's).
    ///
    /// # Errors
    /// As [`crate::analysis::check_fit_validity`].
    pub fn new(surface: &'a NurbsSurface, source: &'a str, offsets: &Offsets) -> Result<Self, HullError> {
        let start = std::time::Instant::now();
        let error = crate::measure_fit_error(surface, offsets, None);
        let validity = crate::analysis::check_fit_validity(surface, offsets)?;
        Ok(Measured { surface, source, error, validity, seconds: start.elapsed().as_secs_f64() })
    }
}

fn is_zero(n: &usize) -> bool {
    *n == 0
}

impl Report {
    /// The report of one fit.
    pub fn new(offsets: &Offsets, outcome: &FitOutcome) -> Self {
        let s = &outcome.surface;
        Report {
            hullskin: env!("CARGO_PKG_VERSION"),
            method: outcome.config.method.name(),
            input: InputSummary::of(offsets),
            surface: SurfaceSummary::of(s),
            parameterization: outcome.config.param.name(),
            error: outcome.error.clone(),
            seconds: outcome.fit_seconds + outcome.error_seconds,
            fit_seconds: outcome.fit_seconds,
            error_seconds: outcome.error_seconds,
            optimization: outcome.optimization.clone(),
            tolerance_search: None,
            folds: outcome.folds.clone(),
            fairing: outcome.fairing.clone(),
            rejected: outcome.rejected.clone(),
            overfitting: None,
            held_out_referee: outcome.held_out_referee.clone(),
            validity: outcome.validity.clone(),
            fairness: outcome.fairness_figures(),
            envelope_held: outcome.envelope_held,
            surface_source: None,
        }
    }

    /// The report of a surface measured as it is: method `given`, parameterization
    /// `closest points` (every offset's parameters found by projection), no fit time.
    pub fn measured(offsets: &Offsets, m: &Measured<'_>) -> Self {
        let s = m.surface;
        Report {
            hullskin: env!("CARGO_PKG_VERSION"),
            method: GIVEN,
            input: InputSummary::of(offsets),
            surface: SurfaceSummary::of(s),
            parameterization: "closest points",
            error: m.error.clone(),
            seconds: m.seconds,
            fit_seconds: 0.0,
            error_seconds: m.seconds,
            optimization: None,
            tolerance_search: None,
            folds: Vec::new(),
            fairing: None,
            rejected: Vec::new(),
            overfitting: None,
            held_out_referee: None,
            validity: m.validity.clone(),
            fairness: crate::fairing::FairnessFigures::of(s),
            envelope_held: 0,
            surface_source: Some(m.source.to_string()),
        }
    }
}

/// The `method` of a surface measured as it is.
pub const GIVEN: &str = "given";

impl InputSummary {
    fn of(offsets: &Offsets) -> Self {
        InputSummary {
            source: offsets.source.clone(),
            sections: offsets.sections.len(),
            points: offsets.num_points(),
            units: offsets.units.symbol(),
            warnings: Vec::new(),
        }
    }
}

impl SurfaceSummary {
    fn of(s: &NurbsSurface) -> Self {
        SurfaceSummary {
            degree: [s.degree_u(), s.degree_v()],
            control_points: [s.n_u(), s.n_v()],
            rational: s.is_rational(),
        }
    }
}

/// The IGES date: `SOURCE_DATE_EPOCH` when set (reproducible builds), else now.
fn timestamp() -> String {
    let secs =
        std::env::var("SOURCE_DATE_EPOCH").ok().and_then(|s| s.trim().parse::<i64>().ok()).unwrap_or_else(|| {
            std::time::SystemTime::now()
                .duration_since(std::time::UNIX_EPOCH)
                .map(|d| i64::try_from(d.as_secs()).unwrap_or(0))
                .unwrap_or(0)
        });
    iges_timestamp(secs)
}

/// Write `surface.igs`, `surface.json` and `report.json` into the directory `dir` (created if
/// needed), all or nothing: the surface is checked ([`check_finite`]), the three files are
/// built in memory, staged beside `dir` and moved in together ([`OutputDir`]), so a failure
/// leaves what was there byte for byte.
///
/// # Errors
/// [`HullError::UnwritableSurface`] for a surface with a non-finite control point, a bad weight
/// or bad knots (before any file is created); [`HullError::Io`] naming the file or directory
/// that could not be written.
pub fn write_fit_outputs(dir: &Path, offsets: &Offsets, outcome: &FitOutcome) -> Result<(), HullError> {
    write_fit_outputs_with_report(dir, offsets, outcome, &Report::new(offsets, outcome))
}

/// [`write_fit_outputs`] with `report.json` from `report` (e.g. [`Report::new`] plus a
/// tolerance search).
///
/// # Errors
/// As [`write_fit_outputs`].
pub fn write_fit_outputs_with_report(
    dir: &Path,
    offsets: &Offsets,
    outcome: &FitOutcome,
    report: &Report,
) -> Result<(), HullError> {
    let surface = &outcome.surface;
    check_finite(surface)?;
    let units = offsets.units;
    let io_err = |path: &Path| {
        let path = path.to_path_buf();
        move |error: io::Error| HullError::Io { path, error }
    };
    // Build everything in memory first, so nothing is written if any part fails.
    let mut iges = Vec::new();
    write_iges(&mut iges, surface, &IgesMeta::new(units.into(), "surface.igs", &timestamp()))
        .map_err(io_err(&dir.join("surface.igs")))?;
    let mut json = Vec::new();
    write_surface_json(&mut json, surface, units).map_err(io_err(&dir.join("surface.json")))?;
    let mut report =
        serde_json::to_vec_pretty(report).map_err(|e| io_err(&dir.join("report.json"))(io::Error::other(e)))?;
    report.push(b'\n');
    let mut out = OutputDir::stage(dir)?;
    for (name, bytes) in [("surface.igs", &iges), ("surface.json", &json), ("report.json", &report)] {
        out.write_bytes(name, bytes)?;
    }
    out.commit()?;
    Ok(())
}

/// Write `report.json` alone into `dir` (created if needed), staged and moved in like
/// [`write_fit_outputs`]: the report of a surface measured as it is, whose surface files are
/// the user's own.
///
/// # Errors
/// [`HullError::Io`] naming the file or directory that could not be written.
pub fn write_report_json(dir: &Path, report: &Report) -> Result<(), HullError> {
    let mut bytes = serde_json::to_vec_pretty(report)
        .map_err(|e| HullError::Io { path: dir.join("report.json"), error: io::Error::other(e) })?;
    bytes.push(b'\n');
    let mut out = OutputDir::stage(dir)?;
    out.write_bytes("report.json", &bytes)?;
    out.commit()?;
    Ok(())
}

/// A short fixed-width table of the fit for the terminal.
pub fn summary_table(offsets: &Offsets, outcome: &FitOutcome) -> String {
    let u = offsets.units.symbol();
    let e = &outcome.error;
    let seconds = outcome.fit_seconds + outcome.error_seconds;
    let mut t = summary_head(offsets, outcome.config.method.name(), &outcome.surface, e, seconds);
    if let Some(h) = &e.held_out {
        let _ = writeln!(t, "{}", held_out_line(h, u));
        if let Some(w) = &h.worst {
            let line = w.line.map(|l| format!(", line {l}")).unwrap_or_default();
            let _ = writeln!(
                t,
                "worst held-out offset: section {} point {}{line}: {:.3e} {u} from the refit without it",
                w.section,
                w.index + 1,
                w.distance
            );
        }
    }
    for line in fit_decisions(offsets, outcome) {
        let _ = writeln!(t, "{line}");
    }
    worst_line(&mut t, e, u);
    t
}

/// What the fit decided, a line each, as the summary table prints them under its row: the
/// weight optimisation, the alternative made for validity, the fairing, the envelope hold and
/// every surface rejected with why (the report page lists them as notes).
pub fn fit_decisions(offsets: &Offsets, outcome: &FitOutcome) -> Vec<String> {
    let u = offsets.units.symbol();
    let mut lines = Vec::new();
    if let Some(r) = &outcome.held_out_referee {
        lines.push(r.summary(u));
    }
    if let Some(o) = &outcome.optimization {
        lines.push(format!(
            "weights by {}: objective {:.4e} -> {:.4e} {u} in {} evaluations, {} iterations ({}), weights {:.3}..{:.3}, {:.2} s",
            o.algorithm,
            o.start_value,
            o.final_value,
            o.evaluations,
            o.iterations,
            o.stop.phrase(),
            o.weight_range[0],
            o.weight_range[1],
            o.seconds,
        ));
    }
    if let Some(f) = &outcome.fairing {
        // The alternatives first: the fairing line's plain fit is the one used's.
        if let Some(p) = &f.alternatives {
            lines.push(p.summary(&f.before, u));
        }
        lines.push(f.summary(offsets.units));
    }
    if outcome.envelope_held > 0 {
        let held = match outcome.config.hold_on {
            crate::HoldOn::Net => "control-point coordinates",
            crate::HoldOn::Surface => "surface samples and control-point coordinates",
        };
        lines.push(format!(
            "envelope: the least squares left the offsets' envelope; refitted with {} {held} held on its faces, so \
             the surface stays within it (--envelope free keeps the plain fit)",
            outcome.envelope_held
        ));
    }
    lines.extend(outcome.rejected.iter().map(|r| format!("rejected: {r}")));
    lines
}

/// The summary table of a surface measured as it is: the surface's file, then the table of
/// [`summary_table`] with the method `given`.
pub fn measured_summary_table(offsets: &Offsets, m: &Measured<'_>) -> String {
    let mut t = format!("surface: {} (measured as it is, not fitted)\n", m.source);
    t.push_str(&summary_head(offsets, GIVEN, m.surface, &m.error, m.seconds));
    worst_line(&mut t, &m.error, offsets.units.symbol());
    t
}

/// The input line and the one-row table of method, control points, degree, errors and time.
fn summary_head(offsets: &Offsets, method: &str, s: &NurbsSurface, e: &FitError, seconds: f64) -> String {
    let u = offsets.units.symbol();
    let mut t = String::new();
    let _ = writeln!(
        t,
        "input: {} ({} sections, {} points, {})",
        offsets.source,
        offsets.sections.len(),
        offsets.num_points(),
        offsets.units.plural_name()
    );
    let _ = writeln!(
        t,
        "{:<8} {:>10} {:>7} {:>12} {:>12} {:>12} {:>10}",
        "method", "ctrl pts", "degree", "max err", "mean err", "RMS err", "time"
    );
    let _ = writeln!(
        t,
        "{:<8} {:>10} {:>7} {:>12} {:>12} {:>12} {:>10}",
        method,
        format!("{}x{}", s.n_u(), s.n_v()),
        format!("{},{}", s.degree_u(), s.degree_v()),
        format!("{:.3e} {u}", e.overall.max),
        format!("{:.3e} {u}", e.overall.mean),
        format!("{:.3e} {u}", e.overall.rms),
        format!("{:.2} ms", 1e3 * seconds),
    );
    t
}

fn worst_line(t: &mut String, e: &FitError, u: &str) {
    if let Some(w) = &e.worst {
        let line = w.line.map(|l| format!(", line {l}")).unwrap_or_default();
        let _ = writeln!(t, "worst offset: section {} point {}{line}: {:.3e} {u}", w.section, w.index + 1, w.distance);
    }
}

/// The warnings of a fit, one sentence each, for standard error (the summary table has the
/// figures): projections that stopped at their iteration limit, weights on their bounds (of
/// the optimised surface written: not of one that gave way to an approximation, whose
/// optimisation the summary still reports), every validity finding.
pub fn summary_warnings(offsets: &Offsets, outcome: &FitOutcome) -> Vec<String> {
    let u = offsets.units.symbol();
    let mut out = projection_warnings(&outcome.error);
    let written = outcome.config.method.algorithm().is_some();
    if let Some(o) = outcome.optimization.as_ref().filter(|o| written && o.weights_at_bounds > 0) {
        out.push(format!(
            "{} weights ended on their bounds [{}, {}], a sign of over-fitting (expected fewer control points, or \
             wider bounds)",
            o.weights_at_bounds, o.weight_bounds[0], o.weight_bounds[1]
        ));
    }
    out.extend(outcome.validity.iter().map(|f| f.message(u)));
    out
}

/// The warnings of a surface measured as it is: projections stopped at their limit, every
/// validity finding.
pub fn measured_warnings(offsets: &Offsets, m: &Measured<'_>) -> Vec<String> {
    let mut out = projection_warnings(&m.error);
    out.extend(m.validity.iter().map(|f| f.message(offsets.units.symbol())));
    out
}

fn projection_warnings(e: &FitError) -> Vec<String> {
    let mut out = Vec::new();
    if e.unconverged_projections > 0 {
        out.push(format!(
            "{} of {} projections stopped at the iteration limit (their distances are upper bounds)",
            e.unconverged_projections, e.overall.points
        ));
    }
    out
}

/// The summary's line of the held-out error, e.g. `held out (4 folds): RMS 3.1e-2 m, max
/// 1.2e-1 m (sections: ..., points: ...)`.
fn held_out_line(h: &crate::HeldOutError, u: &str) -> String {
    let part = |name: &str, s: &crate::ErrorStats| match s.points {
        0 => format!("{name}: none held out"),
        n => format!("{name}: RMS {:.3e} {u}, max {:.3e} {u} over {n}", s.rms, s.max),
    };
    format!(
        "held out ({} folds): RMS {:.3e} {u}, max {:.3e} {u} ({}; {}), {} refits in {:.2} s",
        h.folds,
        h.rms,
        h.max,
        part("sections", &h.sections),
        part("points", &h.points),
        h.refits,
        h.seconds
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::{fit_offsets, series60_sample, FitConfig};

    #[test]
    fn outputs_are_written_and_read_back() {
        let dir = tempfile::tempdir().expect("temp dir");
        let offsets = series60_sample();
        let out = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        write_fit_outputs(dir.path(), &offsets, &out).expect("writes");
        let report: serde_json::Value =
            serde_json::from_str(&std::fs::read_to_string(dir.path().join("report.json")).expect("read"))
                .expect("valid JSON");
        assert_eq!(report["method"], "approx");
        assert_eq!(report["input"]["sections"], 25);
        assert_eq!(report["input"]["points"], 200);
        assert_eq!(report["surface"]["degree"], serde_json::json!([3, 3]));
        assert_eq!(report["error"]["max"].as_f64(), Some(out.error.overall.max));
        // The findings, each with its kind, place and size (the sample's default fit has some).
        let validity = report["validity"].as_array().expect("always a list");
        assert_eq!(validity.len(), out.validity.len());
        for (v, f) in validity.iter().zip(&out.validity) {
            assert_eq!(v["kind"], f.kind.name());
            assert_eq!((v["size"].as_f64(), v["place"]["x"].as_f64()), (Some(f.size), Some(f.place.x)));
        }
        let text = std::fs::read_to_string(dir.path().join("surface.json")).expect("read");
        let (s, units) = crate::export::read_surface_json(&text).expect("reads back");
        assert_eq!(units, "m");
        assert_eq!(s, out.surface);
        let iges = std::fs::read_to_string(dir.path().join("surface.igs")).expect("read");
        assert!(iges.lines().all(|l| l.len() == 80));
        let table = summary_table(&offsets, &out);
        assert!(table.contains("approx") && table.contains("25 sections"), "{table}");
    }

    #[test]
    fn the_held_out_error_goes_into_the_report_and_the_summary() {
        let dir = tempfile::tempdir().expect("temp dir");
        let offsets = series60_sample();
        let mut out = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        let read = |dir: &Path| -> serde_json::Value {
            serde_json::from_str(&std::fs::read_to_string(dir.join("report.json")).expect("read")).expect("JSON")
        };
        write_fit_outputs(dir.path(), &offsets, &out).expect("writes");
        assert!(read(dir.path())["error"].get("held_out").is_none(), "left out unless asked for");
        assert!(!summary_table(&offsets, &out).contains("held out"));
        let h = crate::held_out_for_config(&offsets, &out.config, &crate::HeldOutOptions::default()).expect("ok");
        out.error.held_out = Some(h.clone());
        write_fit_outputs(dir.path(), &offsets, &out).expect("writes");
        let r = read(dir.path());
        let j = &r["error"]["held_out"];
        assert_eq!((j["rms"].as_f64(), j["max"].as_f64()), (Some(h.rms), Some(h.max)));
        assert_eq!(j["sections"]["points"].as_u64(), Some(h.sections.points as u64));
        assert_eq!((j["folds"].as_u64(), j["refits"].as_u64()), (Some(4), Some(8)));
        assert!(j["points"]["rms"].is_f64() && j["seconds"].is_f64());
        // Beside the error at the offsets, which keeps its place.
        assert_eq!(r["error"]["rms"].as_f64(), Some(out.error.overall.rms));
        let table = summary_table(&offsets, &out);
        let line = format!("held out (4 folds): RMS {:.3e} m, max {:.3e} m (sections: RMS", h.rms, h.max);
        assert!(table.contains(&line), "{table}");
        // The worst held-out offset: the max, named by its place in the table.
        let w = h.worst.as_ref().expect("a worst held-out offset");
        assert_eq!(j["worst"]["distance"].as_f64(), Some(h.max));
        assert_eq!(w.distance, h.max);
        let named = format!("worst held-out offset: section {} point {}", w.section, w.index + 1);
        assert!(table.contains(&named), "{table}");
    }

    #[test]
    fn summary_warns_of_unconverged_projections() {
        let offsets = series60_sample();
        let mut out = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        // The default fit of the sample warns of its validity findings only (it crosses the
        // centre plane at the transom and bulges past its flat side), one line each.
        assert_eq!(summary_warnings(&offsets, &out).len(), out.validity.len());
        // The table holds the figures, the warnings go apart (to standard error).
        assert!(!summary_table(&offsets, &out).contains("warning"));
        out.validity.clear();
        assert!(summary_warnings(&offsets, &out).is_empty(), "a clean fit warns of nothing");
        out.error.unconverged_projections = 3;
        let w = summary_warnings(&offsets, &out);
        assert!(w[0].starts_with("3 of 200 projections stopped at the iteration limit"), "{w:?}");
    }

    #[test]
    fn summary_warns_of_weights_driven_to_their_bounds() {
        // Weights boxed to +-1 %: Levenberg-Marquardt pushes some of the 40 onto the box to
        // lower the residual. The report counts them (within 1e-9 relative) and the summary
        // says how many.
        let offsets = series60_sample();
        let mut optim = crate::optimize::OptimSettings { iterations: Some(5), ..Default::default() };
        optim.weights.bounds = (0.99, 1.01);
        let method = crate::FitMethod::Optimized(crate::optimize::Algorithm::Lm);
        let cfg = FitConfig { method, optim, ctrl: Some((5, 8)), ..FitConfig::default() };
        let out = fit_offsets(&offsets, &cfg).expect("fits");
        let o = out.optimization.as_ref().expect("optimised");
        let on_bound = |w: f64| (w - 0.99).abs() <= 1e-9 * 0.99 || (w - 1.01).abs() <= 1e-9 * 1.01;
        let count = out.surface.weights().into_iter().filter(|&w| on_bound(w)).count();
        assert_eq!(o.weights_at_bounds, count);
        assert!(count > 0, "no weight reached the 1 % bounds: {:?}", o.weight_range);
        let w = summary_warnings(&offsets, &out);
        let line = format!("{count} weights ended on their bounds [0.99, 1.01]");
        assert!(w.iter().any(|l| l.starts_with(&line)), "{w:?}");
        // Where that surface gave way to an approximation (named `approx`, the optimisation's
        // record kept), the written surface's weights are not those: no such warning.
        let gave_way = FitOutcome { config: FitConfig { method: crate::FitMethod::Approx, ..out.config }, ..out };
        assert!(!summary_warnings(&offsets, &gave_way).iter().any(|l| l.contains("on their bounds")));
    }

    #[test]
    fn an_unwritable_surface_writes_nothing_and_keeps_the_earlier_outputs() {
        let root = tempfile::tempdir().expect("temp dir");
        let dir = root.path().join("out");
        let offsets = series60_sample();
        let good = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        write_fit_outputs(&dir, &offsets, &good).expect("writes");
        let before: Vec<Vec<u8>> =
            ["surface.igs", "surface.json", "report.json"].map(|f| std::fs::read(dir.join(f)).expect("read")).into();
        // One control point whose Cartesian x, 1e308 / 1e-10, overflows: homogeneous
        // coordinates the kernel accepts, a point no file may hold.
        let s = &good.surface;
        let mut cw = s.homogeneous().to_vec();
        cw[7] = [1e308, 0.0, 0.0, 1e-10];
        let mut bad = good.clone();
        bad.surface = nurbs::NurbsSurface::try_from_homogeneous(s.knots_u().clone(), s.knots_v().clone(), cw)
            .expect("the kernel accepts finite homogeneous coordinates");
        let err = write_fit_outputs(&dir, &offsets, &bad).expect_err("refused");
        assert!(matches!(err, HullError::UnwritableSurface { .. }), "{err}");
        let after: Vec<Vec<u8>> =
            ["surface.igs", "surface.json", "report.json"].map(|f| std::fs::read(dir.join(f)).expect("read")).into();
        assert!(before == after, "the earlier outputs are byte-identical");
        let entries = std::fs::read_dir(root.path()).expect("list").count();
        assert_eq!(entries, 1, "no staging directory is left beside the output directory");
        // Into a directory that does not exist yet: it is not created.
        let fresh = root.path().join("fresh");
        assert!(write_fit_outputs(&fresh, &offsets, &bad).is_err());
        assert!(!fresh.exists());
    }
}
