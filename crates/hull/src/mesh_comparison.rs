//! A surface fitted to sections sliced from a mesh, measured against the mesh at one draft (what
//! `hullskin slice --check` prints): the surface's hydrostatics beside the mesh's, and the
//! distance of the mesh's wetted starboard vertices to the surface.

use nurbs::{NurbsSurface, TriMesh};

use crate::error::HullError;
use crate::hydrostatics::{Hydrostatics, HydrostaticsOptions, HydrostaticsRow};
use crate::mesh::{mesh_distance, MeshDistance, MeshHydrostatics, VertexFilter};
use crate::offsets::Offsets;

/// A surface against a mesh at the mesh's draft ([`compare_mesh_and_surface`]).
#[derive(Clone, Debug)]
pub struct MeshComparison {
    /// The surface's hydrostatics at the mesh's draft.
    pub surface: HydrostaticsRow,
    /// `100 (surface - mesh) / mesh` of the displaced volume (NaN where the mesh's is 0).
    pub volume_pct: f64,
    /// The same of the wetted surface.
    pub wetted_surface_pct: f64,
    /// The same of the waterplane area.
    pub waterplane_pct: f64,
    /// Surface minus mesh: LCB.
    pub lcb_diff: f64,
    /// Surface minus mesh: KB.
    pub kb_diff: f64,
    /// The distance of the mesh's wetted starboard vertices within the sections' length to the
    /// surface ([`mesh_distance`]); `None` when `sections` has no point.
    pub distance: Option<MeshDistance>,
}

/// `surface` (fitted to `sections`, sliced from `mesh`) against `mesh`, whose hydrostatics at
/// its draft are `at` ([`crate::mesh::mesh_hydrostatics`]): the surface's figures at the same
/// draft with their differences from the mesh's, and the distance of the mesh's wetted
/// starboard vertices (between the sections' ends, up to the draft) to the surface.
///
/// # Errors
/// Those of [`Hydrostatics::new`] and [`Hydrostatics::at`] (a surface that cannot be
/// integrated, a draft above it).
pub fn compare_mesh_and_surface(
    surface: &NurbsSurface,
    mesh: &TriMesh,
    sections: &Offsets,
    at: &MeshHydrostatics,
) -> Result<MeshComparison, HullError> {
    let row = Hydrostatics::new(surface, &HydrostaticsOptions::default()).and_then(|h| h.at(at.draft))?;
    let pct = |a: f64, b: f64| if b != 0.0 { 100.0 * (a - b) / b } else { f64::NAN };
    let distance = VertexFilter::for_sections(sections, at.draft).map(|filter| mesh_distance(mesh, surface, &filter));
    Ok(MeshComparison {
        volume_pct: pct(row.vol, at.volume),
        wetted_surface_pct: pct(row.s, at.wetted_surface),
        waterplane_pct: pct(row.aw, at.waterplane_area),
        lcb_diff: row.lcb - at.lcb,
        kb_diff: row.vcb - at.vcb,
        surface: row,
        distance,
    })
}
