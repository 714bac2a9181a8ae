//! The kernel's one error type.

use thiserror::Error;

use crate::Vec3;

/// Everything that can go wrong in the NURBS kernel. Variants carry the offending values.
#[derive(Debug, Clone, PartialEq, Error)]
#[non_exhaustive]
pub enum NurbsError {
    #[error("degree {degree} is not supported (1 to {max})")]
    BadDegree { degree: usize, max: usize },
    #[error("knot vector has {len} knots; degree {degree} needs at least {min}")]
    TooFewKnots { len: usize, degree: usize, min: usize },
    #[error("knot {index} is not finite ({value})")]
    NonFiniteKnot { index: usize, value: f64 },
    #[error("knots decrease at index {index}: {prev} then {value}")]
    DecreasingKnots { index: usize, prev: f64, value: f64 },
    #[error("knot vector is not clamped: the first and last {needed} knots must be equal")]
    NotClamped { needed: usize },
    #[error("interior knot {value} has multiplicity {multiplicity}, more than the degree {degree}")]
    KnotMultiplicity { value: f64, multiplicity: usize, degree: usize },
    #[error("knot vector has an empty domain [{start}, {end}]")]
    EmptyDomain { start: f64, end: f64 },
    #[error("expected {expected} control points, got {got}")]
    ControlPointCount { expected: usize, got: usize },
    #[error("expected {expected} weights, got {got}")]
    WeightCount { expected: usize, got: usize },
    #[error("weight {index} is {value}; weights must be finite and positive")]
    BadWeight { index: usize, value: f64 },
    #[error("control point {index} is not finite")]
    NonFinitePoint { index: usize },
    #[error("parameter {value} lies outside the domain [{start}, {end}]")]
    ParameterOutOfDomain { value: f64, start: f64, end: f64 },
    #[error("{what}: need at least {needed} points, got {got}")]
    TooFewPoints { what: String, needed: usize, got: usize },
    #[error("{what}: points {index} and {next} coincide")]
    CoincidentPoints { what: String, index: usize, next: usize },
    #[error("{what}: {count} control points requested, but {min} to {max} are possible here")]
    BadControlPointCount { what: String, count: usize, min: usize, max: usize },
    /// Least squares with more control points than distinct data parameters: the collocation
    /// matrix has at most `distinct` independent rows, so the normal equations are singular
    /// whatever the knots. Refused (not reduced silently): `max` is the most that can work.
    #[error(
        "{what}: {count} control points requested, but the {points} points have only {distinct} distinct parameters \
         (expected at most {max} control points, or points that are not repeated)"
    )]
    TooManyControlPoints { what: String, count: usize, points: usize, distinct: usize, max: usize },
    #[error("linear system is singular or too ill-conditioned ({what})")]
    SingularSystem { what: String },
    #[error("curves are not compatible: {what}")]
    Incompatible { what: String },
    #[error("result is not finite ({what})")]
    NonFiniteResult { what: String },
    #[error("{what}: parameters decrease at index {index}: {prev} then {value}")]
    DecreasingParameters { what: String, index: usize, prev: f64, value: f64 },
    /// A tessellation tolerance that is not a positive finite length of at least `floor`,
    /// `relative` of the surface's size ([`crate::MIN_TESSELLATION_TOLERANCE_REL`]).
    #[error(
        "tessellation tolerance {tolerance}: expected a length of at least {floor:.3e} ({relative:e} of the surface's size)"
    )]
    TessellationFloor { tolerance: f64, floor: f64, relative: f64 },
    /// A tessellation tolerance that would need more than `max` grid lines in a direction
    /// ([`crate::MAX_GRID_LINES`]).
    #[error(
        "tessellation tolerance {tolerance} needs more than {max} grid lines (expected a tolerance nearer the surface's size)"
    )]
    TessellationGridLines { tolerance: f64, max: usize },
    /// A tessellation tolerance at the rounding of double precision: a chord still deviates
    /// by `deviation` where no interval can be halved any more.
    #[error(
        "tessellation tolerance {tolerance} cannot be met in double precision (a chord deviates by {deviation:.3e}; \
         expected a larger tolerance)"
    )]
    TessellationRounding { tolerance: f64, deviation: f64 },
    /// A vertex of the mesh named `mesh` with a coordinate that is not finite; `index` counts
    /// from 0, the message from 1 (as mesh files number their vertices).
    #[error("{mesh}: vertex {} is ({}, {}, {}) (expected finite coordinates)", index + 1, vertex.x, vertex.y, vertex.z)]
    NonFiniteVertex { mesh: String, index: usize, vertex: Vec3 },
    /// A triangle of the mesh named `mesh` that refers to a vertex beyond the `vertices`
    /// there are; `index` counts from 0, the message from 1.
    #[error(
        "{mesh}: triangle {} refers to vertex indices {indices:?} (expected indices below the vertex count {vertices})",
        index + 1
    )]
    TriangleIndex { mesh: String, index: usize, indices: [u32; 3], vertices: usize },
}
