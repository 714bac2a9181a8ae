//! Degree elevation of curves and surfaces (The NURBS Book 5.5).
//!
//! A curve of degree `p` is raised to degree `p + t` without changing its shape; every distinct
//! knot, the ends included, gains multiplicity `t`, so a curve with `s` distinct interior knots
//! gets `n + 1 + t (s + 1)` control points. Everything acts on the homogeneous control points,
//! so rational curves are elevated exactly. Each Bezier segment `b_0 ..= b_p` is elevated with
//! (eq. 5.36)
//! `b'_i = sum_{j = max(0, i-t)}^{min(p, i)} C(p, j) C(t, i-j) / C(p+t, i) b_j`, `i = 0 ..= p+t`.
//!
//! A5.9 reassembles the elevated segments by knot removal, which is unstable next to short
//! spans; here the control points are read off as blossoms instead (see `elevate_points`).
//! A5.9 stays in the tests as a cross-check. A surface is elevated in one direction by
//! elevating every row of its net in that direction.

use crate::curve::{binomial, Homogeneous};
use crate::knots::MAX_DEGREE;
use crate::refine::{lerp, refine_points, Direction};
use crate::{KnotVector, NurbsCurve, NurbsError, NurbsSurface};

/// The Bezier degree-elevation coefficients of eq. 5.36,
/// `e[i][j] = C(p, j) C(t, i-j) / C(p+t, i)` for `max(0, i-t) <= j <= min(p, i)`.
fn bezier_elevation_coefficients(p: usize, t: usize) -> [[f64; MAX_DEGREE + 1]; MAX_DEGREE + 1] {
    let ph = p + t;
    let mut e = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
    for (i, row) in e.iter_mut().enumerate().take(ph + 1) {
        let inv = 1.0 / binomial(ph, i);
        for (j, c) in row.iter_mut().enumerate().take(p.min(i) + 1).skip(i.saturating_sub(t)) {
            *c = inv * binomial(p, j) * binomial(t, i - j);
        }
    }
    e
}

/// Raise the degree of the homogeneous control polygon `pw` over the clamped knots `kv` by
/// `t >= 1` (with `p + t <= MAX_DEGREE`). Returns the new knots and control points.
///
/// The steps of A5.9 without its knot removal, which divides by knot differences and loses
/// accuracy like `1 / h^2` next to a short span `h` (2e-6 relative error measured for a quintic
/// raised by 3 with `h = 1e-6`):
/// 1. split the curve into Bezier segments by refining every interior knot to multiplicity `p`
///    (A5.6 done with A5.4, convex combinations only);
/// 2. elevate each segment with eq. 5.36 (convex combinations);
/// 3. read off each new control point as the blossom of the elevated curve at the new knots,
///    `Q_i = f(ubar_{i+1}, ..., ubar_{i+p+t})` (the dual functional property of B-splines,
///    The NURBS Book 5.6 / Ramshaw's polar forms), evaluated by de Casteljau on the longest
///    segment in the support `[ubar_i, ubar_{i+p+t+1}]` of `N_{i,p+t}`. The blossom arguments
///    then lie within a few segment lengths of it, so the extrapolation factors stay bounded
///    whatever the shortest span.
fn elevate_points(kv: &KnotVector, pw: &[Homogeneous], t: usize) -> (Vec<f64>, Vec<Homogeneous>) {
    let p = kv.degree();
    let ph = p + t;
    let breaks = kv.interior_breaks();
    let (start, end) = kv.domain();

    // 1. Bezier segments: segment k spans [ends[k], ends[k + 1]] with points bez[k p ..= k p + p].
    let x: Vec<f64> = breaks.iter().flat_map(|&(value, mult)| std::iter::repeat_n(value, p - mult)).collect();
    let bez = if x.is_empty() { pw.to_vec() } else { refine_points(kv, pw, &x) };
    let mut ends = Vec::with_capacity(breaks.len() + 2);
    ends.push(start);
    ends.extend(breaks.iter().map(|b| b.0));
    ends.push(end);
    let segments = ends.len() - 1;
    debug_assert_eq!(bez.len(), segments * p + 1);

    // 2. Elevate each segment.
    let coef = bezier_elevation_coefficients(p, t);
    let elevated: Vec<[Homogeneous; MAX_DEGREE + 1]> = (0..segments)
        .map(|k| {
            let seg = &bez[k * p..=k * p + p];
            let mut out = [[0.0; 4]; MAX_DEGREE + 1];
            for (i, o) in out.iter_mut().enumerate().take(ph + 1) {
                for j in i.saturating_sub(t)..=p.min(i) {
                    for c in 0..4 {
                        o[c] += coef[i][j] * seg[j][c];
                    }
                }
            }
            out
        })
        .collect();

    // 3. The new knots, and the control points as blossoms.
    let mut uh = vec![start; ph + 1];
    for &(value, mult) in &breaks {
        uh.extend(std::iter::repeat_n(value, mult + t));
    }
    uh.extend(std::iter::repeat_n(end, ph + 1));
    let count = uh.len() - ph - 1;
    let qw = (0..count)
        .map(|i| {
            // The longest non-empty span [uh[j], uh[j + 1]], i <= j <= i + ph, and its segment.
            let j = (i..=i + ph)
                .max_by(|&a, &b| (uh[a + 1] - uh[a]).total_cmp(&(uh[b + 1] - uh[b])))
                .expect("the range is not empty");
            let k = ends.partition_point(|&e| e <= uh[j]) - 1;
            let (a, len) = (ends[k], ends[k + 1] - ends[k]);
            let mut b = elevated[k];
            for r in 1..=ph {
                let s = (uh[i + r] - a) / len;
                for l in 0..=ph - r {
                    b[l] = lerp(s, &b[l + 1], &b[l]);
                }
            }
            b[0]
        })
        .collect();
    (uh, qw)
}

impl NurbsCurve {
    /// Raise the degree by `t` (The NURBS Book 5.5: Bezier decomposition, eq. 5.36 on each
    /// segment, recomposition by blossoming; see the module docs). The curve is unchanged;
    /// every distinct knot, the ends included, gains multiplicity `t`. `t = 0` returns a copy.
    /// Accuracy does not depend on the knot spacing (round-off about 1e-15 relative to the
    /// control polygon size in the tests, also next to spans of length 1e-6).
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`] if the new degree would exceed [`MAX_DEGREE`].
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsCurve, Vec3};
    /// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 1.0)];
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
    /// let c = NurbsCurve::try_new(k, &pts, None)?;
    /// // A quadratic Bezier raised to degree 4 (A5.9): five control points, the same curve.
    /// let e = c.elevate_degree(2)?;
    /// assert_eq!((e.degree(), e.num_control_points()), (4, 5));
    /// for i in 0..=10 {
    ///     let t = i as f64 / 10.0;
    ///     assert!(e.point(t).distance(c.point(t)) < 1e-14);
    /// }
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn elevate_degree(&self, t: usize) -> Result<NurbsCurve, NurbsError> {
        let p = self.degree();
        let ph = p.saturating_add(t);
        if ph > MAX_DEGREE {
            return Err(NurbsError::BadDegree { degree: ph, max: MAX_DEGREE });
        }
        if t == 0 {
            return Ok(self.clone());
        }
        let (uh, qw) = elevate_points(self.knots(), self.homogeneous(), t);
        Ok(NurbsCurve::from_parts_unchecked(KnotVector::new_unchecked(ph, uh), qw))
    }
}

impl NurbsSurface {
    /// Raise the degree in u by `t`: [`NurbsCurve::elevate_degree`] on every row of the net along u.
    ///
    /// # Errors
    /// As [`NurbsCurve::elevate_degree`].
    pub fn elevate_degree_u(&self, t: usize) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::U, |c| c.elevate_degree(t))
    }

    /// Raise the degree in v by `t`: [`NurbsCurve::elevate_degree`] on every row of the net along v.
    ///
    /// # Errors
    /// As [`NurbsCurve::elevate_degree`].
    pub fn elevate_degree_v(&self, t: usize) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::V, |c| c.elevate_degree(t))
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::fixtures::{arb_curve, arb_surface, circle};
    use crate::refine::tests::{assert_same_curve, assert_same_surface};
    use crate::Vec3;
    use proptest::prelude::*;

    /// The NURBS Book A5.9 (DegreeElevateCurve), transcribed, as an independent reference:
    /// raise the degree of `pw` over `kv` by `t >= 1`; returns the new knots and control points.
    // Transcribed index for index from the book, hence the range loops.
    #[allow(clippy::needless_range_loop)]
    fn a5_9_reference(kv: &KnotVector, pw: &[Homogeneous], t: usize) -> (Vec<f64>, Vec<Homogeneous>) {
        let p = kv.degree();
        let u = kv.as_slice();
        let n = pw.len() - 1;
        let m = n + p + 1;
        let ph = p + t;
        let ph2 = ph / 2;
        // Bezier degree-elevation coefficients bezalfs[i][j] (eq. 5.36), symmetric in (i, j).
        let mut bezalfs = [[0.0; MAX_DEGREE + 1]; MAX_DEGREE + 1];
        bezalfs[0][0] = 1.0;
        bezalfs[ph][p] = 1.0;
        for i in 1..=ph2 {
            let inv = 1.0 / binomial(ph, i);
            for j in i.saturating_sub(t)..=p.min(i) {
                bezalfs[i][j] = inv * binomial(p, j) * binomial(t, i - j);
            }
        }
        for i in ph2 + 1..ph {
            for j in i.saturating_sub(t)..=p.min(i) {
                bezalfs[i][j] = bezalfs[ph - i][p - j];
            }
        }

        const ZERO: Homogeneous = [0.0; 4];
        let mut bpts = [ZERO; MAX_DEGREE + 1];
        let mut next_bpts = [ZERO; MAX_DEGREE + 1];
        let mut ebpts = [ZERO; MAX_DEGREE + 1];
        let mut alfs = [0.0; MAX_DEGREE + 1];
        // The book's `kind` and `cind` are the lengths of uh and qw.
        let distinct = 1 + u.windows(2).filter(|w| w[0] != w[1]).count();
        let mut uh: Vec<f64> = Vec::with_capacity(u.len() + t * distinct);
        let mut qw: Vec<Homogeneous> = Vec::with_capacity(pw.len() + t * distinct);
        uh.extend(std::iter::repeat_n(u[0], ph + 1));
        qw.push(pw[0]);
        bpts[..=p].copy_from_slice(&pw[..=p]);
        let (mut a, mut b) = (p, p + 1);
        let mut ua = u[0];
        let mut r: isize = -1;
        while b < m {
            let i0 = b;
            while b < m && u[b] == u[b + 1] {
                b += 1;
            }
            let mul = b - i0 + 1;
            let ub = u[b];
            let oldr = r;
            r = p as isize - mul as isize;
            // Insert u_b r times to get the Bezier segment.
            let lbz = if oldr > 0 { (oldr as usize + 2) / 2 } else { 1 };
            let rbz = if r > 0 { ph - (r as usize).div_ceil(2) } else { ph };
            if r > 0 {
                let r = r as usize;
                let numer = ub - ua;
                for k in (mul + 1..=p).rev() {
                    alfs[k - mul - 1] = numer / (u[a + k] - ua);
                }
                for j in 1..=r {
                    let s = mul + j;
                    for k in (s..=p).rev() {
                        bpts[k] = lerp(alfs[k - s], &bpts[k], &bpts[k - 1]);
                    }
                    next_bpts[r - j] = bpts[p];
                }
            }
            // Degree-elevate the Bezier segment.
            for (i, e) in ebpts.iter_mut().enumerate().take(ph + 1).skip(lbz) {
                let mut h = ZERO;
                for j in i.saturating_sub(t)..=p.min(i) {
                    for c in 0..4 {
                        h[c] += bezalfs[i][j] * bpts[j][c];
                    }
                }
                *e = h;
            }
            // Remove the knot u_a oldr times.
            if oldr > 1 {
                let kind = uh.len() as isize;
                let cind = qw.len() as isize;
                let (mut first, mut last) = (kind - 2, kind);
                let den = ub - ua;
                let bet = (ub - uh[kind as usize - 1]) / den;
                for tr in 1..oldr {
                    let (mut i, mut j) = (first, last);
                    let mut kj = j - kind + 1;
                    while j - i > tr {
                        if i < cind {
                            let iu = i as usize;
                            let alf = (ub - uh[iu]) / (ua - uh[iu]);
                            qw[iu] = lerp(alf, &qw[iu], &qw[iu - 1]);
                        }
                        if j >= lbz as isize {
                            let k = kj as usize;
                            let g = if j - tr <= kind - ph as isize + oldr {
                                (ub - uh[(j - tr) as usize]) / den
                            } else {
                                bet
                            };
                            ebpts[k] = lerp(g, &ebpts[k], &ebpts[k + 1]);
                        }
                        i += 1;
                        j -= 1;
                        kj -= 1;
                    }
                    first -= 1;
                    last += 1;
                }
            }
            if a != p {
                // Load the knot u_a (oldr >= 0 here: this is not the first segment).
                uh.extend(std::iter::repeat_n(ua, (ph as isize - oldr) as usize));
            }
            qw.extend_from_slice(&ebpts[lbz..=rbz]);
            if b < m {
                // Set up the next segment.
                let r = r.max(0) as usize;
                bpts[..r].copy_from_slice(&next_bpts[..r]);
                bpts[r..=p].copy_from_slice(&pw[b - p + r..=b]);
                a = b;
                b += 1;
                ua = ub;
            } else {
                uh.extend(std::iter::repeat_n(ub, ph + 1));
            }
        }
        debug_assert_eq!(qw.len() + ph + 1, uh.len());
        (uh, qw)
    }

    /// Number of distinct interior knots.
    fn breaks(kv: &KnotVector) -> usize {
        kv.interior_breaks().len()
    }

    #[test]
    fn line_elevated_to_cubic_has_evenly_spaced_points() {
        // A degree-1 Bezier segment from A to B elevated by 2: P_i = A + i/3 (B - A).
        let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
        let (a, b) = (Vec3::new(1.0, -2.0, 0.5), Vec3::new(4.0, 2.0, -1.0));
        let c = NurbsCurve::try_new(kv, &[a, b], None).expect("valid");
        let e = c.elevate_degree(2).expect("degree 3 is fine");
        assert_eq!(e.degree(), 3);
        assert_eq!(e.knots().as_slice(), &[0., 0., 0., 0., 1., 1., 1., 1.]);
        for (i, q) in e.control_points().iter().enumerate() {
            // Two roundings in the coefficient and one in the sum.
            crate::assert_near!(*q, a + (b - a) * (i as f64 / 3.0), 1e-14);
        }
    }

    #[test]
    fn rational_circle_unchanged_by_elevation() {
        let r = 1.7;
        let c = circle(r);
        for t in 1..=3 {
            let e = c.elevate_degree(t).expect("within MAX_DEGREE");
            assert_eq!(e.degree(), 2 + t);
            // Knots 0.25, 0.5, 0.75 (double) and the ends all gain t.
            assert_eq!(e.knots().multiplicity(0.5), 2 + t);
            assert_eq!(e.knots().multiplicity(0.0), 3 + t);
            assert_eq!(e.num_control_points(), c.num_control_points() + t * 4);
            assert_same_curve(&c, &e);
            for i in 0..=400 {
                // On the circle: the same round-off budget as the circle test in curve.rs.
                let u = f64::from(i) / 400.0;
                crate::assert_near!(e.point(u).norm(), r, 1e-12 * r);
            }
        }
    }

    #[test]
    fn elevation_respects_max_degree() {
        let c = circle(1.0);
        assert!(matches!(c.elevate_degree(MAX_DEGREE), Err(NurbsError::BadDegree { .. })));
        assert!(matches!(c.elevate_degree(usize::MAX), Err(NurbsError::BadDegree { .. })));
        assert_eq!(c.elevate_degree(MAX_DEGREE - 2).expect("exactly MAX_DEGREE").degree(), MAX_DEGREE);
        assert_eq!(c.elevate_degree(0).expect("no-op"), c);
    }

    #[test]
    fn agrees_with_a5_9_on_well_spaced_knots() {
        // Knots at least 0.1 apart, multiplicities 1 to p, degrees 1 to 5, t = 1 to 3: A5.9's
        // knot removal is well conditioned here, and both algorithms must give the same net.
        for p in 1..=5usize {
            for t in 1..=3usize {
                let mut k = vec![0.0; p + 1];
                for (j, v) in [0.2, 0.35, 0.5, 0.8].into_iter().enumerate() {
                    k.extend(std::iter::repeat_n(v, 1 + (j + p) % p));
                }
                k.extend(vec![1.0; p + 1]);
                let kv = KnotVector::try_new(p, k).expect("valid");
                let cw: Vec<Homogeneous> = (0..kv.num_basis())
                    .map(|i| {
                        let (x, w) = (i as f64, 1.0 + 0.6 * (1.3 * i as f64).sin());
                        [w * (2.0 * x).sin(), w * x, w * (0.7 * x).cos(), w]
                    })
                    .collect();
                let c = NurbsCurve::try_from_homogeneous(kv.clone(), cw.clone()).expect("valid");
                let e = c.elevate_degree(t).expect("small degree");
                let (uh, qw) = a5_9_reference(&kv, &cw, t);
                assert_eq!(e.knots().as_slice(), uh.as_slice());
                assert_eq!(e.num_control_points(), qw.len());
                for (a, b) in e.homogeneous().iter().zip(&qw) {
                    for c4 in 0..4 {
                        // Both are O(p^2) convex or bounded affine combinations of points of
                        // size <= 12: 1e-12 absolute is a few hundred ulps.
                        crate::assert_near!(a[c4], b[c4], 1e-12, "p {p} t {t}");
                    }
                }
            }
        }
    }

    #[test]
    fn elevation_is_accurate_next_to_short_spans() {
        // A quintic with knots 0.4 and 0.4 + h, raised by 3. A5.9 loses accuracy like 1/h^2
        // here (2e-6 relative at h = 1e-6, 4e-8 at h = 1e-5); the blossom recomposition must
        // stay at round-off level, 1e-13 relative (measured: below 4e-15).
        let p = 5;
        for h in [1e-2, 1e-4, 1e-6, 1e-9] {
            let mut k = vec![0.0; p + 1];
            k.extend([0.2, 0.4, 0.4 + h, 0.7]);
            k.extend(vec![1.0; p + 1]);
            let kv = KnotVector::try_new(p, k).expect("valid");
            let n = kv.num_basis();
            let pts: Vec<Vec3> = (0..n)
                .map(|i| Vec3::new(5.0 * (1.7 * i as f64).sin(), 3.0 * (0.3 * i as f64).cos(), i as f64))
                .collect();
            let w: Vec<f64> = (0..n).map(|i| 1.0 + 0.7 * (2.1 * i as f64).sin()).collect();
            let c = NurbsCurve::try_new(kv, &pts, Some(&w)).expect("valid");
            let e = c.elevate_degree(3).expect("degree 8");
            let tol = 1e-13 * pts.iter().map(|q| q.norm()).fold(1.0, f64::max);
            for i in 0..=2000 {
                let u = f64::from(i) / 2000.0;
                crate::assert_near!(e.point(u), c.point(u), tol, "h {h} u {u}");
            }
            for u in [0.4, 0.4 + 0.5 * h, 0.4 + h] {
                crate::assert_near!(e.point(u), c.point(u), tol, "h {h} u {u}");
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        #[test]
        fn elevation_leaves_the_curve_unchanged(c in arb_curve(), t in 1usize..=3) {
            let e = c.elevate_degree(t).expect("degree at most 8");
            prop_assert_eq!(e.degree(), c.degree() + t);
            let s = breaks(c.knots());
            prop_assert_eq!(e.num_control_points(), c.num_control_points() + t * (s + 1));
            for (value, mult) in c.knots().interior_breaks() {
                prop_assert_eq!(e.knots().multiplicity(value), mult + t);
            }
            assert_same_curve(&c, &e);
            // Elevating twice by 1 is elevating once by 2 (up to round-off).
            let e2 = c.elevate_degree(1).and_then(|d| d.elevate_degree(t - 1)).expect("same degree");
            prop_assert_eq!(e2.knots(), e.knots());
            assert_same_curve(&e, &e2);
        }

        #[test]
        fn surface_elevation_leaves_the_surface_unchanged(s in arb_surface(), tu in 0usize..=2, tv in 0usize..=2) {
            let e = s.elevate_degree_u(tu).expect("small degree").elevate_degree_v(tv).expect("small degree");
            prop_assert_eq!(e.degree_u(), s.degree_u() + tu);
            prop_assert_eq!(e.degree_v(), s.degree_v() + tv);
            prop_assert_eq!(e.n_u(), s.n_u() + tu * (breaks(s.knots_u()) + 1));
            prop_assert_eq!(e.n_v(), s.n_v() + tv * (breaks(s.knots_v()) + 1));
            assert_same_surface(&s, &e);
        }
    }
}
