//! Unit tests of planar cuts on closed-form surfaces: sheets, a half cylinder, a sphere octant
//! through its pole, a flat-bottomed patch.

use super::*;
use crate::KnotVector;

/// A bilinear-in-x, quadratic-in-z test sheet `y = a + b z^2` over x in [0, 1], z in [0, 1].
fn parabolic_sheet(a: f64, b: f64) -> NurbsSurface {
    let ku = KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
    let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
    // z = u, y = a + b u^2: Bernstein coefficients of u^2 are (0, 0, 1).
    let mut pts = Vec::new();
    for (z, y) in [(0.0, a), (0.5, a), (1.0, a + b)] {
        for x in [0.0, 1.0] {
            pts.push(Vec3::new(x, y, z));
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, None).expect("valid")
}

#[test]
fn three_point_curvature_of_a_circle_is_one_over_radius_and_signed() {
    let r = 2.5;
    let pt = |a: f64| [r * a.cos(), r * a.sin()];
    let k = three_point_curvature(pt(0.1), pt(0.3), pt(0.5)).expect("distinct");
    // Three points on a circle define it exactly: round-off only.
    assert!((k - 1.0 / r).abs() <= 1e-12, "{k}");
    let k = three_point_curvature(pt(0.5), pt(0.3), pt(0.1)).expect("distinct");
    assert!((k + 1.0 / r).abs() <= 1e-12, "{k}");
    assert_eq!(three_point_curvature([0., 0.], [0., 0.], [1., 1.]), None);
}

#[test]
fn an_x_cut_of_a_parabolic_sheet_is_the_parabola_with_its_curvature() {
    let (a, b) = (0.3, 0.8);
    let s = parabolic_sheet(a, b);
    let cuts = cut_surface(&s, AxisPlane::x(0.37), &CutOptions::default());
    assert_eq!(cuts.len(), 1);
    let c = &cuts[0];
    // z increasing (the x-plane rule): from 0 to 1.
    assert!(c.points[0].point.z.abs() <= 1e-12 && (c.points[c.points.len() - 1].point.z - 1.0).abs() <= 1e-12);
    for p in &c.points {
        let z = p.point.z;
        // y = a + b z^2 traversed with z increasing in (y, z): kappa = -y''/(1+y'^2)^1.5
        // with y as a function of z: the curve (y(z), z) has y' = 2 b z, y'' = 2 b and turns
        // clockwise (kappa < 0) for b > 0.
        let want = -(2.0 * b) / (1.0 + (2.0 * b * z).powi(2)).powf(1.5);
        assert!((p.curvature - want).abs() <= 1e-12, "z {z}: {} vs {want}", p.curvature);
        assert!((p.point.y - (a + b * z * z)).abs() <= 1e-12);
        assert!((p.point.x - 0.37).abs() <= 1e-14);
    }
}

#[test]
fn plane_missing_the_surface_or_non_finite_gives_nothing() {
    let s = parabolic_sheet(0.3, 0.8);
    assert!(cut_surface(&s, AxisPlane::x(2.0), &CutOptions::default()).is_empty());
    assert!(cut_surface(&s, AxisPlane::z(-1.0), &CutOptions::default()).is_empty());
    assert!(cut_surface(&s, AxisPlane::y(f64::NAN), &CutOptions::default()).is_empty());
}

#[test]
fn a_boundary_edge_in_the_plane_is_found_from_either_side() {
    let s = parabolic_sheet(0.3, 0.8);
    // x = 0 and x = 1 are the v edges; the surface lies on one side of each.
    for x in [0.0, 1.0] {
        let cuts = cut_surface(&s, AxisPlane::x(x), &CutOptions::default());
        assert_eq!(cuts.len(), 1, "x = {x}");
        assert!(cuts[0].points.iter().all(|p| (p.point.x - x).abs() <= 1e-15));
        let zs: Vec<f64> = cuts[0].points.iter().map(|p| p.point.z).collect();
        assert!(zs.windows(2).all(|w| w[1] > w[0]), "z increasing");
    }
}

/// A cubic patch whose first knot span in u is exactly flat at z = 0 (out to the knot line
/// `u = 0.4`), then a rounded turn and a vertical side; its breadth varies along x.
fn flat_bottomed_patch() -> NurbsSurface {
    let ku = KnotVector::try_new(3, vec![0., 0., 0., 0., 0.4, 0.7, 1., 1., 1., 1.]).expect("valid");
    let kv = KnotVector::try_new(3, vec![0., 0., 0., 0., 1., 1., 1., 1.]).expect("valid");
    let section = [(0.0, 0.0), (1.0, 0.0), (2.0, 0.0), (3.0, 0.0), (4.0, 1.0), (4.0, 3.0)];
    let breadth = [0.6, 1.0, 1.0, 0.7];
    let mut pts = Vec::new();
    for (y, z) in section {
        for (j, b) in breadth.iter().enumerate() {
            pts.push(Vec3::new(10.0 * j as f64 / 3.0, y * b, z));
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, None).expect("valid")
}

/// Every point of every branch lies on its plane to `rel` of the model size `size`.
fn assert_on_plane(cuts: &[CutCurve], size: f64, rel: f64) {
    for c in cuts {
        for p in &c.points {
            assert!(c.plane.distance(p.point) <= rel * size, "{:?}: point {:?} off the plane", c.plane, p.point);
        }
    }
}

#[test]
fn an_x_cut_of_a_half_cylinder_is_a_counter_clockwise_half_circle_of_curvature_one_over_r() {
    let r = 2.5;
    let s = crate::fixtures::half_cylinder_along_x(r, 12.0);
    let size = s.model_size().expect("a finite net");
    let cuts = cut_surface(&s, AxisPlane::x(4.0), &CutOptions::default());
    assert_eq!(cuts.len(), 1);
    let c = &cuts[0];
    assert_on_plane(&cuts, size, 1e-12);
    let (mut worst_r, mut worst_k): (f64, f64) = (0.0, 0.0);
    for p in &c.points {
        worst_r = worst_r.max(((p.point.y).hypot(p.point.z - r) - r).abs());
        worst_k = worst_k.max((p.curvature - 1.0 / r).abs() * r);
    }
    eprintln!("half cylinder x = 4: radius {worst_r:e}, kappa {worst_k:e} (rel), {} points", c.points.len());
    // Exact rational arcs: round-off only.
    assert!(worst_r <= 1e-12 && worst_k <= 1e-10, "{worst_r:e} {worst_k:e}");
    // Bottom to top, and the polyline turns by at most the asked 2 degrees per point.
    assert!(c.points[0].point.z.abs() <= 1e-12 && (c.points[c.points.len() - 1].point.z - 2.0 * r).abs() <= 1e-12);
    let xy = c.coords();
    for w in xy.windows(3) {
        let (a, b) = ([w[1][0] - w[0][0], w[1][1] - w[0][1]], [w[2][0] - w[1][0], w[2][1] - w[1][1]]);
        let turn = (a[0] * b[1] - a[1] * b[0]).atan2(a[0] * b[0] + a[1] * b[1]);
        assert!(turn > 0.0 && turn <= 2f64.to_radians() + 1e-12, "turn {}", turn.to_degrees());
    }
    // Half a circle: pi r, to the chord sag of 2-degree segments (1 - sinc(1 deg) ~ 5e-5).
    assert!((c.length() - std::f64::consts::PI * r).abs() <= 1e-4 * r, "{}", c.length());
}

#[test]
fn sphere_sections_have_curvature_of_their_circle_even_through_the_pole() {
    let r = 3.0;
    // Equator at u = 0, the pole (a collapsed edge) at u = 1.
    let s = crate::fixtures::sphere_octant(r).reversed_u();
    let size = s.model_size().expect("a finite net");
    let opts = CutOptions::default();
    // x = c cuts the octant in an arc of radius sqrt(r^2 - c^2); x = 0 and y = 0 are the
    // boundary meridians, which end at the pole (the collapsed edge u = 1).
    for plane in [AxisPlane::x(1.0), AxisPlane::x(2.9), AxisPlane::x(0.0), AxisPlane::y(0.0)] {
        let cuts = cut_surface(&s, plane, &opts);
        assert_eq!(cuts.len(), 1, "{plane:?}");
        assert_on_plane(&cuts, size, 1e-12);
        let rc = (r * r - plane.value.powi(2)).sqrt();
        let mut worst: f64 = 0.0;
        for p in &cuts[0].points {
            assert!((p.point.norm() - r).abs() <= 1e-12, "{:?} off the sphere", p.point);
            assert!(p.curvature.is_finite());
            worst = worst.max((p.curvature.abs() - 1.0 / rc).abs() * rc);
        }
        eprintln!("sphere {plane:?}: |kappa| r_c - 1 <= {worst:e}, {} points", cuts[0].points.len());
        // Analytic away from the pole, discrete (2-degree circle fit: exact on a circle up to
        // round-off) at it.
        assert!(worst <= 1e-6, "{plane:?}: {worst:e}");
    }
    // The tangent plane at the pole touches the patch at one point: no branch.
    assert!(cut_surface(&s, AxisPlane::z(r), &opts).is_empty());
}

#[test]
fn the_z_cut_at_a_flat_bottom_is_the_edge_of_the_flat() {
    let s = flat_bottomed_patch();
    let size = s.model_size().expect("a finite net");
    let cuts = cut_surface(&s, AxisPlane::z(0.0), &CutOptions::default());
    assert_eq!(cuts.len(), 1);
    let c = &cuts[0];
    // The flat is exactly z = 0: the points are on the plane to round-off.
    assert_on_plane(&cuts, size, 1e-15);
    assert!(c.points.iter().all(|p| p.curvature.is_finite()));
    // It is the edge of the flat: the knot line u = 0.4, where the rounded turn starts.
    for p in &c.points {
        assert!((p.uv.0 - 0.4).abs() <= 1e-9, "u = {}", p.uv.0);
    }
    let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
    assert!(first.x.abs() <= 1e-12 && (last.x - 10.0).abs() <= 1e-12);
    // A z-plane just above: one branch on the turn, outside the flat.
    let above = cut_surface(&s, AxisPlane::z(0.01), &CutOptions::default());
    assert_eq!(above.len(), 1);
    assert!(above[0].points.iter().all(|p| p.uv.0 > 0.4));
}
