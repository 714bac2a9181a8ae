//! The NURBS kernel: knot vectors, B-spline basis functions, rational curves and
//! surfaces with derivatives and curvature, knot insertion and refinement, degree elevation,
//! closest-point projection, planar cuts by axis planes, iso-curves and their level sets,
//! tessellation into a triangle mesh, and fitting (parameterization, interpolation, least
//! squares, skinning). `f64` and 3-D only; no I/O; every fallible call returns [`NurbsError`].
//!
//! Skin a surface through a family of sections, then measure how far a point lies from it:
//!
//! ```
//! use nurbs::fit::{skin_interpolate, SkinOptions};
//! use nurbs::{ProjectionOptions, SurfaceProjector, Vec3};
//!
//! // Five sections across a half cylinder of radius 1 (x along its axis), seven points each.
//! let sections: Vec<Vec<Vec3>> = (0..5)
//!     .map(|k| {
//!         (0..7)
//!             .map(|i| std::f64::consts::PI * i as f64 / 6.0)
//!             .map(|a| Vec3::new(k as f64, a.cos(), a.sin()))
//!             .collect()
//!     })
//!     .collect();
//! let skin = skin_interpolate(&sections, &SkinOptions::default())?;
//! // A bicubic through every point: its control net is 7 x 5.
//! assert_eq!((skin.surface.n_u(), skin.surface.n_v()), (7, 5));
//! // The point (2, 0, 0) on the axis is at distance ~1 from the surface (the cubic
//! // approximates the circle to about 1e-3 with seven points).
//! let foot = SurfaceProjector::new(&skin.surface, ProjectionOptions::default()).project(Vec3::new(2.0, 0.0, 0.0));
//! assert!(foot.converged && (foot.distance - 1.0).abs() < 2e-3, "{}", foot.distance);
//! # Ok::<(), nurbs::NurbsError>(())
//! ```
//!
//! The modules: `knots`, `basis`, `curve`, `surface` (evaluation, derivatives, curvature),
//! `refine` and `elevate` (knot insertion, degree elevation), `project` (closest points),
//! `plane` (planes normal to an axis) and `cut` (planar cuts with their curvature),
//! `iso` (iso-curves over a span, with the roots of a level set along them), `brent` (Brent's
//! root finder and maximiser), `tessellate` and `mesh` (a surface triangulated to a chord
//! tolerance, the triangle mesh), `fit` (parameterization, knots, interpolation, least squares,
//! skinning, corner lines, bounded refits), `linalg` (band and dense factorizations),
//! `quadrature` (Gauss-Legendre) and `tolerance` (named tolerances).

pub mod basis;
mod brent;
mod curve;
mod cut;
mod elevate;
mod error;
pub mod fit;
#[cfg(any(test, feature = "fixtures"))]
#[doc(hidden)]
pub mod fixtures;
mod grid;
mod iso;
mod knots;
mod linalg;
mod mesh;
mod plane;
mod project;
mod quadrature;
mod refine;
mod scattered;
mod surface;
mod tessellate;
#[macro_use]
pub mod tolerance;
mod vec3;

pub use brent::{brent_max, brent_root};
pub use curve::{Homogeneous, NurbsCurve};
// Planar cuts of a surface by axis planes: ordered polylines with the cut curve's curvature.
pub use cut::{cut_curvature, cut_surface, cut_surface_many, three_point_curvature, CutCurve, CutOptions, CutPoint};
pub use error::NurbsError;
pub use grid::{FirstDerivatives, FirstDerivativesCache};
pub use iso::{Direction, IsoCurve};
pub use knots::{split_spans, KnotVector, MAX_DEGREE};
pub use linalg::{
    band_cholesky, band_forward, band_solve, dense_cholesky, dense_solve, dot, BadPivot, BandedCholesky, BandedLu,
};
pub use mesh::{EdgeCounts, TriMesh};
// Planes normal to a coordinate axis, with their 2-D drawing coordinates.
pub use plane::{Axis, AxisPlane};
pub use quadrature::GaussLegendre;
pub use scattered::PointEvaluator;
pub use surface::{Curvature, NurbsSurface, SurfaceDerivatives};
pub use tessellate::{tessellate, Tessellation, TessellationOptions, MAX_GRID_LINES, MIN_TESSELLATION_TOLERANCE_REL};
pub use vec3::Vec3;
// refine / elevate / project: their helpers add `pub use` lines below.
pub use project::{
    project_point_to_curve, CurveProjection, CurveProjector, ProjectionOptions, SurfaceProjection, SurfaceProjector,
};
pub use refine::merge_knot_vectors;
