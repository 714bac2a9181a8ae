//! Point inversion on a curve: [`CurveProjector`] and [`project_point_to_curve`].

use super::sampling::{intervals_by_turning, sample_params_by_span};
use super::surface::Seed;
use super::MAX_HALVINGS;
use super::{abs_tolerance, held_at_bound, step_1d, tangential, CurveProjection, ProjectionOptions};
use crate::basis::{ders_basis_funs, BasisRow};
use crate::knots::MAX_DEGREE;
use crate::{NurbsCurve, Vec3};

/// `C(u)`, `C'(u)`, `C''(u)` without allocation (A3.2 on the homogeneous curve, then A4.2).
pub(super) fn curve_ders2(c: &NurbsCurve, u: f64) -> [Vec3; 3] {
    let k = c.knots();
    let u = k.clamp(u);
    let p = c.degree();
    let span = k.find_span(u);
    let mut ders: [BasisRow; 3] = [[0.0; MAX_DEGREE + 1]; 3];
    ders_basis_funs(k.as_slice(), span, u, p, 2, &mut ders);
    let cw = &c.homogeneous()[span - p..=span];
    let mut a = [[0.0f64; 4]; 3];
    for (k, row) in ders.iter().enumerate() {
        for (j, h) in cw.iter().enumerate() {
            for t in 0..4 {
                a[k][t] += row[j] * h[t];
            }
        }
    }
    let xyz = |h: [f64; 4]| Vec3::new(h[0], h[1], h[2]);
    let w0 = a[0][3];
    let c0 = xyz(a[0]) / w0;
    let c1 = (xyz(a[1]) - c0 * a[1][3]) / w0;
    let c2 = (xyz(a[2]) - c1 * (2.0 * a[1][3]) - c0 * a[2][3]) / w0;
    [c0, c1, c2]
}

/// Projects points onto one curve; the one-dimensional counterpart of [`SurfaceProjector`](crate::SurfaceProjector):
/// samples (point, first and second derivatives) per knot span as set by
/// [`ProjectionOptions::grid`], a bounding sphere per span, and Newton on
/// `g(u) = C'(u) . (C(u) - P)` (The NURBS Book eq. 6.3-6.4) from the best few nodes nearer than
/// their neighbours, intervals where `g` turns from negative to positive (at their ends or in
/// the cubic Hermite interpolant of `g` and `g'`), and end points where `g` points out of the
/// domain, with the same safeguards.
#[derive(Clone, Debug)]
pub struct CurveProjector<'a> {
    curve: &'a NurbsCurve,
    options: ProjectionOptions,
    eps: f64,
    us: Vec<f64>,
    /// `[C(u), C'(u), C''(u)]` at `us`.
    samples: Vec<[Vec3; 3]>,
    /// Index of each span's first sample.
    starts: Vec<usize>,
    /// Per span: centre node (a curve point) and radius of a sphere holding the span.
    spans: Vec<(Vec3, f64)>,
    /// Largest coordinate magnitude of the control polygon (scale of evaluation round-off).
    magnitude: f64,
}

impl<'a> CurveProjector<'a> {
    /// Sample `curve` and prepare the span bounds.
    pub fn new(curve: &'a NurbsCurve, options: ProjectionOptions) -> Self {
        let base = 4 * options.grid.max(curve.degree()).max(1);
        let br = curve.knots().span_breaks();
        let counts = intervals_by_turning(&br, base, |u| curve_ders2(curve, u)[1]);
        let (us, starts, counts) = sample_params_by_span(&br, &counts, (false, false));
        let samples: Vec<[Vec3; 3]> = us.iter().map(|&u| curve_ders2(curve, u)).collect();
        let pts = curve.control_points();
        let (mut lo, mut hi) = (pts[0], pts[0]);
        for p in &pts {
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        let eps = abs_tolerance(&options, (hi - lo).norm());
        let spans = br
            .windows(2)
            .enumerate()
            .map(|(i, w)| {
                let center = samples[starts[i] + counts[i] / 2][0];
                let f = 2 * counts[i];
                let fine: Vec<Vec3> = (0..=f)
                    .map(|a| curve.point(if a == f { w[1] } else { w[0] + (w[1] - w[0]) * a as f64 / f as f64 }))
                    .collect();
                let far = fine.iter().map(|&p| (p - center).norm()).fold(0.0, f64::max);
                let sag =
                    (1..f).step_by(2).map(|a| (fine[a] - (fine[a - 1] + fine[a + 1]) * 0.5).norm()).fold(0.0, f64::max);
                (center, far + sag + eps)
            })
            .collect();
        let magnitude = lo.norm().max(hi.norm());
        CurveProjector { curve, options, eps, us, samples, starts, spans, magnitude }
    }

    /// The closest point of the curve to `q`. For a finite `q` every field is finite.
    pub fn project(&self, q: Vec3) -> CurveProjection {
        let u0 = self.us[0];
        if !q.is_finite() {
            let point = self.curve.point(u0);
            return CurveProjection { u: u0, point, distance: (point - q).norm(), iterations: 0, converged: false };
        }
        let upper = self.spans.iter().map(|(c, _)| (q - *c).norm()).fold(f64::INFINITY, f64::min);
        // Per node: |C - q|^2, g = C' . (C - q) and g' = |C'|^2 + C'' . (C - q).
        let vals: Vec<(f64, f64, f64)> = self
            .samples
            .iter()
            .map(|&[p, t, t2]| {
                let r = p - q;
                (r.norm_squared(), t.dot(r), t.norm_squared() + t2.dot(r))
            })
            .collect();
        let n = vals.len();
        let us = &self.us;
        let bound = |s: usize| (q - self.spans[s].0).norm() - self.spans[s].1;
        let span_of = |i: usize| self.starts.partition_point(|&st| st <= i).saturating_sub(1);
        let mut seeds: Vec<Seed> = Vec::new();
        for (i, &(d2, g, h)) in vals.iter().enumerate() {
            let left_ok = i == 0 || vals[i - 1].0 > d2;
            let right_ok = i + 1 == n || vals[i + 1].0 >= d2;
            let end_held = (i == 0 && g >= 0.0) || (i + 1 == n && g <= 0.0);
            if (left_ok && right_ok) || end_held {
                // A node on a break belongs to two spans: take the lower bound. A held end
                // stands for itself only, not for the interval beside it.
                let lower = bound(span_of(i)).min(bound(span_of(i.saturating_sub(1))));
                let range = if end_held {
                    [us[i], us[i], 0.0, 0.0]
                } else {
                    [us[i.saturating_sub(1)], us[(i + 1).min(n - 1)], 0.0, 0.0]
                };
                seeds.push(Seed { d2, u: us[i], v: 0.0, range, lower });
            }
            // g turns from negative to positive inside the interval: seen at its ends, or in the
            // cubic Hermite interpolant of g, g' (a minimum and a maximum both in one interval).
            if i + 1 < n {
                let (g1, h1) = (vals[i + 1].1, vals[i + 1].2);
                if let Some(t) = hermite_turn(g, h, g1, h1, us[i + 1] - us[i]) {
                    let range = [us[i], us[i + 1], 0.0, 0.0];
                    let u = us[i] + t * (us[i + 1] - us[i]);
                    seeds.push(Seed { d2: d2.min(vals[i + 1].0), u, v: 0.0, range, lower: bound(span_of(i)) });
                }
            }
        }
        seeds.retain(|s| s.lower <= upper);
        seeds.sort_unstable_by(|x, y| x.d2.total_cmp(&y.d2));
        let mut best: Option<CurveProjection> = None;
        let mut feet: Vec<f64> = Vec::new();
        let mut runs = 0;
        for seed in &seeds {
            if runs >= self.options.candidates.max(1) {
                break;
            }
            if matches!(&best, Some(bp) if seed.lower >= bp.distance) {
                continue;
            }
            if feet.iter().any(|&u| seed.covers(u, 0.0)) {
                continue;
            }
            runs += 1;
            let res = self.refine(q, seed.u);
            feet.push(res.u);
            if !matches!(&best, Some(bp) if bp.distance <= res.distance) {
                best = Some(res);
            }
        }
        best.unwrap_or_else(|| self.refine(q, u0))
    }

    /// Safeguarded one-dimensional Newton iteration from `u`.
    pub(super) fn refine(&self, q: Vec3, u: f64) -> CurveProjection {
        let (ua, ub) = self.curve.domain();
        let eps = self.eps;
        let mut u = u.clamp(ua, ub);
        let mut d = curve_ders2(self.curve, u);
        let mut r = d[0] - q;
        let mut f = r.norm_squared();
        let mut converged = false;
        let mut iterations = 0;
        'newton: while iterations < self.options.max_iterations {
            if f.sqrt() <= eps {
                converged = true;
                break;
            }
            let g = d[1].dot(r);
            let gg = d[1].norm_squared();
            if held_at_bound(u, ua, ub, g) || g * g <= eps * eps * gg {
                converged = true;
                break;
            }
            iterations += 1;
            let du = step_1d(gg + r.dot(d[2]), gg, g);
            let res0 = tangential(d[1], r, false);
            let mut alpha = 1.0;
            for _ in 0..MAX_HALVINGS {
                let nu = (u + alpha * du).clamp(ua, ub);
                let moved = (d[1] * (nu - u)).norm();
                let nd = curve_ders2(self.curve, nu);
                let nr = nd[0] - q;
                let nf = nr.norm_squared();
                // As for surfaces: within the rounding noise of f, the residual decides.
                let noise = 16.0 * f64::EPSILON * (nf.sqrt() * self.magnitude + nf);
                let flat = nf <= f + noise && tangential(nd[1], nr, false) < res0;
                if nf < f || flat {
                    (u, d, r, f) = (nu, nd, nr, nf);
                    if moved <= eps {
                        converged = true;
                        break 'newton;
                    }
                    continue 'newton;
                }
                if moved <= eps {
                    converged = true;
                    break 'newton;
                }
                alpha *= 0.5;
            }
            break;
        }
        CurveProjection { u, point: d[0], distance: f.sqrt(), iterations, converged }
    }
}

/// Where in `[0, 1]` the cubic Hermite interpolant of `g` (values `g0`, `g1`, derivatives `h0`,
/// `h1` per unit parameter over an interval of width `w`) first turns from negative to positive,
/// checked at 8 sub-intervals; `None` if it does not.
pub(super) fn hermite_turn(g0: f64, h0: f64, g1: f64, h1: f64, w: f64) -> Option<f64> {
    const STEPS: usize = 8;
    let (m0, m1) = (h0 * w, h1 * w);
    let p = |t: f64| {
        let (t2, t3) = (t * t, t * t * t);
        (2.0 * t3 - 3.0 * t2 + 1.0) * g0 + (t3 - 2.0 * t2 + t) * m0 + (-2.0 * t3 + 3.0 * t2) * g1 + (t3 - t2) * m1
    };
    let mut prev = g0;
    for k in 1..=STEPS {
        let t = k as f64 / STEPS as f64;
        let cur = if k == STEPS { g1 } else { p(t) };
        if prev < 0.0 && cur > 0.0 {
            return Some(t - 0.5 / STEPS as f64);
        }
        prev = cur;
    }
    None
}

/// The closest point of `curve` to `q` (builds a [`CurveProjector`]; keep one instead when
/// projecting many points onto the same curve).
///
/// ```
/// use nurbs::{project_point_to_curve, KnotVector, NurbsCurve, ProjectionOptions, Vec3};
/// // The quarter unit circle: the foot of a point is on its ray from the centre.
/// let k = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0])?;
/// let p = [Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 0.0)];
/// let arc = NurbsCurve::try_new(k, &p, Some(&[1.0, std::f64::consts::FRAC_1_SQRT_2, 1.0]))?;
/// let q = Vec3::new(1.5, 2.0, 0.0);
/// let foot = project_point_to_curve(&arc, q, &ProjectionOptions::default());
/// assert!(foot.converged);
/// assert!(foot.point.distance(Vec3::new(0.6, 0.8, 0.0)) < 1e-10);
/// assert!((foot.distance - 1.5).abs() < 1e-10);
/// # Ok::<(), nurbs::NurbsError>(())
/// ```
pub fn project_point_to_curve(curve: &NurbsCurve, q: Vec3, opts: &ProjectionOptions) -> CurveProjection {
    CurveProjector::new(curve, *opts).project(q)
}
