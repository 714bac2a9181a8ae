//! Control points held in a box: the least squares of [`WeightProblem`] (with its fairness term)
//! under `lo <= P_c <= hi`, coordinate by coordinate.
//!
//! The rest of this module's documentation is on [`WeightProblem::surface_within`], where the library's users read it.

pub use nurbs::fit::ControlBox;
use nurbs::{NurbsError, NurbsSurface};

use crate::optimize::Objective;

use super::{band_cholesky, band_solve, HullError, Scratch, WeightMode, WeightProblem, WeightsKind};

/// The lower-triangle band entry `(i, j)`, `j <= i`, of the layout in `linalg`.
#[inline]
fn at(i: usize, j: usize, stride: usize, bw: usize) -> usize {
    i * stride + j + bw - i
}

impl WeightProblem {
    /// The rational surface of variables `x` whose control points minimise the least squares
    /// (with the fairness term) within `bounds`, and how many control-point coordinates ended on
    /// a bound. Without an active bound it is [`WeightProblem::surface`].
    ///
    /// By the convex hull property of a NURBS surface with positive weights (The NURBS Book, P4.4
    /// for surfaces), every point of the surface is a convex combination of its control points, so
    /// control points within the box keep the whole surface within it: a bound on the control net is
    /// a guarantee between the offsets, where a check of the offsets alone sees nothing. Used with the
    /// offsets' envelope (widened by less than the validity allowance), it keeps a fit from crossing
    /// the centre plane, bulging past the largest half-breadth or the keel, or running past the end
    /// sections.
    ///
    /// Each coordinate is a strictly convex quadratic programme `min 1/2 y^T G y - b^T y`,
    /// `l <= y <= h` (homogeneous `y = w P`, so `l = w lo`), with `G` the banded normal matrix. It is
    /// solved by a primal active set (Nocedal and Wright, *Numerical Optimization*, 2nd ed., 16.5):
    /// the bounded variables are eliminated from the banded system (their rows and columns replaced
    /// by the diagonal), every free variable past a bound is put on it, and once none is, the bound
    /// whose multiplier `(G y - b)_c` has the wrong sign the most is released, one at a time, until
    /// the KKT conditions hold. Each step is one band factorization, `n bw^2 / 2`.
    ///
    /// # Errors
    /// [`HullError::Weights`] in `Fixed` mode (the control points do not move), for a wrong `x`
    /// or an empty box (`lo > hi`); [`HullError::Fit`] if a system is singular.
    pub fn surface_within(&self, x: &[f64], bounds: &ControlBox) -> Result<(NurbsSurface, usize), HullError> {
        if self.options.mode != WeightMode::Resolved {
            return Err(HullError::Weights(WeightsKind::BoxNeedsResolved));
        }
        if (0..3).any(|t| !(bounds.lo[t] <= bounds.hi[t])) {
            return Err(HullError::Weights(WeightsKind::EmptyBox { lo: bounds.lo, hi: bounds.hi }));
        }
        if x.len() != self.dim() || !x.iter().all(|t| t.is_finite()) {
            return Err(HullError::Weights(WeightsKind::Variables { got: x.len(), expected: self.dim() }));
        }
        let singular = || HullError::Fit {
            method: "weights",
            reason: NurbsError::SingularSystem { what: "least-squares control points within the box".into() },
        };
        let mut sc = Scratch::default();
        if !self.assemble(&self.table, x, &mut sc) {
            return Err(singular());
        }
        let pat = &self.pat;
        let n = pat.n();
        let g = sc.band.clone();
        let mut y = vec![[0.0f64; 3]; n];
        let mut active_total = 0;
        let tol = 1e-12 * self.size.max(f64::MIN_POSITIVE);
        for t in 0..3 {
            let b: Vec<f64> = sc.y.iter().map(|r| r[t]).collect();
            let lo: Vec<f64> = sc.w.iter().map(|w| bounds.lo[t] * w).collect();
            let hi: Vec<f64> = sc.w.iter().map(|w| bounds.hi[t] * w).collect();
            let (yt, active) = self.box_qp(&g, &b, &lo, &hi, tol).ok_or_else(singular)?;
            active_total += active;
            for (c, v) in yt.into_iter().enumerate() {
                y[c][t] = v;
            }
        }
        let cw = self.homogeneous_net(x, &y, &sc.w);
        let surface = NurbsSurface::try_from_homogeneous(self.ku.clone(), self.kv.clone(), cw)
            .map_err(|source| HullError::Fit { method: "weights", reason: source })?;
        Ok((surface, active_total))
    }

    /// One coordinate's box-constrained quadratic programme (see [`WeightProblem::surface_within`]); `None` if a system is
    /// singular. Returns the solution and the number of active bounds.
    fn box_qp(&self, g: &[f64], b: &[f64], lo: &[f64], hi: &[f64], tol: f64) -> Option<(Vec<f64>, usize)> {
        let pat = &self.pat;
        let (n, bw, stride) = (pat.n(), pat.bw, pat.stride);
        // `fixed[c]`: the bound value variable c is held at.
        let mut fixed: Vec<Option<f64>> = vec![None; n];
        let full = |i: usize, j: usize| {
            let (r, c) = if i >= j { (i, j) } else { (j, i) };
            if r - c <= bw {
                g[at(r, c, stride, bw)]
            } else {
                0.0
            }
        };
        let mut band = vec![0.0; g.len()];
        // Every step adds or releases a bound; the cap only guards against cycling by
        // round-off (a strictly convex QP has a unique solution the active set reaches).
        for _ in 0..4 * n + 8 {
            band.copy_from_slice(g);
            let mut rhs: Vec<[f64; 1]> = b.iter().map(|&v| [v]).collect();
            for c in 0..n {
                let Some(val) = fixed[c] else { continue };
                for r in c.saturating_sub(bw)..(c + bw + 1).min(n) {
                    if fixed[r].is_none() {
                        rhs[r][0] -= full(r, c) * val;
                    }
                }
            }
            for c in 0..n {
                let Some(val) = fixed[c] else { continue };
                let diag = g[at(c, c, stride, bw)];
                for j in c.saturating_sub(bw)..c {
                    band[at(c, j, stride, bw)] = 0.0;
                }
                for r in c + 1..(c + bw + 1).min(n) {
                    band[at(r, c, stride, bw)] = 0.0;
                }
                band[at(c, c, stride, bw)] = diag;
                rhs[c][0] = diag * val;
            }
            if !band_cholesky(&mut band, n, bw, stride) {
                return None;
            }
            band_solve(&band, n, bw, stride, &mut rhs);
            let y: Vec<f64> = rhs.iter().map(|r| r[0]).collect();
            if !y.iter().all(|v| v.is_finite()) {
                return None;
            }
            let mut added = false;
            for c in 0..n {
                if fixed[c].is_none() {
                    if y[c] < lo[c] - tol {
                        fixed[c] = Some(lo[c]);
                        added = true;
                    } else if y[c] > hi[c] + tol {
                        fixed[c] = Some(hi[c]);
                        added = true;
                    }
                }
            }
            if added {
                continue;
            }
            // Multipliers of the active bounds: mu = (G y - b)_c, >= 0 at a lower bound, <= 0 at
            // an upper one. Release the worst wrong sign.
            let mut worst: Option<(usize, f64)> = None;
            for c in 0..n {
                let Some(val) = fixed[c] else { continue };
                let mu: f64 =
                    (c.saturating_sub(bw)..(c + bw + 1).min(n)).map(|j| full(c, j) * y[j]).sum::<f64>() - b[c];
                let wrong = if val == lo[c] && val != hi[c] {
                    -mu
                } else if val == hi[c] && val != lo[c] {
                    mu
                } else {
                    0.0
                };
                let scale = g[at(c, c, stride, bw)] * tol;
                if wrong > scale && worst.is_none_or(|(_, w)| wrong > w) {
                    worst = Some((c, wrong));
                }
            }
            match worst {
                Some((c, _)) => fixed[c] = None,
                None => return Some((y, fixed.iter().filter(|f| f.is_some()).count())),
            }
        }
        None
    }
}

#[cfg(test)]
mod tests {
    use crate::optimize::{Objective, WeightOptions, WeightProblem};
    use crate::{fit_offsets, series60_sample, FitConfig};

    use super::ControlBox;

    fn sample_problem() -> (WeightProblem, crate::Offsets) {
        let offsets = series60_sample();
        let fit = fit_offsets(&offsets, &FitConfig::default()).expect("sample fits");
        (WeightProblem::from_fit(&fit, &offsets, WeightOptions::default()).expect("shapes match"), offsets)
    }

    #[test]
    fn an_inactive_box_changes_nothing_and_an_active_one_holds_the_whole_net() {
        let (p, _) = sample_problem();
        let x = p.start();
        let free = p.surface(&x).expect("regular");
        let wide = ControlBox { lo: [-1e3; 3], hi: [1e3; 3] };
        let (same, active) = p.surface_within(&x, &wide).expect("regular");
        assert_eq!(active, 0);
        for i in 0..free.n_u() {
            for j in 0..free.n_v() {
                // The same banded system solved again: identical to round-off of 10^2 m values.
                assert!((free.control_point(i, j) - same.control_point(i, j)).norm() < 1e-9);
            }
        }
        // The free least squares puts some control points below y = 0 (the transom's keel);
        // held in y >= 0 none is, and so, by the convex hull property, no point of the surface.
        let min_y = |s: &nurbs::NurbsSurface| {
            (0..s.n_u())
                .flat_map(|i| (0..s.n_v()).map(move |j| (i, j)))
                .map(|(i, j)| s.control_point(i, j).y)
                .fold(f64::MAX, f64::min)
        };
        assert!(min_y(&free) < -1e-3, "{}", min_y(&free));
        let half = ControlBox { lo: [-1e3, 0.0, -1e3], hi: [1e3; 3] };
        let (held, active) = p.surface_within(&x, &half).expect("regular");
        assert!(active > 0);
        assert!(min_y(&held) >= -1e-9, "{}", min_y(&held));
        for k in 0..=40 {
            for l in 0..=40 {
                let (u0, u1) = held.domain_u();
                let (v0, v1) = held.domain_v();
                let pt = held.point(u0 + (u1 - u0) * k as f64 / 40.0, v0 + (v1 - v0) * l as f64 / 40.0);
                assert!(pt.y >= -1e-9, "{pt:?}");
            }
        }
    }

    #[test]
    fn the_box_solution_satisfies_the_kkt_conditions() {
        // Against brute force: no feasible move of one control-point coordinate lowers the
        // objective of the held fit (the QP is convex, so coordinate-wise optimality on the
        // free variables and the multipliers' signs on the bound ones are the KKT conditions).
        let (p, offsets) = sample_problem();
        let x = p.start();
        let bx = ControlBox { lo: [-1e3, 0.05, 0.2], hi: [1e3, 7.9, 1e3] };
        let (held, _) = p.surface_within(&x, &bx).expect("regular");
        let points: Vec<nurbs::Vec3> = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
        let params = p.params().to_vec();
        let sse = |s: &nurbs::NurbsSurface| -> f64 {
            points.iter().zip(&params).map(|(q, &(u, v))| (s.point(u, v) - *q).norm().powi(2)).sum()
        };
        let base = sse(&held);
        let h = 1e-4;
        for i in 0..held.n_u() {
            for j in 0..held.n_v() {
                let c = held.control_point(i, j);
                for t in 1..3 {
                    for sign in [-1.0, 1.0] {
                        let mut a = c.to_array();
                        a[t] += sign * h;
                        if a[t] < bx.lo[t] || a[t] > bx.hi[t] {
                            continue;
                        }
                        let mut pts = held.control_points();
                        pts[i * held.n_v() + j] = nurbs::Vec3::new(a[0], a[1], a[2]);
                        let moved =
                            nurbs::NurbsSurface::try_new(held.knots_u().clone(), held.knots_v().clone(), &pts, None)
                                .expect("valid");
                        // A step of 1e-4 m changes the sum by O(h^2) at the optimum; a first-order
                        // gain would show as a drop of order h times the gradient.
                        assert!(sse(&moved) >= base - 1e-9, "({i},{j}) coord {t} {sign}: {} < {base}", sse(&moved));
                    }
                }
            }
        }
    }
}
