//! B-spline basis functions and their derivatives (The NURBS Book A2.2 and A2.3).
//!
//! `N_{i,0}(u) = 1 if u_i <= u < u_{i+1}`, and
//! `N_{i,p}(u) = (u - u_i)/(u_{i+p} - u_i) N_{i,p-1}(u) + (u_{i+p+1} - u)/(u_{i+p+1} - u_{i+1}) N_{i+1,p-1}(u)`.

use crate::knots::MAX_DEGREE;

/// Stack scratch for one row of basis values.
pub type BasisRow = [f64; MAX_DEGREE + 1];

/// The `p + 1` non-vanishing basis functions `N_{span-p,p}(u) ..= N_{span,p}(u)` written to
/// `out[..=p]` (A2.2). `knots` is the full knot vector, `span` from `find_span`.
///
/// ```
/// use nurbs::basis::basis_funs;
/// use nurbs::{KnotVector, MAX_DEGREE};
/// let k = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.3, 0.6, 1.0, 1.0, 1.0, 1.0])?;
/// let mut n = [0.0; MAX_DEGREE + 1];
/// for i in 0..=20 {
///     let t = i as f64 / 20.0;
///     basis_funs(k.as_slice(), k.find_span(t), t, 3, &mut n);
///     // Partition of unity and non-negativity (The NURBS Book P2.4, P2.3).
///     assert!((n[..4].iter().sum::<f64>() - 1.0).abs() < 1e-15);
///     assert!(n[..4].iter().all(|&b| b >= 0.0));
/// }
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
#[inline]
pub fn basis_funs(knots: &[f64], span: usize, u: f64, p: usize, out: &mut BasisRow) {
    let mut left = [0.0; MAX_DEGREE + 1];
    let mut right = [0.0; MAX_DEGREE + 1];
    out[0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            let temp = out[r] / (right[r + 1] + left[j - r]);
            out[r] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        out[j] = saved;
    }
}

/// The non-vanishing basis functions and their derivatives up to order `n` (A2.3):
/// `ders[k][j]` is the k-th derivative of `N_{span-p+j,p}` at `u`. Derivatives above `p` are 0.
pub fn ders_basis_funs(knots: &[f64], span: usize, u: f64, p: usize, n: usize, ders: &mut [BasisRow]) {
    // Scratch sized to the degree: zeroing a (MAX_DEGREE + 1)^2 table on every call cost more
    // than the arithmetic of a cubic.
    match p {
        1 => ders_basis_funs_sized::<2>(knots, span, u, p, n, ders),
        2 => ders_basis_funs_sized::<3>(knots, span, u, p, n, ders),
        3 => ders_basis_funs_sized::<4>(knots, span, u, p, n, ders),
        4 => ders_basis_funs_sized::<5>(knots, span, u, p, n, ders),
        5 => ders_basis_funs_sized::<6>(knots, span, u, p, n, ders),
        _ => ders_basis_funs_sized::<{ MAX_DEGREE + 1 }>(knots, span, u, p, n, ders),
    }
}

/// A2.3 with scratch arrays of `N >= p + 1` entries.
fn ders_basis_funs_sized<const N: usize>(
    knots: &[f64],
    span: usize,
    u: f64,
    p: usize,
    n: usize,
    ders: &mut [BasisRow],
) {
    debug_assert!(ders.len() > n && p < N);
    let mut ndu = [[0.0; N]; N];
    let mut left = [0.0; N];
    let mut right = [0.0; N];
    ndu[0][0] = 1.0;
    for j in 1..=p {
        left[j] = u - knots[span + 1 - j];
        right[j] = knots[span + j] - u;
        let mut saved = 0.0;
        for r in 0..j {
            ndu[j][r] = right[r + 1] + left[j - r];
            let temp = ndu[r][j - 1] / ndu[j][r];
            ndu[r][j] = saved + right[r + 1] * temp;
            saved = left[j - r] * temp;
        }
        ndu[j][j] = saved;
    }
    for j in 0..=p {
        ders[0][j] = ndu[j][p];
    }
    for row in ders.iter_mut().take(n + 1).skip(1) {
        row[..=p].fill(0.0);
    }
    let nd = n.min(p);
    let mut a = [[0.0; N]; 2];
    for r in 0..=p {
        let (mut s1, mut s2) = (0usize, 1usize);
        a[0][0] = 1.0;
        for k in 1..=nd {
            let mut d = 0.0;
            let rk = r as isize - k as isize;
            let pk = p - k;
            if r >= k {
                a[s2][0] = a[s1][0] / ndu[pk + 1][r - k];
                d = a[s2][0] * ndu[r - k][pk];
            }
            let j1 = if rk >= -1 { 1 } else { (-rk) as usize };
            let j2 = if r as isize - 1 <= pk as isize { k - 1 } else { p - r };
            for j in j1..=j2 {
                let idx = (rk + j as isize) as usize;
                a[s2][j] = (a[s1][j] - a[s1][j - 1]) / ndu[pk + 1][idx];
                d += a[s2][j] * ndu[idx][pk];
            }
            if r <= pk {
                a[s2][k] = -a[s1][k - 1] / ndu[pk + 1][r];
                d += a[s2][k] * ndu[r][pk];
            }
            ders[k][r] = d;
            std::mem::swap(&mut s1, &mut s2);
        }
    }
    let mut fac = p as f64;
    for k in 1..=nd {
        for j in 0..=p {
            ders[k][j] *= fac;
        }
        fac *= (p - k) as f64;
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::KnotVector;
    use proptest::prelude::*;

    fn knots_strategy() -> impl Strategy<Value = (usize, Vec<f64>)> {
        (1usize..=6, prop::collection::vec(0.01f64..1.0, 0..8)).prop_map(|(p, gaps)| {
            let mut k = vec![0.0; p + 1];
            let mut acc = 0.0;
            for g in &gaps {
                acc += g;
                k.push(acc);
            }
            let end = acc + 0.5;
            k.extend(std::iter::repeat_n(end, p + 1));
            (p, k)
        })
    }

    #[test]
    fn book_example_2_4() {
        // The NURBS Book Ex. 2.4: U = {0,0,0,1,2,3,4,4,5,5,5}, p = 2, u = 5/2:
        // N_{2,2} = 1/8, N_{3,2} = 6/8, N_{4,2} = 1/8.
        let kv = KnotVector::try_new(2, vec![0., 0., 0., 1., 2., 3., 4., 4., 5., 5., 5.]).expect("valid");
        let span = kv.find_span(2.5);
        let mut n = [0.0; MAX_DEGREE + 1];
        basis_funs(kv.as_slice(), span, 2.5, 2, &mut n);
        assert_eq!(&n[..3], &[0.125, 0.75, 0.125]);
        let mut d = [[0.0; MAX_DEGREE + 1]; 3];
        ders_basis_funs(kv.as_slice(), span, 2.5, 2, 2, &mut d);
        // First derivatives at 5/2: -1/2, 0, 1/2; second: 1, -2, 1.
        assert_eq!(&d[1][..3], &[-0.5, 0.0, 0.5]);
        assert_eq!(&d[2][..3], &[1.0, -2.0, 1.0]);
    }

    proptest! {
        #[test]
        fn partition_of_unity_and_nonnegative((p, k) in knots_strategy(), t in 0.0f64..=1.0) {
            let kv = KnotVector::try_new(p, k).expect("valid by construction");
            let (a, b) = kv.domain();
            let u = a + t * (b - a);
            let span = kv.find_span(u);
            let mut n = [0.0; MAX_DEGREE + 1];
            basis_funs(kv.as_slice(), span, u, p, &mut n);
            let s: f64 = n[..=p].iter().sum();
            prop_assert!((s - 1.0).abs() < crate::tolerance::EVAL_REL * 10.0, "sum {}", s);
            prop_assert!(n[..=p].iter().all(|&x| x >= -1e-15));
            // Derivatives of a partition of unity sum to zero; ders[0] equals basis_funs.
            let mut d = [[0.0; MAX_DEGREE + 1]; 3];
            ders_basis_funs(kv.as_slice(), span, u, p, 2, &mut d);
            for j in 0..=p { prop_assert!((d[0][j] - n[j]).abs() < 1e-14); }
            let scale = (b - a).recip().powi(2) * 100.0;
            prop_assert!(d[1][..=p].iter().sum::<f64>().abs() < 1e-9 * scale);
            prop_assert!(d[2][..=p].iter().sum::<f64>().abs() < 1e-8 * scale * scale);
        }

        #[test]
        fn derivative_matches_central_difference((p, k) in knots_strategy(), t in 0.05f64..0.95) {
            let kv = KnotVector::try_new(p, k).expect("valid by construction");
            let (a, b) = kv.domain();
            let u = a + t * (b - a);
            let span = kv.find_span(u);
            let ks = kv.as_slice();
            // Stay away from knots so the finite difference stays within one polynomial piece.
            let h = 1e-6 * (b - a);
            prop_assume!(ks[span] < u - 2.0 * h && u + 2.0 * h < ks[span + 1]);
            let mut d = [[0.0; MAX_DEGREE + 1]; 3];
            ders_basis_funs(ks, span, u, p, 2, &mut d);
            let (mut np, mut nm) = ([0.0; MAX_DEGREE + 1], [0.0; MAX_DEGREE + 1]);
            basis_funs(ks, span, u + h, p, &mut np);
            basis_funs(ks, span, u - h, p, &mut nm);
            for j in 0..=p {
                let fd = (np[j] - nm[j]) / (2.0 * h);
                // Central difference error O(h^2 N'''), round-off O(eps / h).
                let tol = 1e-6 * (1.0 + d[1][j].abs()) / (b - a);
                prop_assert!((fd - d[1][j]).abs() < tol, "j {} fd {} exact {}", j, fd, d[1][j]);
            }
        }
    }
}
