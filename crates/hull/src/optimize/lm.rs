//! Levenberg-Marquardt on the variable-projection functional of the weights (Golub and Pereyra
//! 1973, with Kaufman's 1975 Jacobian), and optionally on the data parameters too.
//!
//! Each iteration solves `(J^T J + μ D) h = -J^T r` with Marquardt's scaling
//! `D = diag(J^T J)` (floored at `1e-12 max_i (J^T J)_ii`), for the variables not held at a bound
//! by the gradient (an active-set projection: a variable on its bound whose gradient points out
//! of the box is frozen for that step), clamps `x + h` into the box, and accepts the step when
//! the sum of squares falls. The damping follows Nielsen (1999): on success
//! `μ <- μ max(1/3, 1 - (2 ϱ - 1)^3)` with `ϱ` the ratio of actual to predicted decrease, on
//! failure `μ <- μ ν, ν <- 2 ν` (Madsen, Nielsen and Tingleff, *Methods for non-linear least
//! squares problems*, 2004, Alg. 3.16).
//!
//! Stops when the relative decrease of `|r|^2` and its prediction both fall below
//! `tolerance`, when the scaled gradient `max_i |J_i^T r| / (|J_i| |r|)` of the free variables
//! falls below `gradient_tolerance`, when the step is below `step_tolerance (|x| +
//! step_tolerance)`, when the value reaches round-off (`1e-15` of the model size), or after
//! `max_iterations` (one trial step each). Only decreases are accepted, so the result is never
//! worse than the start.
//!
//! With [`run_with_parameters`] the unknowns are the log-weights and every offset's `u_k` (and
//! `v_k`), the control points still eliminated by least squares: this recovers exactly
//! rational shapes (circular sections) to round-off, which weights at fixed parameters cannot.

use super::weights::{JacobianKind, Linearization, ParamFreedom, WeightProblem};
use super::{Control, Objective, OptimResult, Progress, StopReason};
use super::linalg::{dense_cholesky, dense_solve, dot};

/// Settings of [`run`], [`polish`] and [`run_with_parameters`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LmOptions {
    /// Trial steps at most.
    pub max_iterations: usize,
    /// Relative decrease of the sum of squares (actual and predicted) below which the run
    /// has converged.
    pub tolerance: f64,
    /// Scaled gradient (cosine between a Jacobian column and the residual) below which the
    /// run has converged.
    pub gradient_tolerance: f64,
    /// Relative step length below which the run has converged.
    pub step_tolerance: f64,
    /// Initial damping `μ_0` (relative to the Marquardt scaling).
    pub initial_damping: f64,
    /// Which Jacobian of the weights.
    pub jacobian: JacobianKind,
}

impl Default for LmOptions {
    /// 100 iterations, tolerances `1e-10`, `μ_0 = 1e-3`, Kaufman's Jacobian.
    fn default() -> Self {
        LmOptions {
            max_iterations: 100,
            tolerance: 1e-10,
            gradient_tolerance: 1e-10,
            step_tolerance: 1e-10,
            initial_damping: 1e-3,
            jacobian: JacobianKind::Kaufman,
        }
    }
}

/// The outcome of [`run_with_parameters`]: the weights' run and the moved data parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamFit {
    /// `x` are the log-weights; `value` is the objective at [`ParamFit::params`].
    pub result: OptimResult,
    /// The data parameters `(u_k, v_k)` at the end.
    pub params: Vec<(f64, f64)>,
}

/// Levenberg-Marquardt from the problem's start (all weights 1).
pub fn run(problem: &WeightProblem, opts: &LmOptions, control: &Control<'_>) -> OptimResult {
    polish(problem, &problem.start(), opts, control)
}

/// Levenberg-Marquardt from `x0` (clamped into the box), e.g. the best point of an
/// evolutionary search: the hybrid "global search, then local polish". The result is never
/// worse than `x0`.
pub fn polish(problem: &WeightProblem, x0: &[f64], opts: &LmOptions, control: &Control<'_>) -> OptimResult {
    let mut x = x0.to_vec();
    x.resize(problem.dim(), 0.0);
    let (lo, hi) = (problem.lower().to_vec(), problem.upper().to_vec());
    clamp(&mut x, &lo, &hi);
    let kind = opts.jacobian;
    engine(
        x,
        &lo,
        &hi,
        problem.size(),
        |z| problem.value(z),
        |z| problem.residuals_and_jacobian(z, kind),
        opts,
        control,
    )
}

/// Levenberg-Marquardt on the log-weights (from `x0`, clamped) and the data parameters
/// (`free`: `u_k`, or `u_k` and `v_k`, each boxed to its domain), starting at the problem's
/// parameters. The control points are eliminated by least squares as in
/// [`WeightProblem::residuals_and_jacobian_with_params`]. Use
/// `problem.with_params(&fit.params)?.surface(&fit.result.x)` for the surface.
pub fn run_with_parameters(
    problem: &WeightProblem,
    x0: &[f64],
    free: ParamFreedom,
    opts: &LmOptions,
    control: &Control<'_>,
) -> ParamFit {
    let d = problem.dim();
    let base: Vec<(f64, f64)> = problem.params().to_vec();
    let (t, tlo, thi) = problem.param_vars(&base, free);
    let mut lo = problem.lower().to_vec();
    let mut hi = problem.upper().to_vec();
    lo.extend(tlo);
    hi.extend(thi);
    let mut z = x0.to_vec();
    z.resize(d, 0.0);
    z.extend(t);
    clamp(&mut z, &lo, &hi);
    let params_of = |z: &[f64]| problem.params_from_vars(&base, &z[d..], free);
    let result = engine(
        z,
        &lo,
        &hi,
        problem.size(),
        |z| {
            let table = problem.basis_table(&params_of(z), false);
            problem.value_with(&table, &z[..d])
        },
        |z| problem.residuals_and_jacobian_with_params(&z[..d], &params_of(z), free),
        opts,
        control,
    );
    let params = params_of(&result.x);
    let mut result = result;
    result.x.truncate(d);
    ParamFit { result, params }
}

fn clamp(x: &mut [f64], lo: &[f64], hi: &[f64]) {
    for ((xi, &l), &h) in x.iter_mut().zip(lo).zip(hi) {
        *xi = if xi.is_nan() { 0.0f64.clamp(l, h) } else { xi.clamp(l, h) };
    }
}

/// `J^T J` (row-major `cols x cols`) and `J^T r`.
fn normal_equations(lin: &Linearization) -> (Vec<f64>, Vec<f64>) {
    let n = lin.cols;
    let mut a = vec![0.0; n * n];
    for i in 0..n {
        let ci = lin.column(i);
        for j in 0..=i {
            let v = dot(ci, lin.column(j));
            a[i * n + j] = v;
            a[j * n + i] = v;
        }
    }
    let g = (0..n).map(|i| dot(lin.column(i), &lin.residuals)).collect();
    (a, g)
}

/// The Levenberg-Marquardt loop over `z` in the box `[lo, hi]`; `value(z) = |r(z)|`.
#[allow(clippy::too_many_arguments)]
fn engine(
    mut z: Vec<f64>,
    lo: &[f64],
    hi: &[f64],
    size: f64,
    value: impl Fn(&[f64]) -> f64,
    linearize: impl Fn(&[f64]) -> Option<Linearization>,
    opts: &LmOptions,
    control: &Control<'_>,
) -> OptimResult {
    let n = z.len();
    let mut evaluations = 1;
    let Some(mut lin) = linearize(&z) else {
        return OptimResult {
            x: z,
            value: f64::INFINITY,
            evaluations,
            iterations: 0,
            history: vec![f64::INFINITY],
            stop: StopReason::Converged,
        };
    };
    let mut f = lin.value();
    let mut history = vec![f];
    let (mut a, mut g) = normal_equations(&lin);
    let mut col_norm: Vec<f64> = (0..n).map(|i| a[i * n + i].sqrt()).collect();
    let mut mu = opts.initial_damping.max(f64::MIN_POSITIVE);
    let mut nu = 2.0;
    let floor = 1e-15 * size;
    let mut stop = StopReason::Iterations;
    let mut iterations = 0;
    let mut free: Vec<usize> = Vec::with_capacity(n);
    let mut m = Vec::with_capacity(n * n);
    let mut rhs = Vec::with_capacity(n);
    while iterations < opts.max_iterations {
        if control.stopped() {
            stop = StopReason::Interrupted;
            break;
        }
        if f <= floor {
            stop = StopReason::Converged;
            break;
        }
        // Free variables: not on a bound with the descent direction -g pointing out.
        free.clear();
        free.extend((0..n).filter(|&i| !((z[i] <= lo[i] && g[i] > 0.0) || (z[i] >= hi[i] && g[i] < 0.0))));
        let grad = free
            .iter()
            .map(|&i| if col_norm[i] > 0.0 { g[i].abs() / (col_norm[i] * f) } else { 0.0 })
            .fold(0.0, f64::max);
        if free.is_empty() || grad <= opts.gradient_tolerance {
            stop = StopReason::Converged;
            break;
        }
        iterations += 1;
        // (A_FF + μ D_FF) h_F = -g_F; a free variable on a bound whose step points out of the
        // box joins the fixed ones and the step is solved again.
        let mut step = None;
        while !free.is_empty() {
            let Some(h) = damped_step(&a, &g, n, &free, mu, &mut m, &mut rhs) else { break };
            let before = free.len();
            free.retain(|&i| !((z[i] <= lo[i] && h[i] < 0.0) || (z[i] >= hi[i] && h[i] > 0.0)));
            if free.len() == before {
                step = Some(h);
                break;
            }
        }
        let mut accepted = false;
        if let Some(full) = step {
            // The step projected into the box; if clamping spoils the model's decrease, the
            // step shortened to the first bound instead (a descent step for any length up to
            // the full one, as (A + μ D) h = -g makes the model decrease along h up to 1).
            let mut zn = z.clone();
            for i in 0..n {
                zn[i] += full[i];
            }
            clamp(&mut zn, lo, hi);
            let mut h: Vec<f64> = zn.iter().zip(&z).map(|(a, b)| a - b).collect();
            let mut predicted = model_decrease(&a, &g, &h);
            if !(predicted > 0.0) {
                let alpha = (0..n)
                    .map(|i| {
                        if full[i] > 0.0 {
                            (hi[i] - z[i]) / full[i]
                        } else if full[i] < 0.0 {
                            (lo[i] - z[i]) / full[i]
                        } else {
                            1.0
                        }
                    })
                    .fold(1.0f64, f64::min)
                    .max(0.0);
                for i in 0..n {
                    zn[i] = z[i] + alpha * full[i];
                }
                clamp(&mut zn, lo, hi);
                h = zn.iter().zip(&z).map(|(a, b)| a - b).collect();
                predicted = model_decrease(&a, &g, &h);
            }
            let hn = h.iter().map(|t| t * t).sum::<f64>().sqrt();
            let zn_norm = z.iter().map(|t| t * t).sum::<f64>().sqrt();
            if hn <= opts.step_tolerance * (zn_norm + opts.step_tolerance) {
                stop = StopReason::Converged;
                history.push(f);
                break;
            }
            let fn_ = value(&zn);
            evaluations += 1;
            let actual = 0.5 * (f * f - fn_ * fn_);
            if std::env::var("LM_DEBUG").is_ok() {
                eprintln!("it {iterations} mu {mu:e} f {f:e} fn {fn_:e} pred {predicted:e} act {actual:e} |h| {hn:e} free {}/{n}", free.len());
            }
            if fn_.is_finite() && actual > 0.0 {
                if let Some(l) = linearize(&zn) {
                    accepted = true;
                    let rho = if predicted > 0.0 { actual / predicted } else { 1.0 };
                    mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    let small = actual <= opts.tolerance * 0.5 * f * f
                        && predicted.abs() <= opts.tolerance * 0.5 * f * f;
                    z = zn;
                    lin = l;
                    f = lin.value();
                    (a, g) = normal_equations(&lin);
                    col_norm = (0..n).map(|i| a[i * n + i].sqrt()).collect();
                    if small {
                        history.push(f);
                        (control.progress)(progress(iterations, opts, f, evaluations));
                        stop = StopReason::Converged;
                        break;
                    }
                }
            }
        }
        if !accepted {
            mu *= nu;
            nu *= 2.0;
            if !(mu < 1e30) {
                history.push(f);
                stop = StopReason::Converged;
                break;
            }
        }
        history.push(f);
        (control.progress)(progress(iterations, opts, f, evaluations));
    }
    OptimResult { x: z, value: f, evaluations, iterations, history, stop }
}

/// The damped Gauss-Newton step on the `free` variables (zero elsewhere), `None` if the damped
/// matrix is not positive definite to working precision.
fn damped_step(
    a: &[f64],
    g: &[f64],
    n: usize,
    free: &[usize],
    mu: f64,
    m: &mut Vec<f64>,
    rhs: &mut Vec<f64>,
) -> Option<Vec<f64>> {
    let nf = free.len();
    let dmax = free.iter().map(|&i| a[i * n + i]).fold(0.0, f64::max);
    m.clear();
    m.resize(nf * nf, 0.0);
    for (r, &i) in free.iter().enumerate() {
        for (c, &j) in free.iter().enumerate() {
            m[r * nf + c] = a[i * n + j];
        }
        m[r * nf + r] += mu * a[i * n + i].max(1e-12 * dmax).max(f64::MIN_POSITIVE);
    }
    rhs.clear();
    rhs.extend(free.iter().map(|&i| -g[i]));
    if !dense_cholesky(m, nf) {
        return None;
    }
    dense_solve(m, nf, rhs);
    if !rhs.iter().all(|h| h.is_finite()) {
        return None;
    }
    let mut h = vec![0.0; n];
    for (&i, &hi) in free.iter().zip(rhs.iter()) {
        h[i] = hi;
    }
    Some(h)
}

/// The Gauss-Newton model's decrease of `F = |r|^2 / 2` along `h`: `-h^T g - h^T A h / 2`.
fn model_decrease(a: &[f64], g: &[f64], h: &[f64]) -> f64 {
    let n = h.len();
    let mut hah = 0.0;
    for i in 0..n {
        if h[i] != 0.0 {
            hah += h[i] * dot(&a[i * n..(i + 1) * n], h);
        }
    }
    -dot(h, g) - 0.5 * hah
}

fn progress(iteration: usize, opts: &LmOptions, best: f64, evaluations: usize) -> Progress {
    Progress { iteration, iterations: opts.max_iterations, best, evaluations }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::weights::{WeightLayout, WeightMode, WeightOptions};
    use crate::optimize::quiet;
    use crate::{fit_offsets, measure_fit_error, series60_sample, FitConfig, FitOutcome, Offsets, Section, Units};
    use nurbs::{KnotVector, NurbsSurface, Vec3};
    use std::sync::atomic::AtomicBool;
    use std::time::Instant;

    fn fit(offsets: &Offsets, degree: (usize, usize), ctrl: (usize, usize)) -> FitOutcome {
        let cfg = FitConfig { degree, ctrl: Some(ctrl), ..FitConfig::default() };
        fit_offsets(offsets, &cfg).expect("fits")
    }

    fn problem(offsets: &Offsets, out: &FitOutcome, mode: WeightMode, layout: WeightLayout) -> WeightProblem {
        let opts = WeightOptions { mode, layout, ..WeightOptions::default() };
        WeightProblem::from_fit(out, offsets, opts).expect("shapes match")
    }

    /// Free-form sections: curved, non-planar strips over a Gaussian bump, 15 sections of 14
    /// points.
    fn free_form() -> Offsets {
        let sections = (0..15)
            .map(|k| {
                let t = k as f64 / 14.0;
                let pts = (0..14)
                    .map(|i| {
                        let s = i as f64 / 13.0;
                        let x = 4.0 * s + 0.4 * (3.0 * t).sin();
                        let y = 3.0 * t + 0.3 * s * s;
                        let z = 1.5 * (-4.0 * ((s - 0.5).powi(2) + (t - 0.4).powi(2))).exp() + 0.2 * s * t;
                        Vec3::new(x, y, z)
                    })
                    .collect();
                Section::new(format!("{k}"), pts)
            })
            .collect();
        Offsets { source: "free-form test".into(), units: Units::Metre, sections }
    }

    /// Quarter circles in the planes x = const, radius r(x) = r0 + c x: exactly the rational
    /// surface of degree (2, 1) with control points (x_j, r_j (1,0)), (x_j, r_j (1,1)),
    /// (x_j, r_j (0,1)) and weights 1, sqrt(2)/2, 1 in each column j = 0, 1.
    fn cone_surface() -> NurbsSurface {
        let (x0, x1, r0, r1) = (0.0, 10.0, 2.0, 3.0);
        let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let h = std::f64::consts::FRAC_1_SQRT_2;
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for (i, (cy, cz, wi)) in [(1.0, 0.0, 1.0), (1.0, 1.0, h), (0.0, 1.0, 1.0)].into_iter().enumerate() {
            let _ = i;
            for (x, r) in [(x0, r0), (x1, r1)] {
                pts.push(Vec3::new(x, r * cy, r * cz));
                w.push(wi);
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    /// Offsets on the exact surface at irregular parameters: 6 sections, 7 points each.
    fn cone_offsets() -> Offsets {
        let s = cone_surface();
        let vs = [0.0, 0.17, 0.38, 0.55, 0.81, 1.0];
        let sections = vs
            .iter()
            .enumerate()
            .map(|(k, &v)| {
                let pts = (0..7)
                    .map(|i| {
                        let t = i as f64 / 6.0;
                        let u = t + if i == 0 || i == 6 { 0.0 } else { 0.05 * (3.0 * t + k as f64).sin() };
                        s.point(u, v)
                    })
                    .collect();
                Section::new(format!("{k}"), pts)
            })
            .collect();
        Offsets { source: "cone test".into(), units: Units::Metre, sections }
    }

    #[test]
    fn explore_cone() {
        let o = cone_offsets();
        for sec in &o.sections {
            for q in &sec.points {
                let r = (q.y * q.y + q.z * q.z).sqrt();
                assert!((r - (2.0 + 0.1 * q.x)).abs() < 1e-14, "{q:?}");
            }
        }
        let out = fit(&o, (2, 1), (3, 2));
        let size = o.size();
        println!("plain rel max {:e}", out.error.overall.max / size);
        for (name, bounds, free) in [
            ("weights only", (0.1, 10.0), ParamFreedom::None),
            ("weights+uv", (0.1, 10.0), ParamFreedom::UV),
            ("weights+u", (0.1, 10.0), ParamFreedom::U),
            ("weights+u+secv", (0.1, 10.0), ParamFreedom::USectionV),
            ("nonrational+u+secv", (1.0, 1.0), ParamFreedom::USectionV),
            ("nonrational+uv", (1.0, 1.0), ParamFreedom::UV),
        ] {
            for reg in [1e-6, 0.0] {
                let opts = WeightOptions { bounds, regularization: reg, ..WeightOptions::default() };
                let p = WeightProblem::from_fit(&out, &o, opts).expect("ok");
                let t = Instant::now();
                let pf = quiet(|c| run_with_parameters(&p, &p.start(), free, &LmOptions { max_iterations: 200, ..LmOptions::default() }, c));
                let dt = t.elapsed().as_secs_f64();
                let s = p.with_params(&pf.params).expect("ok").surface(&pf.result.x).expect("ok");
                let e = measure_fit_error(&s, &o, None);
                println!("{name} reg {reg}: rel max {:e} value {:e} it {} ev {} {:?} {dt:.4}s w {:?}", e.overall.max / size, pf.result.value, pf.result.iterations, pf.result.evaluations, pf.result.stop, s.weights());
                println!("   hist {:?}", &pf.result.history[..pf.result.history.len().min(15)]);
                if bounds.0 == 2.0 && reg == 0.0 {
                    println!("   cps {:?}", s.control_points());
                    println!("   params {:?}", pf.params);
                    let pts: Vec<Vec3> = o.sections.iter().flat_map(|s| s.points.clone()).collect();
                    let worst = pts.iter().zip(&pf.params).map(|(q, &(u, v))| (s.point(u, v) - *q).norm()).fold(0.0, f64::max);
                    println!("   kernel parametric max {worst:e}");
                }
            }
        }
    }

    #[test]
    fn explore_fixed() {
        let o = series60_sample();
        let out = fit(&o, (3, 3), (6, 12));
        let p = problem(&o, &out, WeightMode::Fixed, WeightLayout::Full);
        for tol in [1e-10, 1e-14, 0.0] {
            let opts = LmOptions { tolerance: tol, gradient_tolerance: tol, step_tolerance: tol, max_iterations: 300, ..LmOptions::default() };
            let r = quiet(|c| run(&p, &opts, c));
            println!("tol {tol}: {:?} it {} f {} hist {:?}", r.stop, r.iterations, r.value, &r.history[..r.history.len().min(12)]);
        }
    }

    #[test]
    fn explore() {
        let o = series60_sample();
        for ctrl in [(6, 12), (5, 8)] {
            let out = fit(&o, (3, 3), ctrl);
            for mode in [WeightMode::Fixed, WeightMode::Resolved] {
                for layout in [WeightLayout::Full, WeightLayout::RankOne] {
                    let p = problem(&o, &out, mode, layout);
                    let t = Instant::now();
                    let r = quiet(|c| run(&p, &LmOptions::default(), c));
                    let dt = t.elapsed().as_secs_f64();
                    let f0 = p.value(&p.start());
                    let s = p.surface(&r.x).expect("ok");
                    let e = measure_fit_error(&s, &o, None);
                    println!("s60 {ctrl:?} {mode:?} {layout:?}: f0 {f0:.5} f {:.5} red {:.1}% it {} ev {} {:?} {dt:.4}s true rms {:.5} (plain {:.5}) wmin {:.3} wmax {:.3}",
                        r.value, 100.0 * (1.0 - r.value / f0), r.iterations, r.evaluations, r.stop, e.overall.rms, out.error.overall.rms,
                        s.weights().iter().cloned().fold(f64::INFINITY, f64::min), s.weights().iter().cloned().fold(0.0, f64::max));
                }
            }
        }
        let o = free_form();
        let out = fit(&o, (3, 3), (6, 6));
        for mode in [WeightMode::Fixed, WeightMode::Resolved] {
            for layout in [WeightLayout::Full, WeightLayout::RankOne] {
                let p = problem(&o, &out, mode, layout);
                let t = Instant::now();
                let r = quiet(|c| run(&p, &LmOptions::default(), c));
                let dt = t.elapsed().as_secs_f64();
                let f0 = p.value(&p.start());
                println!("ff {mode:?} {layout:?}: f0 {f0:.6} f {:.6} red {:.1}% it {} ev {} {:?} {dt:.4}s", r.value, 100.0 * (1.0 - r.value / f0), r.iterations, r.evaluations, r.stop);
            }
        }
    }
}
