//! The Gauss-Newton model of one Levenberg-Marquardt iteration, and its damped step
//! `(J^T J + R + μ D) h = -(J^T r + R θ)` on the free variables, two ways.
//!
//! The rest of this module's documentation is on [`LmOptions`](super::LmOptions), where the library's users read it.

use std::cell::RefCell;
use std::rc::Rc;

use super::super::linalg::{dense_cholesky, dense_solve, dot};
use super::super::weights::{JacobianOp, WeightLayout, WeightProblem};
use super::super::Objective;
use super::LmOptions;

/// The local model of one iteration.
pub(super) trait Model {
    /// `J^T r + R θ`, the gradient of `|r|^2 / 2`.
    fn gradient(&self) -> &[f64];
    /// Marquardt's scaling `D` (the diagonal of `J^T J + R`, or an upper bound of it).
    fn scaling(&self) -> &[f64];
    /// The damped step on the `free` variables (zero elsewhere); `None` if the damped matrix is
    /// not positive definite to working precision or the step is not finite.
    fn damped_step(&mut self, free: &[usize], mu: f64) -> Option<Vec<f64>>;
    /// The model's decrease of `F = |r|^2 / 2` along `h`: `-h^T g - h^T (J^T J + R) h / 2`.
    fn decrease(&mut self, h: &[f64]) -> f64;
}

/// The damping's diagonal: `μ max(D_i, 1e-12 max_F D)`, so a variable with a zero column is
/// still damped.
fn damping(diag: &[f64], free: &[usize], mu: f64) -> impl Fn(f64) -> f64 {
    let dmax = free.iter().map(|&i| diag[i]).fold(0.0, f64::max);
    let floor = (1e-12 * dmax).max(f64::MIN_POSITIVE);
    move |d| mu * d.max(floor)
}

/// The normal equations formed: `a = J^T J + R` row-major, `g = J^T r + R θ`.
pub(super) struct Dense {
    a: Vec<f64>,
    g: Vec<f64>,
    diag: Vec<f64>,
    n: usize,
    m: Vec<f64>,
    rhs: Vec<f64>,
}

impl Dense {
    pub(super) fn new(a: Vec<f64>, g: Vec<f64>) -> Self {
        let n = g.len();
        let diag = (0..n).map(|i| a[i * n + i]).collect();
        Dense { a, g, diag, n, m: Vec::new(), rhs: Vec::new() }
    }
}

impl Model for Dense {
    fn gradient(&self) -> &[f64] {
        &self.g
    }
    fn scaling(&self) -> &[f64] {
        &self.diag
    }
    fn damped_step(&mut self, free: &[usize], mu: f64) -> Option<Vec<f64>> {
        let (a, n, nf, diag) = (&self.a, self.n, free.len(), &self.diag);
        let damp = damping(diag, free, mu);
        let (m, rhs) = (&mut self.m, &mut self.rhs);
        m.clear();
        m.resize(nf * nf, 0.0);
        for (r, &i) in free.iter().enumerate() {
            for (c, &j) in free.iter().enumerate() {
                m[r * nf + c] = a[i * n + j];
            }
            m[r * nf + r] += damp(diag[i]);
        }
        rhs.clear();
        rhs.extend(free.iter().map(|&i| -self.g[i]));
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
    fn decrease(&mut self, h: &[f64]) -> f64 {
        let n = h.len();
        let mut hah = 0.0;
        for i in 0..n {
            if h[i] != 0.0 {
                hah += h[i] * dot(&self.a[i * n..(i + 1) * n], h);
            }
        }
        -dot(h, &self.g) - 0.5 * hah
    }
}

/// The model by products with `J^T J` (see the docs of `LmOptions`).
pub(super) struct MatrixFree<'a> {
    problem: &'a WeightProblem,
    op: JacobianOp<'a>,
    g: Vec<f64>,
    diag: Vec<f64>,
    /// CG's relative residual `η` and iteration cap.
    tol: f64,
    max_cg: usize,
    /// Scratch: a product's data rows and its full-length input and output.
    rows: Vec<[f64; 3]>,
    full: Vec<f64>,
    out: Vec<f64>,
    /// CG iterations of the last step (for measurements).
    pub(super) cg_iterations: usize,
    /// CG's preconditioner when set: the normal matrix of an earlier point, factored (see
    /// [`StaleFactor`]); else Jacobi's.
    stale: Option<Rc<RefCell<StaleFactor>>>,
}

/// The normal matrix `J^T J + R` formed once, at a run's first point, and its damped Cholesky
/// factor, as the preconditioner of the matrix-free step at the run's later points (a
/// preconditioner need only be positive definite; the closer to the current matrix, the
/// fewer CG iterations). Unlike Jacobi's diagonal it sees the projection, which is what makes
/// `J^T J` ill-conditioned. Refactored (not re-formed) when the damping has moved more than
/// [`REFACTOR_RATIO`] from the factored one; the free set is that of the step (the factor's
/// inverse restricted to it, positive definite too).
pub(super) struct StaleFactor {
    /// `J^T J + R`, row-major `d x d`.
    normal: Vec<f64>,
    d: usize,
    /// Cholesky factor of `normal + μ D` (empty: not factored, or not positive definite).
    factor: Vec<f64>,
    /// The `μ` of `factor`.
    mu: f64,
    /// Whether the last factorization failed (then Jacobi's preconditioner is used).
    failed: bool,
    /// Scratch, `d`.
    full: Vec<f64>,
}

/// [`StaleFactor`] refactors when `μ` has moved by more than this factor either way. Measured
/// on the DTMB 5415 main hull, the fair objective: 10 gives 23 iterations (7 factorizations in
/// the first 20), 100 gives 24, never refactoring 36 (and on the five grids of 176 to 256 weights 1.1x-1.8x the time).
const REFACTOR_RATIO: f64 = 10.0;

impl StaleFactor {
    /// The preconditioner from the normal matrix `J^T J + R` (`d x d`, row-major).
    pub(super) fn new(normal: Vec<f64>, d: usize) -> Self {
        StaleFactor { normal, d, factor: Vec::new(), mu: 0.0, failed: false, full: vec![0.0; d] }
    }

    /// Factors `normal + μ D` unless the current factor's `μ` is within [`REFACTOR_RATIO`];
    /// `false` if it is not positive definite.
    fn prepare(&mut self, mu: f64, diag: &[f64], free: &[usize]) -> bool {
        let ratio = mu / self.mu;
        let fresh = !self.factor.is_empty() && (1.0 / REFACTOR_RATIO..=REFACTOR_RATIO).contains(&ratio);
        if fresh || (self.failed && self.mu == mu) {
            return fresh;
        }
        let damp = damping(diag, free, mu);
        let d = self.d;
        self.factor.clone_from(&self.normal);
        for (i, &di) in diag.iter().enumerate() {
            self.factor[i * d + i] += damp(di);
        }
        self.mu = mu;
        self.failed = !dense_cholesky(&mut self.factor, d);
        if self.failed {
            self.factor.clear();
        }
        !self.failed
    }

    /// `z = (M^{-1})_FF r` on the free variables `free`.
    fn apply(&mut self, free: &[usize], r: &[f64], z: &mut [f64]) {
        self.full.iter_mut().for_each(|t| *t = 0.0);
        for (&i, &ri) in free.iter().zip(r) {
            self.full[i] = ri;
        }
        dense_solve(&self.factor, self.d, &mut self.full);
        for (&i, zi) in free.iter().zip(z.iter_mut()) {
            *zi = self.full[i];
        }
    }
}

impl<'a> MatrixFree<'a> {
    /// The model at `x` from its Jacobian operator; CG stops at relative residual `tol` or
    /// after `max_cg` iterations. `None` if the gradient is not finite.
    pub(super) fn new(
        problem: &'a WeightProblem,
        mut op: JacobianOp<'a>,
        x: &[f64],
        tol: f64,
        max_cg: usize,
    ) -> Option<Self> {
        let mut g = op.gradient();
        problem.prior_apply(x, &mut g);
        let mut diag = op.diag_ata();
        let prior = problem.prior_diag();
        for (d, r) in diag.iter_mut().zip(&prior) {
            *d += r;
        }

        let d = g.len();
        g.iter().all(|t| t.is_finite()).then(|| MatrixFree {
            problem,
            op,
            g,
            diag,
            tol,
            max_cg,
            rows: Vec::new(),
            full: vec![0.0; d],
            out: vec![0.0; d],
            cg_iterations: 0,
            stale: None,
        })
    }

    /// Preconditions CG with `stale` (shared by the models of one run) instead of Jacobi.
    pub(super) fn set_preconditioner(&mut self, stale: Rc<RefCell<StaleFactor>>) {
        self.stale = Some(stale);
    }

    /// Sets CG's relative residual `η` (the forcing term of this step).
    pub(super) fn set_tolerance(&mut self, tol: f64) {
        self.tol = tol;
    }

    /// `out = (J^T J + R) full`.
    fn product(&mut self) {
        self.op.normal_apply(&self.full, &mut self.out, &mut self.rows);
        self.problem.prior_apply(&self.full, &mut self.out);
    }
}

impl Model for MatrixFree<'_> {
    fn gradient(&self) -> &[f64] {
        &self.g
    }
    fn scaling(&self) -> &[f64] {
        &self.diag
    }
    fn damped_step(&mut self, free: &[usize], mu: f64) -> Option<Vec<f64>> {
        let nf = free.len();
        let damp = damping(&self.diag, free, mu);
        let dd: Vec<f64> = free.iter().map(|&i| damp(self.diag[i])).collect();
        let precond: Vec<f64> = free.iter().zip(&dd).map(|(&i, &d)| 1.0 / (self.diag[i] + d)).collect();
        let stale = self.stale.clone().filter(|s| s.borrow_mut().prepare(mu, &self.diag, free));
        let apply_m = |r: &[f64], z: &mut [f64]| match &stale {
            Some(s) => s.borrow_mut().apply(free, r, z),
            None => {
                for ((zk, &rk), &pk) in z.iter_mut().zip(r).zip(&precond) {
                    *zk = rk * pk;
                }
            }
        };
        // Preconditioned CG on K_FF h = -g_F, K = J^T J + R + μ D, from h = 0.
        let mut h = vec![0.0; nf];
        let mut r: Vec<f64> = free.iter().map(|&i| -self.g[i]).collect();
        let bnorm = dot(&r, &r).sqrt();
        let mut zv = vec![0.0; nf];
        apply_m(&r, &mut zv);
        let mut p = zv.clone();
        let mut rz = dot(&r, &zv);
        let mut q = vec![0.0; nf];
        self.cg_iterations = 0;
        let max_cg = self.max_cg;
        while self.cg_iterations < max_cg.min(nf.max(1)) && bnorm > 0.0 {
            self.full.iter_mut().for_each(|t| *t = 0.0);
            for (&i, &pi) in free.iter().zip(&p) {
                self.full[i] = pi;
            }
            self.product();
            for (((qk, &i), &pk), &dk) in q.iter_mut().zip(free).zip(&p).zip(&dd) {
                *qk = self.out[i] + dk * pk;
            }
            let pq = dot(&p, &q);
            if !(pq > 0.0) {
                // Not positive definite along p (round-off): keep what was reached.
                if self.cg_iterations == 0 {
                    return None;
                }
                break;
            }
            self.cg_iterations += 1;
            let alpha = rz / pq;
            for k in 0..nf {
                h[k] += alpha * p[k];
                r[k] -= alpha * q[k];
            }
            if dot(&r, &r).sqrt() <= self.tol * bnorm {
                break;
            }
            apply_m(&r, &mut zv);
            let rz_next = dot(&r, &zv);
            let beta = rz_next / rz;
            rz = rz_next;
            for k in 0..nf {
                p[k] = zv[k] + beta * p[k];
            }
        }
        if !h.iter().all(|t| t.is_finite()) {
            return None;
        }
        let mut step = vec![0.0; self.g.len()];
        for (&i, &hi) in free.iter().zip(&h) {
            step[i] = hi;
        }
        Some(step)
    }
    fn decrease(&mut self, h: &[f64]) -> f64 {
        self.full.copy_from_slice(h);
        self.product();
        -dot(h, &self.g) - 0.5 * dot(h, &self.out)
    }
}

/// The inexact-Newton forcing term of the next step, Eisenstat and Walker's choice 2
/// ("Choosing the forcing terms in an inexact Newton method", SIAM J. Sci. Comput. 17, 1996,
/// eq. 2.6 with its safeguard 2.7): `η_k = γ (|g_k| / |g_{k-1}|)^α` with `γ = 0.9`, `α = 2`,
/// raised to `γ η_{k-1}^α` when that exceeds `0.1` (so one lucky step does not make the next
/// one needlessly exact), and kept within `[eta_min, eta_max]`. `prev` is `None` at the
/// first step, which gets `eta_max`. The gradient norms are those of `|r|^2 / 2` at the
/// accepted points: the step is solved as accurately as the iteration converges, loosely far
/// from the minimum and tightly near it, where a truncated step would stall the run.
pub(super) fn forcing(prev: Option<(f64, f64)>, g_norm: f64, eta_max: f64, eta_min: f64) -> f64 {
    const GAMMA: f64 = 0.9;
    const ALPHA: f64 = 2.0;
    let Some((prev_eta, prev_g)) = prev else { return eta_max };
    let ratio = if prev_g > 0.0 { g_norm / prev_g } else { 1.0 };
    let mut eta = GAMMA * ratio.powf(ALPHA);
    let safeguard = GAMMA * prev_eta.powf(ALPHA);
    if safeguard > 0.1 {
        eta = eta.max(safeguard);
    }
    if eta.is_nan() {
        eta = eta_max;
    }
    eta.clamp(eta_min.min(eta_max), eta_max)
}

/// How the damped step is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum StepPath {
    Dense,
    MatrixFree,
}

/// Products per matrix-free iteration assumed by [`step_path`]: [`TYPICAL_CG`] CG iterations
/// (or [`LmOptions::max_cg`] if fewer), the gradient and the model's decrease.
const EXTRA_PRODUCTS: usize = 2;

/// CG iterations of a typical matrix-free step for [`step_path`]'s estimate: the loose first
/// steps of the forcing sequence take a few, the tight last ones up to the cap.
const TYPICAL_CG: usize = 8;

/// How much cheaper the matrix-free iteration must be to be chosen: a truncated step gains
/// less than the exact one (on the Series 60 table, 114 weights, where it is estimated 2x
/// cheaper, LM ended at 4.65 mm objective against 3.58 mm with the dense step).
const MATRIX_FREE_MARGIN: usize = 4;

/// The cheaper step for `problem`: forming and factoring the normal equations costs about
/// `d n (bw + d / 3) + d^3 / 6` multiply-adds an iteration
/// ([`WeightProblem::normal_equations`]), the matrix-free step about
/// `TYPICAL_CG + 2` products. [`LmOptions::matrix_free`] overrides the choice.
pub(super) fn step_path(problem: &WeightProblem, opts: &LmOptions) -> StepPath {
    match opts.matrix_free {
        Some(true) => return StepPath::MatrixFree,
        Some(false) => return StepPath::Dense,
        None => {}
    }
    if problem.options().layout == WeightLayout::RankOne {
        return StepPath::Dense;
    }
    let dense = dense_cost(problem);
    let free = (opts.max_cg.min(TYPICAL_CG) + EXTRA_PRODUCTS) * problem.product_cost();
    if MATRIX_FREE_MARGIN * free < dense {
        StepPath::MatrixFree
    } else {
        StepPath::Dense
    }
}

/// Multiply-adds of forming and factoring the normal equations once,
/// `d n (bw + d / 3) + d^3 / 6` ([`WeightProblem::normal_equations`]).
fn dense_cost(problem: &WeightProblem) -> usize {
    let d = problem.dim();
    let (n, bw) = (problem.ctrl().0 * problem.ctrl().1, problem.bandwidth());
    d * n * (bw + d / 3) + d * d * d / 6
}

/// The most products of `J^T J` that forming and factoring a [`StaleFactor`] may cost. On the
/// grids of 176 to 256 weights of `testdata/` it costs 42 to 72 products and cut LM's
/// iterations on the fair objective 2x-5x (DTMB 5415 main 105 -> 23, MATLAB Series 60 120 ->
/// 24); on Gunnerus, WPB and the yacht (564 to 780 weights, 367 to 481 products) `hullskin
/// fit --method lm` took 1.1x, 1.9x and 3.5x the time with it (one run each), the frigate
/// (495 weights, 245 products) 0.9x.
const STALE_FACTOR_PRODUCTS: usize = 120;

/// Whether the matrix-free step of `problem` is preconditioned by a [`StaleFactor`] formed at
/// the run's first point: on the fair objective (`WeightOptions::fair > 0`, where the weights
/// stay near 1 and the first point's `J^T J` stays close to the later ones'), when forming it
/// costs at most [`STALE_FACTOR_PRODUCTS`] products. On the plain objective the weights travel
/// to their bounds and the first point's matrix goes stale: the same preconditioner took
/// 1.3x-7x the time there, to lower objectives whose surfaces had validity findings (DTMB
/// 5415 bow, MATLAB Series 60, cargo ship). [`LmOptions::stale_factor`] overrides the choice.
pub(super) fn stale_factor_pays(problem: &WeightProblem, opts: &LmOptions) -> bool {
    opts.stale_factor.unwrap_or_else(|| {
        problem.options().fair > 0.0 && dense_cost(problem) <= STALE_FACTOR_PRODUCTS * problem.product_cost()
    })
}

/// The gain of a probe's last 10 iterations, relative to its objective, above which
/// [`continuation_factor`] goes on with the factored preconditioner: a run still descending
/// that fast on Jacobi's is crawling towards a minimum it reaches only with the factor. On the
/// fair objective (`tools/lm_speed.sh`'s tables), after the 20 iterations of `run_best_of`'s
/// probe: Gunnerus 2.6e-2, WPB 5.4e-2, the frigate 7.9e-3, the DTMB 5415 mesh 9.2e-2, the Wigley
/// mesh 1.8e-2, where Jacobi's runs end 8.7 % to 20 % of the way short of the factor's minimum
/// (the frigate at 86 iterations, the three others at the 120-iteration cap; WPB at 60, 0.5 %
/// short); the DTC mesh 2.7e-3 and the yacht 2.1e-3, which end at 28 and 33 iterations, where
/// forming the factor (about 100 ms at 713 to 780 weights) would double LM's time.
pub(super) const CRAWL_GAIN: f64 = 5e-3;

/// The preconditioner of [`super::run_best_of`]'s continuation after its probe: as `opts` says
/// where it says, or where the factor is used from the start ([`stale_factor_pays`]); else the
/// factor, formed where the probe ended, on the fair objective's matrix-free step when the
/// probe's last 10 iterations (`history`, the best value after each) gained more than
/// [`CRAWL_GAIN`] of the objective.
pub(super) fn continuation_factor(problem: &WeightProblem, opts: &LmOptions, history: &[f64]) -> Option<bool> {
    if opts.stale_factor.is_some() || problem.options().fair <= 0.0 || stale_factor_pays(problem, opts) {
        return opts.stale_factor;
    }
    let crawling = match history {
        [.., a, _, _, _, _, _, _, _, _, _, b] => *b > 0.0 && (a - b) > CRAWL_GAIN * b,
        _ => false,
    };
    crawling.then_some(true)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::weights::{WeightMode, WeightOptions};
    use crate::{fit_offsets, series60_sample, FitConfig};

    /// `run_best_of`'s continuation on Gunnerus (564 weights, the fair objective, where the
    /// factor is not formed at the start): a probe still gaining more than [`CRAWL_GAIN`] in its
    /// last 10 iterations goes on with the factor, one gaining less, too short a history or the
    /// plain objective with Jacobi's, and the options' choice stands. Run: with the factor
    /// the continuation converges, to a lower objective than Jacobi's reaches at the same
    /// budget (measured 1.866e-2 against 1.951e-2 m from 2.369e-2, Jacobi's at the cap).
    #[test]
    fn a_crawling_probe_goes_on_with_the_factor() {
        let path = std::path::Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/gunnerus_offsets.csv");
        let offsets = crate::read_offsets(&path, crate::Units::Metre).expect("reads");
        let fit = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        let p = WeightProblem::from_fit(&fit, &offsets, WeightOptions::default())
            .and_then(|p| p.with_fairness(crate::NET_FAIR, crate::WEIGHT_SMOOTHING))
            .expect("shapes match");
        let opts = LmOptions { max_iterations: 120, ..LmOptions::default() };
        assert!(!stale_factor_pays(&p, &opts) && step_path(&p, &opts) == StepPath::MatrixFree, "d = {}", p.dim());
        // 1 % of the objective an iteration (over 10 % in 10), and 0.01 % (0.1 % in 10).
        let crawl: Vec<f64> = (0..=20).map(|k| 1.0 - 0.01 * k as f64).collect();
        let settled: Vec<f64> = (0..=20).map(|k| 1.0 - 1e-4 * k as f64).collect();
        assert_eq!(continuation_factor(&p, &opts, &crawl), Some(true));
        assert_eq!(continuation_factor(&p, &opts, &settled), None);
        assert_eq!(continuation_factor(&p, &opts, &crawl[..10]), None);
        assert_eq!(continuation_factor(&p, &LmOptions { stale_factor: Some(false), ..opts }, &crawl), Some(false));
        let plain = p.with_fairness(0.0, 0.0).expect("usable");
        assert_eq!(continuation_factor(&plain, &opts, &crawl), None);
        let quiet = |o: &LmOptions| crate::quiet(|c| super::super::run_best_of(&[&p], o, 20, c)).1;
        let (chosen, jacobi) = (quiet(&opts), quiet(&LmOptions { stale_factor: Some(false), ..opts }));
        assert_eq!(chosen.stop, super::super::StopReason::Converged, "{} iterations", chosen.iterations);
        assert_eq!(jacobi.stop, super::super::StopReason::Iterations);
        assert!(chosen.value < jacobi.value, "{:e} against {:e}", chosen.value, jacobi.value);
    }

    /// Both models at one point of a small problem (Series 60 sample, 6 x 12, 72 weights): the
    /// same gradient and quadratic model, and CG solved to round-off gives the step of the
    /// dense system with the matrix-free scaling.
    #[test]
    fn dense_and_matrix_free_models_agree_on_a_small_problem() {
        let offsets = series60_sample();
        let fit = fit_offsets(&offsets, &FitConfig { ctrl: Some((6, 12)), ..FitConfig::default() }).expect("fits");
        for mode in [WeightMode::Resolved, WeightMode::Fixed] {
            // No anchor: then J^T J is exactly A^T (I - H G^{-1} H^T) A / m on both sides.
            let opts = WeightOptions { mode, regularization: 1e-3, anchor: 0.0, ..WeightOptions::default() };
            let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match");
            let d = p.dim();
            let x: Vec<f64> = (0..d).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
            let ne = p.normal_equations(&x).expect("regular");
            let mut dense = Dense::new(ne.jtj.clone(), ne.jtr.clone());
            let op = p.jacobian_op(&x).expect("regular");
            let mut mf = MatrixFree::new(&p, op, &x, 1e-13, 10 * d).expect("finite");
            let gmax = ne.jtr.iter().map(|t| t.abs()).fold(0.0, f64::max);
            let gerr = dense.gradient().iter().zip(mf.gradient()).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            // The same sums in another order (the projected term is round-off at the
            // least-squares solution): 1e-9 of the largest component.
            assert!(gerr <= 1e-9 * gmax, "{mode:?}: gradient {gerr:e} of {gmax:e}");
            let h: Vec<f64> = (0..d).map(|i| 0.01 * ((i as f64) * 1.3).cos()).collect();
            let (a, b) = (dense.decrease(&h), mf.decrease(&h));
            assert!((a - b).abs() <= 1e-9 * a.abs().max(b.abs()), "{mode:?}: decrease {a:e} vs {b:e}");
            // The matrix-free scaling bounds the dense one from above.
            assert!(dense.scaling().iter().zip(mf.scaling()).all(|(a, b)| *a <= b * (1.0 + 1e-12)));
            // Free: all but every fifth variable. CG minimises the damped quadratic
            // q(h) = g^T h + h^T (J^T J + R + μ D) h / 2 on them: its minimum equals the dense
            // solve's with the same scaling D (the well-conditioned measure: the steps
            // themselves differ along the nearly flat directions by round-off / μ).
            let free: Vec<usize> = (0..d).filter(|i| i % 5 != 0).collect();
            let mu = 1e-3;
            let step = mf.damped_step(&free, mu).expect("positive definite");
            let mut same_d = Dense::new(ne.jtj.clone(), ne.jtr.clone());
            same_d.diag = mf.scaling().to_vec();
            let exact = same_d.damped_step(&free, mu).expect("positive definite");
            let damp = damping(mf.scaling(), &free, mu);
            let mut q = |h: &[f64]| {
                let ds: f64 = free.iter().map(|&i| damp(mf.scaling()[i]) * h[i] * h[i]).sum();
                -same_d.decrease(h) + 0.5 * ds
            };
            let (qm, qd) = (q(&step), q(&exact));
            assert!(qd < 0.0 && (qm - qd).abs() <= 1e-9 * qd.abs(), "{mode:?}: q {qm:e} vs dense {qd:e}");
            assert!((0..d).filter(|i| i % 5 == 0).all(|i| step[i] == 0.0));
            // A truncated CG step (2 iterations) still descends.
            let mut short = MatrixFree::new(&p, p.jacobian_op(&x).expect("regular"), &x, 1e-13, 2).expect("finite");
            let hs = short.damped_step(&free, mu).expect("positive definite");
            assert_eq!(short.cg_iterations, 2);
            assert!(short.decrease(&hs) > 0.0);
        }
    }

    /// Preconditioned by the normal matrix of the same point, CG solves the damped step in
    /// one iteration (the preconditioner is the system up to round-off) and refactors only
    /// when the damping moves more than `REFACTOR_RATIO`; with the matrix of another point, or
    /// on a free subset (where it is the inverse's block, not the block's inverse), it still
    /// reaches the step, in fewer iterations than Jacobi's.
    #[test]
    fn the_stale_factor_preconditions_the_matrix_free_step() {
        let offsets = series60_sample();
        let fit = fit_offsets(&offsets, &FitConfig { ctrl: Some((6, 12)), ..FitConfig::default() }).expect("fits");
        let opts = WeightOptions { regularization: 1e-3, anchor: 0.0, ..WeightOptions::default() };
        let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match");
        let p = p.with_fairness(1e-3, 1e-4).expect("usable");
        let d = p.dim();
        let x: Vec<f64> = (0..d).map(|i| 0.3 * ((i as f64) * 0.7).sin()).collect();
        let here = p.normal_equations(&x).expect("regular");
        let all: Vec<usize> = (0..d).collect();
        let subset: Vec<usize> = (0..d).filter(|i| i % 7 != 3).collect();
        let mu = 1e-3;
        let model =
            |tol: f64| MatrixFree::new(&p, p.jacobian_op(&x).expect("regular"), &x, tol, 10 * d).expect("finite");
        // Jacobi-preconditioned CG to round-off: the steps, and its iterations to 1e-8.
        let jacobi = |free: &[usize]| {
            let h = model(1e-13).damped_step(free, mu).expect("positive definite");
            let mut m = model(1e-8);
            m.damped_step(free, mu).expect("positive definite");
            (h, m.cg_iterations)
        };
        let close = |a: &[f64], b: &[f64]| {
            let scale = b.iter().map(|t| t.abs()).fold(0.0, f64::max);
            a.iter().zip(b).map(|(s, t)| (s - t).abs()).fold(0.0, f64::max) <= 1e-6 * scale
        };
        let stale = Rc::new(RefCell::new(StaleFactor::new(here.jtj.clone(), d)));
        let mut m = model(1e-8);
        m.set_preconditioner(Rc::clone(&stale));
        let h = m.damped_step(&all, mu).expect("positive definite");
        assert_eq!(m.cg_iterations, 1);
        let (exact, _) = jacobi(&all);
        assert!(close(&h, &exact), "stale-preconditioned step against Jacobi's to round-off");
        // Within the ratio the factor is kept; beyond it, refactored.
        let kept = stale.borrow().factor.clone();
        m.damped_step(&all, 5.0 * mu).expect("positive definite");
        assert_eq!(stale.borrow().factor, kept);
        assert_eq!(stale.borrow().mu, mu);
        m.damped_step(&all, 20.0 * mu).expect("positive definite");
        assert_eq!(stale.borrow().mu, 20.0 * mu);
        // A free subset, and the matrix of another point.
        let (exact, its) = jacobi(&subset);
        let h = m.damped_step(&subset, mu).expect("positive definite");
        assert!(close(&h, &exact), "on a free subset");
        assert!((0..d).filter(|i| i % 7 == 3).all(|i| h[i] == 0.0));
        assert!(m.cg_iterations < its, "{} CG iterations, Jacobi {its}", m.cg_iterations);
        let y: Vec<f64> = x.iter().map(|t| 0.9 * t + 0.02).collect();
        let there = p.normal_equations(&y).expect("regular");
        let mut m = model(1e-8);
        m.set_preconditioner(Rc::new(RefCell::new(StaleFactor::new(there.jtj, d))));
        let h = m.damped_step(&subset, mu).expect("positive definite");
        assert!(close(&h, &exact), "with another point's matrix");
        assert!(m.cg_iterations < its, "{} CG iterations, Jacobi {its}", m.cg_iterations);
        // On the fair objective of a small problem it pays; on the plain one it does not;
        // the option overrides.
        let lm = LmOptions::default();
        assert!(stale_factor_pays(&p, &lm));
        let plain = WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match");
        assert!(!stale_factor_pays(&plain, &lm));
        assert!(stale_factor_pays(&plain, &LmOptions { stale_factor: Some(true), ..lm }));
        assert!(!stale_factor_pays(&p, &LmOptions { stale_factor: Some(false), ..lm }));
    }

    #[test]
    fn small_problems_take_the_dense_step_and_large_ones_the_matrix_free() {
        let offsets = series60_sample();
        let path = |ctrl: (usize, usize)| {
            let fit = fit_offsets(&offsets, &FitConfig { ctrl: Some(ctrl), ..FitConfig::default() }).expect("fits");
            let p = WeightProblem::from_fit(&fit, &offsets, WeightOptions::default()).expect("shapes match");
            step_path(&p, &LmOptions::default())
        };
        // 5 x 8 = 40 weights: forming 40 x 40 is cheaper than 10 products; 8 x 25 = 200
        // weights: the dense system costs ~40 times more than one product per CG iteration.
        assert_eq!(path((5, 8)), StepPath::Dense);
        assert_eq!(path((8, 25)), StepPath::MatrixFree);
        let forced = LmOptions { matrix_free: Some(true), ..LmOptions::default() };
        let fit = fit_offsets(&offsets, &FitConfig { ctrl: Some((5, 8)), ..FitConfig::default() }).expect("fits");
        let p = WeightProblem::from_fit(&fit, &offsets, WeightOptions::default()).expect("shapes match");
        assert_eq!(step_path(&p, &forced), StepPath::MatrixFree);
    }

    /// The forcing term against Eisenstat and Walker's formula 2.6 and safeguard 2.7.
    #[test]
    fn the_forcing_term_follows_eisenstat_and_walker() {
        let (max, min) = (0.5, 1e-4);
        // The first step: the loosest.
        assert_eq!(forcing(None, 1.0, max, min), max);
        // The gradient fell 10x after a step at η = 0.01: 0.9 (0.1)^2 = 0.009 (the safeguard,
        // 0.9 * 1e-4, is below 0.1 and does not apply).
        let eta = forcing(Some((0.01, 1.0)), 0.1, max, min);
        assert!((eta - 0.009).abs() < 1e-15, "{eta}");
        // The same fall after a loose step (η = 0.5, safeguard 0.9 * 0.25 = 0.225 > 0.1).
        let eta = forcing(Some((0.5, 1.0)), 0.1, max, min);
        assert!((eta - 0.225).abs() < 1e-15, "{eta}");
        // A rising gradient: capped at the loosest; a collapse: floored at the tightest.
        assert_eq!(forcing(Some((0.01, 1.0)), 2.0, max, min), max);
        assert_eq!(forcing(Some((0.01, 1.0)), 1e-6, max, min), min);
        // Degenerate norms give a finite term within the bounds.
        for (prev, g) in [(Some((0.01, 0.0)), 0.0), (Some((0.01, f64::NAN)), 1.0), (Some((0.01, 1.0)), f64::NAN)] {
            let eta = forcing(prev, g, max, min);
            assert!((min..=max).contains(&eta), "{prev:?} {g}: {eta}");
        }
    }
}
