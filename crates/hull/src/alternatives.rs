//! The default fit made again for validity: when the faired approximation on the default
//! parameterization ([`SkinParameterization::default`]) and the default control-point counts,
//! its control net held within the offsets' envelope, still folds or faces inwards, the same
//! fit is made with its SURFACE held within the envelope instead ([`HoldOn::Surface`]), then
//! the two cures its warning names (another `--param`, another count across), each fitted and
//! faired the same way, and the first sound one within
//! [`UNSOUND_SLACK`](crate::UNSOUND_SLACK) of the tolerance replaces it.
//!
//! Why: where the sections change shape abruptly, the least squares across them rings, and
//! where the ringing folds the net or turns it over depends on the knots, so on the count and
//! the parameters; no smoothing removes it. R/V Gunnerus's forecastle step (the deck jumps
//! 3.5 m between the stations at x = 16.24 and 16.82 m) keeps 0.085 m² of inward-facing facets
//! at 47 control points across at every smoothing, none on universal parameters along the
//! sections (nor at 48 across, but far less fair there). Holding the net within the envelope's
//! faces flattens poles a convex section needs past them; holding the surface's points lets
//! them go there, and on Gunnerus that fit is sound, closer to the offsets and fairer than
//! either ([`sounder_alternative`]). The DTMB 5415 mesh's net rings across the crease of its
//! raked transom's lower edge, hooking 0.59 m behind the first station at the default 31
//! control points across, at none of 30 or 32, with either hold (README, Known defects). On a
//! table of three sections, which the net interpolates across, only the parameters and the
//! hold can change.
//!
//! And made again for fairness: when that fit is sound but, its net held, less fair than the
//! plain least squares before the hold (issue 11's fairness floor: thin-plate energy, largest
//! |K|, inflections), it is made with its surface held instead, and used when that one is
//! sound, within the tolerance and no less fair. The net hold flattens poles as above, and
//! can bend the net where the plain fit was smooth: the Series 60 Cb 0.80 parent's largest |K|
//! rises from 2.42 to 3.09 1/m² by the net hold alone, and is 2.33 held on the surface. Where
//! that one is not used either, the fit is made on [`FAIRNESS_PARAMETERIZATIONS`], its net held,
//! faired against the default parameters' plain least squares (the trawler's).

use nurbs::fit::{Parameterization, SkinParameterization};

use crate::analysis::FindingKind;
use crate::fairing::UNSOUND_SLACK;
use crate::fit::{AlternativeReason, AlternativeTry, Alternatives, FairReport, FairnessFigures};
use crate::{Fairing, FitConfig, FitMethod, FitOutcome, HoldOn, HullError};

/// The parameterizations tried after the surface hold, in order, at the default counts:
/// universal along the sections (uniform knots, the parameters at the basis functions' maxima),
/// then chord length along, both with chord length across, then centripetal in both
/// directions. Measured on R/V Gunnerus's default fit (12x47, its net held within the envelope): no
/// finding with the first two (max error 183.8 and 231.9 mm, held-out max 652.6 and 669.2 mm,
/// against 181.3 and 665.4 mm with 0.085 m² facing inwards), 0.93 m² facing inwards with the
/// third; on random hull-like tables (1,500 of the property test's, seeds 1 to 4 and 11) the
/// default parameters left 4 unsound, the first removed 2 of them and the third another, a
/// zero-width end's fold (the fourth goes at another count, [`ALTERNATIVE_COUNTS_ACROSS`]). Not
/// tried, for they were no better on Gunnerus: centripetal along
/// with uniform or universal across (1.7 and 1.8 m² facing inwards), uniform along (0.11 m²).
pub const ALTERNATIVE_PARAMETERIZATIONS: [SkinParameterization; 3] = [
    SkinParameterization { u: Parameterization::Universal, v: Parameterization::ChordLength },
    SkinParameterization { u: Parameterization::ChordLength, v: Parameterization::ChordLength },
    SkinParameterization { u: Parameterization::Centripetal, v: Parameterization::Centripetal },
];

/// The control-point counts across the sections tried after [`ALTERNATIVE_PARAMETERIZATIONS`],
/// on the default parameterization: one fewer, then one more than the default count, then two
/// and three fewer (within the kernel's range; fewer first, for the default fit's fewest control
/// points, and fewer across is the cure the fold's warning names). Measured: the DTMB 5415 mesh,
/// which no parameterization makes sound, is sound at 23x30 (max error 691.6 mm against 693.3,
/// and fairer: thin-plate energy 3050 against 54974). The FastShip container ship
/// (`testdata/mesh/fastship_cont.wrl.gz`, its stem rising 12.6 m between the stations at x =
/// 141.4 and 143.0 m) folds at the default 23x30 and at 23x29 and 23x31, with any hold,
/// parameterization or smoothing, and is sound at 23x28 (max error 1.049 m), 23x27 and 23x26
/// (0.907 and 0.805 m). Not first, because a count can be sound and far less fair than a
/// parameterization: R/V Gunnerus at 12x48 is sound and closer to the offsets (max error 145.7
/// mm, held-out max 483.5 mm) but its thin-plate energy is 23055 and its largest |K| 2748 1/m²,
/// against 294 and 16.6 on universal parameters at 12x47 (and 17206 and 101 for the plain least
/// squares at 12x48).
pub const ALTERNATIVE_COUNTS_ACROSS: [isize; 4] = [-1, 1, -2, -3];

/// The parameterizations tried for fairness after the surface hold, with the net hold, at the
/// default counts: universal along the sections, chord length across. Measured on the trawler,
/// whose net-held default fit is less fair than its plain least squares (thin-plate energy 346
/// against 168, 91 inflections against 87) and whose surface hold misses the tolerance (59.6
/// mm against 39.19): its least squares is sound at 39.0 mm and, smoothed at `ν` between 4e-3
/// and 7e-3, no less fair by every figure (energy 124.6 to 128.2, largest |K| 441 to 518
/// 1/m², 85 to 87 inflections) and closer between the offsets (held-out max 170 to 174 mm
/// against the plain least squares' 221.7). Not tried: chord length along (energy 690 held, so
/// far from it that no smoothing within the tolerance could be expected to bring it back), nor
/// centripetal in both directions (held-out max 392 mm).
pub const FAIRNESS_PARAMETERIZATIONS: [SkinParameterization; 1] =
    [SkinParameterization { u: Parameterization::Universal, v: Parameterization::ChordLength }];

/// How far past the tolerance the least squares of an alternative for fairness may be and still
/// be faired: 10 %. Smoothing can bring a fit a little closer to the offsets than its least
/// squares (the Series 60 Cb 0.80 held on its surface: 95.7 mm plain, 93.5 mm at `ν` = 1e-3,
/// within `--tolerance default`'s 93.8 mm), not much (the trawler's held on its surface, 52 %
/// past its tolerance, is not faired: a second search for nothing).
pub const SCREEN_SLACK: f64 = 1.1;

/// Folds and inward-facing facets: what the envelope hold cannot remove.
fn unsound(out: &FitOutcome) -> bool {
    out.validity.iter().any(|f| matches!(f.kind, FindingKind::Fold | FindingKind::InwardFacing))
}

/// `chosen`, the faired approximation of `config` (`--fair auto`, the default
/// parameterization and counts, the net hold), or, when it folds or faces inwards, the first
/// that is sound (no validity finding at all) within [`UNSOUND_SLACK`] times the fairing's
/// tolerance of: the same fit held on its surface ([`HoldOn::Surface`]), the fits of
/// [`ALTERNATIVE_PARAMETERIZATIONS`] at the default counts, then of
/// [`ALTERNATIVE_COUNTS_ACROSS`] on the default parameterization, these two with the net hold
/// (`refit(config)`: the same fit, faired the same way, with those settings). With none,
/// `chosen` stays: a fit with fewer findings but not none was not worth it where measured (the
/// DTMB 5415 mesh's fold would give way to 1.6 m² of inward-facing facets at 1.5 times the max
/// error). When `chosen` is sound but less fair than the plain least squares for its net hold
/// ([`AlternativeReason::Fairness`]), the surface hold is tried: its least squares first, and
/// where that is sound and closer than the tolerance, the fit faired on it, used when sound,
/// within the tolerance and no less fair by every figure; then [`FAIRNESS_PARAMETERIZATIONS`]
/// with the net hold, each faired to be no less fair than the plain least squares `chosen` is
/// judged against (`refit`'s second argument: that one's figures), its search from the least
/// smoothing up ([`crate::fairing::fair`]), used on the same terms. The outcome's fairing report records
/// the choice ([`Alternatives`]) and its time includes every fit tried. Any other setting (a
/// parameterization, counts or hold asked for, a given `λ`, interpolation) returns `chosen` as
/// it is.
///
/// The surface hold first, measured (release, `hullskin fit`, default cross-validation): R/V
/// Gunnerus is sound with it at max error 112.6 mm, held-out max 560.6 mm, thin-plate energy
/// 132 and largest |K| 3.15 1/m², against 183.8 mm, 652.6 mm, 294 and 16.6 1/m² on universal
/// parameters (the net hold's 0.085 m² facing inwards at 181.3 mm, 665.4 mm); one faired fit
/// either way. On the DTMB 5415 mesh it keeps the fold (max 693.3 mm), so the four fits tried
/// before 23x30 are five now, the same surface at the end (3.40 -> 4.52 s wall, best of 3,
/// loaded machine). Of random hull-like tables the default left 8 of 3,300 unsound (property test
/// strategy, 11 seeds), 7 of them sound held on the surface and the eighth at one count more
/// across; of 800 of three or four sections with a pointed end 11, all sound held on the
/// surface, where the parameterizations and counts alone left 2.
pub(crate) fn sounder_alternative(
    chosen: FitOutcome,
    config: &FitConfig,
    refit: impl Fn(&FitConfig, Option<FairnessFigures>) -> Result<FitOutcome, HullError>,
) -> FitOutcome {
    let auto = matches!(config.fair, Fairing::Auto { .. });
    let default =
        config.param == SkinParameterization::default() && config.ctrl.is_none() && config.hold_on == HoldOn::Net;
    if !auto || config.method != FitMethod::Approx || !default {
        return chosen;
    }
    let Some(fairing) = chosen.fairing.clone() else { return chosen };
    let Some(tolerance) = fairing.tolerance else { return chosen };
    let reason = if unsound(&chosen) {
        AlternativeReason::Validity
    } else if less_fair_held(&chosen, &fairing) {
        AlternativeReason::Fairness
    } else {
        return chosen;
    };
    let limit = match reason {
        AlternativeReason::Validity => UNSOUND_SLACK * tolerance,
        AlternativeReason::Fairness => tolerance,
    };
    let (nu, nv) = (chosen.surface.n_u(), chosen.surface.n_v());
    let surface = std::iter::once(FitConfig { hold_on: HoldOn::Surface, ..*config });
    let params = ALTERNATIVE_PARAMETERIZATIONS.iter().map(|&param| FitConfig { param, ..*config });
    let counts = ALTERNATIVE_COUNTS_ACROSS
        .iter()
        .filter_map(|&d| nv.checked_add_signed(d))
        .map(|n| FitConfig { ctrl: Some((nu, n)), ..*config });
    let alternatives: Vec<FitConfig> = match reason {
        AlternativeReason::Validity => surface.chain(params).chain(counts).collect(),
        // Faired within the same tolerance as `chosen`, not within its own least squares' max
        // error: the fairest surface within it is what is asked for (measured on the 4 x 3
        // example while its plain fit was on averaged parameters: held on its surface at
        // 114.9 mm; within 145.3 mm, `chosen`'s, `ν` = 1e-2 made it fairer than the plain least
        // squares by every figure at 125 mm).
        AlternativeReason::Fairness => surface
            .chain(FAIRNESS_PARAMETERIZATIONS.iter().map(|&param| FitConfig { param, ..*config }))
            .map(|c| FitConfig { fair: Fairing::Auto { tolerance: Some(limit) }, ..c })
            .collect(),
    };
    // An alternative for fairness on another parameterization is faired to be no less fair
    // than the plain least squares `chosen` is judged against (the floor's), not its own (the
    // surface hold's own is that one).
    let against =
        |c: &FitConfig| (reason == AlternativeReason::Fairness && c.param != config.param).then_some(fairing.before);
    let mut tried = Vec::new();
    let mut used: Option<(usize, FitOutcome)> = None;
    let mut seconds = chosen.fit_seconds + chosen.error_seconds;
    for alternative in alternatives {
        // For fairness, the surface hold's least squares first: where it is unsound, or misses
        // the tolerance by more than [`SCREEN_SLACK`], the search over the smoothing weights is
        // not made (the trawler's held on the surface: 59.6 mm against 39.2). Another
        // parameterization's search is its own screen: it begins at the least smoothing and
        // stops at the first fit past the tolerance or unsound there.
        let against = against(&alternative);
        let screen = match reason {
            AlternativeReason::Fairness if against.is_none() => Some(FitConfig { fair: Fairing::Off, ..alternative }),
            _ => None,
        };
        // The least squares where it is screened out (tried, not faired), else nothing.
        let screened_out = match screen {
            Some(screen) => {
                let Ok(plain) = refit(&screen, None) else { continue };
                if !plain.validity.is_empty() || plain.error.overall.max >= SCREEN_SLACK * limit {
                    Some(plain)
                } else {
                    seconds += plain.fit_seconds + plain.error_seconds;
                    None
                }
            }
            None => None,
        };
        let (out, passed) = match screened_out {
            Some(plain) => (plain, false),
            None => {
                let Ok(out) = refit(&alternative, against) else { continue };
                (out, true)
            }
        };
        seconds += out.fit_seconds + out.error_seconds;
        let (max, findings) = (out.error.overall.max, out.validity.len());
        let control_points = [out.surface.n_u(), out.surface.n_v()];
        let (param, hold) = (alternative.param.name(), alternative.hold_on);
        let mut accepted = passed && findings == 0 && max <= limit;
        let mut no_less_fair = None;
        if accepted && reason == AlternativeReason::Fairness {
            let fair = out.fairing.as_ref().is_some_and(|f| f.after.no_less_fair_than(&fairing.before));
            no_less_fair = Some(fair);
            accepted = fair;
        }
        tried.push(AlternativeTry { param, hold, control_points, max, findings, no_less_fair, accepted: false });
        if accepted {
            used = Some((tried.len() - 1, out));
            break;
        }
    }
    let mut choice = Alternatives {
        reason,
        requested: config.param.name(),
        control_points: [nu, nv],
        max: chosen.error.overall.max,
        findings: chosen.validity.len(),
        figures: (reason == AlternativeReason::Fairness).then_some(fairing.after),
        limit,
        tried,
    };
    let mut out = match used {
        Some((k, out)) => {
            choice.tried[k].accepted = true;
            out
        }
        None => chosen,
    };
    out.fit_seconds = seconds - out.error_seconds;
    if let Some(f) = out.fairing.as_mut() {
        f.alternatives = Some(choice);
    }
    out
}

/// Sound, but held within the envelope and less fair for it than the plain least squares
/// before the hold (the report's `before`) by some figure: thin-plate energy, curvature
/// extreme or inflections ([`crate::FairnessFigures::no_less_fair_than`]).
fn less_fair_held(chosen: &FitOutcome, fairing: &FairReport) -> bool {
    chosen.envelope_held > 0 && chosen.validity.is_empty() && !fairing.after.no_less_fair_than(&fairing.before)
}
