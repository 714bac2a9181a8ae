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
/// control points of degree `p`: The NURBS Book eq. 9.68-9.69 in a form symmetric under
/// reversal of the data.
///
/// Write `T(x)` for the piecewise-linear interpolant of the parameters over their index,
/// `T(k) = t_k`. Eq. 9.69, with `d = (m + 1)/(n - p + 1)`, `i = floor(j d)`, `alpha = j d - i`,
/// sets `u_{p+j} = (1 - alpha) t_{i-1} + alpha t_i = T(j d - 1)`. Applied to the reversed data and
/// mirrored back it gives `T(j d)` instead: the book's formula is biased by half an index
/// toward `t_0`. This function uses the centred
///
/// `u_{p+j} = T(j d - 1/2)`, `j = 1..=n-p`,
///
/// which is symmetric (mirrored data give mirrored knots). Consecutive interior knots sit
/// `d > 1` index units apart, so every interior knot span holds a parameter strictly inside
/// it, and the end spans hold `t_0` and `t_m`: each span holds at least one `t_k`, as eq. 9.69
/// ensures. Schoenberg-Whitney holds too: in index units the support of `N_{i,p}` is
/// `(y_{i-p}, y_{i+1})` with `y_j = j d - 1/2` (0 and `m` beyond the ends), and the greedy
/// choice `k_i = max(k_{i-1} + 1, smallest integer > y_{i-p})` stays below `y_{i+1}` because
/// `(i - j)(d - 1) + (p + 1) d - 2 > 0`, and below `m` for `i < n` because
/// `(n - j + 1)(d - 1) + 1/2 > 0`. It is still verified ([`schoenberg_whitney`]). The
/// knots depend linearly on the parameters, so the knots of averaged parameters are the average
/// of the knots (used by skinning). For `n = m` the system is square: interpolation with these
/// knots.
///
/// # Errors
/// [`NurbsError::BadControlPointCount`] unless `degree + 1 <= n_ctrl <= params.len()`,
/// [`NurbsError::BadDegree`], [`NurbsError::DecreasingParameters`] unless `params` strictly
/// increase. [`NurbsError::SingularSystem`] (Schoenberg-Whitney failing) is a guard that the
/// argument above rules out for strictly increasing parameters.
pub fn approximation_knots(params: &[f64], n_ctrl: usize, degree: usize) -> Result<KnotVector, NurbsError> {
    check_degree(degree)?;
    let count = params.len();
    check_ctrl_count(n_ctrl, count, degree, "least-squares knot placement")?;
    check_params(params, true, "approximation parameters")?;
    let p = degree;
    let interior = n_ctrl - p - 1;
    let d = count as f64 / (interior + 1) as f64;
    let t = |x: f64| -> f64 {
        // 0 <= x <= count - 1 holds for x = j d - 1/2 with 1 <= j <= interior.
        let i = (x.floor() as usize).min(count - 2);
        let alpha = x - i as f64;
        (1.0 - alpha) * params[i] + alpha * params[i + 1]
    };
    let mut k = Vec::with_capacity(n_ctrl + p + 1);
    k.extend(std::iter::repeat_n(params[0], p + 1));
    k.extend((1..=interior).map(|j| t(j as f64 * d - 0.5)));
    k.extend(std::iter::repeat_n(params[count - 1], p + 1));
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
                    // Every interior span contains a parameter strictly inside, the end spans
                    // at least t_0 or t_m, and Schoenberg-Whitney holds.
                    for w in ka[p..len - p].windows(2) {
                        let interior = w[0] > t[0] && w[1] < t[m - 1];
                        let has = |x: f64| if interior { w[0] < x && x < w[1] } else { w[0] <= x && x <= w[1] };
                        assert!(t.iter().any(|&x| has(x)), "empty span {w:?}");
                    }
                    schoenberg_whitney(&t, &a, "test").expect("placement satisfies Schoenberg-Whitney");
                }
            }
        }
    }

    #[test]
    fn book_formula_is_biased_and_ours_is_not() {
        // Uniform data: the centred formula gives the uniform knots exactly when d is an
        // integer; 9 points, 5 control points of degree 2: d = 9/3 = 3, knots T(2.5), T(5.5).
        let t: Vec<f64> = (0..9).map(|k| k as f64 / 8.0).collect();
        let kv = approximation_knots(&t, 5, 2).expect("valid");
        assert_near!(kv.as_slice()[3], 2.5 / 8.0, 1e-15);
        assert_near!(kv.as_slice()[4], 5.5 / 8.0, 1e-15);
        // Their mean is 1/2: symmetric about the middle, where eq. 9.69 gives T(2), T(5), mean 7/16.
        assert_near!(kv.as_slice()[3] + kv.as_slice()[4], 1.0, 1e-15);
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
