//! A polynomial (non-rational) B-spline surface within a tolerance of a rational one, for
//! receiving systems that drop the weights of IGES entity 128 or STEP's rational B-splines.
//!
//! The rest of this module's documentation is on [`polynomial_approximation`], where the library's users read it.

use nurbs::fit::LeastSquaresSolver;
use nurbs::{KnotVector, NurbsSurface};
use rayon::prelude::*;

use crate::{ExportToleranceKind, HullError};

/// Smallest tolerance accepted, relative to the diagonal of the control-net box: ten thousand
/// times the rounding of a coordinate.
pub const MIN_POLYNOMIAL_TOLERANCE_REL: f64 = 1e-12;

/// The largest error measured on the check grid must be at most this times the tolerance:
/// the error of a degree-`p` fit oscillates with at most `p + 1` extrema per span, which the
/// check grid's `4 (p + 1)` points per span sample at least four times per period, so a peak
/// between them is at most `1 / cos(pi / 4) = sqrt 2` times the sampled maximum.
pub const SAMPLED_FACTOR: f64 = std::f64::consts::FRAC_1_SQRT_2;

/// Largest control-point count per direction before the approximation gives up.
pub const MAX_CONTROL_POINTS: usize = 4096;

/// A polynomial surface close to a rational one, and how close.
#[derive(Clone, Debug, PartialEq)]
pub struct PolynomialApproximation {
    /// The surface, every weight 1.
    pub surface: NurbsSurface,
    /// Largest `|S(u, v) - P(u, v)|` on the check grid (0 when exact), at most
    /// `tolerance / sqrt 2`.
    pub max_deviation: f64,
    /// True if the source's weights were all equal: the same surface, no approximation.
    pub exact: bool,
    /// Points of the check grid (0 when exact).
    pub check_points: usize,
    /// Rounds of knot insertion.
    pub refinements: usize,
}

/// The distinct knots of `k` (domain ends included).
fn breaks(k: &KnotVector) -> Vec<f64> {
    let (a, b) = k.domain();
    let mut out = vec![a];
    for &x in k.as_slice() {
        if x > a && x < b && out.last().is_some_and(|&l| x > l) {
            out.push(x);
        }
    }
    out.push(b);
    out
}

/// `per_span - 1` equal steps inside every span of `breaks`, ends shared: the fit's samples
/// (`per_span = p + 2`) or the check grid.
fn spread(breaks: &[f64], steps: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(steps * breaks.len());
    for w in breaks.windows(2) {
        for s in 0..steps {
            out.push(w[0] + (w[1] - w[0]) * s as f64 / steps as f64);
        }
    }
    out.push(breaks[breaks.len() - 1]);
    out
}

/// Index of the span of `breaks` holding `t` (the last span for the end).
fn span_of(breaks: &[f64], t: f64) -> usize {
    breaks[1..breaks.len() - 1].partition_point(|&b| b <= t)
}

/// Least-squares polynomial net on `ku` x `kv` through samples of `s` (see [`polynomial_approximation`]).
fn fit(s: &NurbsSurface, ku: &KnotVector, kv: &KnotVector) -> Result<NurbsSurface, HullError> {
    let fail = |e: nurbs::NurbsError| HullError::Fit { method: "polynomial approximation", reason: e };
    let pu = spread(&breaks(ku), ku.degree() + 1);
    let pv = spread(&breaks(kv), kv.degree() + 1);
    let su = LeastSquaresSolver::new(&pu, ku).map_err(fail)?;
    let sv = LeastSquaresSolver::new(&pv, kv).map_err(fail)?;
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    // Along u for every sampled v: rows[b][i].
    let rows: Vec<Vec<[f64; 3]>> = pv
        .par_iter()
        .map(|&v| {
            let data: Vec<[f64; 3]> = pu.iter().map(|&u| s.point(u, v).to_array()).collect();
            su.solve(&data)
        })
        .collect::<Result<_, _>>()
        .map_err(fail)?;
    // Along v through the intermediate points, for every i.
    let cols: Vec<Vec<[f64; 3]>> = (0..nu)
        .into_par_iter()
        .map(|i| {
            let data: Vec<[f64; 3]> = rows.iter().map(|r| r[i]).collect();
            sv.solve(&data)
        })
        .collect::<Result<_, _>>()
        .map_err(fail)?;
    let mut pts = Vec::with_capacity(nu * nv);
    for col in &cols {
        pts.extend(col.iter().map(|&c| nurbs::Vec3::from_array(c)));
    }
    NurbsSurface::try_new(ku.clone(), kv.clone(), &pts, None).map_err(fail)
}

/// The error of the fit in each direction alone, per knot span: along u, the largest
/// `|S(u, v) - C_v(u)|` over the check grid, `C_v` the least-squares polynomial curve on `ku`
/// through the samples of the iso-curve `S(., v)` (for every check `v`); along v likewise.
/// The tensor-product fit's error is about their sum, so a direction whose error is small
/// needs no knots.
fn directional_errors(
    s: &NurbsSurface,
    ku: &KnotVector,
    kv: &KnotVector,
    cu: &[f64],
    cv: &[f64],
) -> Result<(Vec<f64>, Vec<f64>), HullError> {
    let fail = |e: nurbs::NurbsError| HullError::Fit { method: "polynomial approximation", reason: e };
    // Errors along `k` (a knot vector of the first parameter of `eval`) for every `other`.
    let along = |k: &KnotVector, checks: &[f64], others: &[f64], eval: &(dyn Fn(f64, f64) -> nurbs::Vec3 + Sync)| {
        let b = breaks(k);
        let params = spread(&b, k.degree() + 1);
        let solver = LeastSquaresSolver::new(&params, k).map_err(fail)?;
        let per_line: Vec<Vec<f64>> = others
            .par_iter()
            .map(|&o| {
                let data: Vec<[f64; 3]> = params.iter().map(|&t| eval(t, o).to_array()).collect();
                let ctrl: Vec<nurbs::Vec3> = solver.solve(&data)?.into_iter().map(nurbs::Vec3::from_array).collect();
                let curve = nurbs::NurbsCurve::try_new(k.clone(), &ctrl, None)?;
                let mut e = vec![0.0f64; b.len() - 1];
                for &t in checks {
                    let i = span_of(&b, t);
                    e[i] = e[i].max(eval(t, o).distance(curve.point(t)));
                }
                Ok(e)
            })
            .collect::<Result<_, nurbs::NurbsError>>()
            .map_err(fail)?;
        Ok::<Vec<f64>, HullError>((0..b.len() - 1).map(|i| per_line.iter().fold(0.0f64, |m, e| m.max(e[i]))).collect())
    };
    let eu = along(ku, cu, cv, &|u, v| s.point(u, v))?;
    let ev = along(kv, cv, cu, &|v, u| s.point(u, v))?;
    Ok((eu, ev))
}

/// A polynomial surface within `tolerance` (a length in the surface's unit) of `s` (see
/// [Method](#method) below).
///
/// # Method
///
/// When every weight is the same, `S(u, v) = sum N_i N_j w P_ij / sum N_i N_j w = sum N_i N_j
/// P_ij` (partition of unity), so the same net with unit weights is the same surface: exact.
///
/// Otherwise the rational surface is approximated by least squares on its own parameters,
/// keeping its degrees and starting from its knots (The NURBS Book 9.4.1, fitted first along u
/// for every sampled v, then along v through the resulting control points, as in the
/// tensor-product fits of 9.4.3; the boundary curves' end points are interpolated):
///
/// 1. sample `S` at `p + 2` equally spaced parameters per knot span in u (ends shared), the
///    same in v with `q + 2`, and fit the polynomial net `P_ij` with the current knots;
/// 2. measure `e = |S(u, v) - P(u, v)|` on a check grid with three points between every two
///    samples, an upper bound on the distance between the surfaces at those points (the
///    same parameters on both; the closest points can only be nearer);
/// 3. insert the midpoint of every knot span in which the error exceeds the tolerance (in u
///    where the fit along u alone errs by more than half of it, likewise in v, or both
///    directions of the offending cells when neither does), and fit again, until no check
///    point exceeds `tolerance / sqrt 2` (`SAMPLED_FACTOR`: the margin for the peaks between
///    check points).
///
/// The error of a degree-`p` fit falls as `h^(p+1)` with the span length `h`, so each round
/// halves the offending spans and divides their error by about `2^(p+1)`.
///
/// # Errors
/// [`HullError::ExportTolerance`] if `tolerance` is not a positive finite number or would need more
/// than [`MAX_CONTROL_POINTS`] control points in a direction; [`HullError::Fit`] if a
/// least-squares system fails (cannot happen with the samples used, which satisfy the
/// Schoenberg-Whitney condition).
pub fn polynomial_approximation(s: &NurbsSurface, tolerance: f64) -> Result<PolynomialApproximation, HullError> {
    let (lo, hi) = s.control_bounds();
    let floor = MIN_POLYNOMIAL_TOLERANCE_REL * (hi - lo).norm();
    if !(tolerance.is_finite() && tolerance > 0.0 && tolerance >= floor) {
        return Err(HullError::ExportTolerance {
            tolerance,
            kind: ExportToleranceKind::ApproximationFloor { floor, relative: MIN_POLYNOMIAL_TOLERANCE_REL },
        });
    }
    let w = s.weights();
    if w.iter().all(|&x| x == w[0]) {
        let surface = NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &s.control_points(), None)
            .map_err(|e| HullError::Fit { method: "polynomial approximation", reason: e })?;
        return Ok(PolynomialApproximation {
            surface,
            max_deviation: 0.0,
            exact: true,
            check_points: 0,
            refinements: 0,
        });
    }
    let (mut ku, mut kv) = (s.knots_u().clone(), s.knots_v().clone());
    let mut refinements = 0;
    loop {
        let approx = fit(s, &ku, &kv)?;
        let (bu, bv) = (breaks(&ku), breaks(&kv));
        let cu = spread(&bu, 4 * (ku.degree() + 1));
        let cv = spread(&bv, 4 * (kv.degree() + 1));
        // Largest error per (u span, v span).
        let errors: Vec<(usize, usize, f64)> = cu
            .par_iter()
            .flat_map_iter(|&u| {
                let (approx, bu, bv) = (&approx, &bu, &bv);
                cv.iter().map(move |&v| (span_of(bu, u), span_of(bv, v), s.point(u, v).distance(approx.point(u, v))))
            })
            .collect();
        let max_deviation = errors.iter().fold(0.0f64, |m, e| m.max(e.2));
        if max_deviation <= SAMPLED_FACTOR * tolerance {
            return Ok(PolynomialApproximation {
                surface: approx,
                max_deviation,
                exact: false,
                check_points: errors.len(),
                refinements,
            });
        }
        // Split the spans whose one-directional error exceeds half the tolerance; if none
        // does, every span of every offending cell.
        let (eu, ev) = directional_errors(s, &ku, &kv, &cu, &cv)?;
        let half = 0.5 * SAMPLED_FACTOR * tolerance;
        let mut split_u: Vec<bool> = eu.iter().map(|&e| e > half).collect();
        let mut split_v: Vec<bool> = ev.iter().map(|&e| e > half).collect();
        if !split_u.iter().chain(&split_v).any(|&b| b) {
            for &(i, j, e) in &errors {
                if e > SAMPLED_FACTOR * tolerance {
                    split_u[i] = true;
                    split_v[j] = true;
                }
            }
        }
        let insert = |k: &KnotVector, b: &[f64], split: &[bool]| -> Result<KnotVector, HullError> {
            let mut knots = k.as_slice().to_vec();
            for (w, _) in b.windows(2).zip(split).filter(|(_, &s)| s) {
                knots.push(0.5 * (w[0] + w[1]));
            }
            knots.sort_by(f64::total_cmp);
            KnotVector::try_new(k.degree(), knots)
                .map_err(|e| HullError::Fit { method: "polynomial approximation", reason: e })
        };
        ku = insert(&ku, &bu, &split_u)?;
        kv = insert(&kv, &bv, &split_v)?;
        refinements += 1;
        if ku.num_basis() > MAX_CONTROL_POINTS || kv.num_basis() > MAX_CONTROL_POINTS {
            return Err(HullError::ExportTolerance {
                tolerance,
                kind: ExportToleranceKind::ControlPoints {
                    max: MAX_CONTROL_POINTS,
                    refinements,
                    deviation: max_deviation,
                },
            });
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::fixtures::quarter_cylinder_along_x;
    use nurbs::Vec3;

    #[test]
    fn equal_weights_are_exact() {
        let ku = KnotVector::uniform(3, 6).expect("valid");
        let kv = KnotVector::uniform(2, 4).expect("valid");
        let pts: Vec<Vec3> = (0..24).map(|k| Vec3::new(k as f64, (k * k % 7) as f64, (k % 5) as f64)).collect();
        let s = NurbsSurface::try_new(ku, kv, &pts, Some(&[2.5; 24])).expect("valid");
        let a = polynomial_approximation(&s, 1e-9).expect("exact");
        assert!(a.exact && a.max_deviation == 0.0 && !a.surface.is_rational());
        assert!(a.surface.weights().iter().all(|&w| w == 1.0));
        for (u, v) in [(0.1, 0.2), (0.5, 0.5), (0.93, 0.07), (1.0, 1.0)] {
            // Only rounding differs between the rational and the polynomial evaluation.
            assert!(s.point(u, v).distance(a.surface.point(u, v)) < 1e-12);
        }
    }

    #[test]
    fn the_cylinder_is_approximated_to_the_tolerance() {
        let r = 2.0;
        let s = quarter_cylinder_along_x(r, 4.0);
        for tol in [1e-3, 1e-5, 1e-7] {
            let a = polynomial_approximation(&s, tol).expect("approximates");
            assert!(!a.exact && !a.surface.is_rational());
            assert!(a.max_deviation <= SAMPLED_FACTOR * tol);
            // Independent check off the check grid: distance to the cylinder y^2 + z^2 = r^2
            // at 400 other parameters, within the tolerance (the sqrt 2 margin covers the
            // peaks between check points).
            let mut worst = 0.0f64;
            for a_ in 0..20 {
                for b_ in 0..20 {
                    let (u, v) = ((a_ as f64 + 0.37) / 20.0, (b_ as f64 + 0.61) / 20.0);
                    let p = a.surface.point(u, v);
                    worst = worst.max(((p.y * p.y + p.z * p.z).sqrt() - r).abs());
                }
            }
            assert!(worst <= tol, "tolerance {tol}: radius off by {worst}");
            // Corners interpolated (fixed ends of the least squares).
            assert!(a.surface.point(0.0, 0.0).distance(s.point(0.0, 0.0)) < 1e-12);
            assert!(a.surface.point(1.0, 1.0).distance(s.point(1.0, 1.0)) < 1e-12);
            // Straight along v: no knot is needed there.
            assert_eq!(a.surface.n_v(), 2);
        }
        // Quadratic error h^3: 100 times tighter needs about 100^(1/3) ~ 4.6 times the spans.
        let coarse = polynomial_approximation(&s, 1e-3).expect("ok").surface.n_u();
        let fine = polynomial_approximation(&s, 1e-5).expect("ok").surface.n_u();
        assert!(fine > 2 * coarse && fine < 12 * coarse, "{coarse} -> {fine} control points");
    }

    #[test]
    fn bad_tolerances_are_refused() {
        let s = quarter_cylinder_along_x(1.0, 4.0);
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-300] {
            let e = polynomial_approximation(&s, t).expect_err("refused");
            assert!(
                matches!(
                    e,
                    HullError::ExportTolerance { kind: crate::ExportToleranceKind::ApproximationFloor { .. }, .. }
                ),
                "{t}: {e}"
            );
            assert!(e.to_string().starts_with("approximation tolerance "), "{e}");
        }
    }
}
