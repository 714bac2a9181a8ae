//! What a fit is asked for ([`FitConfig`]: method, degrees, control points, parameterization,
//! knuckles, fairing, envelope hold) and what it gives ([`FitOutcome`], with the report of its
//! fairing, [`FairReport`]): the vocabulary the pipeline ([`crate::fit_offsets`]), its stages
//! (fairing, the weight optimisation, the held-out refits) and the reports share. It sits
//! below all of them, so that none has to import another to name a fit.

use std::fmt;
use std::str::FromStr;

use nurbs::fit::{AlongParameters, CornerOptions, KnuckleLine, SkinParameterization};

use crate::flats::FlatLine;
use crate::units::Units;
use nurbs::NurbsSurface;
use serde::Serialize;

use crate::analysis::{bending_energy, default_quadrature, plane_fairness, FairnessOptions, PlaneFairness};
use crate::curvature_range::{gaussian_curvature_range, CURVATURE_GRID};
use crate::fit_error::FitError;
use crate::optimize::{Algorithm, OptimReport, OptimSettings};

/// How the surface is built from the sections.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum FitMethod {
    /// Skinning interpolation (The NURBS Book 10.3): passes through every offset.
    Interp,
    /// Skinning approximation: least squares with `NU x NV` control points.
    Approx,
    /// Skinning approximation whose weights are then optimised by an algorithm.
    Optimized(Algorithm),
}

impl FitMethod {
    /// The name used on the command line and in reports.
    pub fn name(self) -> &'static str {
        match self {
            FitMethod::Interp => "interp",
            FitMethod::Approx => "approx",
            FitMethod::Optimized(a) => a.name(),
        }
    }

    /// The weight optimiser, for the optimised methods.
    pub fn algorithm(self) -> Option<Algorithm> {
        match self {
            FitMethod::Optimized(a) => Some(a),
            _ => None,
        }
    }
}

impl fmt::Display for FitMethod {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for FitMethod {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "interp" | "interpolation" => Ok(FitMethod::Interp),
            "approx" | "approximation" => Ok(FitMethod::Approx),
            t => t
                .parse::<Algorithm>()
                .map(FitMethod::Optimized)
                .map_err(|_| format!("unknown method `{s}` (expected interp, approx, ga, pso, gsa, lm or gsa+lm)")),
        }
    }
}

/// Whether the fitted surface keeps the knuckles (chines) of the sections.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum Knuckles {
    /// One smooth surface: no knuckle is looked for.
    Off,
    /// Knuckle lines found by [`find_knuckle_lines`](nurbs::fit::find_knuckle_lines) with these settings are kept as tangent
    /// discontinuities (a knot of multiplicity `p` along the sections,
    /// [`skin_interpolate_with_knuckles`](nurbs::fit::skin_interpolate_with_knuckles)); without any, the fit is the plain skin.
    Auto(CornerOptions),
    /// As [`Knuckles::Auto`], and where no knuckle line is found, an approximation (`approx`,
    /// and the start of the optimised methods) of a hull with flats of side or bottom
    /// ([`find_flat_lines`](crate::flats::find_flat_lines)) is refitted within the flats' planes, `y <= y_max` and
    /// `z >= z_min` ([`refit_within_flats`](crate::flats::refit_within_flats)): no ringing past the flats, for 2 more control
    /// points along `u` per flat line and up to 2 more across per line's end. Interpolation is
    /// left as it is (held on the planes it could no longer pass through every offset). Not the
    /// default: at equal control-point counts the plain approximation is closer to the offsets
    /// (README, hull features).
    AutoFlats(CornerOptions),
}

impl Default for Knuckles {
    /// [`Knuckles::Auto`] with [`CornerOptions::default`], which finds no knuckle line on any
    /// table of `testdata/` (round bilges, bulbs and transoms) and finds the chine of a
    /// hard-chine hull.
    fn default() -> Self {
        Knuckles::Auto(CornerOptions::default())
    }
}

impl Knuckles {
    /// The name used on the command line: `off`, or `auto` (with the angle when it is not
    /// the default, `auto(25 deg)`).
    pub fn name(self) -> String {
        match self {
            Knuckles::Off => "off".into(),
            Knuckles::Auto(o) if o == CornerOptions::default() => "auto".into(),
            Knuckles::Auto(o) => format!("auto({} deg)", o.min_angle_deg),
            Knuckles::AutoFlats(o) if o == CornerOptions::default() => "auto+flats".into(),
            Knuckles::AutoFlats(o) => format!("auto+flats({} deg)", o.min_angle_deg),
        }
    }
}

/// Settings of [`fit_offsets`](crate::fit_offsets).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct FitConfig {
    pub method: FitMethod,
    /// Degrees `(p, q)`: along the sections (u) and across them (v).
    pub degree: (usize, usize),
    /// Control points `(NU, NV)` of `approx`; `None` picks [`default_ctrl`](crate::default_ctrl).
    pub ctrl: Option<(usize, usize)>,
    /// Parameterization along the sections (u) and across them (v); the default is
    /// centripetal along, chord length across ([`SkinParameterization::default`]).
    pub param: SkinParameterization,
    /// Settings of the weight optimisation (optimised methods only).
    pub optim: OptimSettings,
    /// Knuckles (chines) kept as tangent discontinuities; the default looks for them.
    pub knuckles: Knuckles,
    /// The fairness term of `approx` and of the optimised methods (README, "Fairing"); the
    /// default is [`Fairing::Off`], the plain least squares (the command line's default is
    /// [`Fairing::Auto`]). Not applied to `interp` (it passes through every offset) nor to a
    /// fit refitted within flats (`auto+flats`).
    pub fair: Fairing,
    /// [`SkinOptions::smoothing`](nurbs::fit::SkinOptions::smoothing) of the skinning approximation (set by the [`Fairing`] chosen).
    pub smoothing: f64,
    /// Whether an approximation (`approx`, and the start of the optimised methods) that leaves
    /// the offsets' envelope is held within it ([`EnvelopeHold`]; the default holds it in the
    /// offsets' own envelope). An optimised surface re-solves its control points: one that
    /// leaves the envelope is held too (its weights kept), or gives way to the held
    /// approximation where that is closer to the offsets.
    pub envelope: EnvelopeHold,
    /// What that hold holds behind the envelope's faces: the control net (the default) or
    /// the surface's points ([`HoldOn`]; the surface hold is the first alternative the default
    /// fit tries when it is unsound, before [`crate::ALTERNATIVE_PARAMETERIZATIONS`]).
    pub hold_on: HoldOn,
    /// [`SkinOptions::along`](nurbs::fit::SkinOptions::along): the parameters along the
    /// sections (equal counts only) chosen by the least residual (the default), or imposed;
    /// `--fair auto` imposes the plain fit's on a smoothed fit whose own choice differs
    /// ([`Fairing::Auto`]).
    pub along: AlongParameters,
}

/// What [`FitConfig::envelope`] holds behind the faces of the envelope a surface crossed. The
/// end sections' planes and the planes of the flats a fit was refitted within (`auto+flats`)
/// are held on the control net either way. Serialised as its [`HoldOn::name`].
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum HoldOn {
    /// The control net ([`nurbs::fit::bounded_refit`]): by the convex-hull property no point
    /// of the surface can cross a face held.
    #[default]
    Net,
    /// Sampled points of the surface ([`nurbs::fit::held_refit`]: 8, then 16 per knot span
    /// each way), the net free wherever the surface is within; where that still has a
    /// validity finding, the net hold is fitted too and the one with fewer findings (folds
    /// first) kept, the surface hold on a tie.
    Surface,
}

impl HoldOn {
    /// `net` or `surface`, as `report.json` names it.
    pub fn name(self) -> &'static str {
        match self {
            HoldOn::Net => "net",
            HoldOn::Surface => "surface",
        }
    }
}

/// How [`FitConfig::envelope`] holds a surface that leaves the offsets' envelope: a refit of
/// its control net behind the faces it crossed ([`nurbs::fit::bounded_refit`]), so that by the
/// convex-hull property no point of it can cross them.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum EnvelopeHold {
    /// Keep the least squares as it is (its findings reported).
    Free,
    /// Behind the faces of the offsets' own envelope ([`Envelope::bounds`](crate::Envelope::bounds)).
    #[default]
    Own,
    /// Behind the faces of this box: the envelope of a whole table, for the cross-validation
    /// refits of part of it (the principal dimensions of the hull are known even where some
    /// of its offsets are held out).
    Given(nurbs::fit::ControlBox),
}

impl Default for FitConfig {
    fn default() -> Self {
        FitConfig {
            method: FitMethod::Approx,
            degree: (3, 3),
            ctrl: None,
            param: SkinParameterization::default(),
            optim: OptimSettings::default(),
            knuckles: Knuckles::default(),
            fair: Fairing::Off,
            smoothing: 0.0,
            envelope: EnvelopeHold::Own,
            hold_on: HoldOn::Net,
            along: AlongParameters::LeastResidual,
        }
    }
}

/// A fitted surface with its measured error and timings.
#[derive(Clone, Debug)]
pub struct FitOutcome {
    pub config: FitConfig,
    pub surface: NurbsSurface,
    /// Data parameters `(u, v)` of every offset, per section.
    pub params: Vec<Vec<(f64, f64)>>,
    pub error: FitError,
    /// Seconds spent in the kernel's skinning.
    pub fit_seconds: f64,
    /// Seconds spent measuring the error by projection.
    pub error_seconds: f64,
    /// What the weight optimisation did (optimised methods only).
    pub optimization: Option<OptimReport>,
    /// The knuckle lines kept in the surface (empty without any, or with [`Knuckles::Off`]).
    pub knuckle_lines: Vec<KnuckleLine>,
    /// The flat lines the surface was refitted within ([`Knuckles::AutoFlats`]; empty otherwise).
    pub flat_lines: Vec<FlatLine>,
    /// Where the surface folds back across its sections ([`crate::analysis::find_folds`]);
    /// empty for a sound surface.
    pub folds: Vec<crate::analysis::Fold>,
    /// What fairing did (`approx` and the optimised methods with a fairness setting).
    pub fairing: Option<FairReport>,
    /// Results not taken as the answer, and why (e.g. an optimised surface that folds: the
    /// fair start is kept instead).
    pub rejected: Vec<String>,
    /// Every defect of the surface ([`crate::analysis::check_fit_validity`]: folds, leaving the
    /// offsets' envelope, bulging through a flat of the offsets, inward-facing facets); empty
    /// for a valid surface.
    pub validity: Vec<crate::analysis::Finding>,
    /// Control-point coordinates held on the offsets' envelope: an approximation that left it
    /// is refitted with its net within the envelope ([`nurbs::fit::bounded_refit`]), or with
    /// its surface's samples and some of its net ([`HoldOn::Surface`], the count is of both);
    /// 0 when none was needed.
    pub envelope_held: usize,
    /// The fairness figures the fairing measured, with the surface they are of: reused by
    /// [`FitOutcome::fairness_figures`] for that very surface only.
    pub(crate) measured_fairness: Option<(NurbsSurface, FairnessFigures)>,
    /// The offsets' closest points `(u, v)` found by the true error's measurement (in input
    /// order, each projection started at the fit's parameters), with the surface and the
    /// parameters they were found for: the optimisers' foot-point start reuses them for that
    /// very surface and those parameters only ([`crate::optimize::FittedSurface::foot_points`]).
    pub(crate) measured_feet: Option<std::sync::Arc<MeasuredFeet>>,
    /// The surface before the envelope hold refitted it (`envelope_held > 0`): the plain least
    /// squares whose fairness `--fair auto` keeps.
    pub(crate) unheld: Option<NurbsSurface>,
    /// The parameters the skin fitted the sections at along them
    /// ([`SkinResult::along`](nurbs::fit::SkinResult::along)): the least-squares choice a
    /// smoothed fit is compared with; [`AlongParameters::LeastResidual`] where none was made
    /// (interpolation, an optimised surface).
    pub(crate) along: AlongParameters,
    /// The default fit's held-out referee ([`crate::refereed_by_held_out`]; [`crate::fit_offsets_within`]
    /// with [`crate::Goal::Count`] sets it), `None` for any other fit.
    pub held_out_referee: Option<HeldOutReferee>,
}

impl FitOutcome {
    /// The fairness figures of `surface` (`report.json`'s `fairness`): those the fairing
    /// already measured (its `after`, or `before` when it kept the plain fit) when they are of
    /// this very surface, else measured now ([`FairnessFigures::of`]).
    pub fn fairness_figures(&self) -> FairnessFigures {
        match &self.measured_fairness {
            Some((measured, figures)) if *measured == self.surface => *figures,
            _ => FairnessFigures::of(&self.surface),
        }
    }

    /// This outcome, with `figures` recorded as its surface's ([`FitOutcome::fairness_figures`]).
    pub(crate) fn with_fairness(self, figures: FairnessFigures) -> Self {
        FitOutcome { measured_fairness: Some((self.surface.clone(), figures)), ..self }
    }

    /// How defective the surface is, for choosing between fits: `(folds, findings)`, folds
    /// first, then validity findings of any kind (compared in that order).
    pub fn defects(&self) -> (usize, usize) {
        (self.folds.len(), self.validity.len())
    }
}

/// The fairness term of a fit: smoothing of the skinning approximation (each least-squares
/// curve, along the sections and across them, with a bending-energy term,
/// [`nurbs::fit::SkinOptions::smoothing`]), and the choice of its weight.
///
/// A naval architect fairs "within building tolerance": the fairest surface whose error at the
/// offsets stays within a tolerance, and a sound one (no fold). [`Fairing::Auto`] does that
/// literally: the tolerance is `--tolerance` or, by default, the plain
/// approximation's own max error at the same control points, so fairing never costs accuracy at
/// the offsets unless the plain fit has validity findings (a fold, the surface leaving the
/// offsets' envelope, ...: then the fit with fewer is worth up to twice the tolerance,
/// [`UNSOUND_SLACK`](crate::UNSOUND_SLACK)); "fairer" is measured as a naval architect would,
/// by the thin-plate energy `∫ (k1^2 + k2^2) dA`, the largest Gaussian curvature and the
/// inflections of the stations and waterlines ([`FairnessFigures`](crate::FairnessFigures)), all no
/// worse than the plain fit's.
///
/// Measured (release, `ν` = 1e-4 .. 1 on the tables in `testdata/`): the 116 m cargo ship's
/// thin-plate energy falls from 1.5e5 to 2.1e3 at `ν` = 1e-3 with the max error 105 mm against
/// the plain fit's 108 mm; the Series 60 sample's from 91 to 61 at `ν` = 1e-2 (max 103.5 mm
/// against 100.5, RMS 23.9 against 28.1 mm); R/V Gunnerus's forecastle fold goes at `ν` = 1e-2
/// (max 85 mm against 63); on the exact Wigley hull any smoothing costs accuracy (2.4 µm RMS
/// plain, 29 µm at 1e-3), so the plain fit stays.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Fairing {
    /// None: the plain least squares (`--fair 0`).
    #[default]
    Off,
    /// This weight: the smoothing `ν` of the approximation
    /// ([`nurbs::fit::SkinOptions::smoothing`]) and, for the weight optimisers, the net's
    /// fairness [`WeightOptions::fair`](crate::optimize::WeightOptions::fair).
    Lambda(f64),
    /// The fairest surface within `tolerance` (README, "Fairing"); `None`: the plain approximation's
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

/// One smoothing weight tried.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FairTry {
    pub lambda: f64,
    /// True max error at the offsets; `None` (`null`) where it was not measured: a fit the
    /// search could not take, with a validity finding where the plain fit has none, else with
    /// at least as many defects as the plain fit (see [`Fairing::Auto`]).
    pub max: Option<f64>,
    /// Validity findings ([`crate::analysis::check_fit_validity`]).
    pub findings: usize,
    /// The one taken: sound, within the tolerance and fairer; or, for a plain fit with
    /// findings, the least smoothing with the fewest (within twice the tolerance).
    pub accepted: bool,
    /// The parameters along the sections imposed on this fit: `own` or `mean`, the plain
    /// fit's, where the smoothed fit's least residual chose the other (the same `λ` is then
    /// tried both ways); left out where the fit chose them.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub along: Option<&'static str>,
}

/// What a naval architect checks of a surface's fairness: its thin-plate energy, its
/// Gaussian-curvature range and the inflections of its stations and waterlines.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FairnessFigures {
    /// `∫ (k1^2 + k2^2) dA`, dimensionless ([`crate::analysis::BendingEnergy::thin_plate`]).
    pub thin_plate: f64,
    /// Smallest and largest Gaussian curvature on the comparison grid, 1/units^2.
    pub gaussian: [f64; 2],
    /// Inflections of the 21 stations evenly spaced along the surface's length
    /// ([`crate::analysis::fairness_report`] with its default options).
    pub station_inflections: usize,
    /// Inflections of the 10 waterlines evenly spaced up its height, as the stations'.
    pub waterline_inflections: usize,
}

impl FairnessFigures {
    /// The figures of `surface`.
    pub fn of(surface: &nurbs::NurbsSurface) -> Self {
        Self::with_inflections(surface, Self::without_inflections(surface))
    }

    /// The figures of `surface` if it is no less fair than `other`
    /// ([`FairnessFigures::no_less_fair_than`]), else `None`; the inflections (the planar cuts,
    /// most of the cost) are counted only for a surface whose thin-plate energy and curvature
    /// extreme pass. The same figures and verdict as [`FairnessFigures::of`] followed by the
    /// comparison.
    pub(crate) fn of_no_less_fair(surface: &nurbs::NurbsSurface, other: &FairnessFigures) -> Option<Self> {
        let cheap = Self::without_inflections(surface);
        if !(cheap.thin_plate <= other.thin_plate && cheap.curvature_extreme() <= other.curvature_extreme()) {
            return None;
        }
        Some(Self::with_inflections(surface, cheap)).filter(|f| f.no_less_fair_than(other))
    }

    /// The thin-plate energy (as [`crate::analysis::fairness_report`] with its default options
    /// integrates it) and the curvature range, the inflections left 0.
    fn without_inflections(surface: &nurbs::NurbsSurface) -> Self {
        let thin_plate = bending_energy(surface, default_quadrature(surface)).thin_plate;
        let gaussian = gaussian_curvature_range(surface, CURVATURE_GRID).map_or([f64::NAN; 2], |k| [k.min, k.max]);
        FairnessFigures { thin_plate, gaussian, station_inflections: 0, waterline_inflections: 0 }
    }

    /// `figures` with the inflections of `surface`'s stations and waterlines counted.
    fn with_inflections(surface: &nurbs::NurbsSurface, figures: Self) -> Self {
        let (_, stations, waterlines, _) = plane_fairness(surface, &FairnessOptions::default());
        let count = |planes: &[PlaneFairness]| planes.iter().map(|p| p.inflections).sum();
        FairnessFigures { station_inflections: count(&stations), waterline_inflections: count(&waterlines), ..figures }
    }

    /// Inflections of the stations and waterlines together.
    pub fn inflections(&self) -> usize {
        self.station_inflections + self.waterline_inflections
    }

    /// The largest `|K|`.
    pub fn curvature_extreme(&self) -> f64 {
        self.gaussian[0].abs().max(self.gaussian[1].abs())
    }

    /// No less fair than `other` by every figure: thin-plate energy, curvature extreme and
    /// inflections.
    pub fn no_less_fair_than(&self, other: &FairnessFigures) -> bool {
        self.thin_plate <= other.thin_plate
            && self.curvature_extreme() <= other.curvature_extreme()
            && self.inflections() <= other.inflections()
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
    /// The fits tried, in their order, up to the one taken where no later fit could displace
    /// it (README, "Fairing"): the weights after it are not tried.
    pub tried: Vec<FairTry>,
    /// Validity findings of the plain approximation.
    pub plain_findings: usize,
    /// Before (the plain least squares at the same control points, before any envelope hold)
    /// and after.
    pub before: FairnessFigures,
    pub after: FairnessFigures,
    /// The alternatives to the default fit's parameterization and counts, when `--fair auto`
    /// replaced them for validity or tried to ([`Alternatives`]; left out otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub alternatives: Option<Alternatives>,
}

impl FairReport {
    /// One line for the summary table (`units`: the offsets' unit symbol).
    pub fn summary(&self, units: Units) -> String {
        let figures = format!(
            "thin-plate energy {:.4} -> {:.4}, Gaussian curvature [{:.3e}, {:.3e}] -> [{:.3e}, {:.3e}] 1/{units}^2",
            self.before.thin_plate,
            self.after.thin_plate,
            self.before.gaussian[0],
            self.before.gaussian[1],
            self.after.gaussian[0],
            self.after.gaussian[1]
        ) + &format!(", inflections {} -> {}", self.before.inflections(), self.after.inflections());
        let limit = self.tolerance.map(|t| format!(" within max error {t:.3e} {units}")).unwrap_or_default();
        let chosen = self.tried.iter().find(|t| t.accepted);
        if let (Some(c), Some(t), Some(max)) = (chosen, self.tolerance, chosen.and_then(|c| c.max)) {
            if max > t || self.plain_findings > 0 {
                return format!(
                    "fairing ({}): smoothing {:.0e} leaves {} validity finding(s) against the plain fit's {}, at a \
                     max error of {max:.3e} {units} against {t:.3e} {units}; {figures}",
                    self.setting, self.lambda, c.findings, self.plain_findings
                );
            }
        }
        if self.lambda == 0.0 {
            format!(
                "fairing ({}): none of {} smoothed fits{limit} was sound and fairer (thin-plate energy, curvature \
                 extreme, inflections) than the plain least squares, which is kept",
                self.setting,
                self.tried.len()
            )
        } else {
            format!("fairing ({}): smoothing {:.0e}{limit}, {figures}", self.setting, self.lambda)
        }
    }
}

/// One alternative tried ([`Alternatives::tried`]).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct AlternativeTry {
    /// Its parameterization, as `--param` takes it.
    pub param: &'static str,
    /// What its envelope hold held: `net` or `surface`.
    pub hold: HoldOn,
    /// Its control-point counts `[NU, NV]`.
    pub control_points: [usize; 2],
    /// The faired fit's true max error at the offsets.
    pub max: f64,
    /// Its validity findings.
    pub findings: usize,
    /// Made for fairness ([`AlternativeReason::Fairness`]): whether it is no less fair than
    /// the plain least squares ([`FairnessFigures::no_less_fair_than`]; measured of a sound fit
    /// within the tolerance only, left out otherwise).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub no_less_fair: Option<bool>,
    /// The one used.
    pub accepted: bool,
}

/// Why the default fit was made again ([`Alternatives`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "lowercase")]
pub enum AlternativeReason {
    /// It folds or faces inwards.
    Validity,
    /// It is sound, but its envelope hold left it less fair than the plain least squares
    /// (the report's `before`) by thin-plate energy, curvature extreme or inflections.
    Fairness,
}

/// Why the default fit's parameterization, counts and hold are what `report.json` says (the
/// `fairing` block's `alternatives`, [`crate::ALTERNATIVE_PARAMETERIZATIONS`] and
/// [`crate::ALTERNATIVE_COUNTS_ACROSS`]): the default left a fold or inward-facing facets
/// (`findings` validity findings in all), or was sound but less fair than the plain least
/// squares once held (`reason`), and `tried` lists the alternatives fitted, the one used marked
/// (none when none qualified within `limit`).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Alternatives {
    pub reason: AlternativeReason,
    /// The parameterization asked for (the default) and the default counts.
    pub requested: &'static str,
    pub control_points: [usize; 2],
    /// Its faired fit's max error at the offsets and validity findings.
    pub max: f64,
    pub findings: usize,
    /// Its fairness figures ([`AlternativeReason::Fairness`]; those of the one used are the
    /// fairing block's `after`).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub figures: Option<FairnessFigures>,
    /// The max error an alternative may have: [`UNSOUND_SLACK`](crate::UNSOUND_SLACK) times the
    /// fairing's tolerance for validity, the tolerance itself for fairness.
    pub limit: f64,
    pub tried: Vec<AlternativeTry>,
}

impl Alternatives {
    /// One line for the summary table (`plain`: the plain least squares' figures, the fairing
    /// block's `before`; `units`: the offsets' unit symbol).
    pub fn summary(&self, plain: &FairnessFigures, units: &str) -> String {
        let counts = |c: [usize; 2]| format!("{}x{}", c[0], c[1]);
        let head = match (self.reason, &self.figures) {
            (AlternativeReason::Fairness, Some(f)) => format!(
                "alternatives: {} at {}, its control net held within the offsets' envelope, is sound but less fair \
                 than the plain least squares ({}) at a max error of {:.3e} {units}",
                self.requested,
                counts(self.control_points),
                less_fair_by(f, plain, units),
                self.max
            ),
            _ => format!(
                "alternatives: {} at {} leaves {} validity finding(s) (a fold or inward-facing facets) at a max error \
                 of {:.3e} {units}",
                self.requested,
                counts(self.control_points),
                self.findings,
                self.max
            ),
        };
        let name = |t: &AlternativeTry| match t.hold {
            HoldOn::Net => format!("{} at {}", t.param, counts(t.control_points)),
            hold => format!("{} held on the {} at {}", t.param, hold.name(), counts(t.control_points)),
        };
        let tried = |t: &AlternativeTry| {
            let fair = match t.no_less_fair {
                Some(true) => ", no less fair",
                Some(false) => ", less fair",
                None => "",
            };
            format!("{} {} finding(s) at {:.3e} {units}{fair}", name(t), t.findings, t.max)
        };
        let list = self.tried.iter().map(tried).collect::<Vec<_>>().join(", ");
        let qualifies = match self.reason {
            AlternativeReason::Validity => "has none",
            AlternativeReason::Fairness => "has none and is no less fair",
        };
        let wanted = match self.reason {
            AlternativeReason::Validity => "sound within max error",
            AlternativeReason::Fairness => "sound and no less fair with its least squares below max error",
        };
        match self.tried.iter().find(|t| t.accepted) {
            Some(t) => format!(
                "{head}; {} {qualifies} (max error {:.3e} {units}, within {:.3e} {units}) and is used (tried: {list})",
                name(t),
                t.max,
                self.limit
            ),
            None => {
                format!("{head}; no alternative is {wanted} {:.3e} {units} (tried: {list}), so it is kept", self.limit)
            }
        }
    }
}

/// The figures by which `figures` are worse than `plain`'s, each with both values.
fn less_fair_by(figures: &FairnessFigures, plain: &FairnessFigures, units: &str) -> String {
    let mut worse = Vec::new();
    if figures.thin_plate > plain.thin_plate {
        worse.push(format!("thin-plate energy {:.4} against {:.4}", figures.thin_plate, plain.thin_plate));
    }
    if figures.curvature_extreme() > plain.curvature_extreme() {
        worse.push(format!(
            "largest |K| {:.3e} against {:.3e} 1/{units}^2",
            figures.curvature_extreme(),
            plain.curvature_extreme()
        ));
    }
    if figures.inflections() > plain.inflections() {
        worse.push(format!("inflections {} against {}", figures.inflections(), plain.inflections()));
    }
    worse.join(", ")
}

/// [`FitOutcome::measured_feet`]: the feet of the offsets on `surface`, projected from `params`.
#[derive(Debug, PartialEq)]
pub(crate) struct MeasuredFeet {
    pub(crate) surface: NurbsSurface,
    pub(crate) params: Vec<Vec<(f64, f64)>>,
    pub(crate) feet: Vec<(f64, f64)>,
}

impl crate::optimize::FittedSurface for FitOutcome {
    fn surface(&self) -> &NurbsSurface {
        &self.surface
    }

    fn params(&self) -> &[Vec<(f64, f64)>] {
        &self.params
    }

    fn foot_points(&self) -> Option<&[(f64, f64)]> {
        self.measured_feet
            .as_deref()
            .filter(|m| m.surface == self.surface && m.params == self.params)
            .map(|m| m.feet.as_slice())
    }
}

/// What the referee found (`report.json` `held_out_referee`): the held-out max errors of the
/// plain approximation and of the default fit, and the alternatives tried when the default
/// fit was the farther.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeldOutReferee {
    /// The folds of the cross-validations compared ([`crate::HeldOutOptions::DEFAULT_FOLDS`]).
    pub folds: usize,
    /// The held-out max error of the plain approximation at the default fit's control points
    /// (the default parameterization, no fairing, not held within the envelope).
    pub plain_max: f64,
    /// The default fit's held-out max error (before any alternative replaced it).
    pub default_max: f64,
    /// The largest max error at the offsets an alternative may have: the default fit's
    /// fairing tolerance.
    pub limit: f64,
    /// The alternatives tried, in order (none where the default fit was no farther).
    pub tried: Vec<RefereeTry>,
    /// Seconds of the default fit (fit and error at the offsets, its fairing search and
    /// alternatives included) and of its cross-validation.
    pub default_fit_seconds: f64,
    pub default_held_out_seconds: f64,
    /// Seconds of the referee itself: the plain approximation and its cross-validation, and
    /// every alternative fitted and cross-validated.
    pub seconds: f64,
}

/// One alternative the referee tried: as the default fit's alternatives are recorded
/// (`no_less_fair` against the plain approximation, measured of a sound fit within the limit
/// only; `max` that of its least squares, which is not faired), and its held-out max error.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct RefereeTry {
    #[serde(flatten)]
    pub fit: AlternativeTry,
    /// The smoothing `ν` it was fitted with: the default fit's ([`FairReport::lambda`]).
    pub smoothing: f64,
    /// Its held-out max error (measured of a sound, no less fair fit within the limit only).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_out_max: Option<f64>,
}

impl HeldOutReferee {
    /// One line for the summary (`units`: the offsets' unit symbol).
    pub fn summary(&self, units: &str) -> String {
        let compared = |how: &str| {
            format!(
                "held-out referee ({} folds): {:.3e} {units}, {how} than the plain approximation's {:.3e} {units} (the \
                 same control points, not held within the envelope)",
                self.folds, self.default_max, self.plain_max
            )
        };
        if self.default_max <= self.plain_max {
            return compared("no farther");
        }
        let head = compared("farther");
        let tried: Vec<String> = self
            .tried
            .iter()
            .map(|RefereeTry { fit: t, smoothing, held_out_max }| {
                let smoothed = if *smoothing > 0.0 { format!(", smoothing {smoothing:.0e}") } else { String::new() };
                let what = format!(
                    "{} held on the {} at {}x{}{smoothed}: max error {:.3e} {units}, {} finding(s)",
                    t.param,
                    t.hold.name(),
                    t.control_points[0],
                    t.control_points[1],
                    t.max,
                    t.findings
                );
                let fair = match t.no_less_fair {
                    Some(true) => ", no less fair",
                    Some(false) => ", less fair",
                    None => "",
                };
                let held = held_out_max.map(|h| format!(", held out {h:.3e} {units}")).unwrap_or_default();
                let used = if t.accepted { ": used" } else { "" };
                format!("{what}{fair}{held}{used}")
            })
            .collect();
        if self.tried.is_empty() {
            return format!("{head}; kept: held on its surface already, no alternative tried");
        }
        let verdict = if self.tried.iter().any(|t| t.fit.accepted) {
            "the closer alternative is used".to_string()
        } else {
            format!("no alternative sound, no less fair, within {:.3e} {units} and closer; kept", self.limit)
        };
        format!("{head}; {verdict} (tried: {})", tried.join("; "))
    }
}
