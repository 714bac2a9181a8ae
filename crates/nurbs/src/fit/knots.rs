//! Knot vectors for fitting: averaging (interpolation), symmetric placement (least squares),
//! uniform (paired with universal parameters), and the Schoenberg-Whitney check.

use super::Parameterization;
use crate::basis::{basis_funs, BasisRow};
use crate::linalg::BandedLu;
use crate::{KnotVector, NurbsError, MAX_DEGREE};

/// Check that `params` are finite and non-decreasing (strictly increasing if `strict`).
pub(crate) fn check_params(params: &[f64], strict: bool, what: &str) -> Result<(), NurbsError> {
    for (index, &value) in params.iter().enumerate() {
        if !value.is_finite() {
            return Err(NurbsError::ParameterOutOfDomain { value, start: f64::NEG_INFINITY, end: f64::INFINITY });
        }
        if index > 0 {
            let prev = params[index - 1];
            if value < prev || (strict && value == prev) {
                return Err(NurbsError::DecreasingParameters { what: what.to_string(), index, prev, value });
            }
        }
    }
    Ok(())
}

/// The averaging knot vector of The NURBS Book eq. 9.8 for interpolating `m + 1 = params.len()`
/// points with degree `p`:
/// `u_0 = ... = u_p = t_0`, `u_{m+1} = ... = u_{m+p+1} = t_m`, and
/// `u_{j+p} = (1/p) sum_{i=j}^{j+p-1} t_i` for `j = 1..=m-p`.
/// It reflects the parameter distribution and makes the interpolation matrix totally positive
/// and nonsingular (every `t_j` lies in the support of `N_{j,p}`, Schoenberg-Whitney).
///
/// # Errors
/// [`NurbsError::BadDegree`], [`NurbsError::TooFewPoints`] if `params.len() <= degree`,
/// [`NurbsError::DecreasingParameters`] unless `params` strictly increase,
/// [`NurbsError::ParameterOutOfDomain`] for a non-finite parameter.
pub fn averaging_knots(params: &[f64], degree: usize) -> Result<KnotVector, NurbsError> {
    check_degree(degree)?;
    let n = params.len();
    if n <= degree {
        return Err(NurbsError::TooFewPoints {
            what: format!("interpolation of degree {degree}"),
            needed: degree + 1,
            got: n,
        });
    }
    check_params(params, true, "interpolation parameters")?;
    let p = degree;
    let (a, b) = (params[0], params[n - 1]);
    let mut k = Vec::with_capacity(n + p + 1);
    k.extend(std::iter::repeat_n(a, p + 1));
    // Running window sum of p consecutive parameters.
    let mut sum: f64 = params[1..p].iter().sum();
    for j in 1..n - p {
        sum += params[j + p - 1];
        k.push(sum / p as f64);
        sum -= params[j];
    }
    k.extend(std::iter::repeat_n(b, p + 1));
    KnotVector::try_new(p, k)
}

/// The optimal knots for interpolation at `params` with degree `p` (order `k = p + 1`) of
/// Micchelli, Rivlin and Winograd (1976) and Gaffney and Powell (1976), computed as in de Boor,
/// *A Practical Guide to Splines*, XIII (`SPLOPT`): the interior knots `ξ_1 < ... < ξ_{n-k}`
/// (`n = params.len()`) are the sign changes of the function `h = ±1` that is orthogonal to every
/// B-spline of order `k` on the data parameters,
///
/// `∫ M_j(x) h(x) dx = 0`, `j = 0..n-k-1`, `h = (-1)^i` on `(ξ_i, ξ_{i+1})`,
///
/// where `M_j` is the B-spline with knots `t_j..t_{j+k}` normalized to unit integral and
/// `ξ_0 = t_0`, `ξ_{n-k+1} = t_{n-1}`. With these knots the interpolant is the optimal recovery
/// of a function known only at the parameters, for the class of functions with a bounded `k`-th
/// derivative: no other linear or nonlinear scheme has a smaller worst-case error, at every
/// point at once. Like the averaging knots of eq. 9.8 (the Newton iteration's start) they depend
/// on the parameters only, satisfy `t_i < ξ_i < t_{i+k}` (the Schoenberg-Whitney condition:
/// the interpolation matrix is nonsingular), and are symmetric under reversal; unlike them
/// they come from an error bound, and they follow uneven parameters more closely (as the
/// not-a-knot choice `ξ_i = t_{i+(k-1)/2}` does for uniform ones, which they nearly equal).
///
/// The system `F(ξ) = 0`, `F_j = (-1)^{n-k} + 2 sum_i (-1)^{i-1} I_j(ξ_i)` with
/// `I_j(x) = ∫_{t_0}^x M_j`, is solved by Newton's method, `∂F_j/∂ξ_i = 2 (-1)^{i-1} M_j(ξ_i)`, a
/// band matrix (half-bandwidth `p` under the interlacing) that is totally positive after the
/// column signs are removed; each step is halved until the knots stay interlaced and `|F|`
/// decreases. `M_j` is integrated exactly (Gauss-Legendre with `k` nodes per interval between
/// parameters). If the iteration does not converge to `max |F_j| <= 1e-12` (not met in
/// practice), the averaging knots are returned. For degree 1 the averaging knots are the data
/// parameters (the polyline) and are returned as they are; with `n = k` points there are no
/// interior knots.
///
/// # Errors
/// As [`averaging_knots`].
pub fn optimal_knots(params: &[f64], degree: usize) -> Result<KnotVector, NurbsError> {
    let averaging = averaging_knots(params, degree)?;
    let (n, p) = (params.len(), degree);
    let k = p + 1;
    if p < 2 || n <= k {
        return Ok(averaging);
    }
    let m = n - k;
    let start: Vec<f64> = averaging.as_slice()[k..k + m].to_vec();
    let Some(xi) = OptimalKnots::new(params, k)?.solve(start) else {
        return Ok(averaging);
    };
    let mut knots = Vec::with_capacity(n + k);
    knots.extend(std::iter::repeat_n(params[0], k));
    knots.extend_from_slice(&xi);
    knots.extend(std::iter::repeat_n(params[n - 1], k));
    let kv = KnotVector::try_new(p, knots)?;
    match schoenberg_whitney(params, &kv, "optimal interpolation knots") {
        Ok(()) => Ok(kv),
        Err(_) => Ok(averaging),
    }
}

/// The Newton iteration of [`optimal_knots`].
struct OptimalKnots<'a> {
    t: &'a [f64],
    k: usize,
    /// The clamped knot vector `[t_0 (k times), t_1..t_{n-2}, t_{n-1} (k times)]`: its basis
    /// function `j + k - 1` is `N_j` with the knots `t_j..t_{j+k}`, and `M_j = k N_j / (t_{j+k} - t_j)`.
    clamped: KnotVector,
    nodes: Vec<f64>,
    weights: Vec<f64>,
    /// `cum[j * (k + 1) + s] = ∫_{t_j}^{t_{j+s}} M_j`, `s = 0..=k` (0, ..., 1).
    cum: Vec<f64>,
}

impl<'a> OptimalKnots<'a> {
    /// Largest `|F_j|` accepted as converged (`F_j` is a difference of areas of a unit-integral
    /// function: 1e-12 is a few thousand ulps of 1, the knots then move by about that relative
    /// to their spacing).
    const TOL: f64 = 1e-12;
    const MAX_ITER: usize = 50;

    fn new(t: &'a [f64], k: usize) -> Result<Self, NurbsError> {
        let (n, p) = (t.len(), k - 1);
        let mut u = vec![t[0]; k];
        u.extend_from_slice(&t[1..n - 1]);
        u.extend(std::iter::repeat_n(t[n - 1], k));
        let clamped = KnotVector::try_new(p, u)?;
        let gl = crate::GaussLegendre::new(k);
        let (nodes, weights) = (gl.nodes().to_vec(), gl.weights().to_vec());
        let mut me = OptimalKnots { t, k, clamped, nodes, weights, cum: vec![0.0; (n - k) * (k + 1)] };
        // Integrals over whole intervals between parameters, then running sums.
        for r in 0..n - 1 {
            let piece = me.partial(r, t[r + 1]);
            for (j, a) in me.in_interval(r) {
                me.cum[j * (k + 1) + r - j + 1] = piece[a];
            }
        }
        for j in 0..n - k {
            for s in 1..=k {
                me.cum[j * (k + 1) + s] += me.cum[j * (k + 1) + s - 1];
            }
        }
        Ok(me)
    }

    /// The number of equations and unknowns, `n - k`.
    fn m(&self) -> usize {
        self.t.len() - self.k
    }

    /// The index `r` of the interval `[t_r, t_{r+1})` holding `x` (the last for `x = t_{n-1}`).
    fn interval(&self, x: f64) -> usize {
        self.clamped.find_span(x) - (self.k - 1)
    }

    /// `M_j(x)` for `j = j0 + a`, `a = 0..=p`, by A2.2 on the clamped knots (0 where `j` is
    /// not in `0..m`: the clamped end functions are not among the `M_j`), and `j0`.
    fn values(&self, x: f64) -> (isize, BasisRow) {
        self.values_in(self.clamped.find_span(x), x)
    }

    /// [`OptimalKnots::values`] with the knot span of `x` known.
    fn values_in(&self, span: usize, x: f64) -> (isize, BasisRow) {
        let p = self.k - 1;
        let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
        basis_funs(self.clamped.as_slice(), span, x, p, &mut row);
        // Basis function span - p + a is N_j for j = span - 2p + a.
        let j0 = span as isize - 2 * p as isize;
        for (a, v) in row.iter_mut().enumerate().take(p + 1) {
            *v = match usize::try_from(j0 + a as isize).ok().filter(|&j| j < self.m()) {
                Some(j) => self.k as f64 / (self.t[j + self.k] - self.t[j]) * *v,
                None => 0.0,
            };
        }
        (j0, row)
    }

    /// `∫_{t_r}^x M_j` for `x` in interval `r` and `j = r - p + a`, `a = 0..=p` (as
    /// [`OptimalKnots::values`]): Gauss-Legendre with `k` nodes, exact for the polynomial of
    /// degree `k - 1` of each `M_j` there.
    fn partial(&self, r: usize, x: f64) -> BasisRow {
        let a = self.t[r];
        let (mid, half) = (0.5 * (a + x), 0.5 * (x - a));
        let mut acc: BasisRow = [0.0; MAX_DEGREE + 1];
        for (&s, &w) in self.nodes.iter().zip(&self.weights) {
            // Every node lies in interval r, knot span r + p of the clamped knots, so the rows
            // line up (j0 = r - p).
            let (_, row) = self.values_in(r + self.k - 1, mid + half * s);
            acc.iter_mut().zip(&row).take(self.k).for_each(|(c, v)| *c += w * half * v);
        }
        acc
    }

    /// The `(j, a)` pairs of interval `r`: `j = r - p + a` in `0..m`.
    fn in_interval(&self, r: usize) -> impl Iterator<Item = (usize, usize)> {
        let (p, m) = (self.k - 1, self.m());
        (0..=p).filter_map(move |a| (r + a).checked_sub(p).filter(|&j| j < m).map(|j| (j, a)))
    }

    /// `F(ξ)` (see [`optimal_knots`]): `F_j = (-1)^m + 2 sum_i (-1)^{i-1} I_j(ξ_i)` with `ξ_i` at
    /// index `i - 1` of `xi`, `I_j(x) = ∫_{t_j}^x M_j`, which is 1 past the support of `M_j`.
    fn residual(&self, xi: &[f64]) -> Vec<f64> {
        let (m, k) = (xi.len(), self.k);
        let sign = |i: usize| if i.is_multiple_of(2) { 1.0 } else { -1.0 };
        let mut f = vec![0.0; m];
        // Contributions of 1 to every j whose support ends at or before ξ_i: j + k <= r, i.e.
        // j < r + 1 - k, accumulated as a difference array.
        let mut ended = vec![0.0; m + 1];
        for (i, &x) in xi.iter().enumerate() {
            let r = self.interval(x);
            let partial = self.partial(r, x);
            for (j, a) in self.in_interval(r) {
                // ∫_{t_j}^{x} = ∫_{t_j}^{t_r} + ∫_{t_r}^{x}; here j <= r < j + k.
                f[j] += sign(i) * (self.cum[j * (k + 1) + r - j] + partial[a]);
            }
            let stop = (r + 1).saturating_sub(k).min(m);
            ended[0] += sign(i);
            ended[stop] -= sign(i);
        }
        let mut run = 0.0;
        for (fj, e) in f.iter_mut().zip(&ended) {
            run += e;
            *fj = sign(m) + 2.0 * (*fj + run);
        }
        f
    }

    /// `t_i < ξ_i < t_{i+k}` and strictly increasing.
    fn interlaced(&self, xi: &[f64]) -> bool {
        xi.iter().enumerate().all(|(i, &x)| self.t[i] < x && x < self.t[i + self.k])
            && xi.windows(2).all(|w| w[0] < w[1])
    }

    /// Damped Newton from `xi`; `None` if it does not converge.
    fn solve(&self, mut xi: Vec<f64>) -> Option<Vec<f64>> {
        let (m, p) = (xi.len(), self.k - 1);
        if !self.interlaced(&xi) {
            return None;
        }
        let norm = |f: &[f64]| f.iter().fold(0.0f64, |a, x| a.max(x.abs()));
        let mut f = self.residual(&xi);
        for _ in 0..Self::MAX_ITER {
            if norm(&f) <= Self::TOL {
                return Some(xi);
            }
            // J' = J diag((-1)^{i-1}): J'_{ji} = 2 M_j(ξ_i) >= 0, a collocation matrix, totally
            // positive, in the band |i - j| <= p under the interlacing.
            let mut jac = BandedLu::zeros(m, p, p);
            for (i, &x) in xi.iter().enumerate() {
                let (j0, row) = self.values(x);
                for (a, &v) in row.iter().enumerate().take(p + 1) {
                    if let Some(j) = usize::try_from(j0 + a as isize).ok().filter(|&j| j < m && j.abs_diff(i) <= p) {
                        jac.set(j, i, 2.0 * v);
                    }
                }
            }
            jac.factor("optimal knots (Newton)").ok()?;
            let mut step: Vec<[f64; 1]> = f.iter().map(|&x| [-x]).collect();
            jac.solve(&mut step);
            // Undo the column signs: δ_i = (-1)^{i-1} δ'_i, i counted from 1.
            let delta: Vec<f64> =
                step.iter().enumerate().map(|(i, s)| if i.is_multiple_of(2) { s[0] } else { -s[0] }).collect();
            let mut lambda = 1.0;
            loop {
                let cand: Vec<f64> = xi.iter().zip(&delta).map(|(x, d)| x + lambda * d).collect();
                if self.interlaced(&cand) {
                    let fc = self.residual(&cand);
                    if norm(&fc) < norm(&f) {
                        xi = cand;
                        f = fc;
                        break;
                    }
                }
                lambda *= 0.5;
                if lambda < 1e-10 {
                    return None;
                }
            }
        }
        (norm(&f) <= Self::TOL).then_some(xi)
    }
}

/// Knots for least-squares approximation of `m + 1 = params.len()` points by `n + 1 = n_ctrl`
/// control points of degree `p`: the idea of The NURBS Book eq. 9.68-9.69 (knots follow the
/// distribution of the parameters, every span holds data) in a form that is symmetric under
/// reversal of the data and well conditioned up to `n = m`.
///
/// Write `T(x)` for the piecewise-linear interpolant of the parameters over their index,
/// `T(k) = t_k`. Eq. 9.69 (`d = (m + 1)/(n - p + 1)`) sets `u_{p+j} = T(j d - 1)`: applied to the
/// reversed data and mirrored back it gives `T(j d)`, i.e. the book's formula is biased by half
/// an index toward `t_0`. A centred `T(j d - 1/2)` removes the bias but, as `n` approaches `m`,
/// puts knots next to data parameters and the normal equations become nearly singular
/// (smallest singular value 4e-12 measured at 62 poles for 62 points). Here the parameters are
/// first resampled at `n + 1` evenly spread indices, `s_i = T(i m / n)`, `i = 0..=n`, and the
/// knots are their averages (eq. 9.8 on the resampled parameters):
///
/// `u_{p+j} = (1/p) sum_{i=j}^{j+p-1} s_i`, `j = 1..=n-p`.
///
/// Properties: symmetric (mirrored data give mirrored knots, as `T` and the averages are);
/// linear in the parameters (the knots of averaged parameters are the average of the knots, used
/// by skinning); for `n = m` exactly the averaging knots of interpolation; consecutive knots sit
/// about `m/n >= 1` index units apart, so every span holds data. The Schoenberg-Whitney
/// condition is verified ([`schoenberg_whitney`]) as a guard.
///
/// # Errors
/// [`NurbsError::BadControlPointCount`] unless `degree + 1 <= n_ctrl <= params.len()`,
/// [`NurbsError::BadDegree`], [`NurbsError::DecreasingParameters`] unless `params` strictly
/// increase, [`NurbsError::SingularSystem`] if Schoenberg-Whitney fails.
pub fn approximation_knots(params: &[f64], n_ctrl: usize, degree: usize) -> Result<KnotVector, NurbsError> {
    check_degree(degree)?;
    let count = params.len();
    check_ctrl_count(n_ctrl, count, degree, "least-squares knot placement")?;
    check_params(params, true, "approximation parameters")?;
    let p = degree;
    let (m, n) = (count - 1, n_ctrl - 1);
    let t = |x: f64| -> f64 {
        let i = (x.floor().max(0.0) as usize).min(m - 1);
        let alpha = x - i as f64;
        (1.0 - alpha) * params[i] + alpha * params[i + 1]
    };
    // Resampled parameters; exact at the ends and, for n = m, everywhere.
    let s: Vec<f64> = (0..=n)
        .map(|i| {
            if n == m {
                params[i]
            } else if i == n {
                params[m]
            } else {
                t(i as f64 * m as f64 / n as f64)
            }
        })
        .collect();
    let mut k = Vec::with_capacity(n_ctrl + p + 1);
    k.extend(std::iter::repeat_n(params[0], p + 1));
    k.extend((1..=n - p).map(|j| s[j..j + p].iter().sum::<f64>() / p as f64));
    k.extend(std::iter::repeat_n(params[m], p + 1));
    let kv = KnotVector::try_new(p, k)?;
    schoenberg_whitney(params, &kv, "least-squares knot placement")?;
    Ok(kv)
}

/// Knots for least-squares approximation with the same amount of data in every span: The
/// NURBS Book eq. 9.68-9.69 in its symmetric (centred) form. With `T` the piecewise-linear
/// interpolant of the parameters over their index (`T(k) = t_k`, as in
/// [`approximation_knots`]) and `d = (m + 1) / (n - p + 1)`,
///
/// `u_{p+j} = T(j d - 1/2)`, `j = 1..=n-p`,
///
/// where the book's `T(j d - 1)` is biased by half an index toward `t_0`. Every span holds
/// about `d` parameters, including the two end spans; [`approximation_knots`] instead makes
/// its end spans about twice as wide as the others (they are the averaging knots of `n + 1`
/// resampled parameters). Which fits better depends on the data: on tables with
/// sections crowded at the ends (where the shape changes fastest) the equal spans are better,
/// on tables with evenly spaced sections the wider end spans; the skinning therefore tries
/// both ([`crate::fit::skin_approximate`]). As `n` approaches `m` the spans shrink to about one
/// parameter and knots come close to parameters: for 62 uneven parameters (30 random sets,
/// cubic) the smallest singular value of the collocation matrix was above 0.1 up to `n = 31`,
/// then fell to 2e-3 at 50 and 2e-15 at 62, where [`approximation_knots`] stays above 1e-2.
/// Symmetric under reversal of the data; the Schoenberg-Whitney condition is verified.
///
/// # Errors
/// As [`approximation_knots`].
pub fn centred_approximation_knots(params: &[f64], n_ctrl: usize, degree: usize) -> Result<KnotVector, NurbsError> {
    check_degree(degree)?;
    let count = params.len();
    check_ctrl_count(n_ctrl, count, degree, "least-squares knot placement")?;
    check_params(params, true, "approximation parameters")?;
    let p = degree;
    let m = count - 1;
    let d = count as f64 / (n_ctrl - p) as f64;
    let t = |x: f64| -> f64 {
        let i = (x.floor().max(0.0) as usize).min(m - 1);
        let alpha = x - i as f64;
        (1.0 - alpha) * params[i] + alpha * params[i + 1]
    };
    let mut k = Vec::with_capacity(n_ctrl + p + 1);
    k.extend(std::iter::repeat_n(params[0], p + 1));
    k.extend((1..n_ctrl - p).map(|j| t(j as f64 * d - 0.5)));
    k.extend(std::iter::repeat_n(params[m], p + 1));
    let kv = KnotVector::try_new(p, k)?;
    schoenberg_whitney(params, &kv, "least-squares knot placement (centred)")?;
    Ok(kv)
}

/// The knot vector to interpolate data with parameters `params` of the given kind: uniform for
/// [`Parameterization::Universal`] (the pairing that defines the universal parameters: on the
/// uniform clamped knots each `t_k` is the maximum of `N_{k,p}`), the optimal knots of
/// [`optimal_knots`] otherwise.
///
/// Why not the averaging knots of eq. 9.8: both depend on the parameters only and keep one
/// control point per data point, but the optimal knots come from an error bound, and on the
/// nine tables of `tools/peers/results.md` (skinning, between the offsets) they lowered the
/// error of the surface through the offsets by 5 % in the geometric mean of max and RMS, by
/// up to 25 % on the analytic surfaces, and moved it by at most 3 % the other way on the real
/// tables. The not-a-knot choice (knots at the parameters but the second and the last but
/// one) was measured too: 1 % worse than averaging.
///
/// # Errors
/// As [`averaging_knots`] or [`KnotVector::uniform`].
pub fn knots_for_interpolation(
    params: &[f64],
    degree: usize,
    kind: Parameterization,
) -> Result<KnotVector, NurbsError> {
    match kind {
        Parameterization::Universal => uniform_on(params, params.len(), degree),
        _ => optimal_knots(params, degree),
    }
}

/// The knot vector to approximate data with parameters `params` by `n_ctrl` control points:
/// uniform for [`Parameterization::Universal`], [`approximation_knots`] otherwise. In both
/// cases the Schoenberg-Whitney condition is checked.
///
/// # Errors
/// As [`approximation_knots`]; [`NurbsError::SingularSystem`] if the uniform knots violate
/// Schoenberg-Whitney for these parameters.
pub fn knots_for_approximation(
    params: &[f64],
    n_ctrl: usize,
    degree: usize,
    kind: Parameterization,
) -> Result<KnotVector, NurbsError> {
    match kind {
        Parameterization::Universal => {
            check_degree(degree)?;
            check_ctrl_count(n_ctrl, params.len(), degree, "least-squares knot placement")?;
            let kv = uniform_on(params, n_ctrl, degree)?;
            schoenberg_whitney(params, &kv, "uniform least-squares knots")?;
            Ok(kv)
        }
        _ => approximation_knots(params, n_ctrl, degree),
    }
}

/// Uniform clamped knots with `n` basis functions on `[t_0, t_m]`.
fn uniform_on(params: &[f64], n: usize, degree: usize) -> Result<KnotVector, NurbsError> {
    check_params(params, true, "parameters")?;
    let kv = KnotVector::uniform(degree, n)?;
    match (params.first(), params.last()) {
        (Some(&a), Some(&b)) if (a, b) != (0.0, 1.0) => kv.reparameterized(a, b),
        _ => Ok(kv),
    }
}

fn check_degree(degree: usize) -> Result<(), NurbsError> {
    if degree == 0 || degree > crate::MAX_DEGREE {
        return Err(NurbsError::BadDegree { degree, max: crate::MAX_DEGREE });
    }
    Ok(())
}

pub(crate) fn check_ctrl_count(n_ctrl: usize, points: usize, degree: usize, what: &str) -> Result<(), NurbsError> {
    if n_ctrl < degree + 1 || n_ctrl > points {
        return Err(NurbsError::BadControlPointCount {
            what: format!("{what} ({points} points, degree {degree})"),
            count: n_ctrl,
            min: degree + 1,
            max: points,
        });
    }
    Ok(())
}

/// Check the Schoenberg-Whitney condition (de Boor, A Practical Guide to Splines, XIII): the
/// collocation matrix `N_{i,p}(t_k)` of `n + 1` basis functions at the non-decreasing parameters
/// has full column rank iff there are indices `k_0 < k_1 < ... < k_n` with `N_{i,p}(t_{k_i}) != 0`,
/// i.e. `u_i < t_{k_i} < u_{i+p+1}` (with `t = u_0` allowed for `i = 0` and `t = u_{n+p+1}` for
/// `i = n`, the clamped ends). Supports move right with `i`, so the greedy choice of the first
/// unused admissible parameter decides it in `O(m + n)`.
///
/// # Errors
/// [`NurbsError::SingularSystem`] naming the first basis function without a parameter;
/// [`NurbsError::DecreasingParameters`] or [`NurbsError::ParameterOutOfDomain`] for parameters
/// that decrease or are not finite.
pub fn schoenberg_whitney(params: &[f64], knots: &KnotVector, what: &str) -> Result<(), NurbsError> {
    check_params(params, false, what)?;
    let p = knots.degree();
    let u = knots.as_slice();
    let n = knots.num_basis();
    let last = n - 1;
    let mut k = 0;
    for i in 0..n {
        let (lo, hi) = (u[i], u[i + p + 1]);
        let admissible = |t: f64| (t > lo || (i == 0 && t == lo)) && (t < hi || (i == last && t == hi));
        while k < params.len() && !admissible(params[k]) && params[k] < hi {
            k += 1;
        }
        if k >= params.len() || !admissible(params[k]) {
            return Err(NurbsError::SingularSystem {
                what: format!(
                    "{what}: no parameter left for basis function {i} with support [{lo}, {hi}] \
                     (Schoenberg-Whitney condition fails; {} parameters, {n} control points)",
                    params.len()
                ),
            });
        }
        k += 1;
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;

    fn random_params(seed: u64, n: usize) -> Vec<f64> {
        // A small LCG: uneven but reproducible gaps in (0.05, 1.05).
        let mut s = seed;
        let mut acc = 0.0;
        let mut t = vec![0.0];
        for _ in 1..n {
            s = s.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
            acc += 0.05 + (s >> 11) as f64 / (1u64 << 53) as f64;
            t.push(acc);
        }
        t.iter().map(|x| x / acc).collect()
    }

    #[test]
    fn averaging_knots_follow_eq_9_8() {
        // The NURBS Book Ex. 9.1 style data: t = {0, 5/17, 9/17, 14/17, 1}, p = 3 gives one
        // interior knot (5 + 9 + 14) / (3 * 17) = 28/51.
        let t = [0.0, 5.0 / 17.0, 9.0 / 17.0, 14.0 / 17.0, 1.0];
        let kv = averaging_knots(&t, 3).expect("valid");
        assert_eq!(kv.num_basis(), 5);
        // Sum of three values and a division: a few ulps.
        assert_near!(kv.as_slice()[4], 28.0 / 51.0, 1e-15);
        assert!(matches!(averaging_knots(&t, 5), Err(NurbsError::TooFewPoints { .. })));
        assert!(matches!(
            averaging_knots(&[0.0, 0.5, 0.5, 1.0], 2),
            Err(NurbsError::DecreasingParameters { index: 2, .. })
        ));
    }

    #[test]
    fn symmetric_placement_mirrors_under_reversal() {
        for seed in 0..40u64 {
            let m = 6 + (seed as usize % 30);
            let t = random_params(seed, m);
            let rev: Vec<f64> = t.iter().rev().map(|x| 1.0 - x).collect();
            for p in 1..=5usize.min(m - 1) {
                for n_ctrl in p + 1..=m {
                    let a = approximation_knots(&t, n_ctrl, p).expect("valid");
                    let b = approximation_knots(&rev, n_ctrl, p).expect("valid");
                    let (ka, kb) = (a.as_slice(), b.as_slice());
                    let len = ka.len();
                    for i in 0..len {
                        // u_i(t) = 1 - u_{len-1-i}(reversed t); a few roundings of values in [0, 1].
                        assert_near!(ka[i], 1.0 - kb[len - 1 - i], 1e-14, "seed {seed} p {p} n {n_ctrl}");
                    }
                    schoenberg_whitney(&t, &a, "test").expect("placement satisfies Schoenberg-Whitney");
                }
            }
        }
    }

    #[test]
    fn centred_placement_spreads_the_data_evenly_and_mirrors() {
        // Uniform data, 13 points, 7 control points of degree 3: d = 13/4, knots at indices
        // 2.75, 6, 9.25, i.e. 11/48, 1/2, 37/48; every span (end spans included) holds 3 or 4
        // parameters.
        let t: Vec<f64> = (0..13).map(|k| k as f64 / 12.0).collect();
        let kv = centred_approximation_knots(&t, 7, 3).expect("valid");
        // A few roundings of values in [0, 1].
        for (got, want) in kv.as_slice()[4..7].iter().zip([2.75 / 12.0, 0.5, 9.25 / 12.0]) {
            assert_near!(*got, want, 1e-15);
        }
        let u = kv.as_slice();
        for s in 3..7 {
            // Half-open spans, the last one closed.
            let inside = t.iter().filter(|&&x| x >= u[s] && (x < u[s + 1] || (s == 6 && x == 1.0))).count();
            assert!((3..=4).contains(&inside), "span {s}: {inside}");
        }
        for seed in 0..40u64 {
            let m = 6 + (seed as usize % 30);
            let t = random_params(seed, m);
            let rev: Vec<f64> = t.iter().rev().map(|x| 1.0 - x).collect();
            for p in 1..=5usize.min(m - 1) {
                for n_ctrl in p + 1..=m {
                    // Near n = m on uneven data the centred knots may leave a basis function
                    // without a parameter: then it must say so, for the data and its mirror.
                    match (centred_approximation_knots(&t, n_ctrl, p), centred_approximation_knots(&rev, n_ctrl, p)) {
                        (Ok(a), Ok(b)) => {
                            let (ka, kb) = (a.as_slice(), b.as_slice());
                            for i in 0..ka.len() {
                                // A few roundings of values in [0, 1].
                                assert_near!(ka[i], 1.0 - kb[ka.len() - 1 - i], 1e-14, "seed {seed} p {p} n {n_ctrl}");
                            }
                        }
                        (Err(NurbsError::SingularSystem { .. }), Err(NurbsError::SingularSystem { .. })) => {}
                        other => panic!("seed {seed} p {p} n {n_ctrl}: {other:?}"),
                    }
                }
            }
        }
    }

    /// `M_j(x)` of [`optimal_knots`] from the crate's basis functions: on the clamped knot
    /// vector `[t_0 (k times), t_1..t_{n-2}, t_{n-1} (k times)]`, basis function `j + k - 1` has
    /// the knots `t_j..t_{j+k}`.
    fn unit_bspline(t: &[f64], p: usize, j: usize, x: f64) -> f64 {
        let (n, k) = (t.len(), p + 1);
        let mut u = vec![t[0]; k];
        u.extend_from_slice(&t[1..n - 1]);
        u.extend(std::iter::repeat_n(t[n - 1], k));
        let kv = KnotVector::try_new(p, u).expect("valid");
        let span = kv.find_span(x);
        let mut row = [0.0; MAX_DEGREE + 1];
        crate::basis::basis_funs(kv.as_slice(), span, x, p, &mut row);
        let r = j + k - 1;
        let value = (r + p).checked_sub(span).filter(|&i| i <= p).map_or(0.0, |i| row[i]);
        k as f64 / (t[j + k] - t[j]) * value
    }

    #[test]
    fn optimal_knots_satisfy_their_defining_condition() {
        for seed in 0..12u64 {
            let n = 6 + (seed as usize % 9);
            let t = random_params(seed, n);
            for p in 2..=5usize.min(n - 2) {
                let kv = optimal_knots(&t, p).expect("valid");
                let (k, u) = (p + 1, kv.as_slice());
                let xi = &u[k..n];
                // Interlaced with the parameters: the Schoenberg-Whitney condition.
                for (i, &x) in xi.iter().enumerate() {
                    assert!(t[i] < x && x < t[i + k], "seed {seed} p {p}: ξ_{i} = {x}");
                }
                schoenberg_whitney(&t, &kv, "test").expect("interlaced knots");
                // ∫ M_j h = 0 for h = ±1 changing sign at every ξ, integrated piece by piece
                // between all parameters and knots with p + 1 Gauss nodes (exact).
                let mut breaks: Vec<f64> = t.iter().chain(xi).copied().collect();
                breaks.sort_by(f64::total_cmp);
                let gl = crate::GaussLegendre::new(k);
                let (nodes, weights) = (gl.nodes(), gl.weights());
                for j in 0..n - k {
                    let mut f = 0.0;
                    for w in breaks.windows(2) {
                        let (a, b) = (w[0], w[1]);
                        let sign = if xi.iter().filter(|&&x| x <= a).count() % 2 == 0 { 1.0 } else { -1.0 };
                        let (mid, half) = (0.5 * (a + b), 0.5 * (b - a));
                        f += sign
                            * half
                            * nodes
                                .iter()
                                .zip(weights)
                                .map(|(&s, &g)| g * unit_bspline(&t, p, j, mid + half * s))
                                .sum::<f64>();
                    }
                    // The Newton tolerance is 1e-12 on areas of order 1.
                    assert!(f.abs() < 1e-11, "seed {seed} p {p} j {j}: {f}");
                }
            }
        }
    }

    #[test]
    fn optimal_knots_are_symmetric_and_near_not_a_knot_on_uniform_data() {
        for seed in 0..20u64 {
            let n = 5 + (seed as usize % 25);
            let t = random_params(seed, n);
            let rev: Vec<f64> = t.iter().rev().map(|x| 1.0 - x).collect();
            for p in 2..=4usize.min(n - 1) {
                let (a, b) = (optimal_knots(&t, p).expect("valid"), optimal_knots(&rev, p).expect("valid"));
                let (ka, kb) = (a.as_slice(), b.as_slice());
                for i in 0..ka.len() {
                    // Converged to 1e-12 in the areas, from mirrored starts: knots agree to ~1e-12.
                    assert_near!(ka[i], 1.0 - kb[ka.len() - 1 - i], 1e-10, "seed {seed} p {p}");
                }
            }
        }
        // Uniform parameters, cubic: close to the not-a-knot knots t_2..t_{n-3} (within a tenth
        // of the spacing; 9 points: 0.2417, 0.3731, 1/2, ... against 1/4, 3/8, 1/2, ...).
        for n in [6usize, 9, 17, 40] {
            let t: Vec<f64> = (0..n).map(|i| i as f64 / (n - 1) as f64).collect();
            let kv = optimal_knots(&t, 3).expect("valid");
            for (x, nak) in kv.as_slice()[4..n].iter().zip(&t[2..n - 2]) {
                assert!((x - nak).abs() < 0.1 / (n - 1) as f64, "n {n}: {x} vs {nak}");
            }
        }
        // Degree 1: the data parameters (the polyline); 4 points of degree 3: no interior knot.
        let t = random_params(3, 7);
        assert_eq!(optimal_knots(&t, 1).expect("valid"), averaging_knots(&t, 1).expect("valid"));
        assert_eq!(optimal_knots(&t[..4], 3).expect("valid").as_slice().len(), 8);
        assert!(matches!(optimal_knots(&t[..3], 3), Err(NurbsError::TooFewPoints { .. })));
    }

    #[test]
    fn interpolation_on_optimal_knots_reproduces_polynomials_of_the_degree() {
        // Any spline space of degree p contains the polynomials of degree p, so interpolation at
        // distinct parameters must return a cubic curve exactly.
        let cubic =
            |s: f64| crate::Vec3::new(1.0 + 2.0 * s - 3.0 * s * s + 5.0 * s.powi(3), s.powi(3) - s, 0.5 * s * s);
        for seed in 0..10u64 {
            let t = random_params(seed, 6 + seed as usize);
            let kv = optimal_knots(&t, 3).expect("valid");
            let q: Vec<crate::Vec3> = t.iter().map(|&s| cubic(s)).collect();
            let c = crate::fit::interpolate_curve(&q, 3, &t, &kv).expect("valid");
            for i in 0..=100 {
                let s = i as f64 / 100.0;
                // Well-conditioned banded solve on coordinates of size ~5.
                assert_near!(c.point(s), cubic(s), 1e-12, "seed {seed} at {s}");
            }
        }
    }

    #[test]
    fn placement_is_centred_and_reduces_to_averaging() {
        // Uniform data, 9 points, 5 control points of degree 2: resampled parameters
        // 0, 1/4, 1/2, 3/4, 1 and knots their pairwise means 3/8, 5/8, symmetric about 1/2
        // (eq. 9.69 gives T(2), T(5) = 1/4, 5/8: mean 7/16, biased toward 0).
        let t: Vec<f64> = (0..9).map(|k| k as f64 / 8.0).collect();
        let kv = approximation_knots(&t, 5, 2).expect("valid");
        // A few roundings of values in [0, 1].
        assert_near!(kv.as_slice()[3], 3.0 / 8.0, 1e-15);
        assert_near!(kv.as_slice()[4], 5.0 / 8.0, 1e-15);
        // With as many control points as points it is the averaging knot vector of eq. 9.8.
        for seed in 0..20u64 {
            let t = random_params(seed, 12);
            let a = approximation_knots(&t, 12, 3).expect("valid");
            let b = averaging_knots(&t, 3).expect("valid");
            for (x, y) in a.as_slice().iter().zip(b.as_slice()) {
                assert_near!(*x, *y, 1e-15);
            }
        }
    }

    #[test]
    fn least_squares_stays_well_conditioned_up_to_interpolation() {
        // The centred T(j d - 1/2) placement made the normal equations nearly singular as the
        // control points approached the points (smallest singular value of the collocation
        // matrix 2e-12 at 62 of 62); the resampled averages keep it near 0.1 (measured with
        // numpy). The solver refuses pivots below 1e-12 of their diagonal, so every count must
        // factor.
        for seed in 0..10u64 {
            let m = 30 + seed as usize * 4;
            let t = random_params(seed, m);
            for n_ctrl in (m - 4..=m).chain([m / 2, m * 3 / 4]) {
                let kv = approximation_knots(&t, n_ctrl, 3).expect("valid");
                crate::fit::LeastSquaresSolver::new(&t, &kv)
                    .unwrap_or_else(|e| panic!("seed {seed}: {n_ctrl} of {m} points: {e}"));
            }
        }
    }

    #[test]
    fn schoenberg_whitney_detects_empty_supports() {
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 0.5, 0.6, 1.0, 1.0]).expect("valid");
        // Degree 1: hats N_0 on [0, 0.5], N_1 on [0, 0.6], N_2 on [0.5, 1], N_3 on [0.6, 1].
        // Three parameters cannot serve four functions; with four, N_1 needs one in (0, 0.6).
        assert!(schoenberg_whitney(&[0.0, 0.55, 1.0], &kv, "t").is_err());
        assert!(schoenberg_whitney(&[0.0, 0.3, 0.55, 1.0], &kv, "t").is_ok());
        assert!(schoenberg_whitney(&[0.0, 0.3, 0.7, 0.8, 1.0], &kv, "t").is_ok());
        assert!(schoenberg_whitney(&[0.0, 0.7, 0.8, 0.9, 1.0], &kv, "t").is_err());
    }

    #[test]
    fn knot_choice_pairs_universal_with_uniform() {
        let t = crate::fit::param::universal_params(8, 3, "t").expect("valid");
        let kv = knots_for_interpolation(&t, 3, Parameterization::Universal).expect("valid");
        assert_eq!(kv, KnotVector::uniform(3, 8).expect("valid"));
        let ka = knots_for_approximation(&t, 6, 3, Parameterization::Universal).expect("valid");
        assert_eq!(ka, KnotVector::uniform(3, 6).expect("valid"));
        assert!(matches!(
            approximation_knots(&t, 9, 3),
            Err(NurbsError::BadControlPointCount { count: 9, min: 4, max: 8, .. })
        ));
        assert!(matches!(approximation_knots(&t, 3, 3), Err(NurbsError::BadControlPointCount { .. })));
    }
}
