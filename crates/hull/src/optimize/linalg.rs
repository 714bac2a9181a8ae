//! The weight optimisation's factorizations are the kernel's ([`nurbs::band_cholesky`],
//! [`nurbs::dense_cholesky`], layouts in `nurbs`' linear-algebra docs); here only as the
//! `bool` the hot loop tests. And the Gram product of the normal equations
//! ([`subtract_gram_below`]).

use nalgebra::{DMatrix, DMatrixView, DMatrixViewMut, Dyn};
use rayon::prelude::*;

pub(crate) use nurbs::{band_solve, dense_solve, dot};

/// The blocks of [`subtract_gram_below`]: `GRAM_BLOCK x GRAM_BLOCK` entries of the product at a
/// time. A constant (not the thread count) so that every entry is summed the same way whatever
/// the thread count.
const GRAM_BLOCK: usize = 64;

/// `g -= W^T W` below the diagonal of `g` (row-major `d x d`; the diagonal and the entries
/// above it are left as they are), with `W` column-major `len x d` (column `v` at
/// `w[v len..(v + 1) len]`) whose column `v` is zero above row `from[v]`.
///
/// By blocks of [`GRAM_BLOCK`] columns: block `(I, J)`, `J <= I`, is one matrix product
/// `W[r.., I]^T W[r.., J]` (nalgebra's `gemm`, on matrixmultiply's cache-blocked kernels) from
/// the row `r` where a column of both blocks first has a non-zero, skipping the zero rows above
/// it; the block rows run in parallel. Each entry is the same sum whatever the thread count.
/// Against one dot product per entry from `max(from[v], from[w])` (the same sum in another
/// order): at the 713 weights of the Wigley mesh 16 ms against 42 on two threads.
pub(crate) fn subtract_gram_below(g: &mut [f64], d: usize, w: &[f64], len: usize, from: &[usize]) {
    debug_assert!(g.len() == d * d && w.len() == d * len && from.len() == d);
    if d == 0 {
        return;
    }
    let first = |b: std::ops::Range<usize>| from[b].iter().copied().min().unwrap_or(len).min(len);
    g.par_chunks_mut(GRAM_BLOCK * d).enumerate().for_each(|(bi, rows)| {
        let (i0, i1) = (bi * GRAM_BLOCK, ((bi + 1) * GRAM_BLOCK).min(d));
        let top_i = first(i0..i1);
        // W[top_i.., I]^T copied column-major (`h x (len - top_i)`), so that the left factor's
        // columns are contiguous: see `blocked_cholesky` (nalgebra's `gemm` reads a column with
        // a row stride other than 1 past its end where a side is 5 or less).
        let h = i1 - i0;
        let wt: Vec<f64> = (top_i..len).flat_map(|t| (i0..i1).map(move |v| w[v * len + t])).collect();
        for j0 in (0..=i0).step_by(GRAM_BLOCK) {
            let j1 = (j0 + GRAM_BLOCK).min(d);
            let r = top_i.max(first(j0..j1));
            if r == len {
                continue;
            }
            let k = len - r;
            // W[r.., I]^T: the copy's columns from `r`.
            let a = DMatrixView::<f64, Dyn, Dyn>::from_slice_with_strides(&wt[(r - top_i) * h..], h, k, 1, h);
            let b = DMatrixView::<f64, Dyn, Dyn>::from_slice_with_strides(&w[j0 * len + r..], k, j1 - j0, 1, len);
            let mut c = DMatrix::<f64>::zeros(h, j1 - j0);
            c.gemm(1.0, &a, &b, 0.0);
            for v in i0..i1 {
                let row = &mut rows[(v - i0) * d..(v - i0 + 1) * d];
                for (x, gx) in row[j0..j1.min(v)].iter_mut().enumerate() {
                    *gx -= c[(v - i0, x)];
                }
            }
        }
    });
}

/// [`nurbs::band_cholesky`]: `false` when a pivot marks the matrix singular.
pub(crate) fn band_cholesky(a: &mut [f64], n: usize, bw: usize, stride: usize) -> bool {
    nurbs::band_cholesky(a, n, bw, stride).is_ok()
}

/// [`nurbs::dense_cholesky`]: `false` when a pivot marks the matrix singular. Above
/// `2 CHOLESKY_BLOCK` rows by blocks ([`blocked_cholesky`]).
pub(crate) fn dense_cholesky(a: &mut [f64], n: usize) -> bool {
    if n > 2 * CHOLESKY_BLOCK {
        return blocked_cholesky(a, n);
    }
    nurbs::dense_cholesky(a, n).is_ok()
}

/// The block columns of [`blocked_cholesky`]; a constant, so that the factor is the same
/// whatever the thread count.
const CHOLESKY_BLOCK: usize = 64;

/// [`nurbs::dense_cholesky`] by blocks of [`CHOLESKY_BLOCK`] columns, right-looking (Golub and
/// Van Loan, *Matrix Computations*, 4th ed., Alg. 4.2.3 with the updates as matrix products):
/// each block column's diagonal block is factored as there, the rows below it solved against
/// it (in parallel), and the trailing lower triangle updated by the products of that panel
/// (nalgebra's `gemm`, by blocks, in parallel). The same factor up to round-off and the same
/// layout (row-major, lower triangle; the upper triangle of `a` is overwritten in the diagonal
/// blocks, and read by nobody), the same pivot test against the matrix's own diagonal. At 713
/// and 736 (the Wigley mesh, WPB) 3.5x to 4x faster than the unblocked factorization, whose
/// inner products run over whole rows.
fn blocked_cholesky(a: &mut [f64], n: usize) -> bool {
    debug_assert_eq!(a.len(), n * n);
    let diag: Vec<f64> = (0..n).map(|i| a[i * n + i]).collect();
    let mut panel = Vec::new();
    for k0 in (0..n).step_by(CHOLESKY_BLOCK) {
        let k1 = (k0 + CHOLESKY_BLOCK).min(n);
        // The diagonal block, the earlier blocks' share already taken off.
        for i in k0..k1 {
            let (done, rest) = a.split_at_mut(i * n);
            let row = &mut rest[..n];
            solve_against_block(row, &done[k0 * n..], n, k0, i);
            let d = row[i] - dot(&row[k0..i], &row[k0..i]);
            // As nurbs' pivot test, against the matrix's own diagonal entry; false for NaN.
            if !(d > nurbs::tolerance::PIVOT_REL * diag[i]) {
                return false;
            }
            row[i] = d.sqrt();
        }
        if k1 == n {
            break;
        }
        // The panel below it: each row solved against the block's factor.
        let (top, below) = a.split_at_mut(k1 * n);
        let block = &top[k0 * n..];
        below.par_chunks_mut(n).for_each(|row| solve_against_block(row, block, n, k0, k1));
        // The trailing lower triangle less the panel's products, from a copy of the panel
        // (`m x w`, column-major), by blocks of rows in parallel. Column-major, so that the
        // left factor's columns are contiguous: nalgebra 0.35's `gemm` multiplies blocks with
        // a side of 5 or less column by column, and its `axcpy` then reads a column with a row
        // stride other than 1 past its end (dimforge/nalgebra#1613). A row-major panel
        // corrupted the heap where a trailing block had 5 rows or fewer (`--method lm --fair 0`
        // on the DTMB 5415 bow of `testdata/`); the matrixmultiply kernels of the larger blocks
        // give the same bits either way.
        let (m, w) = (n - k1, k1 - k0);
        panel.clear();
        panel.extend((k0..k1).flat_map(|c| below.chunks(n).map(move |row| row[c])));
        below.par_chunks_mut(CHOLESKY_BLOCK * n).enumerate().for_each(|(bi, rows)| {
            let (i0, i1) = (bi * CHOLESKY_BLOCK, ((bi + 1) * CHOLESKY_BLOCK).min(m));
            let pi = DMatrixView::<f64, Dyn, Dyn>::from_slice_with_strides(&panel[i0..], i1 - i0, w, 1, m);
            for j0 in (0..=i0).step_by(CHOLESKY_BLOCK) {
                let j1 = (j0 + CHOLESKY_BLOCK).min(m);
                let pj = DMatrixView::<f64, Dyn, Dyn>::from_slice_with_strides(&panel[j0..], w, j1 - j0, m, 1);
                let mut c = DMatrixViewMut::<f64, Dyn, Dyn>::from_slice_with_strides_mut(
                    &mut rows[k1 + j0..],
                    i1 - i0,
                    j1 - j0,
                    n,
                    1,
                );
                c.gemm(-1.0, &pi, &pj, 1.0);
            }
        });
    }
    true
}

/// Row `row`'s entries `k0..end` of [`blocked_cholesky`]'s factor, solved against the factor
/// rows `k0..end` of the block column starting at `k0` (`block`, row-major with `n` columns,
/// its first row the factor's row `k0`), the earlier blocks' share already taken off.
fn solve_against_block(row: &mut [f64], block: &[f64], n: usize, k0: usize, end: usize) {
    for j in k0..end {
        let rj = &block[(j - k0) * n..(j - k0 + 1) * n];
        row[j] = (row[j] - dot(&row[k0..j], &rj[k0..j])) / rj[j];
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A pseudo-random number in `[-1, 1)` (a fixed sequence: the tests need no seed).
    fn noise(i: usize) -> f64 {
        let x = (i as u64).wrapping_mul(6364136223846793005).wrapping_add(1442695040888963407);
        ((x >> 11) as f64 / (1u64 << 53) as f64) * 2.0 - 1.0
    }

    /// `W` (`len x d`, column-major) with column `v` zero above row `from[v]`.
    fn tall(len: usize, d: usize) -> (Vec<f64>, Vec<usize>) {
        let from: Vec<usize> = (0..d).map(|v| (v * len / (2 * d) + v % 7).min(len)).collect();
        let w = (0..d * len).map(|i| if i % len >= from[i / len] { noise(i) } else { 0.0 }).collect();
        (w, from)
    }

    /// `B^T B + n I` of a random `B`: symmetric positive definite, condition number moderate.
    fn spd(n: usize) -> Vec<f64> {
        let b: Vec<f64> = (0..n * n).map(noise).collect();
        let mut a = vec![0.0; n * n];
        for i in 0..n {
            for j in 0..n {
                a[i * n + j] =
                    (0..n).map(|k| b[k * n + i] * b[k * n + j]).sum::<f64>() + if i == j { n as f64 } else { 0.0 };
            }
        }
        a
    }

    fn in_pool<T: Send>(threads: usize, f: impl FnOnce() -> T + Send) -> T {
        rayon::ThreadPoolBuilder::new().num_threads(threads).build().expect("a pool").install(f)
    }

    /// Against one dot product per entry (what `normal_equations` did): the same sums in
    /// another order, so equal to round-off (entries are sums of up to 500 products of numbers
    /// in [-1, 1]: 1e-12 absolute is a few hundred ulps of the largest); on and above the
    /// diagonal nothing is touched; and the same bits on 1 and 3 threads.
    #[test]
    fn the_blocked_gram_product_is_the_dot_products() {
        let (len, d) = (500, 203);
        let (w, from) = tall(len, d);
        let g0: Vec<f64> = (0..d * d).map(|i| noise(i + 7)).collect();
        let mut g = g0.clone();
        subtract_gram_below(&mut g, d, &w, len, &from);
        for v in 0..d {
            for u in v..d {
                assert_eq!(g[v * d + u], g0[v * d + u], "({v}, {u}) on or above the diagonal");
            }
        }
        assert_gram_is_the_dot_products(&g0, &g, d, &w, len, &from, 1e-12);
        let on = |threads| {
            in_pool(threads, || {
                let mut g = g0.clone();
                subtract_gram_below(&mut g, d, &w, len, &from);
                g
            })
        };
        assert!(on(1) == g && on(3) == g, "the same bits whatever the thread count");
    }

    /// The blocked factor is the unblocked one to round-off (relative 1e-12 of the largest
    /// entry: a well-conditioned matrix of order 300), solves as well, is the same bits on 1
    /// and 3 threads, and refuses a singular matrix as the unblocked one does.
    #[test]
    fn the_blocked_cholesky_is_the_unblocked_one() {
        let n = 300;
        let a = spd(n);
        let blocked = blocked_factor_of(&a, n);
        // A x = b recovered: b = A 1.
        let mut x: Vec<f64> = (0..n).map(|i| a[i * n..(i + 1) * n].iter().sum()).collect();
        dense_solve(&blocked, n, &mut x);
        assert!(x.iter().all(|xi| (xi - 1.0).abs() < 1e-10), "{:?}", &x[..4]);
        let on = |threads| {
            in_pool(threads, || {
                let mut f = a.clone();
                assert!(blocked_cholesky(&mut f, n));
                f
            })
        };
        let one = on(1);
        let lower = |f: &[f64]| {
            (0..n).flat_map(|i| (0..=i).map(move |j| (i, j))).map(|(i, j)| f[i * n + j]).collect::<Vec<f64>>()
        };
        assert!(lower(&one) == lower(&blocked) && lower(&on(3)) == lower(&blocked));
        // Row 250 (in the fourth block) made a copy of row 10: singular; both refuse it.
        let mut s = a.clone();
        for j in 0..n {
            s[250 * n + j] = a[10 * n + j];
            s[j * n + 250] = a[j * n + 10];
        }
        s[250 * n + 250] = a[10 * n + 10];
        assert!(!blocked_cholesky(&mut s.clone(), n));
        assert!(nurbs::dense_cholesky(&mut s, n).is_err());
    }

    /// Blocks with a side of 5 or less (a trailing block of rows, a short run of non-zero rows):
    /// nalgebra 0.35's `gemm` multiplies those column by column and read a strided left factor
    /// past its end, which corrupted the heap (`--method lm --fair 0` on the DTMB 5415 bow and the
    /// cargo ship of `testdata/` aborted). A debug build checks the reads, so these orders failed
    /// here before the left factors were laid out column-major. The same sums as above.
    #[test]
    fn blocks_with_a_short_side_are_multiplied_within_their_data() {
        // d = 133: row blocks of 64, 64 and 5; columns 130 to 132 non-zero in their last 3 rows.
        let (len, d) = (40, 133);
        let from: Vec<usize> = (0..d).map(|v| if v >= 130 { len - 3 } else { v % 5 }).collect();
        let w: Vec<f64> = (0..d * len).map(|i| if i % len >= from[i / len] { noise(i) } else { 0.0 }).collect();
        let g0: Vec<f64> = (0..d * d).map(|i| noise(i + 3)).collect();
        let mut g = g0.clone();
        subtract_gram_below(&mut g, d, &w, len, &from);
        // Sums of up to 40 products of numbers in [-1, 1]: 1e-13 is a few hundred ulps.
        assert_gram_is_the_dot_products(&g0, &g, d, &w, len, &from, 1e-13);
        // Orders whose trailing blocks of the factor's update have 3, 5 and 1 rows (and columns).
        for n in [131, 133, 193] {
            blocked_factor_of(&spd(n), n);
        }
    }

    /// The blocked factor of `a` (order `n`), checked against the unblocked one: equal to
    /// round-off, 1e-12 of the largest entry (the well-conditioned matrices of [`spd`]).
    fn blocked_factor_of(a: &[f64], n: usize) -> Vec<f64> {
        let mut blocked = a.to_vec();
        assert!(blocked_cholesky(&mut blocked, n), "order {n}");
        let mut plain = a.to_vec();
        nurbs::dense_cholesky(&mut plain, n).expect("positive definite");
        let scale = plain.iter().fold(0.0f64, |m, x| m.max(x.abs()));
        for i in 0..n {
            for j in 0..=i {
                let (b, p) = (blocked[i * n + j], plain[i * n + j]);
                assert!((b - p).abs() <= 1e-12 * scale, "order {n}: L({i}, {j}): {b} against {p}");
            }
        }
        blocked
    }

    /// `g` (from `g0` by [`subtract_gram_below`] with `w`, `len`, `from`) below the diagonal
    /// against one dot product per entry from `max(from[v], from[u])`, within `tol`.
    fn assert_gram_is_the_dot_products(
        g0: &[f64],
        g: &[f64],
        d: usize,
        w: &[f64],
        len: usize,
        from: &[usize],
        tol: f64,
    ) {
        for v in 0..d {
            for u in 0..v {
                let r = from[v].max(from[u]);
                let want = g0[v * d + u] - dot(&w[v * len + r..(v + 1) * len], &w[u * len + r..(u + 1) * len]);
                assert!((g[v * d + u] - want).abs() < tol, "({v}, {u}): {} against {want}", g[v * d + u]);
            }
        }
    }
}
