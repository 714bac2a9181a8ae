//! Triangulation of a NURBS surface to a chordal tolerance: the mesh that the mesh formats
//! (STL, OBJ, glTF) are written from.
//!
//! **Grid.** The surface is sampled on a tensor grid of parameters `u_0 < .. < u_m`,
//! `v_0 < .. < v_n` that contains every distinct knot (so no triangle straddles a knot, where
//! the surface may be only C^0) and starts with every knot span cut in two. Each grid cell
//! `[u_i, u_i+1] x [v_j, v_j+1]` becomes two triangles, split along the diagonal whose
//! midpoint is nearer the surface. A tensor grid keeps the mesh conforming (no T-junctions,
//! so no cracks) at the price of some triangles where a direction is refined across the
//! whole surface.
//!
//! **Refinement.** The deviation of a chord `P_a P_b` (a triangle edge, diagonals included)
//! is measured at its parametric midpoint `m`: `e` = the distance from `S(m)` to the line
//! `P_a P_b`. On an arc that is quadratic in its parameter, `C(t) = C_0 + a t + b t^2`, the
//! distance to the chord is `|b_perp| t (1 - t)`, largest at `t = 1/2` whatever the speed, so
//! this is the chord's sagitta; unlike the distance to the chord's midpoint it ignores the
//! harmless slide along the chord of an uneven parameterization. Every u-interval with an
//! edge along u of `e > 3/4 T` and every such v-interval is bisected (a cell whose edges are
//! all within `3/4 T` but whose diagonal is not, a twisted cell, has both its intervals
//! bisected), and the grid is measured again, until no edge deviates by more than `3/4 T`
//! (`T` the tolerance). Why 3/4: over a cell small enough for the surface to be quadratic in
//! `(u, v)`, the deviation of the surface from a triangle's plane is a quadratic vanishing at
//! the corners, `e(l) = a l2 l3 + b l1 l3 + c l1 l2` in barycentric coordinates `l`, whose
//! values at the edge midpoints, `a / 4`, `b / 4`, `c / 4`, are at most the edges' `e`;
//! since `l2 l3 + l1 l3 + l1 l2 <= 1/3`, `|e| <= 4/3 max(edge deviations) <= T`.
//!
//! **Orientation.** Normals are `S_u x S_v` turned so that the area-weighted mean of their y
//! component is positive: the mesh faces +y on the whole. That is the outward side of a
//! surface on the side `y >= 0` of the plane `y = 0` that, closed by that plane (outward
//! normal -y) and by caps whose normals have no y component, bounds a solid: `sum n dA = 0`
//! over the closed surface, so the surface's `integral n_y dA` equals the area it closes off
//! in the plane and is positive for the outward side. Triangles are wound counter-clockwise
//! seen from that side. The mirror image (`y -> -y`, [`TessellationOptions::mirror`]) has its
//! winding reversed so that it too faces outward.

use std::collections::HashMap;

use rayon::prelude::*;

use crate::{NurbsError, NurbsSurface, TriMesh, Vec3};

/// Factor on the tolerance for the edge-midpoint deviation (see the module docs).
const MIDPOINT_FACTOR: f64 = 0.75;

/// Smallest tolerance accepted, relative to the diagonal of the control-net box: the mesh
/// formats hold f32 coordinates (relative precision 6e-8), so a tighter chord is pointless.
pub const MIN_TESSELLATION_TOLERANCE_REL: f64 = 1e-7;

/// Largest number of grid lines per direction before the tessellation gives up.
pub const MAX_GRID_LINES: usize = 8192;

/// Settings of [`tessellate`].
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct TessellationOptions {
    /// Largest distance between the triangles and the surface, in the surface's length unit.
    pub tolerance: f64,
    /// Add the mirror image in the plane `y = 0` (every vertex with `y -> -y`, every triangle
    /// with its winding reversed so that it faces outward too): the whole of a solid whose
    /// half on `y >= 0` the surface bounds.
    pub mirror: bool,
}

impl TessellationOptions {
    /// The default tolerance of a surface: `1e-4` of the diagonal of its control-net box
    /// (0.012 for a box of diagonal 120), without the mirror image.
    pub fn for_surface(surface: &NurbsSurface) -> Self {
        let (lo, hi) = surface.control_bounds();
        TessellationOptions { tolerance: 1e-4 * (hi - lo).norm(), mirror: false }
    }
}

/// A surface triangulated to a tolerance: the mesh (positions, outward unit normals at the
/// vertices, counter-clockwise triangles seen from outside) and what the tessellation knows
/// of every vertex and of the grid it was made on.
#[derive(Clone, Debug, PartialEq)]
pub struct Tessellation {
    /// The triangle mesh, with its vertex normals (unit, outward: see the module docs).
    /// Triangles with two coincident corners (at a boundary collapsed to a point) are left
    /// out, and so are the vertices no triangle uses.
    pub mesh: TriMesh,
    /// Gaussian curvature `K` at every vertex (orientation-free; at a collapsed boundary the
    /// limit from inside the domain); NaN where it is undefined.
    pub gaussian: Vec<f64>,
    /// The surface parameters `(u, v)` of every vertex (a mirrored vertex has those of the
    /// vertex it mirrors).
    pub params: Vec<(f64, f64)>,
    /// The grid parameters along u and v.
    pub grid_u: Vec<f64>,
    pub grid_v: Vec<f64>,
    /// Largest edge-midpoint deviation measured (at most `3/4` of the tolerance).
    pub max_midpoint_deviation: f64,
    /// The tolerance the mesh was made for.
    pub tolerance: f64,
    /// True if the outward normal is `-(S_u x S_v)`.
    pub flipped: bool,
}

/// Surface points by exact parameter bits, evaluated once.
struct PointCache<'a> {
    surface: &'a NurbsSurface,
    points: HashMap<(u64, u64), Vec3>,
}

impl PointCache<'_> {
    /// Evaluate (in parallel) every `(u, v)` not seen yet.
    fn fill(&mut self, uv: &[(f64, f64)]) {
        let mut todo: Vec<(f64, f64)> =
            uv.iter().copied().filter(|&(u, v)| !self.points.contains_key(&(u.to_bits(), v.to_bits()))).collect();
        todo.sort_by(|a, b| a.partial_cmp(b).expect("finite parameters"));
        todo.dedup();
        let s = self.surface;
        let new: Vec<Vec3> = todo.par_iter().map(|&(u, v)| s.point(u, v)).collect();
        for ((u, v), p) in todo.into_iter().zip(new) {
            self.points.insert((u.to_bits(), v.to_bits()), p);
        }
    }

    fn get(&self, u: f64, v: f64) -> Vec3 {
        self.points[&(u.to_bits(), v.to_bits())]
    }
}

/// Deviations of the current grid: per u-interval and per v-interval the largest edge
/// midpoint error charged to it, per cell whether the `(i, j)-(i+1, j+1)` diagonal is the
/// better one, and the largest deviation of any edge (diagonals included).
struct GridErrors {
    u: Vec<f64>,
    v: Vec<f64>,
    main_diagonal: Vec<bool>,
    max: f64,
}

fn measure(cache: &mut PointCache, gu: &[f64], gv: &[f64], limit: f64) -> GridErrors {
    let mid = |a: f64, b: f64| 0.5 * (a + b);
    let mut uv = Vec::new();
    for &u in gu {
        for &v in gv {
            uv.push((u, v));
        }
        for w in gv.windows(2) {
            uv.push((u, mid(w[0], w[1])));
        }
    }
    for wu in gu.windows(2) {
        let um = mid(wu[0], wu[1]);
        for &v in gv {
            uv.push((um, v));
        }
        for w in gv.windows(2) {
            uv.push((um, mid(w[0], w[1])));
        }
    }
    cache.fill(&uv);
    let (m, n) = (gu.len(), gv.len());
    let mut eu = vec![0.0f64; m - 1];
    let mut ev = vec![0.0f64; n - 1];
    let mut main_diagonal = vec![true; (m - 1) * (n - 1)];
    let mut max = 0.0f64;
    let dev = chord_deviation;
    // Edge deviations: along u at (i, j) for the edge (i, j)-(i+1, j); along v likewise.
    let mut edge_u = vec![0.0f64; (m - 1) * n];
    let mut edge_v = vec![0.0f64; m * (n - 1)];
    for i in 0..m - 1 {
        let um = mid(gu[i], gu[i + 1]);
        for j in 0..n {
            let e = dev(cache.get(um, gv[j]), cache.get(gu[i], gv[j]), cache.get(gu[i + 1], gv[j]));
            edge_u[i * n + j] = e;
            eu[i] = eu[i].max(e);
        }
    }
    for i in 0..m {
        for j in 0..n - 1 {
            let vm = mid(gv[j], gv[j + 1]);
            let e = dev(cache.get(gu[i], vm), cache.get(gu[i], gv[j]), cache.get(gu[i], gv[j + 1]));
            edge_v[i * (n - 1) + j] = e;
            ev[j] = ev[j].max(e);
        }
    }
    max = eu.iter().chain(&ev).fold(max, |a, &b| a.max(b));
    // Diagonals: the better one is kept. Its deviation is charged to both directions only when
    // no edge of the cell exceeds the limit (a twisted cell); otherwise splitting the
    // offending edges' intervals comes first and the diagonal is measured again after.
    for i in 0..m - 1 {
        for j in 0..n - 1 {
            let c = cache.get(mid(gu[i], gu[i + 1]), mid(gv[j], gv[j + 1]));
            let (p00, p10) = (cache.get(gu[i], gv[j]), cache.get(gu[i + 1], gv[j]));
            let (p01, p11) = (cache.get(gu[i], gv[j + 1]), cache.get(gu[i + 1], gv[j + 1]));
            let (d_main, d_anti) = (dev(c, p00, p11), dev(c, p10, p01));
            main_diagonal[i * (n - 1) + j] = d_main <= d_anti;
            let e = d_main.min(d_anti);
            max = max.max(e);
            let edges =
                [edge_u[i * n + j], edge_u[i * n + j + 1], edge_v[i * (n - 1) + j], edge_v[(i + 1) * (n - 1) + j]];
            if e > limit && edges.iter().all(|&x| x <= limit) {
                eu[i] = eu[i].max(e);
                ev[j] = ev[j].max(e);
            }
        }
    }
    GridErrors { u: eu, v: ev, main_diagonal, max }
}

/// Distance from `p` to the line through `a` and `b` (to `a` if they coincide).
fn chord_deviation(p: Vec3, a: Vec3, b: Vec3) -> f64 {
    let d = b - a;
    let len2 = d.norm_squared();
    let r = p - a;
    if len2 > 0.0 {
        (r - d * (r.dot(d) / len2)).norm()
    } else {
        r.norm()
    }
}

/// Bisect the intervals whose error exceeds `limit`; returns whether any was.
fn refine(grid: &mut Vec<f64>, errors: &[f64], limit: f64) -> bool {
    let mut out = Vec::with_capacity(2 * grid.len());
    let mut changed = false;
    for (k, w) in grid.windows(2).enumerate() {
        out.push(w[0]);
        let m = 0.5 * (w[0] + w[1]);
        // A bisection that rounds onto an end point would never end.
        if errors[k] > limit && m > w[0] && m < w[1] {
            out.push(m);
            changed = true;
        }
    }
    out.push(grid[grid.len() - 1]);
    *grid = out;
    changed
}

/// How far inside the domain the normal and curvature of a degenerate point (on a boundary
/// collapsed to a point) are taken as limits ([`NurbsSurface::nudged_inside`]).
const NUDGE_REL: f64 = 1e-6;

/// Triangulate `surface` so that no triangle is farther than `options.tolerance` from it: a
/// tensor grid of parameters through every knot, refined until every chord's sagitta is
/// within `3/4` of the tolerance, so that the triangles are within it; normals and winding
/// facing +y on the whole (see the source's module docs for the grid, the bound and the
/// orientation).
///
/// A quarter cylinder of radius 2 meshed to 1e-3: its vertices lie on the cylinder, the
/// middles of its triangles' edges within the tolerance inside it, and the mesh is one open
/// strip (only its border is open).
///
/// ```
/// use nurbs::{tessellate, TessellationOptions};
///
/// let (r, tol) = (2.0, 1e-3);
/// // y^2 + z^2 = r^2 for y >= 0, z <= 0, along x from 0 to 3.
/// let surface = nurbs::fixtures::quarter_cylinder_along_x(r, 3.0);
/// let tess = tessellate(&surface, &TessellationOptions { tolerance: tol, mirror: false })?;
/// let mesh = &tess.mesh;
/// let radius = |p: nurbs::Vec3| (p.y * p.y + p.z * p.z).sqrt();
/// assert!(mesh.vertices.iter().all(|&p| (radius(p) - r).abs() < 1e-12));
/// for t in 0..mesh.triangles.len() {
///     let [a, b, c] = mesh.corners(t);
///     for m in [(a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5] {
///         assert!(radius(m) <= r && r - radius(m) <= tol);
///     }
/// }
/// // A strip of m x n grid points: every interior edge shared by two triangles, the
/// // 2 (m - 1) + 2 (n - 1) edges of the border by one.
/// let (m, n) = (tess.grid_u.len(), tess.grid_v.len());
/// let edges = mesh.edge_counts();
/// assert_eq!((edges.open, edges.non_manifold), (2 * (m - 1) + 2 * (n - 1), 0));
/// assert_eq!(mesh.triangles.len(), 2 * (m - 1) * (n - 1));
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
///
/// # Errors
/// [`NurbsError::TessellationFloor`] if the tolerance is not a positive finite number of at
/// least [`MIN_TESSELLATION_TOLERANCE_REL`] of the surface's size;
/// [`NurbsError::TessellationGridLines`] if meeting it would take more than
/// [`MAX_GRID_LINES`] grid lines in a direction (a tolerance far below the surface's size);
/// [`NurbsError::TessellationRounding`] if it is below the rounding of double precision.
pub fn tessellate(surface: &NurbsSurface, options: &TessellationOptions) -> Result<Tessellation, NurbsError> {
    let tol = options.tolerance;
    let (lo, hi) = surface.control_bounds();
    let floor = MIN_TESSELLATION_TOLERANCE_REL * (hi - lo).norm();
    if !(tol.is_finite() && tol > 0.0 && tol >= floor) {
        return Err(NurbsError::TessellationFloor { tolerance: tol, floor, relative: MIN_TESSELLATION_TOLERANCE_REL });
    }
    // The distinct knots, each span cut in two.
    let halved = |mut grid: Vec<f64>| {
        let all = vec![1.0; grid.len() - 1];
        refine(&mut grid, &all, 0.0);
        grid
    };
    let (mut gu, mut gv) = (halved(surface.knots_u().span_breaks()), halved(surface.knots_v().span_breaks()));
    let mut cache = PointCache { surface, points: HashMap::new() };
    let limit = MIDPOINT_FACTOR * tol;
    let errors = loop {
        let e = measure(&mut cache, &gu, &gv, limit);
        let changed_u = refine(&mut gu, &e.u, limit);
        let changed_v = refine(&mut gv, &e.v, limit);
        if !changed_u && !changed_v {
            break e;
        }
        if gu.len() > MAX_GRID_LINES || gv.len() > MAX_GRID_LINES {
            return Err(NurbsError::TessellationGridLines { tolerance: tol, max: MAX_GRID_LINES });
        }
    };
    let max_midpoint_deviation = errors.max;
    if max_midpoint_deviation > limit {
        // Only when a bisection rounded onto an end point: the tolerance is at the rounding.
        return Err(NurbsError::TessellationRounding { tolerance: tol, deviation: max_midpoint_deviation });
    }
    let (m, n) = (gu.len(), gv.len());

    // Vertices of the surface (its mirror image comes after): points, raw normals S_u x S_v
    // and curvature.
    struct Vertex {
        n: Vec3,
        k: f64,
    }
    let uv: Vec<(f64, f64)> = gu.iter().flat_map(|&u| gv.iter().map(move |&v| (u, v))).collect();
    let verts: Vec<Vertex> = uv
        .par_iter()
        .map(|&(u, v)| {
            let d = surface.derivatives(u, v);
            let (un, vn) = surface.nudged_inside(u, v, NUDGE_REL);
            let n = d.normal().or_else(|| surface.normal(un, vn)).unwrap_or(Vec3::new(0.0, 0.0, 0.0));
            let k = d.curvature().or_else(|| surface.curvature(un, vn)).map_or(f64::NAN, |c| c.gaussian);
            Vertex { n, k }
        })
        .collect();
    let positions: Vec<Vec3> = uv.iter().map(|&(u, v)| cache.get(u, v)).collect();

    // Triangles in (u, v) order: counter-clockwise about S_u x S_v.
    let id = |i: usize, j: usize| (i * n + j) as u32;
    let mut triangles: Vec<[u32; 3]> = Vec::with_capacity(2 * (m - 1) * (n - 1));
    for i in 0..m - 1 {
        for j in 0..n - 1 {
            let (a, b, c, d) = (id(i, j), id(i + 1, j), id(i + 1, j + 1), id(i, j + 1));
            if errors.main_diagonal[i * (n - 1) + j] {
                triangles.extend([[a, b, c], [a, c, d]]);
            } else {
                triangles.extend([[a, b, d], [b, c, d]]);
            }
        }
    }
    let eps = 1e-12 * (hi - lo).norm();
    triangles.retain(|t| {
        let [a, b, c] = t.map(|k| positions[k as usize]);
        a.distance(b) > eps && b.distance(c) > eps && c.distance(a) > eps
    });
    // Orientation: the sign of integral n_y dA over the triangles (twice the area each).
    let ny: f64 = triangles
        .iter()
        .map(|t| {
            let [a, b, c] = t.map(|k| positions[k as usize]);
            (b - a).cross(c - a).y
        })
        .sum();
    let flipped = ny < 0.0;
    let sign = if flipped { -1.0 } else { 1.0 };
    if flipped {
        for t in &mut triangles {
            t.swap(1, 2);
        }
    }
    // Keep only the vertices some triangle uses (a collapsed boundary leaves unused copies of
    // its point), renumbered in order.
    let mut new_index = vec![u32::MAX; positions.len()];
    for t in &triangles {
        for &k in t {
            new_index[k as usize] = 0;
        }
    }
    let mut kept = Vec::with_capacity(positions.len());
    for (k, slot) in new_index.iter_mut().enumerate() {
        if *slot == 0 {
            *slot = kept.len() as u32;
            kept.push(k);
        }
    }
    for t in &mut triangles {
        *t = t.map(|k| new_index[k as usize]);
    }
    let mut tess = Tessellation {
        mesh: TriMesh {
            source: "tessellated surface".into(),
            vertices: kept.iter().map(|&k| positions[k]).collect(),
            triangles,
            degenerate: 0,
            normals: kept.iter().map(|&k| verts[k].n * sign).collect(),
        },
        gaussian: kept.iter().map(|&k| verts[k].k).collect(),
        params: kept.iter().map(|&k| uv[k]).collect(),
        grid_u: gu,
        grid_v: gv,
        max_midpoint_deviation,
        tolerance: tol,
        flipped,
    };
    if options.mirror {
        mirror(&mut tess);
    }
    Ok(tess)
}

/// Append the mirror image: every vertex with `y -> -y`, every triangle with its winding
/// reversed (a reflection turns counter-clockwise into clockwise).
fn mirror(tess: &mut Tessellation) {
    let mesh = &mut tess.mesh;
    let count = mesh.vertices.len();
    let offset = count as u32;
    let flip = |p: Vec3| Vec3::new(p.x, -p.y, p.z);
    let positions: Vec<Vec3> = mesh.vertices.iter().map(|&p| flip(p)).collect();
    let normals: Vec<Vec3> = mesh.normals.iter().map(|&p| flip(p)).collect();
    mesh.vertices.extend(positions);
    mesh.normals.extend(normals);
    tess.gaussian.extend_from_within(..count);
    tess.params.extend_from_within(..count);
    let image: Vec<[u32; 3]> = mesh.triangles.iter().map(|&[a, b, c]| [a + offset, c + offset, b + offset]).collect();
    mesh.triangles.extend(image);
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::quarter_cylinder_along_x as quarter_cylinder;
    use crate::{KnotVector, ProjectionOptions, SurfaceProjector};

    fn opts(tolerance: f64) -> TessellationOptions {
        TessellationOptions { tolerance, mirror: false }
    }

    #[test]
    fn cylinder_chords_stay_within_the_tolerance() {
        let r = 2.0;
        let s = quarter_cylinder(r, 3.0);
        for tol in [1e-2, 1e-3, 1e-4] {
            let tess = tessellate(&s, &opts(tol)).expect("tessellates");
            // Vertices on the cylinder (exact evaluation, rounding only).
            for p in &tess.mesh.vertices {
                assert!(((p.y * p.y + p.z * p.z).sqrt() - r).abs() < 1e-12, "{p:?}");
            }
            // The farthest point of a chord of angle a from the circle is its middle, at
            // r (1 - cos(a / 2)); every point of a triangle is inside the circle, at most
            // the largest such sagitta away, which must be within the tolerance.
            let mut worst = 0.0f64;
            for t in &tess.mesh.triangles {
                let [a, b, c] = t.map(|k| tess.mesh.vertices[k as usize]);
                for (w0, w1, w2) in [(1.0, 1.0, 1.0), (1.0, 1.0, 0.0), (0.0, 1.0, 1.0), (1.0, 0.0, 1.0)] {
                    let q = (a * w0 + b * w1 + c * w2) * (1.0 / (w0 + w1 + w2));
                    worst = worst.max(r - (q.y * q.y + q.z * q.z).sqrt());
                }
            }
            assert!(worst <= tol, "deviation {worst} > {tol}");
            // Not grossly over-refined: the number of arcs is within a factor 2.5 of the
            // fewest equal arcs meeting the tolerance, n = ceil((pi/2) / (2 acos(1 - tol/r))).
            let fewest = (std::f64::consts::FRAC_PI_2 / (2.0 * (1.0 - tol / r).acos())).ceil();
            let arcs = (tess.grid_u.len() - 1) as f64;
            assert!(arcs >= fewest && arcs <= 2.5 * fewest, "{arcs} arcs, fewest {fewest} at tolerance {tol}");
            // A cylinder is straight along x: no refinement there beyond the initial split.
            assert_eq!(tess.grid_v.len(), 3);
            assert!(tess.max_midpoint_deviation <= MIDPOINT_FACTOR * tol);
        }
    }

    #[test]
    fn normals_are_unit_outward_and_match_the_winding() {
        let s = quarter_cylinder(2.0, 3.0);
        for mirror in [false, true] {
            let tess = tessellate(&s, &TessellationOptions { tolerance: 1e-3, mirror }).expect("tessellates");
            for (p, nrm) in tess.mesh.vertices.iter().zip(&tess.mesh.normals) {
                // Outward from the cylinder's axis (the x axis): n = (0, y, z) / r.
                let radial = Vec3::new(0.0, p.y, p.z) * 0.5;
                assert!((nrm.norm() - 1.0).abs() < 1e-12);
                assert!(nrm.distance(radial) < 1e-9, "normal {nrm:?} at {p:?}");
            }
            for t in 0..tess.mesh.triangles.len() {
                let f = tess.mesh.face_normal(t);
                let [a, b, c] = tess.mesh.triangles[t].map(|k| tess.mesh.vertices[k as usize]);
                let centroid = (a + b + c) * (1.0 / 3.0);
                assert!(f.dot(Vec3::new(0.0, centroid.y, centroid.z)) > 0.0, "triangle {t} faces inward");
            }
            let half = tess.mesh.vertices.len() / if mirror { 2 } else { 1 };
            if mirror {
                for k in 0..half {
                    let (a, b) = (tess.mesh.vertices[k], tess.mesh.vertices[k + half]);
                    assert_eq!((a.x, -a.y, a.z), (b.x, b.y, b.z));
                }
            }
        }
    }

    #[test]
    fn orientation_does_not_depend_on_the_parameterization() {
        // The transposed surface has S_u x S_v reversed; the mesh must face the same way.
        let s = quarter_cylinder(2.0, 3.0);
        let a = tessellate(&s, &opts(1e-3)).expect("tessellates");
        let b = tessellate(&s.transposed(), &opts(1e-3)).expect("tessellates");
        assert_ne!(a.flipped, b.flipped);
        for tess in [a, b] {
            let t = tess.mesh.triangles.len() / 2;
            let [p, _, _] = tess.mesh.triangles[t].map(|k| tess.mesh.vertices[k as usize]);
            assert!(tess.mesh.face_normal(t).dot(Vec3::new(0.0, p.y, p.z)) > 0.0);
        }
    }

    #[test]
    fn collapsed_boundary_triangles_are_dropped_and_vertices_lie_on_a_rational_surface() {
        // A rational bicubic patch whose v = v1 boundary collapses to one point.
        let ku = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.4, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]).expect("valid");
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                let t = 1.0 - j as f64 / (nv - 1) as f64;
                pts.push(Vec3::new(5.0 * j as f64, t * (1.0 + i as f64), t * (i * i) as f64 * 0.4 - 2.0));
                w.push(1.0 + 0.2 * ((i + 2 * j) % 3) as f64);
            }
        }
        let s = NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid");
        let tol = 2e-3;
        let tess = tessellate(&s, &opts(tol)).expect("tessellates");
        let (m, n) = (tess.grid_u.len(), tess.grid_v.len());
        // The last column of every cell row is a fan onto the tip: one triangle per cell.
        assert_eq!(tess.mesh.triangles.len(), 2 * (m - 1) * (n - 1) - (m - 1));
        // Every vertex is used by a triangle, and fewer than the grid's are left.
        let mut used = vec![false; tess.mesh.vertices.len()];
        tess.mesh.triangles.iter().flatten().for_each(|&k| used[k as usize] = true);
        assert!(used.iter().all(|&u| u));
        assert!(tess.mesh.vertices.len() < m * n);
        for k in 0..tess.mesh.triangles.len() {
            assert!(tess.mesh.face_normal(k).norm() > 0.5, "degenerate triangle {k}");
        }
        assert!(tess.mesh.normals.iter().all(|v| (v.norm() - 1.0).abs() < 1e-9), "a normal is missing");
        assert!(tess.gaussian.iter().all(|k| k.is_finite()));
        // Triangle centroids and edge midpoints within the tolerance of the surface.
        let projector = SurfaceProjector::new(&s, ProjectionOptions::default());
        let mut worst = 0.0f64;
        for t in &tess.mesh.triangles {
            let [a, b, c] = t.map(|k| tess.mesh.vertices[k as usize]);
            for q in [(a + b + c) * (1.0 / 3.0), (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5] {
                worst = worst.max(projector.project(q).distance);
            }
        }
        assert!(worst <= tol, "deviation {worst} > {tol}");
    }

    #[test]
    fn bad_tolerances_are_refused() {
        let s = quarter_cylinder(2.0, 3.0);
        for t in [0.0, -1.0, f64::NAN, f64::INFINITY, 1e-300] {
            match tessellate(&s, &opts(t)) {
                Err(NurbsError::TessellationFloor { tolerance, floor, relative }) => {
                    assert!(tolerance.to_bits() == t.to_bits(), "{tolerance} {t}");
                    assert!(floor > 0.0 && relative == MIN_TESSELLATION_TOLERANCE_REL, "{floor}");
                }
                other => panic!("{t}: {other:?}"),
            }
        }
    }
}
