//! Surfaces shared by the benchmarks.

use nurbs::{KnotVector, NurbsSurface, Vec3};

/// A deterministic rational surface with `nu x nv` control points, degrees `(p, q)`, non-uniform
/// knots and weights in [0.75, 1.25]; `collapse` pinches the first row to one point.
pub fn surface(nu: usize, nv: usize, p: usize, q: usize, collapse: bool) -> NurbsSurface {
    let knots = |n: usize, d: usize| {
        let mut k = vec![0.0; d + 1];
        let segs = n - d;
        for i in 1..segs {
            let t = i as f64 / segs as f64;
            k.push(t + 0.3 * t * (1.0 - t) * (i as f64).sin() / segs as f64);
        }
        k.extend(std::iter::repeat_n(1.0, d + 1));
        KnotVector::try_new(d, k).expect("valid knots")
    };
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64, j as f64);
            let y = if collapse && i == 0 { 0.0 } else { y };
            pts.push(Vec3::new(x, y, (0.7 * x).sin() * (0.5 * y).cos()));
            w.push(1.0 + 0.5 * ((i * 7 + j * 3) % 5) as f64 / 4.0 - 0.25);
        }
    }
    NurbsSurface::try_new(knots(nu, p), knots(nv, q), &pts, Some(&w)).expect("valid surface")
}
