//! The error between the offsets, by cross-validation: refit without some of the offsets and
//! measure how far the held-out ones are from the refitted surface.
//!
//! The rest of this module's documentation is on [`held_out_error`], where the library's users read it.

use std::sync::atomic::{AtomicU64, AtomicUsize, Ordering};
use std::time::Instant;

use nurbs::{NurbsError, NurbsSurface};
use rayon::prelude::*;
use serde::Serialize;

use crate::fit_error::{project_offsets, ErrorStats, HeldOutError, WorstPoint};
use crate::optimize::{quiet, Control, Progress};
use crate::pipeline::fit_surface_with;
use crate::{default_ctrl, FitConfig, FitMethod, HeldOutKind, HullError, Offsets, Section};

/// Settings of the cross-validation.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
pub struct HeldOutOptions {
    /// `K`, the number of folds of each kind (at least 2).
    pub folds: usize,
    /// Hold out whole sections.
    pub sections: bool,
    /// Hold out points within the sections.
    pub points: bool,
    /// Degrees `(p, q)` of the fit: no refit is given fewer than `p + 1` points in a section
    /// or fewer than `q + 1` sections ([`held_out_for_config`] takes them from its config).
    pub degree: (usize, usize),
}

impl HeldOutOptions {
    /// `K` by default: each refit keeps three quarters of the offsets of its kind, close to
    /// the full table, and the eight refits (both kinds) stay cheap.
    pub const DEFAULT_FOLDS: usize = 4;

    /// The default options with `folds` folds.
    pub fn with_folds(folds: usize) -> Self {
        HeldOutOptions { folds, ..Self::default() }
    }

    /// Check the options.
    ///
    /// # Errors
    /// [`HullError::HeldOut`] for fewer than 2 folds (one fold would hold out everything), or
    /// neither kind of hold-out asked for.
    pub fn validate(&self) -> Result<(), HullError> {
        if self.folds < 2 {
            return Err(HullError::HeldOut(HeldOutKind::Folds { folds: self.folds, default: Self::DEFAULT_FOLDS }));
        }
        if !(self.sections || self.points) {
            return Err(HullError::HeldOut(HeldOutKind::NothingAsked));
        }
        Ok(())
    }
}

impl Default for HeldOutOptions {
    fn default() -> Self {
        HeldOutOptions { folds: Self::DEFAULT_FOLDS, sections: true, points: true, degree: (3, 3) }
    }
}

/// Which kind of offsets a split holds out.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Sections,
    Points,
}

/// One refit: the offsets it is fitted to and those it is measured on.
#[derive(Clone, Debug)]
struct Split {
    kind: Kind,
    train: Offsets,
    held: Offsets,
}

/// The points of `section` whose index satisfies `keep` (their source lines kept in step).
fn section_where(section: &Section, keep: impl Fn(usize) -> bool) -> Section {
    let pick = |i: &usize| keep(*i);
    Section {
        label: section.label.clone(),
        points: (0..section.points.len()).filter(pick).map(|i| section.points[i]).collect(),
        lines: (0..section.lines.len()).filter(pick).map(|i| section.lines[i]).collect(),
        column: section.column,
    }
}

/// Sections with their index in the table.
type Numbered<'a> = Vec<(usize, &'a Section)>;

/// Fold `f` of the sections: interior sections `k mod K = f` held out, `None` if there is none
/// or the rest would be fewer than `q + 1` sections.
fn section_split(offsets: &Offsets, options: &HeldOutOptions, f: usize) -> Option<Split> {
    let n = offsets.sections.len();
    let out = |k: usize| k > 0 && k + 1 < n && k % options.folds == f;
    let (held, train): (Numbered, Numbered) = offsets.sections.iter().enumerate().partition(|&(k, _)| out(k));
    if held.is_empty() || train.len() < options.degree.1 + 1 {
        return None;
    }
    let pick = |v: Vec<(usize, &Section)>| Offsets {
        sections: v.into_iter().map(|(_, s)| s.clone()).collect(),
        ..offsets.clone()
    };
    Some(Split { kind: Kind::Sections, train: pick(train), held: pick(held) })
}

/// Fold `f` of the points: interior points `i mod K = f` of every section that can spare them
/// (not one point, at least `p + 1` left), `None` if no section can.
fn point_split(offsets: &Offsets, options: &HeldOutOptions, f: usize) -> Option<Split> {
    let tol = crate::COINCIDENT_REL * offsets.size();
    let mut train = Vec::with_capacity(offsets.sections.len());
    let mut held = Vec::new();
    for s in &offsets.sections {
        let n = s.points.len();
        let out = |i: usize| i > 0 && i + 1 < n && i % options.folds == f;
        let count = (0..n).filter(|&i| out(i)).count();
        if count == 0 || n - count < options.degree.0 + 1 || s.is_point(tol) {
            train.push(s.clone());
        } else {
            train.push(section_where(s, |i| !out(i)));
            held.push(section_where(s, out));
        }
    }
    if held.is_empty() {
        return None;
    }
    let with = |sections| Offsets { sections, ..offsets.clone() };
    Some(Split { kind: Kind::Points, train: with(train), held: with(held) })
}

/// Every split of `options`, sections' folds first, in fold order.
fn splits(offsets: &Offsets, options: &HeldOutOptions) -> Vec<Split> {
    let folds = 0..options.folds;
    let sections = folds.clone().filter(|_| options.sections).filter_map(|f| section_split(offsets, options, f));
    let points = folds.filter(|_| options.points).filter_map(|f| point_split(offsets, options, f));
    sections.chain(points).collect()
}

/// The held-out error of the fitter `fit` on `offsets`: see [`held_out_error`]. `fit` is any
/// method (a closure over [`crate::fit_offsets`], a fair fit, an optimiser); it is called once
/// per split, in parallel, and must be a pure function of the offsets it is given for the
/// result not to depend on the thread count.
///
/// The error at the offsets ([`crate::measure_fit_error`]) says nothing of the surface between
/// them: interpolation has none there whatever it does in between. K-fold cross-validation
/// (Hastie, Tibshirani and Friedman, *The Elements of Statistical Learning*, 2nd ed., 7.10)
/// estimates it from the data alone. With `K` folds, `f = 0, ..., K - 1`:
///
/// - **sections**: fold `f` refits without the interior sections `k` with `k mod K = f` (the
///   first and last stay: they bound the hull, and extrapolation past the ends is not what is
///   measured) and measures those sections' offsets;
/// - **points**: fold `f` refits without the interior points `i` (neither the first nor the
///   last of their section) with `i mod K = f` of every section, and measures them. A section
///   that would keep fewer than `p + 1` points (the degree along the sections), or that is one
///   point (a pointed stem), keeps all of its own.
///
/// Every held-out offset `Q` is measured by its true distance `min_{u,v} |S(u, v) - Q|` to the
/// refitted surface (closest-point projection, as the error at the offsets). The reported
/// `rms` and `max` are over all held-out offsets of both kinds, each measured once per kind
/// (every interior section, every interior point of a section that can spare it, is held out
/// exactly once).
///
/// A refit sees the data with gaps twice the spacing where the held-out offsets were: the
/// figure is the error of a slightly coarser table's fit, so it tends to overstate the error of
/// the full fit between its offsets (a conservative estimate; the Wigley test of
/// `tests/fit/held_out.rs` measures by how much on an exact surface).
///
/// The refits are independent and run in parallel (rayon); each is a pure function of its data,
/// and the distances are gathered in a fixed order, so the result is bit for bit the same
/// whatever the thread count, provided the fitter itself is (every method of
/// [`crate::fit_offsets`] is, for a given seed).
///
/// # Errors
/// [`HullError::HeldOut`] for invalid `options` or offsets too few to hold any out for the
/// degrees, and the first error of a refit (in split order).
pub fn held_out_error(
    offsets: &Offsets,
    fit: impl Fn(&Offsets) -> Result<NurbsSurface, HullError> + Sync,
    options: &HeldOutOptions,
) -> Result<HeldOutError, HullError> {
    unstopped(quiet(|control| held_out_error_with(offsets, fit, options, control)))
}

/// The result of a run that no stop can end ([`quiet`]): always `Some`.
fn unstopped(result: Result<Option<HeldOutError>, HullError>) -> Result<HeldOutError, HullError> {
    result?.ok_or(HullError::HeldOut(HeldOutKind::Stopped))
}

/// [`held_out_error`] with progress reports (`iteration` = refits done of `iterations`,
/// `best` = the largest held-out distance so far) and a stop flag: once it is raised no refit
/// starts and the result is `Ok(None)` (a partial estimate is not an estimate).
///
/// # Errors
/// As [`held_out_error`].
pub fn held_out_error_with(
    offsets: &Offsets,
    fit: impl Fn(&Offsets) -> Result<NurbsSurface, HullError> + Sync,
    options: &HeldOutOptions,
    control: &Control<'_>,
) -> Result<Option<HeldOutError>, HullError> {
    options.validate()?;
    let start = Instant::now();
    let splits = splits(offsets, options);
    if splits.is_empty() {
        let most = offsets.sections.iter().map(|s| s.points.len()).max().unwrap_or(0);
        return Err(HullError::HeldOut(HeldOutKind::TooFewOffsets {
            offsets: offsets.source.clone(),
            sections: offsets.sections.len(),
            most,
            degree: options.degree,
        }));
    }
    let done = AtomicUsize::new(0);
    // The largest distance so far, for the progress report: the bits of a non-negative float
    // order as the float does.
    let worst = AtomicU64::new(0);
    let measured: Vec<Option<Result<Measured, HullError>>> = splits
        .par_iter()
        .map(|split| {
            if control.stopped() {
                return None;
            }
            let result = fit(&split.train).map(|surface| {
                let feet = project_offsets(&surface, &split.held, None);
                let farthest = worst_held(offsets, &split.held, &feet);
                (feet.iter().map(|p| p.distance).collect::<Vec<f64>>(), farthest)
            });
            if let Ok((d, _)) = &result {
                worst
                    .fetch_max(d.iter().copied().filter(|d| *d >= 0.0).fold(0.0, f64::max).to_bits(), Ordering::SeqCst);
            }
            let best = f64::from_bits(worst.load(Ordering::SeqCst));
            let iteration = done.fetch_add(1, Ordering::SeqCst) + 1;
            (control.progress)(Progress { iteration, iterations: splits.len(), best, evaluations: iteration });
            Some(result)
        })
        .collect();
    let (mut sections, mut points) = (Vec::new(), Vec::new());
    let mut worst: Option<WorstPoint> = None;
    for (split, m) in splits.iter().zip(measured) {
        let Some(result) = m else { return Ok(None) };
        let (distances, split_worst) = result?;
        // The farthest of all, the first of the splits' order on a tie.
        if let Some(w) = split_worst.filter(|w| worst.as_ref().is_none_or(|b| w.distance > b.distance)) {
            worst = Some(w);
        }
        if let Some(d) = distances.iter().find(|d| !d.is_finite()) {
            return Err(HullError::Fit {
                method: "held-out refit",
                reason: NurbsError::NonFiniteResult { what: format!("held-out distance {d}") },
            });
        }
        match split.kind {
            Kind::Sections => sections.extend(distances),
            Kind::Points => points.extend(distances),
        }
    }
    if control.stopped() {
        return Ok(None);
    }
    let all: Vec<f64> = sections.iter().chain(&points).copied().collect();
    let overall = ErrorStats::from_distances(&all);
    Ok(Some(HeldOutError {
        rms: overall.rms,
        max: overall.max,
        sections: ErrorStats::from_distances(&sections),
        points: ErrorStats::from_distances(&points),
        folds: options.folds,
        refits: splits.len(),
        seconds: start.elapsed().as_secs_f64(),
        worst,
    }))
}

/// What one refit left out measured: the held-out offsets' distances, in their order, and the
/// farthest of them ([`worst_held`]).
type Measured = (Vec<f64>, Option<WorstPoint>);

/// The offset of `held` (a part of `offsets`) farthest from its foot in `feet` (in `held`'s
/// order), named by its index and line in `offsets`: a point is found again in its section by
/// its label and its coordinates, which the split copies bit for bit.
fn worst_held(offsets: &Offsets, held: &Offsets, feet: &[nurbs::SurfaceProjection]) -> Option<WorstPoint> {
    let mut w = crate::fit_error::fit_error_of(held, feet).worst?;
    let whole = offsets.sections.iter().find(|s| s.label == w.section);
    if let Some(i) = whole.and_then(|s| s.points.iter().position(|q| q.to_array() == w.point)) {
        w.index = i;
    }
    Some(w)
}

/// Whether `outcome`'s held-out error must still be measured with `options` (a caller
/// fitting as the command line does then measures it with [`held_out_refit_config`]). The
/// default fit's held-out referee ([`crate::refereed_by_held_out`]) and `--tolerance default`
/// ([`crate::Goal::DefaultTolerance`]) measured it with the default options (the degrees are
/// the fit's either way): that figure is kept for the default options, and dropped for 0 folds
/// (off), as any other.
pub fn held_out_wanted(outcome: &mut crate::FitOutcome, options: &HeldOutOptions) -> bool {
    if options.folds == 0 {
        outcome.error.held_out = None;
        return false;
    }
    let default = HeldOutOptions { degree: options.degree, ..HeldOutOptions::default() };
    !(outcome.error.held_out.is_some() && *options == default)
}

/// The settings the held-out refits of `outcome` use: the fit's own, with the approximation's
/// automatic fairing replaced by the smoothing it chose (or none, where it kept the plain fit),
/// so the refits measure the surface that was written between its offsets, at the cost of one
/// fit each instead of a whole search each.
pub fn held_out_refit_config(outcome: &crate::FitOutcome) -> FitConfig {
    let mut config = outcome.config;
    if config.method.algorithm().is_none() {
        if let crate::Fairing::Auto { .. } = config.fair {
            config.fair = match &outcome.fairing {
                Some(r) if r.lambda > 0.0 => crate::Fairing::Lambda(r.lambda),
                _ => crate::Fairing::Off,
            };
        }
    }
    config
}

/// For an optimised method with a held-out error: a warning line when it over-fits against
/// the plain approximation at the same control points ([`HeldOutError::overfits`]: lower RMS
/// at the offsets, higher held-out RMS), which is fitted and cross-validated for it (the cost
/// of an approximation and its refits, small beside the optimiser's).
pub fn overfitting_warning(offsets: &Offsets, outcome: &crate::FitOutcome) -> Option<String> {
    let held = outcome.error.held_out.as_ref()?;
    outcome.config.method.algorithm()?;
    let plain = FitConfig { method: FitMethod::Approx, ..outcome.config };
    let base = crate::fit_offsets(offsets, &plain).ok()?;
    let base_held =
        held_out_for_config(offsets, &held_out_refit_config(&base), &HeldOutOptions::with_folds(held.folds)).ok()?;
    let (at, at_base) = (outcome.error.overall.rms, base.error.overall.rms);
    held.overfits(at, at_base, &base_held).then(|| {
        let u = offsets.units.symbol();
        format!(
            "warning: {} over-fits: RMS {at:.3e} {u} at the offsets, below the plain approximation's {at_base:.3e} {u}, \
             but {:.3e} {u} held out, above its {:.3e} {u} (expected fewer control points or a fairer fit)",
            outcome.config.method, held.rms, base_held.rms
        )
    })
}

/// The held-out error of [`crate::fit_offsets`] with `config` (its degrees replace those of
/// `options`). Each refit keeps the full fit's density of control points: its counts
/// (`config.ctrl`, or [`default_ctrl`] of all the offsets) scaled by the share of the data the
/// refit keeps in each direction (the points of the largest section along u, the sections
/// across), rounded up, within `degree + 1` and the data. Keeping the counts themselves would
/// fit the sparser table with about one control point per offset, where least squares rings
/// between unevenly spaced data: on the Wigley hull the held-out error of the sections was 100
/// times the true error between them that way, 4.1 times with the scaled counts
/// (`tests/fit/held_out.rs`). Interpolation has one pole per offset whatever it is given.
///
/// # Errors
/// As [`held_out_error`].
pub fn held_out_for_config(
    offsets: &Offsets,
    config: &FitConfig,
    options: &HeldOutOptions,
) -> Result<HeldOutError, HullError> {
    unstopped(quiet(|control| held_out_for_config_with(offsets, config, options, control)))
}

/// [`held_out_for_config`] with progress and a stop flag, as [`held_out_error_with`]; a weight
/// optimisation inside a refit also stops on the flag.
///
/// # Errors
/// As [`held_out_error`].
pub fn held_out_for_config_with(
    offsets: &Offsets,
    config: &FitConfig,
    options: &HeldOutOptions,
    control: &Control<'_>,
) -> Result<Option<HeldOutError>, HullError> {
    let options = HeldOutOptions { degree: config.degree, ..*options };
    let ctrl = config.ctrl.unwrap_or_else(|| default_ctrl(offsets, config.degree));
    let full = data_extent(offsets);
    let inner = Control { stop: control.stop, progress: &|_| {} };
    // The refits keep the whole table's envelope (its principal dimensions), not the smaller
    // one of what they are given.
    let envelope = match (config.envelope, crate::Envelope::of_offsets(offsets)) {
        (crate::EnvelopeHold::Own, Some(e)) => crate::EnvelopeHold::Given(e.bounds()),
        (hold, _) => hold,
    };
    let config = &FitConfig { envelope, ..*config };
    let refit = |train: &Offsets| {
        let config = refit_config(train, config, ctrl, full);
        match fit_surface_with(train, &config, &inner) {
            // Knuckle points are shared between the pieces of a section, which narrows the
            // counts that work: take the nearest, as the pipeline does for its default.
            Err(HullError::Fit { reason: NurbsError::BadControlPointCount { count, min, max, .. }, .. })
                if config.ctrl.is_some_and(|(nu, _)| nu == count) && min <= max =>
            {
                let ctrl = config.ctrl.map(|(nu, nv)| (nu.clamp(min, max), nv));
                fit_surface_with(train, &FitConfig { ctrl, ..config }, &inner)
            }
            other => other,
        }
    };
    held_out_error_with(offsets, refit, &options, control)
}

/// The settings of a refit on `train`: those of the full fit, with its control points `ctrl`
/// scaled from the full data's extent `full` to the refit's (interpolation as is).
fn refit_config(train: &Offsets, config: &FitConfig, ctrl: (usize, usize), full: (usize, usize)) -> FitConfig {
    if config.method == FitMethod::Interp {
        return *config;
    }
    let (nu_max, nv_max) = data_extent(train);
    // ceil(count * kept / all), at least degree + 1 (the data carry that much: they were
    // checked for it) and at most the data.
    let scale = |count: usize, kept: usize, all: usize, degree: usize| {
        (count * kept).div_ceil(all.max(1)).max(degree + 1).min(kept.max(degree + 1)).min(count)
    };
    let nu = scale(ctrl.0, nu_max, full.0, config.degree.0);
    let nv = scale(ctrl.1, nv_max, full.1, config.degree.1);
    FitConfig { ctrl: Some((nu, nv)), ..*config }
}

/// The extent of a table: the points of its largest section (not counting pointed ends) and
/// its sections.
fn data_extent(offsets: &Offsets) -> (usize, usize) {
    let tol = crate::COINCIDENT_REL * offsets.size();
    let n_max = offsets.sections.iter().filter(|s| !s.is_point(tol)).map(|s| s.points.len()).max().unwrap_or(0);
    (n_max, offsets.sections.len())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fit_error::overfit;
    use crate::{fit_offsets, series60_sample};
    use nurbs::{assert_near, Vec3};

    /// `k` sections of `n` points each on the plane y = 1 + x / 10 (point `i` at z = i).
    fn planar(k: usize, n: usize) -> Offsets {
        let sections = (0..k)
            .map(|s| {
                let x = s as f64;
                let pts = (0..n).map(|i| Vec3::new(x, 1.0 + x / 10.0, i as f64)).collect();
                Section { lines: (0..n).map(|i| 100 * s + i).collect(), ..Section::new(format!("{s}"), pts) }
            })
            .collect();
        Offsets::new("test", crate::Units::Metre, sections)
    }

    #[test]
    fn options_are_validated() {
        assert!(HeldOutOptions::default().validate().is_ok());
        let e = HeldOutOptions::with_folds(1).validate().expect_err("one fold");
        assert!(e.to_string().contains("expected at least 2 folds"), "{e}");
        assert!(HeldOutOptions::with_folds(0).validate().is_err());
        let none = HeldOutOptions { sections: false, points: false, ..HeldOutOptions::default() };
        assert!(none.validate().expect_err("nothing").to_string().contains("expected sections, points"));
        // Bad options fail before any refit.
        let never = |_: &Offsets| -> Result<NurbsSurface, HullError> { unreachable!("no refit") };
        assert!(held_out_error(&planar(6, 6), never, &HeldOutOptions::with_folds(1)).is_err());
    }

    #[test]
    fn every_interior_offset_is_held_out_once_per_kind() {
        // 10 sections of 9 points, K = 4: the interior sections 1..=8 and, in every section,
        // the interior points 1..=7 are each held out by exactly one fold; the ends never.
        let offsets = planar(10, 9);
        let options = HeldOutOptions { degree: (3, 3), ..HeldOutOptions::default() };
        let all = splits(&offsets, &options);
        let (sec, pts): (Vec<&Split>, Vec<&Split>) = all.iter().partition(|s| s.kind == Kind::Sections);
        assert_eq!((sec.len(), pts.len()), (4, 4));
        let mut labels: Vec<String> =
            sec.iter().flat_map(|s| s.held.sections.iter().map(|h| h.label.clone())).collect();
        labels.sort_by_key(|l| l.parse::<usize>().unwrap_or(0));
        assert_eq!(labels, ["1", "2", "3", "4", "5", "6", "7", "8"]);
        for s in &sec {
            assert_eq!(s.train.sections.len() + s.held.sections.len(), 10);
            assert_eq!(
                (s.train.sections[0].label.as_str(), s.train.sections.last().map(|l| l.label.as_str())),
                ("0", Some("9"))
            );
        }
        let mut held_z: Vec<Vec<f64>> = vec![Vec::new(); 10];
        for s in &pts {
            assert_eq!(s.held.sections.len(), 10, "every section spares points");
            for (h, t) in s.held.sections.iter().zip(&s.train.sections) {
                let k: usize = h.label.parse().expect("number");
                held_z[k].extend(h.points.iter().map(|p| p.z));
                assert_eq!(h.points.len() + t.points.len(), 9);
                // The ends stay, and the source lines follow their points.
                assert_eq!((t.points[0].z, t.points.last().map(|p| p.z)), (0.0, Some(8.0)));
                assert!(t.points.iter().zip(&t.lines).all(|(p, &l)| l == 100 * k + p.z as usize));
            }
        }
        for z in &mut held_z {
            z.sort_by(f64::total_cmp);
            assert_eq!(z, &[1.0, 2.0, 3.0, 4.0, 5.0, 6.0, 7.0]);
        }
    }

    #[test]
    fn short_sections_keep_their_points_and_too_few_sections_are_not_split() {
        // 5 points with degree 3: holding out one (i = 1 for fold 1) leaves 4 = p + 1, fine;
        // 4 points: one less would leave 3 < p + 1, so they are kept.
        let mut offsets = planar(5, 5);
        offsets.sections[2].points.pop();
        let options = HeldOutOptions::default();
        let p = point_split(&offsets, &options, 1).expect("some section spares a point");
        assert_eq!(p.held.sections.len(), 4, "section 2 (4 points) keeps its own");
        assert!(p.held.sections.iter().all(|s| s.label != "2"));
        // 5 sections with degree 3 across: holding one out leaves 4 = q + 1; with 4, none.
        assert!(section_split(&offsets, &options, 1).is_some());
        assert!(section_split(&planar(4, 5), &options, 1).is_none());
        // Nothing at all to hold out: said, not a zero error.
        let never = |_: &Offsets| -> Result<NurbsSurface, HullError> { unreachable!("no refit") };
        let e = held_out_error(&planar(3, 4), never, &options).expect_err("too small");
        assert!(e.to_string().contains("can be held out: 3 sections of at most 4 points"), "{e}");
        // A pointed end section keeps its points.
        let mut pointed = planar(6, 6);
        let stem = pointed.sections[5].points[0];
        pointed.sections[5].points = vec![stem; 6];
        let p = point_split(&pointed, &options, 1).expect("splits");
        assert!(p.held.sections.iter().all(|s| s.label != "5"));
    }

    #[test]
    fn a_plane_is_predicted_exactly_and_the_counts_add_up() {
        // A plane is reproduced exactly by any skin of its points (affine invariance of
        // B-splines), so every held-out distance is round-off: 1e-12 of the 10 m model.
        let offsets = planar(9, 8);
        let config = FitConfig { method: FitMethod::Interp, ..FitConfig::default() };
        let h = held_out_for_config(&offsets, &config, &HeldOutOptions::default()).expect("cross-validates");
        assert!(h.max < 1e-11, "{h:?}");
        assert_eq!((h.folds, h.refits), (4, 8));
        // Sections 1..=7 of 8 points, and in each of the 9 sections the points 1..=6.
        assert_eq!((h.sections.points, h.points.points), (7 * 8, 9 * 6));
        assert!(h.rms <= h.max && h.seconds >= 0.0);
    }

    #[test]
    fn the_generic_core_takes_any_fitter_and_reports_its_errors() {
        let offsets = series60_sample();
        let fit = |o: &Offsets| fit_offsets(o, &FitConfig::default()).map(|out| out.surface);
        let h = held_out_error(&offsets, fit, &HeldOutOptions::default()).expect("cross-validates");
        // The same splits through the convenience; its counts are the full fit's scaled to
        // each reduced table, the closure re-picks the default of each (three quarters of it):
        // nearly the same counts, an error of the same order.
        let c = held_out_for_config(&offsets, &FitConfig::default(), &HeldOutOptions::default()).expect("ok");
        assert_eq!((h.refits, h.sections.points, h.points.points), (c.refits, c.sections.points, c.points.points));
        assert!(h.rms > 0.0 && c.rms > 0.0 && c.rms < 2.0 * h.rms && h.rms < 2.0 * c.rms, "{h:?} {c:?}");
        // All four combine into the overall figure: RMS^2 is the point-weighted mean of the
        // parts' RMS^2 (round-off of two summation orders: 1e-12 relative).
        let n = (c.sections.points + c.points.points) as f64;
        let combined =
            ((c.sections.rms.powi(2) * c.sections.points as f64 + c.points.rms.powi(2) * c.points.points as f64) / n)
                .sqrt();
        assert_near!(c.rms, combined, 1e-12 * c.rms);
        assert_eq!(c.max, c.sections.max.max(c.points.max));
        // A failing refit is the error.
        let failing = |_: &Offsets| -> Result<NurbsSurface, HullError> { Err(HullError::NoSurface) };
        let e = held_out_error(&offsets, failing, &HeldOutOptions::default()).expect_err("fails");
        assert!(matches!(e, HullError::NoSurface), "{e}");
    }

    #[test]
    fn refits_keep_the_density_of_control_points() {
        // 25 sections of 8 points: 6 x 19 control points. Holding out 6 sections leaves 19:
        // ceil(19 * 19 / 25) = 15 across; 2 points of 8 leave 6: ceil(6 * 6 / 8) = 5, and never
        // fewer than degree + 1 = 4, nor more than the data.
        let full = series60_sample();
        let config = FitConfig::default();
        let mut train = full.clone();
        train.sections.drain(1..7);
        let c = refit_config(&train, &config, (6, 19), data_extent(&full));
        assert_eq!(c.ctrl, Some((6, 15)));
        for s in &mut train.sections {
            s.points.drain(1..3);
        }
        assert_eq!(refit_config(&train, &config, (6, 19), data_extent(&full)).ctrl, Some((5, 15)));
        assert_eq!(refit_config(&train, &config, (4, 4), data_extent(&full)).ctrl, Some((4, 4)));
        let interp = FitConfig { method: FitMethod::Interp, ..config };
        assert_eq!(refit_config(&train, &interp, (6, 19), data_extent(&full)).ctrl, None);
    }

    #[test]
    fn a_raised_stop_starts_no_refit() {
        let stop = std::sync::atomic::AtomicBool::new(true);
        let control = Control { stop: &stop, progress: &|_| {} };
        let never = |_: &Offsets| -> Result<NurbsSurface, HullError> { unreachable!("stopped") };
        let r = held_out_error_with(&planar(6, 6), never, &HeldOutOptions::default(), &control);
        assert!(matches!(r, Ok(None)), "{r:?}");
    }

    /// A point held out among others of its section is named by its index in the whole
    /// section, not in the part held out, with its own input line.
    #[test]
    fn the_worst_held_out_offset_is_named_by_its_place_in_the_whole_table() {
        let offsets = series60_sample();
        let surface = fit_offsets(&offsets, &FitConfig::default()).expect("fits").surface;
        let k = offsets.sections.len() / 2;
        // Every other point of one section from the third on, as a point fold holds them out.
        let part = section_where(&offsets.sections[k], |i| i >= 2 && i.is_multiple_of(2));
        let held = Offsets::new("part", offsets.units, vec![part]);
        let feet = project_offsets(&surface, &held, None);
        let w = worst_held(&offsets, &held, &feet).expect("a worst offset");
        let whole = &offsets.sections[k];
        assert!(w.index >= 2 && w.index.is_multiple_of(2), "{w:?}");
        assert_eq!((w.section.as_str(), w.point), (whole.label.as_str(), whole.points[w.index].to_array()));
        assert_eq!(w.line, whole.lines.get(w.index).copied());
        let most = feet.iter().map(|p| p.distance).fold(0.0, f64::max);
        assert_eq!(w.distance, most);
    }

    #[test]
    fn overfitting_is_lower_at_the_offsets_and_higher_between() {
        assert!(overfit(0.0, 2.0, 1.0, 1.5));
        assert!(!overfit(0.0, 1.0, 1.0, 1.5), "better everywhere");
        assert!(!overfit(1.0, 2.0, 1.0, 1.5), "not lower at the offsets");
        let h = |rms| HeldOutError {
            rms,
            max: rms,
            sections: ErrorStats::default(),
            points: ErrorStats::default(),
            folds: 4,
            refits: 8,
            seconds: 0.0,
            worst: None,
        };
        assert!(h(2.0).overfits(0.5, 1.0, &h(1.0)));
        assert!(!h(0.9).overfits(0.5, 1.0, &h(1.0)));
    }
}
