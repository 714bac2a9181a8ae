//! Point inversion on a surface: [`SurfaceProjector`], seeds from a sampled grid, then Newton
//! with bounds, collapsed edges and backtracking (see the module documentation).

use super::sampling::TURN_STEPS;
use super::sampling::{fine_params, intervals_for_turning, sample_params_by_span, span_radius, turning_params};
use super::{abs_tolerance, held_at_bound, step_1d, tangential, ProjectionOptions, SurfaceProjection, SINGULAR_REL};
use super::{GN_DAMPING, MAX_HALVINGS};
use crate::{split_spans, NurbsSurface, SurfaceDerivatives, Vec3};

/// The Newton (or safeguarded) step `(du, dv)` at a surface point, given which parameters are
/// held at a bound.
pub(super) fn surface_step(
    d: &SurfaceDerivatives,
    r: Vec3,
    gu: f64,
    gv: f64,
    hold_u: bool,
    hold_v: bool,
) -> (f64, f64) {
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
pub(super) struct Block {
    /// A grid node near the middle of the span (a point of the surface).
    pub(super) center: Vec3,
    /// Every point of the surface over the span lies within this distance of `center`.
    pub(super) radius: f64,
    /// First node row (u) and column (v) of the span, and its intervals in u and v: it spans
    /// `na + 1` by `nb + 1` nodes.
    pub(super) a0: usize,
    pub(super) b0: usize,
    pub(super) na: usize,
    pub(super) nb: usize,
}

/// A grid node: the point and its first partial derivatives.
#[derive(Clone, Copy, Debug)]
pub(super) struct Sample {
    pub(super) p: Vec3,
    pub(super) su: Vec3,
    pub(super) sv: Vec3,
}

/// A start point for Newton where the samples suggest a local minimum.
#[derive(Clone, Copy, Debug)]
pub(super) struct Seed {
    /// Smallest sampled squared distance near the seed (the ranking key).
    pub(super) d2: f64,
    pub(super) u: f64,
    pub(super) v: f64,
    /// The parameter box `[u0, u1, v0, v1]` the seed stands for: a start is skipped when an
    /// earlier Newton run already ended inside its box.
    pub(super) range: [f64; 4],
    /// Lower bound of the distance over the span the seed was found in.
    pub(super) lower: f64,
}

impl Seed {
    pub(super) fn covers(&self, u: f64, v: f64) -> bool {
        let [u0, u1, v0, v1] = self.range;
        (u0..=u1).contains(&u) && (v0..=v1).contains(&v)
    }

    /// A seed on a domain edge (its box is flat in u or v) stands for a constrained minimum.
    pub(super) fn on_edge(&self) -> bool {
        self.range[0] == self.range[1] || self.range[2] == self.range[3]
    }

    /// Seeds of one kind whose boxes touch lie in one basin as far as the samples can tell.
    pub(super) fn touches(&self, o: &Seed) -> bool {
        self.on_edge() == o.on_edge()
            && self.range[0] <= o.range[1]
            && o.range[0] <= self.range[1]
            && self.range[2] <= o.range[3]
            && o.range[2] <= self.range[3]
    }
}

/// Group seeds into clusters of touching boxes (union-find); returns each seed's cluster root.
pub(super) fn cluster_seeds(seeds: &[Seed], parent: &mut Vec<usize>) {
    pub(super) fn root(parent: &mut [usize], mut i: usize) -> usize {
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
pub(super) struct Scratch {
    pub(super) order: Vec<(f64, usize)>,
    /// Per node of the span being scanned: `(|S - q|^2, S_u . (S - q), S_v . (S - q))`.
    pub(super) vals: Vec<[f64; 3]>,
    pub(super) seeds: Vec<Seed>,
    /// `(u, v, S(u, v))` of the Newton runs so far.
    pub(super) feet: Vec<(f64, f64, Vec3)>,
    /// Cluster root of each seed, and whether a cluster has been refined.
    pub(super) cluster: Vec<usize>,
    pub(super) cluster_done: Vec<bool>,
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
        let (bu, bv) = (surface.knots_u().span_breaks(), surface.knots_v().span_breaks());
        // Intervals per span: the base count, more where some iso-line bends sharply.
        let lines_u = split_spans(&bu, &vec![base_u; bu.len() - 1]);
        let lines_v = split_spans(&bv, &vec![base_v; bv.len() - 1]);
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
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
    /// // A bilinear patch on the plane z = 0: the foot of (0.3, 0.8, 2) is (0.3, 0.8, 0).
    /// let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0])?;
    /// let net = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0)];
    /// let s = NurbsSurface::try_new(k.clone(), k, &net, None)?;
    /// let foot = SurfaceProjector::new(&s, ProjectionOptions::default()).project(Vec3::new(0.3, 0.8, 2.0));
    /// assert!((foot.u - 0.3).abs() < 1e-12 && (foot.v - 0.8).abs() < 1e-12);
    /// assert!((foot.distance - 2.0).abs() < 1e-12);
    /// // A point beyond an edge lands on that edge (u held at its bound).
    /// let foot = SurfaceProjector::new(&s, ProjectionOptions::default()).project(Vec3::new(1.5, 0.5, 0.0));
    /// assert!((foot.u - 1.0).abs() < 1e-12 && (foot.distance - 0.5).abs() < 1e-12);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
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

    pub(super) fn project_with(&self, q: Vec3, scratch: &mut Scratch) -> SurfaceProjection {
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
    pub(super) fn scan_block(&self, q: Vec3, b: &Block, lower: f64, vals: &mut Vec<[f64; 3]>, seeds: &mut Vec<Seed>) {
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
    pub(super) fn gauss_newton_lands_near(&self, a: usize, b: usize, corners: [[f64; 3]; 4]) -> bool {
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
    pub(super) fn is_local_min(
        &self,
        q: Vec3,
        vals: &[[f64; 3]],
        b: &Block,
        la: usize,
        lb: usize,
        d2: f64,
        node: usize,
    ) -> bool {
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
    pub(super) fn is_edge_local_min(&self, q: Vec3, a: usize, b: usize, d2: f64, node: usize) -> bool {
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
    pub(super) fn refine(&self, q: Vec3, u: f64, v: f64) -> SurfaceProjection {
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
            // On a collapsed edge (all of it one point, as a pointed end) every v (or u) gives
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
    pub(super) fn noise(&self, f: f64) -> f64 {
        16.0 * f64::EPSILON * (f.sqrt() * self.magnitude + f)
    }

    /// Bit mask of the collapsed edges `(u, v)` lies on (bits: u0, u1, v0, v1).
    pub(super) fn collapsed_edge_of(&self, u: f64, v: f64) -> u8 {
        let ((ua, ub), (va, vb)) = (self.surface.domain_u(), self.surface.domain_v());
        let on = [u <= ua, u >= ub, v <= va, v >= vb];
        (0..4).filter(|&k| on[k] && self.collapsed[k]).fold(0, |m, k| m | (1 << k))
    }

    /// Is `(u, v)` held on a bound whose edge is collapsed to a point?
    pub(super) fn on_collapsed_edge(&self, u: f64, v: f64, hold_u: bool, hold_v: bool) -> bool {
        let ((ua, ub), (va, vb)) = (self.surface.domain_u(), self.surface.domain_v());
        let [cu0, cu1, cv0, cv1] = self.collapsed;
        (hold_u && ((u <= ua && cu0) || (u >= ub && cu1))) || (hold_v && ((v <= va && cv0) || (v >= vb && cv1)))
    }

    /// At a point held on a collapsed edge (all of it one point), the parameter along the edge
    /// whose direction into the surface decreases the distance most, if one does.
    pub(super) fn leave_collapsed_edge(
        &self,
        q: Vec3,
        u: f64,
        v: f64,
        hold_u: bool,
        hold_v: bool,
    ) -> Option<(f64, f64)> {
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
