//! Drawn curve pieces in drawing coordinates, and their flattening into polylines.
//!
//! The rest of this module's documentation is on [`Segment`], where the library's users read it.

use std::f64::consts::PI;

/// A point or vector of the drawing plane, drawing units.
pub type P2 = [f64; 2];

/// Halvings of one starting interval in [`Segment::flatten`]: at most 2^14 chords per
/// interval, far more than any drawn station needs at a tolerance of a millionth of the sheet.
pub const MAX_DEPTH: u32 = 14;

/// An affine map of the plane, `(x, y) -> (a x + c y + e, b x + d y + f)` (the SVG
/// `matrix(a b c d e f)` order).
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Affine {
    pub a: f64,
    pub b: f64,
    pub c: f64,
    pub d: f64,
    pub e: f64,
    pub f: f64,
}

impl Affine {
    /// The identity.
    pub const IDENTITY: Affine = Affine { a: 1.0, b: 0.0, c: 0.0, d: 1.0, e: 0.0, f: 0.0 };

    /// The image of point `p`.
    pub fn apply(&self, p: P2) -> P2 {
        [self.a * p[0] + self.c * p[1] + self.e, self.b * p[0] + self.d * p[1] + self.f]
    }

    /// The image of vector `v` (no translation).
    pub fn vector(&self, v: P2) -> P2 {
        [self.a * v[0] + self.c * v[1], self.b * v[0] + self.d * v[1]]
    }

    /// `self ∘ inner`: `inner` applied first (an SVG child's transform inside its parent's).
    pub fn compose(&self, inner: &Affine) -> Affine {
        let s = self;
        Affine {
            a: s.a * inner.a + s.c * inner.b,
            b: s.b * inner.a + s.d * inner.b,
            c: s.a * inner.c + s.c * inner.d,
            d: s.b * inner.c + s.d * inner.d,
            e: s.a * inner.e + s.c * inner.f + s.e,
            f: s.b * inner.e + s.d * inner.f + s.f,
        }
    }

    /// True when every coefficient is finite.
    pub fn is_finite(&self) -> bool {
        [self.a, self.b, self.c, self.d, self.e, self.f].iter().all(|v| v.is_finite())
    }
}

/// A rational B-spline curve of the plane with any (not necessarily clamped) knot vector:
/// `C(t) = sum N_i,p(t) w_i P_i / sum N_i,p(t) w_i` on `[t_p, t_n]`, `n` control points.
#[derive(Clone, Debug, PartialEq)]
pub struct Spline {
    degree: usize,
    knots: Vec<f64>,
    /// Homogeneous control points `(w x, w y, w)`.
    cw: Vec<[f64; 3]>,
}

impl Spline {
    /// Validate and build.
    ///
    /// # Errors
    /// A sentence saying what is wrong (the DXF reader adds the place): degree 0, a knot count
    /// other than control points + degree + 1, knots that decrease or are not finite, an empty
    /// domain, or a weight that is not finite and positive.
    pub fn try_new(degree: usize, knots: Vec<f64>, points: &[P2], weights: Option<&[f64]>) -> Result<Self, String> {
        let n = points.len();
        if degree == 0 {
            return Err("degree 0".into());
        }
        if n <= degree {
            return Err(format!("{n} control points for degree {degree} (at least degree + 1 needed)"));
        }
        if knots.len() != n + degree + 1 {
            return Err(format!(
                "{} knots for {n} control points of degree {degree} (control points + degree + 1 = {} needed)",
                knots.len(),
                n + degree + 1
            ));
        }
        if let Some(k) = knots.iter().position(|k| !k.is_finite()) {
            return Err(format!("knot {} is not finite", k + 1));
        }
        if let Some(k) = knots.windows(2).position(|w| w[1] < w[0]) {
            return Err(format!("knot {} = {} is less than knot {} = {}", k + 2, knots[k + 1], k + 1, knots[k]));
        }
        if !(knots[n] > knots[degree]) {
            return Err(format!("empty parameter range [{}, {}]", knots[degree], knots[n]));
        }
        let w = match weights {
            Some(w) if w.len() != n => return Err(format!("{} weights for {n} control points", w.len())),
            Some(w) => w.to_vec(),
            None => vec![1.0; n],
        };
        if let Some(i) = w.iter().position(|&wi| !(wi.is_finite() && wi > 0.0)) {
            return Err(format!("weight {} = {} is not a positive number", i + 1, w[i]));
        }
        if points.iter().flatten().any(|c| !c.is_finite()) {
            return Err("a control point is not finite".into());
        }
        let cw = points.iter().zip(&w).map(|(p, &wi)| [wi * p[0], wi * p[1], wi]).collect();
        Ok(Spline { degree, knots, cw })
    }

    /// The parameter range `[t_p, t_n]`.
    pub fn domain(&self) -> (f64, f64) {
        (self.knots[self.degree], self.knots[self.cw.len()])
    }

    /// The distinct knots within the domain, ends included: where the pieces of the spline
    /// meet.
    pub fn breaks(&self) -> Vec<f64> {
        let (a, b) = self.domain();
        let mut out: Vec<f64> = Vec::new();
        for &k in &self.knots[self.degree..=self.cw.len()] {
            if k >= a && k <= b && out.last() != Some(&k) {
                out.push(k);
            }
        }
        out
    }

    /// The control points (Euclidean).
    pub fn control_points(&self) -> Vec<P2> {
        self.cw.iter().map(|c| [c[0] / c[2], c[1] / c[2]]).collect()
    }

    /// `C(t)` by de Boor's algorithm on the homogeneous points; `t` is clamped to the domain.
    pub fn point(&self, t: f64) -> P2 {
        let (p, n) = (self.degree, self.cw.len());
        let (a, b) = self.domain();
        let t = t.clamp(a, b);
        // The span k, p <= k <= n - 1, with t_k <= t < t_k+1; at the end of the domain the
        // last non-empty span.
        let mut k = p;
        for j in p..n {
            if self.knots[j] <= t && self.knots[j] < self.knots[j + 1] {
                k = j;
            }
        }
        let mut d: Vec<[f64; 3]> = (0..=p).map(|j| self.cw[j + k - p]).collect();
        for r in 1..=p {
            for j in (r..=p).rev() {
                let lo = self.knots[j + k - p];
                let hi = self.knots[j + 1 + k - r];
                let alpha = if hi > lo { (t - lo) / (hi - lo) } else { 0.0 };
                for c in 0..3 {
                    d[j][c] = (1.0 - alpha) * d[j - 1][c] + alpha * d[j][c];
                }
            }
        }
        [d[p][0] / d[p][2], d[p][1] / d[p][2]]
    }

    fn transformed(&self, m: &Affine) -> Spline {
        let cw = self
            .cw
            .iter()
            .map(|c| {
                let q = m.apply([c[0] / c[2], c[1] / c[2]]);
                [q[0] * c[2], q[1] * c[2], c[2]]
            })
            .collect();
        Spline { degree: self.degree, knots: self.knots.clone(), cw }
    }
}

/// One drawn piece of a curve, in drawing coordinates.
///
/// A drawn piece ([`Segment`]) is one of
///
/// - a straight line;
/// - an elliptical arc `p(t) = c + u cos t + v sin t`, `t` from `t0` to `t1`: circles, DXF
///   `ARC`/`CIRCLE`/`ELLIPSE`, polyline bulges and SVG `A` commands. `u` and `v` are conjugate
///   semi-diameters, so the form survives any affine map (SVG transforms, the mirrored DXF
///   object coordinate system);
/// - a Bézier curve of any degree (SVG `C`, `S`, `Q`, `T`), evaluated by de Casteljau's
///   algorithm;
/// - a rational B-spline with any knot vector ([`Spline`], DXF `SPLINE`), evaluated by de Boor's
///   algorithm in homogeneous coordinates (The NURBS Book, 2nd ed., section 4.2 and the
///   algorithm of section 3.2 lifted to 4-D).
///
/// Flattening samples each piece at points *on* the curve: the chord between two neighbouring
/// samples is accepted when the curve at 1/4, 1/2 and 3/4 of its parameter interval lies
/// within the flatness tolerance of that chord, otherwise the interval is halved (at most
/// 14 times, `MAX_DEPTH`). Every returned point is a point of the drawn curve, to round-off.
#[derive(Clone, Debug, PartialEq)]
pub enum Segment {
    /// A straight line from the first point to the second.
    Line(P2, P2),
    /// `c + u cos t + v sin t` for `t` from `t0` to `t1` (either direction).
    Arc { c: P2, u: P2, v: P2, t0: f64, t1: f64 },
    /// A Bézier curve with these control points (2 or more).
    Bezier(Vec<P2>),
    /// A rational B-spline.
    Spline(Spline),
}

impl Segment {
    /// The circular arc of a polyline vertex with bulge `b` from `p1` to `p2` (DXF: the bulge
    /// is `tan(theta / 4)`, `theta` the included angle, positive counter-clockwise). The centre
    /// lies on the chord's left normal `n` at `c = m + n (L / 2) / tan(theta / 2)` from the
    /// chord's midpoint `m`, `L` the chord length. A straight line when `b` is 0 or the ends
    /// coincide.
    pub fn bulge(p1: P2, p2: P2, b: f64) -> Segment {
        let d = [p2[0] - p1[0], p2[1] - p1[1]];
        let len = d[0].hypot(d[1]);
        if b == 0.0 || !b.is_finite() || len == 0.0 {
            return Segment::Line(p1, p2);
        }
        let theta = 4.0 * b.atan();
        let n = [-d[1] / len, d[0] / len];
        let h = 0.5 * len / (0.5 * theta).tan();
        let c = [0.5 * (p1[0] + p2[0]) + n[0] * h, 0.5 * (p1[1] + p2[1]) + n[1] * h];
        let r = (p1[0] - c[0]).hypot(p1[1] - c[1]);
        let t0 = (p1[1] - c[1]).atan2(p1[0] - c[0]);
        Segment::Arc { c, u: [r, 0.0], v: [0.0, r], t0, t1: t0 + theta }
    }

    /// The SVG elliptical arc from `p1` to `p2` with radii `rx`, `ry`, x axis rotated by `phi`
    /// degrees and the two flags, by the endpoint-to-centre conversion of SVG 1.1 appendix
    /// F.6.5, radii scaled up when too small (F.6.6). `None` when the ends coincide (the arc
    /// draws nothing); a line when a radius is 0.
    pub fn svg_arc(p1: P2, p2: P2, rx: f64, ry: f64, phi: f64, large: bool, sweep: bool) -> Option<Segment> {
        if p1 == p2 {
            return None;
        }
        let (mut rx, mut ry) = (rx.abs(), ry.abs());
        if rx == 0.0 || ry == 0.0 {
            return Some(Segment::Line(p1, p2));
        }
        let (s, c) = phi.to_radians().sin_cos();
        let (hx, hy) = (0.5 * (p1[0] - p2[0]), 0.5 * (p1[1] - p2[1]));
        let x1 = c * hx + s * hy;
        let y1 = -s * hx + c * hy;
        let lambda = (x1 * x1) / (rx * rx) + (y1 * y1) / (ry * ry);
        if lambda > 1.0 {
            rx *= lambda.sqrt();
            ry *= lambda.sqrt();
        }
        let num = rx * rx * ry * ry - rx * rx * y1 * y1 - ry * ry * x1 * x1;
        let den = rx * rx * y1 * y1 + ry * ry * x1 * x1;
        let mut coef = if den > 0.0 { (num / den).max(0.0).sqrt() } else { 0.0 };
        if large == sweep {
            coef = -coef;
        }
        let (cx1, cy1) = (coef * rx * y1 / ry, -coef * ry * x1 / rx);
        let centre = [c * cx1 - s * cy1 + 0.5 * (p1[0] + p2[0]), s * cx1 + c * cy1 + 0.5 * (p1[1] + p2[1])];
        let angle = |ux: f64, uy: f64| uy.atan2(ux);
        let t0 = angle((x1 - cx1) / rx, (y1 - cy1) / ry);
        let t_end = angle((-x1 - cx1) / rx, (-y1 - cy1) / ry);
        let mut dt = t_end - t0;
        if sweep && dt < 0.0 {
            dt += 2.0 * PI;
        } else if !sweep && dt > 0.0 {
            dt -= 2.0 * PI;
        }
        Some(Segment::Arc { c: centre, u: [rx * c, rx * s], v: [-ry * s, ry * c], t0, t1: t0 + dt })
    }

    /// The point at parameter `t` (for lines and Béziers `t` in [0, 1]).
    fn eval(&self, t: f64) -> P2 {
        match self {
            Segment::Line(a, b) => [a[0] + (b[0] - a[0]) * t, a[1] + (b[1] - a[1]) * t],
            Segment::Arc { c, u, v, .. } => {
                let (s, co) = t.sin_cos();
                [c[0] + u[0] * co + v[0] * s, c[1] + u[1] * co + v[1] * s]
            }
            Segment::Bezier(p) => de_casteljau(p, t),
            Segment::Spline(s) => s.point(t),
        }
    }

    /// The starting parameter intervals, before adaptive halving.
    fn intervals(&self) -> Vec<f64> {
        let even = |a: f64, b: f64, n: usize| (0..=n).map(|i| a + (b - a) * i as f64 / n as f64).collect::<Vec<_>>();
        match self {
            Segment::Line(..) => vec![0.0, 1.0],
            // Eighths of a turn at most: no interval holds an inflection-free arc whose
            // middle could hide from the three test points.
            Segment::Arc { t0, t1, .. } => even(*t0, *t1, ((t1 - t0).abs() / (0.25 * PI)).ceil().max(1.0) as usize),
            Segment::Bezier(p) => even(0.0, 1.0, p.len().saturating_sub(1).max(1)),
            Segment::Spline(s) => {
                let b = s.breaks();
                let mut out = vec![b[0]];
                for w in b.windows(2) {
                    out.push(0.5 * (w[0] + w[1]));
                    out.push(w[1]);
                }
                out
            }
        }
    }

    /// The first point.
    pub fn start(&self) -> P2 {
        self.eval(self.intervals()[0])
    }

    /// The last point.
    pub fn end(&self) -> P2 {
        let i = self.intervals();
        self.eval(i[i.len() - 1])
    }

    /// Points bounding the piece: end points and control points (every piece lies in their
    /// convex hull, arcs in the box of `c ± (|u| + |v|)`).
    pub fn hull_points(&self) -> Vec<P2> {
        match self {
            Segment::Line(a, b) => vec![*a, *b],
            Segment::Arc { c, u, v, .. } => {
                let r = u[0].hypot(u[1]) + v[0].hypot(v[1]);
                vec![[c[0] - r, c[1] - r], [c[0] + r, c[1] + r]]
            }
            Segment::Bezier(p) => p.clone(),
            Segment::Spline(s) => s.control_points(),
        }
    }

    /// The piece mapped by `m`.
    pub fn transformed(&self, m: &Affine) -> Segment {
        match self {
            Segment::Line(a, b) => Segment::Line(m.apply(*a), m.apply(*b)),
            Segment::Arc { c, u, v, t0, t1 } => {
                Segment::Arc { c: m.apply(*c), u: m.vector(*u), v: m.vector(*v), t0: *t0, t1: *t1 }
            }
            Segment::Bezier(p) => Segment::Bezier(p.iter().map(|q| m.apply(*q)).collect()),
            Segment::Spline(s) => Segment::Spline(s.transformed(m)),
        }
    }

    /// Append points of the piece to `out`, from its start to its end, such that the curve
    /// between neighbouring points stays within about `tol` of their chord (see the module
    /// docs). The start is appended too.
    pub fn flatten(&self, tol: f64, out: &mut Vec<P2>) {
        if let Segment::Line(a, b) = self {
            out.extend([*a, *b]);
            return;
        }
        let ts = self.intervals();
        let tol = if tol > 0.0 && tol.is_finite() { tol } else { f64::MIN_POSITIVE };
        let mut prev = self.eval(ts[0]);
        out.push(prev);
        for w in ts.windows(2) {
            let next = self.eval(w[1]);
            self.refine(w[0], w[1], prev, next, tol, MAX_DEPTH, out);
            prev = next;
        }
    }

    #[allow(clippy::too_many_arguments)]
    fn refine(&self, a: f64, b: f64, pa: P2, pb: P2, tol: f64, depth: u32, out: &mut Vec<P2>) {
        let m = 0.5 * (a + b);
        let pm = self.eval(m);
        let flat =
            [0.25, 0.75].iter().map(|s| self.eval(a + s * (b - a))).chain([pm]).all(|q| seg_dist(q, pa, pb) <= tol);
        if flat || depth == 0 {
            out.push(pb);
        } else {
            self.refine(a, m, pa, pm, tol, depth - 1, out);
            self.refine(m, b, pm, pb, tol, depth - 1, out);
        }
    }
}

/// A Bézier curve's point by de Casteljau's algorithm (The NURBS Book A1.5).
fn de_casteljau(p: &[P2], t: f64) -> P2 {
    let mut q = p.to_vec();
    for k in 1..q.len() {
        for i in 0..q.len() - k {
            q[i] = [(1.0 - t) * q[i][0] + t * q[i + 1][0], (1.0 - t) * q[i][1] + t * q[i + 1][1]];
        }
    }
    q.first().copied().unwrap_or([0.0, 0.0])
}

/// Distance from `q` to the segment `a b`.
pub fn seg_dist(q: P2, a: P2, b: P2) -> f64 {
    let d = [b[0] - a[0], b[1] - a[1]];
    let len2 = d[0] * d[0] + d[1] * d[1];
    let t = if len2 > 0.0 { (((q[0] - a[0]) * d[0] + (q[1] - a[1]) * d[1]) / len2).clamp(0.0, 1.0) } else { 0.0 };
    (q[0] - a[0] - t * d[0]).hypot(q[1] - a[1] - t * d[1])
}

/// Distance from `q` to the polyline `p` (infinite for an empty one).
pub fn polyline_dist(q: P2, p: &[P2]) -> f64 {
    match p {
        [] => f64::INFINITY,
        [a] => (q[0] - a[0]).hypot(q[1] - a[1]),
        _ => p.windows(2).map(|w| seg_dist(q, w[0], w[1])).fold(f64::INFINITY, f64::min),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dist(a: P2, b: P2) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// Bulge 1 is a half circle, counter-clockwise; -1 the other half. Every flattened point
    /// lies on the circle to round-off (1e-12 of the radius 2).
    #[test]
    fn bulge_one_is_a_half_circle() {
        for b in [1.0, -1.0] {
            let s = Segment::bulge([2.0, 0.0], [-2.0, 0.0], b);
            let mut pts = Vec::new();
            s.flatten(1e-4, &mut pts);
            assert!(dist(pts[0], [2.0, 0.0]) < 1e-12 && dist(*pts.last().expect("points"), [-2.0, 0.0]) < 1e-12);
            for p in &pts {
                assert!((p[0].hypot(p[1]) - 2.0).abs() < 1e-12, "{p:?}");
            }
            // Counter-clockwise (b > 0) from angle 0 to angle pi passes through (0, 2), the
            // clockwise half through (0, -2).
            let lowest = pts.iter().map(|p| p[1]).fold(f64::INFINITY, f64::min);
            let highest = pts.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max);
            if b > 0.0 {
                assert!((highest - 2.0).abs() < 1e-12 && lowest > -1e-12, "ccw half through the top");
            } else {
                assert!((lowest + 2.0).abs() < 1e-12 && highest < 1e-12, "cw half through the bottom");
            }
        }
    }

    /// The chord sagitta of a circle of radius r over angle dt is r (1 - cos(dt / 2)); the
    /// flattening keeps it below the tolerance, and does not oversample by more than a factor
    /// of 4 over the ideal uniform count (halving overshoots by at most 2 per level).
    #[test]
    fn flattening_meets_the_tolerance() {
        let r = 50.0;
        let tol = 1e-3;
        let s = Segment::Arc { c: [1.0, 1.0], u: [r, 0.0], v: [0.0, r], t0: 0.0, t1: 0.5 * PI };
        let mut pts = Vec::new();
        s.flatten(tol, &mut pts);
        for w in pts.windows(2) {
            let mid = [0.5 * (w[0][0] + w[1][0]) - 1.0, 0.5 * (w[0][1] + w[1][1]) - 1.0];
            assert!(r - mid[0].hypot(mid[1]) <= tol, "sagitta {}", r - mid[0].hypot(mid[1]));
        }
        let ideal = (0.5 * PI / (2.0 * (1.0 - tol / r).acos())).ceil() as usize;
        assert!(pts.len() - 1 <= 4 * ideal, "{} chords for an ideal {ideal}", pts.len() - 1);
    }

    /// SVG 1.1 F.6.5 on a known case: the quarter of the circle of radius 10 about the origin
    /// from (10, 0) to (0, 10), small arc, positive sweep, centre back at the origin.
    #[test]
    fn svg_arc_finds_the_centre() {
        let s = Segment::svg_arc([10.0, 0.0], [0.0, 10.0], 10.0, 10.0, 0.0, false, true).expect("an arc");
        let Segment::Arc { c, t0, t1, .. } = s else { panic!("an arc") };
        assert!(dist(c, [0.0, 0.0]) < 1e-12, "{c:?}");
        assert!((t1 - t0 - 0.5 * PI).abs() < 1e-12);
        // The large arc the other way round has its centre at (10, 10).
        let s = Segment::svg_arc([10.0, 0.0], [0.0, 10.0], 10.0, 10.0, 0.0, true, true).expect("an arc");
        let Segment::Arc { c, t0, t1, .. } = s else { panic!("an arc") };
        assert!(dist(c, [10.0, 10.0]) < 1e-12, "{c:?}");
        assert!((t1 - t0 - 1.5 * PI).abs() < 1e-12);
        // Radii too small are scaled up: radius 1 between points 20 apart is a half circle of 10.
        let s = Segment::svg_arc([10.0, 0.0], [-10.0, 0.0], 1.0, 1.0, 0.0, false, true).expect("an arc");
        assert!(dist(s.eval(0.5 * (s.intervals()[0] + *s.intervals().last().expect("ts"))), [0.0, 10.0]) < 1e-9);
        assert!(Segment::svg_arc([1.0, 1.0], [1.0, 1.0], 3.0, 3.0, 0.0, false, false).is_none());
    }

    /// A rational quadratic with weights 1, 1/sqrt 2, 1 is a quarter circle (The NURBS Book
    /// example 7.1); an unclamped uniform cubic B-spline starts at (P0 + 4 P1 + P2) / 6.
    #[test]
    fn splines_evaluate_like_the_book() {
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let s = Spline::try_new(
            2,
            vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0],
            &[[1.0, 0.0], [1.0, 1.0], [0.0, 1.0]],
            Some(&[1.0, w, 1.0]),
        )
        .expect("valid");
        for i in 0..=20 {
            let p = s.point(f64::from(i) / 20.0);
            assert!((p[0].hypot(p[1]) - 1.0).abs() < 1e-14, "{p:?}");
        }
        let pts = [[0.0, 0.0], [6.0, 0.0], [6.0, 6.0], [0.0, 6.0]];
        let u = Spline::try_new(3, (0..8).map(f64::from).collect(), &pts, None).expect("valid");
        assert_eq!(u.domain(), (3.0, 4.0));
        let p = u.point(3.0);
        assert!(dist(p, [5.0, 1.0]) < 1e-14, "{p:?}");
        assert!(Spline::try_new(2, vec![0.0, 0.0, 1.0, 1.0], &pts[..3], None).is_err());
        assert!(Spline::try_new(2, vec![0.0, 0.0, 0.0, 2.0, 1.0, 1.0], &pts[..3], None).is_err());
        assert!(Spline::try_new(1, vec![0.0, 0.0, 1.0, 1.0], &pts[..2], Some(&[1.0, 0.0])).is_err());
    }

    /// Affine maps compose like matrices: the composite maps a point as the two in turn.
    #[test]
    fn affine_composition_order() {
        let t = Affine { e: 5.0, f: -2.0, ..Affine::IDENTITY };
        let s = Affine { a: 2.0, d: -1.0, ..Affine::IDENTITY };
        let p = [1.5, 3.0];
        assert_eq!(t.compose(&s).apply(p), t.apply(s.apply(p)));
        assert_eq!(s.compose(&t).apply(p), s.apply(t.apply(p)));
        assert_ne!(t.compose(&s).apply(p), s.compose(&t).apply(p));
    }

    #[test]
    fn distances_to_segments() {
        assert_eq!(seg_dist([0.0, 1.0], [-1.0, 0.0], [1.0, 0.0]), 1.0);
        assert_eq!(seg_dist([3.0, 4.0], [0.0, 0.0], [0.0, 0.0]), 5.0);
        assert_eq!(seg_dist([4.0, 0.0], [0.0, 0.0], [1.0, 0.0]), 3.0);
        assert_eq!(polyline_dist([0.0, 0.0], &[]), f64::INFINITY);
    }
}
