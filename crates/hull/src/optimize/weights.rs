//! The NURBS weight-optimisation objective: the RMS parametric residual of the offsets as a
//! function of the (log-)weights, with the control points either kept or re-solved.
//!
//! With data points `Q_k` at parameters `(u_k, v_k)`, B-spline products
//! `B_kc = N_{i,p}(u_k) N_{j,q}(v_k)` (`c = (i, j)`) and weights `w_c`, the rational basis is
//! `R_kc(w) = B_kc w_c / W_k`, `W_k = sum_c B_kc w_c` (The NURBS Book eq. 4.15), and
//! `S_k = sum_c R_kc(w) P_c`. The objective is
//!
//! `f(θ) = sqrt( (1/m) sum_k |S_k - Q_k|^2 + ρ^2 (1/d) sum_i θ_i^2 )`,
//!
//! over `d` log-weights `θ` in a box (weights in `[0.1, 10]` by default), `m` offsets, and a
//! mild regularisation `ρ = regularization x model size` that keeps the log-weights near 0
//! (weights near 1) where the data do not care, and fixes the scale gauge (multiplying all weights
//! by one factor changes nothing else). At `θ = 0` the penalty vanishes. With a fairness term
//! ([`WeightOptions::fair`]) the data and fairness parts are taken at the gauge-fixed `Π θ`
//! (`gauge`), as the energy of the homogeneous net would otherwise fall with the weights' scale.
//!
//! * [`WeightMode::Fixed`]: `P_c` are the control points of the plain approximation.
//! * [`WeightMode::Resolved`] (variable projection, Golub and Pereyra 1973): for each `w`,
//!   `P(w) = argmin_P sum_k |sum_c R_kc(w) P_c - Q_k|^2`. Writing `Y_c = w_c P_c` (homogeneous
//!   coordinates) and `h_kc = B_kc / W_k`, `S_k = sum_c h_kc Y_c`, so `Y` solves the normal
//!   equations `G Y = H^T Q` with `G = H^T H` - the same system as `R^T R P = R^T Q`
//!   (`R = H diag(w)`), without the `w_c w_d` scaling that would square the weights' spread
//!   into its condition number. Each row of `H` has `(p+1)(q+1)` non-zeros, so `G` is banded:
//!   half-bandwidth `p n_v + q` in u-major order, `q n_u + p` in v-major order; the smaller is
//!   used. The B-spline products are computed once (they do not depend on `w`): an evaluation
//!   costs at most `m ((p+1)(q+1))^2 / 2` multiply-adds to assemble `G` (much less for the
//!   offsets of one skinned section, which share `v`: their sum is a Kronecker product, see
//!   `add_run`) and `n bw^2 / 2` to factor it, with scratch space reused per thread (no
//!   allocation once warm). Measured (`benches/objective.rs`, one core of this 2-core Xeon):
//!   10 x 8 bicubic, 250 offsets: about 160,000 evaluations/s fixed, 28,000/s re-solved.
//!
//! A singular or too ill-conditioned `G` (Cholesky pivot below `1e-12` of its diagonal, as when
//! some control point has no offset in its support) makes the value `+inf`, never NaN.

use std::cell::RefCell;

use nurbs::basis::{basis_funs, ders_basis_funs, BasisRow};
use nurbs::{KnotVector, NurbsError, NurbsSurface, Vec3, MAX_DEGREE};

use super::linalg::{band_cholesky, band_solve, dot};
use super::net_energy::NetEnergy;

mod gauge;
mod within;
use super::FittedSurface;
use super::Objective;
use crate::{HullError, Offsets};
pub use within::ControlBox;

mod matvec;

pub(crate) use matvec::{Evaluation, JacobianOp};

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

/// Settings of a [`WeightProblem`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct WeightOptions {
    pub mode: WeightMode,
    pub layout: WeightLayout,
    /// Weight range `(lo, hi)`, `0 < lo <= 1 <= hi`. The log-weights are boxed to
    /// `[ln lo, ln hi]`; in the rank-one layout each factor to `[ln lo / 2, ln hi / 2]`, so
    /// every product `a_i b_j` stays in range too.
    pub bounds: (f64, f64),
    /// `ρ / model size` (see the module docs): a log-weight of 1 on every variable costs as much
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

/// The Gauss-Newton normal equations `J^T J` and `J^T r` of the weight variables, with `J`
/// Kaufman's Jacobian ([`JacobianKind::Kaufman`]) in `Resolved` mode, formed without `J`
/// (see [`WeightProblem::normal_equations`]).
#[derive(Clone, Debug, PartialEq)]
pub struct NormalEquations {
    /// `J^T J`, row-major `dim x dim`, symmetric.
    pub jtj: Vec<f64>,
    /// `J^T r`, the gradient of `|r|^2 / 2`.
    pub jtr: Vec<f64>,
    pub dim: usize,
}

/// The structure shared by all evaluations: band layout of the control points and the offsets
/// of one offset's `(p+1)(q+1)` control points from its first.
#[derive(Clone, Debug)]
struct Pattern {
    n_u: usize,
    n_v: usize,
    p: usize,
    q: usize,
    /// Half-bandwidth of `G`.
    bw: usize,
    /// Band order: u-major (`pos = i n_v + j`) or v-major (`pos = j n_u + i`).
    u_major: bool,
    /// `(p+1)(q+1)`.
    nb: usize,
    /// Local entry `l` (in increasing band position) sits at `first + off[l]`.
    off: Vec<usize>,
    /// Local entry `l` is `(a, b)`: `N_{i0+a}(u) N_{j0+b}(v)`.
    ab: Vec<(usize, usize)>,
    /// Length of the local index's inner (band-contiguous) dimension: `q + 1` in u-major
    /// order, `p + 1` in v-major; local entry `l = o inner + i` sits at `o so + i` from the
    /// offset's first control point.
    inner: usize,
    /// Row stride of the band storage: `bw + inner`, the padding taking the upper-triangle
    /// half of the diagonal blocks, so every block is written whole.
    stride: usize,
    /// The blocks of `h h^T` for one offset: `(l, band index minus first stride, first l2)`,
    /// each `inner` long: entries `(l, l2 .. l2 + inner)` for every outer index up to `l`'s.
    blocks: Vec<(usize, usize, usize)>,
    /// Band position -> u-major control index `i n_v + j`.
    grid: Vec<usize>,
}

impl Pattern {
    fn new(p: usize, q: usize, n_u: usize, n_v: usize) -> Self {
        let (bw_u, bw_v) = (p * n_v + q, q * n_u + p);
        let u_major = bw_u <= bw_v;
        let bw = if u_major { bw_u } else { bw_v };
        let mut ab = Vec::with_capacity((p + 1) * (q + 1));
        if u_major {
            for a in 0..=p {
                for b in 0..=q {
                    ab.push((a, b));
                }
            }
        } else {
            for b in 0..=q {
                for a in 0..=p {
                    ab.push((a, b));
                }
            }
        }
        let pos = |i: usize, j: usize| if u_major { i * n_v + j } else { j * n_u + i };
        let off: Vec<usize> = ab.iter().map(|&(a, b)| pos(a, b)).collect();
        // Entry (r, c) = (first + off_l, first + off_l2) sits at r stride + c + bw - r
        // = first stride + off_l (stride - 1) + off_l2 + bw; with l = (o, i), l2 = (o2, i2),
        // off_l2 = o2 so + i2 is contiguous in i2. For o2 = o the entries i2 > i lie above the
        // diagonal, at most inner - 1 columns: in row r's padding.
        let (inner, so) = if u_major { (q + 1, n_v) } else { (p + 1, n_u) };
        let stride = bw + inner;
        let mut blocks = Vec::new();
        for (l, &o_l) in off.iter().enumerate() {
            for o2 in 0..=l / inner {
                blocks.push((l, o_l * (stride - 1) + o2 * so + bw, o2 * inner));
            }
        }
        let mut grid = vec![0; n_u * n_v];
        for i in 0..n_u {
            for j in 0..n_v {
                grid[pos(i, j)] = i * n_v + j;
            }
        }
        Pattern { n_u, n_v, p, q, bw, u_major, nb: ab.len(), off, ab, inner, stride, blocks, grid }
    }

    fn n(&self) -> usize {
        self.n_u * self.n_v
    }

    fn pos(&self, i: usize, j: usize) -> usize {
        if self.u_major {
            i * self.n_v + j
        } else {
            j * self.n_u + i
        }
    }
}

/// The B-spline products of every offset (and, for parameter optimisation, their derivatives
/// in `u` and `v`), independent of the weights.
#[derive(Clone, Debug, Default)]
pub(crate) struct BasisTable {
    /// Band position of each offset's first control point.
    first: Vec<usize>,
    /// `m nb` products, local order.
    vals: Vec<f64>,
    /// `d/du` of the products (empty unless asked for).
    du: Vec<f64>,
    /// `d/dv` of the products (empty unless asked for).
    dv: Vec<f64>,
    /// `N_{i0+a,p}(u_k)`, `p + 1` per offset, and `i0` of each offset.
    nu: Vec<f64>,
    i0: Vec<usize>,
    /// `N_{j0+b,q}(v_k)`, `q + 1` per offset.
    nv: Vec<f64>,
    /// Runs `[k0, k1)` of consecutive offsets sharing one `v` (a skinned section): their
    /// contributions to `G` share the factor `N(v) N(v)^T` and are assembled together.
    runs: Vec<(usize, usize)>,
}

/// Per-thread scratch of one evaluation.
#[derive(Default)]
struct Scratch {
    /// The variables the weights are filled from: `Π θ` when the gauge is fixed (`gauge`).
    xg: Vec<f64>,
    /// Weights in band order.
    w: Vec<f64>,
    /// Rank-one factors `a`, `b`.
    ab: Vec<f64>,
    /// `1 / W_k` per offset.
    s: Vec<f64>,
    /// `h_kl` of one offset.
    h: Vec<f64>,
    /// The normal matrix `G`, then its Cholesky factor.
    band: Vec<f64>,
    /// Homogeneous control points `Y = w P`, band order.
    y: Vec<[f64; 3]>,
    /// A run's `U = sum_k s_k^2 N(u_k) N(u_k)^T`, rows of `2p + 1` around the diagonal.
    gu: Vec<f64>,
    /// A run's `sum_k s_k N(u_k) Q_k`.
    tu: Vec<[f64; 3]>,
}

thread_local! {
    static SCRATCH: RefCell<Scratch> = RefCell::new(Scratch::default());
}

/// The weight-optimisation objective (see the module docs). `Sync`: evaluations may run in
/// parallel, each with its own per-thread scratch.
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
    /// `ρ` of the module docs.
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
    /// [`HullError::Config`] if `points` and `params` differ in length, are empty, hold a
    /// non-finite value, or the options are out of range (`0 < lo <= 1 <= hi` finite,
    /// `regularization >= 0` finite).
    pub fn new(
        surface: &NurbsSurface,
        points: &[Vec3],
        params: &[(f64, f64)],
        options: WeightOptions,
    ) -> Result<Self, HullError> {
        let (lo, hi) = options.bounds;
        if !(lo > 0.0 && lo <= 1.0 && hi >= 1.0 && hi.is_finite()) {
            return Err(HullError::Config(format!(
                "weight bounds ({lo}, {hi}) are not usable (expected 0 < lo <= 1 <= hi, finite)"
            )));
        }
        if !(options.regularization >= 0.0 && options.regularization.is_finite()) {
            return Err(HullError::Config(format!(
                "weight regularization {} is not usable (expected a finite number >= 0)",
                options.regularization
            )));
        }
        for (name, v) in [("fairness", options.fair), ("weight smoothing", options.weight_smoothing)] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(HullError::Config(format!("{name} {v} is not usable (expected a finite number >= 0)")));
            }
        }
        if let Some(k) = options.search_scale {
            if !(k > 0.0 && k.is_finite()) {
                return Err(HullError::Config(format!(
                    "weight search scale {k} is not usable (expected a finite number > 0)"
                )));
            }
        }
        if points.len() != params.len() || points.is_empty() {
            return Err(HullError::Config(format!(
                "{} offsets with {} parameters (expected as many parameters as offsets, at least one)",
                points.len(),
                params.len()
            )));
        }
        if let Some(k) = points.iter().position(|q| !q.is_finite()) {
            return Err(HullError::Config(format!("offset {k} is not finite (expected finite coordinates)")));
        }
        if let Some(k) = params.iter().position(|(u, v)| !(u.is_finite() && v.is_finite())) {
            return Err(HullError::Config(format!("parameters of offset {k} are not finite (expected finite (u, v))")));
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
    /// [`HullError::Config`] if `fit.params()` does not match the offsets point for point, and as
    /// [`WeightProblem::new`].
    pub fn from_fit(fit: &impl FittedSurface, offsets: &Offsets, options: WeightOptions) -> Result<Self, HullError> {
        let shapes_match = fit.params().len() == offsets.sections.len()
            && fit.params().iter().zip(&offsets.sections).all(|(t, s)| t.len() == s.points.len());
        if !shapes_match {
            return Err(HullError::Config(
                "the fit's parameters do not match the offsets (expected the fit of these offsets)".into(),
            ));
        }
        let points: Vec<Vec3> = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
        let params: Vec<(f64, f64)> = fit.params().iter().flatten().copied().collect();
        Self::new(fit.surface(), &points, &params, options)
    }

    /// The same problem at other data parameters (clamped to the domain).
    ///
    /// # Errors
    /// [`HullError::Config`] if `params` does not hold one finite pair per offset.
    pub fn with_params(&self, params: &[(f64, f64)]) -> Result<Self, HullError> {
        if params.len() != self.points.len() {
            return Err(HullError::Config(format!(
                "{} parameters for {} offsets (expected one pair per offset)",
                params.len(),
                self.points.len()
            )));
        }
        if let Some(k) = params.iter().position(|(u, v)| !(u.is_finite() && v.is_finite())) {
            return Err(HullError::Config(format!("parameters of offset {k} are not finite (expected finite (u, v))")));
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
    /// [`HullError::Config`] if either is negative or not finite.
    pub fn with_fairness(&self, fair: f64, weight_smoothing: f64) -> Result<Self, HullError> {
        for (name, v) in [("fairness", fair), ("weight smoothing", weight_smoothing)] {
            if !(v >= 0.0 && v.is_finite()) {
                return Err(HullError::Config(format!("{name} {v} is not usable (expected a finite number >= 0)")));
            }
        }
        let mut out = self.clone();
        out.options.fair = fair;
        out.options.weight_smoothing = weight_smoothing;
        out.set_penalties();
        Ok(out)
    }

    /// Build the fairness operator and the log-weight pairs from the options.
    fn set_penalties(&mut self) {
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
    fn prior_value(&self, x: &[f64]) -> f64 {
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
    fn net_value(&self, sc: &Scratch) -> f64 {
        let (pat, n_v) = (&self.pat, self.pat.n_v);
        self.net.value(|c| sc.y[pat.pos(c / n_v, c % n_v)])
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
    fn param_col(&self, free: ParamFreedom, d: usize, k: usize, dir: usize) -> Option<usize> {
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
    /// [`HullError::Config`] if `x` has the wrong length or a non-finite entry;
    /// [`HullError::Fit`] with [`NurbsError::SingularSystem`] if the least-squares system is
    /// singular or too ill-conditioned, or another kernel error if the result is not finite.
    pub fn surface(&self, x: &[f64]) -> Result<NurbsSurface, HullError> {
        if x.len() != self.dim() || !x.iter().all(|t| t.is_finite()) {
            return Err(HullError::Config(format!(
                "{} weight variables (expected {} finite numbers)",
                x.len(),
                self.dim()
            )));
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

    /// The residual vector `r` (see [`Linearization::residuals`]), `None` where the value is
    /// infinite.
    pub fn residuals(&self, x: &[f64]) -> Option<Vec<f64>> {
        let mut sc = Scratch::default();
        if !self.solve(&self.table, x, &mut sc) {
            return None;
        }
        Some(self.residual_vector(&self.table, x, &sc))
    }

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
    fn gauss_newton(&self, x: &[f64], full_out: bool) -> Option<(Vec<f64>, Vec<f64>)> {
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
            for v in 0..d {
                band_forward_from(&sc.band, n, bw, stride, &mut z[v * n..(v + 1) * n], start[v]);
            }
            band_forward_from(&sc.band, n, bw, stride, &mut hte, 0);
            let t = hte.as_flattened();
            for v in 0..d {
                let wv = z[v * n..(v + 1) * n].as_flattened();
                let sv = start[v].min(n);
                // With the fairness term the least-squares optimality is A^T r = H^T e +
                // λ' D^T D Y = 0, not H^T e = 0, and the projected part of the augmented
                // gradient vanishes: J^T r = A^T e (as in `matvec::JacobianOp::gradient`).
                if self.fair_g == 0.0 {
                    jtr[v] -= dot(&wv[3 * sv..], &t[3 * sv..]);
                }
                for w in if full { 0 } else { v }..=v {
                    let s0 = 3 * sv.max(start[w]).min(n);
                    let ww = dot(&wv[s0..], &z[w * n..(w + 1) * n].as_flattened()[s0..]);
                    jtj[if full { v * d + w } else { v }] -= ww;
                }
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

    // ----- internals -----

    /// Basis products at `params` (clamped), with first derivatives if `derivs`.
    pub(crate) fn basis_table(&self, params: &[(f64, f64)], derivs: bool) -> BasisTable {
        let pat = &self.pat;
        let (p, q, nb) = (pat.p, pat.q, pat.nb);
        let m = params.len();
        let mut t = BasisTable {
            first: Vec::with_capacity(m),
            vals: Vec::with_capacity(m * nb),
            du: Vec::with_capacity(if derivs { m * nb } else { 0 }),
            dv: Vec::with_capacity(if derivs { m * nb } else { 0 }),
            nu: Vec::with_capacity(m * (p + 1)),
            i0: Vec::with_capacity(m),
            nv: Vec::with_capacity(m * (q + 1)),
            runs: Vec::new(),
        };
        let mut last_v = f64::NAN;
        let mut nu = [[0.0; MAX_DEGREE + 1]; 2];
        let mut nv = [[0.0; MAX_DEGREE + 1]; 2];
        for &(u, v) in params {
            let (u, v) = (self.ku.clamp(u), self.kv.clamp(v));
            let (su, sv) = (self.ku.find_span(u), self.kv.find_span(v));
            if derivs {
                ders_basis_funs(self.ku.as_slice(), su, u, p, 1, &mut nu);
                ders_basis_funs(self.kv.as_slice(), sv, v, q, 1, &mut nv);
            } else {
                let (mut bu, mut bv): (BasisRow, BasisRow) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
                basis_funs(self.ku.as_slice(), su, u, p, &mut bu);
                basis_funs(self.kv.as_slice(), sv, v, q, &mut bv);
                nu[0] = bu;
                nv[0] = bv;
            }
            t.first.push(pat.pos(su - p, sv - q));
            t.i0.push(su - p);
            t.nu.extend_from_slice(&nu[0][..=p]);
            t.nv.extend_from_slice(&nv[0][..=q]);
            let k = t.first.len() - 1;
            match t.runs.last_mut() {
                Some(r) if v == last_v => r.1 = k + 1,
                _ => t.runs.push((k, k + 1)),
            }
            last_v = v;
            for &(a, b) in &pat.ab {
                t.vals.push(nu[0][a] * nv[0][b]);
                if derivs {
                    t.du.push(nu[1][a] * nv[0][b]);
                    t.dv.push(nu[0][a] * nv[1][b]);
                }
            }
        }
        t
    }

    /// Weights in band order from the variables (and the rank-one factors in `ab`).
    fn fill_weights(&self, x: &[f64], w: &mut Vec<f64>, ab: &mut Vec<f64>) {
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
    fn solve(&self, table: &BasisTable, x: &[f64], sc: &mut Scratch) -> bool {
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
    fn assemble(&self, table: &BasisTable, x: &[f64], sc: &mut Scratch) -> bool {
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
        match self.options.mode {
            WeightMode::Fixed => {
                for (k, &first) in table.first.iter().enumerate() {
                    let b = &table.vals[k * nb..(k + 1) * nb];
                    let wk = &sc.w[first..];
                    let big_w: f64 = b.iter().zip(&pat.off).map(|(bl, &o)| bl * wk[o]).sum();
                    if !(big_w > 0.0 && big_w.is_finite()) {
                        return false;
                    }
                    sc.s[k] = 1.0 / big_w;
                }
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
                for (k, &first) in table.first.iter().enumerate() {
                    let b = &table.vals[k * nb..(k + 1) * nb];
                    let wk = &sc.w[first..];
                    let big_w: f64 = b.iter().zip(&pat.off).map(|(bl, &o)| bl * wk[o]).sum();
                    if !(big_w > 0.0 && big_w.is_finite()) {
                        return false;
                    }
                    sc.s[k] = 1.0 / big_w;
                }
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
    fn add_run(&self, table: &BasisTable, k0: usize, k1: usize, sc: &mut Scratch) {
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
    fn point_of(&self, table: &BasisTable, sc: &Scratch, k: usize) -> [f64; 3] {
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
    fn value_squared(&self, table: &BasisTable, x: &[f64], sc: &Scratch) -> f64 {
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
    fn residual_vector(&self, table: &BasisTable, x: &[f64], sc: &Scratch) -> Vec<f64> {
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

    /// The fairness rows `sqrt(λ / r) D Y` (x, y, z of each stencil) and the smoothing rows
    /// `σ / sqrt(e) (θ_a - θ_b)`, after the regularisation rows: `|r|^2 = f^2`.
    fn push_penalty_rows(&self, r: &mut Vec<f64>, x: &[f64], sc: &Scratch) {
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
    fn penalty_rows(&self) -> usize {
        (if self.fair_f > 0.0 { 3 * self.net.len() } else { 0 })
            + if self.smooth > 0.0 { self.smooth_pairs.len() } else { 0 }
    }

    /// The variables a band position's log-weight feeds: `[c]` (full grid) or `[i, n_u + j]`
    /// (rank one); the count is returned with them.
    #[inline]
    fn vars_of(&self, pos: usize) -> ([usize; 2], usize) {
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
    fn a_row(
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
    fn derivative_points(&self, sc: &Scratch) -> Vec<[f64; 3]> {
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

/// Overwrite `b` with `L^{-1} b` (forward substitution) for the band Cholesky factor `l` of
/// `band_cholesky`, when `b` is zero before row `start` (so is the result).
fn band_forward_from(l: &[f64], n: usize, bw: usize, stride: usize, b: &mut [[f64; 3]], start: usize) {
    for i in start..n {
        let row = &l[i * stride..i * stride + bw + 1];
        let k0 = i.saturating_sub(bw).max(start);
        let (done, rest) = b.split_at_mut(i);
        let mut s = rest[0];
        for (lk, bk) in row[k0 + bw - i..bw].iter().zip(&done[k0..]) {
            s[0] -= lk * bk[0];
            s[1] -= lk * bk[1];
            s[2] -= lk * bk[2];
        }
        let dg = row[bw];
        rest[0] = [s[0] / dg, s[1] / dg, s[2] / dg];
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
    /// `f(θ)` of the module docs; `+inf` for an infeasible point (wrong length, non-finite
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::optimize::evaluate_all;
    use crate::{fit_offsets, series60_sample, FitConfig, FitOutcome};
    use nurbs::assert_near;

    fn sample_fit(ctrl: (usize, usize)) -> (FitOutcome, Offsets) {
        let offsets = series60_sample();
        let cfg = FitConfig { ctrl: Some(ctrl), ..FitConfig::default() };
        (fit_offsets(&offsets, &cfg).expect("sample fits"), offsets)
    }

    pub(super) fn problem(ctrl: (usize, usize), mode: WeightMode, layout: WeightLayout, reg: f64) -> WeightProblem {
        let (fit, offsets) = sample_fit(ctrl);
        let opts = WeightOptions { mode, layout, regularization: reg, ..WeightOptions::default() };
        WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match")
    }

    /// Deterministic pseudo-random numbers in [-0.5, 0.5).
    pub(super) fn noise(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    fn points_and_params(fit: &FitOutcome, offsets: &Offsets) -> (Vec<Vec3>, Vec<(f64, f64)>) {
        let pts = offsets.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
        (pts, fit.params.iter().flatten().copied().collect())
    }

    #[test]
    fn fixed_mode_at_the_start_is_the_plain_approximations_parametric_rms() {
        let (fit, offsets) = sample_fit((6, 12));
        let (pts, params) = points_and_params(&fit, &offsets);
        let rms =
            (pts.iter().zip(&params).map(|(q, &(u, v))| (fit.surface.point(u, v) - *q).norm_squared()).sum::<f64>()
                / pts.len() as f64)
                .sqrt();
        let p =
            WeightProblem::from_fit(&fit, &offsets, WeightOptions { mode: WeightMode::Fixed, ..Default::default() })
                .expect("shapes match");
        let f = p.value(&p.start());
        // Same sums in a different order (A4.3 vs. the precomputed products): round-off only.
        assert!((f - rms).abs() <= 1e-12 * rms, "{f} vs {rms}");
        assert!(rms > 1e-3, "the 6 x 12 approximation must leave an error to optimise: {rms}");
    }

    #[test]
    fn resolved_mode_at_the_start_is_the_least_squares_optimum() {
        let (fit, offsets) = sample_fit((6, 12));
        let (pts, params) = points_and_params(&fit, &offsets);
        let resolved = WeightProblem::from_fit(&fit, &offsets, WeightOptions::default()).expect("ok");
        let fixed =
            WeightProblem::from_fit(&fit, &offsets, WeightOptions { mode: WeightMode::Fixed, ..Default::default() })
                .expect("ok");
        let (fr, ff) = (resolved.value(&resolved.start()), fixed.value(&fixed.start()));
        // One least-squares solve over all offsets beats the two-stage skinning at the same
        // parameters (and strictly: skinning interpolates the end sections).
        assert!(fr < ff, "resolved {fr} fixed {ff}");
        // Optimality: H^T e = 0, i.e. sum_k B_kc (S_k - Q_k) = 0 for every control point c,
        // measured with the kernel's own evaluation of the resolved surface.
        let s = resolved.surface(&resolved.start()).expect("regular");
        assert!(!s.is_rational());
        let (n_u, n_v) = resolved.ctrl();
        let mut normal = vec![Vec3::ZERO; n_u * n_v];
        let mut scale = 0.0;
        for (q, &(u, v)) in pts.iter().zip(&params) {
            let e = s.point(u, v) - *q;
            let (su, sv) = (s.knots_u().find_span(u), s.knots_v().find_span(v));
            let (mut bu, mut bv) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
            basis_funs(s.knots_u().as_slice(), su, u, s.degree_u(), &mut bu);
            basis_funs(s.knots_v().as_slice(), sv, v, s.degree_v(), &mut bv);
            for a in 0..=s.degree_u() {
                for b in 0..=s.degree_v() {
                    normal[(su - s.degree_u() + a) * n_v + sv - s.degree_v() + b] += e * (bu[a] * bv[b]);
                }
            }
            scale += q.norm();
        }
        let worst = normal.iter().map(|g| g.norm()).fold(0.0, f64::max);
        // The normal equations are solved to about cond(G) ~ 1e4 ulps of the data's size.
        assert!(worst <= 1e-10 * scale, "H^T e = {worst:e} against {scale:e}");
    }

    #[test]
    fn value_is_the_rms_of_the_kernels_rational_surface() {
        let (fit, offsets) = sample_fit((6, 12));
        let (pts, params) = points_and_params(&fit, &offsets);
        let mut seed = 5;
        for mode in [WeightMode::Fixed, WeightMode::Resolved] {
            for layout in [WeightLayout::Full, WeightLayout::RankOne] {
                let opts = WeightOptions { mode, layout, regularization: 0.0, ..Default::default() };
                let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("ok");
                let x: Vec<f64> = (0..p.dim()).map(|_| noise(&mut seed)).collect();
                let s = p.surface(&x).expect("regular");
                let w = p.weights(&x);
                assert_eq!(s.weights().len(), w.len());
                for (a, b) in s.weights().iter().zip(&w) {
                    assert!((a - b).abs() <= 1e-15 * b, "{a} {b}");
                }
                let rms =
                    (pts.iter().zip(&params).map(|(q, &(u, v))| (s.point(u, v) - *q).norm_squared()).sum::<f64>()
                        / pts.len() as f64)
                        .sqrt();
                let f = p.value(&x);
                // Homogeneous round trip and re-ordered sums: round-off.
                assert!((f - rms).abs() <= 1e-10 * rms, "{mode:?} {layout:?}: {f} vs {rms}");
                if mode == WeightMode::Fixed {
                    // The plain approximation's control points are kept.
                    for (a, b) in s.control_points().iter().zip(fit.surface.control_points()) {
                        assert!((*a - b).norm() <= 1e-12 * p.size());
                    }
                }
            }
        }
    }

    #[test]
    fn rank_one_weights_are_products_and_the_scale_gauge_changes_nothing() {
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::RankOne, 0.0);
        let (n_u, n_v) = p.ctrl();
        assert_eq!(p.dim(), n_u + n_v);
        let x: Vec<f64> = (0..p.dim()).map(|i| 0.1 * i as f64 - 0.4).collect();
        let w = p.weights(&x);
        for i in 0..n_u {
            for j in 0..n_v {
                let want = (x[i] + x[n_u + j]).exp();
                assert!((w[i * n_v + j] - want).abs() <= 1e-15 * want);
            }
        }
        // Each product stays within the bounds: the factors are boxed to half the log range.
        assert!((p.upper()[0] - 0.5 * 10f64.ln()).abs() < 1e-15);
        // (α + t, β - t) is the same weight grid; all weights times e^t the same surface.
        let f0 = p.value(&x);
        let shifted: Vec<f64> = x.iter().enumerate().map(|(i, &t)| if i < n_u { t + 0.3 } else { t - 0.3 }).collect();
        assert!((p.value(&shifted) - f0).abs() <= 1e-12 * f0);
        let full = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
        let f_start = full.value(&full.start());
        assert!((full.value(&vec![0.7; full.dim()]) - f_start).abs() <= 1e-12 * f_start);
    }

    /// Central differences of `g` at `x` in direction `i`, step `h`.
    fn central(g: &dyn Fn(&[f64]) -> Vec<f64>, x: &[f64], i: usize, h: f64) -> Vec<f64> {
        let (mut xp, mut xm) = (x.to_vec(), x.to_vec());
        xp[i] += h;
        xm[i] -= h;
        g(&xp).iter().zip(g(&xm)).map(|(a, b)| (a - b) / (2.0 * h)).collect()
    }

    #[test]
    fn jacobians_match_central_differences() {
        let mut seed = 17;
        // Without and with the fairness and smoothing terms (their rows join the residuals).
        for (layout, fair) in [
            (WeightLayout::Full, 0.0),
            (WeightLayout::RankOne, 0.0),
            (WeightLayout::Full, 0.05),
            (WeightLayout::RankOne, 0.05),
        ] {
            for mode in [WeightMode::Fixed, WeightMode::Resolved] {
                let p = problem((5, 8), mode, layout, 1e-3).with_fairness(fair, fair / 10.0).expect("usable");
                let x: Vec<f64> = (0..p.dim()).map(|_| 0.8 * noise(&mut seed)).collect();
                let r = |x: &[f64]| p.residuals(x).expect("regular");
                let kinds: &[JacobianKind] = if mode == WeightMode::Fixed {
                    &[JacobianKind::Kaufman]
                } else {
                    &[JacobianKind::Exact, JacobianKind::Kaufman]
                };
                for &kind in kinds {
                    let lin = p.residuals_and_jacobian(&x, kind).expect("regular");
                    assert_eq!(lin.residuals, r(&x));
                    let jmax = (0..lin.cols).map(|j| dot_norm(lin.column(j))).fold(0.0, f64::max);
                    for i in 0..p.dim() {
                        let fd = central(&r, &x, i, 1e-5);
                        let col = lin.column(i);
                        // Fixed mode (no projection) and the exact Golub-Pereyra Jacobian are
                        // the true derivative: central differences agree to O(h^2) + round-off
                        // / h, about 1e-8 of the largest column.
                        if mode == WeightMode::Fixed || kind == JacobianKind::Exact {
                            let err = col.iter().zip(&fd).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                            assert!(err <= 1e-7 * jmax, "{mode:?} {layout:?} {kind:?} col {i}: {err:e} vs {jmax:e}");
                        }
                        // Kaufman's Jacobian is not the derivative, but its gradient J^T r is.
                        let g_fd: f64 = fd.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                        let g: f64 = col.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                        let gscale = jmax * dot_norm(&lin.residuals);
                        assert!((g - g_fd).abs() <= 1e-7 * gscale, "{mode:?} {layout:?} {kind:?} grad {i}");
                    }
                }
            }
        }
    }

    fn dot_norm(v: &[f64]) -> f64 {
        v.iter().map(|t| t * t).sum::<f64>().sqrt()
    }

    #[test]
    fn parameter_columns_match_central_differences() {
        let mut seed = 23;
        for mode in [WeightMode::Fixed, WeightMode::Resolved] {
            let p = problem((5, 8), mode, WeightLayout::Full, 0.0);
            let x: Vec<f64> = (0..p.dim()).map(|_| 0.5 * noise(&mut seed)).collect();
            // Move the parameters off the knots (one-sided derivatives there) a little.
            let params: Vec<(f64, f64)> =
                p.params().iter().map(|&(u, v)| ((u * 0.98 + 0.01), (v * 0.98 + 0.01))).collect();
            for free in [ParamFreedom::U, ParamFreedom::USectionV, ParamFreedom::UV] {
                let lin = p.residuals_and_jacobian_with_params(&x, &params, free).expect("regular");
                let d = p.dim();
                assert_eq!(lin.cols, d + p.param_count(free));
                let jmax = (0..lin.cols).map(|j| dot_norm(lin.column(j))).fold(0.0, f64::max);
                let r_of = |t: &[f64]| -> Vec<f64> {
                    let pp = p.params_from_vars(&params, t, free);
                    p.with_params(&pp).expect("ok").residuals(&x).expect("regular")
                };
                let (t0, lo, hi) = p.param_vars(&params, free);
                assert_eq!(p.params_from_vars(&params, &t0, free), params);
                assert!(t0.iter().zip(&lo).zip(&hi).all(|((t, l), h)| l <= t && t <= h));
                // Every 7th unknown, and all section v's (the last 25 of USectionV).
                for j in (0..t0.len()).filter(|j| j % 7 == 0 || (free == ParamFreedom::USectionV && j + 25 >= t0.len()))
                {
                    let fd = central(&r_of, &t0, j, 1e-6);
                    let col = lin.column(d + j);
                    // Fixed mode: the true derivative; O(h^2) + round-off / h.
                    if mode == WeightMode::Fixed {
                        let err = col.iter().zip(&fd).map(|(a, b)| (a - b).abs()).fold(0.0, f64::max);
                        assert!(err <= 1e-6 * jmax, "{free:?} unknown {j}: {err:e} vs {jmax:e}");
                    }
                    let g_fd: f64 = fd.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                    let g: f64 = col.iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                    let gscale = jmax * dot_norm(&lin.residuals);
                    assert!((g - g_fd).abs() <= 1e-6 * gscale, "{mode:?} {free:?} unknown {j}: {g:e} vs {g_fd:e}");
                }
            }
        }
    }

    /// The same parameters with every `v` moved to 0 (all offsets on one edge of the domain).
    fn at_v0(params: &[(f64, f64)]) -> Vec<(f64, f64)> {
        params.iter().map(|&(u, _)| (u, 0.0)).collect()
    }

    #[test]
    fn the_anchor_keeps_undetermined_control_points_at_the_plain_fit() {
        let (fit, offsets) = sample_fit((6, 12));
        let (pts, params) = points_and_params(&fit, &offsets);
        // All offsets at v = 0: only the first column of control points (j = 0) is determined
        // by the data; the anchor holds the others at the plain approximation's.
        let p = WeightProblem::new(&fit.surface, &pts, &at_v0(&params), WeightOptions::default()).expect("ok");
        assert!(p.value(&p.start()).is_finite());
        let s = p.surface(&p.start()).expect("anchored system is regular");
        let size = p.size();
        for i in 0..s.n_u() {
            for j in 2..s.n_v() {
                // Far from the data the ridge is the whole equation: P = P_0 up to round-off of
                // the factorization (1e-9 of the model size is generous).
                let d = s.control_point(i, j).distance(fit.surface.control_point(i, j));
                assert!(d <= 1e-9 * size, "({i}, {j}) moved {d:e}");
            }
        }
        // Where the offsets determine the points, the anchor changes the fit by a relative
        // amount of order 1e-9: the value at the start matches the unanchored one.
        let anchored = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
        let plain =
            WeightProblem::new(&fit.surface, &pts, &params, WeightOptions { anchor: 0.0, ..Default::default() })
                .expect("ok");
        let (a, b) = (anchored.value(&anchored.start()), plain.value(&plain.start()));
        assert!((a - b).abs() <= 1e-6 * b, "{a} vs {b}");
    }

    #[test]
    fn singular_systems_give_infinity_not_nan() {
        let (fit, offsets) = sample_fit((6, 12));
        let (pts, params) = points_and_params(&fit, &offsets);
        // Every offset moved to v = 0: most control points have no offset in their support.
        let squashed = at_v0(&params);
        let no_anchor = WeightOptions { anchor: 0.0, ..Default::default() };
        let p = WeightProblem::new(&fit.surface, &pts, &squashed, no_anchor).expect("ok");
        let f = p.value(&p.start());
        assert!(f.is_infinite() && f > 0.0, "{f}");
        assert!(p.residuals(&p.start()).is_none());
        assert!(p.residuals_and_jacobian(&p.start(), JacobianKind::Exact).is_none());
        assert!(matches!(p.surface(&p.start()), Err(HullError::Fit { reason: NurbsError::SingularSystem { .. }, .. })));
        // Fixed mode has no system to solve: finite.
        let fixed = WeightProblem::new(
            &fit.surface,
            &pts,
            &squashed,
            WeightOptions { mode: WeightMode::Fixed, ..Default::default() },
        )
        .expect("ok");
        assert!(fixed.value(&fixed.start()).is_finite());
        // Bad variables are infeasible, not NaN.
        let good = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 1e-6);
        let mut x = good.start();
        x[3] = f64::NAN;
        assert_eq!(good.value(&x), f64::INFINITY);
        assert_eq!(good.value(&x[1..]), f64::INFINITY);
        x[3] = 800.0; // e^800 overflows
        assert_eq!(good.value(&x), f64::INFINITY);
        assert!(good.surface(&x[1..]).is_err());
    }

    #[test]
    fn bad_settings_are_errors() {
        let (fit, offsets) = sample_fit((6, 12));
        for (bounds, reg) in [((0.0, 10.0), 0.0), ((2.0, 10.0), 0.0), ((0.1, f64::INFINITY), 0.0), ((0.1, 10.0), -1.0)]
        {
            let o = WeightOptions { bounds, regularization: reg, ..Default::default() };
            assert!(matches!(WeightProblem::from_fit(&fit, &offsets, o), Err(HullError::Config(_))), "{bounds:?}");
        }
        let (pts, params) = points_and_params(&fit, &offsets);
        assert!(WeightProblem::new(&fit.surface, &pts[1..], &params, WeightOptions::default()).is_err());
        let mut nan = params.clone();
        nan[4].1 = f64::NAN;
        assert!(WeightProblem::new(&fit.surface, &pts, &nan, WeightOptions::default()).is_err());
        let p = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
        assert!(p.with_params(&nan).is_err());
        assert!(p.with_params(&params[1..]).is_err());
        let (_, other) = sample_fit((5, 8));
        assert!(WeightProblem::from_fit(
            &fit,
            &Offsets { sections: other.sections[1..].to_vec(), ..other },
            WeightOptions::default()
        )
        .is_err());
    }

    #[test]
    fn parallel_evaluation_is_bit_identical_to_sequential() {
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 1e-6);
        let mut seed = 99;
        let xs: Vec<Vec<f64>> = (0..64).map(|_| (0..p.dim()).map(|_| 2.0 * noise(&mut seed)).collect()).collect();
        let par = evaluate_all(&p, &xs);
        let seq: Vec<f64> = xs.iter().map(|x| p.value(x)).collect();
        assert_eq!(par, seq);
        assert!(seq.iter().all(|f| f.is_finite()));
        // And the value does not depend on what the thread evaluated before.
        assert_eq!(p.value(&xs[7]), seq[7]);
    }

    #[test]
    fn section_runs_assemble_the_same_system_as_single_offsets() {
        let mut seed = 41;
        // (6, 12) is factored in v-major order, (8, 5) in u-major: both run paths.
        for ctrl in [(6, 12), (8, 5)] {
            let (fit, offsets) = sample_fit(ctrl);
            let (pts, params) = points_and_params(&fit, &offsets);
            let grouped = WeightProblem::new(&fit.surface, &pts, &params, WeightOptions::default()).expect("ok");
            assert_eq!(grouped.table.runs.len(), offsets.sections.len());
            // Interleave the sections: no two consecutive offsets share v, every run is one
            // offset long.
            let n = pts.len();
            let order: Vec<usize> = (0..n).map(|i| (i * 8) % n + (i * 8) / n).collect();
            let mut sorted = order.clone();
            sorted.sort_unstable();
            assert_eq!(sorted, (0..n).collect::<Vec<_>>());
            let pts2: Vec<Vec3> = order.iter().map(|&k| pts[k]).collect();
            let par2: Vec<(f64, f64)> = order.iter().map(|&k| params[k]).collect();
            let single = WeightProblem::new(&fit.surface, &pts2, &par2, WeightOptions::default()).expect("ok");
            assert_eq!(single.table.runs.len(), n);
            for _ in 0..3 {
                let x: Vec<f64> = (0..grouped.dim()).map(|_| 1.5 * noise(&mut seed)).collect();
                let (a, b) = (grouped.value(&x), single.value(&x));
                // The same sums in another order: round-off amplified by cond(G) <~ 1e4.
                assert!((a - b).abs() <= 1e-11 * a, "{ctrl:?}: {a} vs {b}");
                let (sa, sb) = (grouped.surface(&x).expect("ok"), single.surface(&x).expect("ok"));
                for (pa, pb) in sa.control_points().iter().zip(sb.control_points()) {
                    assert!((*pa - pb).norm() <= 1e-9 * grouped.size());
                }
            }
        }
    }

    /// The cases the products' tests sweep: `(8, 5)` is assembled u-major, `(6, 12)` v-major;
    /// both layouts; fixed and re-solved control points, the latter also with the fairness term
    /// and the log-weight smoothing (a prior with off-diagonal entries).
    pub(super) fn product_sweep() -> Vec<((usize, usize), WeightLayout, WeightMode, f64)> {
        let mut cases = Vec::new();
        for ctrl in [(8, 5), (6, 12)] {
            for layout in [WeightLayout::Full, WeightLayout::RankOne] {
                for (mode, fair) in
                    [(WeightMode::Fixed, 0.0), (WeightMode::Resolved, 0.0), (WeightMode::Resolved, 0.05)]
                {
                    cases.push((ctrl, layout, mode, fair));
                }
            }
        }
        cases
    }

    #[test]
    fn normal_equations_match_the_dense_jacobians_products() {
        let mut seed = 29;
        // (8, 5) is assembled u-major, (6, 12) v-major; both layouts and modes.
        for (ctrl, layout, mode, fair) in product_sweep() {
            // The identity behind both needs the pure least-squares G = H^T H (+ the
            // fairness term): no anchor (with it, both are the same O(anchor)
            // approximation of the exact terms).
            let (fit, offsets) = sample_fit(ctrl);
            let opts = WeightOptions {
                mode,
                layout,
                regularization: 1e-3,
                anchor: 0.0,
                fair,
                weight_smoothing: fair / 10.0,
                ..Default::default()
            };
            let p = WeightProblem::from_fit(&fit, &offsets, opts).expect("shapes match");
            let x: Vec<f64> = (0..p.dim()).map(|_| 0.8 * noise(&mut seed)).collect();
            let lin = p.residuals_and_jacobian(&x, JacobianKind::Kaufman).expect("regular");
            let ne = p.normal_equations(&x).expect("regular");
            let d = p.dim();
            assert_eq!((ne.dim, ne.jtj.len(), ne.jtr.len()), (d, d * d, d));
            // The diagonal alone: the same sums, bit for bit.
            let diag = p.jtj_diagonal(&x).expect("regular");
            assert!((0..d).all(|i| diag[i] == ne.jtj[i * d + i]));
            let diag = (0..d).map(|i| dot_norm(lin.column(i)).powi(2)).fold(0.0, f64::max);
            let gscale = diag.sqrt() * dot_norm(&lin.residuals);
            let mut worst = (0.0f64, 0.0f64);
            for i in 0..d {
                for j in 0..d {
                    let dense: f64 = lin.column(i).iter().zip(lin.column(j)).map(|(a, b)| a * b).sum();
                    assert_eq!(ne.jtj[i * d + j], ne.jtj[j * d + i], "symmetric");
                    worst.0 = worst.0.max((ne.jtj[i * d + j] - dense).abs() / diag);
                }
                let g: f64 = lin.column(i).iter().zip(&lin.residuals).map(|(a, b)| a * b).sum();
                worst.1 = worst.1.max((ne.jtr[i] - g).abs() / gscale);
            }
            // The same sums in exact arithmetic; A^T A - W^T W cancels the part of the
            // fixed-point derivative that the re-solved control points absorb, which
            // costs a few digits: measured up to 4e-14 of the largest diagonal entry (1e-15 for
            // the gradient, whose projected term vanishes at the least-squares solution).
            assert!(worst.0 < 1e-12 && worst.1 < 1e-12, "{ctrl:?} {layout:?} {mode:?}: {worst:?}");
        }
        // An infeasible point gives None, like the value's infinity.
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
        assert!(p.normal_equations(&[f64::NAN; 72]).is_none());
        assert!(p.normal_equations(&[0.0; 3]).is_none());
    }

    #[test]
    fn band_order_is_the_cheaper_one() {
        // 6 x 12 bicubic: u-major would give 3 * 12 + 3 = 39, v-major 3 * 6 + 3 = 21.
        let p = problem((6, 12), WeightMode::Resolved, WeightLayout::Full, 0.0);
        assert_eq!(p.bandwidth(), 21);
        let p = problem((8, 5), WeightMode::Resolved, WeightLayout::Full, 0.0);
        assert_eq!(p.bandwidth(), 3 * 5 + 3);
    }

    #[test]
    fn the_search_box_scales_with_kappa_inside_the_bounds() {
        let (fit, offsets) = sample_fit((6, 12));
        let make = |k: Option<f64>| {
            let o = WeightOptions { search_scale: k, ..WeightOptions::default() };
            WeightProblem::from_fit(&fit, &offsets, o).expect("ok")
        };
        let whole = make(None).search_box();
        assert_eq!(whole, (make(None).lower().to_vec(), make(None).upper().to_vec()));
        let (lo1, hi1) = make(Some(1.0)).search_box();
        let (lo2, hi2) = make(Some(2.0)).search_box();
        let p = make(Some(1.0));
        let (x0, f0, d) = (p.start(), p.value(&p.start()), p.dim());
        let ne = p.normal_equations(&x0).expect("start is regular");
        for i in 0..d {
            assert!(p.lower()[i] <= lo1[i] && lo1[i] < x0[i] && x0[i] < hi1[i] && hi1[i] <= p.upper()[i], "{i}");
            // Unclipped, the half-width is f(0) / (sqrt(d) |J_i|) exactly, and doubles with κ.
            let h = f0 / (ne.jtj[i * d + i].sqrt() * (d as f64).sqrt());
            if h < p.upper()[i] / 2.0 {
                assert_near!(hi1[i], h, 1e-15 * h);
                assert_near!(hi2[i] - lo2[i], 2.0 * (hi1[i] - lo1[i]), 1e-14 * h);
            }
        }
        // On this sample the useful moves are far smaller than the bounds for some weights.
        assert!(hi1.iter().any(|&h| h < 0.1 * p.upper()[0]));
        let bad = WeightOptions { search_scale: Some(0.0), ..WeightOptions::default() };
        assert!(matches!(WeightProblem::from_fit(&fit, &offsets, bad), Err(HullError::Config(_))));
    }

    /// The Wigley table's plain approximation is a sharp minimum along most log-weight
    /// directions: GSA over the whole bounds (`search_scale: None`) ends exactly at the start,
    /// while in the sensitivity box it goes below it with the same budget and seed.
    #[test]
    fn gsa_moves_off_a_sharp_start_only_in_the_sensitivity_box() {
        use crate::optimize::{gsa, quiet, GsaOptions};
        let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/wigley_offsets.csv");
        let offsets = crate::read_offsets(std::path::Path::new(path), crate::Units::Metre).expect("wigley table reads");
        let fit = fit_offsets(&offsets, &FitConfig::default()).expect("fits");
        let opts = GsaOptions { iterations: 60, agents: 20, ..GsaOptions::default() };
        let run = |k: Option<f64>| {
            let o = WeightOptions { search_scale: k, ..WeightOptions::default() };
            let p = WeightProblem::from_fit(&fit, &offsets, o).expect("ok");
            let f0 = p.value(&p.start());
            (quiet(|c| gsa::run(&p, &opts, 1, c)).value, f0)
        };
        let (whole, f0) = run(None);
        let (boxed, _) = run(Some(10.0));
        assert_eq!(whole, f0);
        assert!(boxed < 0.99 * f0, "{boxed} vs start {f0}");
    }
}
