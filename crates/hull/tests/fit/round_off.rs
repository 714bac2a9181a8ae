//! A fit is decided by the offsets, not by the rounding: at the interpolation counts every
//! candidate of the skinning approximation passes through the offsets, their residuals are
//! round-off, and the one kept must not depend on it.

use hull::{fit_offsets, read_offsets, EnvelopeHold, Fairing, FitConfig, Offsets, Units};

use crate::common::testdata;

/// The offsets with every coordinate moved by `k` ulps, `k` in -4..=4 by a fixed pattern: a
/// change of the size the order of a sum makes.
fn nudged(o: &Offsets, seed: usize) -> Offsets {
    let mut out = o.clone();
    let mut k = seed;
    for s in &mut out.sections {
        for p in &mut s.points {
            let mut c = p.to_array();
            for v in &mut c {
                k = (k * 7 + 3) % 9;
                *v += (k as f64 - 4.0) * f64::EPSILON * v.abs();
            }
            *p = nurbs::Vec3::from_array(c);
        }
    }
    out
}

#[test]
fn the_plain_fit_at_the_interpolation_counts_does_not_follow_the_rounding() {
    // The Series 60 Cb 0.65 parent at 8x25 (one control point per offset each way): its two
    // candidates (each section on its own parameters, or all on their mean) left residuals of
    // 1.5e-25 and 1.8e-25 m², in either order by the order of summation of the band Cholesky
    // factor, and the net moved by 1.7 m between the offsets (measured).
    let o = read_offsets(&testdata("series60_cb065_offsets.csv"), Units::Metre).expect("reads");
    let config =
        FitConfig { ctrl: Some((8, 25)), fair: Fairing::Off, envelope: EnvelopeHold::Free, ..FitConfig::default() };
    let base = fit_offsets(&o, &config).expect("fits");
    // It interpolates (the round-off of banded solves on a 122 m hull: 1e-9 m).
    assert!(base.error.overall.max < 1e-9, "{}", base.error.overall.max);
    let net = base.surface.control_points();
    for seed in 0..4 {
        let again = fit_offsets(&nudged(&o, seed), &config).expect("fits");
        // The same net but for the nudge carried through the solves (4 ulps of 122 m is
        // 1e-13 m; a condition number of 1e6 makes that 1e-7 m).
        let moved = net.iter().zip(again.surface.control_points()).map(|(a, b)| a.distance(b)).fold(0.0, f64::max);
        assert!(moved < 1e-6, "seed {seed}: the net moved by {moved} m");
    }
}
