//! Rational B-spline (NURBS) curves in 3-D, stored with homogeneous control points
//! `P^w_i = (w_i x_i, w_i y_i, w_i z_i, w_i)`.
//!
//! `C(u) = sum_i N_{i,p}(u) w_i P_i / sum_i N_{i,p}(u) w_i` (The NURBS Book eq. 4.2).

use crate::basis::{basis_funs, ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::{KnotVector, NurbsError, Vec3};

/// Homogeneous control point `(w x, w y, w z, w)`.
pub type Homogeneous = [f64; 4];

pub(crate) fn to_homogeneous(p: Vec3, w: f64) -> Homogeneous {
    [p.x * w, p.y * w, p.z * w, w]
}

pub(crate) fn from_homogeneous(h: Homogeneous) -> Vec3 {
    Vec3::new(h[0] / h[3], h[1] / h[3], h[2] / h[3])
}

/// Validate control points and weights, and pack them homogeneously.
pub(crate) fn pack(points: &[Vec3], weights: Option<&[f64]>, expected: usize) -> Result<Vec<Homogeneous>, NurbsError> {
    if points.len() != expected {
        return Err(NurbsError::ControlPointCount { expected, got: points.len() });
    }
    if let Some(w) = weights {
        if w.len() != expected {
            return Err(NurbsError::WeightCount { expected, got: w.len() });
        }
    }
    points
        .iter()
        .enumerate()
        .map(|(index, &p)| {
            if !p.is_finite() {
                return Err(NurbsError::NonFinitePoint { index });
            }
            let w = weights.map_or(1.0, |w| w[index]);
            if !(w.is_finite() && w > 0.0) {
                return Err(NurbsError::BadWeight { index, value: w });
            }
            Ok(to_homogeneous(p, w))
        })
        .collect()
}

/// Binomial coefficient as f64 (small arguments only).
pub(crate) fn binomial(n: usize, k: usize) -> f64 {
    let mut r = 1.0;
    for i in 0..k {
        r = r * (n - i) as f64 / (i + 1) as f64;
    }
    r
}

/// A NURBS curve.
#[derive(Clone, Debug, PartialEq)]
pub struct NurbsCurve {
    knots: KnotVector,
    cw: Vec<Homogeneous>,
}

impl NurbsCurve {
    /// Build a curve from knots, Euclidean control points and optional weights (all 1 if `None`).
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `points.len()` differs from the number of basis
    /// functions, [`NurbsError::WeightCount`], [`NurbsError::BadWeight`] for a weight that is not
    /// finite and positive, [`NurbsError::NonFinitePoint`].
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsCurve, Vec3};
    /// // A quarter of the unit circle as a rational quadratic (The NURBS Book eq. 7.1):
    /// // control points (1, 0), (1, 1), (0, 1), middle weight cos(45 degrees).
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
    /// let p = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
    /// let arc = NurbsCurve::try_new(k, &p, Some(&[1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0]))?;
    /// for i in 0..=10 {
    ///     assert!((arc.point(i as f64 / 10.0).norm() - 1.0).abs() < 1e-15);
    /// }
    /// // The same net with weights 1 is a parabola, not a circle.
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
    /// let parabola = NurbsCurve::try_new(k, &p, None)?;
    /// assert!((parabola.point(0.5).norm() - 1.0).abs() > 0.01);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn try_new(knots: KnotVector, points: &[Vec3], weights: Option<&[f64]>) -> Result<Self, NurbsError> {
        let cw = pack(points, weights, knots.num_basis())?;
        Ok(NurbsCurve { knots, cw })
    }

    /// Build from homogeneous control points.
    ///
    /// # Errors
    /// As [`NurbsCurve::try_new`].
    pub fn try_from_homogeneous(knots: KnotVector, cw: Vec<Homogeneous>) -> Result<Self, NurbsError> {
        if cw.len() != knots.num_basis() {
            return Err(NurbsError::ControlPointCount { expected: knots.num_basis(), got: cw.len() });
        }
        for (index, h) in cw.iter().enumerate() {
            if !(h[3].is_finite() && h[3] > 0.0) {
                return Err(NurbsError::BadWeight { index, value: h[3] });
            }
            if !h.iter().all(|x| x.is_finite()) {
                return Err(NurbsError::NonFinitePoint { index });
            }
        }
        Ok(NurbsCurve { knots, cw })
    }

    pub(crate) fn from_parts_unchecked(knots: KnotVector, cw: Vec<Homogeneous>) -> Self {
        debug_assert_eq!(cw.len(), knots.num_basis());
        NurbsCurve { knots, cw }
    }

    #[inline]
    pub fn degree(&self) -> usize {
        self.knots.degree()
    }
    #[inline]
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }
    #[inline]
    pub fn domain(&self) -> (f64, f64) {
        self.knots.domain()
    }
    #[inline]
    pub fn num_control_points(&self) -> usize {
        self.cw.len()
    }
    /// Homogeneous control points `(w x, w y, w z, w)`.
    #[inline]
    pub fn homogeneous(&self) -> &[Homogeneous] {
        &self.cw
    }
    pub fn control_point(&self, i: usize) -> Vec3 {
        from_homogeneous(self.cw[i])
    }
    pub fn control_points(&self) -> Vec<Vec3> {
        self.cw.iter().map(|&h| from_homogeneous(h)).collect()
    }
    pub fn weight(&self, i: usize) -> f64 {
        self.cw[i][3]
    }
    pub fn weights(&self) -> Vec<f64> {
        self.cw.iter().map(|h| h[3]).collect()
    }
    /// True if any weight differs from the first.
    pub fn is_rational(&self) -> bool {
        self.cw.iter().any(|h| h[3] != self.cw[0][3])
    }

    /// The point `C(u)` (A4.1); `u` is clamped to the domain.
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsCurve, Vec3};
    /// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 1.0), Vec3::new(4.0, 0.0, 0.0)];
    /// let c = NurbsCurve::try_new(KnotVector::uniform(3, 4)?, &pts, None)?;
    /// // A clamped curve interpolates its end control points (The NURBS Book P3.3).
    /// assert_eq!(c.point(0.0), pts[0]);
    /// assert!(c.point(1.0).distance(pts[3]) < 1e-15);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    #[inline]
    pub fn point(&self, u: f64) -> Vec3 {
        let u = self.knots.clamp(u);
        let p = self.degree();
        let span = self.knots.find_span(u);
        let mut n: BasisRow = [0.0; MAX_DEGREE + 1];
        basis_funs(self.knots.as_slice(), span, u, p, &mut n);
        let mut h = [0.0; 4];
        for (j, nj) in n.iter().enumerate().take(p + 1) {
            let c = &self.cw[span - p + j];
            for k in 0..4 {
                h[k] += nj * c[k];
            }
        }
        from_homogeneous(h)
    }

    /// `C(u)` and its derivatives up to order `d`: `out[k]` = `C^(k)(u)` (A3.2 on the
    /// homogeneous curve, then A4.2: `C^(k) = (A^(k) - sum_{i=1..k} C(k,i) w^(i) C^(k-i)) / w`).
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsCurve, Vec3};
    /// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 1.0), Vec3::new(4.0, 0.0, 0.0)];
    /// let c = NurbsCurve::try_new(KnotVector::uniform(3, 4)?, &pts, Some(&[1.0, 2.0, 0.5, 1.0]))?;
    /// // The first derivative equals the central difference of the points (to O(h^2)).
    /// let (u, h) = (0.4, 1e-5);
    /// let d = c.derivatives(u, 1);
    /// assert_eq!(d[0], c.point(u));
    /// let central = (c.point(u + h) - c.point(u - h)) * (0.5 / h);
    /// assert!(d[1].distance(central) < 1e-8);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn derivatives(&self, u: f64, d: usize) -> Vec<Vec3> {
        let u = self.knots.clamp(u);
        let p = self.degree();
        let span = self.knots.find_span(u);
        let mut ders = vec![[0.0; MAX_DEGREE + 1]; d + 1];
        ders_basis_funs(self.knots.as_slice(), span, u, p, d, &mut ders);
        let mut aw = vec![[0.0; 4]; d + 1];
        for k in 0..=d.min(p) {
            for j in 0..=p {
                let c = &self.cw[span - p + j];
                for c4 in 0..4 {
                    aw[k][c4] += ders[k][j] * c[c4];
                }
            }
        }
        rational_derivatives(&aw)
    }

    /// Reverse the direction of parameterization (domain kept).
    pub fn reversed(&self) -> Self {
        let (a, b) = self.domain();
        let mut k: Vec<f64> = self.knots.as_slice().iter().map(|&u| a + b - u).collect();
        k.reverse();
        let mut cw = self.cw.clone();
        cw.reverse();
        NurbsCurve { knots: KnotVector::new_unchecked(self.degree(), k), cw }
    }
}

/// Euclidean derivatives from homogeneous ones (The NURBS Book A4.2).
pub(crate) fn rational_derivatives(aw: &[[f64; 4]]) -> Vec<Vec3> {
    let d = aw.len() - 1;
    let w0 = aw[0][3];
    let mut ck: Vec<Vec3> = Vec::with_capacity(d + 1);
    for k in 0..=d {
        let mut v = Vec3::new(aw[k][0], aw[k][1], aw[k][2]);
        for i in 1..=k {
            v -= ck[k - i] * (binomial(k, i) * aw[i][3]);
        }
        ck.push(v / w0);
    }
    ck
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fixtures::circle;

    #[test]
    fn circle_is_exact_rational_quadratic() {
        let r = 2.5;
        let c = circle(r);
        assert!(c.is_rational());
        for i in 0..=400 {
            let u = i as f64 / 400.0;
            let d = c.derivatives(u, 2);
            // On the circle, the tangent is orthogonal to the radius vector and the curvature
            // |C' x C''| / |C'|^3 is 1/r: 1e-12 covers round-off of a few dozen operations.
            assert_near!(d[0].norm(), r, 1e-12 * r);
            assert_near!(d[0].dot(d[1]) / d[1].norm(), 0.0, 1e-12 * r);
            let kappa = d[1].cross(d[2]).norm() / d[1].norm().powi(3);
            assert_near!(kappa, 1.0 / r, 1e-11);
        }
    }

    #[test]
    fn derivatives_match_central_differences() {
        let c = circle(1.3);
        for i in 1..40 {
            let u = i as f64 / 40.0 + 0.003;
            let h = 1e-6;
            let d = c.derivatives(u, 2);
            let fd1 = (c.point(u + h) - c.point(u - h)) / (2.0 * h);
            let fd2 = (c.derivatives(u + h, 1)[1] - c.derivatives(u - h, 1)[1]) / (2.0 * h);
            assert_near!(d[1], fd1, 1e-6 * d[1].norm());
            assert_near!(d[2], fd2, 1e-5 * d[2].norm());
            assert_near!(d[0], c.point(u), 1e-14);
        }
    }

    #[test]
    fn rejects_bad_weights_and_counts() {
        let k = KnotVector::uniform(2, 3).expect("valid");
        let p = [Vec3::ZERO, Vec3::new(1., 0., 0.), Vec3::new(2., 1., 0.)];
        assert!(matches!(NurbsCurve::try_new(k.clone(), &p[..2], None), Err(NurbsError::ControlPointCount { .. })));
        assert!(matches!(
            NurbsCurve::try_new(k.clone(), &p, Some(&[1.0, 0.0, 1.0])),
            Err(NurbsError::BadWeight { index: 1, .. })
        ));
        let c = NurbsCurve::try_new(k, &p, None).expect("valid");
        assert!(!c.is_rational());
        assert_near!(c.point(0.0), p[0], 0.0);
        assert_near!(c.point(1.0), p[2], 1e-15);
        let r = c.reversed();
        assert_near!(r.point(0.25), c.point(0.75), 1e-15);
    }
}
