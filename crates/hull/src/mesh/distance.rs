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
    /// The farthest vertex and its foot point on the surface.
    pub worst: Option<(Vec3, Vec3)>,
    /// Projections that stopped at the iteration limit.
    pub unconverged: usize,
}

/// Distance to `surface` of every vertex of `mesh` (used by a triangle) that `filter` accepts.
pub fn mesh_distance(mesh: &TriMesh, surface: &NurbsSurface, filter: &VertexFilter) -> MeshDistance {
    let centre = CENTRE_REL * mesh.size();
    let mut used = vec![false; mesh.vertices.len()];
    for &i in mesh.triangles.iter().flatten() {
        used[i as usize] = true;
    }
    let points: Vec<Vec3> = mesh
        .vertices
        .iter()
        .zip(&used)
        .filter(|&(&p, &u)| u && filter.accepts(p, centre))
        .map(|(&p, _)| p)
        .step_by(filter.every.max(1))
        .collect();
    let projector = SurfaceProjector::new(surface, ProjectionOptions::default());
    let projections: Vec<SurfaceProjection> = points.par_iter().map(|&q| projector.project(q)).collect();
    let distances: Vec<f64> = projections.iter().map(|p| p.distance).collect();
    let worst = projections
        .iter()
        .zip(&points)
        .max_by(|a, b| a.0.distance.total_cmp(&b.0.distance))
        .map(|(proj, &q)| (q, proj.point));
    MeshDistance {
        stats: ErrorStats::from_distances(&distances),
        worst,
        unconverged: projections.iter().filter(|p| !p.converged).count(),
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
        let (q, foot) = d.worst.expect("points");
        assert_eq!(q, Vec3::new(2.0, 0.0, 1.0));
        assert_near!(foot, Vec3::new(2.0, 0.5, 1.0), 1e-12);
    }
}
