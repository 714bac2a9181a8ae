//! Linear algebra of the kernel: band and dense factorizations written on plain slices, so
//! that a hot loop allocates nothing, and their owning wrappers for the fitting systems.
//!
//! * [`BandedLu`]: `A = L U` of a square band matrix without pivoting, for the collocation
//!   matrix `N_{i,p}(t_k)` of interpolation (at most `p + 1` non-zeros per row around the
//!   diagonal).
//! * Banded Cholesky ([`band_cholesky`], [`band_solve`]; [`BandedCholesky`] owns its storage):
//!   `A = L L^T` of a symmetric positive definite matrix of half-bandwidth `bw`, such as the
//!   normal matrix `N^T N` of least squares (half-bandwidth `p`). The lower triangle is stored
//!   by rows of `stride >= bw + 1` slots, row `i` holding `A_{i, i-bw} ..= A_{i,i}` at
//!   `a[i stride ..= i stride + bw]` (entry `(i, j)` at `i stride + j + bw - i`; slots past
//!   `bw` are padding, ignored, so that an assembly may write whole blocks). The first `bw`
//!   rows have slots for `j < 0`; they must hold zeros, which lets every inner product run over
//!   full, contiguous slices. Cost `n bw^2 / 2` multiply-adds (Golub and Van Loan, *Matrix
//!   Computations*, 4th ed., Alg. 4.3.5), against the `O(n^3)` of a dense factorization.
//! * Dense Cholesky ([`dense_cholesky`], [`dense_solve`]) of a small `n x n` matrix stored
//!   row-major (Alg. 4.2.1).
//!
//! All factor once and then solve any number of right-hand sides. A pivot `d_i = a_ii - sum_k
//! l_ik^2` not above [`PIVOT_REL`] `a_ii` marks the matrix singular or too ill-conditioned:
//! `d_i / a_ii` (it equals `1 / (A^{-1})_ii / a_ii`) bounds `1 / cond(A)` from above, and beyond
//! `1e12` the solution would have lost most of its digits.

use crate::tolerance::PIVOT_REL;
use crate::NurbsError;

/// A pivot of a Cholesky factorization that is not above [`PIVOT_REL`] times its diagonal
/// entry (or is NaN): the matrix is singular or too ill-conditioned.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct BadPivot {
    /// The row of the pivot.
    pub row: usize,
    /// The pivot `a_ii - sum_k l_ik^2`.
    pub pivot: f64,
    /// The diagonal entry `a_ii`.
    pub diagonal: f64,
}

/// `A = L U` of a square band matrix with `kl` sub- and `ku` super-diagonals, without
/// pivoting. That is stable for a totally positive matrix such as a B-spline collocation matrix
/// at increasing parameters (de Boor and Pinkus 1977, "Backward error analysis for totally
/// positive linear systems"): its leading principal minors are positive, so the pivots are too,
/// and no fill leaves the band.
#[derive(Clone, Debug)]
pub struct BandedLu {
    n: usize,
    kl: usize,
    ku: usize,
    a: Vec<f64>,
}

impl BandedLu {
    /// The zero matrix of order `n` with `kl` sub- and `ku` super-diagonals.
    pub fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        BandedLu { n, kl, ku, a: vec![0.0; n * (kl + ku + 1)] }
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        debug_assert!(j + self.kl >= i && j <= i + self.ku, "({i}, {j}) outside the band");
        i * (self.kl + self.ku + 1) + j + self.kl - i
    }

    /// Set entry `(i, j)`, which must lie in the band.
    #[inline]
    pub fn set(&mut self, i: usize, j: usize, v: f64) {
        let k = self.idx(i, j);
        self.a[k] = v;
    }

    /// Factor in place (Doolittle: unit lower `L` below the diagonal, `U` on and above).
    ///
    /// # Errors
    /// [`NurbsError::SingularSystem`] if a pivot is not above [`PIVOT_REL`] times the largest
    /// entry of its original row.
    pub fn factor(&mut self, what: &str) -> Result<(), NurbsError> {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        let w = kl + ku + 1;
        let row_max: Vec<f64> =
            (0..n).map(|i| self.a[i * w..(i + 1) * w].iter().fold(0.0f64, |m, x| m.max(x.abs()))).collect();
        for (k, &rm) in row_max.iter().enumerate() {
            let pivot = self.a[self.idx(k, k)];
            let usable = pivot.abs() > PIVOT_REL * rm; // false for NaN too
            if !usable {
                return Err(NurbsError::SingularSystem { what: format!("{what}: pivot {pivot:e} in row {k} of {n}") });
            }
            let jmax = (k + ku).min(n - 1);
            for i in k + 1..=(k + kl).min(n - 1) {
                let ik = self.idx(i, k);
                let l = self.a[ik] / pivot;
                self.a[ik] = l;
                if l != 0.0 {
                    for j in k + 1..=jmax {
                        let (ij, kj) = (self.idx(i, j), self.idx(k, j));
                        self.a[ij] -= l * self.a[kj];
                    }
                }
            }
        }
        Ok(())
    }

    /// Overwrite `b` with `A^{-1} b`, each `[f64; D]` one row of `D` right-hand sides.
    pub fn solve<const D: usize>(&self, b: &mut [[f64; D]]) {
        let (n, kl, ku) = (self.n, self.kl, self.ku);
        debug_assert_eq!(b.len(), n);
        // Forward: L y = b (unit diagonal).
        for i in 0..n {
            let lo = i.saturating_sub(kl);
            let (done, rest) = b.split_at_mut(i);
            for (j, bj) in (lo..i).zip(&done[lo..]) {
                axpy(&mut rest[0], -self.a[self.idx(i, j)], bj);
            }
        }
        // Backward: U x = y.
        for i in (0..n).rev() {
            let hi = (i + ku).min(n - 1);
            let (head, tail) = b.split_at_mut(i + 1);
            let s = &mut head[i];
            for (j, bj) in (i + 1..=hi).zip(&tail[..hi - i]) {
                axpy(s, -self.a[self.idx(i, j)], bj);
            }
            let d = self.a[self.idx(i, i)];
            s.iter_mut().for_each(|x| *x /= d);
        }
    }
}

/// `A = L L^T` of a symmetric positive definite band matrix of half-bandwidth `bw` that owns
/// its storage ([`band_cholesky`] with `stride = bw + 1`).
#[derive(Clone, Debug)]
pub struct BandedCholesky {
    n: usize,
    bw: usize,
    l: Vec<f64>,
}

impl BandedCholesky {
    /// The zero matrix of `n` rows and half-bandwidth `bw`.
    pub fn zeros(n: usize, bw: usize) -> Self {
        BandedCholesky { n, bw, l: vec![0.0; n * (bw + 1)] }
    }

    /// Add `v` to entry `(i, j)` of the lower triangle (`j <= i <= j + bw`).
    #[inline]
    pub fn add(&mut self, i: usize, j: usize, v: f64) {
        debug_assert!(j <= i && i <= j + self.bw, "({i}, {j}) outside the lower band");
        self.l[i * (self.bw + 1) + j + self.bw - i] += v;
    }

    /// Factor in place.
    ///
    /// # Errors
    /// [`NurbsError::SingularSystem`] naming `what` if a pivot `a_ii - sum_k l_ik^2` is not above
    /// [`PIVOT_REL`] times `a_ii`.
    pub fn factor(&mut self, what: &str) -> Result<(), NurbsError> {
        let n = self.n;
        band_cholesky(&mut self.l, n, self.bw, self.bw + 1).map_err(|BadPivot { row, pivot, diagonal }| {
            NurbsError::SingularSystem {
                what: format!("{what}: pivot {pivot:e} against diagonal {diagonal:e} in row {row} of {n}"),
            }
        })
    }

    /// Overwrite `b` with `A^{-1} b`, each `[f64; D]` one row of `D` right-hand sides.
    pub fn solve<const D: usize>(&self, b: &mut [[f64; D]]) {
        band_solve(&self.l, self.n, self.bw, self.bw + 1, b);
    }
}

/// `sum_i a_i b_i` over the common length, with four accumulators (lets the compiler use SIMD
/// lanes; the summation order is fixed, so results are deterministic).
#[inline]
pub fn dot(a: &[f64], b: &[f64]) -> f64 {
    let n = a.len().min(b.len());
    let (a, b) = (&a[..n], &b[..n]);
    let ca = a.chunks_exact(4);
    let cb = b.chunks_exact(4);
    let (ra, rb) = (ca.remainder(), cb.remainder());
    let mut acc = [0.0f64; 4];
    for (x, y) in ca.zip(cb) {
        acc[0] += x[0] * y[0];
        acc[1] += x[1] * y[1];
        acc[2] += x[2] * y[2];
        acc[3] += x[3] * y[3];
    }
    let mut s = (acc[0] + acc[1]) + (acc[2] + acc[3]);
    for (x, y) in ra.iter().zip(rb) {
        s += x * y;
    }
    s
}

/// Factor the band matrix `a` (`n` rows, half-bandwidth `bw`, row `stride`, layout in the
/// module docs) in place into its Cholesky factor `L`.
///
/// # Errors
/// The first [`BadPivot`], leaving `a` partly overwritten, when a pivot is not above
/// [`PIVOT_REL`] times its diagonal entry (or is NaN).
pub fn band_cholesky(a: &mut [f64], n: usize, bw: usize, stride: usize) -> Result<(), BadPivot> {
    let w = bw + 1;
    debug_assert!(stride >= w && a.len() >= n * stride);
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * stride);
        let row = &mut rest[..w];
        // Off-diagonal entries j = max(i - bw, 0) .. i, at slot o = j + bw - i.
        let o0 = bw.saturating_sub(i);
        for o in o0..bw {
            let j = i + o - bw;
            let rj = &done[j * stride..j * stride + w];
            // a_ij - sum_{k = i-bw}^{j-1} l_ik l_jk: row i slots 0..o, row j slots (i - j)..bw
            // (the zero slots of k < 0 change nothing), summed by `dot` (four partial sums, a
            // fixed order: the factor is the same on every run; 10 % off LM on the largest
            // tables of `testdata/`, where this factor is a fifth of its time).
            let s = row[o] - dot(&row[..o], &rj[bw - o..bw]);
            row[o] = s / rj[bw];
        }
        let d = row[bw] - dot(&row[..bw], &row[..bw]);
        row[bw] = checked_sqrt(i, row[bw], d)?;
    }
    Ok(())
}

/// The diagonal entry `l_ii = sqrt(d)` of row `i` of a Cholesky factor, from the pivot
/// `d = a_ii - sum_k l_ik^2`.
///
/// # Errors
/// [`BadPivot`] when the pivot is not above [`PIVOT_REL`] `a_ii` (or is NaN).
#[inline]
fn checked_sqrt(i: usize, aii: f64, d: f64) -> Result<f64, BadPivot> {
    let usable = d > PIVOT_REL * aii; // false for NaN too
    if usable {
        Ok(d.sqrt())
    } else {
        Err(BadPivot { row: i, pivot: d, diagonal: aii })
    }
}

/// Overwrite `b` with `L^{-1} b` (forward substitution, by rows) for the factor `l` of
/// [`band_cholesky`], when `b` is zero before row `start` (so is the result there, and those
/// rows are skipped); each `[f64; D]` is one row of `D` right-hand sides. [`band_solve`]'s
/// first half, for `start` 0.
pub fn band_forward<const D: usize>(l: &[f64], n: usize, bw: usize, stride: usize, b: &mut [[f64; D]], start: usize) {
    debug_assert_eq!(b.len(), n);
    for i in start..n {
        let row = &l[i * stride..i * stride + bw + 1];
        let k0 = i.saturating_sub(bw).max(start);
        let (done, rest) = b.split_at_mut(i);
        let mut s = rest[0];
        for (lk, bk) in row[k0 + bw - i..bw].iter().zip(&done[k0..]) {
            for c in 0..D {
                s[c] -= lk * bk[c];
            }
        }
        let d = row[bw];
        s.iter_mut().for_each(|t| *t /= d);
        rest[0] = s;
    }
}

/// Overwrite `b` with `A^{-1} b` from the factor `l` of [`band_cholesky`]; each `[f64; D]` is
/// one row of `D` right-hand sides.
pub fn band_solve<const D: usize>(l: &[f64], n: usize, bw: usize, stride: usize, b: &mut [[f64; D]]) {
    let w = bw + 1;
    // Forward: L y = b, by rows.
    band_forward(l, n, bw, stride, b, 0);
    // Backward: L^T x = y, by columns of L^T (rows of L, read contiguously): x_i is final
    // once every later x_k has been subtracted from it, then subtracted from the rows above.
    for i in (0..n).rev() {
        let row = &l[i * stride..i * stride + w];
        let k0 = i.saturating_sub(bw);
        let (above, at) = b.split_at_mut(i);
        let d = row[bw];
        let mut x = at[0];
        x.iter_mut().for_each(|t| *t /= d);
        at[0] = x;
        for (lk, bk) in row[k0 + bw - i..bw].iter().zip(&mut above[k0..]) {
            for c in 0..D {
                bk[c] -= lk * x[c];
            }
        }
    }
}

/// Factor the dense symmetric `n x n` matrix `a` (row-major, lower triangle read) in place into
/// `L` (lower triangle; the upper triangle is left as is).
///
/// # Errors
/// The first [`BadPivot`] when a pivot is not above [`PIVOT_REL`] times its diagonal entry.
pub fn dense_cholesky(a: &mut [f64], n: usize) -> Result<(), BadPivot> {
    debug_assert_eq!(a.len(), n * n);
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * n);
        let row = &mut rest[..n];
        for j in 0..i {
            let rj = &done[j * n..j * n + n];
            let s = row[j] - dot(&row[..j], &rj[..j]);
            row[j] = s / rj[j];
        }
        let d = row[i] - dot(&row[..i], &row[..i]);
        row[i] = checked_sqrt(i, row[i], d)?;
    }
    Ok(())
}

/// Overwrite `b` with `A^{-1} b` from the factor of [`dense_cholesky`].
pub fn dense_solve(l: &[f64], n: usize, b: &mut [f64]) {
    for i in 0..n {
        let row = &l[i * n..i * n + n];
        b[i] = (b[i] - dot(&row[..i], &b[..i])) / row[i];
    }
    for i in (0..n).rev() {
        let row = &l[i * n..i * n + n];
        let xi = b[i] / row[i];
        b[i] = xi;
        for (lk, bk) in row[..i].iter().zip(&mut b[..i]) {
            *bk -= lk * xi;
        }
    }
}

/// `y += a x`.
#[inline]
fn axpy<const D: usize>(y: &mut [f64; D], a: f64, x: &[f64; D]) {
    for (yc, xc) in y.iter_mut().zip(x) {
        *yc += a * xc;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::{DMatrix, DVector};

    fn pseudo_random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
    }

    #[test]
    fn banded_lu_matches_nalgebra_dense_lu() {
        let mut seed = 7;
        for (n, kl, ku) in [(1, 0, 0), (5, 1, 2), (12, 3, 1), (30, 2, 2), (9, 0, 3)] {
            let mut band = BandedLu::zeros(n, kl, ku);
            let mut dense = DMatrix::<f64>::zeros(n, n);
            for i in 0..n {
                for j in i.saturating_sub(kl)..=(i + ku).min(n - 1) {
                    // Diagonally dominant: no pivoting needed.
                    let v = if i == j { 4.0 + pseudo_random(&mut seed) } else { pseudo_random(&mut seed) };
                    band.set(i, j, v);
                    dense[(i, j)] = v;
                }
            }
            band.factor("test").expect("dominant diagonal");
            let rhs: Vec<[f64; 2]> = (0..n).map(|_| [pseudo_random(&mut seed), pseudo_random(&mut seed)]).collect();
            let mut x = rhs.clone();
            band.solve(&mut x);
            let lu = dense.lu();
            for c in 0..2 {
                let b = DVector::from_iterator(n, rhs.iter().map(|r| r[c]));
                let reference = lu.solve(&b).expect("nonsingular");
                for i in 0..n {
                    // Well-conditioned (dominant) systems: agreement to a few ulps times n.
                    assert!((x[i][c] - reference[i]).abs() < 1e-13, "n {n} i {i}");
                }
            }
        }
    }

    #[test]
    fn banded_cholesky_matches_nalgebra_cholesky() {
        let mut seed = 11;
        for (n, bw) in [(1, 0), (6, 1), (15, 3), (40, 4)] {
            let mut band = BandedCholesky::zeros(n, bw);
            let mut dense = DMatrix::<f64>::zeros(n, n);
            for i in 0..n {
                for j in i.saturating_sub(bw)..=i {
                    let v = if i == j { 2.0 * bw as f64 + 1.0 } else { pseudo_random(&mut seed) };
                    band.add(i, j, v);
                    dense[(i, j)] = v;
                    dense[(j, i)] = v;
                }
            }
            band.factor("test").expect("dominant diagonal, SPD");
            let rhs: Vec<[f64; 1]> = (0..n).map(|_| [pseudo_random(&mut seed)]).collect();
            let mut x = rhs.clone();
            band.solve(&mut x);
            let reference = dense.cholesky().expect("SPD").solve(&DVector::from_iterator(n, rhs.iter().map(|r| r[0])));
            for i in 0..n {
                assert!((x[i][0] - reference[i]).abs() < 1e-13, "n {n} i {i}");
            }
        }
    }

    #[test]
    fn ill_conditioned_matrices_are_reported_by_the_pivot_ratio() {
        // [[1, 1 - e], [1 - e, 1]] has eigenvalues e and 2 - e, cond = (2 - e) / e, and its
        // second pivot is 1 - (1 - e)^2 ~ 2 e of its diagonal: the pivot test reads the
        // condition number. cond 2e13 is refused; cond 2e10 is solved, to the accuracy that
        // condition allows (cond x eps ~ 4e-6 relative).
        let matrix = |e: f64| {
            let mut ch = BandedCholesky::zeros(2, 1);
            for (i, j, v) in [(0, 0, 1.0), (1, 0, 1.0 - e), (1, 1, 1.0)] {
                ch.add(i, j, v);
            }
            ch
        };
        match matrix(1e-13).factor("t") {
            Err(NurbsError::SingularSystem { what }) => assert!(what.contains("row 1 of 2"), "{what}"),
            other => panic!("cond 2e13 accepted: {other:?}"),
        }
        let mut ch = matrix(1e-10);
        ch.factor("t").expect("cond 2e10 is within the 1e12 threshold");
        // x = (1, -1): b = A x = (e, -e).
        let mut b = [[1e-10], [-1e-10]];
        ch.solve(&mut b);
        assert!((b[0][0] - 1.0).abs() < 1e-5 && (b[1][0] + 1.0).abs() < 1e-5, "{b:?}");
    }

    #[test]
    fn singular_matrices_are_reported() {
        let mut lu = BandedLu::zeros(3, 1, 1);
        for (i, j, v) in [(0, 0, 1.0), (0, 1, 1.0), (1, 0, 1.0), (1, 1, 1.0), (2, 2, 1.0)] {
            lu.set(i, j, v);
        }
        assert!(matches!(lu.factor("t"), Err(NurbsError::SingularSystem { .. })));
        let mut ch = BandedCholesky::zeros(2, 1);
        for (i, j, v) in [(0, 0, 1.0), (1, 0, 1.0), (1, 1, 1.0)] {
            ch.add(i, j, v);
        }
        assert!(matches!(ch.factor("t"), Err(NurbsError::SingularSystem { .. })));
    }

    /// A random SPD band matrix `M M^T + n I` (M banded lower, bandwidth bw) as dense.
    fn spd(n: usize, bw: usize, seed: &mut u64) -> Vec<f64> {
        let mut m = vec![0.0; n * n];
        for i in 0..n {
            for j in i.saturating_sub(bw / 2)..=i {
                m[i * n + j] = pseudo_random(seed);
            }
        }
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] = (0..n).map(|k| m[i * n + k] * m[j * n + k]).sum::<f64>();
            }
            a[i * n + i] += 1.0;
        }
        a
    }

    #[test]
    fn band_and_dense_cholesky_solve_spd_systems() {
        let mut seed = 3;
        for (n, bw) in [(1, 0), (2, 1), (7, 2), (20, 6), (33, 33), (40, 9)] {
            let a = spd(n, bw, &mut seed);
            let x_true: Vec<[f64; 3]> = (0..n)
                .map(|_| [pseudo_random(&mut seed), pseudo_random(&mut seed), pseudo_random(&mut seed)])
                .collect();
            let mut b: Vec<[f64; 3]> = (0..n)
                .map(|i| {
                    let mut r = [0.0; 3];
                    for (j, xj) in x_true.iter().enumerate() {
                        for c in 0..3 {
                            r[c] += a[i * n + j] * xj[c];
                        }
                    }
                    r
                })
                .collect();
            let bw = bw.min(n.saturating_sub(1));
            // Padded rows (stride bw + 3) must give the same answer as tight ones.
            let stride = bw + 1 + 2 * (n % 2);
            let mut band = vec![f64::NAN; n * stride];
            for i in 0..n {
                band[i * stride..i * stride + bw + 1].fill(0.0);
                for j in i.saturating_sub(bw)..=i {
                    band[i * stride + j + bw - i] = a[i * n + j];
                }
            }
            let mut dense = a.clone();
            let mut bd: Vec<f64> = b.iter().map(|r| r[1]).collect();
            assert!(band_cholesky(&mut band, n, bw, stride).is_ok(), "n {n}");
            band_solve(&band, n, bw, stride, &mut b);
            assert!(dense_cholesky(&mut dense, n).is_ok(), "n {n}");
            dense_solve(&dense, n, &mut bd);
            // cond(A) <= ~ (1 + n bw) here: a few hundred ulps of the solution at most.
            for i in 0..n {
                for c in 0..3 {
                    assert!((b[i][c] - x_true[i][c]).abs() < 1e-12, "band n {n} i {i}");
                }
                assert!((bd[i] - x_true[i][1]).abs() < 1e-12, "dense n {n} i {i}");
            }
        }
    }

    #[test]
    fn the_forward_substitution_from_a_later_row_gives_the_full_ones_result() {
        // A right-hand side zero before row `start` (a column of a sparse Jacobian): the
        // forward pass begun there is the whole pass bit for bit (the skipped rows would only
        // subtract zeros), and `L y` gives back the right-hand side.
        let mut seed = 11;
        let (n, bw) = (30, 5);
        let a = spd(n, bw, &mut seed);
        let stride = bw + 1;
        let mut band = vec![0.0; n * stride];
        for i in 0..n {
            for j in i.saturating_sub(bw)..=i {
                band[i * stride + j + bw - i] = a[i * n + j];
            }
        }
        assert!(band_cholesky(&mut band, n, bw, stride).is_ok());
        for start in [0, 1, 7, 29] {
            let b: Vec<[f64; 2]> =
                (0..n).map(|i| if i < start { [0.0; 2] } else { [pseudo_random(&mut seed), -1.0] }).collect();
            let (mut from, mut whole) = (b.clone(), b.clone());
            band_forward(&band, n, bw, stride, &mut from, start);
            band_forward(&band, n, bw, stride, &mut whole, 0);
            assert_eq!(from, whole, "start {start}");
            for i in 0..n {
                for c in 0..2 {
                    let ly: f64 = (i.saturating_sub(bw)..=i).map(|k| band[i * stride + k + bw - i] * from[k][c]).sum();
                    // |L| |y| is O(10) here: a few ulps of it.
                    assert!((ly - b[i][c]).abs() < 1e-12, "start {start} row {i}");
                }
            }
        }
    }

    #[test]
    fn singular_and_nan_matrices_are_refused() {
        // [[1, 1], [1, 1]]: the second pivot is 0.
        let mut band = vec![0.0, 1.0, 1.0, 1.0];
        assert!(band_cholesky(&mut band, 2, 1, 2).is_err());
        let mut dense = vec![1.0, 1.0, 1.0, 1.0];
        assert!(dense_cholesky(&mut dense, 2).is_err());
        let mut nan = vec![f64::NAN];
        assert!(band_cholesky(&mut nan, 1, 0, 1).is_err());
        let mut nan = vec![f64::NAN];
        assert!(dense_cholesky(&mut nan, 1).is_err());
    }

    #[test]
    fn dot_matches_the_naive_sum_on_all_remainders() {
        for n in 0..11 {
            let a: Vec<f64> = (0..n).map(|i| 1.0 + i as f64).collect();
            let b: Vec<f64> = (0..n).map(|i| 0.5 * i as f64).collect();
            // Small integers and halves: exact in any order.
            assert_eq!(dot(&a, &b), a.iter().zip(&b).map(|(x, y)| x * y).sum::<f64>());
        }
    }
}
