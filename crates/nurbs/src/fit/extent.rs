//! The extent of point data: the size of a family of sections and whether a section is a
//! single point.

use crate::tolerance::COINCIDENT_REL;
use crate::Vec3;

/// The diagonal of the axis-aligned bounding box of `points` (0 without points): the size
/// that relative tolerances such as [`COINCIDENT_REL`] are taken of.
///
/// ```
/// use nurbs::{fit::bounding_diagonal, Vec3};
/// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(1.0, 2.0, 0.0), Vec3::new(0.5, 0.0, 2.0)];
/// // The box is 1 x 2 x 2: its diagonal is 3.
/// assert_eq!(bounding_diagonal(&pts), 3.0);
/// assert_eq!(bounding_diagonal(&[]), 0.0);
/// ```
pub fn bounding_diagonal<'a>(points: impl IntoIterator<Item = &'a Vec3>) -> f64 {
    let mut pts = points.into_iter();
    let Some(&first) = pts.next() else { return 0.0 };
    let (lo, hi) = pts.fold((first, first), |(lo, hi), p| {
        (Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)), Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)))
    });
    (hi - lo).norm()
}

/// Whether a section has extent: not all of its points within [`COINCIDENT_REL`] of the data's
/// `size` of the first (the same test as the skinning's degenerate sections). An empty
/// section has none.
pub fn has_extent(points: &[Vec3], size: f64) -> bool {
    points.first().is_some_and(|&c| points.iter().any(|p| p.distance(c) > COINCIDENT_REL * size))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_point_has_no_extent_and_a_segment_has() {
        let p = Vec3::new(1.0, 2.0, 3.0);
        assert!(!has_extent(&[p; 4], 10.0));
        assert!(!has_extent(&[], 10.0));
        assert!(has_extent(&[p, p + Vec3::new(0.0, 1e-6, 0.0)], 10.0));
        // Within the tolerance of the size: one point.
        assert!(!has_extent(&[p, p + Vec3::new(0.0, 0.5 * COINCIDENT_REL, 0.0)], 1.0));
    }
}
