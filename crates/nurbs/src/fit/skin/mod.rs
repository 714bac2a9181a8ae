//! Skinning: one tensor-product surface through (or near) a family of sections
//! (The NURBS Book 9.2.5 and 10.3).
//!
//! The input is `K >= 2` sections, each an ordered list of points; `u` runs along a section
//! and `v` across the sections. A section whose points all coincide (within
//! [`COINCIDENT_REL`] of the data's size; a single point counts too) is *degenerate*: a
//! pointed stem or stern. It becomes a curve whose control points all sit at that point, so
//! the surface edge collapses there. The surface is non-rational (all weights 1) and its
//! control net is stored u-major: index `i * n_v + j`, `i` along the sections, `j` across them.
//!
//! Sections may have different point counts (a table with missing cells, e.g. a ship's offset
//! table whose sections start higher or stop lower). All sections are then fitted on *one* knot vector along `u`
//! with `N` control points (`N = max n_k` for interpolation, `nu` for approximation), and a
//! section with fewer than `N` points is interpolated by its least-bending-energy curve on those
//! knots ([`FairInterpolationSolver`]). The net stays at one pole per point of the largest
//! section, where the classical approach (The NURBS Book 10.3, also Open CASCADE's skinning)
//! interpolates each section on its own knots and merges the knot vectors, which keeps every
//! knot of every section: 517 poles along `u` for the 16-point sections of R/V Gunnerus.
//!
//! The files: `sections` checks and classifies the input, `compatible` fits every section on one
//! knot vector along `u` (compatible curves), `across` the parameters and fits across the
//! sections, `interpolate` and `approximate` the two skins, `knuckles` the skins with `C^0`
//! lines along corners of the sections.

mod across;
mod approximate;
mod compatible;
mod interpolate;
mod knuckles;
mod sections;
#[cfg(test)]
mod tests;

pub use approximate::skin_approximate;
pub use interpolate::skin_interpolate;
pub use knuckles::{skin_approximate_with_knuckles, skin_interpolate_with_knuckles};

use crate::fit::SkinParameterization;
use crate::{NurbsError, NurbsSurface};

/// Settings of [`skin_interpolate`] and [`skin_approximate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SkinOptions {
    /// Degree along the sections, lowered to `N - 1` when the largest section has only `N`
    /// points (shorter sections do not lower it: they are fitted on the common knots).
    pub degree_u: usize,
    /// Degree across the sections (lowered to `K - 1` for `K` sections).
    pub degree_v: usize,
    /// Parameterization along the sections (`u`) and across them (`v`).
    pub param: SkinParameterization,
    /// Smoothing `ν` of [`skin_approximate`] (not of interpolation): each least-squares curve,
    /// along the sections and then across them, minimizes `sum |C(t_k) - Q_k|^2 + λ E(C)`
    /// ([`LeastSquaresSolver::smoothing`](crate::fit::LeastSquaresSolver::smoothing), `E` the bending energy) with
    /// `λ = ν m / (n max_i G_ii)` for `m` data points on `n` control points, `G` the knots'
    /// energy Gram matrix: dimensionless, a control polygon zig-zagging by `δ` costs about
    /// `ν δ^2` per data point, like a residual of `sqrt(ν) δ`. `0` (the default): plain least
    /// squares.
    pub smoothing: f64,
    /// The parameters along the sections of [`skin_approximate`] when they all have the same
    /// count: the choice with the least residual (the default), or one of them imposed.
    pub along: AlongParameters,
}
impl Default for SkinOptions {
    /// Bicubic, centripetal along the sections and chord length across them
    /// ([`SkinParameterization::default`]).
    fn default() -> Self {
        SkinOptions {
            degree_u: 3,
            degree_v: 3,
            param: SkinParameterization::default(),
            smoothing: 0.0,
            along: AlongParameters::LeastResidual,
        }
    }
}

/// The parameters at which [`skin_approximate`] fits the sections along `u`, when all of them
/// (but pointed ends) have the same count; with different counts each section is fitted on its
/// own whatever this says.
///
/// Why it can be imposed: with smoothing ([`SkinOptions::smoothing`]) the residuals of the two
/// choices move differently, and the choice can flip between `ν = 0` and the smallest `ν > 0`,
/// so the smoothed surface is not the plain one smoothed (the 4 x 3 example: 145.3 mm at `ν` = 0
/// on averaged parameters, 201 mm at `ν` = 1e-4 on own ones). A fairing search can impose the
/// plain fit's choice to stay continuous in `ν`.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash)]
pub enum AlongParameters {
    /// Each section on its own and all on their mean both fitted, the one with the least
    /// residual at the points kept ([`skin_approximate`] step 3).
    #[default]
    LeastResidual,
    /// Each section on its own parameters.
    Own,
    /// All sections on the mean of their parameters (The NURBS Book eq. 9.18).
    Mean,
}

/// A skinned surface and the parameters `(u, v)` assigned to every input point.
#[derive(Clone, Debug, PartialEq)]
pub struct SkinResult {
    pub surface: NurbsSurface,
    /// `params[k][i]` belongs to `sections[k][i]`. Interpolation gives
    /// `surface.point(u, v) == sections[k][i]`; approximation gives the points it fitted to.
    pub params: Vec<Vec<(f64, f64)>>,
    /// The parameters the approximation fitted the sections at along `u`: [`AlongParameters::Own`]
    /// or [`AlongParameters::Mean`]; [`AlongParameters::LeastResidual`] for interpolation, which
    /// chooses none, and for a skin with knuckles whose pieces chose differently or were all
    /// interpolated.
    pub along: AlongParameters,
}

/// The result, once [`super::check_surface`] finds its knots and control points finite (and
/// weights positive): the last guard against a solve that lost every digit.
fn checked(result: SkinResult) -> Result<SkinResult, NurbsError> {
    super::check_surface(&result.surface, "skinning")?;
    Ok(result)
}
