//! The built-in sample hull: the Series 60 block-coefficient 0.60 parent.
//!
//! Todd, F.H., "Series 60 - Methodical Experiments with Models of Single-Screw Merchant
//! Ships", David Taylor Model Basin Report 1712, 1963 (public domain). The dimensionless
//! table is scaled to Lpp = 121.92 m, B = 16.26 m, T = 6.50 m (L/B = 7.5, B/T = 2.5):
//!
//! - x = (1 - station/20) Lpp, from the aft perpendicular, forward positive;
//! - z = (z/T) T;
//! - y = cell x MaxBm(waterline) x B/2.
//!
//! 25 stations (0..20 with half stations 0.5, 1.5, 18.5, 19.5), AP first, by 8 waterlines
//! (baseline to 1.5 T), every cell present. The source's typo at the FP, WL 0.25 T (`10`) is
//! set to 0. See `testdata/README.md` and `testdata/gen_series60.py`.

use nurbs::{KnotVector, NurbsSurface, Vec3};

use crate::offsets::{Offsets, Perpendiculars};
use crate::read::parse_offset_table;
use crate::units::Units;

/// The sample's offset table, as committed in `testdata/`.
pub const SERIES60_CB060_CSV: &str = include_str!("../../../testdata/series60_cb060_offsets.csv");

/// The `source` of [`series60_sample`].
pub const SERIES60_SOURCE: &str = "built-in sample: Series 60 Cb 0.60 parent (Todd 1963)";

/// Principal particulars of a hull, for reports and checks. Lengths in `units`.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Particulars {
    /// Length between perpendiculars.
    pub lpp: f64,
    /// Moulded breadth B (twice the largest half-breadth).
    pub beam: f64,
    /// Design draft T (the 1.0 WL).
    pub draft: f64,
    /// Block coefficient V / (Lpp B T) at the design draft, nominal.
    pub cb: f64,
    /// Prismatic coefficient, nominal.
    pub cp: f64,
    /// Longitudinal centre of buoyancy, percent of Lpp from midship, forward positive, nominal.
    pub lcb_percent: f64,
    /// The length unit.
    pub units: Units,
}

/// The Series 60 Cb 0.60 parent as scaled here. Cb, Cp and LCB are Todd's nominal values;
/// integrating the offset table itself (PCHIP in z and x, see `series60/PROVENANCE.md`)
/// gives Cb 0.5972, Cp 0.6138, LCB -1.48 %.
pub const SAMPLE_PARTICULARS: Particulars =
    Particulars { lpp: 121.92, beam: 16.26, draft: 6.50, cb: 0.60, cp: 0.614, lcb_percent: -1.5, units: Units::Metre };

/// The built-in sample as [`Offsets`]: 25 stations of 8 points each, in metres, x from the AP.
pub fn series60_sample() -> Offsets {
    let mut offsets = parse_offset_table(SERIES60_CB060_CSV, SERIES60_SOURCE, Units::Metre)
        .expect("the committed sample table parses (tested in sample::tests)");
    // The table's x runs from the AP to the FP, Lpp apart.
    offsets.perpendiculars = Perpendiculars::try_new(0.0, SAMPLE_PARTICULARS.lpp).ok();
    offsets
}

/// The Wigley hull of length `l`, beam `b` and draft `t` as an exact surface:
/// `y = (b/2) (1 - (2 xi / l)^2) (1 - ((t - z) / t)^2)`, `xi = x - l/2`, `x` from 0 (aft) to
/// `l`, `z` up from the keel to `t`. `y` is quadratic in `x` and in `z`, so the degree (2, 2)
/// Bézier patch with `z = t u` and `x = l v` reproduces it exactly (u runs keel to deck, v aft
/// to fore, as a hullskin fit). Bernstein coefficients: `4 v (1 - v) = 2 B_1(v)` -> `[0, 2, 0]`;
/// `2u - u^2` -> `[0, 1, 1]`. Its closed forms (block coefficient 4/9, centre of buoyancy
/// `5t/8` above the keel at draft `t`) make it the test hull of the hydrostatics and analysis.
///
/// ```
/// let s = hull::wigley_hull(100.0, 10.0, 6.25);
/// // Midship at the design waterline: the half beam.
/// let p = s.point(1.0, 0.5);
/// assert!((p.x - 50.0).abs() < 1e-12 && (p.y - 5.0).abs() < 1e-12 && (p.z - 6.25).abs() < 1e-12);
/// ```
#[must_use]
pub fn wigley_hull(l: f64, b: f64, t: f64) -> NurbsSurface {
    // Bézier knots and a 3 x 3 net: valid whatever the (finite) dimensions.
    let k = || KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("Bezier knots");
    let (fv, gu) = ([0.0, 2.0, 0.0], [0.0, 1.0, 1.0]);
    let mut pts = Vec::new();
    for (i, g) in gu.iter().enumerate() {
        for (j, f) in fv.iter().enumerate() {
            pts.push(Vec3::new(l * j as f64 / 2.0, 0.5 * b * f * g, t * i as f64 / 2.0));
        }
    }
    NurbsSurface::try_new(k(), k(), &pts, None).expect("a 3 x 3 net on Bezier knots")
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::Vec3;

    #[test]
    fn sample_has_25_stations_of_8_points_and_validates() {
        let o = series60_sample();
        assert_eq!(o.source, SERIES60_SOURCE);
        assert_eq!(o.units, Units::Metre);
        assert_eq!(o.sections.len(), 25);
        assert!(o.sections.iter().all(|s| s.points.len() == 8));
        assert!(o.validate(4).is_ok());
    }

    #[test]
    fn sample_spans_lpp_and_one_and_a_half_drafts() {
        let p = SAMPLE_PARTICULARS;
        let (lo, hi) = series60_sample().bounds().expect("points");
        // Each bound is a single decimal product, read back by Rust's correctly rounded
        // parser; allow 1e-12 m of rounding.
        assert!((lo - Vec3::new(0.0, 0.0, 0.0)).norm() <= 1e-12);
        assert!((hi - Vec3::new(p.lpp, p.beam / 2.0, 1.5 * p.draft)).norm() <= 1e-12, "{hi:?}");
    }

    #[test]
    fn widest_point_is_half_the_beam_at_midship() {
        let p = SAMPLE_PARTICULARS;
        let o = series60_sample();
        let mid = o.sections.iter().find(|s| (s.points[0].x - p.lpp / 2.0).abs() < 1e-9).expect("station 10");
        let max_mid = mid.points.iter().map(|q| q.y).fold(f64::MIN, f64::max);
        // 1 x 1 x 16.26/2 written as "8.13": only the parse rounding (1e-15) remains.
        assert!((max_mid - p.beam / 2.0).abs() <= 1e-9, "{max_mid}");
        let max_all = o.sections.iter().flat_map(|s| &s.points).map(|q| q.y).fold(f64::MIN, f64::max);
        assert!((max_all - max_mid).abs() <= 1e-12, "no station is wider than midship");
    }

    #[test]
    fn the_known_typo_at_the_forward_perpendicular_is_fixed() {
        // FP = station 0 = x = Lpp: zero half-breadth on every waterline up to the 1.0 WL
        // (the stem line); the raw source has 10 at WL 0.25 T.
        let o = series60_sample();
        let fp = o.sections.last().expect("sections");
        assert!((fp.points[0].x - SAMPLE_PARTICULARS.lpp).abs() <= 1e-12);
        for q in fp.points.iter().filter(|q| q.z <= SAMPLE_PARTICULARS.draft) {
            assert_eq!(q.y, 0.0, "FP at z = {}", q.z);
        }
    }

    #[test]
    fn stations_run_aft_to_fore_and_waterlines_keel_to_deck() {
        let o = series60_sample();
        assert!(o.sections.windows(2).all(|w| w[1].points[0].x > w[0].points[0].x));
        assert!(o.sections.iter().all(|s| s.points.windows(2).all(|w| w[1].z > w[0].z)));
        assert!(o.sections.iter().all(|s| s.points.iter().all(|q| q.x == s.points[0].x)));
    }

    /// Trapezoid rule over the abscissae `t`.
    fn trapezoid(t: &[f64], f: &[f64]) -> f64 {
        t.windows(2).zip(f.windows(2)).map(|(t, f)| (t[1] - t[0]) * (f[0] + f[1]) / 2.0).sum()
    }

    #[test]
    fn displacement_matches_the_published_block_coefficient() {
        // Integrating the sample to the design draft checks its scaling as a whole (a wrong
        // B/2 or T factor would be off by 2x). The trapezoid rule on 6 waterlines and 25
        // stations cuts the convex sections' corners: it gives Cb 0.5934 where PCHIP gives
        // 0.5972 (PROVENANCE.md) and Todd 0.60; 0.01 covers that quadrature error.
        let p = SAMPLE_PARTICULARS;
        let o = series60_sample();
        let xs: Vec<f64> = o.sections.iter().map(|s| s.points[0].x).collect();
        let areas: Vec<f64> = o
            .sections
            .iter()
            .map(|s| {
                let below: Vec<&Vec3> = s.points.iter().filter(|q| q.z <= p.draft + 1e-9).collect();
                let z: Vec<f64> = below.iter().map(|q| q.z).collect();
                let y: Vec<f64> = below.iter().map(|q| q.y).collect();
                2.0 * trapezoid(&z, &y)
            })
            .collect();
        let volume = trapezoid(&xs, &areas);
        let cb = volume / (p.lpp * p.beam * p.draft);
        assert!((cb - p.cb).abs() <= 0.01, "Cb = {cb}");
        // LCB: the same quadrature gives -1.56 % against Todd's -1.5 %.
        let moment: Vec<f64> = areas.iter().zip(&xs).map(|(a, x)| a * x).collect();
        let lcb = (trapezoid(&xs, &moment) / volume - p.lpp / 2.0) / p.lpp * 100.0;
        assert!((lcb - p.lcb_percent).abs() <= 0.2, "LCB = {lcb} %");
    }
}
