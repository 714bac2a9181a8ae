//! Least-squares curve approximation with interpolated end points (The NURBS Book 9.4.1).
//!
//! Data `Q_0..Q_m` at parameters `t_0..t_m`, `n + 1 <= m + 1` control points of degree `p` on a
//! knot vector with `u_p = t_0`, `u_{n+1} = t_m`. The ends are fixed, `P_0 = Q_0`, `P_n = Q_m`
//! (eq. 9.63); the interior `P_1..P_{n-1}` minimize `sum_{k=1}^{m-1} |Q_k - C(t_k)|^2`
//! (eq. 9.64). With `R_k = Q_k - N_{0,p}(t_k) Q_0 - N_{n,p}(t_k) Q_m` (eq. 9.65) and the
//! `(m-1) x (n-1)` matrix `N_{ki} = N_{i,p}(t_k)`, the minimizer solves the normal equations
//! `(N^T N) P = R`, `R_i = sum_{k=1}^{m-1} N_{i,p}(t_k) R_k` (eq. 9.66-9.67).
//! `N^T N` is symmetric, of half-bandwidth `p`, and positive definite under the
//! Schoenberg-Whitney condition; it is factored once by banded Cholesky
//! ([`LeastSquaresSolver`]) and reused for every set of points with the same parameters and knots.

use super::interp::check_in_domain;
use super::knots::{check_ctrl_count, check_params, knots_for_approximation, schoenberg_whitney};
use super::{parameterize, Parameterization};
use crate::basis::{basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::linalg::BandedCholesky;
use crate::{KnotVector, NurbsCurve, NurbsError, Vec3};

/// The factored normal equations of one parameter vector and knot vector.
#[derive(Clone, Debug)]
pub struct LeastSquaresSolver {
    knots: KnotVector,
    params: Vec<f64>,
    /// `span(t_k)` for every data point.
    spans: Vec<usize>,
    /// `N_{span-p..=span, p}(t_k)`, `p + 1` values per data point.
    basis: Vec<f64>,
    /// `None` when there are no interior control points (`n + 1 = 2`).
    chol: Option<BandedCholesky>,
    /// Smoothing: `(i, λ G_{i,0}, λ G_{i,n})` for the interior unknowns coupled to the fixed
    /// end points by the energy term (empty without smoothing).
    ends: Vec<(usize, f64, f64)>,
}

impl LeastSquaresSolver {
    /// Assemble and factor `N^T N` (eq. 9.66).
    ///
    /// # Errors
    /// - [`NurbsError::BadControlPointCount`] unless `degree + 1 <= knots.num_basis() <= params.len()`;
    /// - [`NurbsError::ParameterOutOfDomain`], [`NurbsError::DecreasingParameters`];
    /// - [`NurbsError::TooManyControlPoints`] if the parameters have fewer distinct values than
    ///   `knots.num_basis()` (repeated points: the normal equations would be singular);
    /// - [`NurbsError::Incompatible`] if the first and last parameters are not the domain ends
    ///   (the end points are interpolated there);
    /// - [`NurbsError::SingularSystem`] if the Schoenberg-Whitney condition fails or the normal
    ///   matrix is too ill-conditioned.
    pub fn new(params: &[f64], knots: &KnotVector) -> Result<Self, NurbsError> {
        Self::smoothing(params, knots, 0.0)
    }

    /// As [`LeastSquaresSolver::new`], with a smoothing term: the interior control points
    /// minimize `sum_k |Q_k - C(t_k)|^2 + λ E(C)`, `E = ∫ |C^(r)|^2 dt` the curve's energy of
    /// order `r = min(p, 2)` (bending energy for `p >= 2`; a smoothing spline on the B-spline
    /// basis, Reinsch 1967 / de Boor's `smooth`), so the normal equations become
    /// `(N^T N + λ G_ff) P_f = R - λ G_fx P_x` with `G_ij = ∫ N_i^(r) N_j^(r)` (banded like
    /// `N^T N`) and `P_x` the interpolated ends. `λ = 0` is [`LeastSquaresSolver::new`]
    /// exactly. `λ` is absolute (squared length per unit energy): callers scale it by the knots'
    /// Gram matrix.
    ///
    /// # Errors
    /// As [`LeastSquaresSolver::new`], and [`NurbsError::Incompatible`] for a negative or
    /// non-finite `lambda`.
    pub fn smoothing(params: &[f64], knots: &KnotVector, lambda: f64) -> Result<Self, NurbsError> {
        if !(lambda >= 0.0 && lambda.is_finite()) {
            return Err(NurbsError::Incompatible {
                what: format!("smoothing weight {lambda} (expected a finite number >= 0)"),
            });
        }
        let gram = if lambda > 0.0 { Some(super::constrained::EnergyGram::new(knots)) } else { None };
        let p = knots.degree();
        let n_ctrl = knots.num_basis();
        let count = params.len();
        check_ctrl_count(n_ctrl, count, p, "least-squares approximation")?;
        check_in_domain(params, knots)?;
        check_params(params, false, "approximation parameters")?;
        check_distinct(params, n_ctrl, "least-squares approximation")?;
        let (start, end) = knots.domain();
        if params[0] != start || params[count - 1] != end {
            return Err(NurbsError::Incompatible {
                what: format!(
                    "least squares with fixed ends needs the first and last parameters ({}, {}) at the domain ends ({start}, {end})",
                    params[0],
                    params[count - 1]
                ),
            });
        }
        schoenberg_whitney(params, knots, "least-squares approximation")?;
        let u = knots.as_slice();
        let mut spans = Vec::with_capacity(count);
        let mut basis = Vec::with_capacity(count * (p + 1));
        let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
        for &t in params {
            let s = knots.find_span(t);
            basis_funs(u, s, t, p, &mut row);
            spans.push(s);
            basis.extend_from_slice(&row[..=p]);
        }
        let unknowns = n_ctrl - 2;
        let chol = if unknowns == 0 {
            None
        } else {
            let mut a = BandedCholesky::zeros(unknowns, p.min(unknowns - 1));
            for k in 1..count - 1 {
                let (s, nk) = (spans[k], &basis[k * (p + 1)..(k + 1) * (p + 1)]);
                for a_ in 0..=p {
                    let i = s - p + a_;
                    if i == 0 || i == n_ctrl - 1 {
                        continue;
                    }
                    for b_ in 0..=a_ {
                        let j = s - p + b_;
                        if j == 0 {
                            continue;
                        }
                        a.add(i - 1, j - 1, nk[a_] * nk[b_]);
                    }
                }
            }
            if let Some(g) = &gram {
                for i in 1..n_ctrl - 1 {
                    for j in i.saturating_sub(p).max(1)..=i {
                        a.add(i - 1, j - 1, lambda * g.get(i, j));
                    }
                }
            }
            a.factor("least-squares normal equations")?;
            Some(a)
        };
        let ends = match &gram {
            Some(g) => (1..n_ctrl - 1)
                .map(|i| (i, lambda * g.get(i, 0), lambda * g.get(i, n_ctrl - 1)))
                .filter(|&(_, a, b)| a != 0.0 || b != 0.0)
                .collect(),
            None => Vec::new(),
        };
        Ok(LeastSquaresSolver { knots: knots.clone(), params: params.to_vec(), spans, basis, chol, ends })
    }

    /// The knot vector of the approximants.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The data parameters.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// Control points of the least-squares curve through `points[0]` and `points[m]` (eq. 9.63
    /// to 9.67), `D` values per point (coordinates, or homogeneous coordinates).
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `points.len()` differs from the parameter count,
    /// [`NurbsError::NonFiniteResult`] if the result is not finite.
    pub fn solve<const D: usize>(&self, points: &[[f64; D]]) -> Result<Vec<[f64; D]>, NurbsError> {
        let count = self.params.len();
        if points.len() != count {
            return Err(NurbsError::ControlPointCount { expected: count, got: points.len() });
        }
        let p = self.knots.degree();
        let n_ctrl = self.knots.num_basis();
        let (q0, qm) = (points[0], points[count - 1]);
        let mut out = vec![[0.0; D]; n_ctrl];
        out[0] = q0;
        out[n_ctrl - 1] = qm;
        if let Some(chol) = &self.chol {
            let rhs = &mut out[1..n_ctrl - 1];
            let rows = self.spans.iter().zip(self.basis.chunks_exact(p + 1)).zip(points);
            for ((&s, nk), &q) in rows.skip(1).take(count - 2) {
                // R_k = Q_k - N_0(t_k) Q_0 - N_n(t_k) Q_m (only when those functions are in the row).
                let mut r = q;
                if s == p {
                    for (rc, qc) in r.iter_mut().zip(q0) {
                        *rc -= nk[0] * qc;
                    }
                }
                if s == n_ctrl - 1 {
                    for (rc, qc) in r.iter_mut().zip(qm) {
                        *rc -= nk[p] * qc;
                    }
                }
                for (a_, &na) in nk.iter().enumerate() {
                    let i = s - p + a_;
                    if i == 0 || i == n_ctrl - 1 {
                        continue;
                    }
                    for (oc, rc) in rhs[i - 1].iter_mut().zip(r) {
                        *oc += na * rc;
                    }
                }
            }
            for &(i, g0, gn) in &self.ends {
                for ((oc, a), b) in rhs[i - 1].iter_mut().zip(q0).zip(qm) {
                    *oc -= g0 * a + gn * b;
                }
            }
            chol.solve(rhs);
        }
        if out.iter().flatten().all(|x| x.is_finite()) {
            Ok(out)
        } else {
            Err(NurbsError::NonFiniteResult { what: "least-squares approximation".into() })
        }
    }

    /// The control points of the approximation of `points`.
    ///
    /// # Errors
    /// [`NurbsError::NonFinitePoint`] for a non-finite point, else as [`LeastSquaresSolver::solve`].
    pub fn control_points(&self, points: &[Vec3]) -> Result<Vec<Vec3>, NurbsError> {
        super::solve_points(points, |b| self.solve(b))
    }

    /// The non-rational least-squares curve of `points`.
    ///
    /// # Errors
    /// As [`LeastSquaresSolver::control_points`].
    pub fn curve(&self, points: &[Vec3]) -> Result<NurbsCurve, NurbsError> {
        Ok(super::polynomial_curve(&self.knots, self.control_points(points)?))
    }
}

/// Refuse `n_ctrl` control points for non-decreasing `params` with fewer distinct values: each
/// distinct value gives one independent row of the collocation matrix `N_{i,p}(t_k)`, so its
/// rank, and that of `N^T N`, is at most their count (The NURBS Book 9.4.1 needs rank `n + 1`).
///
/// # Errors
/// [`NurbsError::TooManyControlPoints`] with the point and distinct-parameter counts.
pub(crate) fn check_distinct(params: &[f64], n_ctrl: usize, what: &str) -> Result<(), NurbsError> {
    let distinct = 1 + params.windows(2).filter(|w| w[1] != w[0]).count();
    if n_ctrl > distinct {
        return Err(NurbsError::TooManyControlPoints {
            what: what.to_string(),
            count: n_ctrl,
            points: params.len(),
            distinct,
            max: distinct,
        });
    }
    Ok(())
}

/// The non-rational curve of degree `degree` with `n_ctrl` control points on `knots` that
/// passes through the first and last points and fits the others in the least-squares sense
/// (The NURBS Book 9.4.1). With `n_ctrl == points.len()` it is the interpolant on `knots`.
///
/// # Errors
/// [`NurbsError::BadControlPointCount`] unless `degree + 1 <= n_ctrl <= points.len()`,
/// [`NurbsError::Incompatible`] if `degree` is not the knots' degree,
/// [`NurbsError::ControlPointCount`] if `knots` does not carry `n_ctrl` basis functions or
/// `params` and `points` differ in length, and the errors of [`LeastSquaresSolver::new`]
/// and [`LeastSquaresSolver::control_points`].
pub fn approximate_curve(
    points: &[Vec3],
    degree: usize,
    n_ctrl: usize,
    params: &[f64],
    knots: &KnotVector,
) -> Result<NurbsCurve, NurbsError> {
    check_ctrl_count(n_ctrl, points.len(), degree, "least-squares approximation")?;
    if knots.degree() != degree {
        return Err(NurbsError::Incompatible {
            what: format!("approximation of degree {degree} on a knot vector of degree {}", knots.degree()),
        });
    }
    if knots.num_basis() != n_ctrl {
        return Err(NurbsError::ControlPointCount { expected: n_ctrl, got: knots.num_basis() });
    }
    if points.len() != params.len() {
        return Err(NurbsError::ControlPointCount { expected: params.len(), got: points.len() });
    }
    LeastSquaresSolver::new(params, knots)?.curve(points)
}

/// Approximate `points` by `n_ctrl` control points with parameters of `kind` and the matching
/// knots ([`knots_for_approximation`]: symmetric eq. 9.68-9.69 placement, or uniform for
/// [`Parameterization::Universal`]).
///
/// # Errors
/// Those of [`parameterize`], [`knots_for_approximation`] and [`approximate_curve`].
///
/// ```
/// use nurbs::fit::{approximate_curve_auto, Parameterization};
/// use nurbs::Vec3;
/// // 20 points of the parabola y = x^2 at equal steps of x: with uniform parameters t = x,
/// // x(t) and y(t) are polynomials a cubic of 4 control points holds exactly, and least
/// // squares (The NURBS Book 9.4.1) reproduces them and keeps the end points.
/// let pts: Vec<Vec3> = (0..20).map(|i| i as f64 / 19.0).map(|x| Vec3::new(x, x * x, 0.0)).collect();
/// let c = approximate_curve_auto(&pts, 3, 4, Parameterization::Uniform)?;
/// assert_eq!(c.num_control_points(), 4);
/// assert!(c.point(0.0).distance(pts[0]) < 1e-14 && c.point(1.0).distance(pts[19]) < 1e-12);
/// for i in 0..=10 {
///     let p = c.point(i as f64 / 10.0);
///     assert!((p.y - p.x * p.x).abs() < 1e-12);
/// }
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn approximate_curve_auto(
    points: &[Vec3],
    degree: usize,
    n_ctrl: usize,
    kind: Parameterization,
) -> Result<NurbsCurve, NurbsError> {
    check_ctrl_count(n_ctrl, points.len(), degree, "least-squares approximation")?;
    let params = parameterize(points, kind, degree)?;
    let knots = knots_for_approximation(&params, n_ctrl, degree, kind)?;
    approximate_curve(points, degree, n_ctrl, &params, &knots)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fit::{approximation_knots, interpolate_curve};

    fn wave(n: usize) -> Vec<Vec3> {
        (0..n)
            .map(|k| {
                let s = k as f64 / (n - 1) as f64;
                Vec3::new(4.0 * s, (3.0 * s).sin(), 0.5 * (5.0 * s).cos())
            })
            .collect()
    }

    fn max_error(c: &NurbsCurve, q: &[Vec3], t: &[f64]) -> f64 {
        q.iter().zip(t).map(|(qk, &tk)| c.point(tk).distance(*qk)).fold(0.0, f64::max)
    }

    #[test]
    fn full_count_equals_interpolation() {
        let q = wave(12);
        let t = parameterize(&q, Parameterization::Centripetal, 3).expect("valid");
        let kv = approximation_knots(&t, q.len(), 3).expect("valid");
        let a = approximate_curve(&q, 3, q.len(), &t, &kv).expect("valid");
        let b = interpolate_curve(&q, 3, &t, &kv).expect("valid");
        for (x, y) in a.control_points().iter().zip(b.control_points()) {
            // Normal equations square the condition number of a well-conditioned matrix
            // (cond ~ 10): 1e-11 allows ~1e5 ulps.
            assert_near!(*x, y, 1e-11);
        }
        assert!(max_error(&a, &q, &t) < 1e-11);
    }

    #[test]
    fn ends_interpolated_and_residual_orthogonal() {
        let q = wave(40);
        let t = parameterize(&q, Parameterization::ChordLength, 3).expect("valid");
        for n_ctrl in [4, 5, 9, 17] {
            let kv = approximation_knots(&t, n_ctrl, 3).expect("valid");
            let c = approximate_curve(&q, 3, n_ctrl, &t, &kv).expect("valid");
            // C(t_0) = P_0 = Q_0 exactly: the basis at the clamped end is (1, 0, ..., 0).
            assert_near!(c.point(t[0]), q[0], 0.0);
            assert_near!(c.point(1.0), q[39], 1e-15);
            // Optimality (eq. 9.66): the residual is orthogonal to every free basis function,
            // sum_k N_i(t_k) (C(t_k) - Q_k) = 0 for i = 1..n-1, up to round-off of ~40 terms.
            for i in 1..n_ctrl - 1 {
                let mut g = Vec3::ZERO;
                for (qk, &tk) in q.iter().zip(&t).skip(1).take(38) {
                    let s = kv.find_span(tk);
                    let mut row = [0.0; MAX_DEGREE + 1];
                    basis_funs(kv.as_slice(), s, tk, 3, &mut row);
                    if let Some(j) = (i + 3).checked_sub(s).filter(|&j| j <= 3) {
                        g += (c.point(tk) - *qk) * row[j];
                    }
                }
                assert!(g.norm() < 1e-12, "n {n_ctrl} i {i} gradient {g:?}");
            }
        }
    }

    #[test]
    fn error_decreases_with_more_control_points() {
        let q = wave(201);
        let t = parameterize(&q, Parameterization::ChordLength, 3).expect("valid");
        let mut prev = f64::INFINITY;
        for n_ctrl in [5, 8, 12, 20, 40] {
            let kv = approximation_knots(&t, n_ctrl, 3).expect("valid");
            let e = max_error(&approximate_curve(&q, 3, n_ctrl, &t, &kv).expect("valid"), &q, &t);
            assert!(e < prev, "n {n_ctrl}: {e} not below {prev}");
            prev = e;
        }
        // A cubic spline with 36 spans approximates this smooth curve to O(h^4): well below 1e-5.
        assert!(prev < 1e-5, "error {prev}");
    }

    #[test]
    fn reproduces_a_spline_on_its_own_knots() {
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.3, 0.5, 0.8, 1., 1., 1., 1.]).expect("valid");
        let cp: Vec<Vec3> = (0..7).map(|i| Vec3::new(i as f64, (i as f64).sqrt(), ((i * 3) % 4) as f64)).collect();
        let truth = NurbsCurve::try_new(kv.clone(), &cp, None).expect("valid");
        let t: Vec<f64> = (0..30).map(|k| (k as f64 / 29.0).powf(1.2)).collect();
        let q: Vec<Vec3> = t.iter().map(|&u| truth.point(u)).collect();
        let c = approximate_curve(&q, 3, 7, &t, &kv).expect("valid");
        for (a, b) in c.control_points().iter().zip(&cp) {
            // Zero residual: the exact solution, up to round-off amplified by cond(N^T N) ~ 1e2.
            assert_near!(*a, *b, 1e-12);
        }
    }

    #[test]
    fn repeated_parameters_cap_the_control_points() {
        let q = wave(10);
        // Points 3 to 5 at one parameter (as repeated points would be): 8 distinct values, so
        // at most 8 control points, whatever the knots.
        let mut t = parameterize(&q, Parameterization::Uniform, 3).expect("valid");
        t[4] = t[3];
        t[5] = t[3];
        let kv = KnotVector::uniform(3, 9).expect("valid");
        let e = approximate_curve(&q, 3, 9, &t, &kv).expect_err("9 > 8 distinct parameters");
        assert_eq!(
            e,
            NurbsError::TooManyControlPoints {
                what: "least-squares approximation".into(),
                count: 9,
                points: 10,
                distinct: 8,
                max: 8
            }
        );
        assert!(e.to_string().contains("the 10 points have only 8 distinct parameters"), "{e}");
        // 8 is not refused for that reason (it may still fail Schoenberg-Whitney on these knots).
        let kv = KnotVector::uniform(3, 8).expect("valid");
        assert!(!matches!(approximate_curve(&q, 3, 8, &t, &kv), Err(NurbsError::TooManyControlPoints { .. })));
    }

    #[test]
    fn ill_conditioned_normal_equations_are_reported_not_solved() {
        // Cubic, 5 control points on [0, 0.5, 1]: the three free ones see only three data a
        // millionth apart. Schoenberg-Whitney holds (each has a parameter inside its support),
        // so the matrix is nonsingular in exact arithmetic, but its rows agree to ~1e-6 and the
        // third pivot is ~(1e-6)^4 of its diagonal: the control points would be noise.
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.]).expect("valid");
        let t = [0.0, 0.3, 0.3 + 1e-6, 0.3 + 2e-6, 1.0];
        assert!(schoenberg_whitney(&t, &kv, "t").is_ok());
        let q = wave(5);
        match approximate_curve(&q, 3, 5, &t, &kv) {
            Err(NurbsError::SingularSystem { what }) => {
                assert!(what.starts_with("least-squares normal equations: pivot"), "{what}")
            }
            other => panic!("expected an ill-conditioned system, got {other:?}"),
        }
        // The same data a tenth apart: well conditioned, solved.
        let t = [0.0, 0.2, 0.5, 0.8, 1.0];
        assert!(approximate_curve(&q, 3, 5, &t, &kv).is_ok());
    }

    #[test]
    fn rejects_bad_counts_and_singular_systems() {
        let q = wave(10);
        let t = parameterize(&q, Parameterization::Uniform, 3).expect("valid");
        assert!(matches!(
            approximate_curve_auto(&q, 3, 11, Parameterization::Uniform),
            Err(NurbsError::BadControlPointCount { count: 11, min: 4, max: 10, .. })
        ));
        assert!(matches!(
            approximate_curve_auto(&q, 3, 3, Parameterization::Uniform),
            Err(NurbsError::BadControlPointCount { .. })
        ));
        // All interior data in the first span: the later basis functions see no data.
        let kv = KnotVector::uniform(3, 8).expect("valid");
        let mut clustered: Vec<f64> = (0..10).map(|k| k as f64 * 0.01).collect();
        clustered[9] = 1.0;
        assert!(matches!(approximate_curve(&q, 3, 8, &clustered, &kv), Err(NurbsError::SingularSystem { .. })));
        // Parameters not reaching the domain end: the ends cannot be interpolated there.
        let mut short = t.clone();
        short[9] = 0.95;
        let kv = approximation_knots(&t, 6, 3).expect("valid");
        assert!(matches!(approximate_curve(&q, 3, 6, &short, &kv), Err(NurbsError::Incompatible { .. })));
        // A line (degree 1, two control points): the chord from Q_0 to Q_m.
        let line = approximate_curve_auto(&q, 1, 2, Parameterization::Uniform).expect("valid");
        assert_eq!(line.control_points(), vec![q[0], q[9]]);
    }
}
