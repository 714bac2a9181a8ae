//! Runs of consecutive points on a plane: where a polyline lies in a plane and where it
//! leaves it.

use crate::{AxisPlane, Vec3};

/// One interior end of a run of points on a plane ([`plane_run_ends`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct RunEnd {
    /// The index of the run's last point on the plane at this end.
    pub index: usize,
    /// `true` at the run's upper end (the run lies before it), `false` at its lower end.
    pub upper: bool,
}

/// The interior ends of the longest run of at least `min_points` (at least 2) consecutive
/// points within `tol` of `plane`, the first such run on a tie: where the polyline leaves the
/// plane. An end that is the first or last point of `points` meets nothing and is left out.
///
/// ```
/// use nurbs::fit::{plane_run_ends, RunEnd};
/// use nurbs::{AxisPlane, Vec3};
/// // Along z = 0 for three points, then up.
/// let pts = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 1.0), (3.0, 2.0)].map(|(y, z)| Vec3::new(0.0, y, z));
/// assert_eq!(plane_run_ends(&pts, AxisPlane::z(0.0), 1e-12, 3), vec![RunEnd { index: 2, upper: true }]);
/// // Two points on the plane are not a run of three.
/// assert!(plane_run_ends(&pts, AxisPlane::z(0.0), 1e-12, 4).is_empty());
/// ```
pub fn plane_run_ends(points: &[Vec3], plane: AxisPlane, tol: f64, min_points: usize) -> Vec<RunEnd> {
    let on = |p: &Vec3| plane.distance(*p) <= tol;
    let mut best: Option<(usize, usize)> = None;
    let mut i = 0;
    while i < points.len() {
        if !on(&points[i]) {
            i += 1;
            continue;
        }
        let start = i;
        while i < points.len() && on(&points[i]) {
            i += 1;
        }
        let len = i - start;
        if len >= min_points.max(2) && best.is_none_or(|(a, b)| len > b - a) {
            best = Some((start, i));
        }
    }
    let Some((a, b)) = best else { return Vec::new() };
    let mut out = Vec::new();
    if a > 0 {
        out.push(RunEnd { index: a, upper: false });
    }
    if b < points.len() {
        out.push(RunEnd { index: b - 1, upper: true });
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_longest_run_gives_both_interior_ends() {
        // Off, on x 2, off, on x 3, off: the second run, both ends interior.
        let ys = [1.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 2.0];
        let pts: Vec<Vec3> = ys.iter().enumerate().map(|(i, &y)| Vec3::new(i as f64, y, 0.0)).collect();
        let ends = plane_run_ends(&pts, AxisPlane::y(0.0), 0.0, 2);
        assert_eq!(ends, vec![RunEnd { index: 4, upper: false }, RunEnd { index: 6, upper: true }]);
        // All on the plane: a run without interior ends.
        assert!(plane_run_ends(&pts, AxisPlane::z(0.0), 0.0, 2).is_empty());
        // The tolerance decides what is on.
        assert_eq!(plane_run_ends(&pts, AxisPlane::y(0.0), 1.0, 2), vec![RunEnd { index: 6, upper: true }]);
        assert_eq!(AxisPlane::x(2.0).distance(Vec3::new(-1.0, 5.0, 5.0)), 3.0);
    }
}
