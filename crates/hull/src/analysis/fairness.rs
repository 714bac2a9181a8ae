//! Fairness measures of a surface: bending energies and the inflections and curvature peaks
//! of its stations and waterlines.
//!
//! The rest of this module's documentation is on [`BendingEnergy`] (the energies) and
//! [`fairness_report`] (the inflections), where the library's users read it.

use nurbs::{cut_surface_many, CutCurve, CutOptions, NurbsSurface, Vec3};
use serde::Serialize;

use super::CutPlane;

/// Which planes to cut.
#[derive(Clone, Debug, PartialEq)]
pub enum PlaneSelection {
    /// `n` planes evenly spaced strictly inside the surface's extent along the plane's axis:
    /// `lo + (hi - lo) k / (n + 1)`, `k = 1..=n` (the end planes usually touch a degenerate
    /// edge: a pointed stem, the keel).
    Count(usize),
    /// The planes at these values (e.g. the offsets' stations), in this order.
    At(Vec<f64>),
}

impl PlaneSelection {
    /// The plane values for an extent `[lo, hi]`.
    pub fn values(&self, lo: f64, hi: f64) -> Vec<f64> {
        match self {
            PlaneSelection::Count(n) => (1..=*n).map(|k| lo + (hi - lo) * k as f64 / (*n + 1) as f64).collect(),
            PlaneSelection::At(v) => v.clone(),
        }
    }
}

/// Settings of [`fairness_report`].
#[derive(Clone, Debug, PartialEq)]
pub struct FairnessOptions {
    pub stations: PlaneSelection,
    pub waterlines: PlaneSelection,
    /// `tau * size`: see the module documentation.
    pub inflection_threshold: f64,
    /// Gauss points per knot span `(u, v)`; `None` takes [`default_quadrature`].
    pub quadrature: Option<(usize, usize)>,
    pub cut: CutOptions,
}

impl Default for FairnessOptions {
    /// 21 stations, 10 waterlines, threshold 1e-6, default cuts.
    fn default() -> Self {
        FairnessOptions {
            stations: PlaneSelection::Count(21),
            waterlines: PlaneSelection::Count(10),
            inflection_threshold: 1e-6,
            quadrature: None,
            cut: CutOptions::default(),
        }
    }
}

/// Integrals over the surface, the measures of its fairness.
///
/// Both are integrated by Gauss-Legendre quadrature over every non-empty knot-span rectangle
/// (the integrands are smooth inside a span; their derivatives jump across knots):
///
/// - **thin plate** `E_tp = integral (k1^2 + k2^2) dA = integral (4 H^2 - 2 K) |S_u x S_v| du dv`,
///   the bending energy of a thin elastic plate (Kirchhoff; Moreton and Sequin 1992,
///   "Functional optimization for fair surface design"). It depends on the shape only, not on
///   the parametrisation, and is scale-free (dimensionless: a sphere's is `8 pi` whatever its
///   radius), so it compares two surfaces of the same hull: a bump raises it.
/// - **parametric** `E_p = integral |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2 du dv` (length^2 per
///   parameter^2: it carries the parametrisation), the stand-in that fitting smoothers
///   minimise because it is quadratic in the control points (Greiner 1994, "Variational design
///   and fairing of spline surfaces"). It only compares surfaces with the same
///   parametrisation, e.g. two fits with the same knots.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct BendingEnergy {
    /// `integral dA`.
    pub area: f64,
    /// `integral (k1^2 + k2^2) dA`, dimensionless.
    pub thin_plate: f64,
    /// `integral |S_uu|^2 + 2 |S_uv|^2 + |S_vv|^2 du dv`.
    pub parametric: f64,
    /// Gauss points per knot span `[u, v]`.
    pub points_per_span: [usize; 2],
    /// Quadrature nodes where the surface is degenerate (left out of `thin_plate`; their
    /// area element is round-off).
    pub skipped: usize,
}

/// Fairness of one branch of a cut.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CutFairness {
    pub points: usize,
    pub length: f64,
    /// Curvature sign changes beyond the threshold.
    pub inflections: usize,
    /// Where each counted sign change is: the zero of the curvature interpolated linearly
    /// between the point where it completes (the first past the threshold) and the one before.
    pub inflections_at: Vec<[f64; 3]>,
    /// Largest `|kappa|` on the branch, with its sign, its point and parameters.
    pub max_curvature: f64,
    pub max_at: [f64; 3],
    pub max_at_uv: [f64; 2],
}

/// Fairness of one plane's cut.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct PlaneFairness {
    pub plane: CutPlane,
    /// One entry per branch, in the cut's order; empty if the plane misses the surface.
    pub branches: Vec<CutFairness>,
    /// Sum over the branches.
    pub inflections: usize,
    /// The branches' largest `|kappa|` (signed), 0 without branches.
    pub max_curvature: f64,
}

/// The fairness report of a surface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FairnessReport {
    pub energy: BendingEnergy,
    /// `tau` in 1/length.
    pub curvature_threshold: f64,
    pub stations: Vec<PlaneFairness>,
    pub waterlines: Vec<PlaneFairness>,
    /// Sum over stations and waterlines.
    pub inflections: usize,
}

/// Gauss-Legendre nodes and weights on `[-1, 1]`, `n` of them (at least 1), ascending, as
/// `(node, weight)` pairs: the kernel's rule ([`nurbs::GaussLegendre`]). Exact for polynomials
/// of degree `2n - 1`.
pub fn gauss_legendre(n: usize) -> Vec<(f64, f64)> {
    nurbs::GaussLegendre::new(n).on(-1.0, 1.0).collect()
}

/// The distinct knot values of the domain (span boundaries).
fn breaks(knots: &nurbs::KnotVector) -> Vec<f64> {
    let k = knots.as_slice();
    let p = knots.degree();
    let mut b = k[p..k.len() - p].to_vec();
    b.dedup();
    b
}

/// Gauss points per knot span `(u, v)` for [`bending_energy`]: `p + 3` along a direction of
/// degree `p`, and at least 32 over the whole direction. The parametric energy of a
/// non-rational surface is a polynomial of degree `2p` per direction, exact from `p + 1`
/// points; the thin-plate integrand is rational in the derivatives (`1 / (EG - F^2)^k`), whose
/// complex poles near the span limit Gauss convergence: on the one-span Wigley hull, 12 points
/// leave 1e-7, 30 points 1e-13 (tested).
pub fn default_quadrature(surface: &NurbsSurface) -> (usize, usize) {
    let per = |knots: &nurbs::KnotVector| {
        let spans = breaks(knots).len().saturating_sub(1).max(1);
        (knots.degree() + 3).max(32usize.div_ceil(spans))
    };
    (per(surface.knots_u()), per(surface.knots_v()))
}

/// [`BendingEnergy`] with `points.0` Gauss points per knot span along u and `points.1` along v
/// (at least 1 each).
pub fn bending_energy(surface: &NurbsSurface, points: (usize, usize)) -> BendingEnergy {
    let (gu, gv) = (gauss_legendre(points.0), gauss_legendre(points.1));
    let (bu, bv) = (breaks(surface.knots_u()), breaks(surface.knots_v()));
    // Every Gauss point of every span on one grid: span i's points from i * gu.len() along u.
    let nodes = |b: &[f64], g: &[(f64, f64)]| -> Vec<f64> {
        b.windows(2).flat_map(|w| g.iter().map(move |&(x, _)| 0.5 * (w[1] + w[0]) + 0.5 * (w[1] - w[0]) * x)).collect()
    };
    let (us, vs) = (nodes(&bu, &gu), nodes(&bv, &gv));
    let grid = surface.derivatives_grid(&us, &vs);
    let (mut area, mut thin, mut param, mut skipped) = (0.0, 0.0, 0.0, 0);
    for (i, wu) in bu.windows(2).enumerate() {
        let hu = 0.5 * (wu[1] - wu[0]);
        for (j, wv) in bv.windows(2).enumerate() {
            let hv = 0.5 * (wv[1] - wv[0]);
            for (a, &(_, au)) in gu.iter().enumerate() {
                for (b, &(_, av)) in gv.iter().enumerate() {
                    let w = au * hu * av * hv;
                    let d = grid[(j * gv.len() + b) * us.len() + i * gu.len() + a];
                    param += w * (d.suu.norm_squared() + 2.0 * d.suv.norm_squared() + d.svv.norm_squared());
                    let da = d.su.cross(d.sv).norm();
                    area += w * da;
                    match d.regular_normal().and_then(|_| d.curvature()) {
                        Some(c) if (c.mean.is_finite() && c.gaussian.is_finite()) => {
                            // k1^2 + k2^2 = (k1 + k2)^2 - 2 k1 k2.
                            thin += w * (4.0 * c.mean * c.mean - 2.0 * c.gaussian) * da;
                        }
                        _ => skipped += 1,
                    }
                }
            }
        }
    }
    BendingEnergy { area, thin_plate: thin, parametric: param, points_per_span: [gu.len(), gv.len()], skipped }
}

/// Inflections and the curvature peak of one branch, with the curvature threshold `tau`
/// (1/length; see the module documentation).
pub fn cut_fairness(curve: &CutCurve, tau: f64) -> CutFairness {
    let mut state = 0i8;
    let mut inflections_at = Vec::new();
    let (mut max_curvature, mut max_k) = (0.0f64, None);
    for (k, p) in curve.points.iter().enumerate() {
        let kappa = p.curvature;
        if kappa.abs() > max_curvature.abs() {
            (max_curvature, max_k) = (kappa, Some(k));
        }
        let sign = if kappa > tau {
            1
        } else if kappa < -tau {
            -1
        } else {
            continue;
        };
        if state != 0 && sign != state {
            // The zero of kappa interpolated linearly from the previous point.
            let q = &curve.points[k - 1];
            let t = if q.curvature != kappa { (q.curvature / (q.curvature - kappa)).clamp(0.0, 1.0) } else { 1.0 };
            let at = q.point + (p.point - q.point) * t;
            inflections_at.push([at.x, at.y, at.z]);
        }
        state = sign;
    }
    let at = max_k.or((!curve.points.is_empty()).then_some(0)).map(|k| &curve.points[k]);
    CutFairness {
        points: curve.points.len(),
        length: curve.length(),
        inflections: inflections_at.len(),
        inflections_at,
        max_curvature,
        max_at: at.map_or([0.0; 3], |p| [p.point.x, p.point.y, p.point.z]),
        max_at_uv: at.map_or([0.0; 2], |p| [p.uv.0, p.uv.1]),
    }
}

/// The fairness report: energies, and each station's and waterline's inflections and peak
/// curvature.
///
/// # Inflections
///
/// Along each branch of a cut the signed curvature of [`CutPoint`](super::CutPoint) is read
/// in order; a sign change counts once the curvature has gone from below `-tau` to above
/// `+tau` or back (hysteresis), values with `|kappa| <= tau` changing nothing. `tau` is
/// [`FairnessOptions::inflection_threshold`] divided by the model size (the diagonal of the
/// control net's box): the default 1e-6 (a radius of a million model sizes) is far above the
/// round-off of the analytic curvature (~1e-12 / size) and far below any visible bend.
/// A closed loop is read from its first point round to it again.
pub fn fairness_report(surface: &NurbsSurface, options: &FairnessOptions) -> FairnessReport {
    let points = options.quadrature.unwrap_or_else(|| default_quadrature(surface));
    let energy = bending_energy(surface, points);
    let (curvature_threshold, stations, waterlines, inflections) = plane_fairness(surface, options);
    FairnessReport { energy, curvature_threshold, stations, waterlines, inflections }
}

/// The cuts' part of [`fairness_report`] (its most costly): `tau`, the stations', the
/// waterlines' and the total inflections.
pub(crate) fn plane_fairness(
    surface: &NurbsSurface,
    options: &FairnessOptions,
) -> (f64, Vec<PlaneFairness>, Vec<PlaneFairness>, usize) {
    let size = surface.model_size().unwrap_or(1.0);
    let tau = options.inflection_threshold.abs() / size;
    let (lo, hi) = surface_bounds(surface);
    let stations: Vec<CutPlane> = options.stations.values(lo.x, hi.x).into_iter().map(CutPlane::Station).collect();
    let waterlines: Vec<CutPlane> =
        options.waterlines.values(lo.z, hi.z).into_iter().map(CutPlane::Waterline).collect();
    let planes: Vec<CutPlane> = stations.iter().chain(&waterlines).copied().collect();
    let cuts = cut_surface_many(surface, &planes, &options.cut);
    let mut per_plane: Vec<PlaneFairness> = planes
        .iter()
        .zip(&cuts)
        .map(|(&plane, branches)| {
            let branches: Vec<CutFairness> = branches.iter().map(|c| cut_fairness(c, tau)).collect();
            let inflections = branches.iter().map(|b| b.inflections).sum();
            let max_curvature =
                branches.iter().map(|b| b.max_curvature).fold(0.0, |m: f64, k| if k.abs() > m.abs() { k } else { m });
            PlaneFairness { plane, branches, inflections, max_curvature }
        })
        .collect();
    let waterlines = per_plane.split_off(stations.len());
    let stations = per_plane;
    let inflections = stations.iter().chain(&waterlines).map(|p| p.inflections).sum();
    (tau, stations, waterlines, inflections)
}

/// The bounding box of the surface's points on a 64 x 64 parameter grid with its knot lines.
fn surface_bounds(surface: &NurbsSurface) -> (Vec3, Vec3) {
    let us = surface.knots_u().param_grid(64, true, 2);
    let vs = surface.knots_v().param_grid(64, true, 2);
    let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    // The grid evaluated at once (each point that of `surface.point`, with the basis functions
    // of each u made once).
    for p in surface.points_grid(&us, &vs) {
        lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
        hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
    }
    (lo, hi)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::CutPoint;

    #[test]
    fn gauss_legendre_integrates_polynomials_of_degree_2n_minus_1() {
        for n in 1..=10 {
            let gl = gauss_legendre(n);
            assert_eq!(gl.len(), n);
            assert!(gl.windows(2).all(|w| w[0].0 < w[1].0), "ascending");
            for deg in 0..2 * n {
                let got: f64 = gl.iter().map(|&(x, w)| w * x.powi(deg as i32)).sum();
                // integral of x^d over [-1, 1]: 2 / (d + 1) for even d, 0 for odd d.
                let want = if deg % 2 == 0 { 2.0 / (deg as f64 + 1.0) } else { 0.0 };
                // Nodes converged to 1e-15: round-off of a sum of n terms.
                assert!((got - want).abs() <= 1e-14, "n {n} degree {deg}: {got} vs {want}");
            }
        }
    }

    fn curve_with(kappas: &[f64]) -> CutCurve {
        let points = kappas
            .iter()
            .enumerate()
            .map(|(i, &k)| CutPoint { uv: (i as f64, 0.0), point: Vec3::new(i as f64, 0.0, 0.0), curvature: k })
            .collect();
        CutCurve { plane: CutPlane::Station(0.0).into(), points }
    }

    #[test]
    fn sign_changes_count_only_beyond_the_threshold() {
        let tau = 1e-3;
        // Round-off around zero between two positive stretches: no inflection.
        let c = curve_with(&[0.5, 0.2, 1e-4, -1e-4, 2e-4, -5e-4, 0.1, 0.3]);
        assert_eq!(cut_fairness(&c, tau).inflections, 0);
        // Positive, through a near-zero stretch, to negative and back: two inflections.
        let c = curve_with(&[0.5, 1e-5, -0.2, -0.4, 0.0, 0.3]);
        let f = cut_fairness(&c, tau);
        assert_eq!(f.inflections, 2);
        // Zeros between points 1 (1e-5) and 2 (-0.2), and at point 4 (0.0) before 5 (0.3).
        let at: Vec<f64> = f.inflections_at.iter().map(|p| p[0]).collect();
        assert!((at[0] - (1.0 + 1e-5 / (1e-5 + 0.2))).abs() <= 1e-15 && at[1] == 4.0, "{at:?}");
        assert_eq!(f.max_curvature, 0.5);
        assert_eq!(f.max_at, [0.0, 0.0, 0.0]);
        let c = curve_with(&[0.1, -0.7]);
        assert_eq!(cut_fairness(&c, tau).max_curvature, -0.7);
    }

    #[test]
    fn plane_selection_spaces_planes_inside_the_extent() {
        assert_eq!(PlaneSelection::Count(3).values(0.0, 8.0), vec![2.0, 4.0, 6.0]);
        assert_eq!(PlaneSelection::At(vec![1.5, 0.5]).values(0.0, 8.0), vec![1.5, 0.5]);
        assert!(PlaneSelection::Count(0).values(0.0, 1.0).is_empty());
    }
}
