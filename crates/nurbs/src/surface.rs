//! Rational B-spline (NURBS) tensor-product surfaces in 3-D.
//!
//! `S(u,v) = sum_i sum_j N_{i,p}(u) N_{j,q}(v) w_ij P_ij / sum_i sum_j N_{i,p}(u) N_{j,q}(v) w_ij`
//! (The NURBS Book eq. 4.15). Control points are stored u-major: index `i * n_v + j`, `i` along
//! u (`0..n_u`), `j` along v (`0..n_v`), homogeneous `(w x, w y, w z, w)`.

use crate::basis::{basis_funs, ders_basis_funs, BasisRow};
use crate::curve::{from_homogeneous, pack, to_homogeneous, Homogeneous};
use crate::knots::MAX_DEGREE;
use crate::tolerance::DEGENERATE_REL;
use crate::{KnotVector, NurbsError, Vec3};

/// The point and partial derivatives up to second order at one `(u, v)`.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct SurfaceDerivatives {
    pub point: Vec3,
    pub su: Vec3,
    pub sv: Vec3,
    pub suu: Vec3,
    pub suv: Vec3,
    pub svv: Vec3,
}

/// Gaussian and mean curvature with the unit normal they refer to.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Curvature {
    /// `K = (L N - M^2) / (E G - F^2)`.
    pub gaussian: f64,
    /// `H = (E N - 2 F M + G L) / (2 (E G - F^2))`, positive when the surface bends toward the normal.
    pub mean: f64,
    /// `n = (S_u x S_v) / |S_u x S_v|`.
    pub normal: Vec3,
}

impl SurfaceDerivatives {
    /// The unit normal `S_u x S_v / |S_u x S_v|`, `None` at a degenerate point.
    pub fn normal(&self) -> Option<Vec3> {
        self.su.cross(self.sv).normalized()
    }

    /// The unit normal where the parametrisation is regular enough for second-order
    /// quantities: `|S_u x S_v| >= DEGENERATE_REL (|S_u|^2 + |S_v|^2)`
    /// ([`DEGENERATE_REL`](crate::tolerance::DEGENERATE_REL)); `None` at and right next to a
    /// collapsed edge (a pole, a pointed end), where the fundamental forms are round-off.
    pub fn regular_normal(&self) -> Option<Vec3> {
        let c = self.su.cross(self.sv);
        let scale = self.su.norm_squared() + self.sv.norm_squared();
        (c.norm() >= DEGENERATE_REL * scale).then(|| c.normalized()).flatten()
    }

    /// Gaussian and mean curvature from the first and second fundamental forms;
    /// `None` where the surface is degenerate (`S_u x S_v = 0`).
    pub fn curvature(&self) -> Option<Curvature> {
        let normal = self.normal()?;
        let (e, f, g) = (self.su.dot(self.su), self.su.dot(self.sv), self.sv.dot(self.sv));
        let (l, m, n) = (self.suu.dot(normal), self.suv.dot(normal), self.svv.dot(normal));
        let det = e * g - f * f;
        if !(det > 0.0) {
            return None;
        }
        Some(Curvature { gaussian: (l * n - m * m) / det, mean: (e * n - 2.0 * f * m + g * l) / (2.0 * det), normal })
    }
}

/// A NURBS surface.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsSurface {
    ku: KnotVector,
    kv: KnotVector,
    cw: Vec<Homogeneous>,
}

impl NurbsSurface {
    /// Build from knots, Euclidean control points (u-major, `n_u * n_v` of them) and optional
    /// weights (all 1 if `None`).
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`], [`NurbsError::WeightCount`],
    /// [`NurbsError::BadWeight`] or [`NurbsError::NonFinitePoint`].
    pub fn try_new(
        knots_u: KnotVector,
        knots_v: KnotVector,
        points: &[Vec3],
        weights: Option<&[f64]>,
    ) -> Result<Self, NurbsError> {
        let cw = pack(points, weights, knots_u.num_basis() * knots_v.num_basis())?;
        Ok(NurbsSurface { ku: knots_u, kv: knots_v, cw })
    }

    /// Build from homogeneous control points (u-major).
    ///
    /// # Errors
    /// As [`NurbsSurface::try_new`].
    pub fn try_from_homogeneous(
        knots_u: KnotVector,
        knots_v: KnotVector,
        cw: Vec<Homogeneous>,
    ) -> Result<Self, NurbsError> {
        let expected = knots_u.num_basis() * knots_v.num_basis();
        if cw.len() != expected {
            return Err(NurbsError::ControlPointCount { expected, got: cw.len() });
        }
        for (index, h) in cw.iter().enumerate() {
            if !(h[3].is_finite() && h[3] > 0.0) {
                return Err(NurbsError::BadWeight { index, value: h[3] });
            }
            if !h.iter().all(|x| x.is_finite()) {
                return Err(NurbsError::NonFinitePoint { index });
            }
        }
        Ok(NurbsSurface { ku: knots_u, kv: knots_v, cw })
    }

    pub(crate) fn from_parts_unchecked(knots_u: KnotVector, knots_v: KnotVector, cw: Vec<Homogeneous>) -> Self {
        debug_assert_eq!(cw.len(), knots_u.num_basis() * knots_v.num_basis());
        NurbsSurface { ku: knots_u, kv: knots_v, cw }
    }

    #[inline]
    pub fn degree_u(&self) -> usize {
        self.ku.degree()
    }
    #[inline]
    pub fn degree_v(&self) -> usize {
        self.kv.degree()
    }
    #[inline]
    pub fn knots_u(&self) -> &KnotVector {
        &self.ku
    }
    #[inline]
    pub fn knots_v(&self) -> &KnotVector {
        &self.kv
    }
    #[inline]
    pub fn n_u(&self) -> usize {
        self.ku.num_basis()
    }
    #[inline]
    pub fn n_v(&self) -> usize {
        self.kv.num_basis()
    }
    #[inline]
    pub fn domain_u(&self) -> (f64, f64) {
        self.ku.domain()
    }
    #[inline]
    pub fn domain_v(&self) -> (f64, f64) {
        self.kv.domain()
    }
    /// Homogeneous control points, u-major.
    #[inline]
    pub fn homogeneous(&self) -> &[Homogeneous] {
        &self.cw
    }
    /// The Euclidean control point `P_ij`.
    pub fn control_point(&self, i: usize, j: usize) -> Vec3 {
        from_homogeneous(self.cw[i * self.n_v() + j])
    }
    /// All Euclidean control points, u-major.
    pub fn control_points(&self) -> Vec<Vec3> {
        self.cw.iter().map(|&h| from_homogeneous(h)).collect()
    }
    pub fn weight(&self, i: usize, j: usize) -> f64 {
        self.cw[i * self.n_v() + j][3]
    }
    /// All weights, u-major.
    pub fn weights(&self) -> Vec<f64> {
        self.cw.iter().map(|h| h[3]).collect()
    }
    /// True if the weights are not all equal.
    pub fn is_rational(&self) -> bool {
        self.cw.iter().any(|h| h[3] != self.cw[0][3])
    }

    /// The point `S(u, v)` (A4.3); parameters are clamped to the domain. Allocation-free.
    #[inline]
    pub fn point(&self, u: f64, v: f64) -> Vec3 {
        let (u, v) = (self.ku.clamp(u), self.kv.clamp(v));
        let (p, q) = (self.degree_u(), self.degree_v());
        let su = self.ku.find_span(u);
        let sv = self.kv.find_span(v);
        let mut nu: BasisRow = [0.0; MAX_DEGREE + 1];
        let mut nv: BasisRow = [0.0; MAX_DEGREE + 1];
        basis_funs(self.ku.as_slice(), su, u, p, &mut nu);
        basis_funs(self.kv.as_slice(), sv, v, q, &mut nv);
        let nvn = self.n_v();
        let mut h = [0.0f64; 4];
        for k in 0..=p {
            let row = &self.cw[(su - p + k) * nvn + sv - q..][..=q];
            let mut t = [0.0f64; 4];
            for (l, c) in row.iter().enumerate() {
                let b = nv[l];
                t[0] += b * c[0];
                t[1] += b * c[1];
                t[2] += b * c[2];
                t[3] += b * c[3];
            }
            let a = nu[k];
            h[0] += a * t[0];
            h[1] += a * t[1];
            h[2] += a * t[2];
            h[3] += a * t[3];
        }
        Vec3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3])
    }

    /// The point and partial derivatives up to second order (A3.6 on the homogeneous surface,
    /// then A4.4): with `A^(k,l)` the homogeneous derivatives and `w` their weight part,
    ///
    /// ```text
    /// S^(k,l) = (A^(k,l) - sum_{i=1..k} C(k,i) w^(i,0) S^(k-i,l)
    ///            - sum_{j=1..l} C(l,j) (w^(0,j) S^(k,l-j) + sum_{i=1..k} C(k,i) w^(i,j) S^(k-i,l-j))) / w
    /// ```
    ///
    /// At an interior knot the derivatives are those of the span to the right.
    pub fn derivatives(&self, u: f64, v: f64) -> SurfaceDerivatives {
        let (u, v) = (self.ku.clamp(u), self.kv.clamp(v));
        let (p, q) = (self.degree_u(), self.degree_v());
        let su = self.ku.find_span(u);
        let sv = self.kv.find_span(v);
        let mut du = [[0.0; MAX_DEGREE + 1]; 3];
        let mut dv = [[0.0; MAX_DEGREE + 1]; 3];
        ders_basis_funs(self.ku.as_slice(), su, u, p, 2, &mut du);
        ders_basis_funs(self.kv.as_slice(), sv, v, q, 2, &mut dv);
        let nvn = self.n_v();
        // a[k][l] homogeneous derivative d^(k+l)/du^k dv^l, k + l <= 2.
        let mut a = [[[0.0f64; 4]; 3]; 3];
        for r in 0..=p {
            let t = row_sums::<2>(&self.cw[(su - p + r) * nvn + sv - q..][..=q], &dv);
            add_row::<2>(&mut a, &du, r, &t);
        }
        rational_surface_derivatives(&a)
    }

    /// The unit normal `S_u x S_v / |S_u x S_v|`. At a degenerate point (a collapsed edge, as at
    /// a pointed end) the normal is taken as the limit from slightly inside the domain.
    pub fn normal(&self, u: f64, v: f64) -> Option<Vec3> {
        if let Some(n) = self.derivatives(u, v).normal() {
            return Some(n);
        }
        let (uu, vv) = self.nudged_inside(u, v, 1e-7);
        self.derivatives(uu, vv).normal()
    }

    /// `(u, v)` moved inside the domain, toward its middle, to at least `rel` of each
    /// direction's length from its boundary: where the normal or curvature of a degenerate
    /// point (on a boundary collapsed to a point) is taken as a limit.
    ///
    /// ```
    /// let s = nurbs::fixtures::quarter_cylinder_along_x(2.0, 3.0);
    /// let ((u0, u1), (v0, _)) = (s.domain_u(), s.domain_v());
    /// let (u, v) = s.nudged_inside(u0, v0 + 0.5, 1e-6);
    /// assert_eq!((u, v), (u0 + 1e-6 * (u1 - u0), v0 + 0.5));
    /// ```
    pub fn nudged_inside(&self, u: f64, v: f64, rel: f64) -> (f64, f64) {
        let ((u0, u1), (v0, v1)) = (self.domain_u(), self.domain_v());
        let (eu, ev) = (rel * (u1 - u0), rel * (v1 - v0));
        (u.clamp(u0 + eu, u1 - eu), v.clamp(v0 + ev, v1 - ev))
    }

    /// Gaussian and mean curvature at `(u, v)`, `None` at a degenerate point.
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsSurface, Vec3};
    /// // A quarter cylinder of radius 2: the quarter circle (rational quadratic) along u, a line
    /// // along v. Its Gaussian curvature is 0 and its mean curvature 1/(2r) in magnitude.
    /// let arc = [Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 2.0, 0.0), Vec3::new(0.0, 2.0, 0.0)];
    /// let net: Vec<Vec3> = arc.iter().flat_map(|&p| [p, p + Vec3::new(0.0, 0.0, 3.0)]).collect();
    /// let w = std::f64::consts::FRAC_1_SQRT_2;
    /// let s = NurbsSurface::try_new(
    ///     KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?,
    ///     KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0])?,
    ///     &net,
    ///     Some(&[1.0, 1.0, w, w, 1.0, 1.0]),
    /// )?;
    /// let c = s.curvature(0.3, 0.6).expect("a regular point");
    /// assert!(c.gaussian.abs() < 1e-12);
    /// assert!((c.mean.abs() - 0.25).abs() < 1e-12);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn curvature(&self, u: f64, v: f64) -> Option<Curvature> {
        self.derivatives(u, v).curvature()
    }

    /// The axis-aligned bounding box of the control net (contains the surface).
    pub fn control_bounds(&self) -> (Vec3, Vec3) {
        let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        for &h in &self.cw {
            let p = from_homogeneous(h);
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        (lo, hi)
    }

    /// The diagonal of the control net's bounding box ([`NurbsSurface::control_bounds`], which
    /// contains the surface): the model size that relative tolerances refer to. `None` for an
    /// empty or non-finite box.
    pub fn model_size(&self) -> Option<f64> {
        let (lo, hi) = self.control_bounds();
        let size = (hi - lo).norm();
        (size.is_finite() && size > 0.0).then_some(size)
    }

    /// The iso-parametric curve at fixed `v` (a curve in u), exact.
    pub fn iso_curve_u(&self, v: f64) -> crate::NurbsCurve {
        let v = self.kv.clamp(v);
        let q = self.degree_v();
        let sv = self.kv.find_span(v);
        let mut nv: BasisRow = [0.0; MAX_DEGREE + 1];
        basis_funs(self.kv.as_slice(), sv, v, q, &mut nv);
        let nvn = self.n_v();
        let cw = (0..self.n_u())
            .map(|i| {
                let mut h = [0.0; 4];
                for (l, b) in nv.iter().enumerate().take(q + 1) {
                    let c = self.cw[i * nvn + sv - q + l];
                    for k in 0..4 {
                        h[k] += b * c[k];
                    }
                }
                h
            })
            .collect();
        crate::NurbsCurve::from_parts_unchecked(self.ku.clone(), cw)
    }

    /// Swap the roles of u and v (the same geometry, transposed net).
    pub fn transposed(&self) -> Self {
        let (nu, nv) = (self.n_u(), self.n_v());
        let mut cw = Vec::with_capacity(self.cw.len());
        for j in 0..nv {
            for i in 0..nu {
                cw.push(self.cw[i * nv + j]);
            }
        }
        NurbsSurface { ku: self.kv.clone(), kv: self.ku.clone(), cw }
    }

    /// Reverse the direction of u (the same geometry, the net's rows in reverse order, the u
    /// knots reflected in their domain; the normal `S_u x S_v` turns round).
    pub fn reversed_u(&self) -> Self {
        let (a, b) = self.domain_u();
        let mut k: Vec<f64> = self.ku.as_slice().iter().map(|&u| a + b - u).collect();
        k.reverse();
        let nv = self.n_v();
        let cw = self.cw.chunks(nv).rev().flatten().copied().collect();
        NurbsSurface { ku: KnotVector::new_unchecked(self.degree_u(), k), kv: self.kv.clone(), cw }
    }

    /// The surface scaled by `k` about the origin (a change of length unit): every control
    /// point times `k`, the weights kept (the same numbers as [`NurbsSurface::try_new`] of the
    /// scaled points and the weights). A scale that overflows gives non-finite points: check
    /// them where that can happen.
    pub fn scaled(&self, k: f64) -> Self {
        let cw = self.cw.iter().map(|&h| to_homogeneous(from_homogeneous(h) * k, h[3])).collect();
        NurbsSurface { ku: self.ku.clone(), kv: self.kv.clone(), cw }
    }
}

// The tensor-product sums of the evaluation (A3.5 on homogeneous points, A4.4), shared by the
// pointwise [`NurbsSurface::derivatives`] and the grid evaluation (`grid.rs`), which imports
// them from here (so the two modules do not import each other).

/// The sums of one control row `row` (its `q + 1` homogeneous points) against the v basis
/// functions and their derivatives `dv`: `t[l] = sum_s dv[l][s] P_s`, `l <= ORDER`.
#[inline]
pub(crate) fn row_sums<const ORDER: usize>(row: &[Homogeneous], dv: &[BasisRow; 3]) -> [[f64; 4]; 3] {
    let mut t = [[0.0f64; 4]; 3];
    for (s, c) in row.iter().enumerate() {
        for l in 0..=ORDER {
            let b = dv[l][s];
            for c4 in 0..4 {
                t[l][c4] += b * c[c4];
            }
        }
    }
    t
}

/// `a[k][l] += du[k][r] t[l]` for `k + l <= ORDER`: row `r`'s share (its [`row_sums`] `t`)
/// of the homogeneous derivatives, `du` the u basis functions and their derivatives.
#[inline]
pub(crate) fn add_row<const ORDER: usize>(a: &mut [[[f64; 4]; 3]; 3], du: &[BasisRow; 3], r: usize, t: &[[f64; 4]; 3]) {
    for k in 0..=ORDER {
        for l in 0..=ORDER - k {
            let b = du[k][r];
            for c4 in 0..4 {
                a[k][l][c4] += b * t[l][c4];
            }
        }
    }
}

/// A4.4 to first order: the point, `S_u` and `S_v` from the homogeneous derivatives.
pub(crate) fn rational_first(a: &[[[f64; 4]; 3]; 3]) -> (Vec3, Vec3, Vec3) {
    let w = |k: usize, l: usize| a[k][l][3];
    let av = |k: usize, l: usize| Vec3::new(a[k][l][0], a[k][l][1], a[k][l][2]);
    let w0 = w(0, 0);
    let s00 = av(0, 0) / w0;
    let s10 = (av(1, 0) - s00 * w(1, 0)) / w0;
    let s01 = (av(0, 1) - s00 * w(0, 1)) / w0;
    (s00, s10, s01)
}

/// A4.4 up to second order from the homogeneous derivatives `a[k][l]` (`k + l <= 2`).
pub(crate) fn rational_surface_derivatives(a: &[[[f64; 4]; 3]; 3]) -> SurfaceDerivatives {
    let w = |k: usize, l: usize| a[k][l][3];
    let av = |k: usize, l: usize| Vec3::new(a[k][l][0], a[k][l][1], a[k][l][2]);
    let w0 = w(0, 0);
    let (s00, s10, s01) = rational_first(a);
    let s20 = (av(2, 0) - s10 * (2.0 * w(1, 0)) - s00 * w(2, 0)) / w0;
    let s02 = (av(0, 2) - s01 * (2.0 * w(0, 1)) - s00 * w(0, 2)) / w0;
    let s11 = (av(1, 1) - s10 * w(0, 1) - s01 * w(1, 0) - s00 * w(1, 1)) / w0;
    SurfaceDerivatives { point: s00, su: s10, sv: s01, suu: s20, suv: s11, svv: s02 }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fixtures::quarter_cylinder;

    #[test]
    fn reversing_u_and_scaling_keep_the_geometry() {
        let s = quarter_cylinder(2.0, 3.0).refine_knots_u(&[0.3]).expect("refined");
        let r = s.reversed_u();
        // Twice: the same net, the knots reflected twice (0.3 comes back within an ulp).
        let twice = r.reversed_u();
        assert_eq!(twice.homogeneous(), s.homogeneous());
        for (a, b) in twice.knots_u().as_slice().iter().zip(s.knots_u().as_slice()) {
            assert!((a - b).abs() <= 1e-15, "{a} {b}");
        }
        // Scaling is try_new of the scaled points, to the bit.
        let pts: Vec<Vec3> = s.control_points().iter().map(|&p| p * 1000.0).collect();
        let by_hand = NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, Some(&s.weights()));
        assert_eq!(Some(s.scaled(1000.0)), by_hand.ok());
        let big = s.scaled(1000.0);
        let (a, b) = s.domain_u();
        for i in 0..=8 {
            for j in 0..=4 {
                let (u, v) = (a + (b - a) * f64::from(i) / 8.0, f64::from(j) / 4.0);
                // Reflected knots and reversed rows evaluate the same basis: round-off.
                assert!((r.point(a + b - u, v) - s.point(u, v)).norm() < 1e-14, "{u} {v}");
                assert!((big.point(u, v) - s.point(u, v) * 1000.0).norm() < 1e-11, "{u} {v}");
            }
        }
        assert_eq!(big.weights(), s.weights());
    }

    #[test]
    fn cylinder_points_normals_and_curvature() {
        let r = 2.0;
        let s = quarter_cylinder(r, 3.0);
        for i in 0..=20 {
            for j in 0..=5 {
                let (u, v) = (i as f64 / 20.0, j as f64 / 5.0);
                let d = s.derivatives(u, v);
                assert_near!(d.point, s.point(u, v), 1e-15);
                assert_near!((d.point.x.powi(2) + d.point.y.powi(2)).sqrt(), r, 1e-13);
                assert_near!(d.point.z, 3.0 * v, 1e-14);
                let c = d.curvature().expect("regular");
                // A cylinder: K = 0, |H| = 1/(2r); the normal is radial.
                assert_near!(c.gaussian, 0.0, 1e-12);
                assert_near!(c.mean.abs(), 0.5 / r, 1e-12);
                assert_near!(c.normal.z, 0.0, 1e-14);
            }
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let s = quarter_cylinder(1.5, 2.0);
        let h = 1e-5;
        for (u, v) in [(0.3, 0.4), (0.71, 0.2), (0.5, 0.9)] {
            let d = s.derivatives(u, v);
            let du = (s.point(u + h, v) - s.point(u - h, v)) / (2.0 * h);
            let dv = (s.point(u, v + h) - s.point(u, v - h)) / (2.0 * h);
            assert_near!(d.su, du, 1e-8);
            assert_near!(d.sv, dv, 1e-8);
            let duu = (s.derivatives(u + h, v).su - s.derivatives(u - h, v).su) / (2.0 * h);
            let duv = (s.derivatives(u, v + h).su - s.derivatives(u, v - h).su) / (2.0 * h);
            assert_near!(d.suu, duu, 1e-7);
            assert_near!(d.suv, duv, 1e-7);
        }
    }

    #[test]
    fn iso_curve_and_transpose_agree_with_surface() {
        let s = quarter_cylinder(1.0, 2.0);
        let c = s.iso_curve_u(0.37);
        let t = s.transposed();
        for i in 0..=10 {
            let u = i as f64 / 10.0;
            assert_near!(c.point(u), s.point(u, 0.37), 1e-15);
            assert_near!(t.point(0.37, u), s.point(u, 0.37), 1e-15);
        }
    }
}
