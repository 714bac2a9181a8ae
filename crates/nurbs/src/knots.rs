//! Clamped knot vectors, validated on construction, and the span search of The NURBS Book A2.1.

use crate::NurbsError;

/// Highest degree the kernel evaluates (fixed-size scratch arrays keep evaluation allocation-free).
pub const MAX_DEGREE: usize = 15;

/// A clamped (open) knot vector `U = {u_0, ..., u_m}` of a given degree `p`:
/// non-decreasing, finite, the first and last `p + 1` knots equal, interior multiplicity at most
/// `p`, and a non-empty domain `[u_p, u_{m-p}]`. It carries `n = m - p` basis functions.
#[derive(Clone, Debug, PartialEq)]
pub struct KnotVector {
    degree: usize,
    knots: Vec<f64>,
}

impl KnotVector {
    /// Validate and build a knot vector.
    ///
    /// # Errors
    /// [`NurbsError::BadDegree`], [`NurbsError::TooFewKnots`], [`NurbsError::NonFiniteKnot`],
    /// [`NurbsError::DecreasingKnots`], [`NurbsError::NotClamped`],
    /// [`NurbsError::KnotMultiplicity`] or [`NurbsError::EmptyDomain`] when `knots` is not a
    /// clamped knot vector of degree `degree`.
    ///
    /// ```
    /// use nurbs::KnotVector;
    /// // Clamped cubic with one interior knot: m + 1 = 9 knots, n + 1 = m - p = 5 basis functions.
    /// let k = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0, 1.0])?;
    /// assert_eq!((k.num_basis(), k.domain()), (5, (0.0, 1.0)));
    /// // Decreasing knots are refused.
    /// assert!(KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 0.5, 1.0, 1.0]).is_err());
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn try_new(degree: usize, knots: Vec<f64>) -> Result<Self, NurbsError> {
        if degree == 0 || degree > MAX_DEGREE {
            return Err(NurbsError::BadDegree { degree, max: MAX_DEGREE });
        }
        let min = 2 * (degree + 1);
        if knots.len() < min {
            return Err(NurbsError::TooFewKnots { len: knots.len(), degree, min });
        }
        for (index, &value) in knots.iter().enumerate() {
            if !value.is_finite() {
                return Err(NurbsError::NonFiniteKnot { index, value });
            }
            if index > 0 && value < knots[index - 1] {
                return Err(NurbsError::DecreasingKnots { index, prev: knots[index - 1], value });
            }
        }
        let m = knots.len() - 1;
        if knots[..=degree].iter().any(|&k| k != knots[0]) || knots[m - degree..].iter().any(|&k| k != knots[m]) {
            return Err(NurbsError::NotClamped { needed: degree + 1 });
        }
        let (start, end) = (knots[degree], knots[m - degree]);
        if end <= start {
            return Err(NurbsError::EmptyDomain { start, end });
        }
        // The end knots have multiplicity exactly p + 1: one more gives a basis function that
        // vanishes everywhere.
        if knots[degree + 1] == start {
            return Err(NurbsError::KnotMultiplicity { value: start, multiplicity: degree + 2, degree });
        }
        if knots[m - degree - 1] == end {
            return Err(NurbsError::KnotMultiplicity { value: end, multiplicity: degree + 2, degree });
        }
        let mut i = degree + 1;
        while i < m - degree {
            let mult = knots[i..].iter().take_while(|&&k| k == knots[i]).count();
            if mult > degree {
                return Err(NurbsError::KnotMultiplicity { value: knots[i], multiplicity: mult, degree });
            }
            i += mult;
        }
        Ok(KnotVector { degree, knots })
    }

    /// Build without validation; the caller guarantees the invariants.
    pub(crate) fn new_unchecked(degree: usize, knots: Vec<f64>) -> Self {
        debug_assert!(KnotVector::try_new(degree, knots.clone()).is_ok(), "invalid knots {knots:?}");
        KnotVector { degree, knots }
    }

    /// A uniform clamped knot vector on [0, 1] with `n` basis functions.
    ///
    /// # Errors
    /// [`NurbsError::BadControlPointCount`] if `n <= degree`, or a degree error.
    pub fn uniform(degree: usize, n: usize) -> Result<Self, NurbsError> {
        if n <= degree {
            return Err(NurbsError::BadControlPointCount {
                what: "uniform knot vector".into(),
                count: n,
                min: degree + 1,
                max: usize::MAX,
            });
        }
        let mut k = vec![0.0; degree + 1];
        let segs = n - degree;
        for i in 1..segs {
            k.push(i as f64 / segs as f64);
        }
        k.extend(std::iter::repeat_n(1.0, degree + 1));
        KnotVector::try_new(degree, k)
    }

    #[inline]
    pub fn degree(&self) -> usize {
        self.degree
    }

    /// The knots `u_0 ..= u_m`.
    #[inline]
    pub fn as_slice(&self) -> &[f64] {
        &self.knots
    }

    /// Number of basis functions (control points), `n + 1` in The NURBS Book's notation.
    #[inline]
    pub fn num_basis(&self) -> usize {
        self.knots.len() - self.degree - 1
    }

    /// The parameter domain `[u_p, u_{m-p}]`.
    #[inline]
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.knots.len() - 1 - self.degree])
    }

    /// Clamp `u` into the domain (NaN maps to the start).
    #[inline]
    pub fn clamp(&self, u: f64) -> f64 {
        let (a, b) = self.domain();
        if u >= a {
            if u <= b {
                u
            } else {
                b
            }
        } else {
            a
        }
    }

    /// The knot span index `i` with `u_i <= u < u_{i+1}` (A2.1); `u` at the domain end maps to
    /// the last non-empty span, `u` outside the domain to the first or last span.
    ///
    /// ```
    /// use nurbs::KnotVector;
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.25, 0.5, 1.0, 1.0, 1.0])?;
    /// let u = k.as_slice();
    /// // u_s <= t < u_{s+1} inside the domain (A2.1); the end of the domain belongs to the last span.
    /// for t in [0.0, 0.1, 0.25, 0.7] {
    ///     let s = k.find_span(t);
    ///     assert!(u[s] <= t && t < u[s + 1], "t = {t}");
    /// }
    /// assert_eq!(k.find_span(1.0), 4);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    #[inline]
    pub fn find_span(&self, u: f64) -> usize {
        let p = self.degree;
        let n = self.num_basis() - 1;
        let k = &self.knots;
        if u >= k[n + 1] {
            return n;
        }
        if u <= k[p] {
            return p;
        }
        // Binary search in [p, n]: last index i with k[i] <= u.
        let (mut lo, mut hi) = (p, n + 1);
        while hi - lo > 1 {
            let mid = (lo + hi) / 2;
            if u < k[mid] {
                hi = mid;
            } else {
                lo = mid;
            }
        }
        lo
    }

    /// Multiplicity of the knot value `u` (0 if `u` is not a knot).
    pub fn multiplicity(&self, u: f64) -> usize {
        self.knots.iter().filter(|&&k| k == u).count()
    }

    /// The distinct interior knot values with their multiplicities.
    pub fn interior_breaks(&self) -> Vec<(f64, usize)> {
        let p = self.degree;
        let m = self.knots.len() - 1;
        let mut out: Vec<(f64, usize)> = Vec::new();
        for &k in &self.knots[p + 1..m - p] {
            match out.last_mut() {
                Some((v, c)) if *v == k => *c += 1,
                _ => out.push((k, 1)),
            }
        }
        out
    }

    /// The distinct knot values bounding the non-empty spans: the domain's start, every
    /// distinct interior knot, the domain's end (`spans + 1` values, increasing). With
    /// [`split_spans`], the parameter grids of the tessellation, the viewer, the curvature
    /// picture and the projectors' sampling.
    ///
    /// ```
    /// use nurbs::KnotVector;
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.25, 0.25, 1.0, 1.0, 1.0])?;
    /// assert_eq!(k.span_breaks(), vec![0.0, 0.25, 1.0]);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn span_breaks(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        let mut out = vec![a];
        out.extend(self.interior_breaks().into_iter().map(|(t, _)| t));
        out.push(b);
        out
    }

    /// Parameter values for sampling along this knot vector: `intervals` uniform intervals of
    /// the domain (at least 1), joined, when `refine_at_knots`, with every distinct interior
    /// knot and with points that split each non-empty knot span into at least `per_span`
    /// intervals. Sorted, without duplicates (values closer than `1e-12` of the domain are one),
    /// the domain ends included.
    ///
    /// ```
    /// use nurbs::KnotVector;
    /// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.25, 1.0, 1.0, 1.0])?;
    /// // Uniform 0, 0.5, 1; with the knot 0.25 and the span midpoints 0.125 and 0.625.
    /// assert_eq!(k.param_grid(2, false, 2), vec![0.0, 0.5, 1.0]);
    /// assert_eq!(k.param_grid(2, true, 2), vec![0.0, 0.125, 0.25, 0.5, 0.625, 1.0]);
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn param_grid(&self, intervals: usize, refine_at_knots: bool, per_span: usize) -> Vec<f64> {
        let (a, b) = self.domain();
        let n = intervals.max(1);
        let mut t: Vec<f64> = (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect();
        if refine_at_knots {
            for w in self.span_breaks().windows(2) {
                let (k0, k1) = (w[0], w[1]);
                let m = per_span.max(1);
                t.extend((0..=m).map(|j| k0 + (k1 - k0) * j as f64 / m as f64));
            }
        }
        t.sort_by(f64::total_cmp);
        // Values closer than round-off of the domain are one grid line.
        let eps = 1e-12 * (b - a).abs();
        t.dedup_by(|x, y| (*x - *y).abs() <= eps);
        t
    }

    /// The same knots mapped affinely onto `[a, b]`.
    ///
    /// # Errors
    /// [`NurbsError::EmptyDomain`] if `b <= a`.
    pub fn reparameterized(&self, a: f64, b: f64) -> Result<Self, NurbsError> {
        if !(b > a) || !a.is_finite() || !b.is_finite() {
            return Err(NurbsError::EmptyDomain { start: a, end: b });
        }
        let (s, e) = self.domain();
        let k = self.knots.iter().map(|&u| if u == e { b } else { a + (u - s) * (b - a) / (e - s) }).collect();
        KnotVector::try_new(self.degree, k)
    }
}

/// Parameters splitting span `i` of `breaks` (increasing; [`KnotVector::span_breaks`]) into
/// `counts[i]` equal intervals (at least 1): `b_i + (b_i+1 - b_i) j / n_i` for `j < n_i`, then
/// the last break, `sum n_i + 1` values. How many intervals each span gets is the caller's
/// sampling rule (a fixed number, in proportion to the span's length, ...).
///
/// ```
/// assert_eq!(nurbs::split_spans(&[0.0, 0.5, 1.0], &[1, 4]), vec![0.0, 0.5, 0.625, 0.75, 0.875, 1.0]);
/// ```
pub fn split_spans(breaks: &[f64], counts: &[usize]) -> Vec<f64> {
    let mut out = Vec::with_capacity(counts.iter().map(|&n| n.max(1)).sum::<usize>() + 1);
    for (w, &n) in breaks.windows(2).zip(counts) {
        let n = n.max(1);
        out.extend((0..n).map(|j| w[0] + (w[1] - w[0]) * j as f64 / n as f64));
    }
    out.extend(breaks.last());
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn param_grid_contains_uniform_points_knots_and_splits_spans() {
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.1, 0.7, 1., 1., 1., 1.]).expect("valid");
        let t = kv.param_grid(4, true, 2);
        // Uniform 0, .25, .5, .75, 1; knots .1, .7; span midpoints .05, .4, .85.
        let want = [0.0, 0.05, 0.1, 0.25, 0.4, 0.5, 0.7, 0.75, 0.85, 1.0];
        assert_eq!(t.len(), want.len(), "{t:?}");
        for (a, b) in t.iter().zip(want) {
            // Affine combinations of the knots: exact to a few ulps.
            assert!((a - b).abs() <= 1e-15, "{t:?}");
        }
        let plain = kv.param_grid(4, false, 2);
        assert_eq!(plain, vec![0.0, 0.25, 0.5, 0.75, 1.0]);
    }

    #[test]
    fn rejects_invalid_vectors() {
        assert!(matches!(KnotVector::try_new(0, vec![0.0, 1.0]), Err(NurbsError::BadDegree { .. })));
        assert!(matches!(KnotVector::try_new(2, vec![0.0, 0.0, 1.0, 1.0]), Err(NurbsError::TooFewKnots { .. })));
        assert!(matches!(
            KnotVector::try_new(1, vec![0.0, 0.0, 0.5, 0.4, 1.0, 1.0]),
            Err(NurbsError::DecreasingKnots { index: 3, .. })
        ));
        assert!(matches!(KnotVector::try_new(1, vec![0.0, 0.1, 1.0, 1.0]), Err(NurbsError::NotClamped { .. })));
        assert!(matches!(
            KnotVector::try_new(1, vec![0.0, 0.0, f64::NAN, 1.0, 1.0]),
            Err(NurbsError::NonFiniteKnot { index: 2, .. })
        ));
        assert!(matches!(
            KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.5, 0.5, 0.5, 1.0, 1.0, 1.0]),
            Err(NurbsError::KnotMultiplicity { multiplicity: 3, .. })
        ));
        assert!(matches!(KnotVector::try_new(1, vec![1.0, 1.0, 1.0, 1.0]), Err(NurbsError::EmptyDomain { .. })));
    }

    #[test]
    fn end_knots_have_multiplicity_exactly_degree_plus_one() {
        for k in [vec![0.0, 0.0, 0.0, 0.0, 1.0, 1.0, 1.0], vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0, 1.0]] {
            assert!(matches!(KnotVector::try_new(2, k), Err(NurbsError::KnotMultiplicity { multiplicity: 4, .. })));
        }
    }

    #[test]
    fn span_search_brackets_the_parameter() {
        let kv = KnotVector::try_new(2, vec![0., 0., 0., 1., 2., 3., 4., 4., 5., 5., 5.]).expect("valid");
        // The NURBS Book Ex. 2.3: u = 5/2 lies in span 4.
        assert_eq!(kv.find_span(2.5), 4);
        assert_eq!(kv.find_span(0.0), 2);
        assert_eq!(kv.find_span(5.0), 7);
        assert_eq!(kv.find_span(4.0), 7);
        for t in 0..=500 {
            let u = t as f64 / 100.0;
            let s = kv.find_span(u);
            let k = kv.as_slice();
            assert!(k[s] <= u && (u < k[s + 1] || (u == 5.0 && s == 7)), "u {u} span {s}");
        }
    }

    #[test]
    fn uniform_vector_and_breaks() {
        let kv = KnotVector::uniform(3, 7).expect("valid");
        assert_eq!(kv.num_basis(), 7);
        assert_eq!(kv.interior_breaks().len(), 3);
        assert_eq!(kv.domain(), (0.0, 1.0));
        let r = kv.reparameterized(2.0, 6.0).expect("valid");
        assert_eq!(r.domain(), (2.0, 6.0));
        assert_eq!(r.as_slice()[5], 4.0);
    }
}
