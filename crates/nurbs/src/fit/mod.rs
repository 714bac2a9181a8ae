//! Fitting: parameterization, knot vectors, interpolation, least squares, skinning.
//!
//! The pipeline for one curve is: data parameters ([`parameterize`], The NURBS Book 9.2.1),
//! a knot vector ([`optimal_knots`] of de Boor for interpolation, [`approximation_knots`] or
//! [`centred_approximation_knots`] for least squares, uniform with
//! [`Parameterization::Universal`]), then a banded solve
//! ([`InterpolationSolver`], A9.1, or [`LeastSquaresSolver`], 9.4.1) that is factored once and
//! reused for every right-hand side sharing parameters and knots. Surfaces are skinned from
//! sections ([`skin_interpolate`], [`skin_approximate`]; 9.2.5 and 10.3).

mod banded;
mod constrained;
mod interp;
mod knots;
mod lsq;
mod param;
mod skin;

pub use constrained::{energy_order, fair_interpolate_curve, row_schoenberg_whitney, FairInterpolationSolver};
pub use interp::{interpolate_curve, interpolate_curve_auto, InterpolationSolver};
pub use knots::{
    approximation_knots, averaging_knots, centred_approximation_knots, knots_for_approximation,
    knots_for_interpolation, optimal_knots, schoenberg_whitney,
};
pub use lsq::{approximate_curve, approximate_curve_auto, LeastSquaresSolver};
pub use param::{common_parameters, parameterize, Parameterization, SkinParameterization, UnknownParameterization};
pub use skin::{skin_approximate, skin_interpolate, SkinOptions, SkinResult};
