//! Compatible curves along `u`: every section fitted on one knot vector with the same number
//! of control points, by interpolation, least-bending-energy interpolation or least squares,
//! blended with the best energy weight; and the placement of that knot vector.

use super::sections::{in_section, Section, UParams};
use crate::basis::{basis_funs, BasisRow};
use crate::fit::constrained::EnergyGram;
use crate::fit::knots::{approximation_knots, centred_approximation_knots};
use crate::fit::lsq::LeastSquaresSolver;
use crate::fit::{FairInterpolationSolver, Parameterization};
use crate::{KnotVector, NurbsError, Vec3, MAX_DEGREE};
use std::collections::HashMap;

/// Share `nu` control points (knuckle points counted once) among pieces whose largest sections
/// have `counts[j]` points: `nu_j` in `[p + 1, max(N_j, p + 1)]`, `sum nu_j = nu + c`, each
/// as near to `N_j (nu + c) / sum N_j` as the bounds allow (see
/// [`skin_approximate_with_knuckles`]).
///
/// # Errors
/// [`NurbsError::BadControlPointCount`] with the feasible range of `nu`.
pub(super) fn share_control_points(nu: usize, counts: &[usize], p: usize) -> Result<Vec<usize>, NurbsError> {
    let c = counts.len() - 1;
    let lo = p + 1;
    let hi: Vec<usize> = counts.iter().map(|&n| n.max(lo)).collect();
    let (min_total, max_total) = (lo * counts.len(), hi.iter().sum::<usize>());
    let total = nu + c;
    if total < min_total || total > max_total {
        return Err(NurbsError::BadControlPointCount {
            what: format!("skinning along the sections with {c} knuckle line(s) ({} pieces)", counts.len()),
            count: nu,
            min: min_total - c,
            max: max_total - c,
        });
    }
    let sum_n: usize = counts.iter().sum();
    let ideal: Vec<f64> = counts.iter().map(|&n| n as f64 * total as f64 / sum_n as f64).collect();
    let mut share: Vec<usize> = ideal.iter().zip(&hi).map(|(&x, &h)| (x.round() as usize).clamp(lo, h)).collect();
    // Move one at a time where the share is furthest from its ideal, first piece on a tie.
    while share.iter().sum::<usize>() != total {
        let grow = share.iter().sum::<usize>() < total;
        let pick = (0..share.len())
            .filter(|&j| if grow { share[j] < hi[j] } else { share[j] > lo })
            .max_by(|&a, &b| {
                let gap = |j: usize| if grow { ideal[j] - share[j] as f64 } else { share[j] as f64 - ideal[j] };
                gap(a).total_cmp(&gap(b)).then(b.cmp(&a))
            })
            .expect("the total lies within the bounds");
        if grow {
            share[pick] += 1;
        } else {
            share[pick] -= 1;
        }
    }
    Ok(share)
}

/// The blend weights `w` of the candidate parameters `(1 - w) t + w m` of a section fitted on
/// the common knots ([`skin_interpolate`] step 2, [`skin_approximate`] step 1).
pub(super) const BLEND_WEIGHTS: [f64; 5] = [0.0, 0.25, 0.5, 0.75, 1.0];

/// The weight of the energy against the squared residual when least-squares candidates are
/// compared: `λ = LSQ_ENERGY_WEIGHT / g` with `g` the largest diagonal entry of the Gram matrix
/// (which scales like `1 / h^3` for knot spacing `h`), so that `λ E` is measured in squared
/// lengths like the residual and a curve whose control points zig-zag by `δ` costs about
/// `1e-3 δ^2` per pole. Small enough to leave a well-posed fit to the data (the candidates'
/// residuals then differ by far more), large enough to reject the near-singular ones, whose
/// energy is larger by orders of magnitude (on R/V Gunnerus: 13 to 16-point sections on 12 to
/// 15 poles overshoot by up to 31 m with their own parameters, 0.16 m at the chosen blend).
pub(super) const LSQ_ENERGY_WEIGHT: f64 = 1e-3;

/// `λ = ν m / (n max_i G_ii)` of [`SkinOptions::smoothing`] for `m` data points on the knots of
/// `gram` (`n` control points).
pub(super) fn smoothing_lambda(gram: &EnergyGram, m: usize, smoothing: f64) -> f64 {
    if smoothing == 0.0 {
        return 0.0;
    }
    smoothing * m as f64 / (gram.len() as f64 * gram.max_diagonal())
}

/// A section fitted on common knots: its score (energy, or penalized residual), control points
/// and parameters.
pub(super) type BlendFit = (f64, Vec<Vec3>, Vec<f64>);

/// `sum_k |C(t_k) - Q_k|^2` of the non-rational curve with control points `cp` on `knots`.
pub(super) fn residual(knots: &KnotVector, t: &[f64], pts: &[Vec3], cp: &[Vec3]) -> f64 {
    let (p, u) = (knots.degree(), knots.as_slice());
    let mut row: BasisRow = [0.0; MAX_DEGREE + 1];
    t.iter()
        .zip(pts)
        .map(|(&x, q)| {
            let s = knots.find_span(x);
            basis_funs(u, s, x, p, &mut row);
            let c = row[..=p].iter().enumerate().fold(Vec3::ZERO, |acc, (j, &b)| acc + cp[s - p + j] * b);
            c.distance(*q).powi(2)
        })
        .sum()
}

/// Fits of sections on one common knot vector: fair interpolation (a section with at most as
/// many points as control points) and least squares (more points), each at the blend of
/// parameters that scores best. One shared Gram matrix, one factorization per distinct
/// parameter vector for interpolation.
pub(super) struct SectionFits<'a> {
    pub(super) knots: &'a KnotVector,
    pub(super) gram: EnergyGram,
    pub(super) solvers: Vec<FairInterpolationSolver>,
    /// The index in `solvers` of each parameter vector (by the bits of its values).
    pub(super) by_params: HashMap<Vec<u64>, usize>,
    /// [`SkinOptions::smoothing`] of the least-squares fits.
    pub(super) smoothing: f64,
}

impl<'a> SectionFits<'a> {
    pub(super) fn new(knots: &'a KnotVector) -> Self {
        SectionFits {
            knots,
            gram: EnergyGram::new(knots),
            solvers: Vec::new(),
            by_params: HashMap::new(),
            smoothing: 0.0,
        }
    }

    /// The fair-interpolation solver for `params`, from the cache or newly factored.
    pub(super) fn solver(&mut self, params: &[f64]) -> Result<&FairInterpolationSolver, NurbsError> {
        let key: Vec<u64> = params.iter().map(|t| t.to_bits()).collect();
        let index = match self.by_params.get(&key) {
            Some(&i) => i,
            None => {
                self.solvers.push(FairInterpolationSolver::with_gram(params, self.knots, &self.gram)?);
                self.by_params.insert(key, self.solvers.len() - 1);
                self.solvers.len() - 1
            }
        };
        Ok(&self.solvers[index])
    }

    /// The least-energy curve through section `k`'s `pts` over the candidate parameters
    /// `(1 - w) own + w m` ([`skin_interpolate`] step 2): its energy `∫ |C''|^2`, control
    /// points and parameters.
    ///
    /// # Errors
    /// The error of the first candidate, in the section's name, if no candidate can be solved
    /// (only possible on knots with interior multiplicity `p`).
    pub(super) fn interpolate(&mut self, pts: &[Vec3], own: Vec<f64>, k: usize) -> Result<BlendFit, NurbsError> {
        let (energy, _, t) = self.best_blend(pts, own, k, |fits, t| Ok((fits.solver(t)?.energy(pts)?, Vec::new())))?;
        let cp = self.solver(&t).and_then(|s| s.control_points(pts)).map_err(|e| in_section(e, k))?;
        Ok((energy, cp, t))
    }

    /// The least-squares curve of section `k`'s `pts` ([`skin_approximate`] step 1) over the
    /// candidate parameters, scored by `sum_k |C(t_k) - Q_k|^2 + λ E(C)`
    /// ([`LSQ_ENERGY_WEIGHT`]): that score, its control points and parameters.
    ///
    /// # Errors
    /// The error of the first candidate, in the section's name, if no candidate can be solved.
    pub(super) fn approximate(&mut self, pts: &[Vec3], own: Vec<f64>, k: usize) -> Result<BlendFit, NurbsError> {
        let smooth = smoothing_lambda(&self.gram, pts.len(), self.smoothing);
        let lambda = self.lambda() + smooth;
        self.best_blend(pts, own, k, |fits, t| {
            let cp = LeastSquaresSolver::smoothing(t, fits.knots, smooth)?.control_points(pts)?;
            Ok((residual(fits.knots, t, pts, &cp) + lambda * fits.gram.energy(&cp), cp))
        })
    }

    /// `λ = LSQ_ENERGY_WEIGHT / max_i G_ii` of these knots.
    pub(super) fn lambda(&self) -> f64 {
        LSQ_ENERGY_WEIGHT / self.gram.max_diagonal()
    }

    /// Solve at every candidate blend of `own` with the Greville spread and keep the lowest
    /// score `solve` returns (with the control points it returned and the parameters).
    pub(super) fn best_blend(
        &mut self,
        pts: &[Vec3],
        own: Vec<f64>,
        k: usize,
        mut solve: impl FnMut(&mut Self, &[f64]) -> Result<(f64, Vec<Vec3>), NurbsError>,
    ) -> Result<BlendFit, NurbsError> {
        let m = greville_spread(self.knots, pts.len());
        let blends = BLEND_WEIGHTS.into_iter().map(|w| {
            let t: Vec<f64> = if w == 0.0 {
                own.clone()
            } else {
                let mut t: Vec<f64> = own.iter().zip(&m).map(|(a, b)| (1.0 - w) * a + w * b).collect();
                // Keep the ends exact (both sequences run from the domain start to its end).
                t[0] = own[0];
                t[own.len() - 1] = own[own.len() - 1];
                t
            };
            solve(self, &t).map(|(score, cp)| (score, (cp, t)))
        });
        let (score, (cp, t)) = least_score(blends, "BLEND_WEIGHTS").map_err(|e| in_section(e, k))?;
        Ok((score, cp, t))
    }
}

/// `n` points spread over the Greville abscissae `ξ_i = (u_{i+1} + ... + u_{i+p}) / p` of
/// `knots` (de Boor, A Practical Guide to Splines, IX) in proportion to their index:
/// `m_j = Ξ(j (N - 1) / (n - 1))` with `Ξ` the piecewise-linear interpolant of `i -> ξ_i`.
/// For `n <= N` consecutive arguments are at least 1 apart, and `Ξ(x)` for `i <= x < i + 1`
/// lies in `[ξ_i, ξ_{i+1}) ⊂ (u_i, u_{i+p+1})`, the support of `N_{i,p}`, so `m_j` can be given `N_{floor(x_j)}`: the collocation rows are
/// independent ([`super::row_schoenberg_whitney`]). (`ξ_i > u_i` because no knot has
/// multiplicity `p + 1` but the clamped ends, where `N_0(u_0) = 1`; `ξ_{i+1} <= u_{i+p+1}`.)
/// `m_0 = u_0`, `m_{n-1} = u_{N+p}`.
pub(super) fn greville_spread(knots: &KnotVector, n: usize) -> Vec<f64> {
    let (p, u, big_n) = (knots.degree(), knots.as_slice(), knots.num_basis());
    let xi = |i: usize| u[i + 1..=i + p].iter().sum::<f64>() / p as f64;
    if n < 2 {
        return vec![xi(0)];
    }
    (0..n)
        .map(|j| {
            if j + 1 == n {
                return xi(big_n - 1);
            }
            let x = (j * (big_n - 1)) as f64 / (n - 1) as f64;
            let i = (x.floor() as usize).min(big_n - 2);
            let a = x - i as f64;
            (1.0 - a) * xi(i) + a * xi(i + 1)
        })
        .collect()
}

/// The knot placements tried by [`skin_approximate`] in each direction.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(super) enum Placement {
    /// [`approximation_knots`].
    Resampled,
    /// [`centred_approximation_knots`].
    Centred,
}

impl Placement {
    pub(super) const ALL: [Placement; 2] = [Placement::Resampled, Placement::Centred];

    pub(super) fn knots(self, params: &[f64], n_ctrl: usize, degree: usize) -> Result<KnotVector, NurbsError> {
        match self {
            Placement::Resampled => approximation_knots(params, n_ctrl, degree),
            Placement::Centred => centred_approximation_knots(params, n_ctrl, degree),
        }
    }
}

/// The placements to try for parameters of `kind`: uniform knots only for universal
/// parameters (their defining pairing), both placements otherwise.
pub(super) fn placements(kind: Parameterization) -> &'static [Option<Placement>] {
    const BOTH: [Option<Placement>; 2] = [Some(Placement::ALL[0]), Some(Placement::ALL[1])];
    const UNIFORM: [Option<Placement>; 1] = [None];
    if kind == Parameterization::Universal {
        &UNIFORM
    } else {
        &BOTH
    }
}

/// Step 1 of [`skin_approximate`]: the common `u` knots, one row of `nu` control points per
/// section, and the parameters used.
pub(super) struct AlongFit {
    pub(super) knots: KnotVector,
    pub(super) rows: Vec<Vec<Vec3>>,
    pub(super) u_of: UParams,
}

/// Fit every section on common knots for each placement and keep the best (step 1). `shared`:
/// every regular section has the parameters `u_of` gives it, all equal (plain least squares,
/// one factorization); otherwise each has its own (blends, [`SectionFits`]).
pub(super) fn fit_along(
    secs: &[Section],
    u_of: UParams,
    nu: usize,
    p: usize,
    kind: Parameterization,
    shared: bool,
    smoothing: f64,
) -> Result<(f64, AlongFit), NurbsError> {
    let fits = placements(kind).iter().map(|&placement| {
        common_approximation_knots(&u_of, nu, p, placement).and_then(|knots| {
            if shared {
                along_shared(secs, &u_of, knots, smoothing)
            } else {
                along_own(secs, u_of.clone(), nu, knots, smoothing)
            }
        })
    });
    least_score(fits, "placements()")
}

/// The candidate of least score (the first on a tie), or the first error when none succeeds;
/// every candidate is tried. `what` names the candidates, which are never none.
pub(super) fn least_score<S: PartialOrd, T>(
    candidates: impl IntoIterator<Item = Result<(S, T), NurbsError>>,
    what: &str,
) -> Result<(S, T), NurbsError> {
    let mut best: Option<(S, T)> = None;
    let mut first_error = None;
    for candidate in candidates {
        match candidate {
            Ok((score, fit)) => {
                if best.as_ref().is_none_or(|(b, _)| score < *b) {
                    best = Some((score, fit));
                }
            }
            Err(e) => {
                first_error.get_or_insert(e);
            }
        }
    }
    match (best, first_error) {
        (Some(fit), _) => Ok(fit),
        (None, Some(e)) => Err(e),
        (None, None) => unreachable!("{what} is never empty"),
    }
}

/// Step 1 with each section on its own parameters (blends); the score is the sum of the
/// sections' penalized residuals (`λ E` for those interpolated).
pub(super) fn along_own(
    secs: &[Section],
    mut u_of: UParams,
    nu: usize,
    knots: KnotVector,
    smoothing: f64,
) -> Result<(f64, AlongFit), NurbsError> {
    let mut fits = SectionFits::new(&knots);
    fits.smoothing = smoothing;
    let lambda = fits.lambda();
    let mut rows: Vec<Vec<Vec3>> = Vec::with_capacity(secs.len());
    let mut score = 0.0;
    for (k, (s, t)) in secs.iter().zip(u_of.iter_mut()).enumerate() {
        rows.push(match (s, t) {
            (Section::Regular(pts), Some(t)) => {
                let own = std::mem::take(t);
                let (sk, cp, used) = if pts.len() > nu {
                    fits.approximate(pts, own, k)?
                } else {
                    let (energy, cp, used) = fits.interpolate(pts, own, k)?;
                    (lambda * energy, cp, used)
                };
                score += sk;
                *t = used;
                cp
            }
            (Section::Point(c, _), _) => vec![*c; nu],
            (Section::Regular(_), None) => unreachable!("own_params gives every regular section parameters"),
        });
    }
    drop(fits);
    Ok((score, AlongFit { knots, rows, u_of }))
}

/// Step 1 with all regular sections at the same parameters: one least-squares factorization.
pub(super) fn along_shared(
    secs: &[Section],
    u_of: &UParams,
    knots: KnotVector,
    smoothing: f64,
) -> Result<(f64, AlongFit), NurbsError> {
    let t = u_of.iter().flatten().next().expect("classify keeps one regular section");
    let gram = EnergyGram::new(&knots);
    let smooth = smoothing_lambda(&gram, t.len(), smoothing);
    let solver = LeastSquaresSolver::smoothing(t, &knots, smooth)?;
    let lambda = LSQ_ENERGY_WEIGHT / gram.max_diagonal() + smooth;
    let nu = knots.num_basis();
    let mut score = 0.0;
    let rows = secs
        .iter()
        .enumerate()
        .map(|(k, s)| match s {
            Section::Regular(pts) => {
                let cp = solver.control_points(pts).map_err(|e| in_section(e, k))?;
                score += residual(&knots, t, pts, &cp) + lambda * gram.energy(&cp);
                Ok(cp)
            }
            Section::Point(c, _) => Ok(vec![*c; nu]),
        })
        .collect::<Result<Vec<_>, NurbsError>>()?;
    Ok((score, AlongFit { knots, rows, u_of: u_of.clone() }))
}

/// The mean of the `placement` knot vectors of the sections with at least `nu` points (or
/// uniform knots for `None`, the universal parameterization).
pub(super) fn common_approximation_knots(
    u_of: &[Option<Vec<f64>>],
    nu: usize,
    p: usize,
    placement: Option<Placement>,
) -> Result<KnotVector, NurbsError> {
    let Some(placement) = placement else {
        return KnotVector::uniform(p, nu);
    };
    let mut sum = vec![0.0; nu + p + 1];
    let mut count = 0usize;
    for (k, t) in u_of.iter().enumerate() {
        if let Some(t) = t.as_ref().filter(|t| t.len() >= nu) {
            let kv = placement.knots(t, nu, p).map_err(|e| in_section(e, k))?;
            sum.iter_mut().zip(kv.as_slice()).for_each(|(s, x)| *s += x);
            count += 1;
        }
    }
    if count == 0 {
        return Err(NurbsError::BadControlPointCount {
            what: "skinning along the sections (no section has that many points)".into(),
            count: nu,
            min: p + 1,
            max: u_of.iter().flatten().map(Vec::len).max().unwrap_or(0),
        });
    }
    // Every section's knots run from 0 to 1, so the clamped ends stay exact.
    let mut knots: Vec<f64> = sum.iter().map(|s| s / count as f64).collect();
    knots[..=p].fill(0.0);
    knots[nu..].fill(1.0);
    KnotVector::try_new(p, knots)
}
