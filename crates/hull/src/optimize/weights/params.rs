//! The offsets' parameters as unknowns beside the weights ([`ParamFreedom`]): how many, their
//! start and box, the parameters they stand for, and their Jacobian columns.

use super::WeightProblem;

/// Which data parameters are unknowns too (for exact recovery of rational shapes). The
/// parameter unknowns follow the weight variables: `u_0 .. u_{m-1}` (all but `None`), then
/// `v_0 .. v_{G-1}` of the sections (`USectionV`), or interleaved `u_k, v_k` (`UV`).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum ParamFreedom {
    /// The parameters stay.
    #[default]
    None,
    /// Each offset's `u_k` moves; `v` stays (sections at known `v`).
    U,
    /// Each offset's `u_k` moves, and each section's one `v`: the offsets of a section stay on
    /// one iso-curve `v = const`, as skinning puts them. A section is a run of consecutive
    /// offsets sharing the same `v` when the problem was built.
    USectionV,
    /// Each offset's `u_k` and `v_k` move independently. Beware: this frees the surface from
    /// having the sections as iso-curves, and then even a polynomial surface can contain a
    /// circular cone's sections (a quadric has polynomial parameterizations).
    UV,
}

impl WeightProblem {
    /// Number of parameter unknowns for `free`.
    pub fn param_count(&self, free: ParamFreedom) -> usize {
        let m = self.points.len();
        match free {
            ParamFreedom::None => 0,
            ParamFreedom::U => m,
            ParamFreedom::USectionV => m + self.section.last().map_or(0, |g| g + 1),
            ParamFreedom::UV => 2 * m,
        }
    }

    /// The parameter unknowns of `params` for `free` (a section's `v` is its first offset's),
    /// with their boxes (the knot domains).
    pub fn param_vars(&self, params: &[(f64, f64)], free: ParamFreedom) -> (Vec<f64>, Vec<f64>, Vec<f64>) {
        let ((u0, u1), (v0, v1)) = (self.ku.domain(), self.kv.domain());
        let (mut x, mut lo, mut hi) = (Vec::new(), Vec::new(), Vec::new());
        let mut push = |t: f64, a: f64, b: f64| {
            x.push(t);
            lo.push(a);
            hi.push(b);
        };
        match free {
            ParamFreedom::None => {}
            ParamFreedom::U => params.iter().for_each(|&(u, _)| push(u, u0, u1)),
            ParamFreedom::USectionV => {
                params.iter().for_each(|&(u, _)| push(u, u0, u1));
                for (k, &(_, v)) in params.iter().enumerate() {
                    if k == 0 || self.section[k] != self.section[k - 1] {
                        push(v, v0, v1);
                    }
                }
            }
            ParamFreedom::UV => params.iter().for_each(|&(u, v)| {
                push(u, u0, u1);
                push(v, v0, v1);
            }),
        }
        (x, lo, hi)
    }

    /// The data parameters given the unknowns `vars` of [`WeightProblem::param_vars`] (the
    /// others taken from `base`).
    pub fn params_from_vars(&self, base: &[(f64, f64)], vars: &[f64], free: ParamFreedom) -> Vec<(f64, f64)> {
        let m = base.len();
        base.iter()
            .enumerate()
            .map(|(k, &(u, v))| match free {
                ParamFreedom::None => (u, v),
                ParamFreedom::U => (vars[k], v),
                ParamFreedom::USectionV => (vars[k], vars[m + self.section[k]]),
                ParamFreedom::UV => (vars[2 * k], vars[2 * k + 1]),
            })
            .collect()
    }

    /// The Jacobian column of the parameter unknown moving `u` (`dir` 0) or `v` (`dir` 1) of
    /// offset `k`, if it is one.
    pub(super) fn param_col(&self, free: ParamFreedom, d: usize, k: usize, dir: usize) -> Option<usize> {
        let m = self.points.len();
        match (free, dir) {
            (ParamFreedom::None, _) => None,
            (ParamFreedom::U, 0) => Some(d + k),
            (ParamFreedom::U, _) => None,
            (ParamFreedom::USectionV, 0) => Some(d + k),
            (ParamFreedom::USectionV, _) => Some(d + m + self.section[k]),
            (ParamFreedom::UV, _) => Some(d + 2 * k + dir),
        }
    }
}
