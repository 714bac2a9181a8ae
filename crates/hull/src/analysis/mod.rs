//! Shape analysis of a surface: planar cuts (stations, waterlines, buttocks), curvature maps
//! and fairness measures.
//!
//! - [`cuts`]: the intersection of a surface with an axis-aligned plane, as ordered polylines
//!   whose points lie on the plane and carry the cut curve's curvature;
//! - [`curvature_map`](mod@curvature_map): Gaussian, mean and principal curvatures on a parameter grid, with
//!   statistics for colour scales and reports;
//! - [`fairness`]: bending energy and the inflections of stations and waterlines;
//! - [`fold`]: where a skinned surface runs backwards across its sections;
//! - [`validity`]: every defect that makes a surface invalid (folds, leaving the offsets'
//!   envelope, bulging through a flat, inward-facing facets).
//!
//! Axes as everywhere in hullskin: x forward, y to starboard, z up.

mod curvature_map;
mod cuts;
mod fairness;
mod fold;
mod validity;

pub use curvature_map::{
    curvature_map, point_bounds, CurvatureField, CurvatureMap, CurvatureMapOptions, CurvatureSample, CurvatureSummary,
    Degeneracy, Extreme, FieldStats, GridLines,
};
pub use cuts::{cut_surface, cut_surface_many, CutCurve, CutOptions, CutPlane, CutPoint};
pub use fairness::{
    bending_energy, default_quadrature, fairness_report, gauss_legendre, BendingEnergy, CutFairness, FairnessOptions,
    FairnessReport, PlaneFairness, PlaneSelection,
};
pub use fold::{find_folds, Fold};
pub(crate) use validity::fit_validity_and_folds;
pub use validity::{
    check_fit_validity, check_validity, Envelope, Finding, FindingKind, Flat, Place, ENVELOPE_REL, FOLD_RUN_REL,
};

use nurbs::{KnotVector, NurbsSurface};

/// Parameter values for a sampling grid along one direction: `intervals` uniform intervals of
/// the domain (at least 1), joined, when `refine_at_knots`, with every distinct interior knot
/// and with points that split each non-empty knot span into at least `per_span` intervals.
/// Sorted, without duplicates, the domain ends included.
pub(crate) fn param_grid(knots: &KnotVector, intervals: usize, refine_at_knots: bool, per_span: usize) -> Vec<f64> {
    let (a, b) = knots.domain();
    let n = intervals.max(1);
    let mut t: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
    if refine_at_knots {
        let k = knots.as_slice();
        let p = knots.degree();
        let mut breaks: Vec<f64> = k[p..k.len() - p].to_vec();
        breaks.dedup();
        for w in breaks.windows(2) {
            let (k0, k1) = (w[0], w[1]);
            let m = per_span.max(1);
            t.extend((0..=m).map(|j| k0 + (k1 - k0) * j as f64 / m as f64));
        }
    }
    t.sort_by(f64::total_cmp);
    // Values closer than round-off of the domain are one grid line.
    let eps = 1e-12 * (b - a).abs();
    t.dedup_by(|x, y| (*x - *y).abs() <= eps);
    t
}

/// Parameter values with a line at every distinct knot and each knot span split in proportion
/// to its length into at least 2 equal parts, about `target` lines in all (the grid of the
/// curvature picture, `view::curvature_map`).
pub(crate) fn span_grid(knots: &KnotVector, target: usize) -> Vec<f64> {
    let (a, b) = knots.domain();
    let mut breaks = vec![a];
    breaks.extend(knots.interior_breaks().into_iter().map(|(k, _)| k).filter(|&k| k > a && k < b));
    breaks.push(b);
    let mut t = Vec::new();
    for w in breaks.windows(2) {
        let n = ((target as f64 * (w[1] - w[0]) / (b - a)).round() as usize).max(2);
        t.extend((0..n).map(|j| w[0] + (w[1] - w[0]) * j as f64 / n as f64));
    }
    t.push(b);
    t
}

/// The diagonal of the control net's bounding box: the model size that relative tolerances
/// refer to. `None` for an empty or non-finite box.
pub(crate) fn model_size(surface: &NurbsSurface) -> Option<f64> {
    let (lo, hi) = surface.control_bounds();
    let size = (hi - lo).norm();
    (size.is_finite() && size > 0.0).then_some(size)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn param_grid_contains_uniform_points_knots_and_splits_spans() {
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.1, 0.7, 1., 1., 1., 1.]).expect("valid");
        let t = param_grid(&kv, 4, true, 2);
        // Uniform 0, .25, .5, .75, 1; knots .1, .7; span midpoints .05, .4, .85.
        let want = [0.0, 0.05, 0.1, 0.25, 0.4, 0.5, 0.7, 0.75, 0.85, 1.0];
        assert_eq!(t.len(), want.len(), "{t:?}");
        for (a, b) in t.iter().zip(want) {
            // Affine combinations of the knots: exact to a few ulps.
            assert!((a - b).abs() <= 1e-15, "{t:?}");
        }
        let plain = param_grid(&kv, 4, false, 2);
        assert_eq!(plain, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
    }

    #[test]
    fn span_grid_has_a_line_at_every_knot_and_splits_spans_by_length() {
        // Spans [0, 0.1], [0.1, 0.5], [0.5, 1]: 20 lines split 2 (the minimum), 8 and 10.
        let k = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.5, 1.0, 1.0, 1.0, 1.0]).expect("valid knots");
        let t = span_grid(&k, 20);
        for knot in [0.0, 0.1, 0.5, 1.0] {
            assert!(t.contains(&knot), "knot {knot} missing");
        }
        assert_eq!(t.len(), 2 + 8 + 10 + 1);
        assert!(t.windows(2).all(|w| w[1] > w[0]));
    }
}
