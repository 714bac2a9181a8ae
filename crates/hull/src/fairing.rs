//! Fairing a fit: the fairness term of the control net ([`WeightOptions::fair`], second
//! differences of the net, creases kept sharp), the control points held within the offsets'
//! envelope ([`ControlBox`]), and the choice of the fairness weight `λ`.
//!
//! A naval architect fairs "within building tolerance": the fairest surface whose error at
//! the offsets stays within a tolerance. [`Fairing::Auto`] does that literally: from the
//! largest `λ` of a decade grid down, the first surface whose true max error at the offsets is
//! within the tolerance (by default the plain approximation's own max error at the same control
//! points, so fairing never costs accuracy at the offsets), which does not fold, and which is
//! fairer than the plain approximation in the measures a naval architect checks (thin-plate
//! energy no higher, Gaussian-curvature range no wider) is taken; if none is, the plain
//! approximation is kept and the report says so.
//! Every candidate is held within the offsets' bounding box widened by half the validity
//! allowance (0.25 % of the half-beam, depth and length; [`fair_surface`]), so that it does not
//! cross the centre plane, bulge past the largest half-breadth or the keel, or run past the end
//! sections.
//!
//! Measured on the tables in `testdata/` (release, `examples`-style sweep of `λ` = 1e-8 .. 1):
//! the 116 m cargo ship's thin-plate energy falls from 1.5e5 to 2.0e3 at `λ` = 1e-4 with the
//! max error 103 mm against the plain fit's 108 mm; the Series 60 sample's barely moves before
//! its max error grows (the plain fit is already fair there); on R/V Gunnerus the global least
//! squares is ill-determined at small `λ` (sections of very unequal counts) and folds, so the
//! plain skin stays unless a larger `λ` is allowed a larger error.

use serde::Serialize;

use crate::analysis::{bending_energy, default_quadrature, find_folds};
use crate::optimize::{ControlBox, Objective, WeightOptions, WeightProblem};
use crate::{gaussian_curvature_range, measure_fit_error, FitOutcome, HullError, Offsets, CURVATURE_GRID};

/// The fairness term of a fit.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Fairing {
    /// None: the plain least squares (`--fair 0`).
    #[default]
    Off,
    /// This `λ` ([`WeightOptions::fair`]).
    Lambda(f64),
    /// The fairest surface within `tolerance` (module docs); `None`: the plain approximation's
    /// own max error.
    Auto { tolerance: Option<f64> },
}

impl Fairing {
    /// The name in reports: `off`, the `λ`, or `auto`.
    pub fn name(self) -> String {
        match self {
            Fairing::Off => "off".into(),
            Fairing::Lambda(l) => format!("{l:e}"),
            Fairing::Auto { .. } => "auto".into(),
        }
    }
}

/// [`WeightOptions::weight_smoothing`] of the optimisers on the fair objective: a difference of
/// 1 between neighbouring log-weights (a factor e) costs as much as an RMS error of 1e-4 of the
/// model size (12 mm on the Series 60 sample), so the weights vary smoothly over the net.
pub const WEIGHT_SMOOTHING: f64 = 1e-4;

/// The decade grid of `λ` that [`Fairing::Auto`] tries, largest first.
pub const AUTO_LAMBDAS: [f64; 8] = [1.0, 1e-1, 1e-2, 1e-3, 1e-4, 1e-5, 1e-6, 1e-7];

/// Share of the validity allowance (0.5 % of the half-beam, depth, length) by which the
/// envelope box of the fair fits exceeds the offsets' bounding box.
const BOX_SHARE: f64 = 0.5;

/// One `λ` tried.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FairTry {
    pub lambda: f64,
    /// True max error at the offsets.
    pub max: f64,
    /// Fold bands found.
    pub folds: usize,
    /// Within the tolerance and fold-free.
    pub accepted: bool,
}

/// Thin-plate energy and Gaussian-curvature range of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FairnessFigures {
    /// `∫ (k1^2 + k2^2) dA`, dimensionless ([`crate::analysis::BendingEnergy::thin_plate`]).
    pub thin_plate: f64,
    /// Smallest and largest Gaussian curvature on the comparison grid, 1/units^2.
    pub gaussian: [f64; 2],
}

impl FairnessFigures {
    /// The figures of `surface`.
    pub fn of(surface: &nurbs::NurbsSurface) -> Self {
        let thin_plate = bending_energy(surface, default_quadrature(surface)).thin_plate;
        let gaussian = gaussian_curvature_range(surface, CURVATURE_GRID).map_or([f64::NAN; 2], |k| [k.min, k.max]);
        FairnessFigures { thin_plate, gaussian }
    }
}

/// What fairing did, for `report.json` (`"fairing"`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FairReport {
    /// `"off"`, a number, or `"auto"`.
    pub setting: String,
    /// The `λ` used (0: the plain approximation was kept).
    pub lambda: f64,
    /// The max error the auto choice allowed.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub tolerance: Option<f64>,
    pub tried: Vec<FairTry>,
    /// Envelope pseudo-offsets added to keep the surface within the offsets' box
    /// ([`fair_surface`]).
    pub held_on_box: usize,
    /// Before (the plain approximation at the same control points) and after.
    pub before: FairnessFigures,
    pub after: FairnessFigures,
}

impl FairReport {
    /// One line for the summary table (`units`: the offsets' unit symbol).
    pub fn summary(&self, units: &str) -> String {
        let figures = format!(
            "thin-plate energy {:.4} -> {:.4}, Gaussian curvature [{:.3e}, {:.3e}] -> [{:.3e}, {:.3e}] 1/{units}^2",
            self.before.thin_plate,
            self.after.thin_plate,
            self.before.gaussian[0],
            self.before.gaussian[1],
            self.after.gaussian[0],
            self.after.gaussian[1]
        );
        let limit = self.tolerance.map(|t| format!(" within max error {t:.3e} {units}")).unwrap_or_default();
        if self.lambda == 0.0 {
            format!(
                "fairing ({}): none of {} fair surfaces{limit} without a fold was fairer (thin-plate energy, curvature \
                 range) than the plain least squares, which is kept",
                self.setting,
                self.tried.len()
            )
        } else {
            format!(
                "fairing ({}): lambda {:.0e}{limit}, {figures}; {} envelope points held it within the offsets' box",
                self.setting, self.lambda, self.held_on_box
            )
        }
    }
}

/// The box the fair fits stay in: the offsets' bounding box (and `y >= 0`) widened by half the
/// validity allowance.
pub fn envelope_box(offsets: &Offsets) -> Option<ControlBox> {
    let (lo, hi) = offsets.bounds()?;
    let half_beam = hi.y.max(0.0);
    let (depth, length) = (hi.z - lo.z, hi.x - lo.x);
    let a = 0.005 * BOX_SHARE;
    Some(ControlBox {
        lo: [lo.x - a * length, -a * half_beam, lo.z - a * depth],
        hi: [hi.x + a * length, hi.y + a * half_beam, hi.z + a * depth],
    })
}

/// A fair surface of `offsets` at `plain`'s knots and parameters: the least squares with
/// fairness `lambda`, held within [`envelope_box`] where it would leave it. Returns the surface
/// and the number of envelope points added.
///
/// The envelope is kept by pseudo-offsets, not by bounding the control points (which would keep
/// the surface inside by the convex hull property, but costs accuracy: the control polygon of a
/// round bilge or a raked stem lies outside the surface by design; measured, the Series 60
/// sample's max error rose from 100 to 144 mm). The surface is sampled on a grid refined at
/// every knot span; each sample outside the box becomes an extra data point at its own
/// parameters, placed at the nearest point of the box, and the least squares is solved again,
/// for at most [`ENVELOPE_ROUNDS`] rounds (the extra points of earlier rounds stay).
///
/// # Errors
/// [`HullError::Config`] for a bad `lambda` or offsets without extent; [`HullError::Fit`] if
/// the system is singular.
pub fn fair_surface(
    offsets: &Offsets,
    plain: &FitOutcome,
    lambda: f64,
) -> Result<(nurbs::NurbsSurface, usize), HullError> {
    let bx = envelope_box(offsets)
        .ok_or_else(|| HullError::Config("offsets without points cannot be faired (expected some points)".into()))?;
    let options = WeightOptions { fair: lambda, ..WeightOptions::default() };
    let mut points: Vec<nurbs::Vec3> = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
    let mut params: Vec<(f64, f64)> = plain.params.iter().flatten().copied().collect();
    let m = points.len();
    let mut surface = {
        let problem = WeightProblem::new(&plain.surface, &points, &params, options)?;
        problem.surface(&problem.start())?
    };
    for _ in 0..ENVELOPE_ROUNDS {
        let outside = outside_samples(&surface, &bx);
        if outside.is_empty() {
            break;
        }
        for (uv, target) in outside {
            params.push(uv);
            points.push(target);
        }
        let problem = WeightProblem::new(&plain.surface, &points, &params, options)?;
        surface = problem.surface(&problem.start())?;
    }
    Ok((surface, points.len() - m))
}

/// Rounds of envelope pseudo-offsets in [`fair_surface`].
pub const ENVELOPE_ROUNDS: usize = 4;

/// Samples of `surface` (8 per knot span each way) outside `bx`, with the nearest point of the
/// box.
fn outside_samples(surface: &nurbs::NurbsSurface, bx: &ControlBox) -> Vec<((f64, f64), nurbs::Vec3)> {
    let us = crate::analysis::param_grid(surface.knots_u(), 16, true, 8);
    let vs = crate::analysis::param_grid(surface.knots_v(), 16, true, 8);
    let mut out = Vec::new();
    for &v in &vs {
        for &u in &us {
            let p = surface.point(u, v).to_array();
            let mut q = p;
            for t in 0..3 {
                q[t] = p[t].clamp(bx.lo[t], bx.hi[t]);
            }
            if q != p {
                out.push(((u, v), nurbs::Vec3::new(q[0], q[1], q[2])));
            }
        }
    }
    out
}

/// Fair `plain` (an approximation of `offsets`) as `fairing` says: the surface, its `λ` and
/// the report. `None` for [`Fairing::Off`].
///
/// # Errors
/// [`HullError::Config`] for a negative or non-finite `λ` or tolerance; as [`fair_surface`].
pub fn fair(
    offsets: &Offsets,
    plain: &FitOutcome,
    fairing: Fairing,
) -> Result<Option<(nurbs::NurbsSurface, FairReport)>, HullError> {
    let check = |name: &str, v: f64| {
        if v >= 0.0 && v.is_finite() {
            Ok(())
        } else {
            Err(HullError::Config(format!("{name} {v} is not usable (expected a finite number >= 0)")))
        }
    };
    let before = || FairnessFigures::of(&plain.surface);
    match fairing {
        Fairing::Off => Ok(None),
        Fairing::Lambda(l) => {
            check("fairness", l)?;
            if l == 0.0 {
                return Ok(None);
            }
            let (s, held) = fair_surface(offsets, plain, l)?;
            let after = FairnessFigures::of(&s);
            let report = FairReport {
                setting: fairing.name(),
                lambda: l,
                tolerance: None,
                tried: Vec::new(),
                held_on_box: held,
                before: before(),
                after,
            };
            Ok(Some((s, report)))
        }
        Fairing::Auto { tolerance } => {
            if let Some(t) = tolerance {
                check("tolerance", t)?;
            }
            let limit = tolerance.unwrap_or(plain.error.overall.max);
            let b = before();
            let mut tried = Vec::new();
            for &l in &AUTO_LAMBDAS {
                let Ok((s, held)) = fair_surface(offsets, plain, l) else { continue };
                let e = measure_fit_error(&s, offsets, Some(&plain.params));
                let folds = find_folds(&s).len();
                let mut accepted = e.overall.max <= limit && folds == 0;
                let after = if accepted { Some(FairnessFigures::of(&s)) } else { None };
                // Fairer in the measures a naval architect checks, not only in the net's
                // differences: no more bending energy, no wider curvature range.
                if let Some(a) = &after {
                    accepted = a.thin_plate <= b.thin_plate
                        && a.gaussian[0] >= b.gaussian[0]
                        && a.gaussian[1] <= b.gaussian[1];
                }
                tried.push(FairTry { lambda: l, max: e.overall.max, folds, accepted });
                if let (true, Some(after)) = (accepted, after) {
                    let report = FairReport {
                        setting: fairing.name(),
                        lambda: l,
                        tolerance: Some(limit),
                        tried,
                        held_on_box: held,
                        before: b,
                        after,
                    };
                    return Ok(Some((s, report)));
                }
            }
            // Nothing fairer within the limit: the plain approximation stays, said so.
            Ok(Some((
                plain.surface.clone(),
                FairReport {
                    setting: fairing.name(),
                    lambda: 0.0,
                    tolerance: Some(limit),
                    tried,
                    held_on_box: 0,
                    before: b,
                    after: b,
                },
            )))
        }
    }
}
