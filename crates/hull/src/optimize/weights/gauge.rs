//! The scale gauge of the fairness term.
//!
//! The rest of this module's documentation is on [`WeightProblem`] (its scale gauge), where the library's users read it.

use super::{WeightLayout, WeightProblem};
use crate::optimize::Objective;

impl WeightProblem {
    /// Whether the data and fairness parts are evaluated at `Π θ` (with a fairness term).
    pub(crate) fn gauge_fixed(&self) -> bool {
        self.fair_f > 0.0
    }

    /// The gauge groups: ranges of variables whose common shift scales every weight.
    pub(crate) fn gauge_groups(&self) -> [std::ops::Range<usize>; 2] {
        match self.options.layout {
            WeightLayout::Full => [0..self.dim(), 0..0],
            WeightLayout::RankOne => [0..self.pat.n_u, self.pat.n_u..self.dim()],
        }
    }

    /// `v <- Π v` over the weight variables (the first `dim` entries), when the gauge is fixed.
    pub(crate) fn project_gauge(&self, v: &mut [f64]) {
        if !self.gauge_fixed() {
            return;
        }
        for g in self.gauge_groups() {
            if g.is_empty() {
                continue;
            }
            let mean = v[g.clone()].iter().sum::<f64>() / g.len() as f64;
            v[g].iter_mut().for_each(|t| *t -= mean);
        }
    }

    /// `J <- J Π` for a column-major Jacobian of `rows` rows whose first `dim` columns are the
    /// weight variables (the parameter columns after them are left alone): each column less
    /// its group's mean column.
    pub(crate) fn project_gauge_columns(&self, jac: &mut [f64], rows: usize) {
        if !self.gauge_fixed() {
            return;
        }
        let mut mean = vec![0.0; rows];
        for g in self.gauge_groups() {
            if g.is_empty() {
                continue;
            }
            mean.iter_mut().for_each(|t| *t = 0.0);
            for v in g.clone() {
                for (m, c) in mean.iter_mut().zip(&jac[v * rows..(v + 1) * rows]) {
                    *m += c;
                }
            }
            let inv = 1.0 / g.len() as f64;
            for v in g {
                for (c, m) in jac[v * rows..(v + 1) * rows].iter_mut().zip(&mean) {
                    *c -= m * inv;
                }
            }
        }
    }

    /// `M <- Π M Π` for a symmetric row-major `dim x dim` matrix.
    pub(crate) fn project_gauge_symmetric(&self, m: &mut [f64]) {
        if !self.gauge_fixed() {
            return;
        }
        let d = self.dim();
        // Rows of M Π, then (M Π)^T = Π M, whose rows projected give Π M Π; its lower
        // triangle mirrored, so it is symmetric to the bit.
        for pass in 0..2 {
            for row in m.chunks_exact_mut(d) {
                self.project_gauge(row);
            }
            for i in 0..d {
                for j in 0..i {
                    if pass == 0 {
                        m.swap(i * d + j, j * d + i);
                    } else {
                        m[j * d + i] = m[i * d + j];
                    }
                }
            }
        }
    }

    /// The homogeneous control net, u-major, of the solved `y` (band order) at the weights
    /// `w_solved` of the solve, written with the weights `e^θ` of `x`: the same net when the
    /// gauge is free; rescaled point by point (`Y e^θ / w`, the same surface) when the solve ran
    /// at `Π θ`.
    pub(crate) fn homogeneous_net(&self, x: &[f64], y: &[[f64; 3]], w_solved: &[f64]) -> Vec<[f64; 4]> {
        let pat = &self.pat;
        let mut cw = vec![[0.0; 4]; pat.n()];
        if !self.gauge_fixed() {
            for (pos, &c) in pat.grid.iter().enumerate() {
                cw[c] = [y[pos][0], y[pos][1], y[pos][2], w_solved[pos]];
            }
            return cw;
        }
        let (mut w, mut ab) = (Vec::new(), Vec::new());
        self.fill_weights(x, &mut w, &mut ab);
        for (pos, &c) in pat.grid.iter().enumerate() {
            let r = w[pos] / w_solved[pos];
            cw[c] = [y[pos][0] * r, y[pos][1] * r, y[pos][2] * r, w[pos]];
        }
        cw
    }
}

#[cfg(test)]
mod tests {
    use super::super::tests::{noise, problem};
    use super::super::{WeightLayout, WeightMode};
    use crate::optimize::Objective;

    /// The variables with every weight times `e^c`: `θ + c` (full grid) or `α + c` (rank one).
    fn scaled(x: &[f64], layout: WeightLayout, n_u: usize, c: f64) -> Vec<f64> {
        x.iter().enumerate().map(|(i, &t)| if layout == WeightLayout::Full || i < n_u { t + c } else { t }).collect()
    }

    #[test]
    fn a_common_factor_on_the_weights_changes_neither_the_surface_nor_the_fair_objective() {
        let mut seed = 5;
        for layout in [WeightLayout::Full, WeightLayout::RankOne] {
            let p = problem((6, 12), WeightMode::Resolved, layout, 1e-3).with_fairness(0.05, 0.005).expect("usable");
            let n_u = p.ctrl().0;
            let x: Vec<f64> = (0..p.dim()).map(|_| 0.6 * noise(&mut seed)).collect();
            // The data and fairness parts, f^2 less the prior (which alone sees the scale).
            let parts = |x: &[f64]| p.value(x).powi(2) - p.prior_value(x);
            let s0 = p.surface(&x).expect("regular");
            for c in [-1.5, 0.7] {
                let xs = scaled(&x, layout, n_u, c);
                // Without the gauge the energy part would scale by e^{2c} (0.05 and 4.1 here);
                // with it the parts agree to the round-off of the solve (cond(G) <~ 1e4).
                let (a, b) = (parts(&x), parts(&xs));
                assert!((a - b).abs() <= 1e-10 * a, "{layout:?} c {c}: {a:e} vs {b:e}");
                let s1 = p.surface(&xs).expect("regular");
                let w = p.weights(&xs);
                for i in 0..s1.n_u() {
                    for j in 0..s1.n_v() {
                        // Written with the weights e^θ of the variables, so within the box.
                        let (got, want) = (s1.weight(i, j), w[i * s1.n_v() + j]);
                        assert!((got - want).abs() <= 1e-14 * want, "{layout:?} weight ({i}, {j})");
                    }
                }
                // The same surface: points on a grid agree to round-off of the model size.
                for a in 0..=10 {
                    for b in 0..=10 {
                        let (u, v) = (a as f64 / 10.0, b as f64 / 10.0);
                        let d = (s0.point(u, v) - s1.point(u, v)).norm();
                        assert!(d <= 1e-10 * p.size(), "{layout:?} c {c} at ({u}, {v}): {d:e}");
                    }
                }
            }
        }
    }

    #[test]
    fn without_a_fairness_term_nothing_is_projected() {
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 1e-3);
        assert!(!p.gauge_fixed());
        let mut v = vec![0.5, -0.25, 2.0];
        p.project_gauge(&mut v);
        assert_eq!(v, [0.5, -0.25, 2.0]);
        let f = p.with_fairness(0.05, 0.0).expect("usable");
        assert!(f.gauge_fixed());
        let mut v = vec![1.0; f.dim()];
        v[0] = 4.0;
        f.project_gauge(&mut v);
        // The mean (1 + 3 / d) removed: a zero sum, the differences kept.
        assert!(v.iter().sum::<f64>().abs() < 1e-12);
        assert!((v[0] - v[1] - 3.0).abs() < 1e-15);
    }
}
