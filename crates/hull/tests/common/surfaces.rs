//! Surfaces and sample points shared by the export checks (IGES, STEP), the CAD readers and
//! the hydrostatics bench (which includes this file by path). The kernel's exact surfaces (the
//! quarter cylinder, the sphere octant) are in `nurbs::fixtures`.

use nurbs::{KnotVector, NurbsSurface, Vec3};

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

/// `s` with two of its weights (the third and fourth) changed to 0.9: a surface the export
/// checks must tell from `s`.
pub fn weights_changed(s: &NurbsSurface) -> NurbsSurface {
    let mut w = s.weights();
    w[2] = 0.9;
    w[3] = 0.9;
    NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &s.control_points(), Some(&w)).expect("valid")
}

/// (a) Rational bicubic, non-uniform knots with a double knot in v, v domain not [0, 1],
/// weights from 0.55 to 1.85: a hull-like half section swept along x.
pub fn rational_bicubic() -> NurbsSurface {
    let ku = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.15, 0.4, 0.42, 1.0, 1.0, 1.0, 1.0]).expect("valid");
    let kv = KnotVector::try_new(3, vec![-1.0, -1.0, -1.0, -1.0, 0.3, 0.3, 2.0, 4.5, 4.5, 4.5, 4.5]).expect("valid");
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (i as f64 / (nu - 1) as f64, j as f64 / (nv - 1) as f64);
            let beam = 8.0 * (1.0 - (2.0 * a - 1.0).powi(4));
            pts.push(Vec3::new(120.0 * a, beam * (b * 1.3).sin().min(1.0) + 0.01 * i as f64, 6.5 * b - 0.2 * a));
            w.push(0.55 + 1.3 * ((i * 7 + j * 3) % 11) as f64 / 10.0);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// (b) Polynomial, degree 2 in u and 3 in v, uniform knots, weights all 1.
pub fn polynomial() -> NurbsSurface {
    let ku = KnotVector::uniform(2, 6).expect("valid");
    let kv = KnotVector::uniform(3, 5).expect("valid");
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    let mut pts = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (x, y) = (i as f64 * 2.5, j as f64 * 1.25);
            pts.push(Vec3::new(x, y, 0.1 * x * x - 0.3 * x * y + 0.05 * y * y * y));
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, None).expect("valid")
}

/// The Wigley hull of length `l`, beam `b` and draft `t`, from the aft end: the library's
/// exact patch [`hull::wigley_hull`].
pub fn wigley_patch(l: f64, b: f64, t: f64) -> NurbsSurface {
    hull::wigley_hull(l, b, t)
}
