//! Cross-check against an independent NURBS library, curvo 0.3.3: points and derivatives of
//! random rational curves and surfaces, knot refinement and degree elevation.
//!
//! curvo stores control points homogeneously and weighted, `Point4 = (w x, w y, w z, w)`
//! (`point_in_span` sums `P^w` times the basis functions, `dehomogenize` divides by the last
//! coordinate), the same as our [`nurbs::Homogeneous`]; its surface net `control_points[i][j]`
//! has `i` along u, our index `i * n_v + j`. Its span search takes the span to the right of an
//! interior knot, as ours does, so even one-sided derivatives are comparable.

use curvo::prelude::{NurbsCurve3D, NurbsSurface3D, UVDirection};
use nalgebra::Point4;
use nurbs::fixtures::{arb_curve, arb_surface, clamped, interior_knots};
use nurbs::{Homogeneous, KnotVector, NurbsCurve, NurbsSurface, Vec3};
use proptest::prelude::*;

/// Both libraries run the same textbook algorithms (A2.2/A2.3 basis functions, A4.2/A4.4
/// rational derivatives, A5.4 refinement) in f64, differing in summation order. With weights
/// in [0.2, 5] the rational quotient amplifies round-off by at most 25; 1e-11 relative to the
/// scale of each quantity leaves a wide margin (measured: curve points and derivatives agree
/// bit for bit, surface values to 1.4e-15, refined nets to 3e-16), while any real discrepancy
/// (a wrong span, index or weight) is O(1).
const REL: f64 = 1e-11;

fn to_point4(h: &Homogeneous) -> Point4<f64> {
    Point4::new(h[0], h[1], h[2], h[3])
}

fn v3(v: &nalgebra::Vector3<f64>) -> Vec3 {
    Vec3::new(v.x, v.y, v.z)
}

fn p3(p: &nalgebra::Point3<f64>) -> Vec3 {
    Vec3::new(p.x, p.y, p.z)
}

fn curvo_curve(c: &NurbsCurve) -> NurbsCurve3D<f64> {
    NurbsCurve3D::try_new(c.degree(), c.homogeneous().iter().map(to_point4).collect(), c.knots().as_slice().to_vec())
        .expect("curvo accepts a valid clamped curve")
}

fn curvo_surface(s: &NurbsSurface) -> NurbsSurface3D<f64> {
    let nv = s.n_v();
    let net = s.homogeneous().chunks(nv).map(|row| row.iter().map(to_point4).collect()).collect();
    NurbsSurface3D::new(
        s.degree_u(),
        s.degree_v(),
        s.knots_u().as_slice().to_vec(),
        s.knots_v().as_slice().to_vec(),
        net,
    )
}

/// Parameters to compare at: a regular grid, the knots themselves and random values.
fn parameters(kv: &KnotVector, extra: &[f64]) -> Vec<f64> {
    let mut t: Vec<f64> = (0..=20).map(|i| f64::from(i) / 20.0).collect();
    t.extend_from_slice(kv.as_slice());
    t.extend_from_slice(extra);
    t
}

fn size(points: &[Vec3]) -> f64 {
    points.iter().map(|p| p.norm()).fold(1.0, f64::max)
}

/// `|a - b| <= REL * scale` for each pair, with the pair's label on failure.
/// Our homogeneous control point `a` and curvo's `b`, as the (ours, theirs, label) pairs of
/// [`assert_close`]: `P^w_at` (x, y, z) and `w_at` (the weight).
fn homogeneous_pairs(a: &Homogeneous, b: &Point4<f64>, at: &str) -> [(Vec3, Vec3, String); 2] {
    [
        (Vec3::new(a[0], a[1], a[2]), Vec3::new(b.x, b.y, b.z), format!("P^w_{at}")),
        (Vec3::new(a[3], 0.0, 0.0), Vec3::new(b.w, 0.0, 0.0), format!("w_{at}")),
    ]
}

/// [`homogeneous_pairs`] of every control point of two curves, in order (curvo's extra
/// trailing points, if any, left out).
fn curve_pairs(ours: &NurbsCurve, theirs: &NurbsCurve3D<f64>) -> Vec<(Vec3, Vec3, String)> {
    ours.homogeneous()
        .iter()
        .zip(theirs.control_points())
        .enumerate()
        .flat_map(|(i, (a, b))| homogeneous_pairs(a, b, &i.to_string()))
        .collect()
}

fn assert_close(pairs: &[(Vec3, Vec3, String)], scale: f64) -> Result<(), TestCaseError> {
    for (a, b, at) in pairs {
        prop_assert!((*a - *b).norm() <= REL * scale, "{at}: ours {a:?}, curvo {b:?}, scale {scale:e}");
    }
    Ok(())
}

/// The largest norm among the reference values, the scale of a derivative.
fn scale_of(pairs: &[(Vec3, Vec3, String)], floor: f64) -> f64 {
    pairs.iter().map(|p| p.1.norm()).fold(floor, f64::max)
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    #[test]
    fn curve_points_and_derivatives_agree(c in arb_curve(), extra in prop::collection::vec(0.0f64..1.0, 5)) {
        let theirs = curvo_curve(&c);
        let mut points = Vec::new();
        let mut firsts = Vec::new();
        for u in parameters(c.knots(), &extra) {
            let ours = c.derivatives(u, 1);
            let d = theirs.rational_derivatives(u, 1);
            points.push((c.point(u), p3(&theirs.point_at(u)), format!("C({u})")));
            points.push((ours[0], v3(&d[0]), format!("C({u}) from derivatives")));
            firsts.push((ours[1], v3(&d[1]), format!("C'({u})")));
        }
        assert_close(&points, size(&c.control_points()))?;
        assert_close(&firsts, scale_of(&firsts, 1.0))?;
    }

    #[test]
    fn surface_points_and_derivatives_agree(
        s in arb_surface(),
        eu in prop::collection::vec(0.0f64..1.0, 3),
        ev in prop::collection::vec(0.0f64..1.0, 3),
    ) {
        let theirs = curvo_surface(&s);
        // curvo's second derivatives need both degrees >= 2 (it sizes its table by the lower).
        let order = if s.degree_u() >= 2 && s.degree_v() >= 2 { 2 } else { 1 };
        let (mut points, mut firsts, mut seconds) = (Vec::new(), Vec::new(), Vec::new());
        for u in parameters(s.knots_u(), &eu) {
            for v in parameters(s.knots_v(), &ev) {
                let ours = s.derivatives(u, v);
                let d = theirs.rational_derivatives(u, v, order);
                points.push((s.point(u, v), p3(&theirs.point_at(u, v)), format!("S({u}, {v})")));
                points.push((ours.point, v3(&d[0][0]), format!("S({u}, {v}) from derivatives")));
                firsts.push((ours.su, v3(&d[1][0]), format!("S_u({u}, {v})")));
                firsts.push((ours.sv, v3(&d[0][1]), format!("S_v({u}, {v})")));
                if order == 2 {
                    seconds.push((ours.suu, v3(&d[2][0]), format!("S_uu({u}, {v})")));
                    seconds.push((ours.suv, v3(&d[1][1]), format!("S_uv({u}, {v})")));
                    seconds.push((ours.svv, v3(&d[0][2]), format!("S_vv({u}, {v})")));
                }
            }
        }
        assert_close(&points, size(&s.control_points()))?;
        assert_close(&firsts, scale_of(&firsts, 1.0))?;
        assert_close(&seconds, scale_of(&seconds, 1.0))?;
    }

    #[test]
    fn curve_refinement_agrees(c in arb_curve(), x in interior_knots(1, 8)) {
        let x: Vec<f64> = x.into_iter().filter(|&v| c.knots().multiplicity(v) < c.degree()).collect();
        let ours = c.refine_knots(&x).expect("legal refinement");
        let mut theirs = curvo_curve(&c);
        theirs.try_refine_knot(x.clone()).expect("curvo refines too");
        prop_assert_eq!(ours.knots().as_slice().to_vec(), theirs.knots().to_vec());
        let pairs = curve_pairs(&ours, &theirs);
        prop_assert_eq!(ours.num_control_points(), theirs.control_points().len());
        // Homogeneous coordinates reach |w P| <= 50.
        assert_close(&pairs, 50.0)?;
    }

    #[test]
    fn surface_refinement_agrees(s in arb_surface(), x in interior_knots(1, 4), y in interior_knots(1, 4)) {
        let x: Vec<f64> = x.into_iter().filter(|&v| s.knots_u().multiplicity(v) < s.degree_u()).collect();
        let y: Vec<f64> = y.into_iter().filter(|&v| s.knots_v().multiplicity(v) < s.degree_v()).collect();
        let ours = s.refine_knots_u(&x).and_then(|t| t.refine_knots_v(&y)).expect("legal refinement");
        let mut theirs = curvo_surface(&s);
        if !x.is_empty() {
            theirs.try_refine_knot(x.clone(), UVDirection::U).expect("curvo refines in u");
        }
        if !y.is_empty() {
            theirs.try_refine_knot(y.clone(), UVDirection::V).expect("curvo refines in v");
        }
        prop_assert_eq!(ours.knots_u().as_slice().to_vec(), theirs.u_knots().to_vec());
        prop_assert_eq!(ours.knots_v().as_slice().to_vec(), theirs.v_knots().to_vec());
        let net = theirs.control_points();
        prop_assert_eq!((net.len(), net[0].len()), (ours.n_u(), ours.n_v()));
        let mut pairs = Vec::new();
        for (i, row) in net.iter().enumerate() {
            for (j, b) in row.iter().enumerate() {
                pairs.extend(homogeneous_pairs(&ours.homogeneous()[i * ours.n_v() + j], b, &format!("{i},{j}")));
            }
        }
        assert_close(&pairs, 50.0)?;
    }

    #[test]
    fn bezier_elevation_agrees(
        p in 1usize..=5,
        seed in prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0, 0.2f64..5.0), 6),
    ) {
        // Only Bezier curves raised by one: curvo 0.3.3's `try_elevate_degree` (its A5.9 port)
        // panics on curves with two or more interior knots (it sizes its output for one
        // segment), underflows for t >= 2, and misplaces the `bet` branch of the knot removal.
        // Even here it pads its output with 3 unused control points (and their knots), so only
        // the leading entries are compared.
        let t = 1;
        let kv = clamped(p, &[]);
        let cw: Vec<Homogeneous> = seed[..=p].iter().map(|&(x, y, z, w)| [x * w, y * w, z * w, w]).collect();
        let c = NurbsCurve::try_from_homogeneous(kv, cw).expect("valid");
        let ours = c.elevate_degree(t).expect("small degree");
        let theirs = curvo_curve(&c).try_elevate_degree(p + t).expect("curvo elevates");
        let (n, m) = (ours.num_control_points(), ours.knots().as_slice().len());
        prop_assert_eq!(theirs.control_points().len(), n + 3);
        prop_assert_eq!(ours.knots().as_slice(), &theirs.knots().to_vec()[..m]);
        let pairs = curve_pairs(&ours, &theirs);
        assert_close(&pairs, 50.0)?;
    }
}
