//! Closest-point projection onto NURBS curves and surfaces (The NURBS Book 6.1).
//!
//! The foot point of `P` on a surface minimises `f(u,v) = |S(u,v) - P|^2 / 2`; at an interior
//! minimum the residual `r = S - P` is normal to the surface (eq. 6.6):
//! `g(u,v) = (S_u . r, S_v . r) = 0`. Newton's method on `g` (eq. 6.7-6.8) solves
//! `J d = -g` with
//! `J = [[|S_u|^2 + r . S_uu, S_u . S_v + r . S_uv], [S_u . S_v + r . S_uv, |S_v|^2 + r . S_vv]]`.
//!
//! Newton only converges locally, so the projectors first sample the surface on a grid adapted
//! to the knot spans (a few samples per span in each direction, more where it bends) and start
//! Newton from the best few places where the samples show a local minimum: nodes nearer than
//! their neighbours, cells where the gradient `g` changes sign, constrained minima on edges and
//! corners (see [`SurfaceProjector`]). Each knot span carries a bounding sphere of the surface
//! over it, which lets a query skip spans that cannot hold a closer point. The result is the
//! best of these local minima: the global one unless the surface hides a minimum between
//! samples.
//!
//! The iteration is made robust for any input:
//! - **clamping and boundaries**: iterates are clamped to the domain (as the Book does for open
//!   surfaces); a parameter sitting on a bound whose gradient points out of the domain is fixed
//!   (the Karush-Kuhn-Tucker condition of the bound) and Newton goes on in one dimension along
//!   that boundary curve;
//! - **singular or indefinite Jacobians** (a collapsed stem or stern edge where
//!   `S_u x S_v = 0`, or a saddle of the distance): the step falls back to Gauss-Newton
//!   `[[|S_u|^2, S_u . S_v], [S_u . S_v, |S_v|^2]] + mu I`, positive definite, so always a descent
//!   direction;
//! - **collapsed edges** (all of an edge one point, as a hull's stem): every parameter along
//!   the edge gives the same point but its own direction into the surface; Newton leaves such
//!   an edge in the steepest of them, and stops there only if none descends;
//! - **monotone decrease**: a step that does not reduce `|S - P|` is halved (backtracking);
//!   within the rounding noise of `|S - P|^2` a step that reduces the tangential residual is
//!   taken instead, so the foot converges to `eps1` even where the distance is flat.
//!
//! Convergence criteria of the Book, with `eps1 = tolerance * model size` (the diagonal of the
//! control net's bounding box):
//! - point coincidence `|S - P| <= eps1`;
//! - zero cosine `|S_u . r| / (|S_u| |r|) <= eps2` (and the same for `S_v`), with
//!   `eps2 = eps1 / |r|`, i.e. the tangential part of the residual is below `eps1`; a direction
//!   fixed at a bound by the rule above counts as satisfied;
//! - step size `|(u_{i+1} - u_i) S_u + (v_{i+1} - v_i) S_v| <= eps1`.

use crate::basis::{ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::tolerance::PROJECTION_REL;
use crate::{KnotVector, NurbsCurve, NurbsSurface, SurfaceDerivatives, Vec3};

/// Settings of curve and surface projection.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ProjectionOptions {
    /// Sampling intervals per knot span in each parameter direction. A surface projector uses
    /// `max(grid, degree, 1)`, more in spans where an iso-line's tangent turns by more than
    /// 0.3 rad per interval (up to 64), and three extra rows graded towards a collapsed edge;
    /// a bicubic surface of 7 x 5 gentle spans with `grid = 4` is sampled at `29 x 21` points.
    /// Curves, cheaper per sample, use four times as many.
    pub grid: usize,
    /// How many distinct local minima are refined by Newton, best sampled candidates first
    /// (a run ending at a foot already found does not count; all runs are bounded by three
    /// times this); more guard against local minima on strongly curved shapes, at a cost.
    pub candidates: usize,
    /// Newton iterations per start point (3 to 6 typically; slow valleys next to a collapsed
    /// edge can take a few dozen).
    pub max_iterations: usize,
    /// Geometric tolerance `eps1` relative to the model size (the diagonal of the control net's
    /// bounding box). Non-finite or negative values are taken as 0 (iterate to the limit).
    pub tolerance: f64,
}

impl Default for ProjectionOptions {
    fn default() -> Self {
        ProjectionOptions { grid: 4, candidates: 4, max_iterations: 60, tolerance: PROJECTION_REL }
    }
}

/// The closest point of a surface to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SurfaceProjection {
    pub u: f64,
    pub v: f64,
    /// `S(u, v)`.
    pub point: Vec3,
    /// `|S(u, v) - q|`.
    pub distance: f64,
    /// Newton iterations of the winning start point.
    pub iterations: usize,
    /// True if a convergence criterion was met (not merely the iteration limit).
    pub converged: bool,
}

/// The closest point of a curve to a query point.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurveProjection {
    pub u: f64,
    /// `C(u)`.
    pub point: Vec3,
    /// `|C(u) - q|`.
    pub distance: f64,
    /// Newton iterations of the winning start point.
    pub iterations: usize,
    /// True if a convergence criterion was met (not merely the iteration limit).
    pub converged: bool,
}

/// Distinct knot values bounding the non-empty spans of `k`, from domain start to end.
fn breaks(k: &KnotVector) -> Vec<f64> {
    let (a, b) = k.domain();
    let mut out = vec![a];
    out.extend(k.interior_breaks().into_iter().map(|(t, _)| t));
    out.push(b);
    out
}

/// Sample parameters: `g` equal intervals in every span of `br`, `g * spans + 1` values.
fn sample_params(br: &[f64], g: usize) -> Vec<f64> {
    let mut out = Vec::with_capacity(g * (br.len() - 1) + 1);
    for w in br.windows(2) {
        for k in 0..g {
            out.push(w[0] + (w[1] - w[0]) * k as f64 / g as f64);
        }
    }
    out.push(br[br.len() - 1]);
    out
}

/// Sample parameters with `counts[i]` equal intervals in span `i` of `br`, plus, when `grade`
/// says so for the first (last) end, [`GRADED_LEVELS`] extra samples halving the first (last)
/// interval towards that end. Returns the parameters, each span's first sample index and each
/// span's final interval count.
fn sample_params_by_span(br: &[f64], counts: &[usize], grade: (bool, bool)) -> (Vec<f64>, Vec<usize>, Vec<usize>) {
    let mut out = Vec::with_capacity(counts.iter().sum::<usize>() + 2 * GRADED_LEVELS + 1);
    let mut starts = Vec::with_capacity(counts.len());
    let mut finals = Vec::with_capacity(counts.len());
    let last = counts.len() - 1;
    for (i, (w, &g)) in br.windows(2).zip(counts).enumerate() {
        starts.push(out.len());
        let h = (w[1] - w[0]) / g as f64;
        let mut n = g;
        for k in 0..g {
            out.push(w[0] + h * k as f64);
            if k == 0 && i == 0 && grade.0 {
                out.extend((1..=GRADED_LEVELS).rev().map(|l| w[0] + h / (1u32 << l) as f64));
                n += GRADED_LEVELS;
            }
        }
        if i == last && grade.1 {
            out.extend((1..=GRADED_LEVELS).map(|l| w[1] - h / (1u32 << l) as f64));
            n += GRADED_LEVELS;
        }
        finals.push(n);
    }
    out.push(br[br.len() - 1]);
    (out, starts, finals)
}

/// Extra sample rows graded towards a collapsed edge (at 1/2, 1/4, 1/8 of the first interval):
/// near a stem the parameterization is polar-like and the distance varies fastest there.
const GRADED_LEVELS: usize = 3;

/// Largest tangent turning per sampling interval, in radians: spans whose tangent turns more
/// get more intervals, so a sharp bend cannot hide a second minimum between two samples.
const TURN_PER_INTERVAL: f64 = 0.3;
/// Upper limit of sampling intervals per knot span.
const MAX_INTERVALS: usize = 64;
/// Sub-steps per span used to measure the turning.
const TURN_STEPS: usize = 16;

/// Intervals per span of `br`: at least `base`, and enough that the tangent `tangent(t)` turns
/// by at most [`TURN_PER_INTERVAL`] per interval (measured at [`turning_params`]).
fn intervals_by_turning(br: &[f64], base: usize, tangent: impl Fn(f64) -> Vec3) -> Vec<usize> {
    let ts: Vec<Vec3> = turning_params(br).into_iter().map(tangent).collect();
    ts.chunks(TURN_STEPS + 1).map(|span| intervals_for_turning(span, base)).collect()
}

/// The parameters at which a span's turning is measured: [`TURN_STEPS`] steps per span of
/// `br`, both ends included, span `k`'s at `k * (TURN_STEPS + 1)..(k + 1) * (TURN_STEPS + 1)`.
fn turning_params(br: &[f64]) -> Vec<f64> {
    br.windows(2)
        .flat_map(|w| {
            (0..=TURN_STEPS).map(move |k| {
                if k == TURN_STEPS {
                    w[1]
                } else {
                    w[0] + (w[1] - w[0]) * k as f64 / TURN_STEPS as f64
                }
            })
        })
        .collect()
}

/// Intervals for one span whose tangents at [`turning_params`] are `ts`: at least `base`, and
/// enough that the tangent turns by at most [`TURN_PER_INTERVAL`] per interval. Tangents
/// shorter than 1e-6 of the longest in the span (a collapsed edge) have no direction and are
/// skipped.
fn intervals_for_turning(ts: &[Vec3], base: usize) -> usize {
    let longest = ts.iter().map(|t| t.norm()).fold(0.0, f64::max);
    let mut total = 0.0;
    let mut prev: Option<Vec3> = None;
    for &t in ts {
        let has_direction = t.norm() > 1e-6 * longest; // false for NaN too
        if !has_direction {
            continue;
        }
        if let Some(p) = prev {
            total += p.cross(t).norm().atan2(p.dot(t));
        }
        prev = Some(t);
    }
    let need = (total / TURN_PER_INTERVAL).ceil();
    let need = if need.is_finite() { need as usize } else { base };
    need.clamp(base, MAX_INTERVALS.max(base))
}

/// `eps1` of the options for a model whose control net has bounding-box diagonal `size`.
fn abs_tolerance(opts: &ProjectionOptions, size: f64) -> f64 {
    let t = if opts.tolerance.is_finite() && opts.tolerance > 0.0 { opts.tolerance } else { 0.0 };
    let size = if size.is_finite() { size } else { 0.0 };
    t * size
}

/// True if parameter `t` sits on a bound of `[a, b]` and the gradient `g = df/dt` points out
/// of the domain (so the constrained minimum keeps `t` there).
#[inline]
fn held_at_bound(t: f64, a: f64, b: f64, g: f64) -> bool {
    (t <= a && g >= 0.0) || (t >= b && g <= 0.0)
}

/// One-dimensional Newton step `-g / h`, or the Gauss-Newton step `-g / |S'|^2` when the second
/// derivative `h` of `f` is not safely positive.
#[inline]
fn step_1d(h: f64, gg: f64, g: f64) -> f64 {
    if h > 1e-10 * gg && h > 0.0 {
        -g / h
    } else if gg > 0.0 {
        -g / gg
    } else {
        0.0
    }
}

/// Relative pivot below which the 2x2 Newton matrix counts as singular (condition ~1e10).
const SINGULAR_REL: f64 = 1e-10;
/// Levenberg-Marquardt term of the Gauss-Newton fallback, relative to `|S_u|^2 + |S_v|^2`.
const GN_DAMPING: f64 = 1e-9;
/// Step halvings tried before a step is given up.
const MAX_HALVINGS: usize = 64;

/// The Newton (or safeguarded) step `(du, dv)` at a surface point, given which parameters are
/// held at a bound.
fn surface_step(d: &SurfaceDerivatives, r: Vec3, gu: f64, gv: f64, hold_u: bool, hold_v: bool) -> (f64, f64) {
    let (uu, uv, vv) = (d.su.norm_squared(), d.su.dot(d.sv), d.sv.norm_squared());
    let j11 = uu + r.dot(d.suu);
    let j12 = uv + r.dot(d.suv);
    let j22 = vv + r.dot(d.svv);
    match (hold_u, hold_v) {
        (false, false) => {
            let det = j11 * j22 - j12 * j12;
            if j11 > 0.0 && j22 > 0.0 && det > SINGULAR_REL * j11 * j22 {
                ((-gu * j22 + gv * j12) / det, (-gv * j11 + gu * j12) / det)
            } else {
                // Gauss-Newton with a small Levenberg-Marquardt term: positive definite
                // (det >= mu (uu + vv) + mu^2 by Cauchy-Schwarz) unless S_u = S_v = 0.
                let mu = GN_DAMPING * (uu + vv);
                let (g11, g22) = (uu + mu, vv + mu);
                let det = g11 * g22 - uv * uv;
                if det > 0.0 && det.is_finite() {
                    ((-gu * g22 + gv * uv) / det, (-gv * g11 + gu * uv) / det)
                } else {
                    (0.0, 0.0)
                }
            }
        }
        (true, false) => (0.0, step_1d(j22, vv, gv)),
        (false, true) => (step_1d(j11, uu, gu), 0.0),
        (true, true) => (0.0, 0.0),
    }
}

/// A bounding sphere of the surface over one knot span, and where its samples start in the grid.
#[derive(Clone, Copy, Debug)]
struct Block {
    /// A grid node near the middle of the span (a point of the surface).
    center: Vec3,
    /// Every point of the surface over the span lies within this distance of `center`.
    radius: f64,
    /// First node row (u) and column (v) of the span, and its intervals in u and v: it spans
    /// `na + 1` by `nb + 1` nodes.
    a0: usize,
    b0: usize,
    na: usize,
    nb: usize,
}

/// A grid node: the point and its first partial derivatives.
#[derive(Clone, Copy, Debug)]
struct Sample {
    p: Vec3,
    su: Vec3,
    sv: Vec3,
}

/// A start point for Newton where the samples suggest a local minimum.
#[derive(Clone, Copy, Debug)]
struct Seed {
    /// Smallest sampled squared distance near the seed (the ranking key).
    d2: f64,
    u: f64,
    v: f64,
    /// The parameter box `[u0, u1, v0, v1]` the seed stands for: a start is skipped when an
    /// earlier Newton run already ended inside its box.
    range: [f64; 4],
    /// Lower bound of the distance over the span the seed was found in.
    lower: f64,
}

impl Seed {
    fn covers(&self, u: f64, v: f64) -> bool {
        let [u0, u1, v0, v1] = self.range;
        (u0..=u1).contains(&u) && (v0..=v1).contains(&v)
    }

    /// A seed on a domain edge (its box is flat in u or v) stands for a constrained minimum.
    fn on_edge(&self) -> bool {
        self.range[0] == self.range[1] || self.range[2] == self.range[3]
    }

    /// Seeds of one kind whose boxes touch lie in one basin as far as the samples can tell.
    fn touches(&self, o: &Seed) -> bool {
        self.on_edge() == o.on_edge()
            && self.range[0] <= o.range[1]
            && o.range[0] <= self.range[1]
            && self.range[2] <= o.range[3]
            && o.range[2] <= self.range[3]
    }
}

/// Group seeds into clusters of touching boxes (union-find); returns each seed's cluster root.
fn cluster_seeds(seeds: &[Seed], parent: &mut Vec<usize>) {
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    parent.clear();
    parent.extend(0..seeds.len());
    for i in 0..seeds.len() {
        for j in i + 1..seeds.len() {
            if seeds[i].touches(&seeds[j]) {
                let (ri, rj) = (root(parent, i), root(parent, j));
                parent[ri.max(rj)] = ri.min(rj);
            }
        }
    }
    for i in 0..seeds.len() {
        let r = root(parent, i);
        parent[i] = r;
    }
}

/// Reusable per-query buffers.
#[derive(Default)]
struct Scratch {
    order: Vec<(f64, usize)>,
    /// Per node of the span being scanned: `(|S - q|^2, S_u . (S - q), S_v . (S - q))`.
    vals: Vec<[f64; 3]>,
    seeds: Vec<Seed>,
    /// `(u, v, S(u, v))` of the Newton runs so far.
    feet: Vec<(f64, f64, Vec3)>,
    /// Cluster root of each seed, and whether a cluster has been refined.
    cluster: Vec<usize>,
    cluster_done: Vec<bool>,
}

/// Projects points onto one surface; build it once, then project many points.
///
/// Construction samples the surface (point and first derivatives) on a grid adapted to the
/// knot spans (see [`ProjectionOptions::grid`]) and bounds each span by a sphere. A query tests
/// the spheres, scans the samples of the spans that may hold a closer point, and starts Newton
/// from the best few places where the samples suggest a local minimum (touching candidates
/// count once):
/// - nodes nearer than their 8 neighbours (or than their 2 neighbours along a domain edge);
/// - grid cells where the gradient `(S_u . r, S_v . r)` changes sign from negative to positive
///   across the cell in both directions (a minimum between samples, caught even when no node
///   shows it: the Poincare-Miranda pattern);
/// - edge segments with such a sign change along the edge while the gradient points out of the
///   domain, and corners where both components point out (constrained minima).
#[derive(Clone, Debug)]
pub struct SurfaceProjector<'a> {
    surface: &'a NurbsSurface,
    options: ProjectionOptions,
    eps: f64,
    us: Vec<f64>,
    vs: Vec<f64>,
    /// Samples at `(us[a], vs[b])`, index `a * vs.len() + b`.
    samples: Vec<Sample>,
    blocks: Vec<Block>,
    /// Largest coordinate magnitude of the control net (scale of evaluation round-off).
    magnitude: f64,
    /// Edges `u = u0`, `u = u1`, `v = v0`, `v = v1` collapsed to a point (within `eps`).
    collapsed: [bool; 4],
}

impl<'a> SurfaceProjector<'a> {
    /// Sample `surface` and prepare the span bounds.
    pub fn new(surface: &'a NurbsSurface, options: ProjectionOptions) -> Self {
        let base_u = options.grid.max(surface.degree_u()).max(1);
        let base_v = options.grid.max(surface.degree_v()).max(1);
        let (bu, bv) = (breaks(surface.knots_u()), breaks(surface.knots_v()));
        // Intervals per span: the base count, more where some iso-line bends sharply.
        let (lines_u, lines_v) = (sample_params(&bu, base_u), sample_params(&bv, base_v));
        // The tangents along each line sampled on one grid per direction.
        let per_span = TURN_STEPS + 1;
        let tu = turning_params(&bu);
        let along_u = surface.first_derivatives_grid(&tu, &lines_v);
        let counts_u: Vec<usize> = (0..bu.len() - 1)
            .map(|k| {
                along_u
                    .chunks(tu.len())
                    .map(|line| {
                        let ts: Vec<Vec3> = line[k * per_span..(k + 1) * per_span].iter().map(|d| d.su).collect();
                        intervals_for_turning(&ts, base_u)
                    })
                    .fold(base_u, usize::max)
            })
            .collect();
        let tv = turning_params(&bv);
        let along_v = surface.first_derivatives_grid(&lines_u, &tv);
        let nl = lines_u.len();
        let counts_v: Vec<usize> = (0..bv.len() - 1)
            .map(|k| {
                (0..nl)
                    .map(|i| {
                        let ts: Vec<Vec3> =
                            (k * per_span..(k + 1) * per_span).map(|j| along_v[j * nl + i].sv).collect();
                        intervals_for_turning(&ts, base_v)
                    })
                    .fold(base_v, usize::max)
            })
            .collect();
        // Collapsed edges, from samples along them; the grid is graded towards them.
        let (lo, hi) = surface.control_bounds();
        let eps = abs_tolerance(&options, (hi - lo).norm());
        let magnitude = lo.norm().max(hi.norm());
        let same = eps.max(64.0 * f64::EPSILON * magnitude);
        let ((ua, ub), (va, vb)) = (surface.domain_u(), surface.domain_v());
        let collapsed_at = |pts: Vec<Vec3>| pts.iter().all(|&p| (p - pts[0]).norm() <= same);
        let collapsed = [
            collapsed_at(lines_v.iter().map(|&v| surface.point(ua, v)).collect()),
            collapsed_at(lines_v.iter().map(|&v| surface.point(ub, v)).collect()),
            collapsed_at(lines_u.iter().map(|&u| surface.point(u, va)).collect()),
            collapsed_at(lines_u.iter().map(|&u| surface.point(u, vb)).collect()),
        ];
        let (us, starts_u, counts_u) = sample_params_by_span(&bu, &counts_u, (collapsed[0], collapsed[1]));
        let (vs, starts_v, counts_v) = sample_params_by_span(&bv, &counts_v, (collapsed[2], collapsed[3]));
        let (nu, nv) = (us.len(), vs.len());
        // u-major samples from the v-major grid.
        let grid = surface.first_derivatives_grid(&us, &vs);
        let mut samples = Vec::with_capacity(nu * nv);
        for i in 0..nu {
            for j in 0..nv {
                let d = &grid[j * nu + i];
                samples.push(Sample { p: d.point, su: d.su, sv: d.sv });
            }
        }
        // Each span's fine grid (twice its sampling) of points, all on one grid: span i's
        // from index fine_u.1[i] along u.
        let (fine_u, fine_v) = (fine_params(&bu, &counts_u), fine_params(&bv, &counts_v));
        let fine = surface.points_grid(&fine_u.0, &fine_v.0);
        let stride = fine_u.0.len();
        let mut blocks = Vec::with_capacity((bu.len() - 1) * (bv.len() - 1));
        for i in 0..bu.len() - 1 {
            for j in 0..bv.len() - 1 {
                let (a0, b0, na, nb) = (starts_u[i], starts_v[j], counts_u[i], counts_v[j]);
                let center = samples[(a0 + na / 2) * nv + b0 + nb / 2].p;
                let (fa, fb) = (fine_u.1[i], fine_v.1[j]);
                let at = |a: usize, b: usize| fine[(fb + b) * stride + fa + a];
                let radius = span_radius(at, center, 2 * na, 2 * nb) + eps;
                blocks.push(Block { center, radius, a0, b0, na, nb });
            }
        }
        SurfaceProjector { surface, options, eps, us, vs, samples, blocks, magnitude, collapsed }
    }

    /// The surface projected onto.
    pub fn surface(&self) -> &'a NurbsSurface {
        self.surface
    }

    /// The options in use.
    pub fn options(&self) -> &ProjectionOptions {
        &self.options
    }

    /// The closest point of the surface to `q`.
    ///
    /// For a finite `q` every field of the result is finite. A non-finite `q` gives
    /// `converged = false` at the domain's first corner, with a non-finite distance.
    pub fn project(&self, q: Vec3) -> SurfaceProjection {
        self.project_with(q, &mut Scratch::default())
    }

    /// The closest point of the surface to `q`, knowing that `S(hint)` is near it (the
    /// parameters a fit assigned to a data point, say): the global search of
    /// [`SurfaceProjector::project`] plus a Newton run from `hint`, the better of the two. The
    /// result is never farther than `S(hint)`.
    pub fn project_near(&self, q: Vec3, hint: (f64, f64)) -> SurfaceProjection {
        let global = self.project(q);
        let (u, v) = (self.surface.knots_u().clamp(hint.0), self.surface.knots_v().clamp(hint.1));
        if !(q.is_finite() && u.is_finite() && v.is_finite()) {
            return global;
        }
        let local = self.refine(q, u, v);
        if local.distance < global.distance {
            local
        } else {
            global
        }
    }

    /// [`SurfaceProjector::project`] for every point of `qs`, reusing buffers.
    pub fn project_many(&self, qs: &[Vec3]) -> Vec<SurfaceProjection> {
        let mut scratch = Scratch::default();
        qs.iter().map(|&q| self.project_with(q, &mut scratch)).collect()
    }

    fn project_with(&self, q: Vec3, scratch: &mut Scratch) -> SurfaceProjection {
        let (u0, v0) = (self.us[0], self.vs[0]);
        if !q.is_finite() {
            let point = self.surface.point(u0, v0);
            return SurfaceProjection {
                u: u0,
                v: v0,
                point,
                distance: (point - q).norm(),
                iterations: 0,
                converged: false,
            };
        }
        // 1. Sphere bounds of the spans; the nearest span centre bounds the answer from above.
        let mut upper = f64::INFINITY;
        for b in &self.blocks {
            upper = upper.min((q - b.center).norm());
        }
        scratch.order.clear();
        for (k, b) in self.blocks.iter().enumerate() {
            let lower = (q - b.center).norm() - b.radius;
            if lower <= upper {
                scratch.order.push((lower, k));
            }
        }
        scratch.order.sort_unstable_by(|x, y| x.0.total_cmp(&y.0));
        // 2. Scan the spans that may hold a closer point, nearest first; collect seeds.
        let mut best2 = upper * upper;
        scratch.seeds.clear();
        for &(lower, k) in &scratch.order {
            if lower > 0.0 && lower * lower > best2 {
                break; // sorted: no later span can hold a closer point either
            }
            let b = self.blocks[k];
            self.scan_block(q, &b, lower, &mut scratch.vals, &mut scratch.seeds);
            best2 = scratch.vals.iter().fold(best2, |m, x| m.min(x[0]));
        }
        scratch.seeds.sort_unstable_by(|x, y| x.d2.total_cmp(&y.d2));
        // 3. Newton from the best few, skipping spans that cannot beat the best so far and
        //    seeds whose box already holds a foot found.
        let mut best: Option<SurfaceProjection> = None;
        let mut runs = 0;
        let mut done_edges = 0u8;
        scratch.feet.clear();
        cluster_seeds(&scratch.seeds, &mut scratch.cluster);
        scratch.cluster_done.clear();
        scratch.cluster_done.resize(scratch.seeds.len(), false);
        // `candidates` distinct local minima at most; a run that ends at a foot already found
        // does not count, but all runs together are bounded by three times that.
        let wanted = self.options.candidates.max(1);
        let mut distinct = 0;
        for (k, seed) in scratch.seeds.iter().enumerate() {
            if distinct >= wanted || runs >= 3 * wanted {
                break;
            }
            // One start per cluster of touching seeds (the best, as they are sorted).
            if scratch.cluster_done[scratch.cluster[k]] {
                continue;
            }
            if matches!(&best, Some(bp) if seed.lower >= bp.distance) {
                continue;
            }
            if scratch.feet.iter().any(|&(u, v, _)| seed.covers(u, v)) {
                continue;
            }
            // All starts on one collapsed edge are one point, and Newton tries every direction
            // out of it: one run per such edge.
            let edge = self.collapsed_edge_of(seed.u, seed.v);
            if edge & done_edges != 0 {
                continue;
            }
            done_edges |= edge;
            scratch.cluster_done[scratch.cluster[k]] = true;
            runs += 1;
            let res = self.refine(q, seed.u, seed.v);
            let again =
                scratch.feet.iter().any(|&(_, _, p)| (p - res.point).norm() <= self.eps.max(1e-9 * res.distance));
            if !again {
                distinct += 1;
            }
            scratch.feet.push((res.u, res.v, res.point));
            if !matches!(&best, Some(bp) if bp.distance <= res.distance) {
                best = Some(res);
            }
        }
        best.unwrap_or_else(|| self.refine(q, u0, v0))
    }

    /// Sample one span against `q` into `vals` and push its seeds.
    fn scan_block(&self, q: Vec3, b: &Block, lower: f64, vals: &mut Vec<[f64; 3]>, seeds: &mut Vec<Seed>) {
        let (nu, nv) = (self.us.len(), self.vs.len());
        let (ru, rv) = (b.na + 1, b.nb + 1);
        vals.clear();
        for a in b.a0..b.a0 + ru {
            for smp in &self.samples[a * nv + b.b0..][..rv] {
                let r = smp.p - q;
                vals.push([r.norm_squared(), smp.su.dot(r), smp.sv.dot(r)]);
            }
        }
        let at = |la: usize, lb: usize| vals[la * rv + lb];
        let (us, vs) = (&self.us, &self.vs);
        let box_of = |a0: usize, a1: usize, b0: usize, b1: usize| [us[a0], us[a1], vs[b0], vs[b1]];
        // Nodes: discrete local minima, in 2-D or along an edge, and corners held by both bounds.
        for la in 0..ru {
            for lb in 0..rv {
                let [d2, gu, gv] = at(la, lb);
                let (a, bb) = (b.a0 + la, b.b0 + lb);
                let node = a * nv + bb;
                let corner_held = (a == 0 || a + 1 == nu)
                    && (bb == 0 || bb + 1 == nv)
                    && (if a == 0 { gu >= 0.0 } else { gu <= 0.0 })
                    && (if bb == 0 { gv >= 0.0 } else { gv <= 0.0 });
                // A seed for a constrained minimum stands for its corner or edge only, not for
                // the cells beside it, whose interior minima are others.
                if corner_held {
                    seeds.push(Seed { d2, u: us[a], v: vs[bb], range: box_of(a, a, bb, bb), lower });
                } else if self.is_local_min(q, vals, b, la, lb, d2, node) {
                    let (a0, a1, b0, b1) =
                        (a.saturating_sub(1), (a + 1).min(nu - 1), bb.saturating_sub(1), (bb + 1).min(nv - 1));
                    seeds.push(Seed { d2, u: us[a], v: vs[bb], range: box_of(a0, a1, b0, b1), lower });
                } else if self.is_edge_local_min(q, a, bb, d2, node) {
                    let (a0, a1) = if a == 0 || a + 1 == nu { (a, a) } else { (a - 1, a + 1) };
                    let (b0, b1) = if bb == 0 || bb + 1 == nv { (bb, bb) } else { (bb - 1, bb + 1) };
                    seeds.push(Seed { d2, u: us[a], v: vs[bb], range: box_of(a0, a1, b0, b1), lower });
                }
            }
        }
        // Cells: the gradient turns from negative to positive across the cell in u and in v.
        for la in 0..b.na {
            for lb in 0..b.nb {
                let (c00, c10, c01, c11) = (at(la, lb), at(la + 1, lb), at(la, lb + 1), at(la + 1, lb + 1));
                let (a, bb) = (b.a0 + la, b.b0 + lb);
                // Ranked by the mean of the corners' squared distances (the minimum would tie all
                // cells around one near node).
                let d2 = 0.25 * (c00[0] + c10[0] + c01[0] + c11[0]);
                let (d2_u0, d2_u1) = (0.5 * (c00[0] + c01[0]), 0.5 * (c10[0] + c11[0]));
                let (d2_v0, d2_v1) = (0.5 * (c00[0] + c10[0]), 0.5 * (c01[0] + c11[0]));
                let range = box_of(a, a + 1, bb, bb + 1);
                let (um, vm) = (0.5 * (us[a] + us[a + 1]), 0.5 * (vs[bb] + vs[bb + 1]));
                let turns_u = |l: [f64; 3], r: [f64; 3]| l[1] < 0.0 && r[1] > 0.0;
                let turns_v = |l: [f64; 3], r: [f64; 3]| l[2] < 0.0 && r[2] > 0.0;
                let cell_turns_u = turns_u(c00, c10) || turns_u(c01, c11);
                let cell_turns_v = turns_v(c00, c01) || turns_v(c10, c11);
                let on_edge = a == 0 || a + 2 == nu || bb == 0 || bb + 2 == nv;
                let interior = cell_turns_u && cell_turns_v;
                if !interior && !on_edge {
                    continue;
                }
                if interior && self.gauss_newton_lands_near(a, bb, [c00, c10, c01, c11]) {
                    seeds.push(Seed { d2, u: um, v: vm, range, lower });
                }
                // Edge segments of the domain: a turn along the edge, held across it.
                if a == 0 && turns_v(c00, c01) && (c00[1] >= 0.0 || c01[1] >= 0.0) {
                    seeds.push(Seed { d2: d2_u0, u: us[a], v: vm, range: box_of(a, a, bb, bb + 1), lower });
                }
                if a + 2 == nu && turns_v(c10, c11) && (c10[1] <= 0.0 || c11[1] <= 0.0) {
                    seeds.push(Seed { d2: d2_u1, u: us[a + 1], v: vm, range: box_of(a + 1, a + 1, bb, bb + 1), lower });
                }
                if bb == 0 && turns_u(c00, c10) && (c00[2] >= 0.0 || c10[2] >= 0.0) {
                    seeds.push(Seed { d2: d2_v0, u: um, v: vs[bb], range: box_of(a, a + 1, bb, bb), lower });
                }
                if bb + 2 == nv && turns_u(c01, c11) && (c01[2] <= 0.0 || c11[2] <= 0.0) {
                    seeds.push(Seed {
                        d2: d2_v1,
                        u: um,
                        v: vs[bb + 1],
                        range: box_of(a, a + 1, bb + 1, bb + 1),
                        lower,
                    });
                }
            }
        }
    }

    /// Does a Gauss-Newton step from the nearest corner of cell `(a, b)` land within one cell of
    /// it? If not, the sign pattern is an artefact (a cell beside the real basin) and the seed
    /// would only repeat another one. Undecided (degenerate corner) counts as yes.
    fn gauss_newton_lands_near(&self, a: usize, b: usize, corners: [[f64; 3]; 4]) -> bool {
        let nv = self.vs.len();
        let idx = [(a, b), (a + 1, b), (a, b + 1), (a + 1, b + 1)];
        let k = (0..4).fold(0, |m, k| if corners[k][0] < corners[m][0] { k } else { m });
        let (ca, cb) = idx[k];
        let smp = &self.samples[ca * nv + cb];
        let (uu, uv, vv) = (smp.su.norm_squared(), smp.su.dot(smp.sv), smp.sv.norm_squared());
        let det = uu * vv - uv * uv;
        let regular = det > SINGULAR_REL * uu * vv; // false for NaN too
        if !regular {
            return true;
        }
        let [_, gu, gv] = corners[k];
        let du = (-gu * vv + gv * uv) / det;
        let dv = (-gv * uu + gu * uv) / det;
        let (u, v) = (self.us[ca] + du, self.vs[cb] + dv);
        let (wu, wv) = (self.us[a + 1] - self.us[a], self.vs[b + 1] - self.vs[b]);
        u >= self.us[a] - wu && u <= self.us[a + 1] + wu && v >= self.vs[b] - wv && v <= self.vs[b + 1] + wv
    }

    /// Is node `(la, lb)` of block `b` (distance^2 `d2`) a discrete local minimum over its
    /// 8 neighbours? Ties go to the lower node index so a plateau (a collapsed edge) gives one.
    #[allow(clippy::too_many_arguments)]
    fn is_local_min(&self, q: Vec3, vals: &[[f64; 3]], b: &Block, la: usize, lb: usize, d2: f64, node: usize) -> bool {
        let nv = self.vs.len();
        let (nu_all, rv) = (self.us.len(), b.nb + 1);
        let (a, bb) = (b.a0 + la, b.b0 + lb);
        for da in -1i64..=1 {
            for db in -1i64..=1 {
                if da == 0 && db == 0 {
                    continue;
                }
                let (na, nb) = (a as i64 + da, bb as i64 + db);
                if na < 0 || nb < 0 || na >= nu_all as i64 || nb >= nv as i64 {
                    continue;
                }
                let (na, nb) = (na as usize, nb as usize);
                let other = na * nv + nb;
                let od2 = if na >= b.a0 && na <= b.a0 + b.na && nb >= b.b0 && nb <= b.b0 + b.nb {
                    vals[(na - b.a0) * rv + nb - b.b0][0]
                } else {
                    (self.samples[other].p - q).norm_squared()
                };
                if od2 < d2 || (od2 == d2 && other < node) {
                    return false;
                }
            }
        }
        true
    }

    /// Is node `(a, b)`, on an edge of the domain, a discrete local minimum along that edge?
    /// A minimum on an edge where the gradient points out of the domain is a constrained local
    /// minimum that the 2-D test misses when a node inside is nearer.
    fn is_edge_local_min(&self, q: Vec3, a: usize, b: usize, d2: f64, node: usize) -> bool {
        let (nu, nv) = (self.us.len(), self.vs.len());
        let wins = |other: usize| {
            let od2 = (self.samples[other].p - q).norm_squared();
            od2 > d2 || (od2 == d2 && other > node)
        };
        let along_v = || (b == 0 || wins(node - 1)) && (b + 1 == nv || wins(node + 1));
        let along_u = || (a == 0 || wins(node - nv)) && (a + 1 == nu || wins(node + nv));
        ((a == 0 || a + 1 == nu) && along_v()) || ((b == 0 || b + 1 == nv) && along_u())
    }

    /// Safeguarded Newton iteration from `(u, v)` (see the module documentation).
    fn refine(&self, q: Vec3, u: f64, v: f64) -> SurfaceProjection {
        let s = self.surface;
        let ((ua, ub), (va, vb)) = (s.domain_u(), s.domain_v());
        let eps = self.eps;
        let (mut u, mut v) = (u.clamp(ua, ub), v.clamp(va, vb));
        let mut d = s.derivatives(u, v);
        let mut r = d.point - q;
        let mut f = r.norm_squared();
        let mut converged = false;
        let mut iterations = 0;
        let mut turned = false;
        // A start on a collapsed edge leaves it in the steepest direction into the surface.
        if self.collapsed_edge_of(u, v) != 0 {
            let (at_u, at_v) = (u <= ua || u >= ub, v <= va || v >= vb);
            if let Some((nu, nv)) = self.leave_collapsed_edge(q, u, v, at_u, at_v) {
                (u, v) = (nu, nv);
                d = s.derivatives(u, v);
                r = d.point - q;
                f = r.norm_squared();
            }
        }
        'newton: while iterations < self.options.max_iterations {
            if f.sqrt() <= eps {
                converged = true; // point coincidence
                break;
            }
            let (gu, gv) = (d.su.dot(r), d.sv.dot(r));
            let hold_u = held_at_bound(u, ua, ub, gu);
            let hold_v = held_at_bound(v, va, vb, gv);
            // Zero cosine, |S_k . r| / (|S_k| |r|) <= eps / |r|, for each free direction.
            let ok_u = hold_u || gu * gu <= eps * eps * d.su.norm_squared();
            let ok_v = hold_v || gv * gv <= eps * eps * d.sv.norm_squared();
            // On a collapsed edge (all of it one point, as a hull's stem) every v (or u) gives
            // the same point but its own direction into the surface: the bound holds only if it
            // holds for all of them, and the direction along the edge means nothing.
            let on_collapsed = self.on_collapsed_edge(u, v, hold_u, hold_v);
            if on_collapsed && !turned {
                turned = true;
                if let Some((nu, nv)) = self.leave_collapsed_edge(q, u, v, hold_u, hold_v) {
                    (u, v) = (nu, nv);
                    d = s.derivatives(u, v);
                    r = d.point - q;
                    f = r.norm_squared();
                    continue;
                }
            }
            if (ok_u && ok_v) || on_collapsed {
                converged = true;
                break;
            }
            iterations += 1;
            let (du, dv) = surface_step(&d, r, gu, gv, hold_u, hold_v);
            let residual = |d: &SurfaceDerivatives, r: Vec3| tangential(d.su, r, hold_u) + tangential(d.sv, r, hold_v);
            let res0 = residual(&d, r);
            let mut alpha = 1.0;
            for _ in 0..MAX_HALVINGS {
                let nu = (u + alpha * du).clamp(ua, ub);
                let nv = (v + alpha * dv).clamp(va, vb);
                let moved = (d.su * (nu - u) + d.sv * (nv - v)).norm();
                let nd = s.derivatives(nu, nv);
                let nr = nd.point - q;
                let nf = nr.norm_squared();
                // Near the foot `f` is flat to round-off: a step that leaves it unchanged within
                // its rounding noise is taken if it reduces the tangential residual instead.
                let flat = nf <= f + self.noise(nf) && residual(&nd, nr) < res0;
                if nf < f || flat {
                    (u, v, d, r, f) = (nu, nv, nd, nr, nf);
                    if moved <= eps {
                        converged = true; // step size
                        break 'newton;
                    }
                    continue 'newton;
                }
                if moved <= eps {
                    converged = true; // no step longer than eps1 decreases the distance
                    break 'newton;
                }
                alpha *= 0.5;
            }
            break; // no decrease found along a descent direction (round-off only)
        }
        SurfaceProjection { u, v, point: d.point, distance: f.sqrt(), iterations, converged }
    }

    /// Rounding noise of `f = |S - q|^2` near `f`: the coordinates of `S` carry errors of a few
    /// ulps of the model's magnitude.
    #[inline]
    fn noise(&self, f: f64) -> f64 {
        16.0 * f64::EPSILON * (f.sqrt() * self.magnitude + f)
    }

    /// Bit mask of the collapsed edges `(u, v)` lies on (bits: u0, u1, v0, v1).
    fn collapsed_edge_of(&self, u: f64, v: f64) -> u8 {
        let ((ua, ub), (va, vb)) = (self.surface.domain_u(), self.surface.domain_v());
        let on = [u <= ua, u >= ub, v <= va, v >= vb];
        (0..4).filter(|&k| on[k] && self.collapsed[k]).fold(0, |m, k| m | (1 << k))
    }

    /// Is `(u, v)` held on a bound whose edge is collapsed to a point?
    fn on_collapsed_edge(&self, u: f64, v: f64, hold_u: bool, hold_v: bool) -> bool {
        let ((ua, ub), (va, vb)) = (self.surface.domain_u(), self.surface.domain_v());
        let [cu0, cu1, cv0, cv1] = self.collapsed;
        (hold_u && ((u <= ua && cu0) || (u >= ub && cu1))) || (hold_v && ((v <= va && cv0) || (v >= vb && cv1)))
    }

    /// At a point held on a collapsed edge (all of it one point), the parameter along the edge
    /// whose direction into the surface decreases the distance most, if one does.
    fn leave_collapsed_edge(&self, q: Vec3, u: f64, v: f64, hold_u: bool, hold_v: bool) -> Option<(f64, f64)> {
        let s = self.surface;
        let ((ua, ub), (va, vb)) = (s.domain_u(), s.domain_v());
        let [cu0, cu1, cv0, cv1] = self.collapsed;
        // Directional derivative into the surface per unit length, along the edge parameter t.
        let slope = |t: f64, across_u: bool, inward: f64| {
            let d = if across_u { s.derivatives(u, t) } else { s.derivatives(t, v) };
            let dir = if across_u { d.su } else { d.sv };
            inward * dir.dot(d.point - q) / dir.norm().max(f64::MIN_POSITIVE)
        };
        // The steepest direction: the best sample, then golden-section search between its
        // neighbours (the slope is smooth in t).
        let steepest = |ts: &[f64], across_u: bool, inward: f64| {
            let (k, _) = ts
                .iter()
                .map(|&t| slope(t, across_u, inward))
                .enumerate()
                .fold((0, f64::INFINITY), |b, (k, m)| if m < b.1 { (k, m) } else { b });
            let (mut lo, mut hi) = (ts[k.saturating_sub(1)], ts[(k + 1).min(ts.len() - 1)]);
            let phi = 0.5 * (5f64.sqrt() - 1.0);
            for _ in 0..40 {
                let (t1, t2) = (hi - phi * (hi - lo), lo + phi * (hi - lo));
                if slope(t1, across_u, inward) < slope(t2, across_u, inward) {
                    hi = t2;
                } else {
                    lo = t1;
                }
            }
            let t = 0.5 * (lo + hi);
            let (m, mk) = (slope(t, across_u, inward), slope(ts[k], across_u, inward));
            if m < mk {
                (t, m)
            } else {
                (ts[k], mk)
            }
        };
        let mut best: Option<(f64, f64, f64)> = None;
        if hold_u && ((u <= ua && cu0) || (u >= ub && cu1)) {
            let (t, m) = steepest(&self.vs, true, if u <= ua { 1.0 } else { -1.0 });
            best = Some((u, t, m));
        }
        if hold_v && ((v <= va && cv0) || (v >= vb && cv1)) {
            let (t, m) = steepest(&self.us, false, if v <= va { 1.0 } else { -1.0 });
            if !matches!(best, Some(b) if b.2 <= m) {
                best = Some((t, v, m));
            }
        }
        best.filter(|b| b.2 < -self.eps).map(|(nu, nv, _)| (nu, nv))
    }
}

/// `(S_k . r)^2 / |S_k|^2`, the squared tangential residual along a free direction `S_k`.
#[inline]
fn tangential(sk: Vec3, r: Vec3, held: bool) -> f64 {
    let n2 = sk.norm_squared();
    if held || n2 == 0.0 {
        0.0
    } else {
        sk.dot(r).powi(2) / n2
    }
}

/// The parameters of every span's fine grid for [`span_radius`]: `2 * counts[i] + 1` equal
/// steps over span `i` of `br`, both ends included, and where each span's start in the list.
fn fine_params(br: &[f64], counts: &[usize]) -> (Vec<f64>, Vec<usize>) {
    let mut out = Vec::new();
    let mut starts = Vec::with_capacity(counts.len());
    for (w, &g) in br.windows(2).zip(counts) {
        starts.push(out.len());
        let f = 2 * g;
        out.extend((0..=f).map(|a| if a == f { w[1] } else { w[0] + (w[1] - w[0]) * a as f64 / f as f64 }));
    }
    (out, starts)
}

/// Radius about `center` of a sphere holding the surface over one span sampled with
/// `fu / 2 x fv / 2` intervals, from its points `at(a, b)` at half that spacing (`a <= fu`,
/// `b <= fv`, [`fine_params`]): the farthest of them, plus the largest deviation of the half-spacing samples from the bilinear interpolation of the
/// coarse ones. That deviation is a second-order sag, four times the sag left between the fine
/// samples, so the bound holds wherever the second derivatives vary little over a cell.
fn span_radius(at: impl Fn(usize, usize) -> Vec3, center: Vec3, fu: usize, fv: usize) -> f64 {
    let mut far: f64 = 0.0;
    let mut sag: f64 = 0.0;
    for a in 0..=fu {
        for b in 0..=fv {
            let p = at(a, b);
            far = far.max((p - center).norm());
            let (a_odd, b_odd) = (a % 2 == 1, b % 2 == 1);
            let interp = match (a_odd, b_odd) {
                (false, false) => continue,
                (true, false) => (at(a - 1, b) + at(a + 1, b)) * 0.5,
                (false, true) => (at(a, b - 1) + at(a, b + 1)) * 0.5,
                (true, true) => (at(a - 1, b - 1) + at(a + 1, b - 1) + at(a - 1, b + 1) + at(a + 1, b + 1)) * 0.25,
            };
            sag = sag.max((p - interp).norm());
        }
    }
    far + sag
}

/// `C(u)`, `C'(u)`, `C''(u)` without allocation (A3.2 on the homogeneous curve, then A4.2).
fn curve_ders2(c: &NurbsCurve, u: f64) -> [Vec3; 3] {
    let k = c.knots();
    let u = k.clamp(u);
    let p = c.degree();
    let span = k.find_span(u);
    let mut ders: [BasisRow; 3] = [[0.0; MAX_DEGREE + 1]; 3];
    ders_basis_funs(k.as_slice(), span, u, p, 2, &mut ders);
    let cw = &c.homogeneous()[span - p..=span];
    let mut a = [[0.0f64; 4]; 3];
    for (k, row) in ders.iter().enumerate() {
        for (j, h) in cw.iter().enumerate() {
            for t in 0..4 {
                a[k][t] += row[j] * h[t];
            }
        }
    }
    let xyz = |h: [f64; 4]| Vec3::new(h[0], h[1], h[2]);
    let w0 = a[0][3];
    let c0 = xyz(a[0]) / w0;
    let c1 = (xyz(a[1]) - c0 * a[1][3]) / w0;
    let c2 = (xyz(a[2]) - c1 * (2.0 * a[1][3]) - c0 * a[2][3]) / w0;
    [c0, c1, c2]
}

/// Projects points onto one curve; the one-dimensional counterpart of [`SurfaceProjector`]:
/// samples (point, first and second derivatives) per knot span as set by
/// [`ProjectionOptions::grid`], a bounding sphere per span, and Newton on
/// `g(u) = C'(u) . (C(u) - P)` (The NURBS Book eq. 6.3-6.4) from the best few nodes nearer than
/// their neighbours, intervals where `g` turns from negative to positive (at their ends or in
/// the cubic Hermite interpolant of `g` and `g'`), and end points where `g` points out of the
/// domain, with the same safeguards.
#[derive(Clone, Debug)]
pub struct CurveProjector<'a> {
    curve: &'a NurbsCurve,
    options: ProjectionOptions,
    eps: f64,
    us: Vec<f64>,
    /// `[C(u), C'(u), C''(u)]` at `us`.
    samples: Vec<[Vec3; 3]>,
    /// Index of each span's first sample.
    starts: Vec<usize>,
    /// Per span: centre node (a curve point) and radius of a sphere holding the span.
    spans: Vec<(Vec3, f64)>,
    /// Largest coordinate magnitude of the control polygon (scale of evaluation round-off).
    magnitude: f64,
}

impl<'a> CurveProjector<'a> {
    /// Sample `curve` and prepare the span bounds.
    pub fn new(curve: &'a NurbsCurve, options: ProjectionOptions) -> Self {
        let base = 4 * options.grid.max(curve.degree()).max(1);
        let br = breaks(curve.knots());
        let counts = intervals_by_turning(&br, base, |u| curve_ders2(curve, u)[1]);
        let (us, starts, counts) = sample_params_by_span(&br, &counts, (false, false));
        let samples: Vec<[Vec3; 3]> = us.iter().map(|&u| curve_ders2(curve, u)).collect();
        let pts = curve.control_points();
        let (mut lo, mut hi) = (pts[0], pts[0]);
        for p in &pts {
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        let eps = abs_tolerance(&options, (hi - lo).norm());
        let spans = br
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let center = samples[starts[i] + counts[i] / 2][0];
                let f = 2 * counts[i];
                let fine: Vec<Vec3> = (0..=f)
                    .map(|a| curve.point(if a == f { w[1] } else { w[0] + (w[1] - w[0]) * a as f64 / f as f64 }))
                    .collect();
                let far = fine.iter().map(|&p| (p - center).norm()).fold(0.0, f64::max);
                let sag =
                    (1..f).step_by(2).map(|a| (fine[a] - (fine[a - 1] + fine[a + 1]) * 0.5).norm()).fold(0.0, f64::max);
                (center, far + sag + eps)
            })
            .collect();
        let magnitude = lo.norm().max(hi.norm());
        CurveProjector { curve, options, eps, us, samples, starts, spans, magnitude }
    }

    /// The closest point of the curve to `q`. For a finite `q` every field is finite.
    pub fn project(&self, q: Vec3) -> CurveProjection {
        let u0 = self.us[0];
        if !q.is_finite() {
            let point = self.curve.point(u0);
            return CurveProjection { u: u0, point, distance: (point - q).norm(), iterations: 0, converged: false };
        }
        let upper = self.spans.iter().map(|(c, _)| (q - *c).norm()).fold(f64::INFINITY, f64::min);
        // Per node: |C - q|^2, g = C' . (C - q) and g' = |C'|^2 + C'' . (C - q).
        let vals: Vec<(f64, f64, f64)> = self
            .samples
            .iter()
            .map(|&[p, t, t2]| {
                let r = p - q;
                (r.norm_squared(), t.dot(r), t.norm_squared() + t2.dot(r))
            })
            .collect();
        let n = vals.len();
        let us = &self.us;
        let bound = |s: usize| (q - self.spans[s].0).norm() - self.spans[s].1;
        let span_of = |i: usize| self.starts.partition_point(|&st| st <= i).saturating_sub(1);
        let mut seeds: Vec<Seed> = Vec::new();
        for (i, &(d2, g, h)) in vals.iter().enumerate() {
            let left_ok = i == 0 || vals[i - 1].0 > d2;
            let right_ok = i + 1 == n || vals[i + 1].0 >= d2;
            let end_held = (i == 0 && g >= 0.0) || (i + 1 == n && g <= 0.0);
            if (left_ok && right_ok) || end_held {
                // A node on a break belongs to two spans: take the lower bound. A held end
                // stands for itself only, not for the interval beside it.
                let lower = bound(span_of(i)).min(bound(span_of(i.saturating_sub(1))));
                let range = if end_held {
                    [us[i], us[i], 0.0, 0.0]
                } else {
                    [us[i.saturating_sub(1)], us[(i + 1).min(n - 1)], 0.0, 0.0]
                };
                seeds.push(Seed { d2, u: us[i], v: 0.0, range, lower });
            }
            // g turns from negative to positive inside the interval: seen at its ends, or in the
            // cubic Hermite interpolant of g, g' (a minimum and a maximum both in one interval).
            if i + 1 < n {
                let (g1, h1) = (vals[i + 1].1, vals[i + 1].2);
                if let Some(t) = hermite_turn(g, h, g1, h1, us[i + 1] - us[i]) {
                    let range = [us[i], us[i + 1], 0.0, 0.0];
                    let u = us[i] + t * (us[i + 1] - us[i]);
                    seeds.push(Seed { d2: d2.min(vals[i + 1].0), u, v: 0.0, range, lower: bound(span_of(i)) });
                }
            }
        }
        seeds.retain(|s| s.lower <= upper);
        seeds.sort_unstable_by(|x, y| x.d2.total_cmp(&y.d2));
        let mut best: Option<CurveProjection> = None;
        let mut feet: Vec<f64> = Vec::new();
        let mut runs = 0;
        for seed in &seeds {
            if runs >= self.options.candidates.max(1) {
                break;
            }
            if matches!(&best, Some(bp) if seed.lower >= bp.distance) {
                continue;
            }
            if feet.iter().any(|&u| seed.covers(u, 0.0)) {
                continue;
            }
            runs += 1;
            let res = self.refine(q, seed.u);
            feet.push(res.u);
            if !matches!(&best, Some(bp) if bp.distance <= res.distance) {
                best = Some(res);
            }
        }
        best.unwrap_or_else(|| self.refine(q, u0))
    }

    /// Safeguarded one-dimensional Newton iteration from `u`.
    fn refine(&self, q: Vec3, u: f64) -> CurveProjection {
        let (ua, ub) = self.curve.domain();
        let eps = self.eps;
        let mut u = u.clamp(ua, ub);
        let mut d = curve_ders2(self.curve, u);
        let mut r = d[0] - q;
        let mut f = r.norm_squared();
        let mut converged = false;
        let mut iterations = 0;
        'newton: while iterations < self.options.max_iterations {
            if f.sqrt() <= eps {
                converged = true;
                break;
            }
            let g = d[1].dot(r);
            let gg = d[1].norm_squared();
            if held_at_bound(u, ua, ub, g) || g * g <= eps * eps * gg {
                converged = true;
                break;
            }
            iterations += 1;
            let du = step_1d(gg + r.dot(d[2]), gg, g);
            let res0 = tangential(d[1], r, false);
            let mut alpha = 1.0;
            for _ in 0..MAX_HALVINGS {
                let nu = (u + alpha * du).clamp(ua, ub);
                let moved = (d[1] * (nu - u)).norm();
                let nd = curve_ders2(self.curve, nu);
                let nr = nd[0] - q;
                let nf = nr.norm_squared();
                // As for surfaces: within the rounding noise of f, the residual decides.
                let noise = 16.0 * f64::EPSILON * (nf.sqrt() * self.magnitude + nf);
                let flat = nf <= f + noise && tangential(nd[1], nr, false) < res0;
                if nf < f || flat {
                    (u, d, r, f) = (nu, nd, nr, nf);
                    if moved <= eps {
                        converged = true;
                        break 'newton;
                    }
                    continue 'newton;
                }
                if moved <= eps {
                    converged = true;
                    break 'newton;
                }
                alpha *= 0.5;
            }
            break;
        }
        CurveProjection { u, point: d[0], distance: f.sqrt(), iterations, converged }
    }
}

/// Where in `[0, 1]` the cubic Hermite interpolant of `g` (values `g0`, `g1`, derivatives `h0`,
/// `h1` per unit parameter over an interval of width `w`) first turns from negative to positive,
/// checked at 8 sub-intervals; `None` if it does not.
fn hermite_turn(g0: f64, h0: f64, g1: f64, h1: f64, w: f64) -> Option<f64> {
    const STEPS: usize = 8;
    let (m0, m1) = (h0 * w, h1 * w);
    let p = |t: f64| {
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * g0 + (t3 - 2.0 * t2 + t) * m0 + (-2.0 * t3 + 3.0 * t2) * g1 + (t3 - t2) * m1
    };
    let mut prev = g0;
    for k in 1..=STEPS {
        let t = k as f64 / STEPS as f64;
        let cur = if k == STEPS { g1 } else { p(t) };
        if prev < 0.0 && cur > 0.0 {
            return Some(t - 0.5 / STEPS as f64);
        }
        prev = cur;
    }
    None
}

/// The closest point of `curve` to `q` (builds a [`CurveProjector`]; keep one instead when
/// projecting many points onto the same curve).
pub fn project_point_to_curve(curve: &NurbsCurve, q: Vec3, opts: &ProjectionOptions) -> CurveProjection {
    CurveProjector::new(curve, *opts).project(q)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::assert_near;
    use proptest::prelude::*;
    use std::f64::consts::{FRAC_1_SQRT_2, FRAC_PI_2};

    /// Quarter cylinder `x^2 + y^2 = r^2`, `x, y >= 0`, `0 <= z <= h`: rational quadratic in u
    /// (u = 0 at (r, 0), u = 1 at (0, r)), linear in v (z = h v).
    fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
        let ku = KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for (x, y, wi) in [(r, 0.0, 1.0), (r, r, FRAC_1_SQRT_2), (0.0, r, 1.0)] {
            for z in [0.0, h] {
                pts.push(Vec3::new(x, y, z));
                w.push(wi);
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    /// The octant `x, y, z >= 0` of the sphere of radius `r` about the origin, as the quarter
    /// meridian (pole (0,0,r) to equator (r,0,0)) revolved by 90 degrees: biquadratic, weights
    /// `w_i w_j`. The row `i = 0` collapses to the pole, where `S_v = 0`.
    fn sphere_octant(r: f64) -> NurbsSurface {
        let k = || KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
        let s = FRAC_1_SQRT_2;
        let meridian = [(0.0, r, 1.0), (r, r, s), (r, 0.0, 1.0)]; // (radius, z, w)
        let turn = [(1.0, 0.0, 1.0), (1.0, 1.0, s), (0.0, 1.0, 1.0)]; // (cos, sin, w) of the net
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for &(rho, z, wi) in &meridian {
            for &(c, sn, wj) in &turn {
                pts.push(Vec3::new(rho * c, rho * sn, z));
                w.push(wi * wj);
            }
        }
        NurbsSurface::try_new(k(), k(), &pts, Some(&w)).expect("valid")
    }

    /// A full circle of radius r in the xy plane, 9-point rational quadratic (The NURBS Book
    /// Ex. 7.2); u = 0 and u = 1 both at (r, 0, 0).
    fn circle(r: f64) -> NurbsCurve {
        let s = FRAC_1_SQRT_2;
        let pts = [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.), (1., 0.)]
            .map(|(x, y)| Vec3::new(r * x, r * y, 0.0));
        let w = [1., s, 1., s, 1., s, 1., s, 1.];
        let k = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
        NurbsCurve::try_new(KnotVector::try_new(2, k).expect("valid"), &pts, Some(&w)).expect("valid")
    }

    /// A wavy bicubic surface over `[0, n_u - 1] x [0, n_v - 1]` in x, y with heights `z(i, j)`,
    /// optionally with the first row collapsed to one point (a hull's stem).
    fn bicubic(
        n_u: usize,
        n_v: usize,
        z: impl Fn(usize, usize) -> f64,
        w: Option<&[f64]>,
        collapse: bool,
    ) -> NurbsSurface {
        let ku = KnotVector::uniform(3, n_u).expect("valid");
        let kv = KnotVector::uniform(3, n_v).expect("valid");
        let mut pts = Vec::new();
        for i in 0..n_u {
            for j in 0..n_v {
                pts.push(if collapse && i == 0 {
                    Vec3::new(0.0, 0.5 * n_v as f64, 0.0)
                } else {
                    Vec3::new(i as f64, j as f64, z(i, j))
                });
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, w).expect("valid")
    }

    fn size(s: &NurbsSurface) -> f64 {
        let (lo, hi) = s.control_bounds();
        (hi - lo).norm()
    }

    /// Brute force: the smallest distance from `q` to `n x n` samples of the surface.
    fn brute_force(samples: &[Vec3], q: Vec3) -> f64 {
        samples.iter().map(|&p| (p - q).norm()).fold(f64::INFINITY, f64::min)
    }

    fn sample_grid(s: &NurbsSurface, n: usize) -> Vec<Vec3> {
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        let mut out = Vec::with_capacity((n + 1) * (n + 1));
        for a in 0..=n {
            for b in 0..=n {
                let (ta, tb) = (a as f64 / n as f64, b as f64 / n as f64);
                out.push(s.point(u0 + (u1 - u0) * ta, v0 + (v1 - v0) * tb));
            }
        }
        out
    }

    /// Common checks of any surface projection: finite, inside the domain, `distance` and
    /// `point` consistent with the surface.
    fn check_consistent(s: &NurbsSurface, q: Vec3, r: &SurfaceProjection) {
        assert!(r.u.is_finite() && r.v.is_finite() && r.point.is_finite() && r.distance.is_finite(), "{r:?}");
        let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
        assert!((u0..=u1).contains(&r.u) && (v0..=v1).contains(&r.v), "{r:?}");
        assert_near!(r.point, s.point(r.u, r.v), 0.0);
        assert_near!(r.distance, (r.point - q).norm(), 0.0);
    }

    #[test]
    fn cylinder_feet_are_radial() {
        let (rad, h) = (2.0, 3.0);
        let s = quarter_cylinder(rad, h);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let size = size(&s);
        for rho in [0.3 * rad, 0.9 * rad, 1.1 * rad, 3.0 * rad] {
            for k in 0..=10 {
                let theta = 0.02 + (FRAC_PI_2 - 0.04) * k as f64 / 10.0;
                for z in [0.1, 1.3, 2.9] {
                    let q = Vec3::new(rho * theta.cos(), rho * theta.sin(), z);
                    let r = proj.project(q);
                    check_consistent(&s, q, &r);
                    assert!(r.converged);
                    // The distance is stationary at the foot: round-off only (1e-15 * size
                    // observed), 1e-12 * size is the default tolerance.
                    assert_near!(r.distance, (rho - rad).abs(), 1e-12 * size);
                    // The foot is first order in the tangential residual eps1 = 1e-12 * size,
                    // amplified by 1 / (1 - kappa d) <= 1 / 0.3 inside the cylinder.
                    let foot = Vec3::new(rad * theta.cos(), rad * theta.sin(), z);
                    assert_near!(r.point, foot, 1e-11 * size);
                }
            }
        }
    }

    #[test]
    fn cylinder_boundary_and_corner_feet() {
        let (rad, h) = (2.0, 3.0);
        let s = quarter_cylinder(rad, h);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let size = size(&s);
        // (query, expected foot, expected u or NaN, expected v or NaN)
        let nan = f64::NAN;
        let t: f64 = 0.7;
        let cases = [
            // beyond the u = 0 edge (angle -0.3): foot on the straight edge x = r, y = 0.
            (Vec3::new(3.0 * (-0.3f64).cos(), 3.0 * (-0.3f64).sin(), 1.2), Vec3::new(rad, 0.0, 1.2), 0.0, nan),
            // beyond the u = 1 edge.
            (Vec3::new(-0.5, 2.5, 2.0), Vec3::new(0.0, rad, 2.0), 1.0, nan),
            // above the top v = 1 edge: foot on the arc z = h.
            (Vec3::new(2.5 * t.cos(), 2.5 * t.sin(), h + 1.0), Vec3::new(rad * t.cos(), rad * t.sin(), h), nan, 1.0),
            // below the bottom edge, inside the cylinder.
            (Vec3::new(1.0 * t.cos(), 1.0 * t.sin(), -0.4), Vec3::new(rad * t.cos(), rad * t.sin(), 0.0), nan, 0.0),
            // corners (u, v) = (0, 0) and (1, 1).
            (Vec3::new(3.0, -1.0, -2.0), Vec3::new(rad, 0.0, 0.0), 0.0, 0.0),
            (Vec3::new(-1.0, 2.5, h + 0.5), Vec3::new(0.0, rad, h), 1.0, 1.0),
        ];
        for (q, foot, u, v) in cases {
            let r = proj.project(q);
            check_consistent(&s, q, &r);
            assert!(r.converged, "{q:?}: {r:?}");
            // Feet on an edge are found by 1-D Newton along the edge: same tolerances as above.
            assert_near!(r.point, foot, 1e-11 * size, "q = {q:?}");
            assert_near!(r.distance, (q - foot).norm(), 1e-12 * size, "q = {q:?}");
            // A parameter held at its bound is exactly the bound (clamped, not approached).
            if !u.is_nan() {
                assert_eq!(r.u, u, "q = {q:?}");
            }
            if !v.is_nan() {
                assert_eq!(r.v, v, "q = {q:?}");
            }
        }
    }

    #[test]
    fn points_on_the_surface_project_to_themselves() {
        let s = bicubic(7, 6, |i, j| 0.4 * ((i * 3 + j * 5) % 7) as f64 / 7.0, None, false);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let size = size(&s);
        for a in 0..=9 {
            for b in 0..=9 {
                let (u, v) = (a as f64 / 9.0, b as f64 / 9.0);
                let q = s.point(u, v);
                let r = proj.project(q);
                check_consistent(&s, q, &r);
                assert!(r.converged);
                // Point coincidence criterion |S - q| <= eps1 = 1e-12 * size.
                assert!(r.distance <= 1e-12 * size, "({u}, {v}): {r:?}");
            }
        }
    }

    #[test]
    fn sphere_octant_with_collapsed_pole() {
        let rad = 1.5;
        let s = sphere_octant(rad);
        // The pole row is collapsed: S_v vanishes there (to round-off).
        assert!(s.derivatives(0.0, 0.4).sv.norm() <= 1e-14, "{:?}", s.derivatives(0.0, 0.4));
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let size = size(&s);
        // Directions in the octant, down to the pole itself (polar angle 0, the degenerate edge).
        for polar in [0.0f64, 1e-9, 1e-3, 0.2, 0.8, 1.5] {
            for azimuth in [0.0, 0.3, 0.9, FRAC_PI_2] {
                let dir = Vec3::new(polar.sin() * azimuth.cos(), polar.sin() * azimuth.sin(), polar.cos());
                for c in [0.4, 0.999, 2.0] {
                    let q = dir * (c * rad);
                    let r = proj.project(q);
                    check_consistent(&s, q, &r);
                    // Along the collapsed edge Newton's matrix is singular; the safeguarded step
                    // still gives the radial foot. Distance: as for the cylinder. The foot: near
                    // the pole S_v ~ 0, the cosine criterion in v is void, and the distance is
                    // flat to round-off (eps_machine * d^2) over foot moves of
                    // d * sqrt(eps_machine) ~ 1e-8 d, the accuracy left to the step criterion.
                    assert_near!(r.distance, (1.0 - c).abs() * rad, 1e-12 * size, "q = {q:?}");
                    assert_near!(r.point, dir * rad, 1e-8 * size, "q = {q:?}: {r:?}");
                }
            }
        }
        // The centre is equidistant from every point; below the octant the equator is.
        let r = proj.project(Vec3::ZERO);
        check_consistent(&s, Vec3::ZERO, &r);
        assert_near!(r.distance, rad, 1e-12 * size);
        let q = Vec3::new(0.0, 0.0, -1.0);
        let r = proj.project(q);
        check_consistent(&s, q, &r);
        assert_near!(r.distance, (rad * rad + 1.0).sqrt(), 1e-12 * size);
    }

    #[test]
    fn collapsed_stem_gives_finite_global_results() {
        let s = bicubic(8, 6, |i, j| 0.3 * (i as f64 * 0.7).sin() * (j as f64 * 0.9).cos(), None, true);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let samples = sample_grid(&s, 200);
        let size = size(&s);
        let stem = s.control_point(0, 0);
        for k in 0..60 {
            let t = k as f64;
            // A spiral of queries about the stem and over the surface.
            let q =
                stem + Vec3::new(0.1 * t * (0.5 * t).cos(), 2.5 + 0.08 * t * (0.5 * t).sin(), 0.6 * (0.37 * t).sin());
            let r = proj.project(q);
            check_consistent(&s, q, &r);
            // No worse than 200 x 200 samples (which lie on the surface): 1e-12 * size is the
            // convergence tolerance.
            assert!(r.distance <= brute_force(&samples, q) + 1e-12 * size, "q = {q:?}: {r:?}");
        }
        let r = proj.project(stem + Vec3::new(-1.0, 0.0, 0.0));
        assert_near!(r.distance, 1.0, 1e-12 * size);
        assert_eq!(r.u, 0.0);
    }

    #[test]
    fn non_finite_query_is_reported_not_converged() {
        let s = quarter_cylinder(1.0, 1.0);
        let r = SurfaceProjector::new(&s, ProjectionOptions::default()).project(Vec3::new(f64::NAN, 0.0, 0.0));
        assert!(!r.converged && r.u.is_finite() && r.v.is_finite());
        let c = circle(1.0);
        let r = project_point_to_curve(&c, Vec3::new(0.0, f64::INFINITY, 0.0), &ProjectionOptions::default());
        assert!(!r.converged && r.u.is_finite());
    }

    #[test]
    fn iteration_limit_is_flagged_and_its_distance_is_an_upper_bound() {
        // Points at radius 3 around a cylinder of radius 2: the true distance is 1 at every
        // angle. One Newton step from the grid's best node cannot meet the zero-cosine test for
        // most of them; those must say so, and the distance they give, that of a point on the
        // surface, can only be larger than the true one.
        let s = quarter_cylinder(2.0, 3.0);
        let once = SurfaceProjector::new(&s, ProjectionOptions { max_iterations: 1, ..ProjectionOptions::default() });
        let full = SurfaceProjector::new(&s, ProjectionOptions::default());
        let mut flagged = 0;
        for k in 0..40 {
            let a = 0.05 + 1.47 * k as f64 / 39.0;
            let q = Vec3::new(3.0 * a.cos(), 3.0 * a.sin(), 0.1 + 0.07 * k as f64);
            let r = once.project(q);
            let f = full.project(q);
            assert!(f.converged, "{q:?}: {f:?}");
            // Converged to the tolerance 1e-12 relative of a model of size ~4.
            assert_near!(f.distance, 1.0, 1e-11);
            if !r.converged {
                flagged += 1;
                assert_eq!(r.iterations, 1);
            }
            assert_near!(s.point(r.u, r.v), r.point, 1e-15);
            assert!(r.distance >= f.distance - 1e-11, "{q:?}: {} < {}", r.distance, f.distance);
        }
        assert!(flagged > 20, "only {flagged} of 40 flagged");
    }

    #[test]
    fn project_near_is_never_farther_than_its_hint() {
        let s = sphere_octant(2.0);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        for i in 0..=10 {
            for j in 0..=10 {
                let hint = (i as f64 / 10.0, j as f64 / 10.0);
                // Points just off the surface near the hint, and far ones.
                for scale in [1.01, 0.5, 3.0] {
                    let q = s.point(hint.0, hint.1) * scale + Vec3::new(0.01, -0.02, 0.005);
                    let r = proj.project_near(q, hint);
                    assert!(r.distance <= s.point(hint.0, hint.1).distance(q) + 1e-15);
                    // And no worse than the global search alone.
                    assert!(r.distance <= proj.project(q).distance + 1e-15);
                    check_consistent(&s, q, &r);
                }
            }
        }
    }

    #[test]
    fn project_many_equals_project() {
        let s = bicubic(6, 5, |i, j| 0.2 * ((i + 2 * j) % 3) as f64, None, false);
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        let qs: Vec<Vec3> =
            (0..20).map(|k| Vec3::new(0.25 * k as f64, 0.2 * k as f64, 0.5 - 0.05 * k as f64)).collect();
        for (q, r) in qs.iter().zip(proj.project_many(&qs)) {
            assert_eq!(r, proj.project(*q));
        }
    }

    #[test]
    fn circle_feet_are_radial_across_the_seam() {
        let rad = 2.0;
        let c = circle(rad);
        let opts = ProjectionOptions::default();
        let size = 2.0 * rad * 2f64.sqrt();
        for k in 0..40 {
            // Angles on both sides of the seam at angle 0 (u = 0 and u = 1).
            let theta = -0.3 + 0.16 * k as f64;
            for rho in [0.2, 1.0, 1.7, 5.0] {
                let q = Vec3::new(rho * theta.cos(), rho * theta.sin(), 0.3);
                let r = project_point_to_curve(&c, q, &opts);
                assert!(r.converged);
                assert_near!(r.point, c.point(r.u), 0.0);
                // Distance to a circle: sqrt((rho - r)^2 + z^2); tolerances as for surfaces.
                assert_near!(r.distance, ((rho - rad).powi(2) + 0.09).sqrt(), 1e-12 * size);
                let foot = Vec3::new(rad * theta.cos(), rad * theta.sin(), 0.0);
                assert_near!(r.point, foot, 1e-10 * size, "theta = {theta}, rho = {rho}");
            }
        }
        // The centre: every point is at distance r.
        let r = project_point_to_curve(&c, Vec3::ZERO, &opts);
        assert!(r.u.is_finite());
        assert_near!(r.distance, rad, 1e-12 * size);
    }

    #[test]
    fn segment_ends_hold_the_foot() {
        let k = KnotVector::uniform(1, 2).expect("valid");
        let c = NurbsCurve::try_new(k, &[Vec3::ZERO, Vec3::new(4.0, 0.0, 0.0)], None).expect("valid");
        let opts = ProjectionOptions::default();
        let r = project_point_to_curve(&c, Vec3::new(6.0, 1.0, 0.0), &opts);
        assert!(r.converged);
        assert_eq!(r.u, 1.0);
        assert_near!(r.distance, 5f64.sqrt(), 1e-15);
        let r = project_point_to_curve(&c, Vec3::new(-1.0, 0.0, 2.0), &opts);
        assert_eq!(r.u, 0.0);
        let r = project_point_to_curve(&c, Vec3::new(1.0, 3.0, 0.0), &opts);
        assert_near!(r.u, 0.25, 1e-15);
        assert_near!(r.distance, 3.0, 1e-15);
    }

    /// A random wavy rational bicubic surface: heights and weights from the strategy.
    ///
    /// Heights of +-0.4 on a unit net and weights 0.7 to 1.4 bend the surface much more than a
    /// hull bends between its stations, yet keep every bend resolved by the sampling grid; half
    /// of the surfaces have a collapsed stem row. (Measured, outside this suite: with +-0.6 and
    /// weights 0.5 to 2 the global minimum is still found in 79 999 of 80 000 queries; the miss,
    /// 0.2 % too far, was next to a collapsed edge.)
    fn random_surface() -> impl Strategy<Value = NurbsSurface> {
        (4usize..9, 4usize..8, any::<bool>()).prop_flat_map(|(nu, nv, collapse)| {
            let n = nu * nv;
            (prop::collection::vec(-0.4f64..0.4, n), prop::collection::vec(0.7f64..1.4, n), Just((nu, nv, collapse)))
                .prop_map(|(z, w, (nu, nv, collapse))| bicubic(nu, nv, |i, j| z[i * nv + j], Some(&w), collapse))
        })
    }

    proptest! {
        // A fixed seed keeps CI deterministic; PROPTEST_CASES=N explores further.
        #![proptest_config(ProptestConfig {
            cases: 48,
            rng_seed: proptest::test_runner::RngSeed::Fixed(0x5eed_cafe),
            ..ProptestConfig::default()
        })]

        #[test]
        fn surface_projection_is_no_worse_than_brute_force(
            s in random_surface(),
            queries in prop::collection::vec((0.0f64..1.0, 0.0f64..1.0, -0.6f64..0.6, -0.3f64..0.3), 8),
        ) {
            let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
            let samples = sample_grid(&s, 150);
            let size = size(&s);
            for (u, v, off, slide) in queries {
                // A point off the surface along the normal (or straight up where it is degenerate),
                // slid sideways, so that many feet lie on edges and corners.
                let d = s.derivatives(u, v);
                let n = d.normal().unwrap_or(Vec3::new(0.0, 0.0, 1.0));
                let q = d.point + n * off + Vec3::new(slide * 3.0, -slide * 2.0, 0.0);
                let r = proj.project(q);
                check_consistent(&s, q, &r);
                // Samples lie on the surface, so the global minimum is no larger than any of
                // them; 1e-12 * size is the convergence tolerance.
                let bf = brute_force(&samples, q);
                prop_assert!(r.distance <= bf + 1e-12 * size, "q = {:?}: {:?}, brute force {}", q, r, bf);
            }
        }

        #[test]
        fn curve_projection_is_no_worse_than_brute_force(
            ys in prop::collection::vec(-1.0f64..1.0, 4..12),
            ws in prop::collection::vec(0.7f64..1.4, 12),
            qs in prop::collection::vec((-1.0f64..12.0, -3.0f64..3.0, -1.0f64..1.0), 6),
        ) {
            let n = ys.len();
            let pts: Vec<Vec3> = ys.iter().enumerate().map(|(i, &y)| Vec3::new(i as f64, y, 0.3 * y * y)).collect();
            let c = NurbsCurve::try_new(KnotVector::uniform(3, n).expect("valid"), &pts, Some(&ws[..n])).expect("valid");
            let proj = CurveProjector::new(&c, ProjectionOptions::default());
            let samples: Vec<Vec3> = (0..=4000).map(|k| c.point(k as f64 / 4000.0)).collect();
            for (x, y, z) in qs {
                let q = Vec3::new(x, y, z);
                let r = proj.project(q);
                prop_assert!(r.u.is_finite() && r.distance.is_finite());
                prop_assert!(r.distance <= brute_force(&samples, q) + 1e-12 * 20.0);
            }
        }
    }
}
