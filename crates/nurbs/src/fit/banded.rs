//! Banded factorizations for the fitting systems: the collocation matrix `N_{i,p}(t_k)` of
//! interpolation has at most `p + 1` non-zeros per row around the diagonal, and the normal
//! matrix `N^T N` of least squares has half-bandwidth `p`. Factoring in band storage costs
//! `O(n p^2)` instead of the `O(n^3)` of a dense factorization (nalgebra has no banded
//! solver; the dense nalgebra solvers serve as the reference in the tests). Both factor once
//! and then solve any number of right-hand sides (one per coordinate, section or column).

use crate::NurbsError;

/// A pivot smaller than this, relative to the size of its row, marks the system singular or
/// too ill-conditioned: the relative pivot bounds the reciprocal condition number from above,
/// and beyond `1e12` the fitted control points would have lost most of their digits.
pub(crate) const PIVOT_REL: f64 = 1e-12;

/// `A = L U` of a square band matrix with `kl` sub- and `ku` super-diagonals, without
/// pivoting. That is stable for a totally positive matrix such as a B-spline collocation matrix
/// at increasing parameters (de Boor and Pinkus 1977, "Backward error analysis for totally
/// positive linear systems"): its leading principal minors are positive, so the pivots are too,
/// and no fill leaves the band.
#[derive(Clone, Debug)]
pub(crate) struct BandedLu {
    n: usize,
    kl: usize,
    ku: usize,
    a: Vec<f64>,
}

impl BandedLu {
    pub(crate) fn zeros(n: usize, kl: usize, ku: usize) -> Self {
        BandedLu { n, kl, ku, a: vec![0.0; n * (kl + ku + 1)] }
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        debug_assert!(j + self.kl >= i && j <= i + self.ku, "({i}, {j}) outside the band");
        i * (self.kl + self.ku + 1) + j + self.kl - i
    }

    /// Set entry `(i, j)`, which must lie in the band.
    #[inline]
    pub(crate) fn set(&mut self, i: usize, j: usize, v: f64) {
        let k = self.idx(i, j);
        self.a[k] = v;
    }

    /// Factor in place (Doolittle: unit lower `L` below the diagonal, `U` on and above).
    ///
    /// # Errors
    /// [`NurbsError::SingularSystem`] if a pivot is not above [`PIVOT_REL`] times the largest
    /// entry of its original row.
    pub(crate) fn factor(&mut self, what: &str) -> Result<(), NurbsError> {
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
    pub(crate) fn solve<const D: usize>(&self, b: &mut [[f64; D]]) {
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

/// `A = L L^T` of a symmetric positive definite band matrix of half-bandwidth `bw`, storing the
/// lower triangle by rows.
#[derive(Clone, Debug)]
pub(crate) struct BandedCholesky {
    n: usize,
    bw: usize,
    l: Vec<f64>,
}

impl BandedCholesky {
    pub(crate) fn zeros(n: usize, bw: usize) -> Self {
        BandedCholesky { n, bw, l: vec![0.0; n * (bw + 1)] }
    }

    #[inline]
    fn idx(&self, i: usize, j: usize) -> usize {
        debug_assert!(j <= i && i <= j + self.bw, "({i}, {j}) outside the lower band");
        i * (self.bw + 1) + j + self.bw - i
    }

    /// Add `v` to entry `(i, j)` of the lower triangle (`j <= i <= j + bw`).
    #[inline]
    pub(crate) fn add(&mut self, i: usize, j: usize, v: f64) {
        let k = self.idx(i, j);
        self.l[k] += v;
    }

    /// Factor in place.
    ///
    /// # Errors
    /// [`NurbsError::SingularSystem`] if a pivot `a_ii - sum_k l_ik^2` is not above
    /// [`PIVOT_REL`] times `a_ii` (it equals `1 / (A^{-1})_ii`, so its ratio to `a_ii` bounds
    /// `1 / cond(A)` from above).
    pub(crate) fn factor(&mut self, what: &str) -> Result<(), NurbsError> {
        let (n, bw) = (self.n, self.bw);
        for i in 0..n {
            let j0 = i.saturating_sub(bw);
            for j in j0..=i {
                let mut s = self.l[self.idx(i, j)];
                for k in j0.max(j.saturating_sub(bw))..j {
                    s -= self.l[self.idx(i, k)] * self.l[self.idx(j, k)];
                }
                if i == j {
                    let aii = self.l[self.idx(i, i)];
                    let usable = s > PIVOT_REL * aii; // false for NaN too
                    if !usable {
                        return Err(NurbsError::SingularSystem {
                            what: format!("{what}: pivot {s:e} against diagonal {aii:e} in row {i} of {n}"),
                        });
                    }
                    let k = self.idx(i, i);
                    self.l[k] = s.sqrt();
                } else {
                    let k = self.idx(i, j);
                    self.l[k] = s / self.l[self.idx(j, j)];
                }
            }
        }
        Ok(())
    }

    /// Overwrite `b` with `A^{-1} b`.
    pub(crate) fn solve<const D: usize>(&self, b: &mut [[f64; D]]) {
        let (n, bw) = (self.n, self.bw);
        debug_assert_eq!(b.len(), n);
        // Forward: L y = b.
        for i in 0..n {
            let lo = i.saturating_sub(bw);
            let (done, rest) = b.split_at_mut(i);
            let s = &mut rest[0];
            for (k, bk) in (lo..i).zip(&done[lo..]) {
                axpy(s, -self.l[self.idx(i, k)], bk);
            }
            let d = self.l[self.idx(i, i)];
            s.iter_mut().for_each(|x| *x /= d);
        }
        // Backward: L^T x = y.
        for i in (0..n).rev() {
            let hi = (i + bw).min(n - 1);
            let (head, tail) = b.split_at_mut(i + 1);
            let s = &mut head[i];
            for (k, bk) in (i + 1..=hi).zip(&tail[..hi - i]) {
                axpy(s, -self.l[self.idx(k, i)], bk);
            }
            let d = self.l[self.idx(i, i)];
            s.iter_mut().for_each(|x| *x /= d);
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
}
