//! Planar cuts of a surface by planes normal to a coordinate axis ([`AxisPlane`]): the
//! intersection curves as ordered polylines whose points lie on the plane and carry the cut
//! curve's signed curvature.
//!
//! # Method
//!
//! 1. **Grid.** The signed distance `f(u, v) = n . S(u, v) - c` of the surface from the plane
//!    is sampled on a parameter grid: [`CutOptions::grid`] uniform intervals joined with the
//!    knot lines, every knot span split in at least two ([`KnotVector::param_grid`]).
//! 2. **Marching squares.** Each grid node is classed as above or below the plane; each grid
//!    edge whose ends differ holds one crossing, and each cell joins its crossings in pairs
//!    (ambiguous saddle cells by the class of the cell centre). Nodes within the tolerance
//!    band `|f| <= tolerance * size` of the plane are put on the less populated side, so a plane
//!    through a whole grid line (a boundary edge lying in the plane, a flat patch lying in it
//!    up to a knot line) still yields the line along it, whichever side of the plane the rest
//!    of the surface lies on.
//! 3. **Refinement.** Each crossing is moved onto the plane by safeguarded Newton iteration
//!    (bisection whenever a Newton step leaves the bracket or fails to halve `|f|`) along its
//!    grid edge, `d f / d s = n . (S_u du + S_v dv)`, until `|f| <= tolerance * size / 100`,
//!    or until a point within the band has its Newton step leave the bracket: the bracket is
//!    one of the nodes' classes, whose change within the band is at the band's edge, not at
//!    `f = 0`, and bisecting towards it would only move away from the plane (the point of
//!    least `|f|` is kept either way).
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
//! `kappa (m . N) = k_n`, so `kappa = k_n / (m . N)` with `m = n_view x t / |t|`
//! ([`cut_curvature`]). `n_view` ([`AxisPlane::view_normal`]) is the normal that makes the
//! plane's 2-D drawing coordinates right-handed (`+x` for an x-plane's `(y, z)`, `+z` for a
//! z-plane's `(x, y)`, `-y` for a y-plane's `(x, z)`): `kappa > 0` when the curve turns
//! counter-clockwise in [`AxisPlane::coords`] as the polyline is traversed. Where the plane is
//! (nearly) tangent to the surface (`|m . N| < 1e-6`) or the normal is undefined (a collapsed
//! edge), the curvature is the discrete one of the polyline: the inverse radius of the circle
//! through the point and its two neighbours ([`three_point_curvature`]).
//!
//! # Orientation and order
//!
//! Open branches run so that, from their first point to their last, the `z` coordinate
//! increases for an x-plane (the second drawing coordinate; on a tie within the tolerance,
//! `y` increasing), and the `x` coordinate increases for a y- or z-plane (the first drawing
//! coordinate; on a tie, the second increasing). Closed loops run counter-clockwise in the
//! plane's 2-D coordinates from their lexicographically smallest point. Branches are sorted
//! by their first point's 2-D coordinates.

use rayon::prelude::*;

#[cfg(doc)]
use crate::KnotVector;
use crate::{AxisPlane, FirstDerivatives, FirstDerivativesCache, NurbsSurface, SurfaceDerivatives, Vec3};

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
    /// The cutting plane.
    pub plane: AxisPlane,
    /// The points in order along the branch.
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

/// The cut of `surface` by `plane`: its branches, each ordered along the curve. Empty when the
/// plane misses the surface, when the surface lies entirely in the plane, or for a non-finite
/// plane value.
///
/// Found by marching squares on a parameter grid, refined onto the plane by safeguarded Newton
/// iteration and densified until the polyline turns by at most
/// [`CutOptions::max_segment_angle_deg`] per point; each point carries the signed curvature of
/// the planar curve ([`cut_curvature`]). Open branches run with `z` increasing for an x-plane
/// and with `x` increasing for a y- or z-plane (on a tie, the other drawing coordinate
/// increasing); closed loops run counter-clockwise in [`AxisPlane::coords`] from their
/// lexicographically smallest point; branches are sorted by their first point's coordinates.
///
/// `plane` is an [`AxisPlane`] or any type that converts into one.
///
/// ```
/// use nurbs::{cut_surface, AxisPlane, CutOptions, KnotVector, NurbsSurface, Vec3};
///
/// // The quarter cylinder x^2 + y^2 = r^2, x, y >= 0, 0 <= z <= 2: rational quadratic
/// // around z (u), linear along z (v).
/// let r = 1.5;
/// let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
/// let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0])?;
/// let (mut pts, mut w) = (Vec::new(), Vec::new());
/// for (x, y, wi) in [(r, 0.0, 1.0), (r, r, std::f64::consts::FRAC_1_SQRT_2), (0.0, r, 1.0)] {
///     for z in [0.0, 2.0] {
///         pts.push(Vec3::new(x, y, z));
///         w.push(wi);
///     }
/// }
/// let cylinder = NurbsSurface::try_new(ku, kv, &pts, Some(&w))?;
///
/// // The plane z = 0.7 cuts it in one quarter circle of radius r.
/// let cuts = cut_surface(&cylinder, AxisPlane::z(0.7), &CutOptions::default());
/// assert_eq!(cuts.len(), 1);
/// let arc = &cuts[0];
/// for p in &arc.points {
///     assert!((p.point.z - 0.7).abs() < 1e-12); // on the plane
///     assert!((p.point.x.hypot(p.point.y) - r).abs() < 1e-12); // on the circle
///     // Run with x increasing, from (0, r) to (r, 0): clockwise in (x, y), curvature -1/r.
///     assert!((p.curvature + 1.0 / r).abs() < 1e-9, "{}", p.curvature);
/// }
/// assert!(arc.points[0].point.x < 1e-12 && (arc.points.last().unwrap().point.x - r).abs() < 1e-12);
/// // A quarter of the circumference, to the chord sag of the 2-degree densification.
/// assert!((arc.length() - 0.5 * std::f64::consts::PI * r).abs() < 1e-3 * r);
/// // A plane that misses the surface gives nothing.
/// assert!(cut_surface(&cylinder, AxisPlane::z(3.0), &CutOptions::default()).is_empty());
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn cut_surface(surface: &NurbsSurface, plane: impl Into<AxisPlane>, options: &CutOptions) -> Vec<CutCurve> {
    match Sampler::new(surface, options) {
        Some(s) => s.cut(plane.into()),
        None => Vec::new(),
    }
}

/// [`cut_surface`] for several planes, sampling the grid once and cutting in parallel (on
/// rayon's current thread pool). The result is in the order of `planes` and equal to cutting
/// each plane on its own.
///
/// ```
/// use nurbs::{cut_surface, cut_surface_many, AxisPlane, CutOptions, KnotVector, NurbsSurface, Vec3};
///
/// // The bilinear patch z = x y over [0, 1]^2 (control points at the corners).
/// let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0])?;
/// let corners = [(0.0, 0.0), (0.0, 1.0), (1.0, 0.0), (1.0, 1.0)].map(|(x, y)| Vec3::new(x, y, x * y));
/// let patch = NurbsSurface::try_new(k.clone(), k, &corners, None)?;
/// let planes = [AxisPlane::x(0.5), AxisPlane::z(0.25), AxisPlane::y(2.0)];
/// let opts = CutOptions::default();
/// let all = cut_surface_many(&patch, &planes, &opts);
/// for (plane, cuts) in planes.iter().zip(&all) {
///     assert_eq!(cuts, &cut_surface(&patch, *plane, &opts));
/// }
/// // x = 0.5 is the straight line z = y / 2; y = 2 misses the patch.
/// assert!(all[0][0].points.iter().all(|p| (p.point.z - 0.5 * p.point.y).abs() < 1e-12 && p.curvature.abs() < 1e-9));
/// assert!(all[2].is_empty());
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn cut_surface_many<P: Into<AxisPlane> + Copy>(
    surface: &NurbsSurface,
    planes: &[P],
    options: &CutOptions,
) -> Vec<Vec<CutCurve>> {
    match Sampler::new(surface, options) {
        Some(s) => {
            let planes: Vec<AxisPlane> = planes.iter().map(|&p| p.into()).collect();
            planes.par_iter().map(|&p| s.cut(p)).collect()
        }
        None => vec![Vec::new(); planes.len()],
    }
}

/// Below this `|m . N|` (the sine of the angle between the plane and the tangent plane) the
/// analytic curvature `k_n / (m . N)` is replaced by the discrete one: it amplifies the
/// round-off of `k_n` (~1e-13 relative) by at most 1e6.
const TANGENT_SIN: f64 = 1e-6;

/// Upper bound on the points of one branch (a safeguard against endless splitting at a
/// corner; never reached at the default settings in the tests).
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
        let size = surface.model_size()?;
        let us = surface.knots_u().param_grid(options.grid.0, true, 2);
        let vs = surface.knots_v().param_grid(options.grid.1, true, 2);
        // u-major from the v-major grid (each point bit-identical to `surface.point`).
        let grid = surface.points_grid(&us, &vs);
        let points: Vec<Vec3> = (0..us.len()).flat_map(|i| grid.iter().skip(i).step_by(us.len()).copied()).collect();
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

    fn cut(&self, plane: AxisPlane) -> Vec<CutCurve> {
        if !plane.value.is_finite() {
            return Vec::new();
        }
        let band = self.band();
        let f: Vec<f64> = self.points.iter().map(|&p| plane.signed_distance(p)).collect();
        let above = f.iter().filter(|&&x| x > band).count();
        let below = f.iter().filter(|&&x| x < -band).count();
        // On-plane nodes join the less populated side (ties: below).
        let zero_above = above < below;
        let class = move |x: f64| if zero_above { x >= -band } else { x > band };
        // Each node's class, once: the marching reads each node up to four times. A plane with
        // every node on one side has no crossing.
        let side: Vec<bool> = f.iter().map(|&x| class(x)).collect();
        if side.iter().all(|&c| c == side[0]) {
            return Vec::new();
        }
        let raw = self.march(plane, &f, &side, &class);
        let mut curves: Vec<CutCurve> =
            raw.into_iter().filter_map(|(nodes, closed)| self.finish_branch(plane, nodes, closed)).collect();
        curves.sort_by(|a, b| {
            let (pa, pb) = (plane.coords(a.points[0].point), plane.coords(b.points[0].point));
            pa[0].total_cmp(&pb[0]).then(pa[1].total_cmp(&pb[1])).then(a.points.len().cmp(&b.points.len()))
        });
        curves
    }

    /// Marching squares: the crossings of the grid edges, chained into branches.
    /// `side` is `class` of each node's `f`.
    fn march(&self, plane: AxisPlane, f: &[f64], side: &[bool], class: &dyn Fn(f64) -> bool) -> Vec<(Vec<Node>, bool)> {
        let (nu, nv) = (self.us.len(), self.vs.len());
        if nu < 2 || nv < 2 {
            return Vec::new();
        }
        // The crossing on each grid edge, `NONE` until found (4 bytes an edge: the table is
        // cleared for every plane).
        const NONE: u32 = u32::MAX;
        let n_h = (nu - 1) * nv; // edges along u: (i, j) - (i + 1, j), id i * nv + j
        let n_edges = n_h + nu * (nv - 1); // edges along v: (i, j) - (i, j + 1), id n_h + i * (nv - 1) + j
        let mut edge_crossing: Vec<u32> = vec![NONE; n_edges];
        let mut crossings: Vec<Node> = Vec::new();
        let mut adj: Vec<Vec<usize>> = Vec::new();
        // One cache of basis functions for the whole cut: consecutive root searches share a
        // knot span or a grid line (a fresh cache per search was a tenth of a cut's cost).
        let mut eval = FirstDerivativesCache::new(self.surface);
        let at = |i: usize, j: usize| side[i * nv + j];
        let mut crossing_of = |edge: usize, crossings: &mut Vec<Node>, adj: &mut Vec<Vec<usize>>| -> usize {
            if edge_crossing[edge] != NONE {
                return edge_crossing[edge] as usize;
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
            let (lo, hi, flo, fhi) = if side[ia] { (b, a, f[ib], f[ia]) } else { (a, b, f[ia], f[ib]) };
            let uv_lo = (self.us[lo.0], self.vs[lo.1]);
            let uv_hi = (self.us[hi.0], self.vs[hi.1]);
            let node = self.root_on_segment(plane, (uv_lo, uv_hi), (flo, fhi), class, &mut eval);
            crossings.push(node);
            adj.push(Vec::new());
            let k = crossings.len() - 1;
            edge_crossing[edge] = u32::try_from(k).expect("fewer crossings than grid edges");
            k
        };
        let h = |i: usize, j: usize| i * nv + j;
        let vedge = |i: usize, j: usize| n_h + i * (nv - 1) + j;
        for i in 0..nu - 1 {
            // Two rows of nodes wholly on one side, the same for both, cross nothing.
            let rows = &side[i * nv..(i + 2) * nv];
            if rows.iter().all(|&c| c == rows[0]) {
                continue;
            }
            for j in 0..nv - 1 {
                let (ca, cb, cc, cd) = (at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1));
                if ca == cb && cb == cc && cc == cd {
                    continue;
                }
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
        plane: AxisPlane,
        (uv_lo, uv_hi): ((f64, f64), (f64, f64)),
        (f_lo, f_hi): (f64, f64),
        class: &dyn Fn(f64) -> bool,
        eval: &mut FirstDerivativesCache<'_>,
    ) -> Node {
        let n = plane.normal();
        let (du, dv) = (uv_hi.0 - uv_lo.0, uv_hi.1 - uv_lo.1);
        let at = |t: f64| (uv_lo.0 + t * du, uv_lo.1 + t * dv);
        let ftol = self.ftol();
        let (mut lo, mut hi) = (0.0f64, 1.0f64);
        let mut best = if f_lo.abs() <= f_hi.abs() { (0.0, f_lo.abs()) } else { (1.0, f_hi.abs()) };
        // The evaluation at the best t so far (none at the segment's ends); `eval` caches the
        // basis functions (along a grid edge one of u and v is fixed).
        let mut best_d: Option<FirstDerivatives> = None;
        let mut t = if f_hi != f_lo { (f_lo / (f_lo - f_hi)).clamp(0.0, 1.0) } else { 0.5 };
        if !(t > 0.0 && t < 1.0) {
            t = 0.5;
        }
        let mut prev_abs = f64::INFINITY;
        if best.1 > ftol {
            for _ in 0..200 {
                let uv = at(t);
                let d = eval.at(uv.0, uv.1);
                let ft = plane.signed_distance(d.point);
                if ft.abs() < best.1 {
                    best = (t, ft.abs());
                    best_d = Some(d);
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
                let inside = newton.is_finite() && newton > lo && newton < hi;
                // Within the on-plane band a class need not be the sign of f: the bracket then
                // closes on the band's edge, and a Newton step out of it means that f's zero is
                // outside, every t inside the bracket farther from the plane than this one
                // (step 3).
                if !inside && class(ft) != (ft > 0.0) {
                    break;
                }
                t = if inside && ft.abs() <= 0.5 * prev_abs { newton } else { 0.5 * (lo + hi) };
                prev_abs = ft.abs();
            }
        }
        let uv = at(best.0);
        let d = best_d.unwrap_or_else(|| eval.at(uv.0, uv.1));
        Node { uv, point: d.point, tangent: raw_tangent(&d, plane.normal()), frozen: false }
    }

    /// A point of the cut between two consecutive points `a` and `b` of a branch: Newton
    /// iteration along the parametric gradient of `f` from the parameter midpoint, else a
    /// bracket along the perpendicular of the parameter chord. `None` if neither lands on the
    /// plane near the midpoint.
    fn between(&self, plane: AxisPlane, a: &Node, b: &Node) -> Option<Node> {
        let ((u0, u1), (v0, v1)) = (self.surface.domain_u(), self.surface.domain_v());
        let clamp = |uv: (f64, f64)| (uv.0.clamp(u0, u1), uv.1.clamp(v0, v1));
        let mid = (0.5 * (a.uv.0 + b.uv.0), 0.5 * (a.uv.1 + b.uv.1));
        // Parameter distances on the unit square.
        let pdist = |p: (f64, f64), q: (f64, f64)| ((p.0 - q.0) / self.du).hypot((p.1 - q.1) / self.dv);
        let reach = pdist(a.uv, b.uv);
        let chord = a.point.distance(b.point);
        let min_len = 0.25 * self.min_segment();
        let ftol = self.ftol();
        let n = plane.normal();
        let accept = |node: Node| -> Option<Node> {
            let (da, db) = (node.point.distance(a.point), node.point.distance(b.point));
            let local = pdist(node.uv, mid) <= reach && da < chord && db < chord && da > min_len && db > min_len;
            local.then_some(node)
        };
        let mut uv = mid;
        for _ in 0..30 {
            let d = self.surface.first_derivatives(uv.0, uv.1);
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
                    let mut eval = FirstDerivativesCache::new(self.surface);
                    let node = self.root_on_segment(plane, (lo.0, hi.0), (lo.1, hi.1), &sign, &mut eval);
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
    fn finish_branch(&self, plane: AxisPlane, nodes: Vec<Node>, closed: bool) -> Option<CutCurve> {
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

    fn densify(&self, plane: AxisPlane, mut pts: Vec<Node>, closed: bool) -> Vec<Node> {
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
            // Each point's turn, once (each is read for the segments on both sides of it).
            let turns: Vec<f64> = (0..n).map(turn_at).collect();
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
                let mut over = turns[k] > max_turn || turns[(k + 1) % n] > max_turn;
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
fn raw_tangent(d: &FirstDerivatives, n: Vec3) -> Option<Vec3> {
    let normal =
        SurfaceDerivatives { point: d.point, su: d.su, sv: d.sv, ..SurfaceDerivatives::default() }.regular_normal()?;
    let t = n.cross(normal);
    (t.norm() >= TANGENT_SIN).then(|| t.normalized()).flatten()
}

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
fn orient(plane: AxisPlane, pts: &mut [Node], closed: bool, eps: f64) {
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
    let (a, b) = plane.run_axes();
    let (primary, secondary) = (last[a] - first[a], last[b] - first[b]);
    if primary < -eps || (primary.abs() <= eps && secondary < 0.0) {
        pts.reverse();
    }
}

/// Signed curvature at each point (see the module documentation), analytic where defined,
/// else discrete.
fn curvatures(surface: &NurbsSurface, plane: AxisPlane, pts: &[Node], closed: bool, spacing: f64) -> Vec<CutPoint> {
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
    // The discrete curvature, computed only where the analytic one is undefined.
    let discrete = |k: usize| -> Option<f64> {
        let (i, j) = (far(k, -1)?, far(k, 1)?);
        if i == j {
            return None;
        }
        three_point_curvature(plane.coords(pts[i].point), plane.coords(pts[k].point), plane.coords(pts[j].point))
    };
    let analytic: Vec<Option<f64>> = (0..n)
        .map(|k| {
            let prev = neighbour(k, -1).unwrap_or(k);
            let next = neighbour(k, 1).unwrap_or(k);
            let dir = pts[next].point - pts[prev].point;
            let d = surface.derivatives(pts[k].uv.0, pts[k].uv.1);
            cut_curvature(&d, plane, dir)
        })
        .collect();
    (0..n)
        .map(|k| {
            let curvature = analytic[k]
                .or_else(|| discrete(k))
                .or_else(|| {
                    // An end point on a degenerate spot: its neighbour's value.
                    let j = if k == 0 { 1.min(n - 1) } else { k - 1 };
                    analytic[j].or_else(|| discrete(j))
                })
                .unwrap_or(0.0);
            CutPoint { uv: pts[k].uv, point: pts[k].point, curvature }
        })
        .collect()
}

/// The signed curvature, at the surface point of `d`, of the planar curve in which `plane`
/// cuts the surface, traversed along `dir`: `kappa = k_n / (m . N)` by Meusnier's theorem,
/// with `k_n` the normal curvature along the cut's tangent `t = n x (S_u x S_v)` (oriented
/// along `dir`), `N` the unit surface normal and `m = n_view x t / |t|`
/// ([`AxisPlane::view_normal`]); positive when the curve turns counter-clockwise in
/// [`AxisPlane::coords`]. `None` where the normal is undefined
/// ([`SurfaceDerivatives::regular_normal`]) or the plane is nearly tangent to the surface
/// (`|m . N| < 1e-6`).
///
/// ```
/// use nurbs::{cut_curvature, AxisPlane, KnotVector, NurbsSurface, Vec3};
///
/// // The parabolic sheet S(u, v) = (u, v, u^2): Bezier of degree 2 in u, 1 in v.
/// let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
/// let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0])?;
/// let mut pts = Vec::new();
/// for (x, z) in [(0.0, 0.0), (0.5, 0.0), (1.0, 1.0)] {
///     pts.extend([Vec3::new(x, 0.0, z), Vec3::new(x, 1.0, z)]);
/// }
/// let sheet = NurbsSurface::try_new(ku, kv, &pts, None)?;
/// // The plane y = 0.5 cuts the parabola z = x^2, of curvature 2 at its vertex; with x
/// // increasing it turns counter-clockwise in the plane's (x, z).
/// let d = sheet.derivatives(0.0, 0.5);
/// let k = cut_curvature(&d, AxisPlane::y(0.5), Vec3::new(1.0, 0.0, 0.0)).unwrap();
/// assert!((k - 2.0).abs() < 1e-12);
/// let back = cut_curvature(&d, AxisPlane::y(0.5), Vec3::new(-1.0, 0.0, 0.0)).unwrap();
/// assert!((back + 2.0).abs() < 1e-12);
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn cut_curvature(d: &SurfaceDerivatives, plane: AxisPlane, dir: Vec3) -> Option<f64> {
    let normal = d.regular_normal()?;
    let axis = plane.normal();
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

/// Signed curvature of the circle through three points of a plane, counter-clockwise positive
/// (the discrete curvature of a polyline at `b`):
/// `2 ((b - a) x (c - b)) / (|b - a| |c - b| |c - a|)`. `None` if two points coincide.
///
/// ```
/// use nurbs::three_point_curvature;
///
/// let on_circle = |a: f64| [2.0 * a.cos(), 2.0 * a.sin()];
/// let k = three_point_curvature(on_circle(0.1), on_circle(0.4), on_circle(0.9)).unwrap();
/// assert!((k - 0.5).abs() < 1e-12); // radius 2, counter-clockwise
/// assert_eq!(three_point_curvature([0.0, 0.0], [1.0, 1.0], [2.0, 2.0]), Some(0.0)); // collinear
/// assert_eq!(three_point_curvature([0.0, 0.0], [0.0, 0.0], [1.0, 0.0]), None);
/// ```
pub fn three_point_curvature(a: [f64; 2], b: [f64; 2], c: [f64; 2]) -> Option<f64> {
    let (ab, bc) = ([b[0] - a[0], b[1] - a[1]], [c[0] - b[0], c[1] - b[1]]);
    let ac = [c[0] - a[0], c[1] - a[1]];
    let denom = ab[0].hypot(ab[1]) * bc[0].hypot(bc[1]) * ac[0].hypot(ac[1]);
    let k = 2.0 * (ab[0] * bc[1] - ab[1] * bc[0]) / denom;
    (denom > 0.0 && k.is_finite()).then_some(k)
}

#[cfg(test)]
mod tests;
