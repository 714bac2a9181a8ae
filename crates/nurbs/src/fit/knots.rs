//! Knot vectors for fitting: averaging (interpolation), symmetric placement (least squares),
//! uniform (paired with universal parameters), and the Schoenberg-Whitney check.

use super::Parameterization;
use crate::{KnotVector, NurbsError};

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

/// The knot vector to interpolate data with parameters `params` of the given kind: uniform for
/// [`Parameterization::Universal`] (the pairing that defines the universal parameters: on the
/// uniform clamped knots each `t_k` is the maximum of `N_{k,p}`), averaging (eq. 9.8) otherwise.
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
        _ => averaging_knots(params, degree),
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
