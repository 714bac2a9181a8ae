//! The NURBS weight-optimisation objective: the RMS parametric residual of the offsets as a
//! function of the (log-)weights, with the control points either kept or re-solved.
//!
//! The rest of this module's documentation is on [`WeightProblem`], where the library's users read it.
//!
//! The files of this module, one part each: `basis` (the band layout and the basis products,
//! independent of the weights), `solve` (one evaluation: weights, control points, residuals,
//! value), `prior` (regularisation, log-weight smoothing, the net's fairness), `gauge` (the
//! fairness term's scale gauge), `params` (the data parameters as unknowns), `linearize` (dense
//! Jacobians), `normal` (the normal equations without `J`), `matvec` (the Jacobian as an
//! operator), `within` (control points held in a box), and `tests`.

use nurbs::{KnotVector, NurbsSurface, Vec3};

use super::linalg::{band_cholesky, band_solve, dot};
use super::net_energy::NetEnergy;

use super::FittedSurface;
use super::Objective;
use crate::{HullError, Offsets, WeightsKind};

mod basis;
mod gauge;
mod linearize;
mod matvec;
mod normal;
mod params;
mod prior;
mod solve;
#[cfg(test)]
mod tests;
mod within;

pub(crate) use basis::BasisTable;
use basis::Pattern;
pub use linearize::{JacobianKind, Linearization};
pub(crate) use matvec::{Evaluation, JacobianOp};
pub use normal::NormalEquations;
pub use params::ParamFreedom;
use solve::Scratch;

/// What happens to the control points when the weights move.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WeightMode {
    /// The plain approximation's control points stay (the simple formulation).
    Fixed,
    /// The control points are re-solved by linear least squares for every weight vector
    /// (variable projection).
    #[default]
    Resolved,
}

impl WeightMode {
    /// The name in reports: `"resolved"` or `"fixed"`.
    pub fn name(self) -> &'static str {
        match self {
            WeightMode::Resolved => "resolved",
            WeightMode::Fixed => "fixed",
        }
    }
}

impl std::str::FromStr for WeightMode {
    type Err = String;

    /// `resolved` or `fixed` (any case, spaces around ignored), as `--control-points` and the
    /// Python `control_points` take it.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "resolved" => Ok(WeightMode::Resolved),
            "fixed" => Ok(WeightMode::Fixed),
            _ => Err(format!("unknown control-point mode `{s}` (expected resolved or fixed)")),
        }
    }
}

/// How the weights are parameterised.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum WeightLayout {
    /// One log-weight per control point: `n_u n_v` variables, `w_ij = exp(θ_{i n_v + j})`.
    #[default]
    Full,
    /// Rank one: `w_ij = a_i b_j = exp(α_i + β_j)`, `n_u + n_v` variables `(α, β)`. Fewer
    /// variables, less over-fitting between the offsets.
    RankOne,
}

impl WeightLayout {
    /// The name in reports: `"full"` or `"rank_one"`.
    pub fn name(self) -> &'static str {
        match self {
            WeightLayout::Full => "full",
            WeightLayout::RankOne => "rank_one",
        }
    }
}

impl std::str::FromStr for WeightLayout {
    type Err = String;

    /// `full`, or `rank1` (also `rank-one`, `rank_one`: [`WeightLayout::name`]'s), any case,
    /// as `--weights` and the Python `weights` take it.
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "full" => Ok(WeightLayout::Full),
            "rank1" | "rank-one" | "rank_one" => Ok(WeightLayout::RankOne),
            _ => Err(format!("unknown weight layout `{s}` (expected full or rank1)")),
        }
    }
}

/// Settings of a [`WeightProblem`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WeightOptions {
    pub mode: WeightMode,
    pub layout: WeightLayout,
    /// Weight range `(lo, hi)`, `0 < lo <= 1 <= hi`. The log-weights are boxed to
    /// `[ln lo, ln hi]`; in the rank-one layout each factor to `[ln lo / 2, ln hi / 2]`, so
    /// every product `a_i b_j` stays in range too.
    pub bounds: (f64, f64),
    /// `ρ / model size` (see [`WeightProblem`]): a log-weight of 1 on every variable costs as much
    /// as an RMS error of `regularization x size`. The default `1e-6` is far below any fit
    /// error of interest (0.1 mm on a 100 m hull) yet pins the scale gauge.
    pub regularization: f64,
    /// Re-solved mode: a ridge `λ = anchor x max diag(G)` pulling each homogeneous control
    /// point toward the plain approximation's, `min |H Y - Q|^2 + λ |Y - w P_0|^2`. Control
    /// points that the offsets do not determine (a support with too few offsets, as where
    /// sections of unequal counts thin out) stay where the two-stage skinning put them instead
    /// of making the system singular; where the offsets determine them, the shift is of
    /// relative size `λ / σ_min(G)`. `0` turns it off. Default `1e-9` (well above the Cholesky
    /// pivot threshold `1e-12`, far below any fit error of interest).
    pub anchor: f64,
    /// The box the evolutionary algorithms (GA, PSO, GSA) search, as a multiple `κ` of each
    /// log-weight's sensitivity step: `θ_i` in `[-h_i, h_i]` (within the bounds) with
    /// `h_i = κ f(0) / (sqrt(d) |J_i|)`, `J_i` the column of Kaufman's Jacobian at the start.
    /// Moving one log-weight by `h_i` alone changes the linearised residual by `κ f(0) /
    /// sqrt(d)`; moving all `d` at random within the box by about `κ f(0) / sqrt(3)`. The
    /// weights' useful range differs by orders of magnitude between hulls (on the Wigley table
    /// the start is so sharp a minimum along most directions that every agent of a swarm spread
    /// over a tenth of `[ln 0.1, ln 10]` was worse than it, and GSA never moved); this is the
    /// "normalise the variables" of the brief, made per problem. `None`: the whole bounds.
    /// Default `Some(10)`: `κ` = 4, 10 and 30 all made GA, PSO and GSA beat the plain fit on
    /// the Series 60 sample, Wigley, two BSpline3D-MATLAB hulls and the cargo ship, where the
    /// whole bounds left GSA (and GA, in true RMS) at the start on three of them. LM and the
    /// LM phase of `gsa+lm` search the whole bounds.
    pub search_scale: Option<f64>,
    /// Fairness `λ` of the control net (`NetEnergy`, re-solved mode only): the control points
    /// minimise `(1/m) sum_k |S_k - Q_k|^2 + λ (1/r) |D Y|^2` (`r` rows of the second-difference
    /// operator `D`, `Y = w P` the homogeneous control points), and the objective carries the
    /// same term, measured in a fixed scale gauge (the weights' geometric mean brought to 1,
    /// see `gauge`) so that scaling all weights together does not lower it. Dimensionless: a
    /// mean squared second difference of the net costs `λ` times as much as a mean squared
    /// residual. `0` (the default) is the plain least squares.
    ///
    /// `D` is the discrete surrogate of the thin-plate energy `∫∫ |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2`
    /// (P-splines: Eilers and Marx, *Flexible smoothing with B-splines and penalties*, Statistical
    /// Science 11 (1996)).
    ///
    /// For a net `P_ij`, `0 <= i < n_u`, `0 <= j < n_v`:
    ///
    /// `E(P) = sum |P_{i-1,j} - 2 P_ij + P_{i+1,j}|^2 + sum |P_{i,j-1} - 2 P_ij + P_{i,j+1}|^2
    ///        + 2 sum |P_ij - P_{i+1,j} - P_{i,j+1} + P_{i+1,j+1}|^2`,
    ///
    /// a quadratic form `|D P|^2` whose rows are the stencils of the three sums. A planar net of evenly spaced
    /// points (a bilinear patch) has `E = 0`; so has any net linear in `(i, j)`.
    ///
    /// Creases stay sharp: where a knot vector has an interior knot of multiplicity `>= degree`
    /// (a knuckle or chine kept by the fit: the surface passes through the control row `s - 1`,
    /// `s` the knot's first index, and is only C0 there), the second differences centred on that
    /// row are left out, so the penalty does not round the crease off. A direction of degree 1
    /// (a ruled direction) uses first differences instead: its control polygon is the surface.
    pub fair: f64,
    /// Smoothness of the log-weights, `σ / model size`: the objective gains
    /// `σ^2 (1/e) sum (θ_a - θ_b)^2` over the `e` pairs of neighbouring weights (grid
    /// neighbours; in the rank-one layout neighbouring `α` and neighbouring `β`), so the weights
    /// vary smoothly over the net instead of running to their bounds one by one. `0` (the
    /// default) leaves them independent.
    pub weight_smoothing: f64,
}

impl Default for WeightOptions {
    /// Re-solved control points, full grid, weights in `[0.1, 10]`, regularisation `1e-6`,
    /// anchor `1e-9`.
    fn default() -> Self {
        WeightOptions {
            mode: WeightMode::Resolved,
            layout: WeightLayout::Full,
            bounds: (0.1, 10.0),
            regularization: 1e-6,
            anchor: 1e-9,
            search_scale: Some(10.0),
            fair: 0.0,
            weight_smoothing: 0.0,
        }
    }
}

/// The weight-optimisation objective. `Sync`: evaluations may run in
/// parallel, each with its own per-thread scratch.
///
/// # The objective
///
/// With data points `Q_k` at parameters `(u_k, v_k)`, B-spline products
/// `B_kc = N_{i,p}(u_k) N_{j,q}(v_k)` (`c = (i, j)`) and weights `w_c`, the rational basis is
/// `R_kc(w) = B_kc w_c / W_k`, `W_k = sum_c B_kc w_c` (The NURBS Book eq. 4.15), and
/// `S_k = sum_c R_kc(w) P_c`. The objective is
///
/// `f(θ) = sqrt( (1/m) sum_k |S_k - Q_k|^2 + ρ^2 (1/d) sum_i θ_i^2 )`,
///
/// over `d` log-weights `θ` in a box (weights in `[0.1, 10]` by default), `m` offsets, and a
/// mild regularisation `ρ = regularization x model size` that keeps the log-weights near 0
/// (weights near 1) where the data do not care, and fixes the scale gauge (multiplying all weights
/// by one factor changes nothing else). At `θ = 0` the penalty vanishes. With a fairness term
/// ([`WeightOptions::fair`]) the data and fairness parts are taken at the gauge-fixed `Π θ`
/// (`gauge`), as the energy of the homogeneous net would otherwise fall with the weights' scale.
///
/// * [`WeightMode::Fixed`]: `P_c` are the control points of the plain approximation.
/// * [`WeightMode::Resolved`] (variable projection, Golub and Pereyra 1973): for each `w`,
///   `P(w) = argmin_P sum_k |sum_c R_kc(w) P_c - Q_k|^2`. Writing `Y_c = w_c P_c` (homogeneous
///   coordinates) and `h_kc = B_kc / W_k`, `S_k = sum_c h_kc Y_c`, so `Y` solves the normal
///   equations `G Y = H^T Q` with `G = H^T H` - the same system as `R^T R P = R^T Q`
///   (`R = H diag(w)`), without the `w_c w_d` scaling that would square the weights' spread
///   into its condition number. Each row of `H` has `(p+1)(q+1)` non-zeros, so `G` is banded:
///   half-bandwidth `p n_v + q` in u-major order, `q n_u + p` in v-major order; the smaller is
///   used. The B-spline products are computed once (they do not depend on `w`): an evaluation
///   costs at most `m ((p+1)(q+1))^2 / 2` multiply-adds to assemble `G` (much less for the
///   offsets of one skinned section, which share `v`: their sum is a Kronecker product, see
///   `add_run`) and `n bw^2 / 2` to factor it, with scratch space reused per thread (no
///   allocation once warm). Measured (`benches/objective.rs`, one core of this 2-core Xeon):
///   10 x 8 bicubic, 250 offsets: about 160,000 evaluations/s fixed, 28,000/s re-solved.
///
/// A singular or too ill-conditioned `G` (Cholesky pivot below `1e-12` of its diagonal, as when
/// some control point has no offset in its support) makes the value `+inf`, never NaN.
///
/// # The fairness term's scale gauge
///
/// Multiplying every weight by one factor `e^c` leaves the rational surface unchanged, and in
/// `Resolved` mode the least-squares homogeneous control points scale with it: `Y -> e^c Y`.
/// The data residuals do not see `c`, but the net's energy `|D Y|^2` does, as `e^{2c}`: a
/// fairness term on `Y` rewards lowering all weights together, and an optimiser runs every
/// weight towards its lower bound without making the surface any fairer (measured: `--method
/// lm` on the built-in sample ended with weights in `[0.1, 0.47]`, 15 of 114 on the bound).
///
/// The fix is to measure the energy in a fixed gauge. With a fairness term, the data and
/// fairness parts of the objective are evaluated at `Π θ`, where `Π` removes the mean of each
/// gauge group (all log-weights; in the rank-one layout `α` and `β` separately, each of whose
/// common shifts scales every weight), so the weights' geometric mean is 1 there:
///
/// `f(θ)^2 = F(Π θ) + θ^T R θ`, `F` the data and fairness parts, `R` the prior,
///
/// which is `F` with the energy `e^{-2 μ} |D Y|^2` (`μ` the mean log-weight) at `θ`: invariant
/// under the scaling, and equal to the old term wherever `μ = 0` (the start). The chain rule
/// gives the Jacobian of those rows as `J(Π θ) Π` (`Π` symmetric and idempotent), the normal
/// matrix `Π J^T J Π` and the gradient `Π J^T r`; the prior (`R`, which pins the gauge at
/// `μ = 0`) is taken at `θ` itself. The surface is the one at `Π θ`, written with the weights
/// `e^θ` of the box. Without a fairness term nothing changes (bit for bit).
#[derive(Clone, Debug)]
pub struct WeightProblem {
    ku: KnotVector,
    kv: KnotVector,
    options: WeightOptions,
    pat: Pattern,
    points: Vec<[f64; 3]>,
    params: Vec<(f64, f64)>,
    table: BasisTable,
    /// The plain approximation's control points, band order (used in `Fixed` mode).
    fixed: Vec<[f64; 3]>,
    lower: Vec<f64>,
    upper: Vec<f64>,
    size: f64,
    /// `ρ` of [`WeightProblem`]'s docs.
    rho: f64,
    /// The section (run of offsets sharing one `v` at construction) of each offset.
    section: Vec<usize>,
    /// The control net's difference operator (u-major indices) and `D^T D` as band entries
    /// `(index into the band storage, value)`: empty when `fair` is 0.
    net: NetEnergy,
    net_band: Vec<(usize, f64)>,
    /// `λ m / r`: the factor of `D^T D` in `G` (`G` sums the unscaled residuals).
    fair_g: f64,
    /// `λ / r`: the factor of `|D Y|^2` in `f^2`.
    fair_f: f64,
    /// Neighbouring variables `(a, b)` of the log-weight smoothing, and `σ^2 / e`.
    smooth_pairs: Vec<(usize, usize)>,
    smooth: f64,
}

impl WeightProblem {
    /// The problem for `surface`'s degrees and knots (its control points serve
    /// [`WeightMode::Fixed`]; its weights, if any, are ignored: the start is all weights 1),
    /// data points `points[k]` at parameters `params[k]` (clamped to the domain).
    ///
    /// # Errors
    /// [`HullError::Weights`] if `points` and `params` differ in length, are empty, hold a
    /// non-finite value, or the bounds are not `0 < lo <= 1 <= hi` finite;
    /// [`HullError::FitSetting`] if another option is out of range (`regularization >= 0`
    /// finite).
    pub fn new(
        surface: &NurbsSurface,
        points: &[Vec3],
        params: &[(f64, f64)],
        options: WeightOptions,
    ) -> Result<Self, HullError> {
        let (lo, hi) = options.bounds;
        if !(lo > 0.0 && lo <= 1.0 && hi >= 1.0 && hi.is_finite()) {
            return Err(HullError::Weights(WeightsKind::Bounds { lo, hi }));
        }
        if !(options.regularization >= 0.0 && options.regularization.is_finite()) {
            return Err(HullError::FitSetting {
                name: "weight regularization",
                value: options.regularization,
                expected: "a finite number >= 0",
            });
        }
        for (name, v) in [("fairness", options.fair), ("weight smoothing", options.weight_smoothing)] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(HullError::FitSetting { name, value: v, expected: "a finite number >= 0" });
            }
        }
        if let Some(k) = options.search_scale {
            if !(k > 0.0 && k.is_finite()) {
                return Err(HullError::FitSetting {
                    name: "weight search scale",
                    value: k,
                    expected: "a finite number > 0",
                });
            }
        }
        if points.len() != params.len() || points.is_empty() {
            return Err(HullError::Weights(WeightsKind::ParameterCount {
                offsets: points.len(),
                params: params.len(),
            }));
        }
        if let Some(k) = points.iter().position(|q| !q.is_finite()) {
            return Err(HullError::Weights(WeightsKind::NonFiniteOffset { index: k }));
        }
        if let Some(k) = params.iter().position(|(u, v)| !(u.is_finite() && v.is_finite())) {
            return Err(HullError::Weights(WeightsKind::NonFiniteParameters { index: k }));
        }
        let (ku, kv) = (surface.knots_u().clone(), surface.knots_v().clone());
        let (n_u, n_v) = (surface.n_u(), surface.n_v());
        let pat = Pattern::new(surface.degree_u(), surface.degree_v(), n_u, n_v);
        let params: Vec<(f64, f64)> = params.iter().map(|&(u, v)| (ku.clamp(u), kv.clamp(v))).collect();
        let mut fixed = vec![[0.0; 3]; n_u * n_v];
        for i in 0..n_u {
            for j in 0..n_v {
                fixed[pat.pos(i, j)] = surface.control_point(i, j).to_array();
            }
        }
        let d = match options.layout {
            WeightLayout::Full => n_u * n_v,
            WeightLayout::RankOne => n_u + n_v,
        };
        let half = if options.layout == WeightLayout::RankOne { 0.5 } else { 1.0 };
        let (lower, upper) = (vec![half * lo.ln(); d], vec![half * hi.ln(); d]);
        let (mut bmin, mut bmax) = (points[0], points[0]);
        for q in points {
            bmin = Vec3::new(bmin.x.min(q.x), bmin.y.min(q.y), bmin.z.min(q.z));
            bmax = Vec3::new(bmax.x.max(q.x), bmax.y.max(q.y), bmax.z.max(q.z));
        }
        let size = (bmax - bmin).norm();
        let mut problem = WeightProblem {
            ku,
            kv,
            options,
            pat,
            points: points.iter().map(|q| q.to_array()).collect(),
            params: Vec::new(),
            table: BasisTable::default(),
            fixed,
            lower,
            upper,
            size,
            rho: options.regularization * size,
            section: Vec::with_capacity(params.len()),
            net: NetEnergy::default(),
            net_band: Vec::new(),
            fair_g: 0.0,
            fair_f: 0.0,
            smooth_pairs: Vec::new(),
            smooth: 0.0,
        };
        problem.set_penalties();
        for (k, &(_, v)) in params.iter().enumerate() {
            let g = match problem.section.last() {
                Some(&g) if v == params[k - 1].1 => g,
                Some(&g) => g + 1,
                None => 0,
            };
            problem.section.push(g);
        }
        problem.table = problem.basis_table(&params, false);
        problem.params = params;
        Ok(problem)
    }

    /// The problem of a plain approximation `fit` of `offsets`: its surface, and every offset
    /// with its fitted parameters, section by section.
    ///
    /// # Errors
    /// [`HullError::Weights`] if `fit.params()` does not match the offsets point for point, and as
    /// [`WeightProblem::new`].
    pub fn from_fit(fit: &impl FittedSurface, offsets: &Offsets, options: WeightOptions) -> Result<Self, HullError> {
        let shapes_match = fit.params().len() == offsets.sections.len()
            && fit.params().iter().zip(&offsets.sections).all(|(t, s)| t.len() == s.points.len());
        if !shapes_match {
            return Err(HullError::Weights(WeightsKind::FitMismatch));
        }
        let points: Vec<Vec3> = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
        let params: Vec<(f64, f64)> = fit.params().iter().flatten().copied().collect();
        Self::new(fit.surface(), &points, &params, options)
    }

    /// The same problem at other data parameters (clamped to the domain).
    ///
    /// # Errors
    /// [`HullError::Weights`] if `params` does not hold one finite pair per offset.
    pub fn with_params(&self, params: &[(f64, f64)]) -> Result<Self, HullError> {
        if params.len() != self.points.len() {
            return Err(HullError::Weights(WeightsKind::ParameterCount {
                offsets: self.points.len(),
                params: params.len(),
            }));
        }
        if let Some(k) = params.iter().position(|(u, v)| !(u.is_finite() && v.is_finite())) {
            return Err(HullError::Weights(WeightsKind::NonFiniteParameters { index: k }));
        }
        let params: Vec<(f64, f64)> = params.iter().map(|&(u, v)| (self.ku.clamp(u), self.kv.clamp(v))).collect();
        let mut out = self.clone();
        out.table = self.basis_table(&params, false);
        out.params = params;
        Ok(out)
    }

    /// The same problem with other fairness settings ([`WeightOptions::fair`],
    /// [`WeightOptions::weight_smoothing`]); the basis products are kept.
    ///
    /// # Errors
    /// [`HullError::FitSetting`] if either is negative or not finite.
    pub fn with_fairness(&self, fair: f64, weight_smoothing: f64) -> Result<Self, HullError> {
        for (name, v) in [("fairness", fair), ("weight smoothing", weight_smoothing)] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(HullError::FitSetting { name, value: v, expected: "a finite number >= 0" });
            }
        }
        let mut out = self.clone();
        out.options.fair = fair;
        out.options.weight_smoothing = weight_smoothing;
        out.set_penalties();
        Ok(out)
    }

    /// The evolutionary algorithms' search box (see [`WeightOptions::search_scale`]): the
    /// bounds narrowed around the start to `±h_i`. A variable the residual does not depend on
    /// (`J_i = 0`), or a start where the Jacobian cannot be formed, keeps its whole bounds.
    pub fn sensitivity_box(&self) -> (Vec<f64>, Vec<f64>) {
        let (mut lo, mut hi) = (self.lower.clone(), self.upper.clone());
        let Some(k) = self.options.search_scale else {
            return (lo, hi);
        };
        let x0 = self.start();
        let d = x0.len();
        let f0 = self.value(&x0);
        let Some(diag) = self.jtj_diagonal(&x0) else {
            return (lo, hi);
        };
        for i in 0..d {
            let h = k * f0 / (diag[i].sqrt() * (d as f64).sqrt());
            if h.is_finite() && h > 0.0 {
                lo[i] = lo[i].max(x0[i] - h);
                hi[i] = hi[i].min(x0[i] + h);
            }
        }
        (lo, hi)
    }

    pub fn options(&self) -> &WeightOptions {
        &self.options
    }
    /// The data parameters `(u_k, v_k)`.
    pub fn params(&self) -> &[(f64, f64)] {
        &self.params
    }
    /// Number of offsets `m`.
    pub fn num_points(&self) -> usize {
        self.points.len()
    }
    /// Control points `(n_u, n_v)`.
    pub fn ctrl(&self) -> (usize, usize) {
        (self.pat.n_u, self.pat.n_v)
    }
    /// The diagonal of the offsets' bounding box.
    pub fn size(&self) -> f64 {
        self.size
    }
    /// Half-bandwidth of the normal matrix (after choosing the cheaper ordering).
    pub fn bandwidth(&self) -> usize {
        self.pat.bw
    }
    /// The sections of [`ParamFreedom::USectionV`]: maximal runs of consecutive offsets that
    /// shared one `v` when the problem was built (kept by [`WeightProblem::with_params`]),
    /// as the index of each offset's section.
    pub fn sections(&self) -> &[usize] {
        &self.section
    }
}

impl Objective for WeightProblem {
    fn dim(&self) -> usize {
        self.lower.len()
    }
    fn lower(&self) -> &[f64] {
        &self.lower
    }
    fn upper(&self) -> &[f64] {
        &self.upper
    }
    /// `f(θ)` of [`WeightProblem`]'s docs; `+inf` for an infeasible point (wrong length, non-finite
    /// entries, singular least-squares system).
    fn value(&self, x: &[f64]) -> f64 {
        self.value_with(&self.table, x)
    }
    /// All weights 1.
    fn start(&self) -> Vec<f64> {
        vec![0.0; self.dim()]
    }
    fn search_box(&self) -> (Vec<f64>, Vec<f64>) {
        self.sensitivity_box()
    }
}
