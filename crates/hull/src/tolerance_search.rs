//! The fewest control points for a tolerance: search the counts `(nu, nv)` of a skinning
//! approximation (plain or weight-optimised) for the smallest valid surface (no validity
//! finding), `nu nv` control points, whose true max error (closest-point distance of every
//! offset, `error.overall.max`) is within a tolerance `T`; where no valid count is within `T`,
//! the smallest within it, marked (`valid: false`).
//!
//! The rest of this module's documentation is on [`fit_to_tolerance`], where the library's users read it.

use std::collections::BTreeMap;

use serde::Serialize;

use crate::optimize::Control;
use crate::{fit_offsets_with, FitConfig, FitMethod, FitOutcome, HullError, Offsets, Units};

/// The default tolerance as a fraction of the beam: 0.5 % (1 % of the largest half-breadth).
///
/// A fraction of the beam because the beam is the size every offset of a hull is read
/// against; 0.5 % because it is what the plain least squares reaches on the tables of
/// `testdata/` at about its default count or fewer (measured: the Series 60 sample 81 mm at
/// 8x25, the yacht 20 mm at 5x23), while a finer figure is reached on most of them only by a
/// net as dense as interpolation's.
pub const DEFAULT_TOLERANCE_OF_BEAM: f64 = 0.005;

/// The default tolerance (`--tolerance default`): [`DEFAULT_TOLERANCE_OF_BEAM`] of the beam `2 max |y|` of the
/// offsets (for free-form sections, twice their largest distance from the plane `y = 0`);
/// `None` for offsets all in that plane (then there is no beam to take a fraction of).
///
/// ```
/// let sample = hull::series60_sample();
/// // The Series 60 parent's beam is 16.26 m: 0.5 % of it is 81 mm.
/// let t = hull::default_tolerance(&sample).expect("a beam");
/// assert!((t - 0.005 * 16.264).abs() < 1e-3, "{t}");
/// ```
pub fn default_tolerance(offsets: &Offsets) -> Option<f64> {
    let half = offsets.sections.iter().flat_map(|s| s.points.iter()).map(|p| p.y.abs()).fold(0.0, f64::max);
    (half > 0.0 && half.is_finite()).then_some(DEFAULT_TOLERANCE_OF_BEAM * 2.0 * half)
}

/// What [`fit_offsets_within`] aims at.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub enum Goal {
    /// `config.ctrl` (or [`crate::default_ctrl`]) as given: no search. The default.
    #[default]
    Count,
    /// The fewest control points within this max error (in the offsets' units); no count
    /// reaching it is an error ([`HullError::ToleranceNotReached`]).
    Tolerance(f64),
    /// The fewest control points within [`default_tolerance`] by a quick search, faired within
    /// it; where no count reaches it, the closest valid surface found, and where none is
    /// valid, the default count; refereed against the default count by the held-out error
    /// (`hullskin fit --tolerance default`).
    DefaultTolerance,
}

impl std::str::FromStr for Goal {
    type Err = String;

    /// `--tolerance`'s value: `default` ([`Goal::DefaultTolerance`]) or a length
    /// ([`Goal::Tolerance`]; its sign and finiteness are checked by the search).
    ///
    /// ```
    /// use hull::Goal;
    /// assert_eq!("default".parse::<Goal>(), Ok(Goal::DefaultTolerance));
    /// assert_eq!("0.05".parse::<Goal>(), Ok(Goal::Tolerance(0.05)));
    /// assert!("5cm".parse::<Goal>().unwrap_err().contains("expected"));
    /// ```
    fn from_str(s: &str) -> Result<Goal, String> {
        let s = s.trim();
        if s.eq_ignore_ascii_case("default") {
            return Ok(Goal::DefaultTolerance);
        }
        s.parse::<f64>().map(Goal::Tolerance).map_err(|_| {
            format!(
                "`{s}` is not a tolerance (expected a max error in the input's units, or `default` for 0.5 % of the beam)"
            )
        })
    }
}

/// Fit `offsets` with `config` as `goal` asks: with `config.ctrl` ([`Goal::Count`]; the default
/// fit, [`crate::refereed_by_held_out`], then cross-validated and refereed by its held-out error), or with
/// the fewest control points whose max error is within a tolerance ([`fit_to_tolerance`] on
/// the plain fits), then that count faired within the tolerance (an automatic fairing takes
/// the tolerance as its bound), with the record of the search. The faired fit is kept when it
/// stays within the tolerance and is no less sound than the searched fit; otherwise the
/// searched fit is kept, the faired one noted in [`FitOutcome::rejected`]. The search fits
/// plain least squares; the default fit of the default count ([`crate::default_ctrl`], as
/// [`Goal::Count`] fits it before its held-out referee: held on its surface where the net hold
/// folds or is less fair, faired) is then taken instead where it is valid and within the
/// tolerance and the count found is not, or has more control points ([`Referee`]).
/// [`Goal::DefaultTolerance`] searches with [`default_tolerance`] and takes the closest
/// surface where none reaches it (offsets in one plane have no beam: they get
/// [`crate::default_ctrl`]). What `hullskin fit` (and every caller that fits as the command
/// line does) runs; a stop on `control` returns the best surface so far.
///
/// # Errors
/// Those of [`crate::fit_offsets`], and of [`fit_to_tolerance`] with a tolerance.
pub fn fit_offsets_within(
    offsets: &Offsets,
    config: &FitConfig,
    goal: Goal,
    control: &Control<'_>,
) -> Result<(FitOutcome, Option<ToleranceSearch>), HullError> {
    let settings = match goal {
        Goal::Count => None,
        Goal::Tolerance(t) => Some(ToleranceSettings::new(t)),
        Goal::DefaultTolerance => default_tolerance(offsets).map(|t| ToleranceSettings {
            closest: true,
            diagonal: true,
            ..ToleranceSettings::new(t)
        }),
    };
    let Some(settings) = settings else {
        let mut outcome = fit_offsets_with(offsets, config, control)?;
        if crate::refereed_by_held_out(config) {
            crate::held_out_referee::referee_default_fit(offsets, &mut outcome, config, control);
        }
        return Ok((outcome, None));
    };
    let start = std::time::Instant::now();
    let (outcome, mut search) = refereed(offsets, config, goal, &settings, control)?;
    search.seconds = start.elapsed().as_secs_f64();
    if goal == Goal::DefaultTolerance {
        search.default = true;
    }
    Ok((outcome, Some(search)))
}

/// [`fit_offsets_within`] with its settings: the search and fairing, then the referee (by
/// accuracy for every tolerance, by the held-out error for [`Goal::DefaultTolerance`]).
/// Measured on R/V Gunnerus with `--tolerance 0.15`: the exact search's plain fits have
/// findings at every count up to 12x48 (128 fits, the cap), whose faired fit is at 145.7 mm
/// with a thin-plate energy of 23055; the default fit of the default count 12x47 is valid at
/// 112.6 mm, energy 131.7, and is kept.
fn refereed(
    offsets: &Offsets,
    config: &FitConfig,
    goal: Goal,
    settings: &ToleranceSettings,
    control: &Control<'_>,
) -> Result<(FitOutcome, ToleranceSearch), HullError> {
    // The default count as `Goal::Count` fits it (without its held-out referee, which this
    // search's own referee replaces), faired within the tolerance as the count
    // searched is ([`faired_within`]): the fairest surface of the default count within it, not
    // the fairest within the default fit's own error (the Series 60 Cb 0.80's default fit is
    // held on its surface and faired within its net hold's 214.5 mm, at 141.1 mm; within 93.8
    // mm, `--tolerance default`, it is at 93.5 mm).
    let fair = faired_within(config.fair, settings.tolerance);
    let default_fit = || fit_offsets_with(offsets, &FitConfig { ctrl: None, fair, ..*config }, control);
    // The default count faired as `hullskin fit` fairs it (within its own error, where `auto`
    // has no tolerance): `None` where that is `default_fit` already.
    let own_fit =
        || (fair != config.fair).then(|| fit_offsets_with(offsets, &FitConfig { ctrl: None, ..*config }, control));
    // `--tolerance default` replaces an unsound count found by the default count: no fairing for it.
    let (searched, mut search) =
        match searched_and_faired(offsets, config, settings, goal != Goal::DefaultTolerance, control)? {
            Searched::Found(outcome, search) => (*outcome, search),
            Searched::NotReached(record) if control.stopped() => return Err(not_reached(&record, offsets, None)),
            // No plain fit reaches the tolerance: the default fit of the default count may.
            Searched::NotReached(mut record) => {
                let usual = default_fit()?;
                let sound = usual.validity.is_empty();
                if !(sound && usual.error.overall.max <= settings.tolerance) {
                    // The closest valid surface named: faired within its own error, the
                    // default fit can be closer than faired within an unreachable tolerance
                    // (the 4 x 4 example within 1e-30 m: 186.0 mm, against its net hold's
                    // 276.5 mm faired within it and the search's 275.7 mm at 5x4). Where the
                    // fairing had a tolerance of its own, that is the same fit: not fitted again.
                    let own = own_fit().transpose()?;
                    let closer = std::iter::once(usual)
                        .chain(own)
                        .filter(|o| o.validity.is_empty())
                        .min_by(|a, b| a.error.overall.max.total_cmp(&b.error.overall.max));
                    return Err(not_reached(&record, offsets, closer.as_ref()));
                }
                let (best, at) = closest_tried(&record.tried).unwrap_or((f64::INFINITY, record.control_points));
                let valid = record.tried.iter().any(|c| c.control_points == at && c.valid);
                let referee = Referee::against(RefereeBasis::Accuracy, (at, best, valid), &usual, true, None);
                record.referee = Some(referee);
                record.keep(&usual);
                return Ok((usual, record));
            }
        };
    if control.stopped() {
        return Ok((searched, search));
    }
    let default_goal = goal == Goal::DefaultTolerance;
    if default_goal && !search.valid {
        // No valid count was found: the default count is kept, as `hullskin fit` makes it (so
        // it is never less sound than that): faired within the tolerance where that leaves no
        // more findings, else within its own error. Measured on R/V Gunnerus: within 48.1 mm
        // no smoothed fit of the default count is sound and its fold stays (163.3 mm); within
        // its own error smoothing 3e-1 removes it (112.6 mm), as the default fit does.
        let mut kept = default_fit()?;
        if !kept.validity.is_empty() && !control.stopped() {
            if let Some(own) = own_fit().transpose()? {
                if own.validity.len() < kept.validity.len() {
                    kept = own;
                }
            }
        }
        search.keep(&kept);
        search.kept_default_count = true;
        return Ok((kept, search));
    }
    let t = if search.reached { settings.tolerance } else { searched.error.overall.max };
    let counts = |o: &FitOutcome| [o.surface.n_u(), o.surface.n_v()];
    let (du, dv) = crate::default_ctrl(offsets, config.degree);
    if [du, dv] == counts(&searched) {
        return Ok((searched, search));
    }
    // The default count is fitted as `Goal::Count` fits it where it could be the answer:
    // its plain fit (the quick search's first probe) within `t`, for the held-out referee
    // below; or the count found not within the tolerance, or larger than the default count.
    // Then the default fit may be what the search's plain fits were not: it holds its surface
    // where the net hold folds or is less fair, and fairs (measured: the Series 60 Cb 0.80's
    // plain fit at its default count 6x19 misses the tolerance by 214.5 mm against 93.8, its
    // default fit is at 93.5 mm).
    let anchor = search.tried.iter().find(|c| c.control_points == [du, dv]).and_then(|c| c.max);
    let [nu, nv] = counts(&searched);
    let fewer = du * dv < nu * nv;
    let held_out_referee = default_goal && anchor.is_some_and(|m| m <= t);
    if !held_out_referee && search.reached && search.valid && !fewer {
        return Ok((searched, search));
    }
    let usual = default_fit()?;
    let sound = |o: &FitOutcome| o.validity.is_empty();
    let within = |o: &FitOutcome| sound(o) && o.error.overall.max <= settings.tolerance;
    let found = (counts(&searched), searched.error.overall.max, sound(&searched));
    let record = |basis, takes, held_out| Referee::against(basis, found, &usual, takes, held_out);
    // By accuracy at the offsets: the default fit valid and within the tolerance where the
    // count found is not (or has findings), or within it with fewer control points; where
    // neither reaches it (`--tolerance default`, whose count found is valid here), valid and
    // closer.
    let (u_max, s_max) = (usual.error.overall.max, searched.error.overall.max);
    let by_accuracy = (within(&usual) && (!within(&searched) || fewer))
        || (!search.reached && !within(&usual) && sound(&usual) && u_max < s_max);
    if by_accuracy || !held_out_referee || control.stopped() {
        search.referee = Some(record(RefereeBasis::Accuracy, by_accuracy, None));
        if !by_accuracy {
            return Ok((searched, search));
        }
        search.keep(&usual);
        return Ok((usual, search));
    }
    // The held-out referee: both within the tolerance (or no farther from it than the count
    // found), by their held-out max error (the error where there are no offsets).
    let options = crate::HeldOutOptions::default();
    let held = |o: &FitOutcome| {
        crate::held_out_for_config_with(offsets, &crate::held_out_refit_config(o), &options, control).ok().flatten()
    };
    let (h_searched, h_usual) = (held(&searched), held(&usual));
    let (Some(hs), Some(hu)) = (h_searched, h_usual) else {
        return Ok((searched, search));
    };
    // The default count replaces the count found when it is as sound, within the tolerance
    // (or no farther from it) and closer to the offsets held out.
    let takes = sound(&usual) >= sound(&searched) && u_max <= t && hu.max < hs.max;
    search.referee = Some(record(RefereeBasis::HeldOut, takes, Some((hs.max, hu.max))));
    // The chosen fit's held-out error is the default cross-validation's: kept.
    let (mut chosen, held_out) = if takes { (usual, hu) } else { (searched, hs) };
    search.keep(&chosen);
    chosen.error.held_out = Some(held_out);
    Ok((chosen, search))
}

impl Referee {
    /// The count found `(counts, max error, valid)` against `usual`, the default fit of the
    /// default count, by `basis`; `held_out` the held-out maxima `(found, usual)` where measured.
    fn against(
        basis: RefereeBasis,
        found: ([usize; 2], f64, bool),
        usual: &FitOutcome,
        chose_default_count: bool,
        held_out: Option<(f64, f64)>,
    ) -> Self {
        Referee {
            basis,
            searched: found.0,
            searched_max: found.1,
            searched_valid: found.2,
            searched_held_out_max: held_out.map(|h| h.0),
            default_count: [usual.surface.n_u(), usual.surface.n_v()],
            default_count_held_out_max: held_out.map(|h| h.1),
            default_count_max: usual.error.overall.max,
            default_count_valid: usual.validity.is_empty(),
            chose_default_count,
        }
    }
}

/// How the referee of a tolerance search compared the count found with the default count.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RefereeBasis {
    /// By accuracy at the offsets: the default count's default fit is kept when it is valid and
    /// within the tolerance where the count found is not, or within it with fewer control
    /// points, or (neither within it) valid and closer to the offsets.
    Accuracy,
    /// By the held-out max error (`--tolerance default` only): both within the tolerance (or
    /// the default count no farther from it than the count found), the default count kept
    /// when it is as sound and closer to the held-out offsets.
    HeldOut,
}

/// The second opinion on a tolerance search: the count it found against
/// the default count ([`crate::default_ctrl`]) as the default fit makes it, compared as
/// [`RefereeBasis`] says, and which was kept.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Referee {
    pub basis: RefereeBasis,
    /// The count the search found `[nu, nv]`, its max error at the offsets and (by the
    /// held-out error only) its held-out max error.
    pub searched: [usize; 2],
    pub searched_max: f64,
    /// Whether the count found's fit has no validity finding.
    pub searched_valid: bool,
    #[serde(skip_serializing_if = "Option::is_none")]
    pub searched_held_out_max: Option<f64>,
    /// The default count `[nu, nv]`, its held-out max error (by the held-out error only).
    pub default_count: [usize; 2],
    #[serde(skip_serializing_if = "Option::is_none")]
    pub default_count_held_out_max: Option<f64>,
    /// The default count's max error at the offsets.
    pub default_count_max: f64,
    /// Whether the default count's fit has no validity finding.
    pub default_count_valid: bool,
    /// Whether the default count was kept.
    pub chose_default_count: bool,
}

/// `fair` with `auto`'s tolerance, where it has none, `t`: the fairest surface within `t`.
fn faired_within(fair: crate::Fairing, t: f64) -> crate::Fairing {
    match fair {
        crate::Fairing::Auto { tolerance: None } => crate::Fairing::Auto { tolerance: Some(t) },
        f => f,
    }
}

/// The fewest control points within `settings` on the plain fits, then that count faired
/// within the tolerance (or, where it was not reached, within the max error reached). The
/// faired fit is kept when it stays within that bound and is no less sound than the searched
/// fit; otherwise the searched fit is kept, the faired one noted in [`FitOutcome::rejected`].
/// Without `fair_unsound`, a searched fit with validity findings is returned unfaired. Where no
/// count reaches an explicit tolerance, the record of the search alone.
fn searched_and_faired(
    offsets: &Offsets,
    config: &FitConfig,
    settings: &ToleranceSettings,
    fair_unsound: bool,
    control: &Control<'_>,
) -> Result<Searched, HullError> {
    let plain = FitConfig { fair: crate::Fairing::Off, ..*config };
    let (outcome, search) = search_counts(offsets, &plain, settings, control)?;
    let Some(outcome) = outcome else {
        return Ok(Searched::NotReached(search));
    };
    let r = ToleranceFit { outcome, search };
    if !fair_unsound && !r.search.valid {
        return Ok(Searched::Found(Box::new(r.outcome), r.search));
    }
    let t = if r.search.reached { settings.tolerance } else { r.outcome.error.overall.max };
    let fair = faired_within(config.fair, t);
    if fair == crate::Fairing::Off || control.stopped() {
        return Ok(Searched::Found(Box::new(r.outcome), r.search));
    }
    let [nu, nv] = r.search.control_points;
    // The default count as the default fit makes it (`ctrl: None`), with its alternatives for
    // validity and fairness: measured on the trawler, whose count found is the default 16x16,
    // the fit on universal parameters faired against the plain least squares (thin-plate energy
    // 125.0 against 346.2 for the default parameters' held net, both within 52.8 mm).
    let ctrl = (crate::default_ctrl(offsets, config.degree) != (nu, nv)).then_some((nu, nv));
    let faired = FitConfig { ctrl, fair, ..*config };
    let out = fit_offsets_with(offsets, &faired, control)?;
    // The faired fit must keep what the search found: within T, and valid if that was.
    let keeps = out.error.overall.max <= t && (out.validity.is_empty() || !r.outcome.validity.is_empty());
    if keeps || control.stopped() {
        // The record is the faired fit's: fairing may have removed the searched fit's findings.
        let mut search = r.search;
        search.keep(&out);
        return Ok(Searched::Found(Box::new(out), search));
    }
    let mut plain = r.outcome;
    plain.rejected.push(format!(
        "the faired fit at {nu}x{nv} (max {:.3e}, {} validity finding(s)) does not keep the searched fit's \
         tolerance or soundness; the searched fit is kept",
        out.error.overall.max,
        out.validity.len()
    ));
    Ok(Searched::Found(Box::new(plain), r.search))
}

/// What [`searched_and_faired`] gives: the count found with its fit and record, or, where no
/// count reaches an explicit tolerance, the record alone (`control_points` the closest count).
enum Searched {
    Found(Box<FitOutcome>, ToleranceSearch),
    NotReached(ToleranceSearch),
}

/// Settings of [`fit_to_tolerance`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ToleranceSettings {
    /// The largest acceptable max error, in the offsets' units.
    pub tolerance: f64,
    /// Fits at most (each a whole fit with its error measurement).
    pub max_fits: usize,
    /// Where no count reaches the tolerance, return the closest surface found (the valid one
    /// with the smallest max error, or the smallest max error if none is valid) instead of
    /// [`HullError::ToleranceNotReached`].
    pub closest: bool,
    /// The quick search: the default count ([`crate::default_ctrl`]), then a bisection over
    /// the counts in proportion to interpolation's (`nu / N = nv / K`), below the default
    /// count when it is within the tolerance and above it when not: about `log2 K` fits,
    /// instead of the exact scan (up to [`Self::max_fits`]). The count found is the fewest on
    /// that diagonal if the error falls as the counts grow along it, not necessarily the
    /// fewest of all counts.
    pub diagonal: bool,
}

impl ToleranceSettings {
    /// Fits at most by default: every count of the Series 60 table (110) and then some; on
    /// larger tables the exact scan may be cut (the bound's surface is still returned).
    pub const DEFAULT_MAX_FITS: usize = 128;

    /// `tolerance` with the default cap on fits.
    pub fn new(tolerance: f64) -> Self {
        ToleranceSettings { tolerance, max_fits: Self::DEFAULT_MAX_FITS, closest: false, diagonal: false }
    }
}

/// One count tried by the search.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct TriedCount {
    /// `[nu, nv]`.
    pub control_points: [usize; 2],
    /// The true max error, `None` if the fit failed (the kernel refused the count).
    pub max: Option<f64>,
    /// Whether `max <= tolerance` and the fit is valid (no validity finding).
    pub within: bool,
    /// Whether the fit has no validity finding (false also for a failed fit).
    pub valid: bool,
}

/// What the search did: `report.json`'s `"tolerance_search"`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct ToleranceSearch {
    pub tolerance: f64,
    /// The count chosen, `[nu, nv]`.
    pub control_points: [usize; 2],
    /// Interpolation's count `[N, K]`: points of the largest section by sections.
    pub interp_control_points: [usize; 2],
    /// `nu nv / (N K)`.
    pub ratio: f64,
    /// Fits done.
    pub fits: usize,
    /// False when the cap on fits or a stop (Ctrl-C) ended the search before it was done.
    pub complete: bool,
    /// Whether the chosen fit is valid: false when no count within the tolerance was, and the
    /// smallest within it (with its findings) was taken.
    pub valid: bool,
    /// Whether the chosen fit is within the tolerance: false only when the closest surface
    /// was asked for ([`ToleranceSettings::closest`]) and no count reached the tolerance.
    pub reached: bool,
    /// Whether the tolerance was the default one ([`Goal::DefaultTolerance`]).
    pub default: bool,
    /// Whether the quick search ran ([`ToleranceSettings::diagonal`]).
    pub quick: bool,
    /// Whether `--tolerance default` found no valid count and kept the default count
    /// ([`crate::default_ctrl`]) as `Goal::Count` fits it before its held-out referee.
    pub kept_default_count: bool,
    /// The comparison of the count found with the default count ([`Referee`]; `None` when they
    /// are the same count, or when the default count could not be the answer: the count found
    /// valid, within the tolerance and with fewer control points, and, for `--tolerance
    /// default`, the default count's plain fit outside the tolerance).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub referee: Option<Referee>,
    /// Wall time of the whole [`fit_offsets_within`] call, seconds: the search, the fairing
    /// of the count found and, for `--tolerance default`, the referee's fit and held-out refits
    /// (0 when only [`fit_to_tolerance`] ran).
    pub seconds: f64,
    /// Every count fitted, in order.
    pub tried: Vec<TriedCount>,
}

impl ToleranceSearch {
    /// Record `kept` as the chosen fit: its count, its ratio to interpolation's, whether it is
    /// valid and within the tolerance.
    fn keep(&mut self, kept: &FitOutcome) {
        let (nu, nv) = (kept.surface.n_u(), kept.surface.n_v());
        let [n, k] = self.interp_control_points;
        self.control_points = [nu, nv];
        self.ratio = (nu * nv) as f64 / (n * k) as f64;
        self.valid = kept.validity.is_empty();
        self.reached = kept.error.overall.max <= self.tolerance;
    }

    /// One line for the terminal: the count chosen against interpolation's, e.g.
    /// `tolerance 1.000e-2 m: 6x12 = 72 control points, 36.0 % of interpolation's 8x25 = 200 (14 fits)`.
    pub fn summary(&self, units: Units) -> String {
        let [nu, nv] = self.control_points;
        let [n, k] = self.interp_control_points;
        let which = if self.default {
            format!("default tolerance {:.3e} {units} (0.5 % of the beam)", self.tolerance)
        } else {
            format!("tolerance {:.3e} {units}", self.tolerance)
        };
        let mut s = if self.kept_default_count {
            format!(
                "{which}: no plain fit the search tried is valid: the default count {nu}x{nv} = {} \
                 control points is kept as the default fit makes it, {}",
                nu * nv,
                match (self.valid, self.reached) {
                    (true, true) => "valid and within the tolerance",
                    (true, false) => "valid, not within the tolerance",
                    (false, _) => "with validity findings",
                }
            )
        } else if self.reached {
            format!("{which}: {nu}x{nv} = {} control points", nu * nv)
        } else {
            format!(
                "{which} not reached by any count: the closest surface found, {nu}x{nv} = {} control points",
                nu * nv
            )
        };
        s.push_str(&format!(
            ", {:.1} % of interpolation's {n}x{k} = {} ({} fits",
            100.0 * self.ratio,
            n * k,
            self.fits
        ));
        if self.quick {
            s.push_str(", quick search over counts in proportion to interpolation's");
        }
        if self.seconds > 0.0 {
            s.push_str(&format!(", {:.2} s in all", self.seconds));
        }
        if !self.complete {
            s.push_str(", search cut short: the count may not be the smallest");
        }
        if !self.valid && !self.kept_default_count {
            s.push_str(if self.reached {
                "; no count within it is valid: the smallest within it is taken, with its findings"
            } else {
                "; no count fitted is valid: the closest is taken, with its findings"
            });
        }
        s.push(')');
        if let Some(r) = &self.referee {
            let [a, b] = r.searched;
            let [c, d] = r.default_count;
            let default = format!(
                "the default count {c}x{d} (max {:.3e} {units}{})",
                r.default_count_max,
                if r.default_count_valid { "" } else { ", with validity findings" }
            );
            s.push_str(&match (r.basis, r.searched_held_out_max, r.default_count_held_out_max) {
                (RefereeBasis::HeldOut, Some(hs), Some(hu)) => format!(
                    "\nheld-out max error {hs:.3e} {units} at {a}x{b} against {hu:.3e} {units} at {default}: {}",
                    if r.chose_default_count {
                        format!("{c}x{d} is kept, closer between the offsets within the tolerance")
                    } else {
                        format!("{a}x{b} is kept")
                    }
                ),
                _ => format!(
                    "\n{a}x{b} (max {:.3e} {units}) against {default}, as the default fit makes it: {}",
                    r.searched_max,
                    match (r.chose_default_count, r.default_count_valid && r.default_count_max <= self.tolerance) {
                        (false, _) => format!("{a}x{b} is kept"),
                        (true, true) if !r.searched_valid => {
                            format!("{c}x{d} is kept, valid and within the tolerance where {a}x{b} has findings")
                        }
                        (true, true) if r.searched_max > self.tolerance => {
                            format!("{c}x{d} is kept, within the tolerance where {a}x{b} is not")
                        }
                        (true, true) => format!("{c}x{d} is kept, within the tolerance with fewer control points"),
                        (true, false) => format!("{c}x{d} is kept, valid and closer to the offsets"),
                    }
                ),
            });
        }
        s
    }
}

/// The chosen fit and the record of the search.
#[derive(Clone, Debug)]
pub struct ToleranceFit {
    pub outcome: FitOutcome,
    pub search: ToleranceSearch,
}

/// The smallest surface (fewest control points `nu nv`) of `config`'s method whose true max
/// error is within `settings.tolerance`; `config.ctrl` is ignored. See [`fit_to_tolerance`] for the
/// strategy and its assumption.
///
/// Strategy. Counts range over `p + 1 <= nu <= N` and `q + 1 <= nv <= K` (`N` offsets in the
/// largest non-degenerate section, `K` sections, `p`, `q` the degrees the kernel uses); `(N, K)`
/// is interpolation's count. If the max error `E(nu, nv)` never grew with either count, the
/// counts within `T` would form a staircase (for each `nu` a least `nv*(nu)`, not growing with
/// `nu`) found by bisection in about `(N - p) log2 K` fits. It is only roughly so: the knots
/// and parameters are chosen per count, and on the Series 60 table `E(8, 19) = 12.7 mm` but
/// `E(8, 20) = 21.4 mm`. So the bisection only supplies a bound, and a scan makes it exact:
///
/// 1. fit `(N, K)` (interpolation for the plain least squares; held within the offsets'
///    envelope it may miss `T` where smaller counts reach it, so the search goes on);
/// 2. bound: for `nu = p + 1, ..., N`, bisect for the least `nv` within `T` over
///    `[q + 1, min(nv(nu - 1), (B - 1) / nu)]`, `B` the fewest control points found within `T`
///    so far (only strictly smaller surfaces are of interest); stop when `nu (q + 1) >= B`.
///    Every success is a fitted, measured surface, so `B` is an upper bound whatever the data;
/// 3. exact: fit the counts with fewer than `B` control points in increasing order of
///    `nu nv`; the first within `T` (with the others of as many control points) is the least,
///    as every smaller count was fitted and missed.
///
/// So the answer is the true least count within `T`, with no assumption on `E`, unless the
/// cap on fits ([`ToleranceSettings::max_fits`]) or a stop (Ctrl-C) cuts the search: then the
/// best surface found so far is returned (within `T`, possibly not the smallest) and marked
/// incomplete. Every count is fitted at most once (memoised). Of two surfaces with as many
/// control points, the one with the smaller max error is kept.
///
/// Measured on the Series 60 table (8 x 25 offsets, 110 counts; release, this 2-core machine):
///
/// | method | T | count (control points) | fits | time |
/// |---|---|---|---|---|
/// | approx | 0.05 m | 8 x 11 (88) | 81 | 0.16 s |
/// | approx | 0.02 m | 8 x 19 (152) | 104 | 0.23 s |
/// | approx | 0.01 m | 8 x 23 (184) | 109 | 0.25 s |
/// | lm | 0.05 m | 7 x 9 (63) | 48 | 0.8 s |
/// | lm | 0.02 m | 6 x 16 (96) | 81 | 1.9 s |
/// | lm | 0.01 m | 6 x 20 (120) | 87 | 2.3 s |
///
/// The bound alone (bisection) gave 8 x 21 and 7 x 15 at 0.02 m. GSA costs about a second a
/// fit: there the cap matters (`--iterations` shortens each fit).
///
/// # Errors
/// [`HullError::FitSetting`] for a tolerance that is not a positive finite number,
/// [`HullError::ToleranceWithInterp`] for the `interp` method (whose count is fixed); [`HullError::ToleranceNotReached`] when no count fitted
/// reaches the tolerance (naming the best max error found); and the errors of
/// [`fit_offsets`](crate::fit_offsets) other than a refused count (invalid offsets, bad
/// degrees).
pub fn fit_to_tolerance(
    offsets: &Offsets,
    config: &FitConfig,
    settings: &ToleranceSettings,
    control: &Control<'_>,
) -> Result<ToleranceFit, HullError> {
    match search_counts(offsets, config, settings, control)? {
        (Some(outcome), search) => Ok(ToleranceFit { outcome, search }),
        (None, search) => Err(not_reached(&search, offsets, None)),
    }
}

/// [`fit_to_tolerance`]'s search: the chosen fit (`None` when no count reaches the tolerance
/// and the closest was not asked for) and the record (then `control_points` the closest count).
fn search_counts(
    offsets: &Offsets,
    config: &FitConfig,
    settings: &ToleranceSettings,
    control: &Control<'_>,
) -> Result<(Option<FitOutcome>, ToleranceSearch), HullError> {
    let t = settings.tolerance;
    if !(t > 0.0 && t.is_finite()) {
        return Err(HullError::FitSetting { name: "tolerance", value: t, expected: "a positive number" });
    }
    if config.method == FitMethod::Interp {
        return Err(HullError::ToleranceWithInterp);
    }
    let (big_n, k) = counts(offsets);
    let nu_lo = config.degree.0.min(big_n.saturating_sub(1)) + 1;
    let nv_lo = config.degree.1.min(k.saturating_sub(1)) + 1;
    let mut s = Searcher {
        offsets,
        config,
        control,
        tolerance: t,
        max_fits: settings.max_fits.max(1),
        memo: BTreeMap::new(),
        tried: Vec::new(),
        best: None,
        unsound: None,
        closest: None,
        keep_closest: settings.closest,
        cut: false,
    };
    if settings.diagonal {
        // The quick search: from the default count, bisection over `nv` on the diagonal
        // `nu / N = nv / K`, down when the default count is within T, up when it is not.
        let (du, dv) = crate::default_ctrl(offsets, config.degree);
        let nu_of = |nv: usize| ((nv * big_n + k / 2) / k.max(1)).clamp(nu_lo, big_n.max(nu_lo));
        let anchor = s.probe(du, dv)?;
        let (mut lo, mut hi) = match anchor {
            Some(true) => (nv_lo, dv.saturating_sub(1)),
            Some(false) => (dv + 1, k),
            None => (1, 0),
        };
        while lo <= hi && hi >= nv_lo {
            let mid = lo + (hi - lo) / 2;
            match s.probe(nu_of(mid), mid)? {
                Some(true) => hi = mid - 1,
                Some(false) => lo = mid + 1,
                None => break,
            }
        }
    } else {
        // 1. Interpolation's count. Held within the offsets' envelope it may miss where fewer
        //    control points reach T (the hold costs more where the net is denser), so a miss
        //    does not end the search: the scan below then covers every count, within the cap.
        s.probe(big_n, k)?;
        // 2. The bound: the staircase, nu upward.
        let mut nv_prev = k;
        for nu in nu_lo..=big_n {
            let best = s.best_count();
            if s.cut || nu * nv_lo >= best {
                break;
            }
            let (mut lo, mut hi) = (nv_lo, nv_prev.min((best - 1) / nu));
            while lo <= hi {
                let mid = lo + (hi - lo) / 2;
                match s.probe(nu, mid)? {
                    Some(true) => {
                        nv_prev = mid;
                        hi = mid - 1;
                    }
                    Some(false) => lo = mid + 1,
                    None => break,
                }
            }
        }
        // 3. Exact: every count below the bound, fewest control points first.
        let bound = s.best_count();
        let mut below: Vec<(usize, usize)> = (nu_lo..=big_n)
            .flat_map(|nu| (nv_lo..=k).map(move |nv| (nu, nv)))
            .filter(|&(a, b)| a * b < bound)
            .collect();
        below.sort_unstable_by_key(|&(a, b)| (a * b, a));
        let mut found: Option<usize> = None;
        for (nu, nv) in below {
            if found.is_some_and(|c| nu * nv > c) {
                break;
            }
            match s.probe(nu, nv)? {
                Some(true) => found = Some(nu * nv),
                Some(false) => {}
                None => break,
            }
        }
    }
    let fits = s.tried.len();
    let reached = s.best.is_some() || s.unsound.is_some();
    let outcome = s.best.or(s.unsound).or(s.closest);
    let valid = outcome.as_ref().is_some_and(|o| o.validity.is_empty());
    let [nu, nv] = match &outcome {
        Some(o) => [o.surface.n_u(), o.surface.n_v()],
        None => closest_tried(&s.tried).map_or([big_n, k], |(_, at)| at),
    };
    let search = ToleranceSearch {
        tolerance: t,
        control_points: [nu, nv],
        interp_control_points: [big_n, k],
        ratio: (nu * nv) as f64 / (big_n * k) as f64,
        fits,
        complete: !s.cut,
        valid,
        reached,
        default: false,
        quick: settings.diagonal,
        kept_default_count: false,
        referee: None,
        seconds: 0.0,
        tried: s.tried,
    };
    Ok((outcome, search))
}

/// The least max error of the counts tried, and its count.
fn closest_tried(tried: &[TriedCount]) -> Option<(f64, [usize; 2])> {
    tried.iter().filter_map(|c| c.max.map(|m| (m, c.control_points))).min_by(|a, b| a.0.total_cmp(&b.0))
}

/// The error of a search that no count reached, from its record (`control_points` the
/// closest count, or interpolation's when no fit was done), naming `closer` instead where it is
/// closer than every count tried (the referee's valid default fit; the fits stay the search's).
fn not_reached(search: &ToleranceSearch, offsets: &Offsets, closer: Option<&FitOutcome>) -> HullError {
    let (mut best, mut at) = closest_tried(&search.tried).unwrap_or((f64::INFINITY, search.control_points));
    if let Some(o) = closer.filter(|o| o.error.overall.max < best) {
        (best, at) = (o.error.overall.max, [o.surface.n_u(), o.surface.n_v()]);
    }
    HullError::ToleranceNotReached {
        tolerance: search.tolerance,
        best,
        control_points: (at[0], at[1]),
        fits: search.fits,
        units: offsets.units.symbol(),
    }
}

/// `(N, K)`: points of the largest non-degenerate section (a pointed end carries no shape
/// along u, as in [`default_ctrl`](crate::default_ctrl)) and sections.
fn counts(offsets: &Offsets) -> (usize, usize) {
    let tol = crate::COINCIDENT_REL * offsets.size();
    let n = offsets.sections.iter().filter(|s| !s.is_point(tol)).map(|s| s.points.len()).max().unwrap_or(0);
    (n, offsets.sections.len())
}

struct Searcher<'a, 'c> {
    offsets: &'a Offsets,
    config: &'a FitConfig,
    control: &'a Control<'c>,
    tolerance: f64,
    max_fits: usize,
    /// `(nu, nv)` -> within the tolerance.
    memo: BTreeMap<(usize, usize), bool>,
    tried: Vec<TriedCount>,
    best: Option<FitOutcome>,
    /// The smallest surface within the tolerance that has validity findings.
    unsound: Option<FitOutcome>,
    /// The closest surface: valid before not, then the smallest max error (kept only when
    /// [`ToleranceSettings::closest`] asks for it).
    closest: Option<FitOutcome>,
    keep_closest: bool,
    /// The cap or a stop ended the search.
    cut: bool,
}

impl Searcher<'_, '_> {
    /// Control points of the best surface so far (`usize::MAX` if none).
    fn best_count(&self) -> usize {
        self.best.as_ref().map_or(usize::MAX, |b| b.surface.n_u() * b.surface.n_v())
    }

    /// Fit `(nu, nv)` (once): `Some(within)`, or `None` once the cap or a stop cuts the search.
    fn probe(&mut self, nu: usize, nv: usize) -> Result<Option<bool>, HullError> {
        if let Some(&within) = self.memo.get(&(nu, nv)) {
            return Ok(Some(within));
        }
        if self.cut || self.tried.len() >= self.max_fits || self.control.stopped() {
            self.cut = true;
            return Ok(None);
        }
        let cfg = FitConfig { ctrl: Some((nu, nv)), ..*self.config };
        let (max, outcome) = match fit_offsets_with(self.offsets, &cfg, self.control) {
            Ok(out) => (Some(out.error.overall.max), Some(out)),
            // The kernel refused this count (too few data for it, a singular system): it
            // does not reach the tolerance.
            Err(HullError::Fit { .. }) => (None, None),
            Err(e) => return Err(e),
        };
        let valid = outcome.as_ref().is_some_and(|o| o.validity.is_empty());
        let close = max.is_some_and(|m| m <= self.tolerance);
        let within = close && valid;
        self.tried.push(TriedCount { control_points: [nu, nv], max, within, valid });
        self.memo.insert((nu, nv), within);
        if let (true, Some(out)) = (self.keep_closest, &outcome) {
            let rank = |o: &FitOutcome| (!o.validity.is_empty(), o.error.overall.max);
            let closer = |c: &FitOutcome| rank(out).0.cmp(&rank(c).0).then(rank(out).1.total_cmp(&rank(c).1)).is_lt();
            if self.closest.as_ref().is_none_or(closer) {
                self.closest = Some(out.clone());
            }
        }
        // Within T but with findings: the answer only if no valid count is.
        if let (true, false, Some(out)) = (close, valid, &outcome) {
            let count = |o: &FitOutcome| o.surface.n_u() * o.surface.n_v();
            if self.unsound.as_ref().is_none_or(|b| nu * nv < count(b)) {
                self.unsound = Some(out.clone());
            }
        }
        if let (true, Some(out)) = (within, outcome) {
            let better = match &self.best {
                None => true,
                Some(b) => {
                    let (c, cb) = (nu * nv, b.surface.n_u() * b.surface.n_v());
                    c < cb || (c == cb && out.error.overall.max < b.error.overall.max)
                }
            };
            if better {
                self.best = Some(out);
            }
        }
        // A fit stopped part-way still counts (its surface is measured), but the search ends.
        if self.control.stopped() {
            self.cut = true;
        }
        Ok(Some(within))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::{quiet, Algorithm, OptimSettings};
    use crate::{fit_offsets, series60_sample, Section, Units};
    use nurbs::Vec3;
    use std::sync::atomic::AtomicBool;

    fn search(offsets: &Offsets, config: &FitConfig, t: f64) -> Result<ToleranceFit, HullError> {
        quiet(|c| fit_to_tolerance(offsets, config, &ToleranceSettings::new(t), c))
    }

    /// 9 stations of 7 waterlines of `y = b/2 (1 - 0.8 (2x/l)^2) (1 - (1 - z/t)^4)`: 4 x 6 =
    /// 24 counts, cheap enough to search completely in a debug build.
    fn small_hull() -> Offsets {
        let (l, b, t) = (100.0, 16.0, 6.0);
        let sections = (0..9)
            .map(|s| {
                let x = -l / 2.0 + l * s as f64 / 8.0;
                let pts = (0..7)
                    .map(|j| {
                        let z = t * j as f64 / 6.0;
                        let y = b / 2.0 * (1.0 - 0.8 * (2.0 * x / l).powi(2)) * (1.0 - (1.0 - z / t).powi(4));
                        Vec3::new(x, y, z)
                    })
                    .collect();
                Section::new(format!("{s}"), pts)
            })
            .collect();
        Offsets::new("small hull", Units::Metre, sections)
    }

    /// The search's own guarantees, read from its record: the surface is within T, the record
    /// matches it, every count is fitted once, and (complete) every count with fewer control
    /// points was fitted and missed, so none is smaller.
    fn assert_least(
        r: &ToleranceFit,
        t: f64,
        counts: (std::ops::RangeInclusive<usize>, std::ops::RangeInclusive<usize>),
    ) {
        let (nu, nv) = (r.outcome.surface.n_u(), r.outcome.surface.n_v());
        assert_eq!(r.search.control_points, [nu, nv]);
        assert!(r.outcome.error.overall.max <= t, "{t}: {}", r.outcome.error.overall.max);
        assert!(r.search.complete);
        assert_eq!(r.search.fits, r.search.tried.len());
        let mut seen: Vec<[usize; 2]> = r.search.tried.iter().map(|c| c.control_points).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), r.search.fits, "a count fitted twice");
        let chosen = r.search.tried.iter().find(|c| c.control_points == [nu, nv]).expect("recorded");
        assert_eq!(chosen.max, Some(r.outcome.error.overall.max));
        for c in &r.search.tried {
            assert_eq!(c.within, c.valid && c.max.is_some_and(|m| m <= t));
        }
        for a in counts.0.clone() {
            for b in counts.1.clone() {
                if a * b < nu * nv {
                    let c = r.search.tried.iter().find(|c| c.control_points == [a, b]);
                    assert!(c.is_some_and(|c| !c.within), "{t}: {a}x{b} not fitted or within, {nu}x{nv} chosen");
                }
            }
        }
    }

    #[test]
    fn the_least_count_within_the_tolerance_and_its_record() {
        let offsets = small_hull();
        // Tolerances between the errors of small and large counts (none hard-coded: the
        // max errors of the plain fits at 4 x 4 and 6 x 7 and between).
        let e = |nu, nv| {
            let cfg = FitConfig { ctrl: Some((nu, nv)), ..FitConfig::default() };
            fit_offsets(&offsets, &cfg).expect("fits").error.overall.max
        };
        let (hi, lo) = (e(4, 4), e(6, 7));
        assert!(lo < hi);
        for t in [hi, (hi * lo).sqrt(), lo] {
            let r = search(&offsets, &FitConfig::default(), t).expect("reachable");
            assert_least(&r, t, (4..=7, 4..=9));
            assert_eq!(r.search.interp_control_points, [7, 9]);
            assert!((r.search.ratio - (r.outcome.surface.n_u() * r.outcome.surface.n_v()) as f64 / 63.0).abs() < 1e-15);
            // The chosen surface is the plain fit at that count, measured the same way.
            let [nu, nv] = r.search.control_points;
            assert_eq!(e(nu, nv), r.outcome.error.overall.max);
            let line = r.search.summary(Units::Metre);
            assert!(line.contains(&format!("{nu}x{nv} = {}", nu * nv)) && line.contains("7x9 = 63"), "{line}");
        }
        // The loosest tolerance is met by the smallest count.
        let r = search(&offsets, &FitConfig::default(), hi).expect("reachable");
        assert_eq!(r.search.control_points, [4, 4]);
    }

    #[test]
    fn exact_where_the_error_is_not_monotone() {
        // On the sample, E(8, 19) < 0.02 < E(8, 20): bisection along nv at nu = 8 steps over
        // 19 (over [4, 25] it tries 14, 20, 23, 21 and returns 21), so only the exact scan finds
        // a count this small.
        // The plain least squares, as measured then (not held within the envelope).
        let offsets = series60_sample();
        let t = 0.02;
        let free = FitConfig { envelope: crate::EnvelopeHold::Free, ..FitConfig::default() };
        let e = |nu, nv| {
            let cfg = FitConfig { ctrl: Some((nu, nv)), ..free };
            fit_offsets(&offsets, &cfg).expect("fits").error.overall.max
        };
        assert!(e(8, 19) <= t && e(8, 20) > t, "the case this test guards");
        let r = search(&offsets, &free, t).expect("reachable");
        assert_least(&r, t, (4..=8, 4..=25));
        let [nu, nv] = r.search.control_points;
        assert!(nu * nv <= 8 * 19, "chose {nu}x{nv}");
        // Not held, every fit of the sample crosses the centre plane: the smallest within T is
        // taken with its findings, and the record says so.
        assert!(!r.search.valid && !r.outcome.validity.is_empty());
        assert!(
            r.search.summary(Units::Metre).contains("no count within it is valid"),
            "{}",
            r.search.summary(Units::Metre)
        );
        // Held within the envelope (the default) the fits are valid, and the one chosen is.
        let held = search(&offsets, &FitConfig::default(), 0.2).expect("reachable");
        assert!(held.search.valid && held.outcome.validity.is_empty(), "{:?}", held.outcome.validity);
        assert!(held.search.tried.iter().all(|c| c.within == (c.valid && c.max.is_some_and(|m| m <= 0.2))));
    }

    #[test]
    fn weight_optimised_methods_are_searched_the_same_way() {
        let offsets = small_hull();
        let plain = |nu, nv| {
            let cfg = FitConfig { ctrl: Some((nu, nv)), ..FitConfig::default() };
            fit_offsets(&offsets, &cfg).expect("fits").error.overall.max
        };
        let t = plain(5, 6);
        // A short LM (20 iterations) keeps the debug build quick.
        let optim = OptimSettings { iterations: Some(20), ..OptimSettings::default() };
        let cfg = FitConfig { method: FitMethod::Optimized(Algorithm::Lm), optim, ..FitConfig::default() };
        let r = search(&offsets, &cfg, t).expect("reachable");
        assert_least(&r, t, (4..=7, 4..=9));
        assert_eq!(r.outcome.optimization.as_ref().map(|o| o.algorithm), Some("lm"));
    }

    #[test]
    fn unreachable_and_meaningless_tolerances_are_errors() {
        let offsets = small_hull();
        // Interpolation's round-off is about 1e-14 of the 100 m model: 1e-15 m is beyond it.
        let e = search(&offsets, &FitConfig::default(), 1e-15).expect_err("below round-off");
        match &e {
            HullError::ToleranceNotReached { best, control_points, fits, units, .. } => {
                // Every count was fitted (4 x 6 of them), the best at interpolation's.
                assert_eq!((*control_points, *fits, *units), ((7, 9), 24, "m"));
                assert!(*best > 1e-15 && *best < 1e-9, "{best}");
            }
            other => panic!("unexpected {other}"),
        }
        assert!(e.to_string().contains("best max error"), "{e}");
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY] {
            assert!(
                matches!(
                    search(&offsets, &FitConfig::default(), t),
                    Err(HullError::FitSetting { name: "tolerance", .. })
                ),
                "{t}"
            );
        }
        let interp = FitConfig { method: FitMethod::Interp, ..FitConfig::default() };
        let e = search(&offsets, &interp, 0.01).expect_err("interp has one count");
        assert!(e.to_string().contains("interp"), "{e}");
    }

    #[test]
    fn an_unreachable_tolerance_gives_the_closest_surface_when_asked() {
        let offsets = small_hull();
        // Below round-off (as above): no count reaches it, and every count is fitted.
        let s = ToleranceSettings { closest: true, ..ToleranceSettings::new(1e-15) };
        let r = quiet(|c| fit_to_tolerance(&offsets, &FitConfig::default(), &s, c)).expect("the closest");
        assert!(!r.search.reached && r.search.complete && r.search.fits == 24);
        // The closest is the smallest max error of every count tried (all valid here).
        let least = r.search.tried.iter().filter_map(|c| c.max).fold(f64::INFINITY, f64::min);
        assert_eq!(r.outcome.error.overall.max, least);
        assert!(r.search.valid && r.outcome.validity.is_empty());
        let line = r.search.summary(Units::Metre);
        assert!(line.contains("not reached by any count: the closest surface found, 7x9"), "{line}");
        assert!(line.contains("control points, ") && !line.contains(",,"), "one comma: {line}");
    }

    #[test]
    fn the_goal_is_parsed_from_the_command_line() {
        assert_eq!(Goal::default(), Goal::Count);
        assert_eq!(" Default ".parse::<Goal>(), Ok(Goal::DefaultTolerance));
        assert_eq!("1e-2".parse::<Goal>(), Ok(Goal::Tolerance(0.01)));
        let e = "five".parse::<Goal>().expect_err("not a length");
        assert!(e.contains("`five`") && e.contains("`default`"), "{e}");
        // Offsets in the plane y = 0 have no beam: `--tolerance default` fits the default count.
        let flat = Offsets::new(
            "flat",
            Units::Metre,
            (0..5)
                .map(|s| {
                    let pts = (0..5).map(|j| Vec3::new(s as f64, 0.0, j as f64 + 0.1 * (s * j) as f64)).collect();
                    Section::new(format!("{s}"), pts)
                })
                .collect(),
        );
        assert_eq!(default_tolerance(&flat), None);
        let (out, search) =
            quiet(|c| fit_offsets_within(&flat, &FitConfig::default(), Goal::DefaultTolerance, c)).expect("fits");
        assert!(search.is_none());
        let (nu, nv) = crate::default_ctrl(&flat, (3, 3));
        assert_eq!((out.surface.n_u(), out.surface.n_v()), (nu, nv));
    }

    #[test]
    fn the_default_fit_is_within_its_tolerance_and_refereed_by_the_held_out_error() {
        let offsets = small_hull();
        let t = default_tolerance(&offsets).expect("a beam");
        // 0.5 % of the 16 m beam.
        assert!((t - 0.08).abs() < 1e-12, "{t}");
        let (out, search) =
            quiet(|c| fit_offsets_within(&offsets, &FitConfig::default(), Goal::DefaultTolerance, c)).expect("fits");
        let search = search.expect("searched");
        assert!(search.default && search.reached && search.valid);
        assert!(out.error.overall.max <= t, "{} > {t}", out.error.overall.max);
        assert!(out.validity.is_empty());
        let counts = [out.surface.n_u(), out.surface.n_v()];
        let (du, dv) = crate::default_ctrl(&offsets, (3, 3));
        match &search.referee {
            // The count found is the default count: nothing to referee.
            None => assert_eq!(search.control_points, [du, dv]),
            Some(r) => {
                assert_eq!(r.default_count, [du, dv]);
                assert_eq!(counts, search.control_points);
                assert_eq!(counts, if r.chose_default_count { r.default_count } else { r.searched });
                // The held-out figure carried is the chosen fit's own, measured again here.
                let again = crate::held_out_for_config(
                    &offsets,
                    &crate::held_out_refit_config(&out),
                    &crate::HeldOutOptions::default(),
                )
                .expect("held out");
                let carried = out.error.held_out.as_ref().expect("carried");
                assert_eq!(carried.max, again.max);
                let kept = if r.chose_default_count { r.default_count_held_out_max } else { r.searched_held_out_max };
                assert_eq!(r.basis, RefereeBasis::HeldOut);
                assert_eq!(kept, Some(again.max));
                // The default count is only taken within the tolerance and when closer.
                if r.chose_default_count {
                    assert!(r.default_count_max <= t && r.default_count_held_out_max < r.searched_held_out_max);
                }
                assert!(
                    search.summary(Units::Metre).contains("held-out max error"),
                    "{}",
                    search.summary(Units::Metre)
                );
            }
        }
        // The searched count is the least within T: no count with fewer control points is.
        let [nu, nv] = search.referee.as_ref().map_or(search.control_points, |r| r.searched);
        for c in search.tried.iter().filter(|c| c.control_points[0] * c.control_points[1] < nu * nv) {
            assert!(!c.within, "{:?}", c.control_points);
        }
    }

    #[test]
    fn the_kept_default_count_says_whether_the_default_fit_is_valid_and_within() {
        // As on R/V Gunnerus (measured): every plain fit of the quick search has a finding, the
        // default fit of the default count 12x47 is valid at 112.6 mm, outside 48.1 mm.
        let mut search = ToleranceSearch {
            tolerance: 0.0481,
            control_points: [12, 47],
            interp_control_points: [16, 62],
            ratio: 564.0 / 992.0,
            fits: 5,
            complete: true,
            valid: true,
            reached: false,
            default: true,
            quick: true,
            kept_default_count: true,
            referee: None,
            seconds: 0.9,
            tried: Vec::new(),
        };
        let says = |s: &ToleranceSearch| s.summary(Units::Metre);
        assert!(
            says(&search).contains("no plain fit the search tried is valid: the default count 12x47 = 564 control points is kept as the default fit makes it, valid, not within the tolerance"),
            "{}",
            says(&search)
        );
        search.reached = true;
        assert!(says(&search).contains("makes it, valid and within the tolerance,"), "{}", says(&search));
        search.valid = false;
        assert!(says(&search).contains("makes it, with validity findings,"), "{}", says(&search));
        assert!(!says(&search).contains("the smallest within it is taken"), "{}", says(&search));
    }

    #[test]
    fn a_cap_or_a_stop_cuts_the_search_and_keeps_a_verified_surface() {
        let offsets = small_hull();
        let t = fit_offsets(&offsets, &FitConfig { ctrl: Some((6, 7)), ..FitConfig::default() })
            .expect("fits")
            .error
            .overall
            .max;
        let s = ToleranceSettings { max_fits: 3, ..ToleranceSettings::new(t) };
        let r = quiet(|c| fit_to_tolerance(&offsets, &FitConfig::default(), &s, c)).expect("corner is within");
        assert_eq!(r.search.fits, 3);
        assert!(!r.search.complete);
        assert!(r.outcome.error.overall.max <= t);
        assert!(r.search.summary(Units::Metre).contains("cut short"));
        // Stopped before the first fit: nothing was fitted, so nothing reached T.
        let stop = AtomicBool::new(true);
        let control = Control { stop: &stop, progress: &|_| {} };
        let e = fit_to_tolerance(&offsets, &FitConfig::default(), &ToleranceSettings::new(t), &control);
        assert!(matches!(e, Err(HullError::ToleranceNotReached { fits: 0, .. })), "{e:?}");
    }

    #[test]
    fn invalid_offsets_are_reported_not_searched() {
        let sections = vec![
            Section::new("a", vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 1.0)]),
            Section::new("b", vec![Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)]),
        ];
        let offsets = Offsets::new("two points each", Units::Metre, sections);
        // Degree 3 needs 4 points per section: an input error, not "no count reached".
        let e = search(&offsets, &FitConfig::default(), 0.1).expect_err("invalid");
        assert!(matches!(e, HullError::Input { .. }), "{e}");
    }
}
