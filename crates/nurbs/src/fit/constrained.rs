//! Fair constrained interpolation: the curve on a given knot vector with `N` control points
//! that passes through `n <= N` points and bends least.
//!
//! With more control points than data points, interpolation leaves `N - n` degrees of freedom.
//! They are fixed by minimizing a quadratic energy, the classical smoothing criterion of
//! variational curve design (Holladay 1957; de Boor, *A Practical Guide to Splines*, XIV;
//! The NURBS Book 9.4.1 fits with constraints by the same Lagrange technique, eq. 9.75):
//!
//! `min E(P) = ∫ |C^(r)(t)|^2 dt = sum_{i,j} G_ij P_i . P_j`  subject to  `A P = Q`,
//!
//! with `C(t) = sum_i N_{i,p}(t) P_i`, the Gram matrix `G_ij = ∫ N_i^(r)(t) N_j^(r)(t) dt` and
//! the `n x N` collocation matrix `A_ki = N_{i,p}(t_k)`. The order is `r = 2` (bending energy:
//! with the knots at the data parameters the minimizer over all `C^2` functions is the natural
//! cubic spline) for degree `p >= 2`, and `r = 1` (membrane energy, whose minimizer is the
//! polyline) for `p = 1`, where second derivatives vanish span by span. `G` is banded
//! (half-bandwidth `p`): each of its entries is a sum over knot spans of integrals of
//! polynomials of degree `2(p - r)`, computed exactly by `p - r + 1`-point Gauss-Legendre
//! quadrature per span.
//!
//! The optimality (KKT) conditions are `G P + A^T λ = 0`, `A P = Q`. `G` is singular (it
//! vanishes on the polynomials of degree `< r`), so it cannot be eliminated directly; since
//! `A P = Q` holds at the solution, adding `A^T A P = A^T Q` to the first row does not change
//! the solution (the augmented-Lagrangian form, Nocedal and Wright, *Numerical Optimization*,
//! 17.3 and 16.1):
//!
//! `H P + A^T μ' = A^T Q`,  `H = G / g + A^T A`,
//!
//! where `g` is the largest diagonal entry of `G` (scaling the energy changes neither the
//! minimizer nor `A`, and balances the two terms). `H` is banded, symmetric, and positive
//! definite exactly when no non-zero spline has zero energy and vanishes at every parameter
//! (`null G ∩ null A = {0}`): for `r = 2` whenever there are two distinct parameters and no
//! interior knot of multiplicity `p` (then `null G` is the straight lines), for `r = 1`
//! always. Writing `P = H^{-1} A^T μ` with `μ = Q - μ'` and substituting in `A P = Q` gives the
//! Schur complement system
//!
//! `S μ = Q`,  `S = A H^{-1} A^T`  (`n x n`),  `P = W μ`,  `W = H^{-1} A^T`,
//!
//! and `S` is positive definite exactly when `A` has full row rank, which for distinct
//! increasing parameters holds iff each data point can be given a basis function of its own,
//! `i_0 < i_1 < ... < i_{n-1}` with `N_{i_k,p}(t_k) != 0` (the Schoenberg-Whitney condition for
//! the rows; Karlin, *Total Positivity*, 1968, ch. 10). Both factorizations are Cholesky with a
//! relative pivot check, so a failure says which condition failed. `H` inherits the condition
//! of the energy (about `(N / n)^4`), but it only enters through `W`, and `S` is computed as
//! `A W` from that same `W`: the constraint residual `A P - Q` depends on the conditioning of
//! `S` alone, which is that of `A` (its eigenvalues lie between those of `A A^T / ||H||` and
//! 1). The cost is `O(N p n + n^3)`, and the factorization serves every coordinate.
//!
//! For `n = N` (a square, nonsingular `A`) the solution is `A^{-1} Q`: ordinary interpolation.

use super::interp::check_in_domain;
use super::knots::check_params;
use crate::basis::{basis_funs, ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::linalg::BandedCholesky;
use crate::{GaussLegendre, KnotVector, NurbsCurve, NurbsError, Vec3};

/// The order `r` of the energy `∫ |C^(r)|^2` minimized for degree `p`: 2 (bending) for
/// `p >= 2`, 1 (stretching) for `p = 1`.
pub fn energy_order(degree: usize) -> usize {
    degree.clamp(1, 2)
}

/// The Gram matrix `G_ij = ∫ N_i^(r) N_j^(r) dt` of one knot vector, lower band by rows
/// (half-bandwidth `p`), and the order `r`.
#[derive(Clone, Debug)]
pub(crate) struct EnergyGram {
    n: usize,
    p: usize,
    order: usize,
    /// `band[i * (p + 1) + p - (i - j)] = G_ij` for `i - p <= j <= i`.
    band: Vec<f64>,
}

impl EnergyGram {
    /// Assemble `G` for the energy of order [`energy_order`] by Gauss-Legendre quadrature with
    /// `p - r + 1` nodes per non-empty knot span (exact: the integrand is a polynomial of
    /// degree `2(p - r)` there).
    pub(crate) fn new(knots: &KnotVector) -> Self {
        let p = knots.degree();
        let order = energy_order(p);
        let n = knots.num_basis();
        let u = knots.as_slice();
        let gl = GaussLegendre::new(p - order + 1);
        let (nodes, weights) = (gl.nodes(), gl.weights());
        let mut band = vec![0.0; n * (p + 1)];
        let mut ders: [BasisRow; 3] = [[0.0; MAX_DEGREE + 1]; 3];
        for s in p..n {
            let (a, b) = (u[s], u[s + 1]);
            if b <= a {
                continue;
            }
            let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
            for (&x, &w) in nodes.iter().zip(weights) {
                ders_basis_funs(u, s, mid + half * x, p, order, &mut ders);
                let d = &ders[order];
                for ia in 0..=p {
                    for ib in 0..=ia {
                        // Functions s - p + ia >= s - p + ib: row i = s - p + ia, offset ia - ib.
                        band[(s - p + ia) * (p + 1) + p - (ia - ib)] += w * half * d[ia] * d[ib];
                    }
                }
            }
        }
        EnergyGram { n, p, order, band }
    }

    /// `G_ij` for `|i - j| <= p` (0 outside the band).
    pub(crate) fn get(&self, i: usize, j: usize) -> f64 {
        let (i, j) = if i >= j { (i, j) } else { (j, i) };
        if i - j > self.p {
            0.0
        } else {
            self.band[i * (self.p + 1) + self.p - (i - j)]
        }
    }

    /// `E = sum_{i,j} G_ij P_i . P_j` of the non-rational curve with control points `cp`.
    pub(crate) fn energy(&self, cp: &[Vec3]) -> f64 {
        let mut e = 0.0;
        for i in 0..self.n {
            for j in i.saturating_sub(self.p)..=i {
                let term = self.get(i, j) * cp[i].dot(cp[j]);
                e += if i == j { term } else { 2.0 * term };
            }
        }
        e
    }

    /// Number of basis functions (rows of `G`).
    pub(crate) fn len(&self) -> usize {
        self.n
    }

    /// The largest diagonal entry of `G`.
    pub(crate) fn max_diagonal(&self) -> f64 {
        (0..self.n).map(|i| self.get(i, i)).fold(0.0, f64::max)
    }
}

/// The factored fair-interpolation system of one parameter vector and knot vector: solves for
/// the control points of the least-energy curve through any points at those parameters
/// (see the module documentation for the mathematics).
#[derive(Clone, Debug)]
pub struct FairInterpolationSolver {
    knots: KnotVector,
    params: Vec<f64>,
    /// `W = H^{-1} A^T`, `N x n` row-major.
    w: Vec<f64>,
    /// Cholesky factor of `S = A W`.
    s: BandedCholesky,
    /// `g`, the largest diagonal entry of the Gram matrix (`H = G / g + A^T A`).
    energy_scale: f64,
}

impl FairInterpolationSolver {
    /// Assemble and factor the system for the data parameters `params` on `knots`.
    ///
    /// # Errors
    /// - [`NurbsError::TooFewPoints`] for no parameter;
    /// - [`NurbsError::Incompatible`] for more parameters than control points (`n > N`: the
    ///   curve cannot interpolate in general; use least squares);
    /// - [`NurbsError::ParameterOutOfDomain`] for a parameter outside the knots' domain or not
    ///   finite, [`NurbsError::DecreasingParameters`] unless they strictly increase;
    /// - [`NurbsError::SingularSystem`] if the interpolation conditions are dependent (no
    ///   distinct basis function for every parameter, see [`row_schoenberg_whitney`]), or the
    ///   energy leaves the curve undetermined (one parameter for a bending energy, or knots of
    ///   multiplicity `p` between parameters), or a system is too ill-conditioned.
    pub fn new(params: &[f64], knots: &KnotVector) -> Result<Self, NurbsError> {
        Self::with_gram(params, knots, &EnergyGram::new(knots))
    }

    /// [`FairInterpolationSolver::new`] with the Gram matrix of `knots` already assembled (it
    /// depends on the knots only, so sections sharing knots share it).
    pub(crate) fn with_gram(params: &[f64], knots: &KnotVector, gram: &EnergyGram) -> Result<Self, NurbsError> {
        let big_n = knots.num_basis();
        let n = params.len();
        debug_assert_eq!(gram.n, big_n, "Gram matrix of another knot vector");
        if n == 0 {
            return Err(NurbsError::TooFewPoints { what: "fair interpolation".into(), needed: 1, got: 0 });
        }
        if n > big_n {
            return Err(NurbsError::Incompatible {
                what: format!(
                    "fair interpolation of {n} points needs at least {n} control points; the knots carry {big_n}"
                ),
            });
        }
        check_in_domain(params, knots)?;
        check_params(params, true, "fair interpolation parameters")?;
        row_schoenberg_whitney(params, knots, "fair interpolation")?;
        let p = knots.degree();
        let u = knots.as_slice();
        // Rows of A: span and the p + 1 non-zero basis values.
        let mut spans = Vec::with_capacity(n);
        let mut rows = Vec::with_capacity(n * (p + 1));
        let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
        for &t in params {
            let s = knots.find_span(t);
            basis_funs(u, s, t, p, &mut row);
            spans.push(s);
            rows.extend_from_slice(&row[..=p]);
        }
        // H = G / g + A^T A, banded with half-bandwidth p.
        let g = gram.max_diagonal();
        if !(g > 0.0 && g.is_finite()) {
            return Err(NurbsError::SingularSystem { what: format!("fair interpolation: energy Gram matrix ({g:e})") });
        }
        let mut h = BandedCholesky::zeros(big_n, p);
        for i in 0..big_n {
            for j in i.saturating_sub(p)..=i {
                h.add(i, j, gram.get(i, j) / g);
            }
        }
        for (&s, a) in spans.iter().zip(rows.chunks_exact(p + 1)) {
            for ia in 0..=p {
                for ib in 0..=ia {
                    h.add(s - p + ia, s - p + ib, a[ia] * a[ib]);
                }
            }
        }
        let order = gram.order;
        h.factor("fair interpolation").map_err(|e| match e {
            NurbsError::SingularSystem { what } => NurbsError::SingularSystem {
                what: format!(
                    "{what}: the energy of order {order} does not determine the curve through {n} points \
                     (a curve of zero energy vanishes at every parameter)"
                ),
            },
            other => other,
        })?;
        // W = H^{-1} A^T, four columns (data points) per banded solve.
        let mut w = vec![0.0; big_n * n];
        let mut col: Vec<[f64; 4]> = vec![[0.0; 4]; big_n];
        let a_rows: Vec<(usize, &[f64])> = spans.iter().copied().zip(rows.chunks_exact(p + 1)).collect();
        for (c0, chunk) in a_rows.chunks(4).enumerate() {
            col.iter_mut().for_each(|c| *c = [0.0; 4]);
            for (c, &(s, a)) in chunk.iter().enumerate() {
                for (ia, &v) in a.iter().enumerate() {
                    col[s - p + ia][c] = v;
                }
            }
            h.solve(&mut col);
            for (i, ci) in col.iter().enumerate() {
                for (c, &v) in ci.iter().enumerate().take(chunk.len()) {
                    w[i * n + 4 * c0 + c] = v;
                }
            }
        }
        // S = A W (symmetric positive definite iff A has full row rank).
        // A full band: the dense lower triangle.
        let mut sc = BandedCholesky::zeros(n, n.saturating_sub(1));
        for (k, &(s, a)) in a_rows.iter().enumerate() {
            for l in 0..=k {
                let v: f64 = a.iter().enumerate().map(|(ia, &av)| av * w[(s - p + ia) * n + l]).sum();
                sc.add(k, l, v);
            }
        }
        sc.factor("fair interpolation: the interpolation conditions are (nearly) dependent")?;
        Ok(FairInterpolationSolver { knots: knots.clone(), params: params.to_vec(), w, s: sc, energy_scale: g })
    }

    /// The energy `E = ∫ |C^(r)|^2` of the least-energy curve through `points`, without forming
    /// the curve: with `μ = S^{-1} Q` and `P = W μ`, `P^T (G / g) P = P^T H P - |A P|^2 =
    /// μ^T S μ - |Q|^2 = μ . Q - |Q|^2`, so `E = g (μ . Q - |Q|^2)`. The points are first moved
    /// so that `Q_0` is at the origin (constants have zero energy and the fit commutes with
    /// translations), which keeps the cancellation in `μ . Q - |Q|^2` relative to the
    /// section's size, not its distance from the origin.
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `points.len()` differs from the parameter count.
    pub(crate) fn energy(&self, points: &[Vec3]) -> Result<f64, NurbsError> {
        let n = self.params.len();
        if points.len() != n {
            return Err(NurbsError::ControlPointCount { expected: n, got: points.len() });
        }
        let q: Vec<[f64; 3]> = points.iter().map(|&x| (x - points[0]).to_array()).collect();
        let mut mu = q.clone();
        self.s.solve(&mut mu);
        let e: f64 = mu.iter().zip(&q).map(|(m, x)| m.iter().zip(x).map(|(a, b)| (a - b) * b).sum::<f64>()).sum();
        Ok(self.energy_scale * e.max(0.0))
    }

    /// The knot vector of the curves.
    pub fn knots(&self) -> &KnotVector {
        &self.knots
    }

    /// The data parameters.
    pub fn params(&self) -> &[f64] {
        &self.params
    }

    /// The control points (`N` rows of `D` values) of the least-energy curve through `points`
    /// (one row per parameter, `D` values each).
    ///
    /// # Errors
    /// [`NurbsError::ControlPointCount`] if `points.len()` differs from the parameter count,
    /// [`NurbsError::NonFiniteResult`] if the result is not finite.
    pub fn solve<const D: usize>(&self, points: &[[f64; D]]) -> Result<Vec<[f64; D]>, NurbsError> {
        let n = self.params.len();
        if points.len() != n {
            return Err(NurbsError::ControlPointCount { expected: n, got: points.len() });
        }
        let mut mu = points.to_vec();
        self.s.solve(&mut mu);
        let out: Vec<[f64; D]> = self
            .w
            .chunks_exact(n)
            .map(|wi| {
                let mut c = [0.0; D];
                for (&wk, mk) in wi.iter().zip(&mu) {
                    for (cc, mc) in c.iter_mut().zip(mk) {
                        *cc += wk * mc;
                    }
                }
                c
            })
            .collect();
        if out.iter().flatten().all(|x| x.is_finite()) {
            Ok(out)
        } else {
            Err(NurbsError::NonFiniteResult { what: "fair interpolation".into() })
        }
    }

    /// The control points of the least-energy curve through `points`.
    ///
    /// # Errors
    /// [`NurbsError::NonFinitePoint`] for a non-finite point, else as
    /// [`FairInterpolationSolver::solve`].
    pub fn control_points(&self, points: &[Vec3]) -> Result<Vec<Vec3>, NurbsError> {
        super::solve_points(points, |b| self.solve(b))
    }

    /// The non-rational least-energy curve through `points`.
    ///
    /// # Errors
    /// As [`FairInterpolationSolver::control_points`].
    pub fn curve(&self, points: &[Vec3]) -> Result<NurbsCurve, NurbsError> {
        Ok(super::polynomial_curve(&self.knots, self.control_points(points)?))
    }
}

/// The non-rational curve on `knots` through `points` at `params` whose energy
/// `∫ |C^(r)|^2 dt` ([`energy_order`]) is least; for as many points as control points, the
/// ordinary interpolant.
///
/// # Errors
/// [`NurbsError::ControlPointCount`] if `points` and `params` differ in length, else those of
/// [`FairInterpolationSolver::new`] and [`FairInterpolationSolver::control_points`].
pub fn fair_interpolate_curve(points: &[Vec3], params: &[f64], knots: &KnotVector) -> Result<NurbsCurve, NurbsError> {
    if points.len() != params.len() {
        return Err(NurbsError::ControlPointCount { expected: params.len(), got: points.len() });
    }
    FairInterpolationSolver::new(params, knots)?.curve(points)
}

/// Check that the collocation matrix `A_ki = N_{i,p}(t_k)` of the strictly increasing
/// parameters has full row rank: there are `i_0 < i_1 < ... < i_{n-1}` with
/// `N_{i_k,p}(t_k) != 0` (the Schoenberg-Whitney condition applied to the rows: the square
/// submatrix of those columns is then nonsingular, de Boor, *A Practical Guide to Splines*,
/// XIII). The functions non-zero at `t` form a range `lo(t) ..= hi(t)` with both ends
/// non-decreasing in `t`, so the greedy choice `i_k = max(i_{k-1} + 1, lo(t_k))` decides it.
///
/// # Errors
/// [`NurbsError::SingularSystem`] naming the first parameter without a basis function of its
/// own.
pub fn row_schoenberg_whitney(params: &[f64], knots: &KnotVector, what: &str) -> Result<(), NurbsError> {
    let p = knots.degree();
    let u = knots.as_slice();
    let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
    let mut next = 0usize;
    for (k, &t) in params.iter().enumerate() {
        let s = knots.find_span(t);
        basis_funs(u, s, t, p, &mut row);
        let nonzero = |j: &usize| row[*j] != 0.0;
        let (lo, hi) = match ((0..=p).find(nonzero), (0..=p).rev().find(nonzero)) {
            (Some(a), Some(b)) => (s - p + a, s - p + b),
            _ => (usize::MAX, 0),
        };
        let i = next.max(lo);
        if i > hi {
            return Err(NurbsError::SingularSystem {
                what: format!(
                    "{what}: point {k} (parameter {t}) has no basis function of its own among the {} \
                     (too many points between knots; Schoenberg-Whitney condition fails)",
                    knots.num_basis()
                ),
            });
        }
        next = i + 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use crate::fit::{averaging_knots, interpolate_curve};
    use nalgebra::{DMatrix, DVector};

    fn collocation(params: &[f64], kv: &KnotVector) -> DMatrix<f64> {
        let (p, n) = (kv.degree(), kv.num_basis());
        let mut a = DMatrix::zeros(params.len(), n);
        for (k, &t) in params.iter().enumerate() {
            let s = kv.find_span(t);
            let mut row = [0.0; MAX_DEGREE + 1];
            basis_funs(kv.as_slice(), s, t, p, &mut row);
            for j in 0..=p {
                a[(k, s - p + j)] = row[j];
            }
        }
        a
    }

    #[test]
    fn gram_matrix_gives_the_energy_of_a_cubic() {
        // C(t) = (t^3, t^2, t) on [0, 1] as a spline on knots with interior breaks: C'' =
        // (6t, 2, 0), ∫ |C''|^2 = 12 + 4 = 16. Control points by interpolation on its own space
        // (the cubic is in it, so interpolation reproduces it).
        let t: Vec<f64> = (0..7).map(|k| (k as f64 / 6.0).powf(1.3)).collect();
        let kv = averaging_knots(&t, 3).expect("valid");
        let q: Vec<Vec3> = t.iter().map(|&x| Vec3::new(x * x * x, x * x, x)).collect();
        let c = interpolate_curve(&q, 3, &t, &kv).expect("valid");
        let e = EnergyGram::new(&kv).energy(&c.control_points());
        // Exact quadrature; round-off of a 7 x 7 quadratic form with entries up to ~1e3.
        assert_near!(e, 16.0, 1e-10);
        // Degree 1: ∫ |C'|^2 of the polyline through (0,0), (1,2), (3,2) at t = 0, 1/3, 1 on its
        // own knots: spans of length 1/3 and 2/3 with velocities (3, 6) and (3, 0): 15 + 6 = 21.
        let kv1 = KnotVector::try_new(1, vec![0.0, 0.0, 1.0 / 3.0, 1.0, 1.0]).expect("valid");
        let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 0.0)];
        assert_near!(EnergyGram::new(&kv1).energy(&pts), 21.0, 1e-12);
        assert_eq!(energy_order(1), 1);
        assert_eq!(energy_order(3), 2);
    }

    #[test]
    fn energy_from_the_multipliers_equals_the_quadratic_form() {
        let kv = KnotVector::uniform(3, 14).expect("valid");
        let t = [0.0, 0.2, 0.3, 0.65, 0.9, 1.0];
        // Far from the origin: the translation keeps the cancellation small.
        let q: Vec<Vec3> = t.iter().map(|&x| Vec3::new(100.0 + x, (5.0 * x).sin(), (x * x * 3.0).cos())).collect();
        let solver = FairInterpolationSolver::new(&t, &kv).expect("valid");
        let direct = EnergyGram::new(&kv).energy(&solver.control_points(&q).expect("valid"));
        let via_mu = solver.energy(&q).expect("valid");
        // Both in double precision from the same factorization; the quadratic form sums
        // terms of size |P|^2 g ~ 1e4 * 1e3 that cancel to E ~ 1e2: agreement to 1e-6 relative.
        assert!((direct - via_mu).abs() <= 1e-6 * direct, "{direct} vs {via_mu}");
    }

    #[test]
    fn square_case_is_ordinary_interpolation() {
        let t: Vec<f64> = (0..9).map(|k| (k as f64 / 8.0).powf(0.8)).collect();
        let kv = averaging_knots(&t, 3).expect("valid");
        let q: Vec<Vec3> = t.iter().map(|&x| Vec3::new(x.cos(), (2.0 * x).sin(), x * x)).collect();
        let a = fair_interpolate_curve(&q, &t, &kv).expect("valid");
        let b = interpolate_curve(&q, 3, &t, &kv).expect("valid");
        for (x, y) in a.control_points().iter().zip(b.control_points()) {
            // Two different solves of a well-conditioned (cond ~ 10) system: round-off.
            assert_near!(*x, y, 1e-12);
        }
    }

    #[test]
    fn interpolates_and_minimizes_the_energy() {
        // 6 points, 20 control points of degree 3 on uniform knots.
        let kv = KnotVector::uniform(3, 20).expect("valid");
        let t = [0.0, 0.13, 0.4, 0.55, 0.81, 1.0];
        let q: Vec<Vec3> = t.iter().map(|&x| Vec3::new(3.0 * x, (4.0 * x).sin(), 0.5 * (x * 7.0).cos())).collect();
        let c = fair_interpolate_curve(&q, &t, &kv).expect("valid");
        for (&x, qk) in t.iter().zip(&q) {
            // The constraint residual depends on cond(S) only (module docs): round-off.
            assert_near!(c.point(x), *qk, 1e-12);
        }
        // Optimality: G P is orthogonal to every direction z with A z = 0 (the gradient of E
        // restricted to the constraint set vanishes): z^T G P = 0 for z = (I - A^T (A A^T)^-1 A) y.
        let gram = EnergyGram::new(&kv);
        let a = collocation(&t, &kv);
        let n = kv.num_basis();
        let gm = DMatrix::from_fn(n, n, |i, j| gram.get(i, j));
        let cp = c.control_points();
        let aat_inv = (&a * a.transpose()).try_inverse().expect("full row rank");
        let proj = DMatrix::identity(n, n) - a.transpose() * aat_inv * &a;
        let mut seed = 3u64;
        for _ in 0..5 {
            let y = DVector::from_fn(n, |_, _| {
                seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                (seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
            });
            let z = &proj * y;
            for coord in 0..3 {
                let pc = DVector::from_iterator(n, cp.iter().map(|p| p.to_array()[coord]));
                let g = (z.transpose() * &gm * &pc)[(0, 0)];
                let scale = z.norm() * gm.norm() * pc.norm();
                // Relative to the sizes involved; H has condition ~ (20 / 6)^4 ~ 1e2-1e4.
                assert!(g.abs() <= 1e-10 * scale, "coordinate {coord}: {g:e} vs {scale:e}");
                // And a step along z does raise the energy (a minimum, not a saddle).
                let moved: Vec<Vec3> = cp
                    .iter()
                    .enumerate()
                    .map(|(i, p)| {
                        let mut a = p.to_array();
                        a[coord] += 1e-2 * z[i];
                        Vec3::from_array(a)
                    })
                    .collect();
                assert!(gram.energy(&moved) > gram.energy(&cp));
            }
        }
    }

    #[test]
    fn line_and_arc_samples_stay_on_their_curves() {
        // Few points of a line `a + s d`: each coordinate is fitted by the same linear map of
        // the data, which reproduces constants (they have zero energy), so the curve is
        // `a + f(t) d` with `f` the fit of the `s_k`: it stays on the line, whatever the
        // parameters.
        let kv = KnotVector::uniform(3, 16).expect("valid");
        let t = [0.0, 0.1, 0.45, 0.5, 1.0];
        let (a, d) = (Vec3::new(1.0, 2.0, 3.0), Vec3::new(2.0, -1.0, 0.5));
        let q: Vec<Vec3> = [0.0, 0.3, 0.4, 0.9, 1.7].iter().map(|&s| a + d * s).collect();
        let c = fair_interpolate_curve(&q, &t, &kv).expect("valid");
        for k in 0..=100 {
            let x = c.point(k as f64 / 100.0) - a;
            // Distance to the line: round-off on coordinates of size ~5.
            assert!(x.cross(d).norm() / d.norm() < 1e-12, "off the line at {k}");
        }
        // Five points of a quarter circle of radius 2 with chord-length parameters on 16 control
        // points: the fair cubic stays within 1% of the radius (0.8% measured, at the ends,
        // where the least-energy curve straightens like a natural spline, C'' -> 0, while the
        // arc keeps its curvature).
        let q: Vec<Vec3> = (0..5)
            .map(|k| {
                let a = std::f64::consts::FRAC_PI_2 * k as f64 / 4.0;
                Vec3::new(2.0 * a.cos(), 2.0 * a.sin(), 0.0)
            })
            .collect();
        let t = crate::fit::parameterize(&q, crate::fit::Parameterization::ChordLength, 3).expect("valid");
        let c = fair_interpolate_curve(&q, &t, &kv).expect("valid");
        let mut worst = 0.0f64;
        for k in 0..=200 {
            let x = c.point(k as f64 / 200.0);
            worst = worst.max((x.norm() - 2.0).abs());
        }
        assert!(worst < 0.02, "radius error {worst}");
    }

    #[test]
    fn singular_cases_are_detected() {
        // Degree 1 on 4 hats over [0, 1/3, 2/3, 1]: three parameters inside one span see only
        // two basis functions, so A has rank 2 < 3.
        let kv = KnotVector::uniform(1, 4).expect("valid");
        let e = FairInterpolationSolver::new(&[0.4, 0.5, 0.6], &kv).expect_err("rank 2");
        assert!(matches!(&e, NurbsError::SingularSystem { what } if what.contains("point 2")), "{e}");
        // Cubic, 9 spans of 1/9: five parameters in [1/3, 4/9] where 4 functions are non-zero.
        let kv3 = KnotVector::uniform(3, 12).expect("valid");
        let t = [0.0, 0.40, 0.41, 0.42, 0.43, 0.44, 1.0];
        assert!(matches!(FairInterpolationSolver::new(&t, &kv3), Err(NurbsError::SingularSystem { .. })));
        // One point and a bending energy: every line through it has zero energy, H is singular.
        let e = FairInterpolationSolver::new(&[0.3], &kv3).expect_err("lines through a point");
        assert!(matches!(&e, NurbsError::SingularSystem { what } if what.contains("does not determine")), "{e}");
        // A knot of multiplicity p = 3 splits the cubic into two C^0 pieces; two points, both
        // left of it, leave the right piece's slope free: zero-energy curves vanish at both.
        let split = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.5, 0.5, 0.5, 1., 1., 1., 1.]).expect("valid");
        assert!(matches!(FairInterpolationSolver::new(&[0.0, 0.2], &split), Err(NurbsError::SingularSystem { .. })));
        // Degree 1 and one point: the membrane energy vanishes only on constants, fixed by it.
        let c = fair_interpolate_curve(&[Vec3::new(1.0, 2.0, 3.0)], &[0.5], &kv).expect("constant");
        assert_near!(c.point(0.1), Vec3::new(1.0, 2.0, 3.0), 1e-14);
        // Input errors.
        assert!(matches!(FairInterpolationSolver::new(&[], &kv), Err(NurbsError::TooFewPoints { .. })));
        assert!(matches!(
            FairInterpolationSolver::new(&[0.0, 0.2, 0.4, 0.6, 1.0], &kv),
            Err(NurbsError::Incompatible { .. })
        ));
        assert!(matches!(
            FairInterpolationSolver::new(&[0.0, 0.5, 0.5], &kv3),
            Err(NurbsError::DecreasingParameters { .. })
        ));
        assert!(matches!(
            FairInterpolationSolver::new(&[0.0, 1.5], &kv3),
            Err(NurbsError::ParameterOutOfDomain { .. })
        ));
    }

    #[test]
    fn row_condition_matches_the_rank() {
        // Against the numerical rank of the collocation matrix for many parameter subsets.
        let kv = KnotVector::try_new(2, vec![0., 0., 0., 0.2, 0.3, 0.7, 1., 1., 1.]).expect("valid");
        let grid: Vec<f64> = (0..=20).map(|k| k as f64 / 20.0).collect();
        let mut seed = 5u64;
        for _ in 0..300 {
            let mut t: Vec<f64> = grid
                .iter()
                .copied()
                .filter(|_| {
                    seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
                    (seed >> 60) < 4
                })
                .collect();
            t.truncate(kv.num_basis());
            if t.is_empty() {
                continue;
            }
            let rank = collocation(&t, &kv).svd(false, false).rank(1e-10);
            let ok = row_schoenberg_whitney(&t, &kv, "t").is_ok();
            assert_eq!(ok, rank == t.len(), "params {t:?}");
        }
    }
}
