//! An indexed triangle mesh: shared vertices, triangles as triples of vertex indices, and unit
//! normals at the vertices where the mesh has them. The one mesh type of the workspace: a
//! surface triangulated to a tolerance ([`crate::tessellate()`]) and a mesh read from a file
//! by the crates above alike.

use std::collections::HashMap;

use crate::{NurbsError, Vec3};

/// An indexed triangle mesh.
///
/// A tetrahedron is closed: every edge is shared by two triangles.
///
/// ```
/// use nurbs::{EdgeCounts, TriMesh, Vec3};
///
/// let v = vec![
///     Vec3::new(0.0, 0.0, 0.0),
///     Vec3::new(1.0, 0.0, 0.0),
///     Vec3::new(0.0, 1.0, 0.0),
///     Vec3::new(0.0, 0.0, 1.0),
/// ];
/// let t = vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]];
/// let mesh = TriMesh::try_new("tetrahedron", v, t)?;
/// assert_eq!(mesh.edge_counts(), EdgeCounts { edges: 6, open: 0, non_manifold: 0 });
/// // The face [0, 2, 1] lies in z = 0, wound clockwise seen from +z: it faces -z (outward).
/// assert_eq!(mesh.face_normal(0), Vec3::new(0.0, 0.0, -1.0));
/// assert_eq!(mesh.size(), 3f64.sqrt());
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct TriMesh {
    /// Where the mesh came from (a file path or a name), for messages.
    pub source: String,
    /// The vertices.
    pub vertices: Vec<Vec3>,
    /// The triangles, counter-clockwise seen from outside for a well-oriented mesh (nothing
    /// here depends on the orientation).
    pub triangles: Vec<[u32; 3]>,
    /// Triangles of the source dropped because two of their corners are the same vertex
    /// (zero area: they cut no plane and bound no volume).
    pub degenerate: usize,
    /// Unit normals at the vertices, one per vertex, outward; empty when the mesh carries
    /// none.
    pub normals: Vec<Vec3>,
}

/// How the edges of a mesh are shared (see [`TriMesh::edge_counts`]).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub struct EdgeCounts {
    /// Distinct edges.
    pub edges: usize,
    /// Edges of exactly one triangle: the mesh is open there.
    pub open: usize,
    /// Edges of three or more triangles.
    pub non_manifold: usize,
}

impl TriMesh {
    /// A mesh named `source` from vertices and triangles (no normals, nothing degenerate).
    ///
    /// # Errors
    /// [`NurbsError::NonFiniteVertex`] for a vertex with a non-finite coordinate,
    /// [`NurbsError::TriangleIndex`] for a triangle with an index out of range.
    pub fn try_new(source: &str, vertices: Vec<Vec3>, triangles: Vec<[u32; 3]>) -> Result<Self, NurbsError> {
        if let Some(index) = vertices.iter().position(|v| !v.is_finite()) {
            return Err(NurbsError::NonFiniteVertex { mesh: source.to_string(), index, vertex: vertices[index] });
        }
        let count = vertices.len();
        if let Some((index, &indices)) =
            triangles.iter().enumerate().find(|(_, t)| t.iter().any(|&i| i as usize >= count))
        {
            return Err(NurbsError::TriangleIndex { mesh: source.to_string(), index, indices, vertices: count });
        }
        Ok(TriMesh { source: source.to_string(), vertices, triangles, degenerate: 0, normals: Vec::new() })
    }

    /// The three corners of triangle `t`.
    pub fn corners(&self, t: usize) -> [Vec3; 3] {
        let [a, b, c] = self.triangles[t];
        [self.vertices[a as usize], self.vertices[b as usize], self.vertices[c as usize]]
    }

    /// The unit normal of triangle `t` by the right-hand rule (outward for a triangle
    /// counter-clockwise seen from outside), `(0, 0, 0)` if it has no area.
    pub fn face_normal(&self, t: usize) -> Vec3 {
        let [a, b, c] = self.corners(t);
        (b - a).cross(c - a).normalized().unwrap_or(Vec3::new(0.0, 0.0, 0.0))
    }

    /// The axis-aligned bounding box `(min, max)` of the vertices used by triangles, `None`
    /// for a mesh without triangles.
    pub fn bounds(&self) -> Option<(Vec3, Vec3)> {
        let mut it = self.triangles.iter().flatten().map(|&i| self.vertices[i as usize]);
        let first = it.next()?;
        Some(it.fold((first, first), |(lo, hi), p| {
            (
                Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)),
                Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)),
            )
        }))
    }

    /// The model size: the diagonal of [`TriMesh::bounds`], 0 without triangles.
    pub fn size(&self) -> f64 {
        self.bounds().map_or(0.0, |(lo, hi)| (hi - lo).norm())
    }

    /// Counts the distinct edges and how many triangles share each: a closed (watertight)
    /// 2-manifold mesh has `open == 0` and `non_manifold == 0`.
    pub fn edge_counts(&self) -> EdgeCounts {
        let mut count: HashMap<u64, u32> = HashMap::with_capacity(self.triangles.len() * 3 / 2);
        for tri in &self.triangles {
            for k in 0..3 {
                *count.entry(TriMesh::edge_key(tri[k], tri[(k + 1) % 3])).or_insert(0) += 1;
            }
        }
        let mut out = EdgeCounts { edges: count.len(), ..EdgeCounts::default() };
        for &c in count.values() {
            match c {
                1 => out.open += 1,
                2 => {}
                _ => out.non_manifold += 1,
            }
        }
        out
    }

    /// The mesh with every vertex moved by `f` (the triangles unchanged; the vertex normals,
    /// which `f` need not carry along, dropped).
    pub fn map_vertices(mut self, f: impl Fn(Vec3) -> Vec3) -> Self {
        for v in &mut self.vertices {
            *v = f(*v);
        }
        self.normals.clear();
        self
    }

    /// The key of the undirected edge `{a, b}`, the same for `(a, b)` and `(b, a)`: the
    /// smaller index in the high 32 bits, the larger in the low.
    pub fn edge_key(a: u32, b: u32) -> u64 {
        let (lo, hi) = if a < b { (a, b) } else { (b, a) };
        (u64::from(lo) << 32) | u64::from(hi)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn edge_counts_of_a_tetrahedron_and_of_an_open_one() {
        let v = vec![
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        let closed = TriMesh::try_new("t", v.clone(), vec![[0, 2, 1], [0, 1, 3], [1, 2, 3], [0, 3, 2]]).expect("ok");
        assert_eq!(closed.edge_counts(), EdgeCounts { edges: 6, open: 0, non_manifold: 0 });
        let open = TriMesh::try_new("t", v.clone(), vec![[0, 2, 1], [0, 1, 3]]).expect("ok");
        assert_eq!(open.edge_counts(), EdgeCounts { edges: 5, open: 4, non_manifold: 0 });
        let e = TriMesh::try_new("t", v, vec![[0, 1, 4]]).expect_err("index 4 of 4 vertices");
        assert_eq!(
            e.to_string(),
            "t: triangle 1 refers to vertex indices [0, 1, 4] (expected indices below the vertex count 4)"
        );
    }

    #[test]
    fn a_non_finite_vertex_is_refused_with_its_number_from_one() {
        let v = vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(f64::NAN, 1.0, 2.0), Vec3::new(0.0, 1.0, 0.0)];
        let e = TriMesh::try_new("m.stl", v, vec![[0, 1, 2]]).expect_err("NaN");
        assert!(matches!(e, NurbsError::NonFiniteVertex { index: 1, .. }), "{e:?}");
        assert_eq!(e.to_string(), "m.stl: vertex 2 is (NaN, 1, 2) (expected finite coordinates)");
    }

    #[test]
    fn edge_keys_ignore_the_direction() {
        assert_eq!(TriMesh::edge_key(3, 7), TriMesh::edge_key(7, 3));
        assert_eq!(TriMesh::edge_key(3, 7), (3u64 << 32) | 7);
    }
}
