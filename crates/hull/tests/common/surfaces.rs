//! Surfaces and sample points shared by the export checks (IGES, STEP).

use nurbs::{NurbsSurface, Vec3};

/// The same surface with every control point multiplied by `k` (a change of length unit).
pub fn scaled(s: &NurbsSurface, k: f64) -> NurbsSurface {
    let pts: Vec<Vec3> = s.control_points().iter().map(|&p| p * k).collect();
    NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, Some(&s.weights())).expect("valid")
}

/// A 9 x 9 grid over the domain, boundaries included, plus 7 irregular interior points: 88.
pub fn samples(s: &NurbsSurface) -> Vec<[f64; 5]> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut uv: Vec<(f64, f64)> = Vec::new();
    for a in 0..=8 {
        for b in 0..=8 {
            uv.push((u0 + (u1 - u0) * a as f64 / 8.0, v0 + (v1 - v0) * b as f64 / 8.0));
        }
    }
    for k in 1..=7 {
        let (a, b) = ((k as f64 * 0.618_034).fract(), (k as f64 * 0.414_214).fract());
        uv.push((u0 + (u1 - u0) * a, v0 + (v1 - v0) * b));
    }
    uv.into_iter()
        .map(|(u, v)| {
            let p = s.point(u, v);
            [u, v, p.x, p.y, p.z]
        })
        .collect()
}
