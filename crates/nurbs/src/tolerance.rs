//! Named tolerances and the `assert_near!` test macro.

/// Two parameters closer than this are the same knot.
pub const KNOT_EQ: f64 = 1e-12;
/// Relative tolerance of floating-point evaluation identities (partition of unity, ...).
pub const EVAL_REL: f64 = 1e-12;
/// Default geometric tolerance of closest-point projection, relative to the model size.
pub const PROJECTION_REL: f64 = 1e-12;
/// Two consecutive input points closer than this (relative to the section length) coincide.
pub const COINCIDENT_REL: f64 = 1e-12;

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
