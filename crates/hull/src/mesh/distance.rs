//! How far a fitted surface lies from the mesh it was sliced from: the distance of the mesh's
//! vertices to the surface by closest-point projection ([`nurbs::SurfaceProjector`]), over the
//! part of the mesh the surface stands for.
//!
//! The surface is the starboard half hull between the first and the last section, below the
//! deck edge; the vertices measured are those on the starboard side (`y >= -1e-6` of the mesh
//! size), within the sections' x range and at most at a given height ([`VertexFilter`]): the
//! draft for the wetted hull (what the hydrostatics see), or the lowest deck edge for the
//! whole side. The vertices are the mesh's own points, so the figures are a one-sided
//! (mesh-to-surface) Hausdorff-type distance: a surface bulging away between vertices is
//! caught only as far as the vertices around it move.

use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjection, SurfaceProjector, Vec3};
use rayon::prelude::*;

use super::TriMesh;
use crate::fit_error::ErrorStats;
use crate::mesh::slice::CENTRE_REL;
use crate::offsets::Offsets;

/// Which vertices [`mesh_distance`] measures.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct VertexFilter {
    /// Lowest and highest x.
    pub x: (f64, f64),
    /// Highest z.
    pub z_max: f64,
    /// Measure every `every`-th accepted vertex (in the mesh's vertex order), 1 for all (0
    /// counts as 1): a quicker estimate on a fine mesh.
    pub every: usize,
}

impl VertexFilter {
    /// The x range of the sections of `offsets` (their first and last points' x), up to
    /// `z_max`; `None` without points.
    pub fn for_sections(offsets: &Offsets, z_max: f64) -> Option<Self> {
        let (lo, hi) = offsets.bounds()?;
        Some(VertexFilter { x: (lo.x, hi.x), z_max, every: 1 })
    }

    fn accepts(&self, p: Vec3, centre: f64) -> bool {
        p.y >= -centre && p.x >= self.x.0 && p.x <= self.x.1 && p.z <= self.z_max
    }
}

/// The distances of the mesh's vertices to a surface.
#[derive(Clone, Debug, PartialEq)]
pub struct MeshDistance {
    /// Max, mean and RMS over the vertices measured, and their number.
    pub stats: ErrorStats,
    /// The farthest vertex of `over_hull` and its foot point on the surface.
    pub worst: Option<(Vec3, Vec3)>,
    /// Projections that stopped at the iteration limit.
    pub unconverged: usize,
    /// The same over the vertices the surface stands for: those whose mesh normal (the
    /// area-weighted mean of its triangles') lies within 60° of the surface's normal at the
    /// foot point, with the orientation most vertices agree on (a mesh may face either way).
    /// The others are a deck, a transom face or a centre-plane lid of a closed mesh, which the
    /// skinned hull surface does not model, or vertices at their sharp edges.
    pub over_hull: ErrorStats,
    /// Vertices left out of `over_hull` (measured in `stats`).
    pub left_out: usize,
}

/// Least cosine between a vertex's normal and the surface's normal at its foot point (with
/// the agreed orientation) for the vertex to count in [`MeshDistance::over_hull`] (cos 60°).
pub const NORMAL_COS: f64 = 0.5;

/// Area-weighted vertex normals (not normalised; zero for unused vertices).
fn vertex_normals(mesh: &TriMesh) -> Vec<Vec3> {
    let mut n = vec![Vec3::new(0.0, 0.0, 0.0); mesh.vertices.len()];
    for t in &mesh.triangles {
        let [a, b, c] = t.map(|i| mesh.vertices[i as usize]);
        let area2 = (b - a).cross(c - a);
        for &i in t {
            n[i as usize] += area2;
        }
    }
    n
}

/// Distance to `surface` of every vertex of `mesh` (used by a triangle) that `filter` accepts.
pub fn mesh_distance(mesh: &TriMesh, surface: &NurbsSurface, filter: &VertexFilter) -> MeshDistance {
    let centre = CENTRE_REL * mesh.size();
    let mut used = vec![false; mesh.vertices.len()];
    for &i in mesh.triangles.iter().flatten() {
        used[i as usize] = true;
    }
    let normals = vertex_normals(mesh);
    let (points, point_normals): (Vec<Vec3>, Vec<Vec3>) = mesh
        .vertices
        .iter()
        .zip(&normals)
        .zip(&used)
        .filter(|&((&p, _), &u)| u && filter.accepts(p, centre))
        .map(|((&p, &n), _)| (p, n))
        .step_by(filter.every.max(1))
        .unzip();
    let projector = SurfaceProjector::new(surface, ProjectionOptions::default());
    let projections: Vec<SurfaceProjection> = points.par_iter().map(|&q| projector.project(q)).collect();
    let distances: Vec<f64> = projections.iter().map(|p| p.distance).collect();
    // Cosine of each vertex's normal with the surface's at its foot (0 where either is
    // undefined), and the orientation most of the mesh agrees on.
    let cosines: Vec<f64> = projections
        .iter()
        .zip(&point_normals)
        .map(|(proj, &n)| match (surface.normal(proj.u, proj.v), n.normalized()) {
            (Some(s), Some(n)) => s.dot(n),
            _ => 0.0,
        })
        .collect();
    let sign = if cosines.iter().sum::<f64>() < 0.0 { -1.0 } else { 1.0 };
    let over: Vec<f64> = projections
        .iter()
        .zip(&cosines)
        .filter(|&(_, &c)| sign * c >= NORMAL_COS)
        .map(|(proj, _)| proj.distance)
        .collect();
    let worst = projections
        .iter()
        .zip(&points)
        .zip(&cosines)
        .filter(|&(_, &c)| sign * c >= NORMAL_COS)
        .max_by(|a, b| a.0 .0.distance.total_cmp(&b.0 .0.distance))
        .map(|((proj, &q), _)| (q, proj.point));
    MeshDistance {
        stats: ErrorStats::from_distances(&distances),
        worst,
        unconverged: projections.iter().filter(|p| !p.converged).count(),
        left_out: distances.len() - over.len(),
        over_hull: ErrorStats::from_distances(&over),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::{assert_near, KnotVector};

    #[test]
    fn distances_to_a_plane_are_the_offsets_of_the_accepted_vertices() {
        // The plane y = 0.5 over x, z in [0, 4]: a vertex's distance is |y - 0.5|.
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let pts = [Vec3::new(0., 0.5, 0.), Vec3::new(0., 0.5, 4.), Vec3::new(4., 0.5, 0.), Vec3::new(4., 0.5, 4.)];
        let plane = NurbsSurface::try_new(k.clone(), k, &pts, None).expect("valid");
        let v = vec![
            Vec3::new(1.0, 0.75, 1.0), // 0.25
            Vec3::new(2.0, 0.0, 1.0),  // 0.5
            Vec3::new(3.0, -0.5, 1.0), // port: not measured
            Vec3::new(2.0, 1.5, 3.0),  // above z_max: not measured
            Vec3::new(9.0, 0.5, 1.0),  // forward of the range: not measured
        ];
        let mesh = TriMesh::try_new("m", v, vec![[0, 1, 2], [2, 3, 4]]).expect("valid");
        let d = mesh_distance(&mesh, &plane, &VertexFilter { x: (0.0, 4.0), z_max: 2.0, every: 1 });
        // Every second accepted vertex: the first one only.
        let half = mesh_distance(&mesh, &plane, &VertexFilter { x: (0.0, 4.0), z_max: 2.0, every: 2 });
        assert_eq!(half.stats.points, 1);
        assert_near!(half.stats.max, 0.25, 1e-12);
        assert_eq!(d.stats.points, 2);
        // Projection onto a plane converges to round-off.
        assert_near!(d.stats.max, 0.5, 1e-12);
        assert_near!(d.stats.mean, 0.375, 1e-12);
        assert_near!(d.stats.rms, (0.3125f64 / 2.0).sqrt(), 1e-12);
        // Both triangles lie across the plane (normals along z): no vertex faces the plane, so
        // none counts over the hull and there is no farthest one of those.
        assert_eq!((d.over_hull.points, d.left_out), (0, 2));
        assert!(d.worst.is_none());
    }

    #[test]
    fn vertices_of_lids_are_told_apart_from_those_over_the_surface() {
        // The plane y = 0.5 over x, z in [0, 4], measured against a mesh of a box: its side
        // y = 0.75 facing +y like the plane (after any orientation: the majority decides), and
        // its lid x = 4.5 facing +x, beyond the plane's edge.
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let pts = [Vec3::new(0., 0.5, 0.), Vec3::new(0., 0.5, 4.), Vec3::new(4., 0.5, 0.), Vec3::new(4., 0.5, 4.)];
        let plane = NurbsSurface::try_new(k.clone(), k, &pts, None).expect("valid");
        for flip in [false, true] {
            let v = vec![
                // The side y = 0.75: two triangles, normal +y.
                Vec3::new(1.0, 0.75, 1.0),
                Vec3::new(1.0, 0.75, 3.0),
                Vec3::new(3.0, 0.75, 1.0),
                Vec3::new(3.0, 0.75, 3.0),
                // The lid x = 4.5, normal +x.
                Vec3::new(4.5, 0.0, 1.0),
                Vec3::new(4.5, 2.0, 1.0),
                Vec3::new(4.5, 0.0, 3.0),
            ];
            let mut t = vec![[0, 1, 2], [1, 3, 2], [4, 5, 6]];
            if flip {
                t.iter_mut().for_each(|t| t.swap(1, 2));
            }
            let mesh = TriMesh::try_new("m", v, t).expect("valid");
            let d = mesh_distance(&mesh, &plane, &VertexFilter { x: (0.0, 10.0), z_max: 10.0, every: 1 });
            assert_eq!((d.stats.points, d.over_hull.points, d.left_out), (7, 4, 3), "flip {flip}");
            // Projection onto a plane is exact to round-off: the lid's (4.5, 2, 1) is
            // |(0.5, 1.5, 0)| from the plane's edge.
            assert_near!(d.stats.max, (0.25f64 + 2.25).sqrt(), 1e-12);
            assert_near!(d.over_hull.max, 0.25, 1e-12);
            assert_near!(d.over_hull.mean, 0.25, 1e-12);
            // The farthest vertex over the hull (all four tie at 0.25) and its foot.
            let (q, foot) = d.worst.expect("vertices over the plane");
            assert_near!(foot, Vec3::new(q.x, 0.5, q.z), 1e-12);
            assert_near!(q.y, 0.75, 0.0);
        }
    }
}
