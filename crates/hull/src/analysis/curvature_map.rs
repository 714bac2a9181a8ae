//! Gaussian, mean and principal curvatures of a surface on a parameter grid, with the
//! statistics a colour scale and a report need.
//!
//! The rest of this module's documentation is on [`curvature_map()`], where the library's users read it.

use nurbs::{KnotVector, NurbsSurface, Vec3};
use rayon::prelude::*;
use serde::Serialize;

use super::span_grid;
use crate::offsets::COINCIDENT_REL;

/// Settings of [`curvature_map`].
#[derive(Clone, Debug, PartialEq)]
pub struct CurvatureMapOptions {
    /// Uniform parameter intervals `(u, v)` (at least 1 each).
    pub grid: (usize, usize),
    /// Join the knot lines to the grid (and split each knot span in at least two), so the
    /// curvature jumps of a C1 spline at its knots are sampled.
    pub refine_at_knots: bool,
    /// Low and high percentiles (0..=100) reported for colour scales, robust to a few extreme
    /// nodes (next to a collapsed edge, at a knot).
    pub percentiles: (f64, f64),
    /// Where the grid lines lie.
    pub lines: GridLines,
    /// When a node counts as degenerate.
    pub degeneracy: Degeneracy,
}

impl Default for CurvatureMapOptions {
    /// 64 x 64 uniform intervals with the knot lines, percentiles 1 % and 99 %, degenerate
    /// nodes told by [`Degeneracy::Skewed`].
    fn default() -> Self {
        CurvatureMapOptions {
            grid: (64, 64),
            refine_at_knots: true,
            percentiles: (1.0, 99.0),
            lines: GridLines::Uniform,
            degeneracy: Degeneracy::Skewed,
        }
    }
}

/// Where the grid lines of a curvature map lie, `grid = (n_u, n_v)` of [`CurvatureMapOptions`]
/// giving the count along each direction.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum GridLines {
    /// `n` uniform intervals of the domain, joined (with `refine_at_knots`) with every knot
    /// line and with the midpoint of every knot span.
    #[default]
    Uniform,
    /// A line at every distinct knot and each knot span split in proportion to its length into
    /// at least 2 equal parts, about `n` lines in all (`refine_at_knots` is implied): the grid
    /// of the curvature picture, whose cells never straddle a knot.
    Spans,
}

/// When a grid node counts as degenerate (its curvatures are then not computed).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Degeneracy {
    /// The parametrisation is locally too skewed for second-order quantities:
    /// `|S_u x S_v| < 1e-8 (|S_u|^2 + |S_v|^2)`, as the planar cuts judge it.
    #[default]
    Skewed,
    /// `|S_u x S_v|` is round-off of the model: at most [`COINCIDENT_REL`] of the square of the
    /// control net's size per unit parameter area (as [`crate::gaussian_curvature_range`]).
    RoundOff,
}

/// Which curvature to read from a sample.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum CurvatureField {
    /// `K = k1 k2`, 1/length^2.
    Gaussian,
    /// `H = (k1 + k2) / 2`, 1/length.
    Mean,
    /// The larger principal curvature.
    K1,
    /// The smaller principal curvature.
    K2,
}

impl CurvatureField {
    pub const ALL: [CurvatureField; 4] =
        [CurvatureField::Gaussian, CurvatureField::Mean, CurvatureField::K1, CurvatureField::K2];

    /// `Gaussian curvature`, `mean curvature`, `larger principal curvature`, `smaller
    /// principal curvature`.
    pub fn name(self) -> &'static str {
        match self {
            CurvatureField::Gaussian => "Gaussian curvature",
            CurvatureField::Mean => "mean curvature",
            CurvatureField::K1 => "larger principal curvature",
            CurvatureField::K2 => "smaller principal curvature",
        }
    }

    /// `K`, `H`, `k1`, `k2`.
    pub fn symbol(self) -> &'static str {
        match self {
            CurvatureField::Gaussian => "K",
            CurvatureField::Mean => "H",
            CurvatureField::K1 => "k1",
            CurvatureField::K2 => "k2",
        }
    }

    /// Power of length in the units' denominator: 2 for K, 1 for the others.
    pub fn power(self) -> i32 {
        match self {
            CurvatureField::Gaussian => 2,
            _ => 1,
        }
    }

    /// `1/m²` for K, `1/m` for the others, for length units `units` (`unit` if empty).
    pub fn units(self, units: &str) -> String {
        let u = if units.is_empty() { "unit" } else { units };
        match self {
            CurvatureField::Gaussian => format!("1/{u}²"),
            _ => format!("1/{u}"),
        }
    }
}

/// Curvatures at one regular grid node.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct CurvatureSample {
    pub gaussian: f64,
    pub mean: f64,
    pub k1: f64,
    pub k2: f64,
    /// The unit normal `S_u x S_v / |S_u x S_v|` the signs refer to.
    pub normal: Vec3,
}

impl CurvatureSample {
    /// The value of `field`.
    pub fn get(&self, field: CurvatureField) -> f64 {
        match field {
            CurvatureField::Gaussian => self.gaussian,
            CurvatureField::Mean => self.mean,
            CurvatureField::K1 => self.k1,
            CurvatureField::K2 => self.k2,
        }
    }

    /// The curvatures with the normal turned over when `flip`: `H`, `k1`, `k2` change sign
    /// (and `k1`, `k2` swap, `k1 >= k2` still), `K` does not.
    pub fn oriented(&self, flip: bool) -> CurvatureSample {
        if !flip {
            return *self;
        }
        CurvatureSample { gaussian: self.gaussian, mean: -self.mean, k1: -self.k2, k2: -self.k1, normal: -self.normal }
    }
}

/// Curvatures on a parameter grid, u-major (`index = i * vs.len() + j`).
#[derive(Clone, Debug, PartialEq)]
pub struct CurvatureMap {
    pub us: Vec<f64>,
    pub vs: Vec<f64>,
    /// `S(u_i, v_j)`.
    pub points: Vec<Vec3>,
    /// `None` where the node is flagged as degenerate.
    pub samples: Vec<Option<CurvatureSample>>,
    /// The percentiles of [`CurvatureMapOptions`], for [`CurvatureMap::summary`].
    pub percentiles: (f64, f64),
}

/// A smallest or largest value and where it is.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Extreme {
    pub value: f64,
    pub u: f64,
    pub v: f64,
    pub point: [f64; 3],
}

/// Statistics of one curvature over the regular nodes.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct FieldStats {
    pub min: Extreme,
    pub max: Extreme,
    /// The `percentiles` (in percent) and their values `low`, `high` (linear interpolation
    /// between order statistics: the value at rank `p / 100 (n - 1)`).
    pub percentiles: [f64; 2],
    pub low: f64,
    pub high: f64,
    /// Plain average over the nodes (not area-weighted).
    pub average: f64,
}

/// The serializable summary of a map, for `report.json`.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct CurvatureSummary {
    /// Grid nodes `[u, v]`.
    pub grid: [usize; 2],
    /// Regular nodes in the statistics.
    pub samples: usize,
    /// Degenerate nodes left out.
    pub flagged: usize,
    /// What the signs of `mean`, `k1`, `k2` refer to.
    pub normal: &'static str,
    /// `None` when every node is flagged.
    pub gaussian: Option<FieldStats>,
    pub mean: Option<FieldStats>,
    pub k1: Option<FieldStats>,
    pub k2: Option<FieldStats>,
}

/// The curvature map of `surface` on the grid of `options`.
///
/// # Definitions
///
/// At each grid node, from the first and second fundamental forms (`E, F, G` and `L, M, N`
/// with the unit normal `n = S_u x S_v / |S_u x S_v|`; The NURBS Book / do Carmo 3-3, the
/// kernel's [`nurbs::Curvature`]):
///
/// ```text
/// K = (L N - M^2) / (E G - F^2),   H = (E N - 2 F M + G L) / (2 (E G - F^2)),
/// k1,2 = H +- sqrt(H^2 - K)        (k1 >= k2; H^2 - K < 0 from round-off is taken as 0)
/// ```
///
/// Signs follow the surface's own normal `S_u x S_v`: `H` and `k1, k2` are positive where
/// the surface bends toward it (a sphere with an inward normal has `H = +1/R`), `K` does not
/// depend on it. A hull fitted by hullskin (u keel to deck, v aft to fore) has its normal
/// pointing outboard, so a convex bilge has `H < 0`.
///
/// Nodes where the normal is undefined or the fundamental forms are round-off (a collapsed
/// edge: a pole, a pointed stem; see [`Degeneracy`]) are flagged (`None`) and left out of the
/// statistics, so nothing is NaN.
///
/// This is the one sampling of curvature over a surface: the report's tables read its
/// statistics, and the curvature picture (`view::curvature_map`, in the crate above) paints its nodes.
pub fn curvature_map(surface: &NurbsSurface, options: &CurvatureMapOptions) -> CurvatureMap {
    let grid = |knots: &KnotVector, n| match options.lines {
        GridLines::Uniform => knots.param_grid(n, options.refine_at_knots, 2),
        GridLines::Spans => span_grid(knots, n),
    };
    let us = grid(surface.knots_u(), options.grid.0);
    let vs = grid(surface.knots_v(), options.grid.1);
    let regular = Regular::new(surface, options.degeneracy);
    let rows: Vec<Vec<(Vec3, Option<CurvatureSample>)>> =
        us.par_iter().map(|&u| vs.iter().map(|&v| sample_at(surface, u, v, regular)).collect()).collect();
    let (points, samples) = rows.into_iter().flatten().unzip();
    CurvatureMap { us, vs, points, samples, percentiles: options.percentiles }
}

/// The test of [`Degeneracy`] for one surface.
#[derive(Clone, Copy)]
enum Regular {
    Skewed,
    /// Smallest `|S_u x S_v|` that is not round-off.
    Area(f64),
}

impl Regular {
    fn new(surface: &NurbsSurface, degeneracy: Degeneracy) -> Self {
        match degeneracy {
            Degeneracy::Skewed => Regular::Skewed,
            Degeneracy::RoundOff => {
                let (lo, hi) = surface.control_bounds();
                let size = (hi - lo).norm();
                let (au, bu) = surface.domain_u();
                let (av, bv) = surface.domain_v();
                Regular::Area(COINCIDENT_REL * size * size / ((bu - au) * (bv - av)))
            }
        }
    }

    fn holds(self, d: &nurbs::SurfaceDerivatives) -> bool {
        match self {
            Regular::Skewed => d.regular_normal().is_some(),
            Regular::Area(tol) => d.su.cross(d.sv).norm() > tol,
        }
    }
}

/// The point and, where regular, the curvatures at `(u, v)`.
fn sample_at(surface: &NurbsSurface, u: f64, v: f64, regular: Regular) -> (Vec3, Option<CurvatureSample>) {
    let d = surface.derivatives(u, v);
    let sample = regular.holds(&d).then(|| d.curvature()).flatten().and_then(|c| {
        let disc = (c.mean * c.mean - c.gaussian).max(0.0).sqrt();
        let s = CurvatureSample {
            gaussian: c.gaussian,
            mean: c.mean,
            k1: c.mean + disc,
            k2: c.mean - disc,
            normal: c.normal,
        };
        [s.gaussian, s.mean, s.k1, s.k2].iter().all(|x| x.is_finite()).then_some(s)
    });
    (d.point, sample)
}

impl CurvatureMap {
    /// The flat index of node `(i, j)`.
    pub fn index(&self, i: usize, j: usize) -> usize {
        i * self.vs.len() + j
    }

    /// The curvatures at node `(i, j)`, `None` if flagged or out of range.
    pub fn sample(&self, i: usize, j: usize) -> Option<&CurvatureSample> {
        if i >= self.us.len() || j >= self.vs.len() {
            return None;
        }
        self.samples[self.index(i, j)].as_ref()
    }

    /// Number of flagged (degenerate) nodes.
    pub fn flagged(&self) -> usize {
        self.samples.iter().filter(|s| s.is_none()).count()
    }

    /// True if the surface's normal `S_u x S_v` points toward the inside of the hull at most
    /// regular nodes: `sum n . (c - p) / |c - p| < 0` over them, `c = (p.x, y_min, z_mid)` the
    /// centre-plane axis at mid-depth of the grid's points. The mean and principal curvatures
    /// of [`CurvatureSample::oriented`] with this `flip` are positive where the hull is convex.
    pub fn outward_flip(&self) -> bool {
        let (lo, hi) = point_bounds(&self.points);
        let z_mid = 0.5 * (lo.z + hi.z);
        let vote: f64 = self
            .points
            .iter()
            .zip(&self.samples)
            .filter_map(|(p, s)| {
                let inward = (Vec3::new(p.x, lo.y, z_mid) - *p).normalized()?;
                Some(s.as_ref()?.normal.dot(inward))
            })
            .sum();
        vote.is_nan() || vote < 0.0
    }

    /// Statistics of `field` over the regular nodes with the percentiles `(lo, hi)` (percent,
    /// clamped to 0..=100); `None` if no node is regular.
    pub fn stats(&self, field: CurvatureField, percentiles: (f64, f64)) -> Option<FieldStats> {
        let nv = self.vs.len();
        let mut values = Vec::with_capacity(self.samples.len());
        let mut min: Option<(f64, usize)> = None;
        let mut max = min;
        for (k, s) in self.samples.iter().enumerate() {
            let Some(s) = s else { continue };
            let x = s.get(field);
            values.push(x);
            if !matches!(min, Some((m, _)) if x >= m) {
                min = Some((x, k));
            }
            if !matches!(max, Some((m, _)) if x <= m) {
                max = Some((x, k));
            }
        }
        let (min, max) = (min?, max?);
        let extreme = |(value, k): (f64, usize)| {
            let p = self.points[k];
            Extreme { value, u: self.us[k / nv], v: self.vs[k % nv], point: [p.x, p.y, p.z] }
        };
        values.sort_by(f64::total_cmp);
        let (plo, phi) = (percentiles.0.clamp(0.0, 100.0), percentiles.1.clamp(0.0, 100.0));
        Some(FieldStats {
            min: extreme(min),
            max: extreme(max),
            percentiles: [plo, phi],
            low: percentile(&values, plo),
            high: percentile(&values, phi),
            average: values.iter().sum::<f64>() / values.len() as f64,
        })
    }

    /// The summary of all four curvatures with the map's percentiles.
    pub fn summary(&self) -> CurvatureSummary {
        let p = self.percentiles;
        let flagged = self.flagged();
        CurvatureSummary {
            grid: [self.us.len(), self.vs.len()],
            samples: self.samples.len() - flagged,
            flagged,
            normal: "S_u x S_v",
            gaussian: self.stats(CurvatureField::Gaussian, p),
            mean: self.stats(CurvatureField::Mean, p),
            k1: self.stats(CurvatureField::K1, p),
            k2: self.stats(CurvatureField::K2, p),
        }
    }
}

/// The bounding box `(min, max)` of the points.
pub fn point_bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    for p in points {
        lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
        hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
    }
    (lo, hi)
}

/// The `p`-th percentile (0..=100) of sorted, non-empty `values`: linear interpolation at rank
/// `p / 100 (n - 1)` (Hyndman and Fan 1996, definition 7).
fn percentile(values: &[f64], p: f64) -> f64 {
    let n = values.len();
    let rank = p / 100.0 * (n - 1) as f64;
    let lo = (rank.floor() as usize).min(n - 1);
    let hi = (lo + 1).min(n - 1);
    let t = rank - lo as f64;
    values[lo] + t * (values[hi] - values[lo])
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::KnotVector;

    /// The saddle `z = x y` over `[-1, 1]^2` as a bilinear patch: `K = -1 / (1 + x^2 + y^2)^2`,
    /// `H = -x y / (1 + x^2 + y^2)^1.5` for the normal `(-y, -x, 1) / |.|` (do Carmo 3-3 ex. 5).
    fn saddle() -> NurbsSurface {
        let k = || KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
        let pts = [
            Vec3::new(-1.0, -1.0, 1.0),
            Vec3::new(-1.0, 1.0, -1.0),
            Vec3::new(1.0, -1.0, -1.0),
            Vec3::new(1.0, 1.0, 1.0),
        ];
        NurbsSurface::try_new(k(), k(), &pts, None).expect("valid")
    }

    #[test]
    fn saddle_curvatures_match_the_graph_formulas() {
        let s = saddle();
        let map = curvature_map(&s, &CurvatureMapOptions { grid: (10, 10), ..Default::default() });
        assert_eq!(map.flagged(), 0);
        for (k, sample) in map.samples.iter().enumerate() {
            let s = sample.expect("regular");
            let p = map.points[k];
            let w = 1.0 + p.x * p.x + p.y * p.y;
            // u along x, v along y: S_u x S_v = (-y, -x, 1) scaled, the normal of the formula.
            assert!(s.normal.z > 0.0);
            // Closed forms evaluated at the same point: round-off only.
            assert!((s.gaussian + 1.0 / (w * w)).abs() <= 1e-14, "{p:?}");
            assert!((s.mean + p.x * p.y / w.powf(1.5)).abs() <= 1e-14, "{p:?}");
            assert!((s.k1 * s.k2 - s.gaussian).abs() <= 1e-14 && (s.k1 + s.k2 - 2.0 * s.mean).abs() <= 1e-14);
            assert!(s.k1 >= s.k2);
        }
        // K is most negative (-1) at the centre, the node (0, 0).
        let st = map.stats(CurvatureField::Gaussian, (1.0, 99.0)).expect("regular nodes");
        assert!((st.min.value + 1.0).abs() <= 1e-14 && st.min.point[0].abs() <= 1e-15, "{st:?}");
        assert!(st.min.value <= st.low && st.low <= st.high && st.high <= st.max.value);
    }

    #[test]
    fn percentiles_interpolate_order_statistics() {
        let v = [1.0, 2.0, 3.0, 4.0, 5.0];
        assert_eq!(percentile(&v, 0.0), 1.0);
        assert_eq!(percentile(&v, 100.0), 5.0);
        assert_eq!(percentile(&v, 50.0), 3.0);
        // Rank 0.1 * 4 = 0.4: 1 + 0.4 (2 - 1).
        assert!((percentile(&v, 10.0) - 1.4).abs() <= 1e-15);
        assert_eq!(percentile(&[7.0], 99.0), 7.0);
    }

    #[test]
    fn a_collapsed_edge_is_flagged_and_left_out() {
        // A triangle-like patch: the edge u = 1 collapses to one point.
        let k = || KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
        let pts = [Vec3::new(0., 0., 0.), Vec3::new(0., 1., 0.), Vec3::new(1., 0.5, 0.2), Vec3::new(1., 0.5, 0.2)];
        let s = NurbsSurface::try_new(k(), k(), &pts, None).expect("valid");
        let map = curvature_map(&s, &CurvatureMapOptions { grid: (4, 4), ..Default::default() });
        assert_eq!(map.flagged(), map.vs.len(), "the row u = 1");
        let summary = map.summary();
        assert_eq!(summary.flagged + summary.samples, map.us.len() * map.vs.len());
        let json = serde_json::to_string(&summary).expect("serializes");
        assert!(!json.contains("NaN") && !json.contains("null"), "{json}");
        // A plane: every curvature is zero.
        let g = summary.gaussian.expect("regular nodes");
        assert!(g.min.value.abs() <= 1e-15 && g.max.value.abs() <= 1e-15);
    }
}
