//! The Gauss-Newton normal equations `J^T J`, `J^T r` of the weights with Kaufman's Jacobian,
//! formed without `J` ([`NormalEquations`]): the Levenberg-Marquardt hot loop, and the diagonal
//! that sizes the evolutionary algorithms' search box.

use rayon::prelude::*;

use super::{dot, Scratch, WeightMode, WeightProblem};
use crate::optimize::linalg::subtract_gram_below;

/// The Gauss-Newton normal equations `J^T J` and `J^T r` of the weight variables, with `J`
/// Kaufman's Jacobian ([`JacobianKind::Kaufman`](super::JacobianKind::Kaufman)) in `Resolved` mode, formed without `J`
/// (see [`WeightProblem::normal_equations`]).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalEquations {
    /// `J^T J`, row-major `dim x dim`, symmetric.
    pub jtj: Vec<f64>,
    /// `J^T r`, the gradient of `|r|^2 / 2`.
    pub jtr: Vec<f64>,
    pub dim: usize,
}

impl WeightProblem {
    /// `J^T J` and `J^T r` of [`WeightProblem::residuals_and_jacobian`] with Kaufman's
    /// Jacobian, without forming `J` (the Levenberg-Marquardt hot loop); `None` where the value
    /// is infinite.
    ///
    /// With `A_v` the derivative of the residuals at fixed control points (column `v`, sparse:
    /// only the offsets in the support of `v`'s control points), `J_v = (I - H G^{-1} H^T) A_v
    /// / sqrt(m)` in `Resolved` mode. As `I - H G^{-1} H^T` is a symmetric projector,
    ///
    /// `m J^T J = A^T A - Z^T G^{-1} Z = A^T A - W^T W`, `Z_v = H^T A_v`, `W_v = L^{-1} Z_v`,
    ///
    /// with `G = L L^T` the Cholesky factor the evaluation made, and
    /// `m J^T r = A^T e - W^T L^{-1} H^T e` (`e_k = S_k - Q_k`; the last term is round-off at the
    /// least-squares solution), plus the regularisation rows' `ρ^2 / d` on the diagonal and
    /// `ρ^2 θ / d`. `Z_v` is non-zero only from the band position `s_v` of the first control
    /// point sharing an offset with `v`, so `W_v` is too (forward substitution from `s_v`),
    /// and `(W^T W)_{vw}` is a dot product over positions `>= max(s_v, s_w)`. Cost about
    /// `d n (bw + d / 3)` multiply-adds on average against `d n bw + 3 m d^2 / 2` for the dense
    /// `J` and its products (Series 60, `6 x 19`, 114 weights: 0.58 ms against 2.0 ms measured;
    /// rank one at `6 x 12`: 0.11 ms against 0.25 ms, as an offset's row of `A` has
    /// `(p+1) + (q+1)` entries there).
    /// In `Fixed` mode `m J^T J = A^T A`.
    pub fn normal_equations(&self, x: &[f64]) -> Option<NormalEquations> {
        let (jtj, jtr) = self.gauss_newton(x, true)?;
        Some(NormalEquations { jtj, jtr, dim: x.len() })
    }

    /// The diagonal of `J^T J` (with the prior's) of [`WeightProblem::normal_equations`], the
    /// same sums without the off-diagonal products: about `d n bw` multiply-adds instead of
    /// `d n (bw + d / 3)`. `None` where the value is infinite.
    pub(crate) fn jtj_diagonal(&self, x: &[f64]) -> Option<Vec<f64>> {
        self.gauss_newton(x, false).map(|(diag, _)| diag)
    }

    /// `(J^T J, J^T r)` (`full`: row-major `d x d`) or `(diag(J^T J), J^T r)`.
    pub(super) fn gauss_newton(&self, x: &[f64], full_out: bool) -> Option<(Vec<f64>, Vec<f64>)> {
        // With the gauge fixed the diagonal of `Π J^T J Π` needs the whole matrix.
        let full = full_out || self.gauge_fixed();
        let mut sc = Scratch::default();
        let table = &self.table;
        if !self.solve(table, x, &mut sc) {
            return None;
        }
        let pat = &self.pat;
        let (n, nb) = (pat.n(), pat.nb);
        let m = table.first.len();
        let d = x.len();
        let resolved = self.options.mode == WeightMode::Resolved;
        let pts = self.derivative_points(&sc);
        // A^T A (lower triangle), A^T e, Z_v (d blocks of n) from s_v on, H^T e.
        let mut ata = vec![0.0; if full { d * d } else { d }];
        let mut ate = vec![0.0; d];
        let mut z = if resolved { vec![[0.0f64; 3]; d * n] } else { Vec::new() };
        let mut start = vec![n; d];
        let mut hte = vec![[0.0f64; 3]; if resolved { n } else { 0 }];
        let mut h = vec![0.0; nb];
        // Offset k's row of A: (variable, dS_k/dvariable), one entry per variable it touches
        // (the rank-one layout sums its control points' derivatives: 2 (p+1) (q+1) into
        // (p+1) + (q+1) entries).
        let mut row: Vec<(usize, [f64; 3])> = Vec::with_capacity(2 * nb);
        for k in 0..m {
            let first = table.first[k];
            let s = sc.s[k];
            for (hl, bl) in h.iter_mut().zip(&table.vals[k * nb..(k + 1) * nb]) {
                *hl = bl * s;
            }
            let sp = self.point_of(table, &sc, k);
            let qk = self.points[k];
            let e = [sp[0] - qk[0], sp[1] - qk[1], sp[2] - qk[2]];
            self.a_row(first, sp, &h, &sc.w, &pts, &mut row);
            if resolved {
                for (&o, &hl) in pat.off.iter().zip(&h) {
                    let t = &mut hte[first + o];
                    t[0] += hl * e[0];
                    t[1] += hl * e[1];
                    t[2] += hl * e[2];
                }
            }
            for (i, &(v, av)) in row.iter().enumerate() {
                ate[v] += av[0] * e[0] + av[1] * e[1] + av[2] * e[2];
                for &(w, aw) in &row[..=i] {
                    if full || w == v {
                        let val = av[0] * aw[0] + av[1] * aw[1] + av[2] * aw[2];
                        ata[if full { v.max(w) * d + v.min(w) } else { v }] += val;
                    }
                }
                if resolved {
                    start[v] = start[v].min(first);
                    let zv = &mut z[v * n + first..(v + 1) * n];
                    for (&o, &h2) in pat.off.iter().zip(&h) {
                        let t = &mut zv[o];
                        t[0] += h2 * av[0];
                        t[1] += h2 * av[1];
                        t[2] += h2 * av[2];
                    }
                }
            }
        }
        let scale = 1.0 / m as f64;
        let mut jtj = ata;
        let mut jtr = ate;
        if resolved {
            let (bw, stride) = (pat.bw, pat.stride);
            // The d substitutions and `W^T W` (most of the cost, `d^2 n / 2` at full, by blocks:
            // `subtract_gram_below`) on rayon's pool, each entry the same sum whatever the thread
            // count.
            z.par_chunks_mut(n).zip(&start).for_each(|(zv, &sv)| nurbs::band_forward(&sc.band, n, bw, stride, zv, sv));
            nurbs::band_forward(&sc.band, n, bw, stride, &mut hte, 0);
            let t = hte.as_flattened();
            let w_of = |v: usize| z[v * n..(v + 1) * n].as_flattened();
            // The first non-zero of each `W_v` (flattened: 3 coordinates a row).
            let first: Vec<usize> = start.iter().map(|&s| 3 * s.min(n)).collect();
            // With the fairness term the least-squares optimality is A^T r = H^T e +
            // λ' D^T D Y = 0, not H^T e = 0, and the projected part of the augmented
            // gradient vanishes: J^T r = A^T e (as in `matvec::JacobianOp::gradient`).
            if self.fair_g == 0.0 {
                for (v, g) in jtr.iter_mut().enumerate() {
                    *g -= dot(&w_of(v)[first[v]..], &t[first[v]..]);
                }
            }
            if full {
                subtract_gram_below(&mut jtj, d, z.as_flattened(), 3 * n, &first);
            }
            // The diagonal one dot product each, so that `jtj_diagonal` gives it bit for bit.
            for (v, &s0) in first.iter().enumerate() {
                jtj[if full { v * d + v } else { v }] -= dot(&w_of(v)[s0..], &w_of(v)[s0..]);
            }
        }
        if !full {
            let prior = self.prior_diag();
            for v in 0..d {
                jtj[v] = jtj[v] * scale + prior[v];
                jtr[v] *= scale;
            }
            self.prior_apply(x, &mut jtr);
            let finite = jtj.iter().chain(&jtr).all(|t| t.is_finite());
            return finite.then_some((jtj, jtr));
        }
        for v in 0..d {
            for w in 0..v {
                // The lower triangle is the one computed; mirror it.
                let lower = jtj[v * d + w] * scale;
                jtj[v * d + w] = lower;
                jtj[w * d + v] = lower;
            }
            jtj[v * d + v] *= scale;
            jtr[v] *= scale;
        }
        // The data and fairness rows were differentiated at `Π x` (see `gauge`).
        self.project_gauge_symmetric(&mut jtj);
        self.project_gauge(&mut jtr);
        if !full_out {
            let prior = self.prior_diag();
            let mut diag: Vec<f64> = (0..d).map(|v| jtj[v * d + v] + prior[v]).collect();
            std::mem::swap(&mut jtj, &mut diag);
            self.prior_apply(x, &mut jtr);
            let finite = jtj.iter().chain(&jtr).all(|t| t.is_finite());
            return finite.then_some((jtj, jtr));
        }
        // The prior: J^T J += R (a column at a time: the diagonal and the smoothing's Laplacian),
        // J^T r += R x.
        self.prior_apply(x, &mut jtr);
        let mut e = vec![0.0; d];
        let mut col = vec![0.0; d];
        for v in 0..d {
            e[v] = 1.0;
            col.iter_mut().for_each(|t| *t = 0.0);
            self.prior_apply(&e, &mut col);
            e[v] = 0.0;
            for (w, c) in col.iter().enumerate() {
                if *c != 0.0 {
                    jtj[w * d + v] += c;
                }
            }
        }
        if !(jtj.iter().all(|t| t.is_finite()) && jtr.iter().all(|t| t.is_finite())) {
            return None;
        }
        Some((jtj, jtr))
    }
}
