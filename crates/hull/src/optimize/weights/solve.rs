//! One evaluation of a [`WeightProblem`]: the weights of the variables, the control points
//! (kept, or re-solved from the banded normal equations `G Y = H^T Q`, assembled a skinned
//! section at a time), the points `S_k`, the residuals and the value.

use std::cell::RefCell;

use nurbs::{NurbsError, NurbsSurface};

use super::{band_cholesky, band_solve, BasisTable, HullError, WeightLayout, WeightMode, WeightProblem, WeightsKind};
use crate::optimize::Objective;

/// Per-thread scratch of one evaluation.
#[derive(Default)]
pub(super) struct Scratch {
    /// The variables the weights are filled from: `Π θ` when the gauge is fixed (`gauge`).
    pub(super) xg: Vec<f64>,
    /// Weights in band order.
    pub(super) w: Vec<f64>,
    /// Rank-one factors `a`, `b`.
    pub(super) ab: Vec<f64>,
    /// `1 / W_k` per offset.
    pub(super) s: Vec<f64>,
    /// `h_kl` of one offset.
    pub(super) h: Vec<f64>,
    /// The normal matrix `G`, then its Cholesky factor.
    pub(super) band: Vec<f64>,
    /// Homogeneous control points `Y = w P`, band order.
    pub(super) y: Vec<[f64; 3]>,
    /// A run's `U = sum_k s_k^2 N(u_k) N(u_k)^T`, rows of `2p + 1` around the diagonal.
    pub(super) gu: Vec<f64>,
    /// A run's `sum_k s_k N(u_k) Q_k`.
    pub(super) tu: Vec<[f64; 3]>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

impl WeightProblem {
    /// The weights `w_ij` of variables `x`, u-major (`i n_v + j`). Not clamped to the box.
    pub fn weights(&self, x: &[f64]) -> Vec<f64> {
        let mut w = Vec::new();
        let mut ab = Vec::new();
        self.fill_weights(x, &mut w, &mut ab);
        let mut out = vec![0.0; w.len()];
        for (pos, &c) in self.pat.grid.iter().enumerate() {
            out[c] = w[pos];
        }
        out
    }

    /// The rational surface of variables `x`: the plain approximation's control points with
    /// these weights ([`WeightMode::Fixed`]) or the least-squares control points for them
    /// ([`WeightMode::Resolved`]).
    ///
    /// # Errors
    /// [`HullError::Weights`] if `x` has the wrong length or a non-finite entry;
    /// [`HullError::Fit`] with [`NurbsError::SingularSystem`] if the least-squares system is
    /// singular or too ill-conditioned, or another kernel error if the result is not finite.
    pub fn surface(&self, x: &[f64]) -> Result<NurbsSurface, HullError> {
        if x.len() != self.dim() || !x.iter().all(|t| t.is_finite()) {
            return Err(HullError::Weights(WeightsKind::Variables { got: x.len(), expected: self.dim() }));
        }
        let mut sc = Scratch::default();
        if !self.solve(&self.table, x, &mut sc) {
            return Err(HullError::Fit {
                method: "weights",
                reason: NurbsError::SingularSystem { what: "least-squares control points for these weights".into() },
            });
        }
        let cw = self.homogeneous_net(x, &sc.y, &sc.w);
        NurbsSurface::try_from_homogeneous(self.ku.clone(), self.kv.clone(), cw)
            .map_err(|source| HullError::Fit { method: "weights", reason: source })
    }

    /// The residual vector `r` (see [`Linearization::residuals`](super::Linearization::residuals)), `None` where the value is
    /// infinite.
    pub fn residuals(&self, x: &[f64]) -> Option<Vec<f64>> {
        let mut sc = Scratch::default();
        if !self.solve(&self.table, x, &mut sc) {
            return None;
        }
        Some(self.residual_vector(&self.table, x, &sc))
    }

    /// Weights in band order from the variables (and the rank-one factors in `ab`).
    pub(super) fn fill_weights(&self, x: &[f64], w: &mut Vec<f64>, ab: &mut Vec<f64>) {
        let pat = &self.pat;
        w.clear();
        w.resize(pat.n(), 0.0);
        match self.options.layout {
            WeightLayout::Full => {
                for (wp, &c) in w.iter_mut().zip(&pat.grid) {
                    *wp = x[c].exp();
                }
            }
            WeightLayout::RankOne => {
                ab.clear();
                ab.extend(x.iter().map(|t| t.exp()));
                for (wp, &c) in w.iter_mut().zip(&pat.grid) {
                    let (i, j) = (c / pat.n_v, c % pat.n_v);
                    *wp = ab[i] * ab[pat.n_u + j];
                }
            }
        }
    }

    /// Weights, `1 / W_k`, and homogeneous control points `Y` for variables `x` at the
    /// parameters of `table` (in `Resolved` mode also the Cholesky factor of `G` in
    /// `sc.band`). `false` if `x` is not finite or of the wrong length, a `W_k` is not positive,
    /// or `G` is singular.
    pub(super) fn solve(&self, table: &BasisTable, x: &[f64], sc: &mut Scratch) -> bool {
        if !self.assemble(table, x, sc) {
            return false;
        }
        if self.options.mode == WeightMode::Fixed {
            return true;
        }
        let pat = &self.pat;
        if !band_cholesky(&mut sc.band, pat.n(), pat.bw, pat.stride) {
            return false;
        }
        band_solve(&sc.band, pat.n(), pat.bw, pat.stride, &mut sc.y);
        sc.y.iter().all(|y| y.iter().all(|c| c.is_finite()))
    }

    /// The first half of [`WeightProblem::solve`]: weights, `1 / W_k` and, in `Resolved` mode,
    /// the normal matrix `G` (in `sc.band`, not yet factored) and right-hand side `H^T Q` (in
    /// `sc.y`); in `Fixed` mode `sc.y` is already `w P`.
    pub(super) fn assemble(&self, table: &BasisTable, x: &[f64], sc: &mut Scratch) -> bool {
        if x.len() != self.dim() || !x.iter().all(|t| t.is_finite()) {
            return false;
        }
        let pat = &self.pat;
        let (n, nb, bw) = (pat.n(), pat.nb, pat.bw);
        if self.gauge_fixed() {
            sc.xg.clear();
            sc.xg.extend_from_slice(x);
            self.project_gauge(&mut sc.xg);
            self.fill_weights(&sc.xg, &mut sc.w, &mut sc.ab);
        } else {
            self.fill_weights(x, &mut sc.w, &mut sc.ab);
        }
        let m = table.first.len();
        sc.s.clear();
        sc.s.resize(m, 0.0);
        sc.y.clear();
        sc.y.resize(n, [0.0; 3]);
        // `1 / W_k` of every offset, in both modes.
        for (k, &first) in table.first.iter().enumerate() {
            let b = &table.vals[k * nb..(k + 1) * nb];
            let wk = &sc.w[first..];
            let big_w: f64 = b.iter().zip(&pat.off).map(|(bl, &o)| bl * wk[o]).sum();
            if !(big_w > 0.0 && big_w.is_finite()) {
                return false;
            }
            sc.s[k] = 1.0 / big_w;
        }
        match self.options.mode {
            WeightMode::Fixed => {
                for ((y, &w), p) in sc.y.iter_mut().zip(&sc.w).zip(&self.fixed) {
                    *y = [w * p[0], w * p[1], w * p[2]];
                }
                true
            }
            WeightMode::Resolved => {
                let stride = pat.stride;
                sc.band.clear();
                sc.band.resize(n * stride, 0.0);
                sc.h.clear();
                sc.h.resize(nb, 0.0);
                for &(k0, k1) in &table.runs {
                    if k1 - k0 > 1 {
                        self.add_run(table, k0, k1, sc);
                        continue;
                    }
                    let (k, first) = (k0, table.first[k0]);
                    let b = &table.vals[k * nb..(k + 1) * nb];
                    let s = sc.s[k];
                    for (h, bl) in sc.h.iter_mut().zip(b) {
                        *h = bl * s;
                    }
                    // G += h h^T (lower triangle), H^T Q += h Q_k.
                    let band = &mut sc.band[first * stride..];
                    match pat.inner {
                        2 => add_blocks::<2>(band, &sc.h, &pat.blocks),
                        3 => add_blocks::<3>(band, &sc.h, &pat.blocks),
                        4 => add_blocks::<4>(band, &sc.h, &pat.blocks),
                        _ => add_blocks_any(band, &sc.h, &pat.blocks, pat.inner),
                    }
                    let qk = self.points[k];
                    let y = &mut sc.y[first..];
                    for (&o, &hl) in pat.off.iter().zip(&sc.h) {
                        let yo = &mut y[o];
                        yo[0] += hl * qk[0];
                        yo[1] += hl * qk[1];
                        yo[2] += hl * qk[2];
                    }
                }
                if self.fair_g > 0.0 {
                    for &(idx, v) in &self.net_band {
                        sc.band[idx] += self.fair_g * v;
                    }
                }
                let anchor = self.options.anchor;
                if anchor > 0.0 {
                    let max_diag = (0..n).map(|c| sc.band[c * stride + bw]).fold(0.0, f64::max);
                    let lambda = anchor * max_diag;
                    for ((c, y), (&w, p)) in sc.y.iter_mut().enumerate().zip(sc.w.iter().zip(&self.fixed)) {
                        sc.band[c * stride + bw] += lambda;
                        y[0] += lambda * w * p[0];
                        y[1] += lambda * w * p[1];
                        y[2] += lambda * w * p[2];
                    }
                }
                true
            }
        }
    }

    /// `G += sum_k h_k h_k^T` and `H^T Q += sum_k h_k Q_k` for a run `[k0, k1)` of offsets
    /// sharing one `v`: with `h_k = s_k N(u_k) (x) N(v)`,
    /// `sum_k h_k h_k^T = U (x) N(v) N(v)^T` and `sum_k h_k Q_k = (sum_k s_k N(u_k) Q_k) (x) N(v)`,
    /// `U = sum_k s_k^2 N(u_k) N(u_k)^T` banded of half-bandwidth `p`. Costs `(p+1)^2` per offset
    /// and `~ (p+1) (q+1)^2` per u index of the run, against `((p+1)(q+1))^2 / 2` per offset.
    pub(super) fn add_run(&self, table: &BasisTable, k0: usize, k1: usize, sc: &mut Scratch) {
        let pat = &self.pat;
        let (p, q, n_u, n_v, bw, stride) = (pat.p, pat.q, pat.n_u, pat.n_v, pat.bw, pat.stride);
        let wu = 2 * p + 1;
        let imin = table.i0[k0..k1].iter().copied().min().unwrap_or(0);
        let imax = table.i0[k0..k1].iter().copied().max().unwrap_or(0) + p;
        let nr = imax - imin + 1;
        sc.gu.clear();
        sc.gu.resize(nr * wu, 0.0);
        sc.tu.clear();
        sc.tu.resize(nr, [0.0; 3]);
        for k in k0..k1 {
            let s = sc.s[k];
            let nu = &table.nu[k * (p + 1)..(k + 1) * (p + 1)];
            let r0 = table.i0[k] - imin;
            let qk = self.points[k];
            for a in 0..=p {
                let ha = s * nu[a];
                let row = &mut sc.gu[(r0 + a) * wu..(r0 + a + 1) * wu];
                // U[i][i'] at row i, slot i' - i + p.
                for (a2, &n2) in nu.iter().enumerate() {
                    row[a2 + p - a] += ha * s * n2;
                }
                let t = &mut sc.tu[r0 + a];
                t[0] += ha * qk[0];
                t[1] += ha * qk[1];
                t[2] += ha * qk[2];
            }
        }
        let nv = &table.nv[k0 * (q + 1)..(k0 + 1) * (q + 1)];
        let first = table.first[k0];
        let j0 = if pat.u_major { first % n_v } else { first / n_u };
        if pat.u_major {
            // Row (i, j0 + b), columns (i', j0 .. j0 + q), i - p <= i' <= i: one block of q + 1.
            for i in imin..=imax {
                let ri = i - imin;
                let t = sc.tu[ri];
                for (y, &nb) in sc.y[i * n_v + j0..=i * n_v + j0 + q].iter_mut().zip(nv) {
                    y[0] += nb * t[0];
                    y[1] += nb * t[1];
                    y[2] += nb * t[2];
                }
                for i2 in i.saturating_sub(p).max(imin)..=i {
                    let coef = sc.gu[ri * wu + i2 + p - i];
                    if coef == 0.0 {
                        continue;
                    }
                    let base = i2 * n_v + j0 + bw;
                    // Constant block lengths for the common degrees (see `add_kron_rows`).
                    match q + 1 {
                        2 => add_kron_rows(&mut sc.band, nv, coef, i * n_v + j0, base, stride, 2),
                        3 => add_kron_rows(&mut sc.band, nv, coef, i * n_v + j0, base, stride, 3),
                        4 => add_kron_rows(&mut sc.band, nv, coef, i * n_v + j0, base, stride, 4),
                        len => add_kron_rows(&mut sc.band, nv, coef, i * n_v + j0, base, stride, len),
                    }
                }
            }
        } else {
            // Row (j0 + b, i), columns (j0 + b', i - p .. i + p): U's row i times N_b N_b'.
            for b in 0..=q {
                for i in imin..=imax {
                    let t = sc.tu[i - imin];
                    let y = &mut sc.y[(j0 + b) * n_u + i];
                    y[0] += nv[b] * t[0];
                    y[1] += nv[b] * t[1];
                    y[2] += nv[b] * t[2];
                }
                for b2 in 0..=b {
                    let cb = nv[b] * nv[b2];
                    if cb == 0.0 {
                        continue;
                    }
                    for i in imin..=imax {
                        let (lo, hi) = (i.saturating_sub(p).max(imin), (i + p).min(imax));
                        let r = (j0 + b) * n_u + i;
                        let idx = r * stride + (j0 + b2) * n_u + lo + bw - r;
                        let urow = &sc.gu[(i - imin) * wu + lo + p - i..(i - imin) * wu + hi + p - i + 1];
                        for (g, &u) in sc.band[idx..idx + hi - lo + 1].iter_mut().zip(urow) {
                            *g += cb * u;
                        }
                    }
                }
            }
        }
    }

    /// `S_k` for offset `k` after [`WeightProblem::solve`].
    #[inline]
    pub(super) fn point_of(&self, table: &BasisTable, sc: &Scratch, k: usize) -> [f64; 3] {
        let nb = self.pat.nb;
        let b = &table.vals[k * nb..(k + 1) * nb];
        let y = &sc.y[table.first[k]..];
        let mut acc = [0.0; 3];
        for (bl, &o) in b.iter().zip(&self.pat.off) {
            let yo = y[o];
            acc[0] += bl * yo[0];
            acc[1] += bl * yo[1];
            acc[2] += bl * yo[2];
        }
        let s = sc.s[k];
        [acc[0] * s, acc[1] * s, acc[2] * s]
    }

    /// `f^2` after [`WeightProblem::solve`].
    pub(super) fn value_squared(&self, table: &BasisTable, x: &[f64], sc: &Scratch) -> f64 {
        let m = table.first.len();
        let mut sum = 0.0;
        for (k, qk) in self.points.iter().enumerate().take(m) {
            let s = self.point_of(table, sc, k);
            let e = [s[0] - qk[0], s[1] - qk[1], s[2] - qk[2]];
            sum += e[0] * e[0] + e[1] * e[1] + e[2] * e[2];
        }
        let mut f2 = sum / m as f64 + self.prior_value(x);
        if self.fair_f > 0.0 {
            f2 += self.fair_f * self.net_value(sc);
        }
        f2
    }

    /// The value at variables `x` and the parameters of `table`: `+inf` if infeasible.
    pub(crate) fn value_with(&self, table: &BasisTable, x: &[f64]) -> f64 {
        let eval = |sc: &mut Scratch| {
            if self.solve(table, x, sc) {
                let f = self.value_squared(table, x, sc).sqrt();
                if f.is_finite() {
                    return f;
                }
            }
            f64::INFINITY
        };
        SCRATCH.with(|cell| match cell.try_borrow_mut() {
            Ok(mut sc) => eval(&mut sc),
            // Only reachable by re-entrance; a fresh scratch keeps it correct.
            Err(_) => eval(&mut Scratch::default()),
        })
    }

    /// The residual vector after [`WeightProblem::solve`].
    pub(super) fn residual_vector(&self, table: &BasisTable, x: &[f64], sc: &Scratch) -> Vec<f64> {
        let m = table.first.len();
        let d = x.len();
        let mut r = Vec::with_capacity(3 * m + d);
        let scale = 1.0 / (m as f64).sqrt();
        for (k, qk) in self.points.iter().enumerate() {
            let s = self.point_of(table, sc, k);
            r.extend((0..3).map(|c| (s[c] - qk[c]) * scale));
        }
        let reg = self.rho / (d as f64).sqrt();
        r.extend(x.iter().map(|t| reg * t));
        self.push_penalty_rows(&mut r, x, sc);
        r
    }
}

/// `G += h h^T` over the blocks of one offset, blocks `L` long (monomorphised for the common
/// degrees so the block is a fixed-length, vectorisable loop).
#[inline]
fn add_blocks<const L: usize>(band: &mut [f64], h: &[f64], blocks: &[(usize, usize, usize)]) {
    for &(l, idx, l2) in blocks {
        let hl = h[l];
        let dst = &mut band[idx..idx + L];
        let src = &h[l2..l2 + L];
        for i in 0..L {
            dst[i] += hl * src[i];
        }
    }
}

/// For rows `r = r0 + b`, `b < len`: `band[r stride + base - r + b'] += coef nv[b] nv[b']`,
/// `b' < len`. Always inlined, so a call with a constant `len` gets fixed-length loops.
#[inline(always)]
fn add_kron_rows(band: &mut [f64], nv: &[f64], coef: f64, r0: usize, base: usize, stride: usize, len: usize) {
    let nv = &nv[..len];
    for (b, &nb) in nv.iter().enumerate() {
        let r = r0 + b;
        let idx = r * stride + base - r;
        let cb = coef * nb;
        for (g, &n2) in band[idx..idx + len].iter_mut().zip(nv) {
            *g += cb * n2;
        }
    }
}

/// [`add_blocks`] for any block length.
fn add_blocks_any(band: &mut [f64], h: &[f64], blocks: &[(usize, usize, usize)], len: usize) {
    for &(l, idx, l2) in blocks {
        let hl = h[l];
        for (g, &h2) in band[idx..idx + len].iter_mut().zip(&h[l2..l2 + len]) {
            *g += hl * h2;
        }
    }
}
