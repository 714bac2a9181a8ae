//! Levenberg-Marquardt on the variable-projection functional of the weights (Golub and Pereyra
//! 1973, with Kaufman's 1975 Jacobian), and optionally on the data parameters too.
//!
//! The rest of this module's documentation is on [`run`], where the library's users read it.

use std::cell::RefCell;
use std::rc::Rc;

use super::linalg::dot;
use super::weights::{Evaluation, JacobianKind, Linearization, ParamFreedom, WeightProblem};
use super::{Control, Objective, OptimResult, Progress, StopReason};

mod model;

use model::{
    continuation_factor, forcing, stale_factor_pays, step_path, Dense, MatrixFree, Model, StaleFactor, StepPath,
};

/// Settings of [`run`] (and of the polish and the parameter correction of [`super::optimize_weights`]).
///
/// # The matrix-free step
///
/// The Gauss-Newton model of one Levenberg-Marquardt iteration, and its damped step
/// `(J^T J + R + μ D) h = -(J^T r + R θ)` on the free variables, two ways:
///
/// * `Dense`: the normal matrix formed (`d x d`), the step by dense Cholesky, `D` its
///   diagonal (Marquardt 1963).
/// * `MatrixFree`: only products with `J^T J` (see `weights/matvec.rs`, each
///   `O(m (p+1)(q+1) + n bw)`), the step by preconditioned conjugate gradients (Hestenes and
///   Stiefel 1952; Nocedal and Wright, *Numerical Optimization*, 2nd ed., Alg. 5.3) stopped at
///   a relative residual `η` (an inexact Newton step: Dembo, Eisenstat and Steihaug 1982;
///   every CG iterate from zero lowers the quadratic model, so a truncated step still
///   descends). `D = diag(A^T A) / m + diag(R)`, the fixed-point part of the diagonal, an upper
///   bound of `diag(J^T J + R)` that costs nothing (the exact one needs `d` band solves), is
///   the damping's scaling and, with `μ`, the Jacobi preconditioner. On the fair objective,
///   where forming `J^T J + R` once costs at most 120 products, CG is preconditioned instead
///   by that matrix at the run's first point (shared by the starts of `run_best_of`),
///   factored with the damping (`lm/model.rs`, `StaleFactor`; [`LmOptions::stale_factor`]).
///
/// `step_path` picks the cheaper by an estimate of the multiply-adds of one iteration.
///
/// Kaufman's Jacobian of the variable-projection residual as an operator: products `J v`,
/// `J^T w` and `(J^T J) v` without forming `J` or `J^T J`, for a matrix-free
/// Levenberg-Marquardt step (conjugate gradients) on problems with many weights.
///
/// With `A` the derivative of the residuals at fixed control points (`3 m x d`, sparse: offset
/// `k`'s row block has one entry `R_kc (P_c - S_k)` per control point `c` of its support,
/// summed into `(p+1) + (q+1)` variables in the rank-one layout), `H` the `m x n` matrix
/// `h_kc = B_kc / W_k` acting on each coordinate, and `G = H^T H` (+ the anchor ridge) with the
/// band Cholesky factor `G = L L^T` that the evaluation made, Kaufman's Jacobian is
/// (Kaufman 1975; see [`WeightProblem::normal_equations`])
///
/// `J = (I - H G^{-1} H^T) A / sqrt(m)` (`Resolved` mode), `J = A / sqrt(m)` (`Fixed`),
///
/// and the normal matrix the dense path forms is `m J^T J = A^T (I - H G^{-1} H^T) A`
/// (one projection: the projector is idempotent when `G = H^T H`, and with the anchor this is
/// the same `O(anchor)` approximation as `normal_equations`). So
///
/// * `J v`: `u = A v` (`3 m (p+1)(q+1)` multiply-adds), `t = H^T u`, `t <- G^{-1} t` (two band
///   substitutions, `6 n bw`), `u <- u - H t`;
/// * `J^T w`: the same projection of `w`, then `A^T`;
/// * `(J^T J) v = A^T (I - H G^{-1} H^T) A v / m`: one projection,
///
/// each `O(m (p+1)(q+1) + n bw)`, against `O(m d^2)` for the dense normal equations. The prior
/// `R` of the log-weights (see `WeightProblem::prior_apply`) is added by the caller's
/// operator, not here.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LmOptions {
    /// Trial steps at most.
    pub max_iterations: usize,
    /// Relative decrease of the sum of squares (actual and predicted) below which the run
    /// has converged. The predicted decrease of a nearly undamped step estimates what is
    /// left to gain, so `1e-7` stops within about `5e-8` of the RMS's local minimum.
    pub tolerance: f64,
    /// Scaled gradient (cosine between a Jacobian column and the residual) below which the
    /// run has converged.
    pub gradient_tolerance: f64,
    /// Relative step length below which the run has converged.
    pub step_tolerance: f64,
    /// Stall test `(window, relative)`: converged when the last `window` iterations together
    /// lowered the RMS by less than `relative` of it (the crawl of weights settling on their
    /// bounds, where each step gains little and the per-step test never fires). `window = 0`
    /// turns it off.
    pub stall: (usize, f64),
    /// Initial damping `μ_0` (relative to the Marquardt scaling).
    pub initial_damping: f64,
    /// Which Jacobian of the weights.
    pub jacobian: JacobianKind,
    /// Matrix-free step (Kaufman's Jacobian only): conjugate gradients stop at this residual
    /// relative to the gradient's, at most (the first step's; later ones follow the forcing
    /// sequence down to [`LmOptions::cg_tolerance_min`]).
    pub cg_tolerance: f64,
    /// Matrix-free step: the tightest relative residual of the forcing sequence (Eisenstat
    /// and Walker's choice 2, `lm/model.rs`); equal to `cg_tolerance` for a fixed one.
    pub cg_tolerance_min: f64,
    /// Matrix-free step: conjugate-gradient iterations at most per step.
    pub max_cg: usize,
    /// `Some(true)`: the matrix-free step; `Some(false)`: the dense normal equations; `None`:
    /// the cheaper by an estimate of the cost (see `lm/model.rs`).
    pub matrix_free: Option<bool>,
    /// Matrix-free step: `Some(true)` preconditions CG with the normal matrix `J^T J + R` formed
    /// at the run's first point and factored (refactored as the damping moves), `Some(false)`
    /// with Jacobi's diagonal; `None`: the former on the fair objective where forming it costs
    /// at most 120 products of `J^T J` (the grids of up to 256 weights of `testdata/`; see
    /// `lm/model.rs`), and in `run_best_of`'s continuation where its probe is still crawling
    /// on Jacobi's (formed where the probe ended; `lm/model.rs`, `continuation_factor`).
    pub stale_factor: Option<bool>,
}

impl Default for LmOptions {
    /// 100 iterations, tolerance `1e-7` (on the Series 60 table, `6 x 19`, the 13 iterations
    /// a tolerance of `1e-10` adds gain `2.6e-8` of the RMS, `1e-10` m), gradient and step
    /// tolerances `1e-10`, stall `(10, 1e-3)`, `μ_0 = 1e-3`, Kaufman's Jacobian.
    ///
    /// The stall test: from the foot points the Series 60 sample at `6 x 19` crawls from
    /// iteration 60 to 138 for 1e-5 of its RMS as weights settle on their bounds, and on the
    /// fair objective (`--fair auto`) the large tables of `testdata/` crawl the same way after
    /// their first 20-30 iterations: with `(10, 1e-5)` the yacht (780 weights) ran to the
    /// 120-iteration cap for 0.3 % of its objective, the DTMB 5415 bow (192) for 0.2 %, with the
    /// true RMS within 0.05 % and the held-out RMS within 0.3 % of where `(10, 1e-3)` stops (at
    /// 51 and 68 iterations; measured on every table, `--fair auto` and `--fair 0`, the README's
    /// LM section). On the plain objective (`--fair 0`) the large tables gain more than 0.1 % in
    /// 10 iterations to the end and run as before.
    fn default() -> Self {
        LmOptions {
            max_iterations: 100,
            tolerance: 1e-7,
            gradient_tolerance: 1e-10,
            step_tolerance: 1e-10,
            stall: (10, 1e-3),
            initial_damping: 1e-3,
            jacobian: JacobianKind::Kaufman,
            cg_tolerance: CG_TOLERANCE,
            cg_tolerance_min: CG_TOLERANCE_MIN,
            max_cg: MAX_CG,
            matrix_free: None,
            stale_factor: None,
        }
    }
}

/// The matrix-free step's loosest relative CG residual (its first step's).
const CG_TOLERANCE: f64 = 0.5;
/// The tightest relative CG residual of the forcing sequence.
const CG_TOLERANCE_MIN: f64 = 1e-2;
/// CG iterations at most per matrix-free step. Measured (`--fair 0`, true RMS at 8 -> 12 -> 16
/// iterations, same run): trawler 3.98 -> 3.27 -> 2.89 mm, MATLAB Series 60 0.348 -> 0.306 ->
/// 0.276, WPB 0.375 -> 0.358 -> 0.326, yacht 0.080 -> 0.075 -> 0.072, at about 1.0, 1.25 and
/// 1.5 times LM's time; Jacobi-preconditioned CG on these tables reaches the cap with its
/// relative residual still near 1 (measured 0.98-1.1 on the trawler and WPB), so the cap,
/// not the forcing term, sets the step's accuracy there. A banded preconditioner with the
/// log-weight prior's couplings did not change the CG iterations or the result (measured on
/// the trawler and WPB, both objectives), nor did the exact diagonal of `J^T J` in place of
/// its upper bound (trawler, 2.10 against 2.20 mm at 8 iterations, 1.92 against 1.93 at 40).
const MAX_CG: usize = 12;

/// The outcome of [`run_with_parameters`]: the weights' run and the moved data parameters.
#[derive(Clone, Debug, PartialEq)]
pub struct ParamFit {
    /// `x` are the log-weights; `value` is the objective at [`ParamFit::params`].
    pub result: OptimResult,
    /// The data parameters `(u_k, v_k)` at the end.
    pub params: Vec<(f64, f64)>,
}

/// Levenberg-Marquardt from the problem's start (all weights 1).
///
/// # Algorithm
///
/// Each iteration solves `(J^T J + μ D) h = -J^T r` with Marquardt's scaling
/// `D = diag(J^T J)` (floored at `1e-12 max_i (J^T J)_ii`), for the variables not held at a bound
/// by the gradient (an active-set projection: a variable on its bound whose gradient points out
/// of the box is frozen for that step), clamps `x + h` into the box, and accepts the step when
/// the sum of squares falls. The damping follows Nielsen (1999): on success
/// `μ <- μ max(1/3, 1 - (2 ϱ - 1)^3)` with `ϱ` the ratio of actual to predicted decrease, on
/// failure `μ <- μ ν, ν <- 2 ν` (Madsen, Nielsen and Tingleff, *Methods for non-linear least
/// squares problems*, 2004, Alg. 3.16).
///
/// Stops when the relative decrease of `|r|^2` and its prediction both fall below
/// `tolerance`, when the scaled gradient `max_i |J_i^T r| / (|J_i| |r|)` of the free variables
/// falls below `gradient_tolerance`, when the step is below `step_tolerance (|x| +
/// step_tolerance)`, when the last `stall.0` iterations together gained less than `stall.1` of
/// the RMS, when the value reaches round-off (`1e-15` of the model size), or after
/// `max_iterations` (one trial step each). Only decreases are accepted, so the result is never
/// worse than the start.
///
/// Cost: with Kaufman's Jacobian the normal equations come straight from the problem's
/// structure ([`WeightProblem::normal_equations`], `J` never formed); with the exact Jacobian
/// or the data parameters, from the dense `J`. Measured on the Series 60 table (release, one
/// core of this 2-core Xeon), against the dense `J` and the former tolerance `1e-10`:
///
/// | control points, layout | iterations | time |
/// |---|---|---|
/// | 6 x 19, full (114 weights) | 91 -> 78 | 189 -> 56 ms |
/// | 6 x 19, rank one | 44 -> 35 | 17.3 -> 6.5 ms |
/// | 6 x 12, full | 25 -> 18 | 24.7 -> 6.3 ms |
/// | 6 x 12, rank one | 20 -> 17 | 5.5 -> 2.3 ms |
///
/// with final values within `3e-8` relative. Neither another damping (`μ_0` from `1e-5` to 1,
/// a floor on `μ`), the exact Jacobian, geodesic acceleration (Transtrum and Sethna 2012) nor
/// a secant update of the large-residual term (Dennis, Gay and Welsch 1981) cut the iteration
/// count at 6 x 19: its long middle phase (ϱ about 0.5 with `μ` below `1e-4`, weights reaching
/// their bounds one by one) is the functional's.
///
/// Many weights: where forming and factoring the normal equations would cost 4x more than
/// the matrix-free step (`lm/model.rs`: preconditioned conjugate gradients on products with
/// Kaufman's `J^T J`, at most [`LmOptions::max_cg`] of them, relative residual from
/// [`LmOptions::cg_tolerance`] down to [`LmOptions::cg_tolerance_min`] by Eisenstat and
/// Walker's forcing sequence as the gradient falls), that is used instead; the evaluation of an accepted point is
/// reused for its model. On the tables of `testdata/` (the README's table, `tools/lm_speed.sh`)
/// this took LM from 60x-970x the plain approximation's time to 7x-13x on 176 to 780 weights,
/// at a higher final RMS where the old runs went furthest (WPB 0.37 mm against 0.027); CG's
/// cap 8 -> 12 with the forcing sequence and a race probe of 20 iterations cut that to 0.317 mm
/// (trawler 3.81 -> 1.99, against 1.77 dense) at 7x-16x.
/// `run_best_of` runs several starts a few iterations each and only the lowest on.
///
/// With `run_with_parameters` the unknowns are the log-weights and every offset's `u_k` (and
/// `v_k`), the control points still eliminated by least squares: this recovers exactly
/// rational shapes (circular sections) to round-off, which weights at fixed parameters cannot.
pub fn run(problem: &WeightProblem, opts: &LmOptions, control: &Control<'_>) -> OptimResult {
    polish(problem, &problem.start(), opts, control)
}

/// Levenberg-Marquardt from `x0` (clamped into the box), e.g. the best point of an
/// evolutionary search: the hybrid "global search, then local polish". The result is never
/// worse than `x0`.
pub fn polish(problem: &WeightProblem, x0: &[f64], opts: &LmOptions, control: &Control<'_>) -> OptimResult {
    polish_from(problem, x0, opts, control, None).0
}

/// [`polish`], also returning the damping `μ` at the end (to go on where it stopped). `normal`:
/// the normal matrix `J^T J + R` the matrix-free step's preconditioner starts from (see
/// [`LmOptions::stale_factor`]), or `None` to form it at `x0` if it is used.
fn polish_from(
    problem: &WeightProblem,
    x0: &[f64],
    opts: &LmOptions,
    control: &Control<'_>,
    normal: Option<&[f64]>,
) -> (OptimResult, f64) {
    let mut x = x0.to_vec();
    x.resize(problem.dim(), 0.0);
    let (lo, hi) = (problem.lower().to_vec(), problem.upper().to_vec());
    clamp(&mut x, &lo, &hi);
    let kind = opts.jacobian;
    if kind == JacobianKind::Kaufman && step_path(problem, opts) == StepPath::MatrixFree {
        // The last evaluation's solved state, reused when the engine asks for the model at
        // the point it just evaluated (an accepted step).
        let last: RefCell<Option<Evaluation>> = RefCell::new(None);
        // The forcing term and gradient norm of the last model built at an accepted point
        // (models at rejected trial points are not built: `engine` asks only for accepted
        // ones and the start).
        let eta: RefCell<Option<(f64, f64)>> = RefCell::new(None);
        // The preconditioner, formed at the first model (the run's start) and shared by the
        // later ones.
        let stale_on = stale_factor_pays(problem, opts);
        // (`None` until tried: a start where it cannot be formed keeps Jacobi's.)
        let stale: RefCell<Option<Option<Rc<RefCell<StaleFactor>>>>> = RefCell::new(None);
        return engine(
            x,
            &lo,
            &hi,
            problem.size(),
            |z| {
                let ev = problem.evaluate(z);
                let f = ev.value();
                *last.borrow_mut() = Some(ev);
                f
            },
            |z| -> Option<Box<dyn Model + '_>> {
                let ev = match last.borrow_mut().take() {
                    Some(ev) if ev.x() == z => ev,
                    _ => problem.evaluate(z),
                };
                let mut m = MatrixFree::new(problem, problem.jacobian_op_at(ev)?, z, opts.cg_tolerance, opts.max_cg)?;
                if stale_on {
                    let mut slot = stale.borrow_mut();
                    let factor = slot.get_or_insert_with(|| {
                        let jtj = match normal {
                            Some(a) if a.len() == z.len() * z.len() => a.to_vec(),
                            _ => problem.normal_equations(z)?.jtj,
                        };
                        Some(Rc::new(RefCell::new(StaleFactor::new(jtj, z.len()))))
                    });
                    if let Some(s) = factor {
                        m.set_preconditioner(Rc::clone(s));
                    }
                }
                let g = dot(m.gradient(), m.gradient()).sqrt();
                let tol = forcing(*eta.borrow(), g, opts.cg_tolerance, opts.cg_tolerance_min);
                m.set_tolerance(tol);
                *eta.borrow_mut() = Some((tol, g));
                Some(Box::new(m))
            },
            opts,
            control,
        );
    }
    engine(
        x,
        &lo,
        &hi,
        problem.size(),
        |z| problem.value(z),
        |z| -> Option<Box<dyn Model>> {
            let (a, g) = match kind {
                // The products straight from the problem's structure (about 4x faster).
                JacobianKind::Kaufman => problem.normal_equations(z).map(|ne| (ne.jtj, ne.jtr)),
                JacobianKind::Exact => problem.residuals_and_jacobian(z, kind).map(|lin| normal_equations(&lin)),
            }?;
            Some(Box::new(Dense::new(a, g)))
        },
        opts,
        control,
    )
}

/// Levenberg-Marquardt from the start (all weights 1) of each of `problems` (the same weights
/// at other data parameters), keeping the lowest objective, without running every start in
/// full: each runs `probe` iterations, and only the lowest goes on, from where it stopped
/// (with its damping), to `opts.max_iterations` in all. Returns the winner's index and its
/// result; the history is the best value so far over the probes, then the winner's
/// continuation, and the iterations and evaluations count every run.
pub fn run_best_of(
    problems: &[&WeightProblem],
    opts: &LmOptions,
    probe: usize,
    control: &Control<'_>,
) -> (usize, OptimResult) {
    let probe_opts = LmOptions { max_iterations: probe.min(opts.max_iterations), ..*opts };
    let mut runs = probes(problems, &probe_opts, control);
    // The lowest value; the first on ties.
    let best = (0..runs.len()).fold(0, |b, i| if runs[i].0.value < runs[b].0.value { i } else { b });
    let (mut history, mut iterations, mut evaluations) = (Vec::new(), 0, 0);
    let mut low = f64::INFINITY;
    for (k, (r, _)) in runs.iter().enumerate() {
        let skip = usize::from(k > 0);
        history.extend(r.history.iter().skip(skip).map(|&v| {
            low = low.min(v);
            low
        }));
        iterations += r.iterations;
        evaluations += r.evaluations;
    }
    let (mut result, mu) = runs.swap_remove(best);
    let left = opts.max_iterations.saturating_sub(result.iterations);
    if result.stop == StopReason::Iterations && left > 0 && !control.stopped() {
        let stale_factor = continuation_factor(problems[best], opts, &result.history);
        let go_on = LmOptions { max_iterations: left, initial_damping: mu, stale_factor, ..*opts };
        let (more, _) = polish_from(problems[best], &result.x, &go_on, control, None);
        history.extend(more.history.iter().skip(1).map(|&v| {
            low = low.min(v);
            low
        }));
        iterations += more.iterations;
        evaluations += more.evaluations;
        if more.value <= result.value {
            result.x = more.x;
            result.value = more.value;
        }
        result.stop = more.stop;
    }
    result.history = history;
    result.iterations = iterations;
    result.evaluations = evaluations;
    (best, result)
}

/// The probes of [`run_best_of`], one per problem, in order: run side by side (`rayon::join`,
/// so on as many threads as the pool has), each the same sequential run whatever the thread
/// count, so the results do not depend on it. Only the first reports progress (two runs'
/// iterations interleaved would be meaningless); all stop on the stop flag. Where the
/// matrix-free step is preconditioned by a [`StaleFactor`], its normal matrix is formed once,
/// at the first problem's start, for all of them (the same weights at other data parameters).
fn probes(problems: &[&WeightProblem], opts: &LmOptions, control: &Control<'_>) -> Vec<(OptimResult, f64)> {
    let shared = match problems {
        [first, _, ..]
            if opts.jacobian == JacobianKind::Kaufman
                && step_path(first, opts) == StepPath::MatrixFree
                && stale_factor_pays(first, opts) =>
        {
            first.normal_equations(&first.start()).map(|ne| ne.jtj)
        }
        _ => None,
    };
    probes_from(problems, opts, control, shared.as_deref())
}

/// [`probes`] with the shared normal matrix.
fn probes_from(
    problems: &[&WeightProblem],
    opts: &LmOptions,
    control: &Control<'_>,
    normal: Option<&[f64]>,
) -> Vec<(OptimResult, f64)> {
    match problems {
        [] => Vec::new(),
        [p] => vec![polish_from(p, &p.start(), opts, control, normal)],
        [first, rest @ ..] => {
            let stop = control.stop;
            let (head, tail) = rayon::join(
                || polish_from(first, &first.start(), opts, control, normal),
                || probes_from(rest, opts, &Control { stop, progress: &|_| {} }, normal),
            );
            let mut runs = Vec::with_capacity(problems.len());
            runs.push(head);
            runs.extend(tail);
            runs
        }
    }
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
    let (result, _) = engine(
        z,
        &lo,
        &hi,
        problem.size(),
        |z| {
            let table = problem.basis_table(&params_of(z), false);
            problem.value_with(&table, &z[..d])
        },
        |z| -> Option<Box<dyn Model>> {
            let lin = problem.residuals_and_jacobian_with_params(&z[..d], &params_of(z), free)?;
            let (a, g) = normal_equations(&lin);
            Some(Box::new(Dense::new(a, g)))
        },
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

/// The Levenberg-Marquardt loop over `z` in the box `[lo, hi]`; `value(z) = |r(z)|`,
/// `normal(z)` the Gauss-Newton model there or `None` where infeasible.
#[allow(clippy::too_many_arguments)]
fn engine<'a>(
    mut z: Vec<f64>,
    lo: &[f64],
    hi: &[f64],
    size: f64,
    value: impl Fn(&[f64]) -> f64,
    normal: impl Fn(&[f64]) -> Option<Box<dyn Model + 'a>>,
    opts: &LmOptions,
    control: &Control<'_>,
) -> (OptimResult, f64) {
    let n = z.len();
    let mut evaluations = 1;
    let Some(mut model) = normal(&z) else {
        let r = OptimResult {
            x: z,
            value: f64::INFINITY,
            evaluations,
            iterations: 0,
            history: vec![f64::INFINITY],
            stop: StopReason::Converged,
        };
        return (r, opts.initial_damping);
    };
    // Values reported are the objective's own (the same sums in the same order as any other
    // caller gets), not |r| of the linearization, which differs by round-off.
    let mut f = value(&z);
    let mut history = vec![f];
    if !f.is_finite() {
        let r = OptimResult {
            x: z,
            value: f64::INFINITY,
            evaluations,
            iterations: 0,
            history,
            stop: StopReason::Converged,
        };
        return (r, opts.initial_damping);
    }
    let mut col_norm: Vec<f64> = model.scaling().iter().map(|t| t.sqrt()).collect();
    let mut mu = opts.initial_damping.max(f64::MIN_POSITIVE);
    let mut nu = 2.0;
    let floor = 1e-15 * size;
    let mut stop = StopReason::Iterations;
    let mut iterations = 0;
    let mut free: Vec<usize> = Vec::with_capacity(n);
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
        let g = model.gradient();
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
            let Some(h) = model.damped_step(&free, mu) else { break };
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
            let mut predicted = model.decrease(&h);
            let descends = predicted > 0.0; // false for NaN too
                                            // The variable whose bound stops a shortened step, and that bound.
            let mut blocking = None;
            if !descends {
                let mut alpha = 1.0f64;
                for i in 0..n {
                    let (t, bound) = if full[i] > 0.0 {
                        ((hi[i] - z[i]) / full[i], hi[i])
                    } else if full[i] < 0.0 {
                        ((lo[i] - z[i]) / full[i], lo[i])
                    } else {
                        continue;
                    };
                    if t < alpha {
                        alpha = t;
                        blocking = Some((i, bound));
                    }
                }
                let alpha = alpha.max(0.0);
                for i in 0..n {
                    zn[i] = z[i] + alpha * full[i];
                }
                clamp(&mut zn, lo, hi);
                // Exactly on its bound, not an ulp inside it: the next iteration holds it there
                // if the gradient pushes it out.
                if let Some((i, bound)) = blocking {
                    zn[i] = bound;
                }
                h = zn.iter().zip(&z).map(|(a, b)| a - b).collect();
                predicted = model.decrease(&h);
            }
            let hn = h.iter().map(|t| t * t).sum::<f64>().sqrt();
            let zn_norm = z.iter().map(|t| t * t).sum::<f64>().sqrt();
            if hn <= opts.step_tolerance * (zn_norm + opts.step_tolerance) {
                if let Some((i, bound)) = blocking {
                    // Not converged: a variable a hair from its bound blocks the step. Put it
                    // on the bound, where the next iteration holds it if the gradient pushes
                    // it out, and go on (stopping here left the cargo ship's fit after 3 of
                    // 100 iterations at 2.2 % above the plain fit).
                    z[i] = bound;
                    f = value(&z);
                    evaluations += 1;
                    match normal(&z) {
                        Some(next) if f.is_finite() => {
                            model = next;
                            col_norm = model.scaling().iter().map(|t| t.sqrt()).collect();
                            history.push(f);
                            continue;
                        }
                        _ => {}
                    }
                }
                stop = StopReason::Converged;
                history.push(f);
                break;
            }
            let fn_ = value(&zn);
            evaluations += 1;
            let actual = 0.5 * (f * f - fn_ * fn_);
            if fn_.is_finite() && actual > 0.0 {
                if let Some(next) = normal(&zn) {
                    accepted = true;
                    let rho = if predicted > 0.0 { actual / predicted } else { 1.0 };
                    mu *= (1.0 - (2.0 * rho - 1.0).powi(3)).max(1.0 / 3.0);
                    nu = 2.0;
                    let small =
                        actual <= opts.tolerance * 0.5 * f * f && predicted.abs() <= opts.tolerance * 0.5 * f * f;
                    z = zn;
                    f = fn_;
                    model = next;
                    col_norm = model.scaling().iter().map(|t| t.sqrt()).collect();
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
            let damped_out = mu >= 1e30 || mu.is_nan();
            if damped_out {
                history.push(f);
                stop = StopReason::Converged;
                break;
            }
        }
        history.push(f);
        (control.progress)(progress(iterations, opts, f, evaluations));
        let (window, relative) = opts.stall;
        if window > 0 && history.len() > window && history[history.len() - 1 - window] - f <= relative * f {
            stop = StopReason::Converged;
            break;
        }
    }
    (OptimResult { x: z, value: f, evaluations, iterations, history, stop }, mu)
}

fn progress(iteration: usize, opts: &LmOptions, best: f64, evaluations: usize) -> Progress {
    Progress { iteration, iterations: opts.max_iterations, best, evaluations }
}

#[cfg(test)]
mod tests;
