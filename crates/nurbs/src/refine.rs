//! Knot insertion (The NURBS Book A5.1) and knot refinement (A5.4) for curves and surfaces,
//! and the knot-vector merging that makes skinned sections compatible.
//!
//! Both operations act on the homogeneous control points `P^w_i = (w_i x_i, w_i y_i, w_i z_i, w_i)`,
//! so rational curves are refined exactly. Inserting `u` in `[u_k, u_{k+1})` replaces the points
//! `P^w_{k-p+1} ..= P^w_k` by `Q^w_i = a_i P^w_i + (1 - a_i) P^w_{i-1}` with
//! `a_i = (u - u_i) / (u_{i+p} - u_i)` (eq. 5.15); the curve is unchanged, point for point.
//!
//! A surface is refined in one direction by applying the curve algorithm to every row of its
//! control net in that direction (A5.3 is A5.1 applied column by column); [`NurbsSurface`]
//! shares the curve code through [`NurbsSurface::map_rows`].

use crate::curve::Homogeneous;
use crate::knots::MAX_DEGREE;
use crate::{KnotVector, NurbsCurve, NurbsError, NurbsSurface};

/// A parameter direction of a surface.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub(crate) enum Direction {
    U,
    V,
}

/// `h = a * x + (1 - a) * y` on homogeneous points.
#[inline]
pub(crate) fn lerp(a: f64, x: &Homogeneous, y: &Homogeneous) -> Homogeneous {
    let b = 1.0 - a;
    [a * x[0] + b * y[0], a * x[1] + b * y[1], a * x[2] + b * y[2], a * x[3] + b * y[3]]
}

/// Check that `x` is a non-decreasing list of parameters strictly inside the domain of `kv`
/// and that inserting all of them keeps every interior multiplicity at most the degree.
fn check_insertion(kv: &KnotVector, x: &[f64]) -> Result<(), NurbsError> {
    let p = kv.degree();
    let (start, end) = kv.domain();
    for (index, &value) in x.iter().enumerate() {
        if !(start <= value && value <= end) {
            return Err(NurbsError::ParameterOutOfDomain { value, start, end });
        }
        if index > 0 && value < x[index - 1] {
            return Err(NurbsError::DecreasingKnots { index, prev: x[index - 1], value });
        }
    }
    let mut i = 0;
    while i < x.len() {
        let count = x[i..].iter().take_while(|&&v| v == x[i]).count();
        let multiplicity = kv.multiplicity(x[i]) + count;
        // The end knots already have multiplicity p + 1: nothing can be inserted there.
        if multiplicity > p {
            return Err(NurbsError::KnotMultiplicity { value: x[i], multiplicity, degree: p });
        }
        i += count;
    }
    Ok(())
}

/// The knot vector `U` with the sorted values `x` merged in (each after the equal knots of `U`).
fn merged_knots(u: &[f64], x: &[f64]) -> Vec<f64> {
    let mut out = Vec::with_capacity(u.len() + x.len());
    let mut j = 0;
    for &k in u {
        while j < x.len() && x[j] < k {
            out.push(x[j]);
            j += 1;
        }
        out.push(k);
    }
    out.extend_from_slice(&x[j..]);
    out
}

/// A5.1: insert `u` (in span `k`, multiplicity `s`) `r` times into the homogeneous control
/// polygon `pw` of degree `p` over the knots `knots`. Needs `r >= 1` and `s + r <= p`.
fn insert_knot_points(
    p: usize,
    knots: &[f64],
    pw: &[Homogeneous],
    u: f64,
    k: usize,
    s: usize,
    r: usize,
) -> Vec<Homogeneous> {
    let np = pw.len() - 1;
    let mut qw = vec![[0.0; 4]; pw.len() + r];
    qw[..=k - p].copy_from_slice(&pw[..=k - p]);
    qw[k - s + r..=np + r].copy_from_slice(&pw[k - s..=np]);
    let mut rw = [[0.0; 4]; MAX_DEGREE + 1];
    rw[..=p - s].copy_from_slice(&pw[k - p..=k - s]);
    let mut l = k - p;
    for j in 1..=r {
        l = k - p + j;
        for i in 0..=p - j - s {
            let alpha = (u - knots[l + i]) / (knots[i + k + 1] - knots[l + i]);
            rw[i] = lerp(alpha, &rw[i + 1], &rw[i]);
        }
        qw[l] = rw[0];
        qw[k + r - j - s] = rw[p - j - s];
    }
    if l + 1 < k - s {
        qw[l + 1..k - s].copy_from_slice(&rw[1..k - s - l]);
    }
    qw
}

/// A5.4: refine the homogeneous control polygon `pw` of degree `p` over `knots` with the
/// non-empty, sorted, validated list `x`. Returns the new control points; the new knots are
/// `merged_knots(knots, x)`.
pub(crate) fn refine_points(kv: &KnotVector, pw: &[Homogeneous], x: &[f64]) -> Vec<Homogeneous> {
    let p = kv.degree();
    let knots = kv.as_slice();
    let n = pw.len() - 1;
    let m = n + p + 1;
    let r = x.len() - 1;
    let a = kv.find_span(x[0]);
    let b = kv.find_span(x[r]) + 1;
    let mut qw = vec![[0.0; 4]; pw.len() + x.len()];
    let mut ubar = vec![0.0; knots.len() + x.len()];
    qw[..=a - p].copy_from_slice(&pw[..=a - p]);
    qw[b - 1 + r + 1..=n + r + 1].copy_from_slice(&pw[b - 1..=n]);
    ubar[..=a].copy_from_slice(&knots[..=a]);
    ubar[b + p + r + 1..=m + r + 1].copy_from_slice(&knots[b + p..=m]);
    let mut i = b + p - 1;
    let mut k = b + p + r;
    for j in (0..=r).rev() {
        while x[j] <= knots[i] && i > a {
            qw[k - p - 1] = pw[i - p - 1];
            ubar[k] = knots[i];
            k -= 1;
            i -= 1;
        }
        qw[k - p - 1] = qw[k - p];
        for l in 1..=p {
            let ind = k - p + l;
            let alpha = ubar[k + l] - x[j];
            if alpha == 0.0 {
                qw[ind - 1] = qw[ind];
            } else {
                let alpha = alpha / (ubar[k + l] - knots[i - p + l]);
                qw[ind - 1] = lerp(alpha, &qw[ind - 1], &qw[ind]);
            }
        }
        ubar[k] = x[j];
        k -= 1;
    }
    debug_assert_eq!(ubar, merged_knots(knots, x));
    qw
}

impl NurbsCurve {
    /// Insert the knot `u` `r` times (The NURBS Book A5.1). The curve is unchanged; it gains
    /// `r` control points. `r = 0` returns a copy.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] if `u` is not in the domain (or not finite),
    /// [`NurbsError::KnotMultiplicity`] if the multiplicity of `u` would exceed the degree
    /// (in particular at the end knots, which already have multiplicity `p + 1`).
    ///
    /// ```
    /// use nurbs::{KnotVector, NurbsCurve, Vec3};
    /// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(3.0, 2.0, 1.0), Vec3::new(4.0, 0.0, 0.0)];
    /// let c = NurbsCurve::try_new(KnotVector::uniform(3, 4)?, &pts, Some(&[1.0, 2.0, 0.5, 1.0]))?;
    /// // Knot insertion (A5.1) adds control points and leaves the curve as it was.
    /// let r = c.insert_knot(0.3, 2)?;
    /// assert_eq!(r.num_control_points(), c.num_control_points() + 2);
    /// for i in 0..=10 {
    ///     let t = i as f64 / 10.0;
    ///     assert!(r.point(t).distance(c.point(t)) < 1e-14);
    /// }
    /// # Ok::<(), nurbs::NurbsError>(())
    /// ```
    pub fn insert_knot(&self, u: f64, r: usize) -> Result<NurbsCurve, NurbsError> {
        let (start, end) = self.domain();
        if !(start <= u && u <= end) {
            return Err(NurbsError::ParameterOutOfDomain { value: u, start, end });
        }
        if r == 0 {
            return Ok(self.clone());
        }
        let kv = self.knots();
        let p = kv.degree();
        let s = kv.multiplicity(u);
        // Checked before anything is allocated, so a huge r is an error, not an abort.
        if s.saturating_add(r) > p {
            return Err(NurbsError::KnotMultiplicity { value: u, multiplicity: s.saturating_add(r), degree: p });
        }
        let k = kv.find_span(u);
        let cw = insert_knot_points(p, kv.as_slice(), self.homogeneous(), u, k, s, r);
        let knots = KnotVector::new_unchecked(p, merged_knots(kv.as_slice(), &vec![u; r]));
        Ok(NurbsCurve::from_parts_unchecked(knots, cw))
    }

    /// Insert all knots of the non-decreasing list `x` at once (knot refinement, The NURBS
    /// Book A5.4). The curve is unchanged. An empty `x` returns a copy.
    ///
    /// # Errors
    /// [`NurbsError::ParameterOutOfDomain`] for a value outside the domain,
    /// [`NurbsError::DecreasingKnots`] if `x` is not sorted, [`NurbsError::KnotMultiplicity`]
    /// if a resulting multiplicity would exceed the degree.
    pub fn refine_knots(&self, x: &[f64]) -> Result<NurbsCurve, NurbsError> {
        check_insertion(self.knots(), x)?;
        if x.is_empty() {
            return Ok(self.clone());
        }
        let kv = self.knots();
        let cw = refine_points(kv, self.homogeneous(), x);
        let knots = KnotVector::new_unchecked(kv.degree(), merged_knots(kv.as_slice(), x));
        Ok(NurbsCurve::from_parts_unchecked(knots, cw))
    }

    /// The knots to pass to [`NurbsCurve::refine_knots`] so that this curve's knot vector
    /// becomes `target`: every value of `target` repeated as many times as its multiplicity
    /// in `target` exceeds its multiplicity here, in order. Knots of this curve that `target`
    /// lacks are ignored (refinement cannot remove them); [`NurbsCurve::refine_to`] checks.
    pub fn knots_to_insert(&self, target: &KnotVector) -> Vec<f64> {
        let mut out = Vec::new();
        let t = target.as_slice();
        let mut i = 0;
        while i < t.len() {
            let count = t[i..].iter().take_while(|&&v| v == t[i]).count();
            let have = self.knots().multiplicity(t[i]);
            out.extend(std::iter::repeat_n(t[i], count.saturating_sub(have)));
            i += count;
        }
        out
    }

    /// Refine this curve so that its knot vector becomes exactly `target` (for skinning: bring
    /// every section onto the knot vector from [`merge_knot_vectors`]).
    ///
    /// # Errors
    /// [`NurbsError::Incompatible`] if `target` has another degree or domain, or does not
    /// contain every knot of this curve with at least its multiplicity.
    pub fn refine_to(&self, target: &KnotVector) -> Result<NurbsCurve, NurbsError> {
        let own = self.knots();
        if target.degree() != own.degree() || target.domain() != own.domain() {
            return Err(NurbsError::Incompatible {
                what: format!(
                    "target knot vector of degree {} on {:?}, curve of degree {} on {:?}",
                    target.degree(),
                    target.domain(),
                    own.degree(),
                    own.domain()
                ),
            });
        }
        for (value, multiplicity) in own.interior_breaks() {
            let there = target.multiplicity(value);
            if there < multiplicity {
                return Err(NurbsError::Incompatible {
                    what: format!(
                        "knot {value} has multiplicity {multiplicity} in the curve but {there} in the target"
                    ),
                });
            }
        }
        let refined = self.refine_knots(&self.knots_to_insert(target))?;
        debug_assert_eq!(refined.knots(), target);
        Ok(refined)
    }
}

/// The smallest knot vector containing all of `vectors`: the union of their knot values, each
/// with the highest multiplicity it has in any of them. Refining every curve to it (with
/// [`NurbsCurve::refine_to`]) makes a family of curves compatible for skinning (The NURBS Book
/// 10.3). Values are compared exactly: reparameterize the vectors onto one domain first
/// ([`KnotVector::reparameterized`]).
///
/// # Errors
/// [`NurbsError::Incompatible`] if `vectors` is empty or the vectors differ in degree or domain.
///
/// ```
/// use nurbs::{merge_knot_vectors, KnotVector};
/// let a = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0])?;
/// let b = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.25, 0.5, 0.5, 1.0, 1.0, 1.0])?;
/// // The union, each knot at the largest of its multiplicities.
/// let m = merge_knot_vectors(&[&a, &b])?;
/// assert_eq!(m.as_slice(), &[0.0, 0.0, 0.0, 0.25, 0.5, 0.5, 1.0, 1.0, 1.0]);
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn merge_knot_vectors(vectors: &[&KnotVector]) -> Result<KnotVector, NurbsError> {
    let first = vectors.first().ok_or_else(|| NurbsError::Incompatible { what: "no knot vectors to merge".into() })?;
    let (p, domain) = (first.degree(), first.domain());
    for (i, kv) in vectors.iter().enumerate() {
        if kv.degree() != p || kv.domain() != domain {
            return Err(NurbsError::Incompatible {
                what: format!(
                    "knot vector {i} has degree {} on {:?}, knot vector 0 degree {p} on {domain:?}",
                    kv.degree(),
                    kv.domain()
                ),
            });
        }
    }
    // Merge the sorted break lists, keeping the highest multiplicity of each value.
    let mut breaks: Vec<(f64, usize)> = Vec::new();
    for kv in vectors {
        let mut merged = Vec::with_capacity(breaks.len());
        let mut a = breaks.iter().copied().peekable();
        let mut b = kv.interior_breaks().into_iter().peekable();
        loop {
            let next = match (a.peek().copied(), b.peek().copied()) {
                (Some(x), Some(y)) if x.0 == y.0 => {
                    a.next();
                    b.next();
                    (x.0, x.1.max(y.1))
                }
                (Some(x), Some(y)) if x.0 < y.0 => {
                    a.next();
                    x
                }
                (_, Some(y)) => {
                    b.next();
                    y
                }
                (Some(x), None) => {
                    a.next();
                    x
                }
                (None, None) => break,
            };
            merged.push(next);
        }
        breaks = merged;
    }
    let mut knots = vec![domain.0; p + 1];
    for (value, multiplicity) in breaks {
        knots.extend(std::iter::repeat_n(value, multiplicity));
    }
    knots.extend(std::iter::repeat_n(domain.1, p + 1));
    KnotVector::try_new(p, knots)
}

impl NurbsSurface {
    /// Apply a curve operation to every row of the control net along `dir` (the rows along u
    /// are the columns `j = const`, with the u knots; along v the rows `i = const`, with the v
    /// knots) and reassemble the net. The operation must give every row the same knot vector,
    /// which holds for knot insertion and degree elevation since they depend on the knots only.
    pub(crate) fn map_rows(
        &self,
        dir: Direction,
        mut op: impl FnMut(&NurbsCurve) -> Result<NurbsCurve, NurbsError>,
    ) -> Result<NurbsSurface, NurbsError> {
        let (nu, nv) = (self.n_u(), self.n_v());
        let cw = self.homogeneous();
        let rows: Vec<NurbsCurve> = match dir {
            Direction::U => (0..nv)
                .map(|j| {
                    let col = (0..nu).map(|i| cw[i * nv + j]).collect();
                    op(&NurbsCurve::from_parts_unchecked(self.knots_u().clone(), col))
                })
                .collect::<Result<_, _>>()?,
            Direction::V => (0..nu)
                .map(|i| {
                    op(&NurbsCurve::from_parts_unchecked(self.knots_v().clone(), cw[i * nv..(i + 1) * nv].to_vec()))
                })
                .collect::<Result<_, _>>()?,
        };
        let knots = rows.first().expect("a control net has at least two rows").knots().clone();
        debug_assert!(rows.iter().all(|c| c.knots() == &knots));
        let len = knots.num_basis();
        Ok(match dir {
            Direction::U => {
                let mut out = Vec::with_capacity(len * nv);
                for i in 0..len {
                    out.extend(rows.iter().map(|c| c.homogeneous()[i]));
                }
                NurbsSurface::from_parts_unchecked(knots, self.knots_v().clone(), out)
            }
            Direction::V => {
                let out = rows.iter().flat_map(|c| c.homogeneous().iter().copied()).collect();
                NurbsSurface::from_parts_unchecked(self.knots_u().clone(), knots, out)
            }
        })
    }

    /// Insert the knot `t` `r` times in the u direction (A5.3). The surface is unchanged.
    ///
    /// # Errors
    /// As [`NurbsCurve::insert_knot`] for the u knots.
    pub fn insert_knot_u(&self, t: f64, r: usize) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::U, |c| c.insert_knot(t, r))
    }

    /// Insert the knot `t` `r` times in the v direction (A5.3). The surface is unchanged.
    ///
    /// # Errors
    /// As [`NurbsCurve::insert_knot`] for the v knots.
    pub fn insert_knot_v(&self, t: f64, r: usize) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::V, |c| c.insert_knot(t, r))
    }

    /// Refine the u knots with the sorted list `x` (A5.5). The surface is unchanged.
    ///
    /// # Errors
    /// As [`NurbsCurve::refine_knots`] for the u knots.
    pub fn refine_knots_u(&self, x: &[f64]) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::U, |c| c.refine_knots(x))
    }

    /// Refine the v knots with the sorted list `x` (A5.5). The surface is unchanged.
    ///
    /// # Errors
    /// As [`NurbsCurve::refine_knots`] for the v knots.
    pub fn refine_knots_v(&self, x: &[f64]) -> Result<NurbsSurface, NurbsError> {
        self.map_rows(Direction::V, |c| c.refine_knots(x))
    }
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;
    use crate::fixtures::{arb_curve, arb_surface, circle, interior_knots};
    use crate::Vec3;
    use proptest::prelude::*;

    /// Size of the control polygon, the scale of round-off in evaluations.
    pub(crate) fn scale_of(points: &[Vec3]) -> f64 {
        points.iter().map(|p| p.norm()).fold(1.0, f64::max)
    }

    /// Knot insertion, refinement and elevation form convex (or boundedly affine) combinations
    /// of homogeneous points, and evaluation does a few dozen more operations; with weights in
    /// [0.2, 5] the division by w costs at most a factor 25. 1e-12 relative to the polygon size
    /// covers that with margin: over 20000 random curves the largest errors measured were
    /// 1e-15 (insertion, refinement) and 5e-15 (elevation by 3).
    pub(crate) const SHAPE_REL: f64 = 1e-12;

    pub(crate) fn assert_same_curve(a: &NurbsCurve, b: &NurbsCurve) {
        assert_eq!(a.domain(), b.domain());
        let tol = SHAPE_REL * scale_of(&a.control_points());
        let (s, e) = a.domain();
        for i in 0..=200 {
            let u = s + (e - s) * f64::from(i) / 200.0;
            crate::assert_near!(a.point(u), b.point(u), tol, "at u = {u}");
        }
        // The knots themselves, where a side derivative could differ in principle.
        for &u in a.knots().as_slice() {
            crate::assert_near!(a.point(u), b.point(u), tol, "at knot u = {u}");
        }
    }

    pub(crate) fn assert_same_surface(a: &NurbsSurface, b: &NurbsSurface) {
        let tol = SHAPE_REL * scale_of(&a.control_points());
        let ((u0, u1), (v0, v1)) = (a.domain_u(), a.domain_v());
        assert_eq!(((u0, u1), (v0, v1)), (b.domain_u(), b.domain_v()));
        for i in 0..=24 {
            for j in 0..=24 {
                let u = u0 + (u1 - u0) * f64::from(i) / 24.0;
                let v = v0 + (v1 - v0) * f64::from(j) / 24.0;
                crate::assert_near!(a.point(u, v), b.point(u, v), tol, "at (u, v) = ({u}, {v})");
            }
        }
    }

    #[test]
    fn book_example_5_1_single_insertion() {
        // The NURBS Book Ex. 5.1: cubic, U = {0,0,0,0,1,2,3,4,5,5,5,5}, insert u = 5/2 once:
        // P_0..P_2 and P_5..P_7 move unchanged; Q_3..Q_5 are interpolated with
        // alpha_3 = 5/6, alpha_4 = 1/2, alpha_5 = 1/6.
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 1., 2., 3., 4., 5., 5., 5., 5.]).expect("valid");
        let pts: Vec<Vec3> =
            (0..8).map(|i| Vec3::new(f64::from(i), f64::from(i * i % 5), 0.5 * f64::from(i))).collect();
        let c = NurbsCurve::try_new(kv, &pts, None).expect("valid");
        let d = c.insert_knot(2.5, 1).expect("inside the domain");
        assert_eq!(d.knots().as_slice(), &[0., 0., 0., 0., 1., 2., 2.5, 3., 4., 5., 5., 5., 5.]);
        let q = d.control_points();
        assert_eq!(q.len(), 9);
        for i in 0..=2 {
            assert_eq!(q[i], pts[i]);
        }
        for (i, a) in [(3, 5.0 / 6.0), (4, 0.5), (5, 1.0 / 6.0)] {
            crate::assert_near!(q[i], pts[i] * a + pts[i - 1] * (1.0 - a), 1e-15);
        }
        for i in 6..9 {
            assert_eq!(q[i], pts[i - 1]);
        }
        assert_same_curve(&c, &d);
    }

    #[test]
    fn rational_circle_unchanged_by_insertion_and_refinement() {
        let r = 2.5;
        let c = circle(r);
        let once = c.insert_knot(0.1, 2).expect("valid insertion");
        let twice = c.refine_knots(&[0.1, 0.1, 0.3, 0.6, 0.9]).expect("valid refinement");
        for d in [&once, &twice] {
            assert_same_curve(&c, d);
            for i in 0..=400 {
                // Every point stays on the circle: 1e-12 covers round-off as in the
                // circle test of curve.rs.
                let u = f64::from(i) / 400.0;
                crate::assert_near!(d.point(u).norm(), r, 1e-12 * r);
            }
        }
        assert_eq!(twice.num_control_points(), c.num_control_points() + 5);
        assert_eq!(twice.knots().multiplicity(0.1), 2);
        assert_eq!(twice.knots().multiplicity(0.3), 1);
    }

    #[test]
    fn bad_insertions_are_errors() {
        let c = circle(1.0);
        assert!(matches!(c.insert_knot(1.5, 1), Err(NurbsError::ParameterOutOfDomain { .. })));
        assert!(matches!(c.insert_knot(f64::NAN, 1), Err(NurbsError::ParameterOutOfDomain { .. })));
        // 0.25 already has multiplicity 2 = p.
        assert!(matches!(c.insert_knot(0.25, 1), Err(NurbsError::KnotMultiplicity { multiplicity: 3, .. })));
        assert!(matches!(c.insert_knot(0.3, 3), Err(NurbsError::KnotMultiplicity { multiplicity: 3, .. })));
        assert!(matches!(c.insert_knot(0.0, 1), Err(NurbsError::KnotMultiplicity { .. })));
        assert!(matches!(c.insert_knot(1.0, 1), Err(NurbsError::KnotMultiplicity { .. })));
        assert!(matches!(c.insert_knot(0.3, usize::MAX), Err(NurbsError::KnotMultiplicity { .. })));
        assert!(matches!(c.refine_knots(&[0.5, 0.4]), Err(NurbsError::DecreasingKnots { index: 1, .. })));
        assert!(matches!(c.refine_knots(&[0.1, 0.1, 0.1]), Err(NurbsError::KnotMultiplicity { .. })));
        assert!(matches!(c.refine_knots(&[-0.1]), Err(NurbsError::ParameterOutOfDomain { .. })));
        assert!(matches!(c.refine_knots(&[1.0]), Err(NurbsError::KnotMultiplicity { .. })));
        assert_eq!(c.refine_knots(&[]).expect("empty is fine"), c);
        assert_eq!(c.insert_knot(0.3, 0).expect("r = 0 is fine"), c);
    }

    #[test]
    fn merge_and_refine_to_make_curves_compatible() {
        let a = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.2, 0.5, 0.5, 1., 1., 1., 1.]).expect("valid");
        let b = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.5, 0.7, 0.7, 0.7, 1., 1., 1., 1.]).expect("valid");
        let merged = merge_knot_vectors(&[&a, &b]).expect("same degree and domain");
        assert_eq!(merged.as_slice(), &[0., 0., 0., 0., 0.2, 0.5, 0.5, 0.7, 0.7, 0.7, 1., 1., 1., 1.]);
        let pts: Vec<Vec3> =
            (0..a.num_basis()).map(|i| Vec3::new(f64::from(i as u32), 1.0, (i as f64).sin())).collect();
        let c = NurbsCurve::try_new(a.clone(), &pts, None).expect("valid");
        assert_eq!(c.knots_to_insert(&merged), vec![0.7, 0.7, 0.7]);
        let r = c.refine_to(&merged).expect("merged contains the curve's knots");
        assert_eq!(r.knots(), &merged);
        assert_same_curve(&c, &r);
        // b lacks the knot 0.2 of the curve; other degrees and domains are incompatible.
        assert!(matches!(c.refine_to(&b), Err(NurbsError::Incompatible { .. })));
        let c2 = KnotVector::uniform(2, 5).expect("valid");
        assert!(matches!(merge_knot_vectors(&[&a, &c2]), Err(NurbsError::Incompatible { .. })));
        let shifted = a.reparameterized(0.0, 2.0).expect("valid");
        assert!(matches!(merge_knot_vectors(&[&a, &shifted]), Err(NurbsError::Incompatible { .. })));
        assert!(matches!(merge_knot_vectors(&[]), Err(NurbsError::Incompatible { .. })));
    }

    #[test]
    fn surface_insertion_keeps_shape_and_counts() {
        let ku = KnotVector::try_new(2, vec![0., 0., 0., 0.4, 1., 1., 1.]).expect("valid");
        let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.5, 1., 1., 1., 1.]).expect("valid");
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let pts: Vec<Vec3> = (0..nu * nv)
            .map(|k| {
                let (i, j) = ((k / nv) as f64, (k % nv) as f64);
                Vec3::new(i, j, (i * 1.3 + j * 0.7).sin())
            })
            .collect();
        let w: Vec<f64> = (0..nu * nv).map(|k| 1.0 + 0.5 * (k as f64).cos()).collect();
        let s = NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid");
        let a = s.insert_knot_u(0.7, 2).expect("valid");
        assert_eq!((a.n_u(), a.n_v()), (nu + 2, nv));
        let b = s.insert_knot_v(0.5, 2).expect("valid");
        assert_eq!((b.n_u(), b.n_v()), (nu, nv + 2));
        assert_eq!(b.knots_v().multiplicity(0.5), 3);
        let c = s.refine_knots_u(&[0.1, 0.4]).expect("valid").refine_knots_v(&[0.2, 0.2, 0.9]).expect("valid");
        assert_eq!((c.n_u(), c.n_v()), (nu + 2, nv + 3));
        for t in [&a, &b, &c] {
            assert_same_surface(&s, t);
        }
        assert!(matches!(s.insert_knot_v(0.5, 3), Err(NurbsError::KnotMultiplicity { .. })));
        assert!(matches!(s.refine_knots_u(&[2.0]), Err(NurbsError::ParameterOutOfDomain { .. })));
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(200))]

        #[test]
        fn insertion_leaves_the_curve_unchanged(c in arb_curve(), t in 0.0f64..1.0, r in 1usize..=5) {
            let p = c.degree();
            let s = c.knots().multiplicity(t);
            let d = c.insert_knot(t, r);
            if s + r > p {
                prop_assert!(matches!(d, Err(NurbsError::KnotMultiplicity { .. })), "{d:?}");
            } else {
                let d = d.expect("valid insertion");
                prop_assert_eq!(d.num_control_points(), c.num_control_points() + r);
                prop_assert_eq!(d.knots().multiplicity(t), s + r);
                assert_same_curve(&c, &d);
                // A5.1 and A5.4 are different algorithms for the same thing.
                let e = c.refine_knots(&vec![t; r]).expect("same insertion");
                prop_assert_eq!(e.knots(), d.knots());
                let tol = SHAPE_REL * scale_of(&c.control_points());
                for (a, b) in d.control_points().iter().zip(e.control_points()) {
                    prop_assert!((*a - b).norm() <= tol, "{a:?} vs {b:?}");
                }
            }
        }

        #[test]
        fn refinement_leaves_the_curve_unchanged(c in arb_curve(), x in interior_knots(1, 12)) {
            // Keep the insertions legal: at most p - s copies of each value.
            let p = c.degree();
            let mut xs: Vec<f64> = Vec::new();
            for v in x {
                if c.knots().multiplicity(v) + xs.iter().filter(|&&y| y == v).count() < p {
                    xs.push(v);
                }
            }
            let d = c.refine_knots(&xs).expect("legal refinement");
            prop_assert_eq!(d.num_control_points(), c.num_control_points() + xs.len());
            prop_assert_eq!(d.knots().as_slice().len(), c.knots().as_slice().len() + xs.len());
            assert_same_curve(&c, &d);
            // Refining to the merged vector reaches it exactly.
            let merged = merge_knot_vectors(&[c.knots(), d.knots()]).expect("same degree and domain");
            prop_assert_eq!(&merged, d.knots());
            prop_assert_eq!(c.knots_to_insert(&merged), xs);
        }

        #[test]
        fn surface_refinement_leaves_the_surface_unchanged(s in arb_surface(), x in interior_knots(1, 4), y in interior_knots(1, 4)) {
            let legal = |kv: &KnotVector, x: Vec<f64>| -> Vec<f64> {
                x.into_iter().filter(|&v| kv.multiplicity(v) < kv.degree()).collect()
            };
            let (x, y) = (legal(s.knots_u(), x), legal(s.knots_v(), y));
            let t = s.refine_knots_u(&x).expect("legal").refine_knots_v(&y).expect("legal");
            prop_assert_eq!(t.n_u(), s.n_u() + x.len());
            prop_assert_eq!(t.n_v(), s.n_v() + y.len());
            assert_same_surface(&s, &t);
            // u then v equals v then u, net for net (the operations commute exactly in exact
            // arithmetic; round-off stays at the SHAPE_REL level).
            let t2 = s.refine_knots_v(&y).expect("legal").refine_knots_u(&x).expect("legal");
            let tol = SHAPE_REL * scale_of(&s.control_points());
            for (a, b) in t.control_points().iter().zip(t2.control_points()) {
                prop_assert!((*a - b).norm() <= tol);
            }
        }
    }
}
