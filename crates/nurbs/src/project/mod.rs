//! Closest-point projection onto NURBS curves and surfaces (The NURBS Book 6.1).
//!
//! The foot point of `P` on a surface minimises `f(u,v) = |S(u,v) - P|^2 / 2`; at an interior
//! minimum the residual `r = S - P` is normal to the surface (eq. 6.6):
//! `g(u,v) = (S_u . r, S_v . r) = 0`. Newton's method on `g` (eq. 6.7-6.8) solves
//! `J d = -g` with
//! `J = [[|S_u|^2 + r . S_uu, S_u . S_v + r . S_uv], [S_u . S_v + r . S_uv, |S_v|^2 + r . S_vv]]`.
//!
//! Newton only converges locally, so the projectors first sample the surface on a grid adapted
//! to the knot spans (a few samples per span in each direction, more where it bends) and start
//! Newton from the best few places where the samples show a local minimum: nodes nearer than
//! their neighbours, cells where the gradient `g` changes sign, constrained minima on edges and
//! corners (see [`SurfaceProjector`]). Each knot span carries a bounding sphere of the surface
//! over it, which lets a query skip spans that cannot hold a closer point. The result is the
//! best of these local minima: the global one unless the surface hides a minimum between
//! samples.
//!
//! The iteration is made robust for any input:
//! - **clamping and boundaries**: iterates are clamped to the domain (as the Book does for open
//!   surfaces); a parameter sitting on a bound whose gradient points out of the domain is fixed
//!   (the Karush-Kuhn-Tucker condition of the bound) and Newton goes on in one dimension along
//!   that boundary curve;
//! - **singular or indefinite Jacobians** (a collapsed stem or stern edge where
//!   `S_u x S_v = 0`, or a saddle of the distance): the step falls back to Gauss-Newton
//!   `[[|S_u|^2, S_u . S_v], [S_u . S_v, |S_v|^2]] + mu I`, positive definite, so always a descent
//!   direction;
//! - **collapsed edges** (all of an edge one point, as at a pointed end): every parameter along
//!   the edge gives the same point but its own direction into the surface; Newton leaves such
//!   an edge in the steepest of them, and stops there only if none descends;
//! - **monotone decrease**: a step that does not reduce `|S - P|` is halved (backtracking);
//!   within the rounding noise of `|S - P|^2` a step that reduces the tangential residual is
//!   taken instead, so the foot converges to `eps1` even where the distance is flat.
//!
//! Convergence criteria of the Book, with `eps1 = tolerance * model size` (the diagonal of the
//! control net's bounding box):
//! - point coincidence `|S - P| <= eps1`;
//! - zero cosine `|S_u . r| / (|S_u| |r|) <= eps2` (and the same for `S_v`), with
//!   `eps2 = eps1 / |r|`, i.e. the tangential part of the residual is below `eps1`; a direction
//!   fixed at a bound by the rule above counts as satisfied;
//! - step size `|(u_{i+1} - u_i) S_u + (v_{i+1} - v_i) S_v| <= eps1`.
//!
//! The files: `sampling` places the start samples (by knot span and turning), `surface` and
//! `curve` hold the two projectors (point inversion on a surface and on a curve).

mod curve;
mod sampling;
mod surface;
#[cfg(test)]
mod tests;

pub use curve::{project_point_to_curve, CurveProjector};
pub use surface::SurfaceProjector;

use crate::tolerance::PROJECTION_REL;
use crate::Vec3;

/// Settings of curve and surface projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectionOptions {
    /// Sampling intervals per knot span in each parameter direction. A surface projector uses
    /// `max(grid, degree, 1)`, more in spans where an iso-line's tangent turns by more than
    /// 0.3 rad per interval (up to 64), and three extra rows graded towards a collapsed edge;
    /// a bicubic surface of 7 x 5 gentle spans with `grid = 4` is sampled at `29 x 21` points.
    /// Curves, cheaper per sample, use four times as many.
    pub grid: usize,
    /// How many distinct local minima are refined by Newton, best sampled candidates first
    /// (a run ending at a foot already found does not count; all runs are bounded by three
    /// times this); more guard against local minima on strongly curved shapes, at a cost.
    pub candidates: usize,
    /// Newton iterations per start point (3 to 6 typically; slow valleys next to a collapsed
    /// edge can take a few dozen).
    pub max_iterations: usize,
    /// Geometric tolerance `eps1` relative to the model size (the diagonal of the control net's
    /// bounding box). Non-finite or negative values are taken as 0 (iterate to the limit).
    pub tolerance: f64,
}

impl Default for ProjectionOptions {
    fn default() -> Self {
        ProjectionOptions { grid: 4, candidates: 4, max_iterations: 60, tolerance: PROJECTION_REL }
    }
}

/// The closest point of a surface to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceProjection {
    pub u: f64,
    pub v: f64,
    /// `S(u, v)`.
    pub point: Vec3,
    /// `|S(u, v) - q|`.
    pub distance: f64,
    /// Newton iterations of the winning start point.
    pub iterations: usize,
    /// True if a convergence criterion was met (not merely the iteration limit).
    pub converged: bool,
}

/// The closest point of a curve to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveProjection {
    pub u: f64,
    /// `C(u)`.
    pub point: Vec3,
    /// `|C(u) - q|`.
    pub distance: f64,
    /// Newton iterations of the winning start point.
    pub iterations: usize,
    /// True if a convergence criterion was met (not merely the iteration limit).
    pub converged: bool,
}

/// `eps1` of the options for a model whose control net has bounding-box diagonal `size`.
pub(super) fn abs_tolerance(opts: &ProjectionOptions, size: f64) -> f64 {
    let t = if opts.tolerance.is_finite() && opts.tolerance > 0.0 { opts.tolerance } else { 0.0 };
    let size = if size.is_finite() { size } else { 0.0 };
    t * size
}

/// True if parameter `t` sits on a bound of `[a, b]` and the gradient `g = df/dt` points out
/// of the domain (so the constrained minimum keeps `t` there).
#[inline]
pub(super) fn held_at_bound(t: f64, a: f64, b: f64, g: f64) -> bool {
    (t <= a && g >= 0.0) || (t >= b && g <= 0.0)
}

/// One-dimensional Newton step `-g / h`, or the Gauss-Newton step `-g / |S'|^2` when the second
/// derivative `h` of `f` is not safely positive.
#[inline]
pub(super) fn step_1d(h: f64, gg: f64, g: f64) -> f64 {
    if h > 1e-10 * gg && h > 0.0 {
        -g / h
    } else if gg > 0.0 {
        -g / gg
    } else {
        0.0
    }
}

/// Relative pivot below which the 2x2 Newton matrix counts as singular (condition ~1e10).
pub(super) const SINGULAR_REL: f64 = 1e-10;
/// Levenberg-Marquardt term of the Gauss-Newton fallback, relative to `|S_u|^2 + |S_v|^2`.
pub(super) const GN_DAMPING: f64 = 1e-9;
/// Step halvings tried before a step is given up.
pub(super) const MAX_HALVINGS: usize = 64;

/// `(S_k . r)^2 / |S_k|^2`, the squared tangential residual along a free direction `S_k`.
#[inline]
pub(super) fn tangential(sk: Vec3, r: Vec3, held: bool) -> f64 {
    let n2 = sk.norm_squared();
    if held || n2 == 0.0 {
        0.0
    } else {
        sk.dot(r).powi(2) / n2
    }
}
