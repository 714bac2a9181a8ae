//! Planar cuts of a surface by axis-aligned planes: stations (`x = c`), waterlines (`z = c`)
//! and buttocks (`y = c`), the lines of a lines plan.
//!
//! # Method
//!
//! 1. **Grid.** The signed distance `f(u, v) = n . S(u, v) - c` of the surface from the plane
//!    is sampled on a parameter grid: [`CutOptions::grid`] uniform intervals joined with the
//!    knot lines, every knot span split in at least two (see `param_grid`).
//! 2. **Marching squares.** Each grid node is classed as above or below the plane; each grid
//!    edge whose ends differ holds one crossing, and each cell joins its crossings in pairs
//!    (ambiguous saddle cells by the class of the cell centre). Nodes within the tolerance
//!    band `|f| <= tolerance * size` of the plane are put on the less populated side, so a plane
//!    through a whole grid line (a boundary edge lying in the plane, the flat bottom at the
//!    baseline, the centre-plane keel edge) still yields the line along it, whichever side of
//!    the plane the rest of the surface lies on.
//! 3. **Refinement.** Each crossing is moved onto the plane by safeguarded Newton iteration
//!    (bisection whenever a Newton step leaves the bracket or fails to halve `|f|`) along its
//!    grid edge, `d f / d s = n . (S_u du + S_v dv)`, until `|f| <= tolerance * size / 100`.
//! 4. **Chaining.** Crossings joined through cells form branches: open ones from boundary to
//!    boundary, closed loops (returned with their first point repeated at the end).
//! 5. **Densification.** A segment is split, its new point put on the plane by Newton
//!    iteration along the parametric gradient of `f` from the parameter midpoint, while the
//!    turning of the polyline at either end exceeds [`CutOptions::max_segment_angle_deg`], or
//!    the chord deviates from the exact tangent at either end by more than half of it.
//!
//! # Curvature
//!
//! With `n` the plane normal, `N` the unit surface normal, the cut's tangent is
//! `t = n x (S_u x S_v) = S_u (n . S_v) - S_v (n . S_u)`, i.e. the parameter direction
//! `(du, dv) = (n . S_v, -n . S_u)`. Its normal curvature is `k_n = II(t,t) / I(t,t)`
//! (`II = L du^2 + 2 M du dv + N dv^2`, The NURBS Book / do Carmo 3-2), and by Meusnier's
//! theorem the planar curve's curvature vector `kappa m` (m the in-plane unit normal) has
//! `kappa (m . N) = k_n`, so `kappa = k_n / (m . N)` with `m = n_view x t / |t|`. `n_view`
//! is the normal that makes the plane's 2-D drawing coordinates right-handed (`+x` for
//! stations (y, z), `+z` for waterlines (x, y), `-y` for buttocks (x, z)): `kappa > 0` when
//! the curve turns counter-clockwise in [`CutPlane::coords`] as the polyline is traversed.
//! Where the plane is (nearly) tangent to the surface (`|m . N| < 1e-6`) or the normal is
//! undefined (a collapsed edge), the curvature is the discrete one of the polyline: the
//! inverse radius of the circle through the point and its two neighbours.
//!
//! # Orientation and order
//!
//! Open branches run keel to deck for stations (z increasing from the first to the last
//! point; on a tie, y increasing), aft to fore for waterlines and buttocks (x increasing; on
//! a tie, y resp. z increasing). Closed loops run counter-clockwise in the plane's 2-D
//! coordinates from their lexicographically smallest point. Branches are sorted by their
//! first point's 2-D coordinates.

use nurbs::{NurbsSurface, SurfaceDerivatives, Vec3};
use rayon::prelude::*;
use serde::Serialize;

use super::{model_size, param_grid};

/// An axis-aligned cutting plane.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub enum CutPlane {
    /// The station plane `x = c` (body plan).
    Station(f64),
    /// The waterline plane `z = c` (half-breadth plan).
    Waterline(f64),
    /// The buttock plane `y = c` (profile).
    Buttock(f64),
}

impl CutPlane {
    /// 2-D coordinates of a point in the plane's own drawing view: Station -> (y, z) (body
    /// plan), Waterline -> (x, y) (half-breadth plan), Buttock -> (x, z) (profile).
    pub fn coords(&self, p: Vec3) -> [f64; 2] {
        match self {
            CutPlane::Station(_) => [p.y, p.z],
            CutPlane::Waterline(_) => [p.x, p.y],
            CutPlane::Buttock(_) => [p.x, p.z],
        }
    }

    /// The plane's constant `c`.
    pub fn value(&self) -> f64 {
        match *self {
            CutPlane::Station(c) | CutPlane::Waterline(c) | CutPlane::Buttock(c) => c,
        }
    }

    /// The unit normal along the plane's axis: `+x`, `+z` or `+y`.
    pub fn axis(&self) -> Vec3 {
        match self {
            CutPlane::Station(_) => Vec3::new(1.0, 0.0, 0.0),
            CutPlane::Waterline(_) => Vec3::new(0.0, 0.0, 1.0),
            CutPlane::Buttock(_) => Vec3::new(0.0, 1.0, 0.0),
        }
    }

    /// `e_a x e_b` of the 2-D coordinates `(a, b)` of [`CutPlane::coords`]: `+x`, `+z`, `-y`.
    /// Counter-clockwise in the drawing is counter-clockwise about this normal.
    pub fn view_normal(&self) -> Vec3 {
        match self {
            CutPlane::Station(_) => Vec3::new(1.0, 0.0, 0.0),
            CutPlane::Waterline(_) => Vec3::new(0.0, 0.0, 1.0),
            CutPlane::Buttock(_) => Vec3::new(0.0, -1.0, 0.0),
        }
    }

    /// Signed distance of `p` from the plane, along [`CutPlane::axis`].
    pub fn signed_distance(&self, p: Vec3) -> f64 {
        self.axis().dot(p) - self.value()
    }

    /// `"station"`, `"waterline"` or `"buttock"`.
    pub fn kind_name(&self) -> &'static str {
        match self {
            CutPlane::Station(_) => "station",
            CutPlane::Waterline(_) => "waterline",
            CutPlane::Buttock(_) => "buttock",
        }
    }
}

/// One point of a cut curve.
#[derive(Clone, Debug, PartialEq)]
pub struct CutPoint {
    /// Surface parameters of the point.
    pub uv: (f64, f64),
    /// The surface point, on the plane to within the tolerance.
    pub point: Vec3,
    /// Signed curvature of the planar cut curve in the plane's 2-D coords (positive = turning
    /// counter-clockwise as the polyline is traversed), 1/length.
    pub curvature: f64,
}

/// One connected branch of a cut, ordered along the curve. A closed loop repeats its first
/// point at the end.
#[derive(Clone, Debug, PartialEq)]
pub struct CutCurve {
    pub plane: CutPlane,
    pub points: Vec<CutPoint>,
}

impl CutCurve {
    /// True for a closed loop (last point equal to the first, at least 4 points).
    pub fn is_closed(&self) -> bool {
        self.points.len() >= 4 && self.points.first().map(|p| p.uv) == self.points.last().map(|p| p.uv)
    }

    /// The points in the plane's 2-D coordinates.
    pub fn coords(&self) -> Vec<[f64; 2]> {
        self.points.iter().map(|p| self.plane.coords(p.point)).collect()
    }

    /// Length of the polyline.
    pub fn length(&self) -> f64 {
        self.points.windows(2).map(|w| w[0].point.distance(w[1].point)).sum()
    }
}

/// Settings of [`cut_surface`].
#[derive(Clone, Debug, PartialEq)]
pub struct CutOptions {
    /// Uniform parameter intervals `(u, v)` of the grid that finds the crossings, joined with
    /// the knot lines (each knot span split in at least two). Features smaller than a grid
    /// cell (two crossings of one grid edge, a loop inside one cell) can be missed.
    pub grid: (usize, usize),
    /// Densify until the polyline turns by at most this angle (degrees) at every point.
    pub max_segment_angle_deg: f64,
    /// Geometric tolerance relative to the model size (the diagonal of the control net's
    /// bounding box): grid nodes within it of the plane count as on the plane; points are
    /// refined to a hundredth of it; segments shorter than 1000 times it are not split.
    pub tolerance: f64,
}

impl Default for CutOptions {
    /// A 64 x 64 grid, 2 degrees (chord sag `R (1 - cos 1deg)` = 1.5e-4 R), tolerance 1e-12.
    fn default() -> Self {
        CutOptions { grid: (64, 64), max_segment_angle_deg: 2.0, tolerance: 1e-12 }
    }
}

/// The cut of `surface` by `plane`: its branches, each ordered along the curve (see the module
/// documentation for orientation and order). Empty when the plane misses the surface, when
/// the surface lies entirely in the plane, or for a non-finite plane value.
pub fn cut_surface(surface: &NurbsSurface, plane: CutPlane, options: &CutOptions) -> Vec<CutCurve> {
    match Sampler::new(surface, options) {
        Some(s) => s.cut(plane),
        None => Vec::new(),
    }
}

/// [`cut_surface`] for several planes, sampling the grid once and cutting in parallel. The
/// result is in the order of `planes` and equal to cutting each plane on its own.
pub fn cut_surface_many(surface: &NurbsSurface, planes: &[CutPlane], options: &CutOptions) -> Vec<Vec<CutCurve>> {
    match Sampler::new(surface, options) {
        Some(s) => planes.par_iter().map(|&p| s.cut(p)).collect(),
        None => vec![Vec::new(); planes.len()],
    }
}

/// Below this `|m . N|` (the sine of the angle between the plane and the tangent plane) the
/// analytic curvature `k_n / (m . N)` is replaced by the discrete one: it amplifies the
/// round-off of `k_n` (~1e-13 relative) by at most 1e6.
const TANGENT_SIN: f64 = 1e-6;

/// Upper bound on the points of one branch (a safeguard against endless splitting at a
/// corner; never reached at the default settings on the hulls tested).
const MAX_POINTS: usize = 50_000;

/// The discrete curvature fallback uses neighbours at least this far apart (relative to the
/// model size): with points accurate to ~1e-15 of the size, its round-off stays below
/// ~1e-15 / (1e-6)^2 = 1e-3 / size.
const DISCRETE_SPACING_REL: f64 = 1e-6;

/// Bound on the densification rounds: each halves the segments it splits.
const MAX_ROUNDS: usize = 40;

/// The surface sampled on the grid, shared by all planes.
struct Sampler<'a> {
    surface: &'a NurbsSurface,
    us: Vec<f64>,
    vs: Vec<f64>,
    /// Grid points, u-major.
    points: Vec<Vec3>,
    size: f64,
    opts: CutOptions,
    /// Parameter domain widths, to measure parameter distances on a unit square.
    du: f64,
    dv: f64,
}

/// A point of a branch under construction.
#[derive(Clone, Copy, Debug)]
struct Node {
    uv: (f64, f64),
    point: Vec3,
    /// Raw cut tangent `n x (S_u x S_v)` normalised; `None` where undefined.
    tangent: Option<Vec3>,
    /// The segment from this node to the next cannot be split any further.
    frozen: bool,
}

impl<'a> Sampler<'a> {
    fn new(surface: &'a NurbsSurface, options: &CutOptions) -> Option<Self> {
        let size = model_size(surface)?;
        let us = param_grid(surface.knots_u(), options.grid.0, true, 2);
        let vs = param_grid(surface.knots_v(), options.grid.1, true, 2);
        let mut points = Vec::with_capacity(us.len() * vs.len());
        for &u in &us {
            for &v in &vs {
                points.push(surface.point(u, v));
            }
        }
        let (u0, u1) = surface.domain_u();
        let (v0, v1) = surface.domain_v();
        let mut opts = options.clone();
        if !(opts.tolerance > 0.0 && opts.tolerance.is_finite()) {
            opts.tolerance = CutOptions::default().tolerance;
        }
        if !(opts.max_segment_angle_deg > 0.0 && opts.max_segment_angle_deg.is_finite()) {
            opts.max_segment_angle_deg = CutOptions::default().max_segment_angle_deg;
        }
        Some(Sampler { surface, us, vs, points, size, opts, du: u1 - u0, dv: v1 - v0 })
    }

    fn band(&self) -> f64 {
        self.opts.tolerance * self.size
    }

    fn ftol(&self) -> f64 {
        0.01 * self.band()
    }

    fn min_segment(&self) -> f64 {
        1e3 * self.band()
    }

    fn cut(&self, plane: CutPlane) -> Vec<CutCurve> {
        if !plane.value().is_finite() {
            return Vec::new();
        }
        let band = self.band();
        let f: Vec<f64> = self.points.iter().map(|&p| plane.signed_distance(p)).collect();
        let above = f.iter().filter(|&&x| x > band).count();
        let below = f.iter().filter(|&&x| x < -band).count();
        // On-plane nodes join the less populated side (ties: below).
        let zero_above = above < below;
        let class = move |x: f64| if zero_above { x >= -band } else { x > band };
        let raw = self.march(plane, &f, &class);
        let mut curves: Vec<CutCurve> =
            raw.into_iter().filter_map(|(nodes, closed)| self.finish_branch(plane, nodes, closed)).collect();
        curves.sort_by(|a, b| {
            let (pa, pb) = (plane.coords(a.points[0].point), plane.coords(b.points[0].point));
            pa[0].total_cmp(&pb[0]).then(pa[1].total_cmp(&pb[1])).then(a.points.len().cmp(&b.points.len()))
        });
        curves
    }

    /// Marching squares: the crossings of the grid edges, chained into branches.
    fn march(&self, plane: CutPlane, f: &[f64], class: &dyn Fn(f64) -> bool) -> Vec<(Vec<Node>, bool)> {
        let (nu, nv) = (self.us.len(), self.vs.len());
        if nu < 2 || nv < 2 {
            return Vec::new();
        }
        let n_h = (nu - 1) * nv; // edges along u: (i, j) - (i + 1, j), id i * nv + j
        let n_edges = n_h + nu * (nv - 1); // edges along v: (i, j) - (i, j + 1), id n_h + i * (nv - 1) + j
        let mut edge_crossing: Vec<Option<usize>> = vec![None; n_edges];
        let mut crossings: Vec<Node> = Vec::new();
        let mut adj: Vec<Vec<usize>> = Vec::new();
        let at = |i: usize, j: usize| class(f[i * nv + j]);
        let mut crossing_of = |edge: usize, crossings: &mut Vec<Node>, adj: &mut Vec<Vec<usize>>| -> usize {
            if let Some(k) = edge_crossing[edge] {
                return k;
            }
            let (a, b) = if edge < n_h {
                let (i, j) = (edge / nv, edge % nv);
                ((i, j), (i + 1, j))
            } else {
                let e = edge - n_h;
                let (i, j) = (e / (nv - 1), e % (nv - 1));
                ((i, j), (i, j + 1))
            };
            let (ia, ib) = (a.0 * nv + a.1, b.0 * nv + b.1);
            // Bracket from the "below" end to the "above" end.
            let (lo, hi, flo, fhi) = if class(f[ia]) { (b, a, f[ib], f[ia]) } else { (a, b, f[ia], f[ib]) };
            let uv_lo = (self.us[lo.0], self.vs[lo.1]);
            let uv_hi = (self.us[hi.0], self.vs[hi.1]);
            let node = self.root_on_segment(plane, uv_lo, uv_hi, flo, fhi, class);
            crossings.push(node);
            adj.push(Vec::new());
            let k = crossings.len() - 1;
            edge_crossing[edge] = Some(k);
            k
        };
        let h = |i: usize, j: usize| i * nv + j;
        let vedge = |i: usize, j: usize| n_h + i * (nv - 1) + j;
        for i in 0..nu - 1 {
            for j in 0..nv - 1 {
                let (ca, cb, cc, cd) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                // Edges in order: a-b, b-c, d-c, a-d.
                let edges = [h(i, j), vedge(i + 1, j), h(i, j + 1), vedge(i, j)];
                let crosses = [ca != cb, cb != cc, cd != cc, ca != cd];
                let count = crosses.iter().filter(|&&c| c).count();
                let mut link = |e0: usize, e1: usize, crossings: &mut Vec<Node>, adj: &mut Vec<Vec<usize>>| {
                    let k0 = crossing_of(edges[e0], crossings, adj);
                    let k1 = crossing_of(edges[e1], crossings, adj);
                    adj[k0].push(k1);
                    adj[k1].push(k0);
                };
                match count {
                    2 => {
                        let mut which = (0..4).filter(|&e| crosses[e]);
                        let (e0, e1) = (which.next().unwrap_or(0), which.next().unwrap_or(0));
                        link(e0, e1, &mut crossings, &mut adj);
                    }
                    4 => {
                        // Saddle: a and c on one side, b and d on the other.
                        let uc = 0.5 * (self.us[i] + self.us[i + 1]);
                        let vc = 0.5 * (self.vs[j] + self.vs[j + 1]);
                        let centre = class(plane.signed_distance(self.surface.point(uc, vc)));
                        if centre == ca {
                            // a and c joined through the centre: cut off the corners b and d.
                            link(0, 1, &mut crossings, &mut adj);
                            link(2, 3, &mut crossings, &mut adj);
                        } else {
                            link(0, 3, &mut crossings, &mut adj);
                            link(1, 2, &mut crossings, &mut adj);
                        }
                    }
                    _ => {}
                }
            }
        }
        chain(&crossings, &adj)
    }

    /// The point where `f` changes class on the parameter segment from `uv_lo` (below) to
    /// `uv_hi` (above), by safeguarded Newton iteration; the evaluated point of smallest `|f|`.
    fn root_on_segment(
        &self,
        plane: CutPlane,
        uv_lo: (f64, f64),
        uv_hi: (f64, f64),
        f_lo: f64,
        f_hi: f64,
        class: &dyn Fn(f64) -> bool,
    ) -> Node {
        let n = plane.axis();
        let (du, dv) = (uv_hi.0 - uv_lo.0, uv_hi.1 - uv_lo.1);
        let at = |t: f64| (uv_lo.0 + t * du, uv_lo.1 + t * dv);
        let ftol = self.ftol();
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut best = if f_lo.abs() <= f_hi.abs() { (0.0, f_lo.abs()) } else { (1.0, f_hi.abs()) };
        let mut t = if f_hi != f_lo { (f_lo / (f_lo - f_hi)).clamp(0.0, 1.0) } else { 0.5 };
        if !(t > 0.0 && t < 1.0) {
            t = 0.5;
        }
        let mut prev_abs = f64::INFINITY;
        if best.1 > ftol {
            for _ in 0..200 {
                let uv = at(t);
                let d = self.surface.derivatives(uv.0, uv.1);
                let ft = plane.signed_distance(d.point);
                if ft.abs() < best.1 {
                    best = (t, ft.abs());
                }
                if ft.abs() <= ftol {
                    break;
                }
                if class(ft) {
                    hi = t;
                } else {
                    lo = t;
                }
                if hi - lo <= 4.0 * f64::EPSILON {
                    break;
                }
                let slope = n.dot(d.su * du + d.sv * dv);
                let newton = t - ft / slope;
                t = if newton.is_finite() && newton > lo && newton < hi && ft.abs() <= 0.5 * prev_abs {
                    newton
                } else {
                    0.5 * (lo + hi)
                };
                prev_abs = ft.abs();
            }
        }
        let uv = at(best.0);
        self.node(plane, uv)
    }

    fn node(&self, plane: CutPlane, uv: (f64, f64)) -> Node {
        let d = self.surface.derivatives(uv.0, uv.1);
        Node { uv, point: d.point, tangent: raw_tangent(&d, plane.axis()), frozen: false }
    }

    /// A point of the cut between two consecutive points `a` and `b` of a branch: Newton
    /// iteration along the parametric gradient of `f` from the parameter midpoint, else a
    /// bracket along the perpendicular of the parameter chord. `None` if neither lands on the
    /// plane near the midpoint.
    fn between(&self, plane: CutPlane, a: &Node, b: &Node) -> Option<Node> {
        let ((u0, u1), (v0, v1)) = (self.surface.domain_u(), self.surface.domain_v());
        let clamp = |uv: (f64, f64)| (uv.0.clamp(u0, u1), uv.1.clamp(v0, v1));
        let mid = (0.5 * (a.uv.0 + b.uv.0), 0.5 * (a.uv.1 + b.uv.1));
        // Parameter distances on the unit square.
        let pdist = |p: (f64, f64), q: (f64, f64)| ((p.0 - q.0) / self.du).hypot((p.1 - q.1) / self.dv);
        let reach = pdist(a.uv, b.uv);
        let chord = a.point.distance(b.point);
        let min_len = 0.25 * self.min_segment();
        let ftol = self.ftol();
        let n = plane.axis();
        let accept = |node: Node| -> Option<Node> {
            let (da, db) = (node.point.distance(a.point), node.point.distance(b.point));
            let local = pdist(node.uv, mid) <= reach && da < chord && db < chord && da > min_len && db > min_len;
            local.then_some(node)
        };
        let mut uv = mid;
        for _ in 0..30 {
            let d = self.surface.derivatives(uv.0, uv.1);
            let fv = plane.signed_distance(d.point);
            if fv.abs() <= ftol {
                if let Some(node) = accept(Node { uv, point: d.point, tangent: raw_tangent(&d, n), frozen: false }) {
                    return Some(node);
                }
                break;
            }
            let (gu, gv) = (n.dot(d.su), n.dot(d.sv));
            let gg = gu * gu + gv * gv;
            if !(gg > 0.0) || !gg.is_finite() {
                break;
            }
            uv = clamp((uv.0 - fv * gu / gg, uv.1 - fv * gv / gg));
        }
        // Bracket along the perpendicular of the chord (unit-square metric).
        let (cu, cv) = ((b.uv.0 - a.uv.0) / self.du, (b.uv.1 - a.uv.1) / self.dv);
        let len = cu.hypot(cv);
        if !(len > 0.0) {
            return None;
        }
        let (pu, pv) = (-cv / len * self.du, cu / len * self.dv);
        let steps: i32 = 8;
        let sample = |k: i32| -> ((f64, f64), f64) {
            let s = reach * f64::from(k) / f64::from(steps);
            let uv = clamp((mid.0 + s * pu, mid.1 + s * pv));
            (uv, plane.signed_distance(self.surface.point(uv.0, uv.1)))
        };
        // Outward from the midpoint on both sides, the nearest sign change first.
        for k in 1..=steps {
            for dir in [1, -1] {
                let inner = sample(dir * (k - 1));
                let outer = sample(dir * k);
                if (inner.1 > 0.0) != (outer.1 > 0.0) {
                    let sign = |x: f64| x > 0.0;
                    let (lo, hi) = if inner.1 > 0.0 { (outer, inner) } else { (inner, outer) };
                    let node = self.root_on_segment(plane, lo.0, hi.0, lo.1, hi.1, &sign);
                    if plane.signed_distance(node.point).abs() <= self.band() {
                        return accept(node);
                    }
                    return None;
                }
            }
        }
        None
    }

    /// Densify, orient and attach curvatures; `None` for a branch of fewer than two distinct
    /// points (a plane touching the surface at a point).
    fn finish_branch(&self, plane: CutPlane, nodes: Vec<Node>, closed: bool) -> Option<CutCurve> {
        let dup = self.min_segment();
        let mut pts: Vec<Node> = Vec::with_capacity(nodes.len());
        for node in nodes {
            let distinct = match pts.last() {
                Some(last) => last.point.distance(node.point) > dup,
                None => true,
            };
            if distinct {
                pts.push(node);
            }
        }
        let mut closed = closed;
        if closed && pts.len() >= 2 && pts[0].point.distance(pts[pts.len() - 1].point) <= dup {
            pts.pop();
        }
        if pts.len() < 3 {
            closed = false;
        }
        if pts.len() < 2 {
            return None;
        }
        let mut pts = self.densify(plane, pts, closed);
        orient(plane, &mut pts, closed, dup);
        let mut points = curvatures(self.surface, plane, &pts, closed, DISCRETE_SPACING_REL * self.size);
        if closed {
            points.push(points[0].clone());
        }
        Some(CutCurve { plane, points })
    }

    fn densify(&self, plane: CutPlane, mut pts: Vec<Node>, closed: bool) -> Vec<Node> {
        let max_turn = self.opts.max_segment_angle_deg.to_radians();
        let min_len = self.min_segment();
        for _ in 0..MAX_ROUNDS {
            let n = pts.len();
            let segs = if closed { n } else { n - 1 };
            // The raw tangent field is continuous along a regular branch: orient it once by
            // the majority of the chords.
            let vote: f64 = (0..segs)
                .map(|k| {
                    let (a, b) = (&pts[k], &pts[(k + 1) % n]);
                    let chord = b.point - a.point;
                    a.tangent.map_or(0.0, |t| t.dot(chord).signum()) + b.tangent.map_or(0.0, |t| t.dot(chord).signum())
                })
                .sum();
            let sign = if vote < 0.0 { -1.0 } else { 1.0 };
            let turn_at = |k: usize| -> f64 {
                if !closed && (k == 0 || k == n - 1) {
                    return 0.0;
                }
                let prev = pts[(k + n - 1) % n].point;
                let next = pts[(k + 1) % n].point;
                angle(pts[k].point - prev, next - pts[k].point)
            };
            let mut split = vec![false; segs];
            for (k, s) in split.iter_mut().enumerate() {
                let (a, b) = (&pts[k], &pts[(k + 1) % n]);
                if a.frozen {
                    continue;
                }
                let chord = b.point - a.point;
                if chord.norm() <= min_len {
                    continue;
                }
                let mut over = turn_at(k) > max_turn || turn_at((k + 1) % n) > max_turn;
                for t in [a.tangent, b.tangent].into_iter().flatten() {
                    over |= angle(t * sign, chord) > 0.5 * max_turn;
                }
                *s = over;
            }
            if !split.iter().any(|&s| s) || n >= MAX_POINTS {
                break;
            }
            let mut out = Vec::with_capacity(n * 2);
            for k in 0..n {
                let mut a = pts[k];
                if k < segs && split[k] && out.len() + (n - k) < MAX_POINTS {
                    let b = &pts[(k + 1) % n];
                    match self.between(plane, &a, b) {
                        Some(m) => {
                            out.push(a);
                            out.push(m);
                            continue;
                        }
                        None => a.frozen = true,
                    }
                }
                out.push(a);
            }
            pts = out;
        }
        pts
    }
}

/// The unit tangent `n x (S_u x S_v)` of the cut by a plane of normal `n`; `None` where the
/// surface normal is undefined or the plane is tangent to the surface.
fn raw_tangent(d: &SurfaceDerivatives, n: Vec3) -> Option<Vec3> {
    let normal = regular_normal(d)?;
    let t = n.cross(normal);
    (t.norm() >= TANGENT_SIN).then(|| t.normalized()).flatten()
}

/// The unit normal where the parametrisation is regular enough for second-order quantities:
/// `|S_u x S_v| >= DEGENERATE_REL (|S_u|^2 + |S_v|^2)`; `None` at and right next to a
/// collapsed edge (a pole, a pointed stem), where the fundamental forms are round-off.
pub(crate) fn regular_normal(d: &SurfaceDerivatives) -> Option<Vec3> {
    let c = d.su.cross(d.sv);
    let scale = d.su.norm_squared() + d.sv.norm_squared();
    (c.norm() >= DEGENERATE_REL * scale).then(|| c.normalized()).flatten()
}

/// Below this ratio `|S_u x S_v| / (|S_u|^2 + |S_v|^2)` (the sine of the angle between the
/// parameter lines times the ratio of their speeds) a point counts as degenerate: the
/// curvature from the fundamental forms then carries a relative round-off of ~1e-16 / 1e-8.
pub(crate) const DEGENERATE_REL: f64 = 1e-8;

/// Angle between two vectors, 0 if either is zero.
fn angle(a: Vec3, b: Vec3) -> f64 {
    let c = a.cross(b).norm();
    let d = a.dot(b);
    if c == 0.0 && d == 0.0 {
        0.0
    } else {
        c.atan2(d)
    }
}

/// Chain crossings joined through cells into branches: open ones first (from each unvisited
/// crossing with one neighbour, in creation order), then closed loops.
fn chain(crossings: &[Node], adj: &[Vec<usize>]) -> Vec<(Vec<Node>, bool)> {
    let mut visited = vec![false; crossings.len()];
    let mut out = Vec::new();
    let walk = |start: usize, visited: &mut Vec<bool>| -> Vec<usize> {
        let mut path = vec![start];
        visited[start] = true;
        let (mut prev, mut cur) = (usize::MAX, start);
        loop {
            let next = adj[cur].iter().copied().find(|&k| k != prev && !visited[k]);
            match next {
                Some(k) => {
                    visited[k] = true;
                    path.push(k);
                    prev = cur;
                    cur = k;
                }
                None => break,
            }
        }
        path
    };
    for k in 0..crossings.len() {
        if !visited[k] && adj[k].len() == 1 {
            let path = walk(k, &mut visited);
            out.push((path.into_iter().map(|i| crossings[i]).collect(), false));
        }
    }
    for k in 0..crossings.len() {
        if !visited[k] && !adj[k].is_empty() {
            let path = walk(k, &mut visited);
            let closed = path.len() >= 3 && adj[path[path.len() - 1]].contains(&k);
            out.push((path.into_iter().map(|i| crossings[i]).collect(), closed));
        }
    }
    out
}

/// Orient a branch as documented in the module: open branches by their end points, closed
/// loops counter-clockwise from their lexicographically smallest point.
fn orient(plane: CutPlane, pts: &mut [Node], closed: bool, eps: f64) {
    let c = |node: &Node| plane.coords(node.point);
    if closed {
        let area: f64 = (0..pts.len())
            .map(|k| {
                let (p, q) = (c(&pts[k]), c(&pts[(k + 1) % pts.len()]));
                p[0] * q[1] - p[1] * q[0]
            })
            .sum();
        if area < 0.0 {
            pts.reverse();
        }
        let start = (0..pts.len())
            .min_by(|&i, &j| {
                let (p, q) = (c(&pts[i]), c(&pts[j]));
                p[0].total_cmp(&q[0]).then(p[1].total_cmp(&q[1]))
            })
            .unwrap_or(0);
        pts.rotate_left(start);
        return;
    }
    let (first, last) = (pts[0].point, pts[pts.len() - 1].point);
    let (primary, secondary) = match plane {
        CutPlane::Station(_) => (last.z - first.z, last.y - first.y),
        CutPlane::Waterline(_) => (last.x - first.x, last.y - first.y),
        CutPlane::Buttock(_) => (last.x - first.x, last.z - first.z),
    };
    if primary < -eps || (primary.abs() <= eps && secondary < 0.0) {
        pts.reverse();
    }
}

/// Signed curvature at each point (see the module documentation), analytic where defined,
/// else discrete.
fn curvatures(surface: &NurbsSurface, plane: CutPlane, pts: &[Node], closed: bool, spacing: f64) -> Vec<CutPoint> {
    let n = pts.len();
    let neighbour = |k: usize, step: isize| -> Option<usize> {
        let j = k as isize + step;
        if closed {
            Some(j.rem_euclid(n as isize) as usize)
        } else {
            (j >= 0 && (j as usize) < n).then_some(j as usize)
        }
    };
    // The nearest neighbour on each side at least `spacing` away: closer points (crowded at a
    // collapsed edge) would turn round-off into curvature.
    let far = |k: usize, step: isize| -> Option<usize> {
        let mut j = k;
        for _ in 0..n {
            j = neighbour(j, step)?;
            if j == k {
                return None;
            }
            if pts[j].point.distance(pts[k].point) >= spacing {
                return Some(j);
            }
        }
        None
    };
    let discrete: Vec<Option<f64>> = (0..n)
        .map(|k| {
            let (i, j) = (far(k, -1)?, far(k, 1)?);
            if i == j {
                return None;
            }
            discrete_curvature(plane.coords(pts[i].point), plane.coords(pts[k].point), plane.coords(pts[j].point))
        })
        .collect();
    let analytic: Vec<Option<f64>> = (0..n)
        .map(|k| {
            let prev = neighbour(k, -1).unwrap_or(k);
            let next = neighbour(k, 1).unwrap_or(k);
            let dir = pts[next].point - pts[prev].point;
            let d = surface.derivatives(pts[k].uv.0, pts[k].uv.1);
            analytic_curvature(&d, plane, dir)
        })
        .collect();
    (0..n)
        .map(|k| {
            let curvature = analytic[k]
                .or(discrete[k])
                .or_else(|| {
                    // An end point on a degenerate spot: its neighbour's value.
                    let j = if k == 0 { 1.min(n - 1) } else { k - 1 };
                    analytic[j].or(discrete[j])
                })
                .unwrap_or(0.0);
            CutPoint { uv: pts[k].uv, point: pts[k].point, curvature }
        })
        .collect()
}

/// `kappa = k_n / (m . N)` of the module documentation, for the cut traversed along `dir`;
/// `None` where the normal is undefined or `|m . N| < TANGENT_SIN`.
pub(crate) fn analytic_curvature(d: &SurfaceDerivatives, plane: CutPlane, dir: Vec3) -> Option<f64> {
    let normal = regular_normal(d)?;
    let axis = plane.axis();
    let (mut a, mut b) = (axis.dot(d.sv), -axis.dot(d.su));
    let mut t = d.su * a + d.sv * b;
    if t.dot(dir) < 0.0 {
        (a, b, t) = (-a, -b, -t);
    }
    let tt = t.dot(t);
    if !(tt > 0.0) || !tt.is_finite() {
        return None;
    }
    let kn = (d.suu * (a * a) + d.suv * (2.0 * a * b) + d.svv * (b * b)).dot(normal) / tt;
    let m = plane.view_normal().cross(t / tt.sqrt());
    let mn = m.dot(normal);
    if !(mn.abs() >= TANGENT_SIN) {
        return None;
    }
    let kappa = kn / mn;
    kappa.is_finite().then_some(kappa)
}

/// Signed curvature of the circle through three points, counter-clockwise positive:
/// `2 ((b - a) x (c - b)) / (|b - a| |c - b| |c - a|)`. `None` if two points coincide.
pub(crate) fn discrete_curvature(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<f64> {
    let (ab, bc) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
    let ac = [c[0] - a[0], c[1] - a[1]];
    let denom = ab[0].hypot(ab[1]) * bc[0].hypot(bc[1]) * ac[0].hypot(ac[1]);
    let k = 2.0 * (ab[0] * bc[1] - ab[1] * bc[0]) / denom;
    (denom > 0.0 && k.is_finite()).then_some(k)
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::KnotVector;

    /// A bilinear-in-x, quadratic-in-z test sheet `y = a + b z^2` over x in [0, 1], z in [0, 1].
    fn parabolic_sheet(a: f64, b: f64) -> NurbsSurface {
        let ku = KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
        // z = u, y = a + b u^2: Bernstein coefficients of u^2 are (0, 0, 1).
        let mut pts = Vec::new();
        for (z, y) in [(0.0, a), (0.5, a), (1.0, a + b)] {
            for x in [0.0, 1.0] {
                pts.push(Vec3::new(x, y, z));
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, None).expect("valid")
    }

    #[test]
    fn coords_and_view_normals_are_right_handed() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert_eq!(CutPlane::Station(0.0).coords(p), [2.0, 3.0]);
        assert_eq!(CutPlane::Waterline(0.0).coords(p), [1.0, 2.0]);
        assert_eq!(CutPlane::Buttock(0.0).coords(p), [1.0, 3.0]);
        for plane in [CutPlane::Station(0.5), CutPlane::Waterline(0.5), CutPlane::Buttock(0.5)] {
            // e_a x e_b from unit vectors mapped to (1, 0) and (0, 1) in the view.
            let basis = [Vec3::new(1., 0., 0.), Vec3::new(0., 1., 0.), Vec3::new(0., 0., 1.)];
            let ea = basis.iter().copied().find(|&e| plane.coords(e) == [1.0, 0.0]).expect("a axis");
            let eb = basis.iter().copied().find(|&e| plane.coords(e) == [0.0, 1.0]).expect("b axis");
            assert_eq!(ea.cross(eb), plane.view_normal(), "{plane:?}");
            assert_eq!(plane.signed_distance(Vec3::new(0.5, 0.5, 0.5)), 0.0);
            assert_eq!(plane.value(), 0.5);
        }
    }

    #[test]
    fn discrete_curvature_of_a_circle_is_one_over_radius_and_signed() {
        let r = 2.5;
        let pt = |a: f64| [r * a.cos(), r * a.sin()];
        let k = discrete_curvature(pt(0.1), pt(0.3), pt(0.5)).expect("distinct");
        // Three points on a circle define it exactly: round-off only.
        assert!((k - 1.0 / r).abs() <= 1e-12, "{k}");
        let k = discrete_curvature(pt(0.5), pt(0.3), pt(0.1)).expect("distinct");
        assert!((k + 1.0 / r).abs() <= 1e-12, "{k}");
        assert_eq!(discrete_curvature([0., 0.], [0., 0.], [1., 1.]), None);
    }

    #[test]
    fn station_of_a_parabolic_sheet_is_the_parabola_with_its_curvature() {
        let (a, b) = (0.3, 0.8);
        let s = parabolic_sheet(a, b);
        let cuts = cut_surface(&s, CutPlane::Station(0.37), &CutOptions::default());
        assert_eq!(cuts.len(), 1);
        let c = &cuts[0];
        // Keel to deck: z from 0 to 1.
        assert!(c.points[0].point.z.abs() <= 1e-12 && (c.points[c.points.len() - 1].point.z - 1.0).abs() <= 1e-12);
        for p in &c.points {
            let z = p.point.z;
            // y = a + b z^2 traversed with z increasing in (y, z): kappa = -y''/(1+y'^2)^1.5
            // with y as a function of z (see tests/shape/analysis.rs for the derivation).
            let want = -(2.0 * b) / (1.0 + (2.0 * b * z).powi(2)).powf(1.5);
            assert!((p.curvature - want).abs() <= 1e-12, "z {z}: {} vs {want}", p.curvature);
            assert!((p.point.y - (a + b * z * z)).abs() <= 1e-12);
            assert!((p.point.x - 0.37).abs() <= 1e-14);
        }
    }

    #[test]
    fn plane_missing_the_surface_or_non_finite_gives_nothing() {
        let s = parabolic_sheet(0.3, 0.8);
        assert!(cut_surface(&s, CutPlane::Station(2.0), &CutOptions::default()).is_empty());
        assert!(cut_surface(&s, CutPlane::Waterline(-1.0), &CutOptions::default()).is_empty());
        assert!(cut_surface(&s, CutPlane::Buttock(f64::NAN), &CutOptions::default()).is_empty());
    }

    #[test]
    fn a_boundary_edge_in_the_plane_is_found_from_either_side() {
        let s = parabolic_sheet(0.3, 0.8);
        // x = 0 and x = 1 are the v edges; the surface lies on one side of each.
        for x in [0.0, 1.0] {
            let cuts = cut_surface(&s, CutPlane::Station(x), &CutOptions::default());
            assert_eq!(cuts.len(), 1, "x = {x}");
            assert!(cuts[0].points.iter().all(|p| (p.point.x - x).abs() <= 1e-15));
            let zs: Vec<f64> = cuts[0].points.iter().map(|p| p.point.z).collect();
            assert!(zs.windows(2).all(|w| w[1] > w[0]), "keel to deck");
        }
    }
}
