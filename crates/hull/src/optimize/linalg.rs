//! The weight optimisation's factorizations are the kernel's ([`nurbs::band_cholesky`],
//! [`nurbs::dense_cholesky`], layouts in `nurbs`' linear-algebra docs); here only as the
//! `bool` the hot loop tests.

pub(crate) use nurbs::{band_solve, dense_solve, dot};

/// [`nurbs::band_cholesky`]: `false` when a pivot marks the matrix singular.
pub(crate) fn band_cholesky(a: &mut [f64], n: usize, bw: usize, stride: usize) -> bool {
    nurbs::band_cholesky(a, n, bw, stride).is_ok()
}

/// [`nurbs::dense_cholesky`]: `false` when a pivot marks the matrix singular.
pub(crate) fn dense_cholesky(a: &mut [f64], n: usize) -> bool {
    nurbs::dense_cholesky(a, n).is_ok()
}
