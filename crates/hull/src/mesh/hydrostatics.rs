//! Hydrostatics of a mesh at a draft, to compare with those of a fitted surface
//! ([`crate::hydrostatics`](mod@crate::hydrostatics)).
//!
//! The rest of this module's documentation is on [`mesh_hydrostatics`], where the library's users read it.

use std::collections::HashMap;

use nurbs::{TriMesh, Vec3};

use crate::mesh::slice::CENTRE_REL;

/// Hydrostatic figures of a mesh at one draft, for the whole ship (both sides).
#[derive(Clone, Copy, Debug, Default, PartialEq, serde::Serialize)]
pub struct MeshHydrostatics {
    /// The waterplane's z.
    pub draft: f64,
    /// Displaced volume.
    pub volume: f64,
    /// Longitudinal centre of buoyancy (x).
    pub lcb: f64,
    /// Vertical centre of buoyancy (KB, z).
    pub vcb: f64,
    /// Wetted surface: the area of the mesh below the waterline.
    pub wetted_surface: f64,
    /// Waterplane area.
    pub waterplane_area: f64,
    /// Longitudinal centre of flotation (x).
    pub lcf: f64,
    /// Transverse second moment of the waterplane about the centre line, `∫ y^2 dA`.
    pub i_t: f64,
    /// x extent of the waterline.
    pub lwl: f64,
    /// y extent of the waterline (twice the largest half-breadth for a starboard-only mesh).
    pub bwl: f64,
    /// True if the mesh's triangles face inward (the signs were turned).
    pub inward: bool,
    /// True if the mesh holds the starboard side only (the figures were doubled).
    pub half: bool,
    /// Edges of one triangle with a vertex below the waterline, off the centre plane.
    pub open_edges_below: usize,
}

/// The hydrostatics of `mesh` at draft `draft` (see [`mesh_hydrostatics`]). A draft below the mesh
/// gives zeros; a non-finite draft gives NaN figures.
///
/// # Method
///
/// Every triangle is clipped to the wet side `z <= T` (Sutherland-Hodgman against one plane;
/// a triangle lying in the waterplane counts as dry) and the figures are sums over the clipped
/// triangles, by the divergence theorem as in [`Hydrostatics`](crate::Hydrostatics): with `F = (0, y g, 0)`,
/// `div F = g`, and `F . n = 0` on the centre plane (`y = 0`), on the waterplane and on any
/// transom at constant x (`n_y = 0`), so the body needs no closing faces there:
///
/// ```text
/// V      = sum ∫ y n_y dA           V LCB = sum ∫ x y n_y dA       V KB = sum ∫ z y n_y dA
/// S      = sum A                    (a half mesh's faces in the centre plane excluded)
/// AW     = -sum ∫ n_z dA            AW LCF = -sum ∫ x n_z dA       I_T = -sum ∫ y^2 n_z dA
/// ```
///
/// The waterplane sums hold because `∮ n_z dA = ∮ x n_z dA = ∮ y^2 n_z dA = 0` over the closed
/// wet body (Gauss with `(0, 0, 1)`, `(0, 0, x)`, `(0, 0, y^2)`), whose closing faces other
/// than the waterplane (centre plane, vertical transom) have `n_z = 0`. `∫ y dA` is the area
/// times the centroid's y; the quadratic integrands are integrated exactly by the edge-midpoint
/// rule `∫ f dA = (A/3)(f(m_ab) + f(m_bc) + f(m_ca))` (Strang and Fix, *An Analysis of the
/// Finite Element Method*, 1973, table 4.1). The figures are thus exact for the polyhedron:
/// only the mesh's faceting separates them from the smooth hull's.
///
/// # Both sides or one
///
/// A mesh with both sides (its lowest y below `-1e-6` of its size) is measured as it is. A mesh
/// of the starboard side only (`y >= 0`, open or closed at the centre plane) is measured and
/// doubled: every figure is then of the whole ship.
///
/// # Orientation
///
/// Outward normals (counter-clockwise triangles seen from outside) give a positive volume. A
/// mesh oriented inward gives a negative one; it is then measured as if turned outward
/// ([`MeshHydrostatics::inward`] says so). A mesh oriented inconsistently gives wrong volumes
/// (no orientation is repaired); [`MeshHydrostatics::open_edges_below`] counts the edges of
/// one triangle below the waterline (off the centre plane), which a hull watertight below the
/// waterline has none of.
pub fn mesh_hydrostatics(mesh: &TriMesh, draft: f64) -> MeshHydrostatics {
    let size = mesh.size();
    let centre = CENTRE_REL * size;
    let half = mesh.bounds().is_some_and(|(lo, _)| lo.y >= -centre);
    let t = draft;
    let (mut vol, mut mx, mut mz, mut s, mut aw, mut ax, mut it) = (0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0);
    let (mut x_lo, mut x_hi, mut y_lo, mut y_hi) = (f64::INFINITY, f64::NEG_INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    let mut poly: Vec<Vec3> = Vec::with_capacity(4);
    for tri in 0..mesh.triangles.len() {
        let c = mesh.corners(tri);
        // Dry, or lying in the waterplane (a deck at the draft): not hull below the water.
        if c.iter().all(|p| p.z >= t) {
            continue;
        }
        // Sutherland-Hodgman against z <= t; crossing points are waterline points.
        poly.clear();
        for k in 0..3 {
            let (a, b) = (c[k], c[(k + 1) % 3]);
            if a.z <= t {
                poly.push(a);
                if a.z == t {
                    (x_lo, x_hi, y_lo, y_hi) = (x_lo.min(a.x), x_hi.max(a.x), y_lo.min(a.y), y_hi.max(a.y));
                }
            }
            if (a.z <= t) != (b.z <= t) {
                let q = a + (b - a) * ((t - a.z) / (b.z - a.z));
                let q = Vec3::new(q.x, q.y, t);
                (x_lo, x_hi, y_lo, y_hi) = (x_lo.min(q.x), x_hi.max(q.x), y_lo.min(q.y), y_hi.max(q.y));
                poly.push(q);
            }
        }
        // A starboard-only mesh may be closed by faces in the centre plane: not hull surface.
        // (In a mesh of both sides, faces at y = 0 are the thin stem or keel: hull surface.)
        let in_centre_plane = half && c.iter().all(|p| p.y.abs() <= centre);
        for k in 1..poly.len().saturating_sub(1) {
            let (a, b, d) = (poly[0], poly[k], poly[k + 1]);
            let n = (b - a).cross(d - a) * 0.5;
            let m = [(a + b) * 0.5, (b + d) * 0.5, (d + a) * 0.5];
            let mid = |f: &dyn Fn(Vec3) -> f64| (f(m[0]) + f(m[1]) + f(m[2])) / 3.0;
            vol += n.y * (a.y + b.y + d.y) / 3.0;
            mx += n.y * mid(&|p| p.x * p.y);
            mz += n.y * mid(&|p| p.z * p.y);
            aw -= n.z;
            ax -= n.z * (a.x + b.x + d.x) / 3.0;
            it -= n.z * mid(&|p| p.y * p.y);
            if !in_centre_plane {
                s += n.norm();
            }
        }
    }
    let sign = if vol < 0.0 { -1.0 } else { 1.0 };
    let factor = if half { 2.0 } else { 1.0 };
    let volume = factor * sign * vol;
    let area = factor * sign * aw;
    let open_edges_below = open_edges_below(mesh, t, centre);
    let has_waterline = x_hi >= x_lo;
    MeshHydrostatics {
        draft,
        volume,
        lcb: if vol != 0.0 { mx / vol } else { 0.0 },
        vcb: if vol != 0.0 { mz / vol } else { 0.0 },
        wetted_surface: factor * s,
        waterplane_area: area,
        lcf: if aw != 0.0 { ax / aw } else { 0.0 },
        i_t: factor * sign * it,
        lwl: if has_waterline { x_hi - x_lo } else { 0.0 },
        bwl: match (has_waterline, half) {
            (false, _) => 0.0,
            (true, true) => 2.0 * y_hi,
            (true, false) => y_hi - y_lo,
        },
        inward: vol < 0.0,
        half,
        open_edges_below,
    }
}

/// Edges of exactly one triangle with an end below `t` and not both ends on the centre plane.
fn open_edges_below(mesh: &TriMesh, t: f64, centre: f64) -> usize {
    let mut count: HashMap<u64, u32> = HashMap::new();
    for tri in &mesh.triangles {
        for k in 0..3 {
            let (a, b) = (tri[k], tri[(k + 1) % 3]);
            let (pa, pb) = (mesh.vertices[a as usize], mesh.vertices[b as usize]);
            if pa.z.min(pb.z) < t && !(pa.y.abs() <= centre && pb.y.abs() <= centre) {
                *count.entry(TriMesh::edge_key(a, b)).or_insert(0) += 1;
            }
        }
    }
    count.values().filter(|&&c| c == 1).count()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::assert_near;

    /// The box `[0, 2] x [y0, 1] x [0, 1]`, outward, optionally without its face at y = y0.
    fn boxed(y0: f64, with_y0_face: bool) -> TriMesh {
        let v: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(if i & 1 == 0 { 0.0 } else { 2.0 }, if i & 2 == 0 { y0 } else { 1.0 }, f64::from(i >> 2))
            })
            .collect();
        let mut quads = vec![[0, 2, 3, 1], [4, 5, 7, 6], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        if with_y0_face {
            quads.push([0, 1, 5, 4]);
        }
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        TriMesh::try_new("box", v, triangles).expect("valid")
    }

    #[test]
    fn a_box_has_its_closed_forms() {
        // Box 2 x 2 x 1 at draft 0.5: V = 2, LCB = 1, KB = 0.25, S = 4 + 4 x (sides) ...
        // S = bottom 4 + two sides 2 x 0.5 each + two ends 2 x 0.5 each = 8; AW = 4, LCF = 1,
        // I_T = ∫ y^2 over [-1, 1] x [0, 2] = 2 x 2/3. All exact for a polyhedron: round-off.
        let full = boxed(-1.0, true);
        let h = mesh_hydrostatics(&full, 0.5);
        assert!(!h.half && !h.inward && h.open_edges_below == 0, "{h:?}");
        for (got, want) in [
            (h.volume, 2.0),
            (h.lcb, 1.0),
            (h.vcb, 0.25),
            (h.wetted_surface, 8.0),
            (h.waterplane_area, 4.0),
            (h.lcf, 1.0),
            (h.i_t, 4.0 / 3.0),
            (h.lwl, 2.0),
            (h.bwl, 2.0),
        ] {
            assert_near!(got, want, 1e-14);
        }
        // The starboard half, open at the centre plane: the same ship.
        let half = mesh_hydrostatics(&boxed(0.0, false), 0.5);
        assert!(half.half && half.open_edges_below == 0, "{half:?}");
        assert_near!(half.volume, 2.0, 1e-14);
        assert_near!(half.wetted_surface, 8.0, 1e-14);
        assert_near!(half.i_t, 4.0 / 3.0, 1e-14);
        // Closed at the centre plane too: its face there is not wetted surface.
        assert_near!(mesh_hydrostatics(&boxed(0.0, true), 0.5).wetted_surface, 8.0, 1e-14);
        // Turned inward: the same figures, flagged.
        let mut inward = full.clone();
        inward.triangles.iter_mut().for_each(|t| t.swap(1, 2));
        let hi = mesh_hydrostatics(&inward, 0.5);
        assert!(hi.inward);
        assert_near!(hi.volume, 2.0, 1e-14);
        assert_near!(hi.waterplane_area, 4.0, 1e-14);
        assert_near!(hi.lcb, 1.0, 1e-14);
    }

    #[test]
    fn a_hole_below_the_waterline_is_counted() {
        let mut open = boxed(-1.0, true);
        open.triangles.remove(0); // half of the bottom
        assert_eq!(mesh_hydrostatics(&open, 0.5).open_edges_below, 3);
        assert_eq!(mesh_hydrostatics(&boxed(-1.0, true), -1.0).volume, 0.0);
    }
}
