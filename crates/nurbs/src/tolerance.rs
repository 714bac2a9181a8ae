//! Named tolerances and the `assert_near!` test macro.

/// Two parameters closer than this are the same knot.
pub const KNOT_EQ: f64 = 1e-12;
/// Relative tolerance of floating-point evaluation identities (partition of unity, ...).
pub const EVAL_REL: f64 = 1e-12;
/// Default geometric tolerance of closest-point projection, relative to the model size.
pub const PROJECTION_REL: f64 = 1e-12;
/// Two points closer than this times the size they are measured against (a section's polyline
/// length, the diagonal of the data's bounding box; a gap of parameters in `[0, 1]`) are one
/// point. 1e-9 is far below any drawing precision (0.1 µm on a 100 m model) yet far above the
/// rounding of a coordinate (1e-16 relative), so it catches only points given twice; the fit
/// refuses such data (its chord-length parameters would repeat) and a section of one repeated
/// point is a pointed end. The same tolerance serves the kernel and the readers above it.
pub const COINCIDENT_REL: f64 = 1e-9;
/// A pivot of a factorization not above this times its diagonal entry (Cholesky) or the largest
/// entry of its row (LU) marks the matrix singular or too ill-conditioned: the relative pivot
/// bounds the reciprocal condition number from above, and beyond `1e12` the solution would have
/// lost most of its digits.
pub const PIVOT_REL: f64 = 1e-12;

/// Below this ratio `|S_u x S_v| / (|S_u|^2 + |S_v|^2)` (the sine of the angle between a
/// surface's parameter lines times the ratio of their speeds) a point counts as degenerate
/// ([`SurfaceDerivatives::regular_normal`](crate::SurfaceDerivatives::regular_normal)): the
/// curvature from the fundamental forms then carries a relative round-off of ~1e-16 / 1e-8.
pub const DEGENERATE_REL: f64 = 1e-8;

/// Assert that two numbers (or `Vec3`s) agree within an absolute tolerance, printing both.
#[macro_export]
macro_rules! assert_near {
    ($a:expr, $b:expr, $tol:expr $(,)?) => {
        $crate::assert_near!($a, $b, $tol, "")
    };
    ($a:expr, $b:expr, $tol:expr, $($msg:tt)+) => {{
        let (a, b, tol) = ($a, $b, $tol);
        let d = $crate::tolerance::Near::distance(&a, &b);
        assert!(
            d <= tol,
            "assert_near failed: |{:?} - {:?}| = {:e} > {:e} {}",
            a, b, d, tol, format!($($msg)+)
        );
    }};
}

/// Values `assert_near!` can compare.
pub trait Near {
    fn distance(&self, other: &Self) -> f64;
}

impl Near for f64 {
    fn distance(&self, other: &Self) -> f64 {
        if self == other {
            0.0
        } else {
            (self - other).abs()
        }
    }
}

impl Near for crate::Vec3 {
    fn distance(&self, other: &Self) -> f64 {
        (*self - *other).norm()
    }
}
