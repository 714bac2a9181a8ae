//! `--tolerance default` against the default fit of the default count: the search fits plain
//! least squares, held as the configuration asks; the default fit also holds its surface where
//! that is sounder or fairer, and fairs. Where that reaches the tolerance and the count found
//! does not, the default count is the answer.

use hull::{fit_offsets_within, quiet, read_offsets, Fairing, FitConfig, Goal, RefereeBasis, Units};

use crate::common::testdata;

#[test]
fn the_default_count_is_kept_where_its_default_fit_reaches_the_tolerance_and_the_count_found_does_not() {
    // Series 60 Cb 0.80: its plain fit at the default count 6x19, net held, misses 0.5 % of
    // the beam (93.8 mm) at 214.5 mm, and the quick search ends at interpolation's 8x25 count
    // at 152.4 mm; the default fit at 6x19 (its surface held, faired) is at 93.5 mm (measured).
    let o = read_offsets(&testdata("series60_cb080_offsets.csv"), Units::Metre).expect("reads");
    let t = hull::default_tolerance(&o).expect("a beam");
    let config = FitConfig { fair: Fairing::Auto { tolerance: None }, ..FitConfig::default() };
    let (out, search) = quiet(|c| fit_offsets_within(&o, &config, Goal::DefaultTolerance, c)).expect("fits");
    let search = search.expect("searched");
    let counts = [out.surface.n_u(), out.surface.n_v()];
    assert_eq!(counts, [6, 19]);
    assert!(out.validity.is_empty(), "{:?}", out.validity);
    assert!(out.error.overall.max <= t, "{} > {t}", out.error.overall.max);
    // The record says what was kept and why, and the count found is still named.
    assert_eq!((search.control_points, search.reached, search.valid), (counts, true, true));
    let r = search.referee.as_ref().expect("refereed");
    assert_eq!(r.basis, RefereeBasis::Accuracy);
    assert!(r.chose_default_count && r.default_count == counts && r.default_count_valid);
    assert_eq!(r.default_count_max, out.error.overall.max);
    // The search's own answer: more control points, not within the tolerance.
    assert!(r.searched[0] * r.searched[1] > 6 * 19 && r.searched_max > t, "{r:?}");
    assert!(!search.tried.iter().any(|c| c.within), "{:?}", search.tried);
    let line = search.summary(Units::Metre);
    let [a, b] = r.searched;
    assert!(line.contains(&format!("6x19 is kept, within the tolerance where {a}x{b} is not")), "{line}");
    // No held-out figure is carried by this referee (none was measured for it).
    assert!(r.searched_held_out_max.is_none() && r.default_count_held_out_max.is_none());
}
