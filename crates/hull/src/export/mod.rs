//! Exports of the fitted surface to exchange formats: IGES 5.3 (surface entity 128, section
//! curves entity 126, and a polynomial approximation for systems that drop weights), STEP
//! AP214, triangle meshes to a chordal tolerance (STL, OBJ, binary glTF, from the kernel's
//! [`nurbs::tessellate()`]) and the lossless
//! hullskin surface JSON. Writers are generic over [`std::io::Write`] and format every real
//! number of text formats through [`crate::float::real`].

mod iges;
mod mesh_out;
mod mirror;
mod polynomial;
mod step;
mod surface_json;

pub use iges::{
    greville_v, iges_timestamp, section_curves, section_parameters, write_iges, write_iges_model, IgesMeta, IgesUnits,
    MAX_STRING_LEN,
};
pub use mesh_out::{curvature_colors, mesh_name, obj_comments, srgb_to_linear, stl_header, write_glb};
pub use mirror::mirrored_full_hull;
pub use polynomial::{
    polynomial_approximation, PolynomialApproximation, MAX_CONTROL_POINTS as MAX_POLYNOMIAL_CONTROL_POINTS,
    MIN_POLYNOMIAL_TOLERANCE_REL,
};
pub use step::{step_timestamp, write_step, StepMeta};
pub use surface_json::{read_surface_json, write_surface_json, SurfaceFile, SurfaceJsonError};
