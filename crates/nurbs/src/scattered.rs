//! Evaluation at many scattered parameter pairs: [`PointEvaluator`], for callers that evaluate
//! one surface at thousands to millions of unrelated `(u, v)` (the Python bindings' vectorised
//! `evaluate`).
//!
//! A4.3 as [`NurbsSurface::point`], with two savings that do not depend on the points:
//! A2.2's denominators `right[r+1] + left[j-r]` are knot differences
//! `u_{span+r+1} - u_{span+1-j+r}`, so their reciprocals are computed once per span (a
//! multiplication per term instead of a division), and the homogeneous point is divided by
//! its weight through one reciprocal; the span is counted without branches; for degrees 1 to
//! 3 the loops are specialised to the degree. The values agree with [`NurbsSurface::point`] to rounding (a few ulps of the
//! control net's size, tested), not bit for bit.

use crate::{KnotVector, NurbsSurface, Vec3};

/// Above this many spans the span is found by binary search.
const MANY_SPANS: usize = 48;

/// One parameter direction: its knots and, for each span `p..=n`, the reciprocals of A2.2's
/// denominators in the order the algorithm uses them (`p (p + 1) / 2` per span).
struct Direction<'a> {
    knots: &'a KnotVector,
    inverse: Vec<f64>,
}

impl<'a> Direction<'a> {
    fn new(knots: &'a KnotVector) -> Self {
        let p = knots.degree();
        let k = knots.as_slice();
        let n = knots.num_basis() - 1;
        let mut inverse = Vec::with_capacity((n - p + 1) * p * (p + 1) / 2);
        for span in p..=n {
            for j in 1..=p {
                for r in 0..j {
                    let d = k[span + r + 1] - k[span + 1 - j + r];
                    // An empty span is never used (find_span skips it); keep its entries finite.
                    inverse.push(if d > 0.0 { 1.0 / d } else { 0.0 });
                }
            }
        }
        Direction { knots, inverse }
    }

    /// The span of `t` (clamped to the domain) and its `N = p + 1` non-zero basis functions.
    #[inline(always)]
    fn basis<const N: usize>(&self, t: f64) -> (usize, [f64; N]) {
        let p = N - 1;
        let t = self.knots.clamp(t);
        let k = self.knots.as_slice();
        // The last span start u_i <= t, as find_span finds it; counted without branches where
        // the spans are few (a binary search mispredicts about half its steps on scattered
        // parameters), searched where they are many.
        let n = k.len() - N - 1;
        let span = if n - p <= MANY_SPANS {
            p + k[p + 1..=n].iter().map(|&ki| usize::from(ki <= t)).sum::<usize>()
        } else {
            self.knots.find_span(t)
        };
        let m = p * (p + 1) / 2;
        let inverse = &self.inverse[(span - p) * m..][..m];
        let mut out = [0.0; N];
        let mut left = [0.0; N];
        let mut right = [0.0; N];
        out[0] = 1.0;
        let mut at = 0;
        for j in 1..=p {
            left[j] = t - k[span + 1 - j];
            right[j] = k[span + j] - t;
            let mut saved = 0.0;
            for r in 0..j {
                let temp = out[r] * inverse[at];
                at += 1;
                out[r] = saved + right[r + 1] * temp;
                saved = left[j - r] * temp;
            }
            out[j] = saved;
        }
        (span, out)
    }
}

/// Evaluates one surface at many `(u, v)`; see the module docs. Parameters are clamped to
/// the domain, as by [`NurbsSurface::point`].
pub struct PointEvaluator<'a> {
    surface: &'a NurbsSurface,
    u: Direction<'a>,
    v: Direction<'a>,
    eval: fn(&PointEvaluator<'a>, f64, f64) -> Vec3,
}

impl<'a> PointEvaluator<'a> {
    /// Prepare `surface` (the reciprocals of its knot differences: a few per span).
    pub fn new(surface: &'a NurbsSurface) -> Self {
        let eval: fn(&PointEvaluator<'a>, f64, f64) -> Vec3 = match (surface.degree_u(), surface.degree_v()) {
            (1, 1) => Self::sized::<2, 2>,
            (1, 2) => Self::sized::<2, 3>,
            (1, 3) => Self::sized::<2, 4>,
            (2, 1) => Self::sized::<3, 2>,
            (2, 2) => Self::sized::<3, 3>,
            (2, 3) => Self::sized::<3, 4>,
            (3, 1) => Self::sized::<4, 2>,
            (3, 2) => Self::sized::<4, 3>,
            (3, 3) => Self::sized::<4, 4>,
            _ => |e: &PointEvaluator<'a>, u, v| e.surface.point(u, v),
        };
        PointEvaluator { surface, u: Direction::new(surface.knots_u()), v: Direction::new(surface.knots_v()), eval }
    }

    /// The point `S(u, v)`.
    #[inline]
    pub fn point(&self, u: f64, v: f64) -> Vec3 {
        (self.eval)(self, u, v)
    }

    /// A4.3 for degrees `NU - 1`, `NV - 1`.
    fn sized<const NU: usize, const NV: usize>(&self, u: f64, v: f64) -> Vec3 {
        let (su, nu) = self.u.basis::<NU>(u);
        let (sv, nv) = self.v.basis::<NV>(v);
        let (p, q) = (NU - 1, NV - 1);
        let stride = self.surface.n_v();
        let cw = self.surface.homogeneous();
        let mut h = [0.0f64; 4];
        for (k, a) in nu.iter().enumerate() {
            let row = &cw[(su - p + k) * stride + sv - q..][..NV];
            let mut t = [0.0f64; 4];
            for (b, c) in nv.iter().zip(row) {
                t[0] += b * c[0];
                t[1] += b * c[1];
                t[2] += b * c[2];
                t[3] += b * c[3];
            }
            h[0] += a * t[0];
            h[1] += a * t[1];
            h[2] += a * t[2];
            h[3] += a * t[3];
        }
        let w = 1.0 / h[3];
        Vec3::new(h[0] * w, h[1] * w, h[2] * w)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A rational surface of degrees `(p, q)` with a repeated interior knot along u (for
    /// p >= 2), control points over a 100-unit box and weights in [0.5, 2].
    fn surface(p: usize, q: usize) -> NurbsSurface {
        let mut ku = vec![0.0; p + 1];
        ku.extend(if p >= 2 { &[0.2, 0.5, 0.5, 0.7][..] } else { &[0.2, 0.5, 0.7][..] });
        ku.extend(vec![1.0; p + 1]);
        let mut kv = vec![0.0; q + 1];
        kv.extend([0.1, 0.4, 0.45, 0.9]);
        kv.extend(vec![1.0; q + 1]);
        let (ku, kv) = (KnotVector::try_new(p, ku).expect("valid"), KnotVector::try_new(q, kv).expect("valid"));
        let (nu, nv) = (ku.num_basis(), kv.num_basis());
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for i in 0..nu {
            for j in 0..nv {
                let (a, b) = (i as f64, j as f64);
                pts.push(Vec3::new(10.0 * a + (b * 1.3).sin(), 8.0 * b + (a * 0.7).cos(), (a * b * 0.37).sin() * 5.0));
                w.push(1.25 + 0.75 * (a * 0.9 + b * 0.4).sin());
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    #[test]
    fn points_agree_with_the_pointwise_evaluation_to_rounding() {
        for (p, q) in [(1, 1), (1, 3), (2, 2), (3, 1), (3, 2), (3, 3), (4, 3), (5, 5)] {
            let s = surface(p, q);
            let e = PointEvaluator::new(&s);
            let mut x = 0.271_828_f64; // any seed in (0, 1)
                                       // Every span, its ends (knots, the domain's ends), and out of the domain (clamped).
            let mut pairs: Vec<(f64, f64)> = [0.0, 0.2, 0.5, 0.7, 1.0, -0.5, 1.5]
                .iter()
                .flat_map(|&u| [0.0, 0.1, 0.4, 0.45, 0.9, 1.0, 2.0].map(|v| (u, v)))
                .collect();
            for _ in 0..2000 {
                x = (x * 997.0 + 0.1234).fract();
                let u = x;
                x = (x * 997.0 + 0.1234).fract();
                pairs.push((u, x));
            }
            for (u, v) in pairs {
                let (a, b) = (e.point(u, v), s.point(u, v));
                // The reciprocals round differently from the divisions: a few ulps of the
                // coordinates' size (100 units, ulp 1.4e-14): 1e-12 leaves a margin of 70 ulps.
                assert!((a - b).norm() <= 1e-12, "degrees ({p}, {q}) at ({u}, {v}): {a:?} vs {b:?}");
                if p > 3 || q > 3 {
                    assert_eq!(a, b, "degrees above 3 use point itself");
                }
            }
        }
    }
}
