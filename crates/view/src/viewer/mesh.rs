//! The viewer's geometry and fields: a tessellation of the surface on a parameter grid refined
//! per knot span, with normals, Gaussian and mean curvature at every vertex, and the distance
//! of every offset to the surface.

use nurbs::{split_spans, KnotVector, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use rayon::prelude::*;

use hull::Offsets;

/// How finely the surface is tessellated for the viewer.
///
/// Every knot span gets at least `per_span` segments, and more in proportion to its share of
/// the parameter domain so that the whole grid has at least `min_long` vertices along the
/// physically longer parameter direction and `min_short` along the other one (the direction
/// is chosen by the lengths of the control polygon, so a hull skinned either way round is
/// sampled alike). `max` caps the vertex count per direction (the smallest count still has one
/// vertex per knot).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Resolution {
    /// Segments per knot span, at least.
    pub per_span: usize,
    /// Vertices along the longer direction (a hull's length), at least.
    pub min_long: usize,
    /// Vertices along the shorter direction (a hull's girth), at least.
    pub min_short: usize,
    /// Vertices per direction, at most (unless there are more distinct knots than that).
    pub max: usize,
}

impl Default for Resolution {
    fn default() -> Self {
        Resolution { per_span: 8, min_long: 60, min_short: 40, max: 600 }
    }
}

/// The sampled surface: an `nu x nv` vertex grid, u-major (`i * nv + j`), with fields at every
/// vertex. A structured grid, not a triangle mesh ([`nurbs::TriMesh`]): the page makes the
/// triangles of the grid (and of the mirrored half) itself, so none are stored; its vertices
/// keep the grid's parameters for the error field and the grid's shape for the page.
#[derive(Clone, Debug)]
pub(crate) struct Mesh {
    pub nu: usize,
    pub nv: usize,
    pub params_u: Vec<f64>,
    pub params_v: Vec<f64>,
    pub positions: Vec<Vec3>,
    /// Unit normals, oriented outward (away from the hull's inside, see [`Mesh::flipped`]).
    pub normals: Vec<Vec3>,
    /// Gaussian curvature `K` (orientation-free); NaN where undefined.
    pub gaussian: Vec<f64>,
    /// Mean curvature, positive where the hull is convex (bends away from the outward normal);
    /// NaN where undefined.
    pub mean: Vec<f64>,
    /// True if the outward normal is `-(S_u x S_v)`: then the triangles' winding is reversed.
    pub flipped: bool,
}

impl Mesh {
    /// Number of triangles of one half: two per grid cell.
    pub fn triangles(&self) -> usize {
        2 * (self.nu - 1) * (self.nv - 1)
    }
}

/// The parameters at which one direction is sampled: the knot vector's span breaks (every
/// distinct knot of the domain, [`KnotVector::span_breaks`]) and `n_s` equal steps inside each
/// span `[a, b]` ([`nurbs::split_spans`]) with
/// `n_s = max(per_span, ceil((min - 1) (b - a) / (end - start)))`, the sum capped near `max`.
pub(crate) fn sample_params(knots: &KnotVector, per_span: usize, min: usize, max: usize) -> Vec<f64> {
    let breaks = knots.span_breaks();
    let (start, end) = knots.domain();
    let len = end - start;
    let spans = breaks.len() - 1;
    let counts = |per: usize, min: usize| -> Vec<usize> {
        breaks
            .windows(2)
            .map(|w| per.max((min.saturating_sub(1) as f64 * (w[1] - w[0]) / len).ceil() as usize).max(1))
            .collect()
    };
    let mut per = per_span.max(1);
    let mut n = counts(per, min);
    // Too many: lower the per-span count and the minimum together until under the cap.
    let cap = max.max(spans + 1);
    let mut min = min;
    while n.iter().sum::<usize>() + 1 > cap && (per > 1 || min > spans + 1) {
        per = (per - 1).max(1);
        min = (min * 9 / 10).max(spans + 1);
        n = counts(per, min);
    }
    split_spans(&breaks, &n)
}

/// Length of the control polygon along u (summed over the rows, averaged) and along v.
fn polygon_lengths(s: &NurbsSurface) -> (f64, f64) {
    let (nu, nv) = (s.n_u(), s.n_v());
    let mut lu = 0.0;
    for j in 0..nv {
        for i in 1..nu {
            lu += s.control_point(i, j).distance(s.control_point(i - 1, j));
        }
    }
    let mut lv = 0.0;
    for i in 0..nu {
        for j in 1..nv {
            lv += s.control_point(i, j).distance(s.control_point(i, j - 1));
        }
    }
    (lu / nv as f64, lv / nu as f64)
}

/// Tessellate `s` and evaluate its normals and curvatures at every vertex.
///
/// The outward side is the one whose normals point away from the hull's centre line, where the
/// centre line is the x axis lifted to mid-depth: the sign of
/// `sum n . (0, y, z - z_mid)` over the vertices (on a starboard half hull both the side,
/// `n ~ +y`, and the bottom, `n ~ -z`, agree). The mean curvature `H` of the kernel, positive
/// where the surface bends toward its normal `S_u x S_v`, is turned so that it is positive
/// where the hull is convex: `H_shown = -H_kernel` with the outward normal.
pub(crate) fn tessellate(s: &NurbsSurface, res: &Resolution) -> Mesh {
    let (lu, lv) = polygon_lengths(s);
    let (min_u, min_v) = if lu >= lv { (res.min_long, res.min_short) } else { (res.min_short, res.min_long) };
    let params_u = sample_params(s.knots_u(), res.per_span, min_u, res.max);
    let params_v = sample_params(s.knots_v(), res.per_span, min_v, res.max);
    let (nu, nv) = (params_u.len(), params_v.len());
    struct Sample {
        p: Vec3,
        n: Vec3,
        k: f64,
        h: f64,
    }
    let samples: Vec<Sample> = (0..nu * nv)
        .into_par_iter()
        .map(|idx| {
            let (u, v) = (params_u[idx / nv], params_v[idx % nv]);
            let d = s.derivatives(u, v);
            let curv = d.curvature().or_else(|| {
                // The curvature of a degenerate point (a collapsed stem or keel edge) as a limit.
                let (uu, vv) = s.nudged_inside(u, v, 1e-6);
                s.curvature(uu, vv)
            });
            let n = s.normal(u, v).or(curv.map(|c| c.normal)).unwrap_or(Vec3::new(0.0, 1.0, 0.0));
            let (k, h) = match curv {
                // The kernel's H refers to its own normal; re-expressed for `n` below.
                Some(c) => (c.gaussian, if c.normal.dot(n) >= 0.0 { c.mean } else { -c.mean }),
                None => (f64::NAN, f64::NAN),
            };
            Sample { p: d.point, n, k, h }
        })
        .collect();
    let (zmin, zmax) =
        samples.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), s| (a.min(s.p.z), b.max(s.p.z)));
    let zmid = 0.5 * (zmin + zmax);
    let outward: f64 = samples.iter().map(|s| s.n.dot(Vec3::new(0.0, s.p.y, s.p.z - zmid))).sum();
    let flipped = outward < 0.0;
    let sign = if flipped { -1.0 } else { 1.0 };
    Mesh {
        nu,
        nv,
        params_u,
        params_v,
        positions: samples.iter().map(|s| s.p).collect(),
        normals: samples.iter().map(|s| s.n * sign).collect(),
        gaussian: samples.iter().map(|s| s.k).collect(),
        // H along the outward normal n_out = sign n is sign H_n; convex-positive is its negative.
        mean: samples.iter().map(|s| -sign * s.h).collect(),
        flipped,
    }
}

/// Every offset with its parameters on the surface and its distance to it.
#[derive(Clone, Debug)]
pub(crate) struct OffsetErrors {
    pub points: Vec<Vec3>,
    /// Closest-point parameters, normalised to `[0, 1]^2`.
    pub uv: Vec<(f64, f64)>,
    pub distance: Vec<f64>,
}

/// Project every offset onto `s` (the same projection as [`hull::measure_fit_error`]).
pub(crate) fn offset_errors(s: &NurbsSurface, offsets: &Offsets) -> OffsetErrors {
    let projector = SurfaceProjector::new(s, ProjectionOptions::default());
    let points: Vec<Vec3> =
        offsets.sections.iter().flat_map(|sec| sec.points.iter().copied()).filter(|p| p.is_finite()).collect();
    let proj: Vec<_> = points.par_iter().map(|&q| projector.project(q)).collect();
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    OffsetErrors {
        uv: proj.iter().map(|p| ((p.u - u0) / (u1 - u0), (p.v - v0) / (v1 - v0))).collect(),
        distance: proj.iter().map(|p| p.distance).collect(),
        points,
    }
}

/// Number of nearest offsets that [`interpolate_errors`] blends.
const SHEPARD_NEIGHBOURS: usize = 6;

/// The offsets' distances spread over the mesh vertices by Shepard's inverse-distance
/// weighting in the normalised parameter square, over the `SHEPARD_NEIGHBOURS` nearest
/// offsets: `e(x) = sum w_k e_k / sum w_k`, `w_k = 1 / |x - x_k|^2` (Shepard 1968, "A
/// two-dimensional interpolation function for irregularly-spaced data"). A vertex on an
/// offset's foot takes that offset's distance. An estimate between the offsets: the error is
/// only measured at them.
pub(crate) fn interpolate_errors(
    mesh: &Mesh,
    err: &OffsetErrors,
    domain_u: (f64, f64),
    domain_v: (f64, f64),
) -> Vec<f64> {
    if err.distance.is_empty() {
        return vec![0.0; mesh.nu * mesh.nv];
    }
    let norm = |t: f64, (a, b): (f64, f64)| (t - a) / (b - a);
    (0..mesh.nu * mesh.nv)
        .into_par_iter()
        .map(|idx| {
            let u = norm(mesh.params_u[idx / mesh.nv], domain_u);
            let v = norm(mesh.params_v[idx % mesh.nv], domain_v);
            let mut near: Vec<(f64, f64)> =
                err.uv.iter().zip(&err.distance).map(|(&(a, b), &e)| ((a - u).powi(2) + (b - v).powi(2), e)).collect();
            let k = SHEPARD_NEIGHBOURS.min(near.len());
            near.select_nth_unstable_by(k - 1, |a, b| a.0.total_cmp(&b.0));
            let near = &near[..k];
            if let Some(&(_, e)) = near.iter().find(|(d2, _)| *d2 < 1e-24) {
                return e;
            }
            let (num, den) = near.iter().fold((0.0, 0.0), |(n, d), &(d2, e)| (n + e / d2, d + 1.0 / d2));
            num / den
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::assert_near;

    /// A half cylinder of radius `r` around the x axis, `y >= 0`, length `l`: rational
    /// quadratic in u (from the bottom `(0, 0, -r)` round to the top `(0, 0, r)`), linear in v.
    fn half_cylinder(r: f64, l: f64) -> NurbsSurface {
        let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 0.5, 0.5, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let ring = [(0.0, -r, 1.0), (r, -r, s), (r, 0.0, 1.0), (r, r, s), (0.0, r, 1.0)];
        let mut pts = Vec::new();
        let mut w = Vec::new();
        for (y, z, wi) in ring {
            for x in [0.0, l] {
                pts.push(Vec3::new(x, y, z));
                w.push(wi);
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
    }

    #[test]
    fn params_contain_every_knot_and_meet_the_minimum() {
        let knots =
            KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.1, 0.15, 0.6, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let p = sample_params(&knots, 8, 60, 600);
        for k in [0.0, 0.1, 0.15, 0.6, 1.0] {
            assert!(p.contains(&k), "knot {k} missing from {p:?}");
        }
        assert!(p.windows(2).all(|w| w[1] > w[0]), "increasing");
        // Four spans: 8 each at least, the long span [0.15, 0.6] ceil(59 * 0.45) = 27.
        assert_eq!(p.len(), 8 + 8 + 27 + 24 + 1);
        assert!(p.len() >= 60);
        // The short span [0.1, 0.15] still gets 8 segments: 9 params inside it, ends included.
        assert_eq!(p.iter().filter(|&&t| (0.1..=0.15).contains(&t)).count(), 9);
    }

    #[test]
    fn params_respect_the_cap() {
        let knots: Vec<f64> = [0.0; 4].into_iter().chain((1..50).map(|i| i as f64 / 50.0)).chain([1.0; 4]).collect();
        let knots = KnotVector::try_new(3, knots).expect("valid");
        let p = sample_params(&knots, 8, 60, 200);
        assert!(p.len() <= 200 && p.len() >= 51, "{}", p.len());
    }

    #[test]
    fn cylinder_normals_point_out_and_curvatures_are_exact() {
        let (r, l) = (2.0, 10.0);
        let s = half_cylinder(r, l);
        let m = tessellate(&s, &Resolution::default());
        assert!(m.nu >= 40 && m.nv >= 60, "{} x {}", m.nu, m.nv);
        for idx in 0..m.nu * m.nv {
            let p = m.positions[idx];
            let radial = Vec3::new(0.0, p.y, p.z) / r;
            // Outward is radial, whatever the parameterisation's own orientation.
            assert_near!(m.normals[idx].dot(radial), 1.0, 1e-9);
            // A cylinder: K = 0 and |H| = 1/(2r); convex, so H > 0 with our sign.
            // Tolerance: rounding of the rational evaluation, well below 1e-9 / r^2.
            assert_near!(m.gaussian[idx], 0.0, 1e-9);
            assert_near!(m.mean[idx], 1.0 / (2.0 * r), 1e-9);
        }
        assert_eq!(m.triangles(), 2 * (m.nu - 1) * (m.nv - 1));
    }

    #[test]
    fn offsets_on_the_surface_have_zero_error_and_off_it_their_distance() {
        let (r, l) = (2.0, 10.0);
        let s = half_cylinder(r, l);
        let t = std::f64::consts::FRAC_PI_4;
        let on = Vec3::new(3.0, r * t.cos(), -r * t.sin());
        let off = Vec3::new(7.0, (r + 0.25) * t.cos(), (r + 0.25) * t.sin());
        let offsets = Offsets {
            source: "test".into(),
            units: hull::Units::Metre,
            perpendiculars: None,
            sections: vec![hull::Section::new("a", vec![on, off])],
        };
        let e = offset_errors(&s, &offsets);
        // Closest-point projection converges to ~1e-12 of the size here.
        assert_near!(e.distance[0], 0.0, 1e-9);
        assert_near!(e.distance[1], 0.25, 1e-9);
        let m = tessellate(&s, &Resolution::default());
        let field = interpolate_errors(&m, &e, s.domain_u(), s.domain_v());
        // Shepard's weights are a convex combination: every value within the data's range.
        assert!(field.iter().all(|&f| (-1e-12..=0.25 + 1e-12).contains(&f)));
        assert!(field.iter().any(|&f| f < 0.05) && field.iter().any(|&f| f > 0.2));
    }
}
