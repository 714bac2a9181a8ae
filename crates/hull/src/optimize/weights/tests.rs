//! Tests of the weight objective: values and Jacobians against finite differences, exact
//! recovery of rational shapes, the modes and layouts, and the fairness term.

use super::*;
use crate::optimize::evaluate_all;
use crate::{fit_offsets, series60_sample, FitConfig, FitOutcome};
use nurbs::assert_near;
use nurbs::basis::basis_funs;
use nurbs::{NurbsError, MAX_DEGREE};

fn sample_fit(ctrl: (usize, usize)) -> (FitOutcome, Offsets) {
    let offsets = series60_sample();
    let cfg = FitConfig { ctrl: Some(ctrl), ..FitConfig::default() };
    (fit_offsets(&offsets, &cfg).expect("sample fits"), offsets)
}

pub(super) fn problem(ctrl: (usize, usize), mode: WeightMode, layout: WeightLayout, reg: f64) -> WeightProblem {
    let (fit, offsets) = sample_fit(ctrl);
    let opts = WeightOptions { mode, layout, regularization: reg, ..WeightOptions::default() };
    WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match")
}

/// Deterministic pseudo-random numbers in [-0.5, 0.5).
pub(super) fn noise(seed: &mut u64) -> f64 {
    *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
}

fn points_and_params(fit: &FitOutcome, offsets: &Offsets) -> (Vec<Vec3>, Vec<(f64, f64)>) {
    let pts = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
    (pts, fit.params.iter().flatten().copied().collect())
}

#[test]
fn fixed_mode_at_the_start_is_the_plain_approximations_parametric_rms() {
    let (fit, offsets) = sample_fit((6, 12));
    let (pts, params) = points_and_params(&fit, &offsets);
    let rms = (pts.iter().zip(&params).map(|(q, &(u, v))| (fit.surface.point(u, v) - *q).norm_squared()).sum::<f64>()
        / pts.len() as f64)
        .sqrt();
    let p = WeightProblem::from_fit(&fit, &offsets, WeightOptions { mode: WeightMode::Fixed, ..Default::default() })
        .expect("shapes match");
    let f = p.value(&p.start());
    // Same sums in a different order (A4.3 vs. the precomputed products): round-off only.
    assert!((f - rms).abs() <= 1e-12 * rms, "{f} vs {rms}");
    assert!(rms > 1e-3, "the 6 x 12 approximation must leave an error to optimise: {rms}");
}

#[test]
fn resolved_mode_at_the_start_is_the_least_squares_optimum() {
    let (fit, offsets) = sample_fit((6, 12));
    let (pts, params) = points_and_params(&fit, &offsets);
    let resolved = WeightProblem::from_fit(&fit, &offsets, WeightOptions::default()).expect("ok");
    let fixed =
        WeightProblem::from_fit(&fit, &offsets, WeightOptions { mode: WeightMode::Fixed, ..Default::default() })
            .expect("ok");
    let (fr, ff) = (resolved.value(&resolved.start()), fixed.value(&fixed.start()));
    // One least-squares solve over all offsets beats the two-stage skinning at the same
    // parameters (and strictly: skinning interpolates the end sections).
    assert!(fr < ff, "resolved {fr} fixed {ff}");
    // Optimality: H^T e = 0, i.e. sum_k B_kc (S_k - Q_k) = 0 for every control point c,
    // measured with the kernel's own evaluation of the resolved surface.
    let s = resolved.surface(&resolved.start()).expect("regular");
    assert!(!s.is_rational());
    let (n_u, n_v) = resolved.ctrl();
    let mut normal = vec![Vec3::ZERO; n_u * n_v];
    let mut scale = 0.0;
    for (q, &(u, v)) in pts.iter().zip(&params) {
        let e = s.point(u, v) - *q;
        let (su, sv) = (s.knots_u().find_span(u), s.knots_v().find_span(v));
        let (mut bu, mut bv) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
        basis_funs(s.knots_u().as_slice(), su, u, s.degree_u(), &mut bu);
        basis_funs(s.knots_v().as_slice(), sv, v, s.degree_v(), &mut bv);
        for a in 0..=s.degree_u() {
            for b in 0..=s.degree_v() {
                normal[(su - s.degree_u() + a) * n_v + sv - s.degree_v() + b] += e * (bu[a] * bv[b]);
            }
        }
        scale += q.norm();
    }
    let worst = normal.iter().map(|g| g.norm()).fold(0.0, f64::max);
    // The normal equations are solved to about cond(G) ~ 1e4 ulps of the data's size.
    assert!(worst <= 1e-10 * scale, "H^T e = {worst:e} against {scale:e}");
}

#[test]
fn value_is_the_rms_of_the_kernels_rational_surface() {
    let (fit, offsets) = sample_fit((6, 12));
    let (pts, params) = points_and_params(&fit, &offsets);
    let mut seed = 5;
    for mode in [WeightMode::Fixed, WeightMode::Resolved] {
        for layout in [WeightLayout::Full, WeightLayout::RankOne] {
            let opts = WeightOptions { mode, layout, regularization: 0.0, ..Default::default() };
            let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("ok");
            let x: Vec<f64> = (0..p.dim()).map(|_| noise(&mut seed)).collect();
            let s = p.surface(&x).expect("regular");
            let w = p.weights(&x);
            assert_eq!(s.weights().len(), w.len());
            for (a, b) in s.weights().iter().zip(&w) {
                assert!((a - b).abs() <= 1e-15 * b, "{a} {b}");
            }
            let rms = (pts.iter().zip(&params).map(|(q, &(u, v))| (s.point(u, v) - *q).norm_squared()).sum::<f64>()
                / pts.len() as f64)
                .sqrt();
            let f = p.value(&x);
            // Homogeneous round trip and re-ordered sums: round-off.
            assert!((f - rms).abs() <= 1e-10 * rms, "{mode:?} {layout:?}: {f} vs {rms}");
            if mode == WeightMode::Fixed {
                // The plain approximation's control points are kept.
                for (a, b) in s.control_points().iter().zip(fit.surface.control_points()) {
                    assert!((*a - b).norm() <= 1e-12 * p.size());
                }
            }
        }
    }
}

#[test]
fn rank_one_weights_are_products_and_the_scale_gauge_changes_nothing() {
    let p = problem((6, 12), WeightMode::Resolved, WeightLayout::RankOne, 0.0);
    let (n_u, n_v) = p.ctrl();
    assert_eq!(p.dim(), n_u + n_v);
    let x: Vec<f64> = (0..p.dim()).map(|i| 0.1 * i as f64 - 0.4).collect();
    let w = p.weights(&x);
    for i in 0..n_u {
        for j in 0..n_v {
            let want = (x[i] + x[n_u + j]).exp();
            assert!((w[i * n_v + j] - want).abs() <= 1e-15 * want);
        }
    }
    // Each product stays within the bounds: the factors are boxed to half the log range.
    assert!((p.upper()[0] - 0.5 * 10f64.ln()).abs() < 1e-15);
    // (α + t, β - t) is the same weight grid; all weights times e^t the same surface.
    let f0 = p.value(&x);
    let shifted: Vec<f64> = x.iter().enumerate().map(|(i, &t)| if i < n_u { t + 0.3 } else { t - 0.3 }).collect();
    assert!((p.value(&shifted) - f0).abs() <= 1e-12 * f0);
    let full = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
    let f_start = full.value(&full.start());
    assert!((full.value(&vec![0.7; full.dim()]) - f_start).abs() <= 1e-12 * f_start);
}

/// Central differences of `g` at `x` in direction `i`, step `h`.
fn central(g: &dyn Fn(&[f64]) -> Vec<f64>, x: &[f64], i: usize, h: f64) -> Vec<f64> {
    let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
    xp[i] += h;
    xm[i] -= h;
    g(&xp).iter().zip(g(&xm)).map(|(a, b)| (a - b) / (2.0 * h)).collect()
}

#[test]
fn jacobians_match_central_differences() {
    let mut seed = 17;
    // Without and with the fairness and smoothing terms (their rows join the residuals).
    for (layout, fair) in [
        (WeightLayout::Full, 0.0),
        (WeightLayout::RankOne, 0.0),
        (WeightLayout::Full, 0.05),
        (WeightLayout::RankOne, 0.05),
    ] {
        for mode in [WeightMode::Fixed, WeightMode::Resolved] {
            let p = problem((5, 8), mode, layout, 1e-3).with_fairness(fair, fair / 10.0).expect("usable");
            let x: Vec<f64> = (0..p.dim()).map(|_| 0.8 * noise(&mut seed)).collect();
            let r = |x: &[f64]| p.residuals(x).expect("regular");
            let kinds: &[JacobianKind] = if mode == WeightMode::Fixed {
                &[JacobianKind::Kaufman]
            } else {
                &[JacobianKind::Exact, JacobianKind::Kaufman]
            };
            for &kind in kinds {
                let lin = p.residuals_and_jacobian(&x, kind).expect("regular");
                assert_eq!(lin.residuals, r(&x));
                let jmax = (0..lin.cols).map(|j| dot_norm(lin.column(j))).fold(0.0, f64::max);
                for i in 0..p.dim() {
                    let fd = central(&r, &x, i, 1e-5);
                    let col = lin.column(i);
                    // Fixed mode (no projection) and the exact Golub-Pereyra Jacobian are
                    // the true derivative: central differences agree to O(h^2) + round-off
                    // / h, about 1e-8 of the largest column.
                    if mode == WeightMode::Fixed || kind == JacobianKind::Exact {
                        let err = col.iter().zip(&fd).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                        assert!(err <= 1e-7 * jmax, "{mode:?} {layout:?} {kind:?} col {i}: {err:e} vs {jmax:e}");
                    }
                    // Kaufman's Jacobian is not the derivative, but its gradient J^T r is.
                    let g_fd: f64 = fd.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                    let g: f64 = col.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                    let gscale = jmax * dot_norm(&lin.residuals);
                    assert!((g - g_fd).abs() <= 1e-7 * gscale, "{mode:?} {layout:?} {kind:?} grad {i}");
                }
            }
        }
    }
}

fn dot_norm(v: &[f64]) -> f64 {
    v.iter().map(|t| t * t).sum::<f64>().sqrt()
}

#[test]
fn parameter_columns_match_central_differences() {
    let mut seed = 23;
    for mode in [WeightMode::Fixed, WeightMode::Resolved] {
        let p = problem((5, 8), mode, WeightLayout::Full, 0.0);
        let x: Vec<f64> = (0..p.dim()).map(|_| 0.5 * noise(&mut seed)).collect();
        // Move the parameters off the knots (one-sided derivatives there) a little.
        let params: Vec<(f64, f64)> = p.params().iter().map(|&(u, v)| ((u * 0.98 + 0.01), (v * 0.98 + 0.01))).collect();
        for free in [ParamFreedom::U, ParamFreedom::USectionV, ParamFreedom::UV] {
            let lin = p.residuals_and_jacobian_with_params(&x, &params, free).expect("regular");
            let d = p.dim();
            assert_eq!(lin.cols, d + p.param_count(free));
            let jmax = (0..lin.cols).map(|j| dot_norm(lin.column(j))).fold(0.0, f64::max);
            let r_of = |t: &[f64]| -> Vec<f64> {
                let pp = p.params_from_vars(&params, t, free);
                p.with_params(&pp).expect("ok").residuals(&x).expect("regular")
            };
            let (t0, lo, hi) = p.param_vars(&params, free);
            assert_eq!(p.params_from_vars(&params, &t0, free), params);
            assert!(t0.iter().zip(&lo).zip(&hi).all(|((t, l), h)| l <= t && t <= h));
            // Every 7th unknown, and all section v's (the last 25 of USectionV).
            for j in (0..t0.len()).filter(|j| j % 7 == 0 || (free == ParamFreedom::USectionV && j + 25 >= t0.len())) {
                let fd = central(&r_of, &t0, j, 1e-6);
                let col = lin.column(d + j);
                // Fixed mode: the true derivative; O(h^2) + round-off / h.
                if mode == WeightMode::Fixed {
                    let err = col.iter().zip(&fd).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                    assert!(err <= 1e-6 * jmax, "{free:?} unknown {j}: {err:e} vs {jmax:e}");
                }
                let g_fd: f64 = fd.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                let g: f64 = col.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                let gscale = jmax * dot_norm(&lin.residuals);
                assert!((g - g_fd).abs() <= 1e-6 * gscale, "{mode:?} {free:?} unknown {j}: {g:e} vs {g_fd:e}");
            }
        }
    }
}

/// The same parameters with every `v` moved to 0 (all offsets on one edge of the domain).
fn at_v0(params: &[(f64, f64)]) -> Vec<(f64, f64)> {
    params.iter().map(|&(u, _)| (u, 0.0)).collect()
}

#[test]
fn the_anchor_keeps_undetermined_control_points_at_the_plain_fit() {
    let (fit, offsets) = sample_fit((6, 12));
    let (pts, params) = points_and_params(&fit, &offsets);
    // All offsets at v = 0: only the first column of control points (j = 0) is determined
    // by the data; the anchor holds the others at the plain approximation's.
    let p = WeightProblem::new(&fit.surface, &pts, &at_v0(&params), WeightOptions::default()).expect("ok");
    assert!(p.value(&p.start()).is_finite());
    let s = p.surface(&p.start()).expect("anchored system is regular");
    let size = p.size();
    for i in 0..s.n_u() {
        for j in 2..s.n_v() {
            // Far from the data the ridge is the whole equation: P = P_0 up to round-off of
            // the factorization (1e-9 of the model size is generous).
            let d = s.control_point(i, j).distance(fit.surface.control_point(i, j));
            assert!(d <= 1e-9 * size, "({i}, {j}) moved {d:e}");
        }
    }
    // Where the offsets determine the points, the anchor changes the fit by a relative
    // amount of order 1e-9: the value at the start matches the unanchored one.
    let anchored = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
    let plain = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions { anchor: 0.0, ..Default::default() })
        .expect("ok");
    let (a, b) = (anchored.value(&anchored.start()), plain.value(&plain.start()));
    assert!((a - b).abs() <= 1e-6 * b, "{a} vs {b}");
}

#[test]
fn singular_systems_give_infinity_not_nan() {
    let (fit, offsets) = sample_fit((6, 12));
    let (pts, params) = points_and_params(&fit, &offsets);
    // Every offset moved to v = 0: most control points have no offset in their support.
    let squashed = at_v0(&params);
    let no_anchor = WeightOptions { anchor: 0.0, ..Default::default() };
    let p = WeightProblem::new(&fit.surface, &pts, &squashed, no_anchor).expect("ok");
    let f = p.value(&p.start());
    assert!(f.is_infinite() && f > 0.0, "{f}");
    assert!(p.residuals(&p.start()).is_none());
    assert!(p.residuals_and_jacobian(&p.start(), JacobianKind::Exact).is_none());
    assert!(matches!(p.surface(&p.start()), Err(HullError::Fit { reason: NurbsError::SingularSystem { .. }, .. })));
    // Fixed mode has no system to solve: finite.
    let fixed = WeightProblem::new(
        &fit.surface,
        &pts,
        &squashed,
        WeightOptions { mode: WeightMode::Fixed, ..Default::default() },
    )
    .expect("ok");
    assert!(fixed.value(&fixed.start()).is_finite());
    // Bad variables are infeasible, not NaN.
    let good = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 1e-6);
    let mut x = good.start();
    x[3] = f64::NAN;
    assert_eq!(good.value(&x), f64::INFINITY);
    assert_eq!(good.value(&x[1..]), f64::INFINITY);
    x[3] = 800.0; // e^800 overflows
    assert_eq!(good.value(&x), f64::INFINITY);
    assert!(good.surface(&x[1..]).is_err());
}

#[test]
fn bad_settings_are_errors() {
    let (fit, offsets) = sample_fit((6, 12));
    for (bounds, reg) in [((0.0, 10.0), 0.0), ((2.0, 10.0), 0.0), ((0.1, f64::INFINITY), 0.0), ((0.1, 10.0), -1.0)] {
        let o = WeightOptions { bounds, regularization: reg, ..Default::default() };
        let e = WeightProblem::from_fit(&fit, &offsets, o).expect_err("refused");
        if reg < 0.0 {
            assert!(matches!(e, HullError::FitSetting { name: "weight regularization", .. }), "{e}");
        } else {
            assert!(matches!(e, HullError::Weights(WeightsKind::Bounds { lo, hi }) if (lo, hi) == bounds), "{e}");
        }
    }
    let (pts, params) = points_and_params(&fit, &offsets);
    assert!(WeightProblem::new(&fit.surface, &pts[1..], &params, WeightOptions::default()).is_err());
    let mut nan = params.clone();
    nan[4].1 = f64::NAN;
    assert!(WeightProblem::new(&fit.surface, &pts, &nan, WeightOptions::default()).is_err());
    let p = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
    assert!(p.with_params(&nan).is_err());
    assert!(p.with_params(&params[1..]).is_err());
    let (_, other) = sample_fit((5, 8));
    assert!(WeightProblem::from_fit(
        &fit,
        &Offsets { sections: other.sections[1..].to_vec(), ..other },
        WeightOptions::default()
    )
    .is_err());
}

#[test]
fn parallel_evaluation_is_bit_identical_to_sequential() {
    let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 1e-6);
    let mut seed = 99;
    let xs: Vec<Vec<f64>> = (0..64).map(|_| (0..p.dim()).map(|_| 2.0 * noise(&mut seed)).collect()).collect();
    let par = evaluate_all(&p, &xs);
    let seq: Vec<f64> = xs.iter().map(|x| p.value(x)).collect();
    assert_eq!(par, seq);
    assert!(seq.iter().all(|f| f.is_finite()));
    // And the value does not depend on what the thread evaluated before.
    assert_eq!(p.value(&xs[7]), seq[7]);
}

#[test]
fn section_runs_assemble_the_same_system_as_single_offsets() {
    let mut seed = 41;
    // (6, 12) is factored in v-major order, (8, 5) in u-major: both run paths.
    for ctrl in [(6, 12), (8, 5)] {
        let (fit, offsets) = sample_fit(ctrl);
        let (pts, params) = points_and_params(&fit, &offsets);
        let grouped = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
        assert_eq!(grouped.table.runs.len(), offsets.sections.len());
        // Interleave the sections: no two consecutive offsets share v, every run is one
        // offset long.
        let n = pts.len();
        let order: Vec<usize> = (0..n).map(|i| (i * 8) % n + (i * 8) / n).collect();
        let mut sorted = order.clone();
        sorted.sort_unstable();
        assert_eq!(sorted, (0..n).collect::<Vec<_>>());
        let pts2: Vec<Vec3> = order.iter().map(|&k| pts[k]).collect();
        let par2: Vec<(f64, f64)> = order.iter().map(|&k| params[k]).collect();
        let single = WeightProblem::new(&fit.surface, &pts2, &par2, WeightOptions::default()).expect("ok");
        assert_eq!(single.table.runs.len(), n);
        for _ in 0..3 {
            let x: Vec<f64> = (0..grouped.dim()).map(|_| 1.5 * noise(&mut seed)).collect();
            let (a, b) = (grouped.value(&x), single.value(&x));
            // The same sums in another order: round-off amplified by cond(G) <~ 1e4.
            assert!((a - b).abs() <= 1e-11 * a, "{ctrl:?}: {a} vs {b}");
            let (sa, sb) = (grouped.surface(&x).expect("ok"), single.surface(&x).expect("ok"));
            for (pa, pb) in sa.control_points().iter().zip(sb.control_points()) {
                assert!((*pa - pb).norm() <= 1e-9 * grouped.size());
            }
        }
    }
}

/// The cases the products' tests sweep: `(8, 5)` is assembled u-major, `(6, 12)` v-major;
/// both layouts; fixed and re-solved control points, the latter also with the fairness term
/// and the log-weight smoothing (a prior with off-diagonal entries).
pub(super) fn product_sweep() -> Vec<((usize, usize), WeightLayout, WeightMode, f64)> {
    let mut cases = Vec::new();
    for ctrl in [(8, 5), (6, 12)] {
        for layout in [WeightLayout::Full, WeightLayout::RankOne] {
            for (mode, fair) in [(WeightMode::Fixed, 0.0), (WeightMode::Resolved, 0.0), (WeightMode::Resolved, 0.05)] {
                cases.push((ctrl, layout, mode, fair));
            }
        }
    }
    cases
}

#[test]
fn normal_equations_match_the_dense_jacobians_products() {
    let mut seed = 29;
    // (8, 5) is assembled u-major, (6, 12) v-major; both layouts and modes.
    for (ctrl, layout, mode, fair) in product_sweep() {
        // The identity behind both needs the pure least-squares G = H^T H (+ the
        // fairness term): no anchor (with it, both are the same O(anchor)
        // approximation of the exact terms).
        let (fit, offsets) = sample_fit(ctrl);
        let opts = WeightOptions {
            mode,
            layout,
            regularization: 1e-3,
            anchor: 0.0,
            fair,
            weight_smoothing: fair / 10.0,
            ..Default::default()
        };
        let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match");
        let x: Vec<f64> = (0..p.dim()).map(|_| 0.8 * noise(&mut seed)).collect();
        let lin = p.residuals_and_jacobian(&x, JacobianKind::Kaufman).expect("regular");
        let ne = p.normal_equations(&x).expect("regular");
        let d = p.dim();
        assert_eq!((ne.dim, ne.jtj.len(), ne.jtr.len()), (d, d * d, d));
        // The diagonal alone: the same sums, bit for bit.
        let diag = p.jtj_diagonal(&x).expect("regular");
        assert!((0..d).all(|i| diag[i] == ne.jtj[i * d + i]));
        let diag = (0..d).map(|i| dot_norm(lin.column(i)).powi(2)).fold(0.0, f64::max);
        let gscale = diag.sqrt() * dot_norm(&lin.residuals);
        let mut worst = (0.0f64, 0.0f64);
        for i in 0..d {
            for j in 0..d {
                let dense: f64 = lin.column(i).iter().zip(lin.column(j)).map(|(a, b)| a * b).sum();
                assert_eq!(ne.jtj[i * d + j], ne.jtj[j * d + i], "symmetric");
                worst.0 = worst.0.max((ne.jtj[i * d + j] - dense).abs() / diag);
            }
            let g: f64 = lin.column(i).iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
            worst.1 = worst.1.max((ne.jtr[i] - g).abs() / gscale);
        }
        // The same sums in exact arithmetic; A^T A - W^T W cancels the part of the
        // fixed-point derivative that the re-solved control points absorb, which
        // costs a few digits: measured up to 4e-14 of the largest diagonal entry (1e-15 for
        // the gradient, whose projected term vanishes at the least-squares solution).
        assert!(worst.0 < 1e-12 && worst.1 < 1e-12, "{ctrl:?} {layout:?} {mode:?}: {worst:?}");
    }
    // An infeasible point gives None, like the value's infinity.
    let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
    assert!(p.normal_equations(&[f64::NAN; 72]).is_none());
    assert!(p.normal_equations(&[0.0; 3]).is_none());
}

#[test]
fn band_order_is_the_cheaper_one() {
    // 6 x 12 bicubic: u-major would give 3 * 12 + 3 = 39, v-major 3 * 6 + 3 = 21.
    let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
    assert_eq!(p.bandwidth(), 21);
    let p = problem((8, 5), WeightMode::Resolved, WeightLayout::Full, 0.0);
    assert_eq!(p.bandwidth(), 3 * 5 + 3);
}

#[test]
fn the_search_box_scales_with_kappa_inside_the_bounds() {
    let (fit, offsets) = sample_fit((6, 12));
    let make = |k: Option<f64>| {
        let o = WeightOptions { search_scale: k, ..WeightOptions::default() };
        WeightProblem::from_fit(&fit, &offsets, o).expect("ok")
    };
    let whole = make(None).search_box();
    assert_eq!(whole, (make(None).lower().to_vec(), make(None).upper().to_vec()));
    let (lo1, hi1) = make(Some(1.0)).search_box();
    let (lo2, hi2) = make(Some(2.0)).search_box();
    let p = make(Some(1.0));
    let (x0, f0, d) = (p.start(), p.value(&p.start()), p.dim());
    let ne = p.normal_equations(&x0).expect("start is regular");
    for i in 0..d {
        assert!(p.lower()[i] <= lo1[i] && lo1[i] < x0[i] && x0[i] < hi1[i] && hi1[i] <= p.upper()[i], "{i}");
        // Unclipped, the half-width is f(0) / (sqrt(d) |J_i|) exactly, and doubles with κ.
        let h = f0 / (ne.jtj[i * d + i].sqrt() * (d as f64).sqrt());
        if h < p.upper()[i] / 2.0 {
            assert_near!(hi1[i], h, 1e-15 * h);
            assert_near!(hi2[i] - lo2[i], 2.0 * (hi1[i] - lo1[i]), 1e-14 * h);
        }
    }
    // On this sample the useful moves are far smaller than the bounds for some weights.
    assert!(hi1.iter().any(|&h| h < 0.1 * p.upper()[0]));
    let bad = WeightOptions { search_scale: Some(0.0), ..WeightOptions::default() };
    assert!(matches!(
        WeightProblem::from_fit(&fit, &offsets, bad),
        Err(HullError::FitSetting { name: "weight search scale", value: 0.0, .. })
    ));
}

/// The Wigley table's plain approximation is a sharp minimum along most log-weight
/// directions: GSA over the whole bounds (`search_scale: None`) ends exactly at the start,
/// while in the sensitivity box it goes below it with the same budget and seed.
#[test]
fn gsa_moves_off_a_sharp_start_only_in_the_sensitivity_box() {
    use crate::optimize::{gsa, quiet, GsaOptions};
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/wigley_offsets.csv");
    let offsets = crate::read_offsets(std::path::Path::new(path), crate::Units::Metre).expect("wigley table reads");
    let fit = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
    let opts = GsaOptions { iterations: 60, agents: 20, ..GsaOptions::default() };
    let run = |k: Option<f64>| {
        let o = WeightOptions { search_scale: k, ..WeightOptions::default() };
        let p = WeightProblem::from_fit(&fit, &offsets, o).expect("ok");
        let f0 = p.value(&p.start());
        (quiet(|c| gsa::run(&p, &opts, 1, c)).value, f0)
    };
    let (whole, f0) = run(None);
    let (boxed, _) = run(Some(10.0));
    assert_eq!(whole, f0);
    assert!(boxed < 0.99 * f0, "{boxed} vs start {f0}");
}

/// The command line and Python read the weight settings with these: every name the reports
/// print reads back as itself, case and spaces aside, and an unknown one names what was
/// expected.
#[test]
fn weight_setting_names_read_back_and_unknown_ones_are_named() {
    for layout in [WeightLayout::Full, WeightLayout::RankOne] {
        assert_eq!(layout.name().parse::<WeightLayout>(), Ok(layout));
        assert_eq!(format!(" {} ", layout.name().to_uppercase()).parse::<WeightLayout>(), Ok(layout));
    }
    assert_eq!("rank1".parse::<WeightLayout>(), Ok(WeightLayout::RankOne));
    for mode in [WeightMode::Resolved, WeightMode::Fixed] {
        assert_eq!(mode.name().parse::<WeightMode>(), Ok(mode));
        assert_eq!(format!(" {} ", mode.name().to_uppercase()).parse::<WeightMode>(), Ok(mode));
    }
    let e = "diagonal".parse::<WeightLayout>().expect_err("unknown");
    assert_eq!(e, "unknown weight layout `diagonal` (expected full or rank1)");
    let e = "free".parse::<WeightMode>().expect_err("unknown");
    assert_eq!(e, "unknown control-point mode `free` (expected resolved or fixed)");
}
