//! Residuals and the dense Jacobian of a [`WeightProblem`] for least-squares solvers
//! ([`Linearization`]): Kaufman's projected Jacobian or Golub and Pereyra's exact one, with the
//! columns of the parameter unknowns.

use super::{band_solve, BasisTable, ParamFreedom, Scratch, WeightLayout, WeightMode, WeightProblem};

/// Which Jacobian of the variable-projection residual to form.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum JacobianKind {
    /// Kaufman's approximation (1975): `J = (I - H G^{-1} H^T) dS/dθ|_P`, the derivative at
    /// fixed control points projected off the range of the least-squares matrix. Its gradient
    /// `J^T r` is exact; `J` itself is exact at zero residual.
    #[default]
    Kaufman,
    /// The exact Jacobian (Golub and Pereyra 1973): Kaufman's plus
    /// `- H G^{-1} D^{-1} (dR/dθ_c)^T e`. About twice the cost. For the data parameters (see
    /// [`ParamFreedom`]) the Kaufman form is always used.
    Exact,
}

/// Residuals and Jacobian at one point, for least-squares solvers.
#[derive(Clone, Debug, PartialEq)]
pub struct Linearization {
    /// `3 m` data rows `(S_k - Q_k) / sqrt(m)` (x, y, z of each offset in turn), then `d`
    /// regularisation rows `ρ θ_i / sqrt(d)`: `|r| = f(θ)`.
    pub residuals: Vec<f64>,
    /// Column-major `rows x cols`: the `d` weight variables, then the free parameters
    /// (`u_0, [v_0,] u_1, ...`).
    pub jacobian: Vec<f64>,
    pub rows: usize,
    pub cols: usize,
}

impl Linearization {
    /// Column `j` of the Jacobian.
    pub fn column(&self, j: usize) -> &[f64] {
        &self.jacobian[j * self.rows..(j + 1) * self.rows]
    }

    /// `|r|`, the objective value.
    pub fn value(&self) -> f64 {
        self.residuals.iter().map(|r| r * r).sum::<f64>().sqrt()
    }
}

impl WeightProblem {
    /// Residuals and the analytic Jacobian with respect to the weight variables (`kind`: see
    /// [`JacobianKind`]); `None` where the value is infinite.
    ///
    /// Derivative of the rational point w.r.t. a log-weight at fixed control points:
    /// `dS_k/dθ_c = R_kc (P_c - S_k)`; rank-one by the chain rule
    /// `dS_k/dα_i = sum_j dS_k/dθ_ij`, `dS_k/dβ_j = sum_i dS_k/dθ_ij`. In `Resolved` mode
    /// projected off the range of `H` (Kaufman) and, for [`JacobianKind::Exact`], corrected by
    /// Golub and Pereyra's second term.
    pub fn residuals_and_jacobian(&self, x: &[f64], kind: JacobianKind) -> Option<Linearization> {
        self.linearize(&self.table, x, ParamFreedom::None, kind)
    }

    /// As [`WeightProblem::residuals_and_jacobian`], at data parameters `params`, some of them
    /// extra unknowns (`free` says which, ordered as [`WeightProblem::param_vars`]): columns
    /// `d..` hold `dS_k/du_k` (and `dS_k/dv`) at fixed control points,
    /// `sum_c (dB_kc/du) w_c (P_c - S_k) / W_k` (a section's `v` column sums its offsets'),
    /// projected (Kaufman) in `Resolved` mode. `None` where the value is infinite or `params`
    /// has the wrong length.
    pub fn residuals_and_jacobian_with_params(
        &self,
        x: &[f64],
        params: &[(f64, f64)],
        free: ParamFreedom,
    ) -> Option<Linearization> {
        if params.len() != self.points.len() {
            return None;
        }
        let table = self.basis_table(params, free != ParamFreedom::None);
        self.linearize(&table, x, free, JacobianKind::Kaufman)
    }

    /// The variables a band position's log-weight feeds: `[c]` (full grid) or `[i, n_u + j]`
    /// (rank one); the count is returned with them.
    #[inline]
    pub(super) fn vars_of(&self, pos: usize) -> ([usize; 2], usize) {
        let c = self.pat.grid[pos];
        match self.options.layout {
            WeightLayout::Full => ([c, 0], 1),
            WeightLayout::RankOne => ([c / self.pat.n_v, self.pat.n_u + c % self.pat.n_v], 2),
        }
    }

    /// Offset `k`'s row of `A` (the derivative of `S_k` at fixed control points): one
    /// `(variable, dS_k/dvariable)` entry per variable its control points feed, in order of
    /// first appearance (the rank-one layout sums `2 (p+1) (q+1)` derivatives into
    /// `(p+1) + (q+1)` entries), with `first` its first control point's band position, `sp`
    /// the point `S_k`, `h` its `h_kl`, `w` the weights in band order and `pts` the
    /// [`WeightProblem::derivative_points`]. `row` is cleared first.
    pub(super) fn a_row(
        &self,
        first: usize,
        sp: [f64; 3],
        h: &[f64],
        w: &[f64],
        pts: &[[f64; 3]],
        row: &mut Vec<(usize, [f64; 3])>,
    ) {
        row.clear();
        for (&o, &hl) in self.pat.off.iter().zip(h) {
            let pos = first + o;
            let r_kc = hl * w[pos];
            let pc = pts[pos];
            let al = [r_kc * (pc[0] - sp[0]), r_kc * (pc[1] - sp[1]), r_kc * (pc[2] - sp[2])];
            let (vars, nv) = self.vars_of(pos);
            for &v in &vars[..nv] {
                match row.iter_mut().find(|(u, _)| *u == v) {
                    Some((_, t)) => {
                        t[0] += al[0];
                        t[1] += al[1];
                        t[2] += al[2];
                    }
                    None => row.push((v, al)),
                }
            }
        }
    }

    /// The points `T_c` of the derivative at fixed control points, `dS_k/dθ_c = R_kc (T_c - S_k)`:
    /// the Euclidean control points `P_c` (the derivative at fixed `P`), or, with a fairness
    /// term, zero (the derivative at fixed homogeneous `Y = w P`, `-R_kc S_k`). Both give the
    /// same projected (Kaufman) Jacobian when the least squares has no penalty, as they differ
    /// by `H δ`, in the range the projection removes; with the penalty `λ |D Y|^2` only the
    /// second is the derivative of the augmented residual `[H Y - Q; sqrt(λ) D Y]`, whose
    /// `D` does not depend on the weights.
    pub(super) fn derivative_points(&self, sc: &Scratch) -> Vec<[f64; 3]> {
        if self.fair_f > 0.0 && self.options.mode == WeightMode::Resolved {
            vec![[0.0; 3]; sc.y.len()]
        } else {
            sc.y.iter().zip(&sc.w).map(|(y, &w)| [y[0] / w, y[1] / w, y[2] / w]).collect()
        }
    }

    /// Residuals and Jacobian at `x` and the parameters of `table` (which must carry
    /// derivatives if `free` is not `None`).
    pub(crate) fn linearize(
        &self,
        table: &BasisTable,
        x: &[f64],
        free: ParamFreedom,
        kind: JacobianKind,
    ) -> Option<Linearization> {
        let mut sc = Scratch::default();
        if !self.solve(table, x, &mut sc) {
            return None;
        }
        let pat = &self.pat;
        let (n, nb, bw) = (pat.n(), pat.nb, pat.bw);
        let m = table.first.len();
        let d = x.len();
        if m != self.points.len() || (free != ParamFreedom::None && table.du.len() != m * nb) {
            return None;
        }
        let cols = d + self.param_count(free);
        let rows = 3 * m + d + self.penalty_rows();
        let residuals = self.residual_vector(table, x, &sc);
        let resolved = self.options.mode == WeightMode::Resolved;
        let exact = resolved && kind == JacobianKind::Exact;
        let mut jac = vec![0.0; rows * cols];
        // Z[v] = H^T A_v (+ Golub-Pereyra term): the right-hand sides of the projections.
        let mut z = if resolved { vec![[0.0f64; 3]; d * n] } else { Vec::new() };
        // The points the derivatives pull towards, and the unscaled residuals.
        let pts = self.derivative_points(&sc);
        let sk: Vec<[f64; 3]> = (0..m).map(|k| self.point_of(table, &sc, k)).collect();
        let ek: Vec<[f64; 3]> =
            sk.iter().zip(&self.points).map(|(s, q)| [s[0] - q[0], s[1] - q[1], s[2] - q[2]]).collect();
        let mut h = vec![0.0; nb];
        for k in 0..m {
            let first = table.first[k];
            let s = sc.s[k];
            let b = &table.vals[k * nb..(k + 1) * nb];
            for (hl, bl) in h.iter_mut().zip(b) {
                *hl = bl * s;
            }
            let (sp, e) = (sk[k], ek[k]);
            for l in 0..nb {
                let pos = first + pat.off[l];
                let r_kc = h[l] * sc.w[pos];
                let pc = pts[pos];
                let a = [r_kc * (pc[0] - sp[0]), r_kc * (pc[1] - sp[1]), r_kc * (pc[2] - sp[2])];
                let (vars, nv) = self.vars_of(pos);
                for &v in &vars[..nv] {
                    let col = &mut jac[v * rows + 3 * k..v * rows + 3 * k + 3];
                    col[0] += a[0];
                    col[1] += a[1];
                    col[2] += a[2];
                    if resolved {
                        let zv = &mut z[v * n..(v + 1) * n];
                        for (&o, &h2) in pat.off.iter().zip(&h) {
                            let t = &mut zv[first + o];
                            // Kaufman: H^T A_v; exact: minus sum_k R_kc h_kc' e_k.
                            let (g0, g1, g2) = if exact {
                                (a[0] - r_kc * e[0], a[1] - r_kc * e[1], a[2] - r_kc * e[2])
                            } else {
                                (a[0], a[1], a[2])
                            };
                            t[0] += h2 * g0;
                            t[1] += h2 * g1;
                            t[2] += h2 * g2;
                        }
                    }
                }
            }
        }
        if exact && self.fair_f == 0.0 {
            // The delta term (H^T e)_c at entry c of its variables' right-hand sides (zero at
            // an exact least-squares solution; kept for round-off).
            let mut hte = vec![[0.0f64; 3]; n];
            for (k, e) in ek.iter().enumerate() {
                let first = table.first[k];
                let s = sc.s[k];
                for (bl, &o) in table.vals[k * nb..(k + 1) * nb].iter().zip(&pat.off) {
                    let t = &mut hte[first + o];
                    for c in 0..3 {
                        t[c] += bl * s * e[c];
                    }
                }
            }
            for (pos, he) in hte.iter().enumerate() {
                let (vars, nv) = self.vars_of(pos);
                for &v in &vars[..nv] {
                    let t = &mut z[v * n + pos];
                    for c in 0..3 {
                        t[c] += he[c];
                    }
                }
            }
        }
        // Parameter columns at fixed control points: a = s sum_l dB_l (Y_l - w_l S_k).
        let mut param_cols: Vec<(usize, usize, [f64; 3])> = Vec::with_capacity(2 * m);
        if free != ParamFreedom::None {
            for k in 0..m {
                let first = table.first[k];
                let s = sc.s[k];
                let sp = sk[k];
                for dir in 0..2 {
                    let Some(v) = self.param_col(free, d, k, dir) else { continue };
                    let db = if dir == 0 { &table.du } else { &table.dv };
                    let mut a = [0.0; 3];
                    for (dbl, &o) in db[k * nb..(k + 1) * nb].iter().zip(&pat.off) {
                        let (y, w) = (sc.y[first + o], sc.w[first + o]);
                        for c in 0..3 {
                            a[c] += dbl * (y[c] - w * sp[c]);
                        }
                    }
                    let a = [a[0] * s, a[1] * s, a[2] * s];
                    // A section's v column sums its offsets' (chain rule).
                    for (t, ac) in jac[v * rows + 3 * k..v * rows + 3 * k + 3].iter_mut().zip(a) {
                        *t += ac;
                    }
                    param_cols.push((v, k, a));
                }
            }
        }
        if resolved {
            // J_v -= H G^{-1} Z_v.
            let mut y = vec![[0.0f64; 3]; n];
            // The fairness rows of column v: -sqrt(λ / r) D G^{-1} Z_v (their Jacobian is the
            // projection's share of the penalty rows; they do not depend on θ directly).
            let pen0 = 3 * m + d;
            let fair_c = self.fair_f.sqrt();
            let project = |jcol: &mut [f64], y: &mut [[f64; 3]]| {
                band_solve(&sc.band, n, bw, pat.stride, y);
                if self.fair_f > 0.0 {
                    for (r, st) in self.net.rows().iter().enumerate() {
                        let mut acc = [0.0; 3];
                        for &(c, w) in st.entries() {
                            let yc = y[pat.pos(c / pat.n_v, c % pat.n_v)];
                            for t in 0..3 {
                                acc[t] += w * yc[t];
                            }
                        }
                        for t in 0..3 {
                            jcol[pen0 + 3 * r + t] = -fair_c * acc[t];
                        }
                    }
                }
                for k in 0..m {
                    let first = table.first[k];
                    let s = sc.s[k];
                    let mut acc = [0.0; 3];
                    for (bl, &o) in table.vals[k * nb..(k + 1) * nb].iter().zip(&pat.off) {
                        let yo = y[first + o];
                        acc[0] += bl * yo[0];
                        acc[1] += bl * yo[1];
                        acc[2] += bl * yo[2];
                    }
                    for c in 0..3 {
                        jcol[3 * k + c] -= s * acc[c];
                    }
                }
            };
            for v in 0..d {
                y.copy_from_slice(&z[v * n..(v + 1) * n]);
                project(&mut jac[v * rows..(v + 1) * rows], &mut y);
            }
            for &(v, k, a) in &param_cols {
                y.iter_mut().for_each(|t| *t = [0.0; 3]);
                let first = table.first[k];
                let s = sc.s[k];
                for (bl, &o) in table.vals[k * nb..(k + 1) * nb].iter().zip(&pat.off) {
                    let hl = bl * s;
                    y[first + o] = [hl * a[0], hl * a[1], hl * a[2]];
                }
                project(&mut jac[v * rows..(v + 1) * rows], &mut y);
            }
        }
        // The data and fairness rows were differentiated at `Π x` (see `gauge`); the prior's
        // rows, set below, at `x`.
        self.project_gauge_columns(&mut jac, rows);
        let scale = 1.0 / (m as f64).sqrt();
        let reg = self.rho / (d as f64).sqrt();
        for v in 0..cols {
            let col = &mut jac[v * rows..(v + 1) * rows];
            col[..3 * m].iter_mut().for_each(|t| *t *= scale);
            if v < d {
                col[3 * m + v] = reg;
            }
        }
        if self.smooth > 0.0 {
            let (c, r0) = (self.smooth.sqrt(), 3 * m + d + if self.fair_f > 0.0 { 3 * self.net.len() } else { 0 });
            for (e, &(a, b)) in self.smooth_pairs.iter().enumerate() {
                jac[a * rows + r0 + e] = c;
                jac[b * rows + r0 + e] = -c;
            }
        }
        if !(jac.iter().all(|t| t.is_finite()) && residuals.iter().all(|t| t.is_finite())) {
            return None;
        }
        Some(Linearization { residuals, jacobian: jac, rows, cols })
    }
}
