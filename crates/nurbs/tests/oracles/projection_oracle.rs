//! Closest points against Open CASCADE 8.0.1 (`GeomAPI_ProjectPointOnSurf`, global minimum),
//! from `testdata/oracle/surfaces.json` (copied from the shared oracle; see its README.md).

use nurbs::{KnotVector, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use serde_json::Value;

fn vec3(v: &Value) -> Vec3 {
    let a: Vec<f64> = v.as_array().expect("3-vector").iter().map(|x| x.as_f64().expect("number")).collect();
    assert_eq!(a.len(), 3, "a point has 3 coordinates");
    Vec3::new(a[0], a[1], a[2])
}

fn floats(v: &Value) -> Vec<f64> {
    v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect()
}

fn build(s: &Value) -> NurbsSurface {
    let deg = |k: &str| s[k].as_u64().expect("degree") as usize;
    let ku = KnotVector::try_new(deg("degree_u"), floats(&s["knots_u"])).expect("oracle knots are valid");
    let kv = KnotVector::try_new(deg("degree_v"), floats(&s["knots_v"])).expect("oracle knots are valid");
    let pts: Vec<Vec3> = s["ctrlpts"].as_array().expect("ctrlpts").iter().map(vec3).collect();
    // Polynomial surfaces have `"weights": null`.
    let w = if s["weights"].is_null() { None } else { Some(floats(&s["weights"])) };
    NurbsSurface::try_new(ku, kv, &pts, w.as_deref()).expect("oracle surface is valid")
}

#[test]
fn closest_points_match_open_cascade() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../../testdata/oracle/surfaces.json");
    let text = std::fs::read_to_string(path).expect("testdata/oracle/surfaces.json is committed");
    let root: Value = serde_json::from_str(&text).expect("valid JSON");
    let mut checked = 0;
    for entry in root["surfaces"].as_array().expect("surfaces") {
        let s = build(&entry["surface"]);
        let name = entry["surface"]["name"].as_str().unwrap_or("?");
        let (lo, hi) = s.control_bounds();
        let size = (hi - lo).norm();
        let proj = SurfaceProjector::new(&s, ProjectionOptions::default());
        for cp in entry["closest_points"].as_array().expect("closest_points") {
            let q = vec3(&cp["query"]);
            let occ_d = cp["distance"].as_f64().expect("distance");
            let occ_foot = vec3(&cp["foot"]);
            let r = proj.project(q);
            // At a minimum the distance is stationary: a parameter error e of either solver
            // changes it by O(e^2 |S_u|^2 / d) only, so both distances agree to evaluation
            // round-off (observed <= 3e-16 relative to the size); 1e-12 * size leaves 1000x room.
            let tol = 1e-12 * size;
            assert!(
                (r.distance - occ_d).abs() <= tol,
                "{name}: q = {q:?}: distance {} vs Open CASCADE {occ_d}",
                r.distance
            );
            // Never worse than the global minimum found by Open CASCADE.
            assert!(r.distance <= occ_d + tol, "{name}: q = {q:?}: a local minimum only");
            // The foot itself is first-order in Open CASCADE's parameter tolerance
            // (Precision::PConfusion = 1e-9) times |S_u|, observed up to 1.5e-10 * size.
            assert!(
                (r.point - occ_foot).norm() <= 1e-8 * size,
                "{name}: q = {q:?}: foot {:?} vs Open CASCADE {occ_foot:?}",
                r.point
            );
            assert!(r.converged, "{name}: projection of {q:?} did not converge");
            // `distance` is |S(u,v) - q| of our own evaluation.
            assert!((r.distance - (s.point(r.u, r.v) - q).norm()).abs() <= 1e-15 * size);
            checked += 1;
        }
    }
    assert_eq!(checked, 36, "six surfaces with six closest points each");
}
