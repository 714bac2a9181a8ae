//! The range of the Gaussian curvature of a surface over a parameter grid joined with its knot
//! lines: a fairness figure of the comparison table ([`crate::compare_offsets`]) and of
//! fairing ([`crate::fairing`]).

use nurbs::{KnotVector, NurbsSurface};
use serde::Serialize;

use crate::offsets::COINCIDENT_REL;

/// Samples per parameter direction of the curvature grid (before the knot lines are added).
pub const CURVATURE_GRID: usize = 41;

/// The range of the Gaussian curvature over a sampled surface.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct CurvatureRange {
    pub max: f64,
    pub min: f64,
    /// Parameters `(u, v)` of the largest and of the smallest value (the first met, u-major).
    pub max_at: [f64; 2],
    pub min_at: [f64; 2],
    /// Points where the curvature was evaluated.
    pub samples: usize,
    /// Degenerate points skipped.
    pub skipped: usize,
}

/// The sample parameters of one direction: `n` uniform values over the domain and every
/// distinct interior knot, sorted, without duplicates.
fn sample_params(knots: &KnotVector, n: usize) -> Vec<f64> {
    let (a, b) = knots.domain();
    let n = n.max(2);
    let mut t: Vec<f64> = (0..n).map(|i| a + (b - a) * i as f64 / (n - 1) as f64).collect();
    t.extend(knots.interior_breaks().into_iter().map(|(k, _)| k));
    t.sort_by(f64::total_cmp);
    t.dedup();
    t
}

/// Largest and smallest Gaussian curvature `K = (LN - M^2) / (EG - F^2)` (The NURBS Book's
/// fundamental forms; `SurfaceDerivatives::curvature`) over a grid of `grid` uniform parameter
/// values per direction (at least 2) joined with the distinct interior knots of each direction
/// (the knot lines). A point is skipped as degenerate where the curvature is undefined
/// (`S_u x S_v = 0`, e.g. along a section collapsed to a point at a stem) or where
/// `|S_u x S_v|` is round-off: at most `1e-9` ([`COINCIDENT_REL`]) of the square of the
/// control net's size per unit parameter area. `None` if every point is degenerate.
pub fn gaussian_curvature_range(surface: &NurbsSurface, grid: usize) -> Option<CurvatureRange> {
    let us = sample_params(surface.knots_u(), grid);
    let vs = sample_params(surface.knots_v(), grid);
    let (lo, hi) = surface.control_bounds();
    let size = (hi - lo).norm();
    let (au, bu) = surface.domain_u();
    let (av, bv) = surface.domain_v();
    let area_tol = COINCIDENT_REL * size * size / ((bu - au) * (bv - av));
    let (mut max, mut min) = (f64::NEG_INFINITY, f64::INFINITY);
    let (mut max_at, mut min_at) = ([0.0; 2], [0.0; 2]);
    let (mut samples, mut skipped) = (0, 0);
    // The grid evaluated at once (v-major, each node that of `surface.derivatives`), read
    // u-major.
    let grid = surface.derivatives_grid(&us, &vs);
    for (i, &u) in us.iter().enumerate() {
        for (j, &v) in vs.iter().enumerate() {
            let d = grid[j * us.len() + i];
            let k = if d.su.cross(d.sv).norm() > area_tol { d.curvature().map(|c| c.gaussian) } else { None };
            match k.filter(|k| k.is_finite()) {
                Some(k) => {
                    samples += 1;
                    if k > max {
                        (max, max_at) = (k, [u, v]);
                    }
                    if k < min {
                        (min, min_at) = (k, [u, v]);
                    }
                }
                None => skipped += 1,
            }
        }
    }
    (samples > 0).then_some(CurvatureRange { max, min, max_at, min_at, samples, skipped })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::{assert_near, Vec3};

    fn bilinear(p00: Vec3, p01: Vec3, p10: Vec3, p11: Vec3) -> NurbsSurface {
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        NurbsSurface::try_new(k.clone(), k, &[p00, p01, p10, p11], None).expect("valid")
    }

    #[test]
    fn curvature_range_of_the_saddle_z_eq_xy() {
        // S(u, v) = (u, v, u v): K = -1 / (1 + u^2 + v^2)^2, largest -1/9 at (1, 1), smallest
        // -1 at (0, 0); both corners are grid points. Round-off of the fundamental forms: 1e-14.
        let s = bilinear(Vec3::new(0., 0., 0.), Vec3::new(0., 1., 0.), Vec3::new(1., 0., 0.), Vec3::new(1., 1., 1.));
        let k = gaussian_curvature_range(&s, CURVATURE_GRID).expect("regular surface");
        assert_near!(k.max, -1.0 / 9.0, 1e-14);
        assert_near!(k.min, -1.0, 1e-14);
        assert_eq!((k.max_at, k.min_at), ([1.0, 1.0], [0.0, 0.0]));
        assert_eq!((k.samples, k.skipped), (41 * 41, 0));
    }

    #[test]
    fn degenerate_edge_is_skipped_and_counted() {
        // A triangle: the edge v = 0 collapses to one point (P00 = P10), so S_u = 0 there; the
        // rest is a plane (K = 0 exactly: all second derivatives lie in the plane).
        let o = Vec3::new(0., 0., 0.);
        let s = bilinear(o, Vec3::new(0., 1., 0.), o, Vec3::new(1., 1., 0.));
        let k = gaussian_curvature_range(&s, 11).expect("not all degenerate");
        assert_eq!(k.skipped, 11, "the 11 samples on v = 0");
        assert_eq!(k.samples, 11 * 10);
        assert_eq!((k.max, k.min), (0.0, 0.0));
        // All degenerate: a surface that is one point.
        let p = bilinear(o, o, o, o);
        assert!(gaussian_curvature_range(&p, 5).is_none());
    }

    #[test]
    fn knot_lines_join_the_grid() {
        let k = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.3, 0.5, 1., 1., 1., 1.]).expect("valid");
        let t = sample_params(&k, 3);
        assert_eq!(t, vec![0.0, 0.3, 0.5, 1.0]);
    }
}
