//! The Gauss-Newton model of one Levenberg-Marquardt iteration, and its damped step
//! `(J^T J + R + μ D) h = -(J^T r + R θ)` on the free variables, two ways:
//!
//! * [`Dense`]: the normal matrix formed (`d x d`), the step by dense Cholesky, `D` its
//!   diagonal (Marquardt 1963).
//! * [`MatrixFree`]: only products with `J^T J` (see `weights/matvec.rs`, each
//!   `O(m (p+1)(q+1) + n bw)`), the step by preconditioned conjugate gradients (Hestenes and
//!   Stiefel 1952; Nocedal and Wright, *Numerical Optimization*, 2nd ed., Alg. 5.3) stopped at
//!   a relative residual `η` (an inexact Newton step: Dembo, Eisenstat and Steihaug 1982;
//!   every CG iterate from zero lowers the quadratic model, so a truncated step still
//!   descends). `D = diag(A^T A) / m + diag(R)`, the fixed-point part of the diagonal, an upper
//!   bound of `diag(J^T J + R)` that costs nothing (the exact one needs `d` band solves), is
//!   the damping's scaling and, with `μ`, the Jacobi preconditioner.
//!
//! [`step_path`] picks the cheaper by an estimate of the multiply-adds of one iteration.

use super::super::linalg::{dense_cholesky, dense_solve, dot};
use super::super::weights::{AtaBand, JacobianOp, WeightLayout, WeightProblem};
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
        let (a, n, nf) = (&self.a, self.n, free.len());
        let damp = damping(&self.diag, free, mu);
        let (m, rhs) = (&mut self.m, &mut self.rhs);
        m.clear();
        m.resize(nf * nf, 0.0);
        for (r, &i) in free.iter().enumerate() {
            for (c, &j) in free.iter().enumerate() {
                m[r * nf + c] = a[i * n + j];
            }
            m[r * nf + r] += damp(a[i * n + i]);
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

/// The model by products with `J^T J` (see the module docs).
pub(super) struct MatrixFree<'a> {
    problem: &'a WeightProblem,
    op: JacobianOp<'a>,
    /// `A^T A / m` banded, for the preconditioner (full layout).
    ata: Option<AtaBand>,
    prior: Vec<f64>,
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
}

impl<'a> MatrixFree<'a> {
    /// The model at `x` from its Jacobian operator; CG stops at relative residual `tol` or
    /// after `max_cg` iterations. `None` if the gradient is not finite.
    pub(super) fn new(problem: &'a WeightProblem, mut op: JacobianOp<'a>, x: &[f64], tol: f64, max_cg: usize) -> Option<Self> {
        let mut g = op.gradient();
        problem.prior_apply(x, &mut g);
        let mut diag = op.diag_ata();
        let prior = problem.prior_diag();
        for (d, r) in diag.iter_mut().zip(&prior) {
            *d += r;
        }
        let d = g.len();
        let ata = if std::env::var_os("LMBAND").is_some() { op.ata_band() } else { None };
        let tol = std::env::var("LMTOL").ok().and_then(|v| v.parse().ok()).unwrap_or(tol);
        g.iter().all(|t| t.is_finite()).then(|| MatrixFree {
            problem,
            op,
            ata,
            prior,
            g,
            diag,
            tol,
            max_cg,
            rows: Vec::new(),
            full: vec![0.0; d],
            out: vec![0.0; d],
            cg_iterations: 0,
        })
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
        // The band preconditioner A^T A / m + diag(R) + μ D on the free variables, where it
        // can be formed; else Jacobi.
        let mut mask = vec![false; self.g.len()];
        let mut extra = self.prior.clone();
        for (&i, &d) in free.iter().zip(&dd) {
            mask[i] = true;
            extra[i] += d;
        }
        let factor = if std::env::var_os("LMJACOBI").is_some() { None } else { self.ata.as_ref().and_then(|b| b.factor(&mask, &extra)) };
        let mut work = Vec::new();
        let mut wide = vec![0.0; self.g.len()];
        let mut apply_m = |r: &[f64], z: &mut [f64]| match (&self.ata, &factor) {
            (Some(b), Some(l)) => {
                wide.iter_mut().for_each(|t| *t = 0.0);
                for (&i, &ri) in free.iter().zip(r) {
                    wide[i] = ri;
                }
                b.solve(l, &mut wide, &mut work);
                for (zk, &i) in z.iter_mut().zip(free) {
                    *zk = wide[i];
                }
            }
            _ => {
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
        let max_cg: usize = std::env::var("LMMAXCG").ok().and_then(|v| v.parse().ok()).unwrap_or(self.max_cg);
        while self.cg_iterations < max_cg.min(nf.max(1)) && bnorm > 0.0 {
            self.full.iter_mut().for_each(|t| *t = 0.0);
            for (&i, &pi) in free.iter().zip(&p) {
                self.full[i] = pi;
            }
            // (J^T J + R) p, by fields (the preconditioner's closure holds `self.ata`).
            self.op.normal_apply(&self.full, &mut self.out, &mut self.rows);
            self.problem.prior_apply(&self.full, &mut self.out);
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
        if std::env::var_os("LMTRACE").is_some() {
            eprintln!("cg {} nf {} mu {mu:e} res {:e}", self.cg_iterations, nf, dot(&r, &r).sqrt() / bnorm);
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

/// How the damped step is solved.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum StepPath {
    Dense,
    MatrixFree,
}

/// CG iterations per step assumed by [`step_path`]'s estimate (measured: see lm.rs).
const EXPECTED_CG: usize = 30;

/// The cheaper step for `problem`: forming and factoring the normal equations costs about
/// `d n (bw + d / 3) + d^3 / 6` multiply-adds an iteration
/// ([`WeightProblem::normal_equations`]), the matrix-free step about `EXPECTED_CG + 2`
/// products. [`LmOptions::matrix_free`] overrides the choice.
pub(super) fn step_path(problem: &WeightProblem, opts: &LmOptions) -> StepPath {
    match opts.matrix_free {
        Some(true) => return StepPath::MatrixFree,
        Some(false) => return StepPath::Dense,
        None => {}
    }
    if problem.options().layout == WeightLayout::RankOne {
        return StepPath::Dense;
    }
    let d = problem.dim();
    let (n, bw) = (problem.ctrl().0 * problem.ctrl().1, problem.bandwidth());
    let dense = d * n * (bw + d / 3) + d * d * d / 6;
    let free = (EXPECTED_CG + 2) * problem.product_cost();
    if free < dense {
        StepPath::MatrixFree
    } else {
        StepPath::Dense
    }
}
