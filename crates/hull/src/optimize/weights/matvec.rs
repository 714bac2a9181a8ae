//! Kaufman's Jacobian of the variable-projection residual as an operator: products `J v`,
//! `J^T w` and `(J^T J) v` without forming `J` or `J^T J`, for a matrix-free
//! Levenberg-Marquardt step (conjugate gradients) on problems with many weights.
//!
//! The rest of this module's documentation is on [`LmOptions`](super::super::LmOptions), where the library's users read it.

use super::{band_solve, Scratch, WeightLayout, WeightMode, WeightProblem};
use crate::optimize::Objective;

/// One evaluation of a [`WeightProblem`]: the point, its value and the solved state.
pub(crate) struct Evaluation {
    x: Vec<f64>,
    value: f64,
    sc: Option<Scratch>,
}

impl Evaluation {
    /// The point evaluated.
    pub(crate) fn x(&self) -> &[f64] {
        &self.x
    }
    /// Its value (`+inf` where infeasible).
    pub(crate) fn value(&self) -> f64 {
        self.value
    }
}

/// Kaufman's Jacobian at one point of a [`WeightProblem`] (its own parameters), with the
/// evaluation's factor kept for the projections. Build with [`WeightProblem::jacobian_op`].
pub(crate) struct JacobianOp<'a> {
    problem: &'a WeightProblem,
    sc: Scratch,
    /// Offset `k`'s row block of `A`: entries `ptr[k] .. ptr[k+1]` of `var` and `val`.
    ptr: Vec<usize>,
    var: Vec<usize>,
    val: Vec<[f64; 3]>,
    /// `h_kl = B_kl / W_k`, `(p+1)(q+1)` per offset.
    h: Vec<f64>,
    /// `e_k = S_k - Q_k`.
    e: Vec<[f64; 3]>,
    resolved: bool,
    /// Scratch of the projection, `n` homogeneous rows.
    t: Vec<[f64; 3]>,
    /// Scratch of the gauge projection of a product's vector (see `gauge`).
    pv: Vec<f64>,
}

impl WeightProblem {
    /// Kaufman's Jacobian at `x` as an operator (see the docs of `LmOptions`); `None` where the value
    /// is infinite.
    #[cfg(test)]
    pub(crate) fn jacobian_op(&self, x: &[f64]) -> Option<JacobianOp<'_>> {
        self.jacobian_op_at(self.evaluate(x))
    }

    /// The value at `x`, bit-identical to [`Objective::value`], with the solved state kept
    /// for [`WeightProblem::jacobian_op_at`] (so an accepted trial point is not solved twice).
    pub(crate) fn evaluate(&self, x: &[f64]) -> Evaluation {
        let mut sc = Scratch::default();
        let table = &self.table;
        let solved = self.solve(table, x, &mut sc);
        let value = if solved { self.value_squared(table, x, &sc).sqrt() } else { f64::INFINITY };
        let value = if value.is_finite() { value } else { f64::INFINITY };
        Evaluation { x: x.to_vec(), value, sc: solved.then_some(sc) }
    }

    /// Kaufman's Jacobian at an evaluated point; `None` where its value is infinite.
    pub(crate) fn jacobian_op_at(&self, ev: Evaluation) -> Option<JacobianOp<'_>> {
        let sc = ev.sc?;
        let x = &ev.x;
        let table = &self.table;
        if !ev.value.is_finite() || x.len() != self.dim() {
            return None;
        }
        let pat = &self.pat;
        let nb = pat.nb;
        let m = table.first.len();
        let pts = self.derivative_points(&sc);
        let mut op = JacobianOp {
            problem: self,
            ptr: Vec::with_capacity(m + 1),
            var: Vec::with_capacity(m * nb),
            val: Vec::with_capacity(m * nb),
            h: Vec::with_capacity(m * nb),
            e: Vec::with_capacity(m),
            resolved: self.options.mode == WeightMode::Resolved,
            t: vec![[0.0; 3]; pat.n()],
            pv: Vec::new(),
            sc: Scratch::default(),
        };
        op.ptr.push(0);
        let mut row = Vec::with_capacity(2 * nb);
        for k in 0..m {
            let first = table.first[k];
            let s = sc.s[k];
            let sp = self.point_of(table, &sc, k);
            let qk = self.points[k];
            op.e.push([sp[0] - qk[0], sp[1] - qk[1], sp[2] - qk[2]]);
            let h0 = op.h.len();
            op.h.extend(table.vals[k * nb..(k + 1) * nb].iter().map(|bl| bl * s));
            self.a_row(first, sp, &op.h[h0..], &sc.w, &pts, &mut row);
            op.var.extend(row.iter().map(|&(v, _)| v));
            op.val.extend(row.iter().map(|&(_, a)| a));
            op.ptr.push(op.var.len());
        }
        let finite = op.val.iter().chain(&op.e).all(|a| a.iter().all(|c| c.is_finite()));
        op.sc = sc;
        finite.then_some(op)
    }

    /// Multiply-adds of one `(J^T J) v` product ([`JacobianOp::normal_apply`]), for choosing
    /// between the dense and the matrix-free step: `A v` and `A^T u` (6 per entry of `A`), and
    /// in `Resolved` mode `H^T u`, `H t` (6 per basis product) and the two band substitutions
    /// (`6 n bw`).
    pub(crate) fn product_cost(&self) -> usize {
        let pat = &self.pat;
        let per_row = match self.options.layout {
            WeightLayout::Full => pat.nb,
            WeightLayout::RankOne => pat.p + pat.q + 2,
        };
        let m = self.points.len();
        let a = 6 * m * per_row;
        if self.options.mode == WeightMode::Resolved {
            a + 6 * m * pat.nb + 6 * pat.n() * pat.bw
        } else {
            a
        }
    }
}

impl JacobianOp<'_> {
    /// Number of offsets `m`.
    fn m(&self) -> usize {
        self.e.len()
    }

    /// `u <- u - H G^{-1} H^T u` (`Resolved` mode; nothing in `Fixed` mode).
    fn project(&mut self, u: &mut [[f64; 3]]) {
        if !self.resolved {
            return;
        }
        let p = self.problem;
        let (pat, table) = (&p.pat, &p.table);
        let nb = pat.nb;
        self.t.iter_mut().for_each(|t| *t = [0.0; 3]);
        for (k, uk) in u.iter().enumerate() {
            let t = &mut self.t[table.first[k]..];
            for (&o, &hl) in pat.off.iter().zip(&self.h[k * nb..(k + 1) * nb]) {
                let to = &mut t[o];
                to[0] += hl * uk[0];
                to[1] += hl * uk[1];
                to[2] += hl * uk[2];
            }
        }
        band_solve(&self.sc.band, pat.n(), pat.bw, pat.stride, &mut self.t);
        for (k, uk) in u.iter_mut().enumerate() {
            let t = &self.t[table.first[k]..];
            for (&o, &hl) in pat.off.iter().zip(&self.h[k * nb..(k + 1) * nb]) {
                let to = t[o];
                uk[0] -= hl * to[0];
                uk[1] -= hl * to[1];
                uk[2] -= hl * to[2];
            }
        }
    }

    /// `u = A v` (unscaled).
    fn apply_a(&self, v: &[f64], u: &mut Vec<[f64; 3]>) {
        u.clear();
        u.extend((0..self.m()).map(|k| {
            let mut acc = [0.0; 3];
            for (&var, a) in self.var[self.ptr[k]..self.ptr[k + 1]].iter().zip(&self.val[self.ptr[k]..]) {
                let x = v[var];
                acc[0] += a[0] * x;
                acc[1] += a[1] * x;
                acc[2] += a[2] * x;
            }
            acc
        }));
    }

    /// `out += c A^T u`.
    fn add_at(&self, u: &[[f64; 3]], c: f64, out: &mut [f64]) {
        for (k, uk) in u.iter().enumerate() {
            for (&var, a) in self.var[self.ptr[k]..self.ptr[k + 1]].iter().zip(&self.val[self.ptr[k]..]) {
                out[var] += c * (a[0] * uk[0] + a[1] * uk[1] + a[2] * uk[2]);
            }
        }
    }

    /// `J v`: `3 m` rows, x, y, z of each offset in turn (the data rows of
    /// [`super::Linearization::jacobian`]).
    #[cfg(test)]
    pub(crate) fn apply(&mut self, v: &[f64]) -> Vec<f64> {
        let mut u = Vec::new();
        let mut v = v.to_vec();
        self.problem.project_gauge(&mut v);
        self.apply_a(&v, &mut u);
        self.project(&mut u);
        let scale = 1.0 / (self.m() as f64).sqrt();
        u.iter().flat_map(|r| r.map(|c| c * scale)).collect()
    }

    /// `J^T w` for `3 m` data rows `w`.
    #[cfg(test)]
    pub(crate) fn apply_t(&mut self, w: &[f64]) -> Vec<f64> {
        let mut u: Vec<[f64; 3]> = w.chunks_exact(3).map(|c| [c[0], c[1], c[2]]).collect();
        self.project(&mut u);
        let mut out = vec![0.0; self.problem.dim()];
        self.add_at(&u, 1.0 / (self.m() as f64).sqrt(), &mut out);
        self.problem.project_gauge(&mut out);
        out
    }

    /// `out = (J^T J) v` as the dense path forms it: `A^T (I - H G^{-1} H^T) A v / m`
    /// (`Π` on both sides when the gauge is fixed, see `gauge`).
    pub(crate) fn normal_apply(&mut self, v: &[f64], out: &mut [f64], u: &mut Vec<[f64; 3]>) {
        if self.problem.gauge_fixed() {
            self.pv.clear();
            self.pv.extend_from_slice(v);
            self.problem.project_gauge(&mut self.pv);
            let pv = std::mem::take(&mut self.pv);
            self.apply_a(&pv, u);
            self.pv = pv;
        } else {
            self.apply_a(v, u);
        }
        self.project(u);
        out.iter_mut().for_each(|t| *t = 0.0);
        self.add_at(u, 1.0 / self.m() as f64, out);
        self.problem.project_gauge(out);
    }

    /// `J^T r` of the data rows: `A^T (I - H G^{-1} H^T) e / m`. With the fairness term the
    /// least-squares optimality is `H^T e + λ' D^T D Y = 0` (not `H^T e = 0`), which makes the
    /// projected part of the augmented gradient vanish: `J^T r = A^T e / m` exactly.
    pub(crate) fn gradient(&mut self) -> Vec<f64> {
        let mut u = self.e.clone();
        if self.problem.fair_f == 0.0 {
            self.project(&mut u);
        }
        let mut out = vec![0.0; self.problem.dim()];
        self.add_at(&u, 1.0 / self.m() as f64, &mut out);
        self.problem.project_gauge(&mut out);
        out
    }

    /// `diag(A^T A) / m` (`diag(Π A^T A Π) / m` when the gauge is fixed): an upper bound of
    /// `diag(J^T J)` (the projection by `H` only removes), for the damping's scaling and the
    /// Jacobi preconditioner.
    pub(crate) fn diag_ata(&self) -> Vec<f64> {
        let dim = self.problem.dim();
        let mut d = vec![0.0; dim];
        for (&var, a) in self.var.iter().zip(&self.val) {
            d[var] += a[0] * a[0] + a[1] * a[1] + a[2] * a[2];
        }
        if self.problem.gauge_fixed() {
            // (Π M Π)_vv = M_vv - 2 (M 1_g)_v / n_g + 1_g^T M 1_g / n_g^2 for v in group g,
            // M = A^T A: one product A^T (A 1_g) per group.
            let mut u = Vec::new();
            for g in self.problem.gauge_groups() {
                if g.is_empty() {
                    continue;
                }
                let mut ones = vec![0.0; dim];
                ones[g.clone()].iter_mut().for_each(|t| *t = 1.0);
                self.apply_a(&ones, &mut u);
                let mut m1 = vec![0.0; dim];
                self.add_at(&u, 1.0, &mut m1);
                let n = g.len() as f64;
                let total: f64 = m1[g.clone()].iter().sum();
                for v in g {
                    d[v] += total / (n * n) - 2.0 * m1[v] / n;
                }
            }
        }
        let scale = 1.0 / self.m() as f64;
        d.iter_mut().for_each(|t| *t *= scale);
        d
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{noise, problem, product_sweep};
    use super::super::{JacobianKind, WeightLayout, WeightMode};
    use crate::optimize::linalg::dot;
    use crate::optimize::Objective;

    #[test]
    fn products_equal_the_dense_jacobians() {
        let mut seed = 17;
        // (8, 5) is factored u-major, (6, 12) v-major; both layouts and modes.
        for (ctrl, layout, mode, fair) in product_sweep() {
            let p = problem(ctrl, mode, layout, 1e-3).with_fairness(fair, fair / 10.0).expect("usable");
            let d = p.dim();
            let x: Vec<f64> = (0..d).map(|_| 0.8 * noise(&mut seed)).collect();
            let lin = p.residuals_and_jacobian(&x, JacobianKind::Kaufman).expect("regular");
            let ne = p.normal_equations(&x).expect("regular");
            let mut op = p.jacobian_op(&x).expect("regular");
            let rows = 3 * p.num_points();
            let v: Vec<f64> = (0..d).map(|_| noise(&mut seed)).collect();
            let w: Vec<f64> = (0..rows).map(|_| noise(&mut seed)).collect();
            // Dense references: J v, J^T w from the columns (data rows only).
            let jv: Vec<f64> = (0..rows).map(|r| (0..d).map(|c| lin.column(c)[r] * v[c]).sum()).collect();
            let jtw: Vec<f64> = (0..d).map(|c| dot(&lin.column(c)[..rows], &w)).collect();
            let scale_v = jv.iter().map(|t| t.abs()).fold(0.0, f64::max);
            let scale_w = jtw.iter().map(|t| t.abs()).fold(0.0, f64::max);
            let op_jv = op.apply(&v);
            let op_jtw = op.apply_t(&w);
            // The same sums in another order, through the same factor: round-off
            // amplified by cond(G) (<~ 1e4 here); with the anchor's ridge the dense
            // J carries the projector twice where the product has it once, an O(1e-9)
            // relative difference that only matters for J^T J (compared below with
            // the dense normal equations, which apply it once too).
            let err_v = jv.iter().zip(&op_jv).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            let err_w = jtw.iter().zip(&op_jtw).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(err_v <= 1e-11 * scale_v, "{ctrl:?} {layout:?} {mode:?}: J v {err_v:e} of {scale_v:e}");
            assert!(err_w <= 1e-11 * scale_w, "{ctrl:?} {layout:?} {mode:?}: J^T w {err_w:e} of {scale_w:e}");
            // (J^T J) v and J^T r against the dense normal equations (their prior
            // diagonal removed: the operator leaves it to the caller).
            let prior = p.prior_diag();
            let (mut rv, mut rx) = (vec![0.0; d], vec![0.0; d]);
            p.prior_apply(&v, &mut rv);
            p.prior_apply(&x, &mut rx);
            let mut out = vec![0.0; d];
            op.normal_apply(&v, &mut out, &mut Vec::new());
            let dense: Vec<f64> = (0..d).map(|i| dot(&ne.jtj[i * d..(i + 1) * d], &v) - rv[i]).collect();
            let sn = dense.iter().map(|t| t.abs()).fold(0.0, f64::max);
            let en = dense.iter().zip(&out).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(en <= 1e-11 * sn, "{ctrl:?} {layout:?} {mode:?}: J^T J v {en:e} of {sn:e}");
            let g = op.gradient();
            let gd: Vec<f64> = (0..d).map(|i| ne.jtr[i] - rx[i]).collect();
            let sg = gd.iter().map(|t| t.abs()).fold(0.0, f64::max);
            let eg = gd.iter().zip(&g).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
            assert!(eg <= 1e-9 * sg, "{ctrl:?} {layout:?} {mode:?}: J^T r {eg:e} of {sg:e}");
            // diag(A^T A) / m bounds diag(J^T J) from above.
            let da = op.diag_ata();
            for i in 0..d {
                let jj = ne.jtj[i * d + i] - prior[i];
                assert!(jj <= da[i] * (1.0 + 1e-12), "{ctrl:?} {layout:?} {mode:?}: {i}: {jj} > {}", da[i]);
            }
        }
    }

    #[test]
    fn an_infeasible_point_gives_no_operator() {
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
        assert!(p.jacobian_op(&[f64::NAN; 72]).is_none());
        assert!(p.jacobian_op(&[0.0; 3]).is_none());
    }
}
