//! The NURBS kernel: knot vectors, B-spline basis functions, rational curves and
//! surfaces with derivatives and curvature, knot insertion and refinement, degree elevation,
//! closest-point projection, and fitting (parameterization, interpolation, least squares,
//! skinning). `f64` and 3-D only; no I/O; every fallible call returns [`NurbsError`].

pub mod basis;
mod curve;
mod elevate;
mod error;
pub mod fit;
#[cfg(any(test, feature = "fixtures"))]
#[doc(hidden)]
pub mod fixtures;
mod grid;
mod knots;
mod linalg;
mod project;
mod quadrature;
mod refine;
mod scattered;
mod surface;
#[macro_use]
pub mod tolerance;
mod vec3;

pub use curve::{Homogeneous, NurbsCurve};
pub use error::NurbsError;
pub use grid::FirstDerivatives;
pub use knots::{KnotVector, MAX_DEGREE};
pub use linalg::{band_cholesky, band_solve, dense_cholesky, dense_solve, dot, BadPivot, BandedCholesky, BandedLu};
pub use quadrature::GaussLegendre;
pub use scattered::PointEvaluator;
pub use surface::{Curvature, NurbsSurface, SurfaceDerivatives};
pub use vec3::Vec3;
// refine / elevate / project: their helpers add `pub use` lines below.
pub use project::{
    project_point_to_curve, CurveProjection, CurveProjector, ProjectionOptions, SurfaceProjection, SurfaceProjector,
};
pub use refine::merge_knot_vectors;
