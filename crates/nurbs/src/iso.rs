//! Iso-parametric curves of a surface over one knot span, with the derivative across them:
//! what an integrator over the parameter domain evaluates at every quadrature node, and what
//! locates the level set `p[axis] = level` of a coordinate along such a curve.
//!
//! At a fixed value `s` of the outer parameter, the surface's homogeneous net contracted with
//! the outer basis functions `N_l(s)` and their derivatives `N_l'(s)` gives two rows of
//! homogeneous control points over the inner span (The NURBS Book A3.6 to first order,
//! split in its two sums):
//!
//! `C0_r = sum_l N_l(s) P^w_{r,l}`, `C1_r = sum_l N_l'(s) P^w_{r,l}`,
//!
//! so that `A(t) = sum_r N_r(t) C0_r` is the homogeneous curve, `A_t = sum_r N_r'(t) C0_r` and
//! `A_s = sum_r N_r(t) C1_r` its derivatives along and across, and `S = A / w`,
//! `S' = (A' - w' S) / w` (A4.4 to first order). Each point then costs one sum over the inner
//! degree, not a sum over the whole patch of control points.
//! [`NurbsSurface::iso_curve_u`] builds the exact whole curve instead, as a [`crate::NurbsCurve`].

use crate::basis::{basis_funs, ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::{brent_root, Axis, FirstDerivatives, NurbsSurface, Vec3};

/// A parameter direction of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Direction {
    /// Along u (v fixed).
    U,
    /// Along v (u fixed).
    V,
}

impl Direction {
    /// The other direction.
    pub fn other(self) -> Direction {
        match self {
            Direction::U => Direction::V,
            Direction::V => Direction::U,
        }
    }
}

/// The iso-parametric curve of a surface along one parameter (`along`, the *inner* one) at a
/// fixed value of the other (the *outer* one), over one knot span in each: the point, both
/// first partial derivatives of the surface, and the roots of a coordinate's level set along
/// it (see the module docs of `iso.rs` for the formulas).
///
/// The curve is the polynomial (rational) piece of the given spans: exact for an inner
/// parameter in the inner span, and for an outer value in the outer span.
///
/// ```
/// use nurbs::{Axis, Direction, IsoCurve};
///
/// // The quarter cylinder y^2 + z^2 = 4 (y >= 0, z <= 0) along x from 0 to 3 (x = 3 v): one
/// // span in each direction.
/// let s = nurbs::fixtures::quarter_cylinder_along_x(2.0, 3.0);
/// let spans = (s.knots_u().find_span(0.5), s.knots_v().find_span(0.5));
/// let iso = IsoCurve::new(&s, Direction::U, 0.25, spans);
/// // A point of the curve is the surface's point, its derivatives the surface's.
/// let (p, d) = (iso.point(0.3), iso.derivatives(0.3));
/// assert!(p.distance(s.point(0.3, 0.25)) < 1e-14 && d.point == p);
/// let exact = s.derivatives(0.3, 0.25);
/// assert!(d.su.distance(exact.su) < 1e-12 && d.sv.distance(exact.sv) < 1e-12);
/// // The root of the level set y = 1 lies on it, on the circle.
/// let t = iso.root(Axis::Y, 1.0, 0.0, 1.0).expect("y runs from 0 to 2 along u");
/// let q = iso.point(t);
/// assert!((q.y - 1.0).abs() < 1e-15 && (q.y.hypot(q.z) - 2.0).abs() < 1e-15);
/// // The level set y = 1 is the line z = -sqrt 3 along x: its tangent dS/dv is (3, 0, 0).
/// let (at, tangent) = iso.cut_point(Axis::Y, t);
/// assert_eq!(at, q);
/// assert!(tangent.distance(nurbs::Vec3::new(3.0, 0.0, 0.0)) < 1e-12);
/// ```
#[derive(Clone, Debug)]
pub struct IsoCurve<'s> {
    knots: &'s [f64],
    degree: usize,
    span: usize,
    along: Direction,
    /// The homogeneous control points of the curve, `C0`.
    c0: [[f64; 4]; MAX_DEGREE + 1],
    /// Their derivatives across (with respect to the outer parameter), `C1`.
    c1: [[f64; 4]; MAX_DEGREE + 1],
}

impl<'s> IsoCurve<'s> {
    /// The curve of `surface` along `along` at the value `at` of the other parameter, over
    /// the knot spans `(span_u, span_v)` (as [`crate::KnotVector::find_span`] gives them).
    ///
    /// # Panics
    /// If a span is not a span of the surface's knot vectors (from `degree` to
    /// `n - 1` in each direction).
    pub fn new(surface: &'s NurbsSurface, along: Direction, at: f64, (su, sv): (usize, usize)) -> Self {
        let (p, q) = (surface.degree_u(), surface.degree_v());
        let nvn = surface.n_v();
        let cw = surface.homogeneous();
        let mut ob: [BasisRow; 2] = [[0.0; MAX_DEGREE + 1]; 2];
        let mut c0 = [[0.0f64; 4]; MAX_DEGREE + 1];
        let mut c1 = [[0.0f64; 4]; MAX_DEGREE + 1];
        // The row of control points r (along u) over the v span, contracted with the outer
        // basis in v (along u) or its r-th term taken by the outer basis in u (along v).
        let (outer_knots, outer_span, outer_degree) = match along {
            Direction::U => (surface.knots_v(), sv, q),
            Direction::V => (surface.knots_u(), su, p),
        };
        ders_basis_funs(outer_knots.as_slice(), outer_span, at, outer_degree, 1, &mut ob);
        for r in 0..=p {
            let row = &cw[(su - p + r) * nvn + sv - q..][..=q];
            for (l, h) in row.iter().enumerate() {
                // (inner index, outer index) of the control point (r, l).
                let (i, o) = match along {
                    Direction::U => (r, l),
                    Direction::V => (l, r),
                };
                for k in 0..4 {
                    c0[i][k] += ob[0][o] * h[k];
                    c1[i][k] += ob[1][o] * h[k];
                }
            }
        }
        let (knots, degree, span) = match along {
            Direction::U => (surface.knots_u().as_slice(), p, su),
            Direction::V => (surface.knots_v().as_slice(), q, sv),
        };
        IsoCurve { knots, degree, span, along, c0, c1 }
    }

    /// The direction the curve runs along.
    pub fn along(&self) -> Direction {
        self.along
    }

    /// The point `S(t)` at the inner parameter `t` (A4.1 on the curve).
    pub fn point(&self, t: f64) -> Vec3 {
        let mut n: BasisRow = [0.0; MAX_DEGREE + 1];
        basis_funs(self.knots, self.span, t, self.degree, &mut n);
        let mut a = [0.0f64; 4];
        for (b, c) in n.iter().zip(&self.c0).take(self.degree + 1) {
            for k in 0..4 {
                a[k] += b * c[k];
            }
        }
        Vec3::new(a[0] / a[3], a[1] / a[3], a[2] / a[3])
    }

    /// The point and both first partial derivatives `S_u`, `S_v` of the surface at the inner
    /// parameter `t`.
    pub fn derivatives(&self, t: f64) -> FirstDerivatives {
        let mut b: [BasisRow; 2] = [[0.0; MAX_DEGREE + 1]; 2];
        ders_basis_funs(self.knots, self.span, t, self.degree, 1, &mut b);
        self.derivatives_with_basis(&b)
    }

    /// As [`IsoCurve::derivatives`] with the inner basis functions and their first
    /// derivatives given ([`crate::basis::ders_basis_funs`] at the curve's inner span, to
    /// order 1): for a tensor rule that evaluates the same inner nodes on many curves.
    pub fn derivatives_with_basis(&self, b: &[BasisRow; 2]) -> FirstDerivatives {
        let (mut a, mut ai, mut ao) = ([0.0f64; 4], [0.0f64; 4], [0.0f64; 4]);
        for j in 0..=self.degree {
            let (n0, n1) = (b[0][j], b[1][j]);
            let (c0, c1) = (&self.c0[j], &self.c1[j]);
            for k in 0..4 {
                a[k] += n0 * c0[k];
                ai[k] += n1 * c0[k];
                ao[k] += n0 * c1[k];
            }
        }
        let w = a[3];
        let point = Vec3::new(a[0] / w, a[1] / w, a[2] / w);
        // A4.4 to first order: S' = (A' - w' S) / w.
        let d = |h: [f64; 4]| (Vec3::new(h[0], h[1], h[2]) - point * h[3]) / w;
        let (s_in, s_out) = (d(ai), d(ao));
        match self.along {
            Direction::U => FirstDerivatives { point, su: s_in, sv: s_out },
            Direction::V => FirstDerivatives { point, su: s_out, sv: s_in },
        }
    }

    /// The root in `[a, b]` of `f(t) = S(t)[axis] - level` if `f`
    /// changes sign there (taking `f <= 0` as one side), by Brent's method to round-off
    /// ([`brent_root`]); `None` if it does not.
    pub fn root(&self, axis: Axis, level: f64, a: f64, b: f64) -> Option<f64> {
        let g = |t: f64| self.point(t)[axis] - level;
        let (ga, gb) = (g(a), g(b));
        if (ga <= 0.0) == (gb <= 0.0) {
            return None;
        }
        Some(brent_root(g, a, b, ga, gb, 0.0))
    }

    /// As [`IsoCurve::root`], or without a sign change (round-off next to where the level set
    /// meets an end) the end where `|f|` is smaller.
    pub fn root_or_end(&self, axis: Axis, level: f64, a: f64, b: f64) -> f64 {
        let g = |t: f64| self.point(t)[axis] - level;
        let (ga, gb) = (g(a), g(b));
        if (ga <= 0.0) != (gb <= 0.0) {
            brent_root(g, a, b, ga, gb, 0.0)
        } else if ga.abs() <= gb.abs() {
            a
        } else {
            b
        }
    }

    /// The point at the inner parameter `r` and the tangent `dS/ds` (`s` the outer
    /// parameter) of the level set of the coordinate `axis` through it, the curve
    /// `inner = r(s)` with `r' = -f_outer / f_inner` (`f` the coordinate; `r' = 0` where
    /// `f_inner = 0`).
    pub fn cut_point(&self, axis: Axis, r: f64) -> (Vec3, Vec3) {
        let d = self.derivatives(r);
        let (s_in, s_out) = match self.along {
            Direction::U => (d.su, d.sv),
            Direction::V => (d.sv, d.su),
        };
        let f_in = s_in[axis];
        let rp = if f_in != 0.0 { -s_out[axis] / f_in } else { 0.0 };
        (d.point, s_in * rp + s_out)
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::rational_surface;

    #[test]
    fn both_directions_agree_with_the_surface_on_a_rational_patch() {
        let s = rational_surface(6, 5, 3, 2, false);
        let (ku, kv) = (s.knots_u(), s.knots_v());
        for &(u, v) in &[(0.13, 0.71), (0.5, 0.5), (0.92, 0.07)] {
            let (u, v) = (ku.clamp(u), kv.clamp(v));
            let spans = (ku.find_span(u), kv.find_span(v));
            let exact = s.derivatives(u, v);
            for (iso, t) in
                [(IsoCurve::new(&s, Direction::U, v, spans), u), (IsoCurve::new(&s, Direction::V, u, spans), v)]
            {
                let d = iso.derivatives(t);
                let scale = 1.0 + exact.su.norm() + exact.sv.norm();
                assert!(d.point.distance(exact.point) < 1e-13, "{:?} at ({u}, {v})", iso.along());
                assert!(d.su.distance(exact.su) < 1e-12 * scale && d.sv.distance(exact.sv) < 1e-12 * scale);
                assert_eq!(iso.point(t), d.point);
            }
        }
        assert_eq!(Direction::U.other(), Direction::V);
    }

    #[test]
    fn root_or_end_takes_the_nearer_end_without_a_sign_change() {
        let s = crate::fixtures::quarter_cylinder_along_x(2.0, 3.0);
        let iso = IsoCurve::new(&s, Direction::U, 0.5, (2, 1));
        // y runs from 0 to 2 along u: no root of y = 5, the end u = 1 (y = 2) is nearer.
        assert_eq!(iso.root(Axis::Y, 5.0, 0.0, 1.0), None);
        assert_eq!(iso.root_or_end(Axis::Y, 5.0, 0.0, 1.0), 1.0);
        assert_eq!(iso.root_or_end(Axis::Y, -1.0, 0.0, 1.0), 0.0);
        let r = iso.root_or_end(Axis::Y, 1.5, 0.0, 1.0);
        assert!((iso.point(r).y - 1.5).abs() < 1e-15);
    }
}
