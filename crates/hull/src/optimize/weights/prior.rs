//! The terms of the objective besides the offsets: the log-weights' prior (the regularisation
//! `ρ` and the smoothing of neighbouring log-weights) and the fairness of the homogeneous
//! control net (`λ |D Y|^2`, [`NetEnergy`]).

use super::{NetEnergy, Scratch, WeightLayout, WeightMode, WeightProblem};
use crate::optimize::Objective;

impl WeightProblem {
    /// Build the fairness operator and the log-weight pairs from the options.
    pub(super) fn set_penalties(&mut self) {
        let pat = &self.pat;
        let (n_u, n_v) = (pat.n_u, pat.n_v);
        let resolved = self.options.mode == WeightMode::Resolved;
        (self.net, self.net_band, self.fair_g, self.fair_f) = (NetEnergy::default(), Vec::new(), 0.0, 0.0);
        if resolved && self.options.fair > 0.0 {
            let net = NetEnergy::new(n_u, n_v, &self.ku, &self.kv);
            if !net.is_empty() {
                let (bw, stride) = (pat.bw, pat.stride);
                // Every entry of D^T D lies within the band: the stencils span two rows of the
                // net along the direction of degree >= 2 (one along a degree-1 direction) and
                // one diagonal step, all within `p n_v + q` (u-major) or `q n_u + p` (v-major).
                self.net_band = net
                    .gram_lower(|c| pat.pos(c / n_v, c % n_v))
                    .into_iter()
                    .map(|(r, c, v)| {
                        debug_assert!(r - c <= bw, "D^T D entry ({r}, {c}) outside the band {bw}");
                        (r * stride + c + bw - r, v)
                    })
                    .collect();
                let rows = net.len() as f64;
                self.fair_f = self.options.fair / rows;
                self.fair_g = self.fair_f * self.points.len() as f64;
                self.net = net;
            }
        }
        let sigma = self.options.weight_smoothing * self.size;
        self.smooth_pairs.clear();
        self.smooth = 0.0;
        if sigma > 0.0 {
            let pairs = &mut self.smooth_pairs;
            match self.options.layout {
                WeightLayout::Full => {
                    for i in 0..n_u {
                        for j in 0..n_v {
                            let c = i * n_v + j;
                            if i + 1 < n_u {
                                pairs.push((c, c + n_v));
                            }
                            if j + 1 < n_v {
                                pairs.push((c, c + 1));
                            }
                        }
                    }
                }
                WeightLayout::RankOne => {
                    pairs.extend((1..n_u).map(|i| (i - 1, i)));
                    pairs.extend((1..n_v).map(|j| (n_u + j - 1, n_u + j)));
                }
            }
            if !pairs.is_empty() {
                self.smooth = sigma * sigma / pairs.len() as f64;
            }
        }
    }

    /// `out += R v`, `R = (ρ^2 / d) I + (σ^2 / e) L` the Hessian of the log-weights' prior
    /// (regularisation and smoothing; `L` the graph Laplacian of the neighbouring pairs), so
    /// that the prior's part of `f^2` is `θ^T R θ`.
    pub(crate) fn prior_apply(&self, v: &[f64], out: &mut [f64]) {
        let reg = self.rho * self.rho / v.len() as f64;
        for (o, t) in out.iter_mut().zip(v) {
            *o += reg * t;
        }
        if self.smooth > 0.0 {
            for &(a, b) in &self.smooth_pairs {
                let g = self.smooth * (v[a] - v[b]);
                out[a] += g;
                out[b] -= g;
            }
        }
    }

    /// The diagonal of `R` (see [`WeightProblem::prior_apply`]).
    pub(crate) fn prior_diag(&self) -> Vec<f64> {
        let d = self.dim();
        let mut diag = vec![self.rho * self.rho / d as f64; d];
        for &(a, b) in &self.smooth_pairs {
            diag[a] += self.smooth;
            diag[b] += self.smooth;
        }
        diag
    }

    /// `θ^T R θ`, the prior's part of `f^2`.
    pub(super) fn prior_value(&self, x: &[f64]) -> f64 {
        let mut f2 = 0.0;
        if self.rho > 0.0 {
            f2 += self.rho * self.rho * x.iter().map(|t| t * t).sum::<f64>() / x.len() as f64;
        }
        if self.smooth > 0.0 {
            f2 += self.smooth * self.smooth_pairs.iter().map(|&(a, b)| (x[a] - x[b]).powi(2)).sum::<f64>();
        }
        f2
    }

    /// `|D Y|^2` of the homogeneous control points after [`WeightProblem::solve`].
    pub(super) fn net_value(&self, sc: &Scratch) -> f64 {
        let (pat, n_v) = (&self.pat, self.pat.n_v);
        self.net.value(|c| sc.y[pat.pos(c / n_v, c % n_v)])
    }

    /// The fairness rows `sqrt(λ / r) D Y` (x, y, z of each stencil) and the smoothing rows
    /// `σ / sqrt(e) (θ_a - θ_b)`, after the regularisation rows: `|r|^2 = f^2`.
    pub(super) fn push_penalty_rows(&self, r: &mut Vec<f64>, x: &[f64], sc: &Scratch) {
        if self.fair_f > 0.0 {
            let (c, n_v) = (self.fair_f.sqrt(), self.pat.n_v);
            for st in self.net.rows() {
                let mut acc = [0.0; 3];
                for &(k, w) in st.entries() {
                    let y = sc.y[self.pat.pos(k / n_v, k % n_v)];
                    for t in 0..3 {
                        acc[t] += w * y[t];
                    }
                }
                r.extend(acc.iter().map(|a| c * a));
            }
        }
        if self.smooth > 0.0 {
            let c = self.smooth.sqrt();
            r.extend(self.smooth_pairs.iter().map(|&(a, b)| c * (x[a] - x[b])));
        }
    }

    /// Number of penalty rows of [`WeightProblem::push_penalty_rows`].
    pub(super) fn penalty_rows(&self) -> usize {
        (if self.fair_f > 0.0 { 3 * self.net.len() } else { 0 })
            + if self.smooth > 0.0 { self.smooth_pairs.len() } else { 0 }
    }
}
