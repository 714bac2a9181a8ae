//! Global curve interpolation (The NURBS Book 9.2.1, A9.1).
//!
//! Given points `Q_0..Q_m`, parameters `t_k` and a knot vector with `m + 1` basis functions of
//! degree `p`, the control points `P_i` solve the `(m+1) x (m+1)` system
//! `sum_i N_{i,p}(t_k) P_i = Q_k` (eq. 9.7). Row `k` has its non-zeros in columns
//! `span(t_k) - p ..= span(t_k)`, so the matrix is banded; it is totally positive, and it is
//! nonsingular iff `N_{k,p}(t_k) != 0` for all `k` (Schoenberg-Whitney), which the averaging
//! knots of eq. 9.8 guarantee. It is factored once ([`InterpolationSolver`]) and reused for
//! every set of points with the same parameters and knots (every coordinate, every section of
//! a skinning, every column of control points).

use super::knots::{check_params, knots_for_interpolation};
use super::{parameterize, Parameterization};
use crate::basis::{basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::linalg::BandedLu;
use crate::{KnotVector, NurbsCurve, NurbsError, Vec3};

/// The factored collocation matrix `N_{i,p}(t_k)` of one parameter vector and knot vector.
#[derive(Clone, Debug)]
pub struct InterpolationSolver {
    knots: KnotVector,
    params: Vec<f64>,
    lu: BandedLu,
}

impl InterpolationSolver {
    /// Assemble and factor the collocation matrix (A9.1 steps 1-2).
    ///
    /// # Errors
    /// - [`NurbsError::ControlPointCount`] if `params.len()` differs from `knots.num_basis()`;
    /// - [`NurbsError::ParameterOutOfDomain`] for a parameter outside the knots' domain (or not
    ///   finite);
    /// - [`NurbsError::DecreasingParameters`] if the parameters decrease;
    /// - [`NurbsError::SingularSystem`] if the matrix is singular (repeated parameters, a
    ///   Schoenberg-Whitney violation) or too ill-conditioned.
    pub fn new(params: &[f64], knots: &KnotVector) -> Result<Self, NurbsError> {
        let n = knots.num_basis();
        if params.len() != n {
            return Err(NurbsError::ControlPointCount { expected: n, got: params.len() });
        }
        check_in_domain(params, knots)?;
        check_params(params, false, "interpolation parameters")?;
        let p = knots.degree();
        let u = knots.as_slice();
        let spans: Vec<usize> = params.iter().map(|&t| knots.find_span(t)).collect();
        // Row k holds columns span_k - p ..= span_k: the lower and upper bandwidths.
        let kl = spans.iter().enumerate().map(|(k, &s)| (k + p).saturating_sub(s)).max().unwrap_or(0);
        let ku = spans.iter().enumerate().map(|(k, &s)| s.saturating_sub(k)).max().unwrap_or(0);
        let mut lu = BandedLu::zeros(n, kl, ku);
        let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
        let (start, end) = knots.domain();
        for (k, (&t, &s)) in params.iter().zip(&spans).enumerate() {
            basis_funs(u, s, t, p, &mut row);
            // At the clamped ends N_0 = 1 (N_{n-1} = 1) exactly; A2.2 can round it to 1 - 1e-16,
            // and a collapsed edge (a stem section reduced to one point) must stay one point.
            if t == start || t == end {
                let one = if t == start { 0 } else { p };
                row.iter_mut().take(p + 1).enumerate().for_each(|(j, x)| *x = if j == one { 1.0 } else { 0.0 });
            }
            for (j, &v) in row.iter().enumerate().take(p + 1) {
                lu.set(k, s - p + j, v);
            }
        }
        lu.factor("curve interpolation matrix")?;
        Ok(InterpolationSolver { knots: knots.clone(), params: params.to_vec(), lu })
    }

    /// The knot vector of the interpolants.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The data parameters.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Overwrite `rhs` (one row per data point, `D` values each: coordinates, or homogeneous
    /// coordinates for a rational fit) with the solution `P` of `N P = rhs`.
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `rhs` has the wrong length,
    /// [`NurbsError::NonFiniteResult`] if the solution is not finite (non-finite data).
    pub fn solve_in_place<const D: usize>(&self, rhs: &mut [[f64; D]]) -> Result<(), NurbsError> {
        if rhs.len() != self.params.len() {
            return Err(NurbsError::ControlPointCount { expected: self.params.len(), got: rhs.len() });
        }
        self.lu.solve(rhs);
        if rhs.iter().flatten().all(|x| x.is_finite()) {
            Ok(())
        } else {
            Err(NurbsError::NonFiniteResult { what: "interpolation".into() })
        }
    }

    /// The control points of the curve through `points` (A9.1 step 3).
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `points.len()` differs from the parameter count,
    /// [`NurbsError::NonFinitePoint`] for a non-finite point.
    pub fn control_points(&self, points: &[Vec3]) -> Result<Vec<Vec3>, NurbsError> {
        if points.len() != self.params.len() {
            return Err(NurbsError::ControlPointCount { expected: self.params.len(), got: points.len() });
        }
        super::solve_points(points, |b| {
            let mut b = b.to_vec();
            self.solve_in_place(&mut b)?;
            Ok(b)
        })
    }

    /// The non-rational curve through `points` at the solver's parameters.
    ///
    /// # Errors
    /// As [`InterpolationSolver::control_points`].
    pub fn curve(&self, points: &[Vec3]) -> Result<NurbsCurve, NurbsError> {
        Ok(super::polynomial_curve(&self.knots, self.control_points(points)?))
    }
}

/// Error unless every parameter lies in the knots' domain.
pub(crate) fn check_in_domain(params: &[f64], knots: &KnotVector) -> Result<(), NurbsError> {
    let (start, end) = knots.domain();
    match params.iter().find(|&&t| !(start <= t && t <= end)) {
        Some(&value) => Err(NurbsError::ParameterOutOfDomain { value, start, end }),
        None => Ok(()),
    }
}

/// The non-rational curve of degree `degree` through `points` at `params` on `knots`
/// (The NURBS Book A9.1): `C(t_k) = Q_k`.
///
/// # Errors
/// [`NurbsError::Incompatible`] if `degree` is not the knots' degree,
/// [`NurbsError::ControlPointCount`] if the counts of points, parameters and basis functions
/// differ, and the errors of [`InterpolationSolver::new`] and
/// [`InterpolationSolver::control_points`]. The degree is never lowered here: with too few
/// points for the degree, build the knots for a lower degree.
pub fn interpolate_curve(
    points: &[Vec3],
    degree: usize,
    params: &[f64],
    knots: &KnotVector,
) -> Result<NurbsCurve, NurbsError> {
    if knots.degree() != degree {
        return Err(NurbsError::Incompatible {
            what: format!("interpolation of degree {degree} on a knot vector of degree {}", knots.degree()),
        });
    }
    if points.len() != params.len() {
        return Err(NurbsError::ControlPointCount { expected: params.len(), got: points.len() });
    }
    InterpolationSolver::new(params, knots)?.curve(points)
}

/// Interpolate `points` with parameters of `kind` and the matching knots (averaging eq. 9.8, or
/// uniform for [`Parameterization::Universal`]).
///
/// # Errors
/// Those of [`parameterize`], [`knots_for_interpolation`] (in particular
/// [`NurbsError::TooFewPoints`] if `points.len() <= degree`) and [`interpolate_curve`].
///
/// ```
/// use nurbs::fit::{interpolate_curve_auto, parameterize, Parameterization};
/// use nurbs::Vec3;
/// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(3.0, 1.5, 0.5), Vec3::new(4.0, 0.0, 1.0), Vec3::new(6.0, 0.5, 1.0)];
/// let c = interpolate_curve_auto(&pts, 3, Parameterization::Centripetal)?;
/// // The curve passes through every point at its parameter (The NURBS Book A9.1).
/// let t = parameterize(&pts, Parameterization::Centripetal, 3)?;
/// for (q, &u) in pts.iter().zip(&t) {
///     assert!(c.point(u).distance(*q) < 1e-12);
/// }
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn interpolate_curve_auto(
    points: &[Vec3],
    degree: usize,
    kind: Parameterization,
) -> Result<NurbsCurve, NurbsError> {
    if points.len() <= degree {
        return Err(NurbsError::TooFewPoints {
            what: format!("interpolation of degree {degree}"),
            needed: degree + 1,
            got: points.len(),
        });
    }
    let params = parameterize(points, kind, degree)?;
    let knots = knots_for_interpolation(&params, degree, kind)?;
    interpolate_curve(points, degree, &params, &knots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fit::averaging_knots;
    use nalgebra::DMatrix;

    /// Points on a helix-like space curve with uneven spacing.
    fn sample(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|k| {
                let s = (k as f64 / (n - 1) as f64).powf(1.3) * 3.0;
                Vec3::new(s.cos() * 2.0, s.sin(), 0.4 * s * s)
            })
            .collect()
    }

    #[test]
    fn passes_through_the_data() {
        for kind in [
            Parameterization::Uniform,
            Parameterization::ChordLength,
            Parameterization::Centripetal,
            Parameterization::Universal,
        ] {
            for p in 1..=5 {
                let q = sample(13);
                let params = parameterize(&q, kind, p).expect("valid");
                let c = interpolate_curve_auto(&q, p, kind).expect("valid");
                assert_eq!(c.degree(), p);
                for (t, qk) in params.iter().zip(&q) {
                    // The solve is backward stable on a well-conditioned collocation matrix:
                    // residuals are a few ulps of the coordinates (size ~4), far below 1e-10.
                    assert_near!(c.point(*t), *qk, 1e-10 * 4.0, "{kind} p {p}");
                }
            }
        }
    }

    #[test]
    fn reproduces_a_spline_of_the_same_degree() {
        // Data sampled from a known cubic B-spline at parameters whose averaging knots are its
        // own knots: interpolation must return that spline's control points.
        let p = 3;
        let t = [0.0, 0.1, 0.25, 0.4, 0.55, 0.7, 0.9, 1.0];
        let knots = averaging_knots(&t, p).expect("valid");
        let cp: Vec<Vec3> =
            (0..8).map(|i| Vec3::new(i as f64, ((i * i) % 5) as f64 - 2.0, (i as f64 * 0.7).sin())).collect();
        let truth = NurbsCurve::try_new(knots.clone(), &cp, None).expect("valid");
        let q: Vec<Vec3> = t.iter().map(|&u| truth.point(u)).collect();
        let c = interpolate_curve(&q, p, &t, &knots).expect("valid");
        for (a, b) in c.control_points().iter().zip(&cp) {
            // Condition number of this collocation matrix is O(10): error a few ulps of 7.
            assert_near!(*a, *b, 1e-12);
        }
        assert!(!c.is_rational());
    }

    #[test]
    fn banded_solution_equals_dense_solution() {
        let q = sample(20);
        let t = parameterize(&q, Parameterization::Centripetal, 4).expect("valid");
        let kv = averaging_knots(&t, 4).expect("valid");
        let c = interpolate_curve(&q, 4, &t, &kv).expect("valid");
        let n = q.len();
        let mut a = DMatrix::<f64>::zeros(n, n);
        for (k, &tk) in t.iter().enumerate() {
            let s = kv.find_span(tk);
            let mut row = [0.0; MAX_DEGREE + 1];
            basis_funs(kv.as_slice(), s, tk, 4, &mut row);
            for j in 0..=4 {
                a[(k, s - 4 + j)] = row[j];
            }
        }
        let b = DMatrix::from_fn(n, 3, |i, j| q[i][j]);
        let x = a.lu().solve(&b).expect("nonsingular");
        for i in 0..n {
            // Both solvers are backward stable on a matrix of modest condition: 1e-11 is ~1e4 ulps.
            assert_near!(c.control_point(i), Vec3::new(x[(i, 0)], x[(i, 1)], x[(i, 2)]), 1e-11);
        }
    }

    #[test]
    fn one_factorization_serves_many_right_hand_sides() {
        let q = sample(9);
        let t = parameterize(&q, Parameterization::ChordLength, 3).expect("valid");
        let kv = averaging_knots(&t, 3).expect("valid");
        let solver = InterpolationSolver::new(&t, &kv).expect("valid");
        for shift in [Vec3::ZERO, Vec3::new(1.0, -2.0, 0.5)] {
            let moved: Vec<Vec3> = q.iter().map(|&x| x + shift).collect();
            let c = solver.curve(&moved).expect("valid");
            for (tk, qk) in t.iter().zip(&moved) {
                assert_near!(c.point(*tk), *qk, 1e-12 * 10.0);
            }
        }
    }

    #[test]
    fn rejects_bad_input() {
        let q = sample(6);
        let t = parameterize(&q, Parameterization::ChordLength, 3).expect("valid");
        let kv = averaging_knots(&t, 3).expect("valid");
        assert!(matches!(interpolate_curve(&q, 2, &t, &kv), Err(NurbsError::Incompatible { .. })));
        assert!(matches!(interpolate_curve(&q[..5], 3, &t, &kv), Err(NurbsError::ControlPointCount { .. })));
        assert!(matches!(
            interpolate_curve_auto(&q[..3], 3, Parameterization::Centripetal),
            Err(NurbsError::TooFewPoints { .. })
        ));
        // Two equal parameters make two equal rows: singular.
        let mut tt = t.clone();
        tt[2] = tt[1];
        assert!(matches!(InterpolationSolver::new(&tt, &kv), Err(NurbsError::SingularSystem { .. })));
        tt[2] = -0.5;
        assert!(matches!(InterpolationSolver::new(&tt, &kv), Err(NurbsError::ParameterOutOfDomain { .. })));
        let mut bad = q.clone();
        bad[3].y = f64::INFINITY;
        assert!(matches!(interpolate_curve(&bad, 3, &t, &kv), Err(NurbsError::NonFinitePoint { index: 3 })));
    }
}
