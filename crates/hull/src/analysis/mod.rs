//! Shape analysis of a surface: planar cuts (stations, waterlines, buttocks), curvature maps
//! and fairness measures.
//!
//! - [`cuts`]: the planes of the lines plan (stations, waterlines, buttocks) as the kernel's
//!   axis planes, whose cuts ([`cut_surface`]) are ordered polylines on the plane carrying the
//!   cut curve's curvature;
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
pub use cuts::CutPlane;
// The kernel's planar cuts, taking a `CutPlane` as it is.
pub(crate) use fairness::plane_fairness;
pub use fairness::{
    bending_energy, default_quadrature, fairness_report, gauss_legendre, BendingEnergy, CutFairness, FairnessOptions,
    FairnessReport, PlaneFairness, PlaneSelection,
};
pub use fold::{find_folds, Fold};
pub use nurbs::{cut_surface, cut_surface_many, CutCurve, CutOptions, CutPoint};
pub use validity::{
    check_fit_validity, check_validity, Envelope, Finding, FindingKind, Flat, Place, ENVELOPE_REL, FOLD_RUN_REL,
};
pub(crate) use validity::{face_findings, fit_face_check, fit_validity_and_folds};

use nurbs::KnotVector;

/// Parameter values with a line at every distinct knot and each knot span split in proportion
/// to its length into at least 2 equal parts, about `target` lines in all (the grid of the
/// curvature picture, `view::curvature_map`).
pub(crate) fn span_grid(knots: &KnotVector, target: usize) -> Vec<f64> {
    let (a, b) = knots.domain();
    let breaks = knots.span_breaks();
    let counts: Vec<usize> =
        breaks.windows(2).map(|w| ((target as f64 * (w[1] - w[0]) / (b - a)).round() as usize).max(2)).collect();
    nurbs::split_spans(&breaks, &counts)
}

#[cfg(test)]
mod tests {
    use super::*;

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
