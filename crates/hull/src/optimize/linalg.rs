//! Small dense and banded Cholesky factorizations for the weight optimisation, written on plain
//! slices so the hot loop of the objective allocates nothing.
//!
//! * Banded: `A = L L^T` of a symmetric positive definite matrix of half-bandwidth `bw`, the
//!   lower triangle stored by rows of `stride >= bw + 1` slots, row `i` holding
//!   `A_{i, i-bw} ..= A_{i,i}` at `a[i stride ..= i stride + bw]` (entry `(i, j)` at
//!   `i stride + j + bw - i`; slots past `bw` are padding, ignored, so that an assembly may
//!   write whole blocks). The first `bw` rows have slots for `j < 0`; they must hold zeros,
//!   which lets every inner product run over full, contiguous slices. Cost `n bw^2 / 2` multiply-adds (Golub and Van Loan,
//!   *Matrix Computations*, 4th ed., Alg. 4.3.5).
//! * Dense: `A = L L^T` of a small `n x n` matrix stored row-major (Alg. 4.2.1), for the
//!   Levenberg-Marquardt step.
//!
//! A pivot `d_i = a_ii - sum_k l_ik^2` not above [`PIVOT_REL`] `a_ii` marks the matrix singular
//! or too ill-conditioned: `d_i / a_ii` bounds `1 / cond(A)` from above, and beyond `1e12` the
//! solution would have lost most of its digits. This is the same threshold as the kernel's
//! banded solver (`nurbs/src/fit/banded.rs`, private there).

/// Relative pivot threshold of both factorizations.
pub(crate) const PIVOT_REL: f64 = 1e-12;

/// `sum_i a_i b_i` over the common length, with four accumulators (lets the compiler use SIMD
/// lanes; the summation order is fixed, so results are deterministic).
#[inline]
pub(crate) fn dot(a: &[f64], b: &[f64]) -> f64 {
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
/// module docs) in place into its Cholesky factor `L`. Returns `false`, leaving `a` partly
/// overwritten, when a pivot is not above [`PIVOT_REL`] times its diagonal entry (or is NaN).
pub(crate) fn band_cholesky(a: &mut [f64], n: usize, bw: usize, stride: usize) -> bool {
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
            // sum_{k = i-bw}^{j-1} l_ik l_jk: row i slots 0..o, row j slots (i - j)..bw.
            let s = row[o] - dot(&row[..o], &rj[bw - o..]);
            row[o] = s / rj[bw];
        }
        let aii = row[bw];
        let d = aii - dot(&row[..bw], &row[..bw]);
        let usable = d > PIVOT_REL * aii; // false for NaN too
        if !usable {
            return false;
        }
        row[bw] = d.sqrt();
    }
    true
}

/// Overwrite `b` with `A^{-1} b` from the factor `l` of [`band_cholesky`]; each `[f64; D]` is
/// one row of `D` right-hand sides.
pub(crate) fn band_solve<const D: usize>(l: &[f64], n: usize, bw: usize, stride: usize, b: &mut [[f64; D]]) {
    let w = bw + 1;
    debug_assert_eq!(b.len(), n);
    // Forward: L y = b, by rows.
    for i in 0..n {
        let row = &l[i * stride..i * stride + w];
        let k0 = i.saturating_sub(bw);
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
    // Backward: L^T x = y, by columns of L^T (rows of L, contiguous).
    for i in (0..n).rev() {
        let row = &l[i * stride..i * stride + w];
        let d = row[bw];
        let mut xi = b[i];
        xi.iter_mut().for_each(|t| *t /= d);
        b[i] = xi;
        let k0 = i.saturating_sub(bw);
        for (lk, bk) in row[k0 + bw - i..bw].iter().zip(&mut b[k0..i]) {
            for c in 0..D {
                bk[c] -= lk * xi[c];
            }
        }
    }
}

/// Factor the dense symmetric `n x n` matrix `a` (row-major, lower triangle read) in place into
/// `L` (lower triangle; the upper triangle is left as is). Returns `false` when a pivot is not
/// above [`PIVOT_REL`] times its diagonal entry.
pub(crate) fn dense_cholesky(a: &mut [f64], n: usize) -> bool {
    debug_assert_eq!(a.len(), n * n);
    for i in 0..n {
        let (done, rest) = a.split_at_mut(i * n);
        let row = &mut rest[..n];
        for j in 0..i {
            let rj = &done[j * n..j * n + n];
            let s = row[j] - dot(&row[..j], &rj[..j]);
            row[j] = s / rj[j];
        }
        let aii = row[i];
        let d = aii - dot(&row[..i], &row[..i]);
        let usable = d > PIVOT_REL * aii; // false for NaN too
        if !usable {
            return false;
        }
        row[i] = d.sqrt();
    }
    true
}

/// Overwrite `b` with `A^{-1} b` from the factor of [`dense_cholesky`].
pub(crate) fn dense_solve(l: &[f64], n: usize, b: &mut [f64]) {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn pseudo_random(seed: &mut u64) -> f64 {
        *seed = seed.wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        (*seed >> 11) as f64 / (1u64 << 53) as f64 - 0.5
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
            assert!(band_cholesky(&mut band, n, bw, stride), "n {n}");
            band_solve(&band, n, bw, stride, &mut b);
            assert!(dense_cholesky(&mut dense, n), "n {n}");
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
    fn singular_and_nan_matrices_are_refused() {
        // [[1, 1], [1, 1]]: the second pivot is 0.
        let mut band = vec![0.0, 1.0, 1.0, 1.0];
        assert!(!band_cholesky(&mut band, 2, 1, 2));
        let mut dense = vec![1.0, 1.0, 1.0, 1.0];
        assert!(!dense_cholesky(&mut dense, 2));
        let mut nan = vec![f64::NAN];
        assert!(!band_cholesky(&mut nan, 1, 0, 1));
        let mut nan = vec![f64::NAN];
        assert!(!dense_cholesky(&mut nan, 1));
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
