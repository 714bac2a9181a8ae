//! Unit tests of planar cuts on closed-form sheets.

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
