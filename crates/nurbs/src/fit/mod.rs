//! Fitting: parameterization, knot vectors, interpolation, least squares, skinning.
//!
//! The pipeline for one curve is: data parameters ([`parameterize`], The NURBS Book 9.2.1),
//! a knot vector ([`optimal_knots`] of de Boor for interpolation, [`approximation_knots`] or
//! [`centred_approximation_knots`] for least squares, uniform with
//! [`Parameterization::Universal`]), then a banded solve
//! ([`InterpolationSolver`], A9.1, or [`LeastSquaresSolver`], 9.4.1) that is factored once and
//! reused for every right-hand side sharing parameters and knots. Surfaces are skinned from
//! sections ([`skin_interpolate`], [`skin_approximate`]; 9.2.5 and 10.3).

use crate::{KnotVector, NurbsCurve, NurbsError, NurbsSurface, Vec3};

mod bounded;
mod constrained;
mod continuity;
mod corners;
mod extent;
mod held;
mod interp;
mod knots;
mod lsq;
mod param;
mod plane_runs;
mod skin;

pub use bounded::{bounded_refit, BoundedRefit, ControlBox, BOUNDED_REFIT_PULL};
pub use constrained::{energy_order, fair_interpolate_curve, row_schoenberg_whitney, FairInterpolationSolver};
pub use continuity::{join_knot_vectors, knot_multiplicity, Continuity};
pub use corners::{
    find_knuckle_lines, knuckle_indices, section_corners, turning_angles, CornerOptions, KnuckleLine, SectionCorner,
};
pub use extent::{bounding_diagonal, has_extent};
pub use held::{held_refit, HeldBounds, HeldRefit, HELD_PULL, HELD_SAMPLES_PER_SPAN, HELD_TOLERANCE};
pub use interp::{interpolate_curve, interpolate_curve_auto, InterpolationSolver};
pub use knots::{
    approximation_knots, averaging_knots, centred_approximation_knots, knots_for_approximation,
    knots_for_interpolation, optimal_knots, schoenberg_whitney,
};
pub use lsq::{approximate_curve, approximate_curve_auto, LeastSquaresSolver};
pub use param::{common_parameters, parameterize, Parameterization, SkinParameterization, UnknownParameterization};
pub use plane_runs::{plane_run_ends, RunEnd};
pub use skin::{
    skin_approximate, skin_approximate_with_knuckles, skin_interpolate, skin_interpolate_with_knuckles,
    AlongParameters, SkinOptions, SkinResult,
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

/// Check a fitted surface before it is handed on: every knot finite and the knot vectors valid
/// (non-decreasing, clamped, interior multiplicity at most the degree: [`KnotVector::try_new`]),
/// every homogeneous control point `(w x, w y, w z, w)` finite with `w > 0`. A solver that
/// loses all its digits returns NaN or infinities rather than an error; this turns them into
/// one, naming the first bad control point as `(i, j)` (u-major, `i` along u).
///
/// # Errors
/// [`NurbsError::NonFiniteResult`] naming `what` and the first bad knot or control point.
pub fn check_surface(surface: &NurbsSurface, what: &str) -> Result<(), NurbsError> {
    for (dir, kv) in [("u", surface.knots_u()), ("v", surface.knots_v())] {
        KnotVector::try_new(kv.degree(), kv.as_slice().to_vec())
            .map_err(|e| NurbsError::NonFiniteResult { what: format!("{what}: knot vector along {dir}: {e}") })?;
    }
    let n_v = surface.n_v();
    for (index, c) in surface.homogeneous().iter().enumerate() {
        let w = c[3];
        if !(c.iter().all(|x| x.is_finite()) && w > 0.0) {
            let (i, j) = (index / n_v, index % n_v);
            return Err(NurbsError::NonFiniteResult {
                what: format!(
                    "{what}: control point ({i}, {j}) is ({}, {}, {}) with weight {w}",
                    c[0] / w,
                    c[1] / w,
                    c[2] / w
                ),
            });
        }
    }
    Ok(())
}

/// The non-rational curve with these knots and control points.
pub(crate) fn polynomial_curve(knots: &KnotVector, control_points: Vec<Vec3>) -> NurbsCurve {
    NurbsCurve::from_parts_unchecked(
        knots.clone(),
        control_points.into_iter().map(|p| crate::curve::to_homogeneous(p, 1.0)).collect(),
    )
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::curve::to_homogeneous;

    /// A bilinear patch over `[0, 1]^2` whose control point `(1, 0)` is `bad` with weight `w`.
    fn patch(bad: Vec3, w: f64) -> NurbsSurface {
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let mut cw: Vec<[f64; 4]> = [Vec3::ZERO, Vec3::new(0.0, 1.0, 0.0), bad, Vec3::new(1.0, 1.0, 0.0)]
            .map(|p| to_homogeneous(p, 1.0))
            .into();
        cw[2] = to_homogeneous(bad, w);
        NurbsSurface::from_parts_unchecked(k.clone(), k, cw)
    }

    #[test]
    fn check_surface_names_the_first_bad_control_point() {
        assert_eq!(check_surface(&patch(Vec3::new(1.0, 0.0, 0.0), 1.0), "t"), Ok(()));
        let e = check_surface(&patch(Vec3::new(1.0, f64::NAN, 0.0), 1.0), "skin").expect_err("NaN");
        assert_eq!(
            e,
            NurbsError::NonFiniteResult { what: "skin: control point (1, 0) is (1, NaN, 0) with weight 1".into() }
        );
        let e = check_surface(&patch(Vec3::new(1.0, 0.0, 0.0), 0.0), "skin").expect_err("zero weight");
        assert!(e.to_string().contains("control point (1, 0)") && e.to_string().contains("weight 0"), "{e}");
        let e = check_surface(&patch(Vec3::new(1.0, 0.0, 0.0), -2.0), "skin").expect_err("negative weight");
        assert!(e.to_string().contains("weight -2"), "{e}");
    }
}
