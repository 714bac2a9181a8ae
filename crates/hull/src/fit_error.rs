//! The true fit error: the distance of every input offset to the surface, measured by
//! closest-point projection (not the parametric residual `|S(u_k, v_k) - Q_k|`, which
//! overstates the error wherever the fit's parameters are not the foot points).

use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjection, SurfaceProjector, Vec3};
use rayon::prelude::*;
use serde::Serialize;

use crate::Offsets;

/// Max, mean and RMS of a set of distances.
#[derive(Clone, Copy, Debug, Default, PartialEq, Serialize)]
pub struct ErrorStats {
    pub max: f64,
    pub mean: f64,
    pub rms: f64,
    /// Number of points measured.
    pub points: usize,
}

impl ErrorStats {
    /// Statistics of `distances` (all zero for an empty set).
    pub fn from_distances(distances: &[f64]) -> Self {
        if distances.is_empty() {
            return ErrorStats::default();
        }
        let n = distances.len() as f64;
        let max = distances.iter().copied().fold(0.0, f64::max);
        let mean = distances.iter().sum::<f64>() / n;
        let rms = (distances.iter().map(|d| d * d).sum::<f64>() / n).sqrt();
        ErrorStats { max, mean, rms, points: distances.len() }
    }
}

/// The error of one section.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct SectionError {
    /// The section's label in the input.
    pub section: String,
    #[serde(flatten)]
    pub stats: ErrorStats,
}

/// Where the largest error is.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct WorstPoint {
    /// Section label.
    pub section: String,
    /// 0-based index of the point in its section.
    pub index: usize,
    /// 1-based input line of the point, when known.
    pub line: Option<usize>,
    /// The offset itself.
    pub point: [f64; 3],
    /// Its foot point on the surface.
    pub foot: [f64; 3],
    pub distance: f64,
}

/// The fit error of a surface against its offsets.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct FitError {
    #[serde(flatten)]
    pub overall: ErrorStats,
    /// The worst offset (`None` without points).
    pub worst: Option<WorstPoint>,
    /// One entry per input section, in input order.
    pub per_section: Vec<SectionError>,
    /// Projections that stopped at the iteration limit instead of a convergence criterion.
    pub unconverged_projections: usize,
    /// The error between the offsets, by cross-validation ([`crate::held_out_for_config`]);
    /// `None` (left out of the JSON) unless it was asked for.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub held_out: Option<HeldOutError>,
}

/// The held-out (cross-validated) error ([`crate::held_out_error`]): `report.json`'s
/// `error.held_out`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct HeldOutError {
    /// RMS of the true distances of all held-out offsets (both kinds) to their refits.
    pub rms: f64,
    /// The largest of them.
    pub max: f64,
    /// The held-out sections' offsets (zero points when none could be held out).
    pub sections: ErrorStats,
    /// The held-out points within sections.
    pub points: ErrorStats,
    /// `K`.
    pub folds: usize,
    /// Refits done (folds of either kind that held something out).
    pub refits: usize,
    /// Wall time of the refits and measurements.
    pub seconds: f64,
    /// The held-out offset farthest from the refit that left it out (its section, its index
    /// and input line in the whole table), where the surface is least sure between the
    /// offsets; `None` when nothing was held out.
    pub worst: Option<WorstPoint>,
}

impl HeldOutError {
    /// Whether a fit with RMS error `at_offsets` at the offsets and this held-out error
    /// over-fits compared with a baseline fit (`baseline_at_offsets`, `baseline`): see
    /// [`overfit`], on the RMS errors.
    pub fn overfits(&self, at_offsets: f64, baseline_at_offsets: f64, baseline: &HeldOutError) -> bool {
        overfit(at_offsets, self.rms, baseline_at_offsets, baseline.rms)
    }
}

/// Over-fitting of fit `a` against fit `b`: `a` is closer to the offsets than `b`
/// (`at_offsets_a < at_offsets_b`) but farther from the held-out ones (`held_a > held_b`), so
/// what it gained at the offsets it lost between them.
pub fn overfit(at_offsets_a: f64, held_a: f64, at_offsets_b: f64, held_b: f64) -> bool {
    at_offsets_a < at_offsets_b && held_a > held_b
}

/// Distance of every offset to `surface` by closest-point projection, per section and overall.
///
/// `hints`, when given, are the parameters the fit assigned to the offsets (`hints[k][i]` for
/// point `i` of section `k`): Newton also starts there, so a measured distance is never larger
/// than the parametric residual, whatever the global search finds.
pub fn measure_fit_error(surface: &NurbsSurface, offsets: &Offsets, hints: Option<&[Vec<(f64, f64)>]>) -> FitError {
    let projections = project_offsets(surface, offsets, hints);
    fit_error_of(offsets, &projections)
}

/// The parametric residual of every offset, `|S(u_k, v_k) - Q_k|` at the parameters `params`
/// the fit gave it (`params[k][i]` for point `i` of section `k`), in the form of
/// [`measure_fit_error`]: an upper bound of the true distance, at the cost of one evaluation
/// per offset, for the surfaces on the way to an answer (a fit the envelope hold refits, a
/// cross-validation refit), whose true error nobody reads.
pub(crate) fn parametric_fit_error(surface: &NurbsSurface, offsets: &Offsets, params: &[Vec<(f64, f64)>]) -> FitError {
    let feet: Vec<SurfaceProjection> = offsets
        .sections
        .iter()
        .zip(params)
        .flat_map(|(s, uv)| s.points.iter().zip(uv))
        .map(|(&q, &(u, v))| {
            let point = surface.point(u, v);
            SurfaceProjection { u, v, point, distance: (point - q).norm(), iterations: 0, converged: true }
        })
        .collect();
    fit_error_of(offsets, &feet)
}

/// The error of `offsets` from the feet `projections` of its points, in input order.
pub(crate) fn fit_error_of(offsets: &Offsets, projections: &[SurfaceProjection]) -> FitError {
    let mut all = Vec::with_capacity(projections.len());
    let mut per_section = Vec::with_capacity(offsets.sections.len());
    let mut worst: Option<WorstPoint> = None;
    let mut unconverged = 0;
    let mut next = projections.iter();
    for section in &offsets.sections {
        let mut distances = Vec::with_capacity(section.points.len());
        for (index, (&q, proj)) in section.points.iter().zip(next.by_ref()).enumerate() {
            if !proj.converged {
                unconverged += 1;
            }
            distances.push(proj.distance);
            if worst.as_ref().is_none_or(|w| proj.distance > w.distance) {
                worst = Some(WorstPoint {
                    section: section.label.clone(),
                    index,
                    line: section.lines.get(index).copied(),
                    point: q.to_array(),
                    foot: proj.point.to_array(),
                    distance: proj.distance,
                });
            }
        }
        per_section
            .push(SectionError { section: section.label.clone(), stats: ErrorStats::from_distances(&distances) });
        all.extend(distances);
    }
    FitError {
        overall: ErrorStats::from_distances(&all),
        worst,
        per_section,
        unconverged_projections: unconverged,
        held_out: None,
    }
}

/// The closest-point projection of every offset onto `surface`, in input order (section by
/// section, point by point), with `hints` as in [`measure_fit_error`].
///
/// The offsets are projected in parallel; each projection is a pure function of its point, so
/// the result does not depend on the thread count.
pub(crate) fn project_offsets(
    surface: &NurbsSurface,
    offsets: &Offsets,
    hints: Option<&[Vec<(f64, f64)>]>,
) -> Vec<SurfaceProjection> {
    let projector = SurfaceProjector::new(surface, ProjectionOptions::default());
    let jobs: Vec<(usize, usize, Vec3)> = offsets
        .sections
        .iter()
        .enumerate()
        .flat_map(|(k, s)| s.points.iter().enumerate().map(move |(i, &q)| (k, i, q)))
        .collect();
    jobs.par_iter()
        .map(|&(k, i, q)| match hints.and_then(|h| h.get(k)).and_then(|h| h.get(i)) {
            Some(&uv) => projector.project_near(q, uv),
            None => projector.project(q),
        })
        .collect()
}

/// The parametric residuals `|S(u_k, v_k) - Q_k|` at given data parameters (an upper bound
/// of the true distance, used where speed matters more than exactness).
pub fn parametric_residuals(surface: &NurbsSurface, points: &[Vec3], params: &[(f64, f64)]) -> Vec<f64> {
    points.iter().zip(params).map(|(&q, &(u, v))| surface.point(u, v).distance(q)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::Section;
    use nurbs::{assert_near, KnotVector};

    /// The plane z = 0 over [0, 2] x [0, 3] as a bilinear surface.
    fn plane() -> NurbsSurface {
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let pts = [Vec3::new(0., 0., 0.), Vec3::new(0., 3., 0.), Vec3::new(2., 0., 0.), Vec3::new(2., 3., 0.)];
        NurbsSurface::try_new(k.clone(), k, &pts, None).expect("valid")
    }

    #[test]
    fn distances_to_a_plane_are_the_heights() {
        let offsets = Offsets {
            source: "test".into(),
            units: crate::Units::Metre,
            perpendiculars: None,
            sections: vec![
                Section::new("a", vec![Vec3::new(0.5, 0.5, 0.1), Vec3::new(1.0, 1.0, -0.3)]),
                Section::new("b", vec![Vec3::new(1.5, 2.0, 0.0), Vec3::new(1.0, 2.5, 0.2)]),
            ],
        };
        let e = measure_fit_error(&plane(), &offsets, None);
        // Good or bad hints change nothing on a plane: the global search finds the foot.
        let bad = vec![vec![(0.9, 0.9); 2]; 2];
        assert_eq!(measure_fit_error(&plane(), &offsets, Some(&bad)).overall, e.overall);
        // Exact answers |z|; projection onto a plane converges to round-off.
        assert_near!(e.overall.max, 0.3, 1e-12);
        assert_near!(e.overall.mean, 0.6 / 4.0, 1e-12);
        assert_near!(e.overall.rms, ((0.01 + 0.09 + 0.04) / 4.0f64).sqrt(), 1e-12);
        assert_eq!(e.per_section.len(), 2);
        assert_near!(e.per_section[1].stats.max, 0.2, 1e-12);
        let w = e.worst.expect("points exist");
        assert_eq!((w.section.as_str(), w.index), ("a", 1));
        assert_near!(w.foot[2], 0.0, 1e-12);
    }

    #[test]
    fn projections_that_do_not_converge_are_counted() {
        // A point with a NaN coordinate (it cannot come through validation, but a caller may
        // measure any offsets) has no foot point: the projector says so and the count shows it,
        // while the other three are measured as usual.
        let offsets = Offsets {
            source: "test".into(),
            perpendiculars: None,
            units: crate::Units::Metre,
            sections: vec![
                Section::new("a", vec![Vec3::new(0.5, 0.5, 0.1), Vec3::new(f64::NAN, 1.0, 0.0)]),
                Section::new("b", vec![Vec3::new(1.5, 2.0, 0.0), Vec3::new(1.0, 2.5, 0.2)]),
            ],
        };
        let e = measure_fit_error(&plane(), &offsets, None);
        assert_eq!((e.unconverged_projections, e.overall.points), (1, 4));
        // Section b is unaffected: exact heights, as in the test above.
        assert_near!(e.per_section[1].stats.max, 0.2, 1e-12);
        let clean = Offsets { sections: offsets.sections[1..].to_vec(), ..offsets };
        assert_eq!(measure_fit_error(&plane(), &clean, None).unconverged_projections, 0);
    }

    #[test]
    fn parametric_residual_bounds_the_true_distance() {
        let s = plane();
        let q = [Vec3::new(1.0, 1.0, 0.5)];
        // Wrong parameters give a larger residual than the true distance 0.5.
        let r = parametric_residuals(&s, &q, &[(0.2, 0.2)]);
        assert!(r[0] > 0.5 + 0.1);
        let r = parametric_residuals(&s, &q, &[(0.5, 1.0 / 3.0)]);
        assert_near!(r[0], 0.5, 1e-12);
    }
}
