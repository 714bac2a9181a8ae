//! Fitting: parameterization, knot vectors, interpolation, least squares, skinning.
//!
//! The pipeline for one curve is: data parameters ([`parameterize`], The NURBS Book 9.2.1),
//! a knot vector ([`optimal_knots`] of de Boor for interpolation, [`approximation_knots`] or
//! [`centred_approximation_knots`] for least squares, uniform with
//! [`Parameterization::Universal`]), then a banded solve
//! ([`InterpolationSolver`], A9.1, or [`LeastSquaresSolver`], 9.4.1) that is factored once and
//! reused for every right-hand side sharing parameters and knots. Surfaces are skinned from
//! sections ([`skin_interpolate`], [`skin_approximate`]; 9.2.5 and 10.3).

use crate::{KnotVector, NurbsCurve, NurbsError, Vec3};

mod banded;
mod constrained;
mod features;
mod interp;
mod knots;
mod lsq;
mod param;
mod skin;

pub use constrained::{energy_order, fair_interpolate_curve, row_schoenberg_whitney, FairInterpolationSolver};
pub use features::{
    find_knuckle_lines, join_knot_vectors, knot_multiplicity, knuckle_indices, section_corners, turning_angles,
    Continuity, CornerOptions, KnuckleLine, SectionCorner,
};
pub use interp::{interpolate_curve, interpolate_curve_auto, InterpolationSolver};
pub use knots::{
    approximation_knots, averaging_knots, centred_approximation_knots, knots_for_approximation,
    knots_for_interpolation, optimal_knots, schoenberg_whitney,
};
pub use lsq::{approximate_curve, approximate_curve_auto, LeastSquaresSolver};
pub use param::{common_parameters, parameterize, Parameterization, SkinParameterization, UnknownParameterization};
pub use skin::{
    skin_approximate, skin_approximate_with_knuckles, skin_interpolate, skin_interpolate_with_knuckles, SkinOptions,
    SkinResult,
};

/// The shared tail of every curve solver: check the points, solve for their coordinates and
/// return the control points.
pub(crate) fn solve_points(
    points: &[Vec3],
    solve: impl FnOnce(&[[f64; 3]]) -> Result<Vec<[f64; 3]>, NurbsError>,
) -> Result<Vec<Vec3>, NurbsError> {
    if let Some(index) = points.iter().position(|p| !p.is_finite()) {
        return Err(NurbsError::NonFinitePoint { index });
    }
    let b: Vec<[f64; 3]> = points.iter().map(|p| p.to_array()).collect();
    Ok(solve(&b)?.into_iter().map(Vec3::from_array).collect())
}

/// The non-rational curve with these knots and control points.
pub(crate) fn polynomial_curve(knots: &KnotVector, control_points: Vec<Vec3>) -> NurbsCurve {
    NurbsCurve::from_parts_unchecked(
        knots.clone(),
        control_points.into_iter().map(|p| crate::curve::to_homogeneous(p, 1.0)).collect(),
    )
}
