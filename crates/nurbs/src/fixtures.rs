//! Test data shared by the kernel's tests and, with the feature `fixtures`, by its integration
//! tests and benchmarks and the tests of the crates above it: one place for each fixture. Not
//! part of the API.
//!
//! Exact surfaces (a quarter cylinder in two placements, a half cylinder, a sphere octant), a full circle,
//! a wavy bicubic net, section families, and proptest strategies for random curves and
//! surfaces.

use std::f64::consts::FRAC_1_SQRT_2;

use proptest::prelude::*;

use crate::{Homogeneous, KnotVector, NurbsCurve, NurbsSurface, Vec3};

/// The quarter cylinder `x^2 + y^2 = r^2`, `x, y >= 0`, `0 <= z <= h`: rational quadratic in
/// u (middle weight 1/sqrt 2; u = 0 at `(r, 0)`, u = 1 at `(0, r)`), linear in v (`z = h v`).
pub fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
    let ku = KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
    let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for (x, y, wi) in [(r, 0.0, 1.0), (r, r, FRAC_1_SQRT_2), (0.0, r, 1.0)] {
        for z in [0.0, h] {
            pts.push(Vec3::new(x, y, z));
            w.push(wi);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// The same quarter cylinder lying along x: `y^2 + z^2 = r^2`, `y >= 0`, `z <= 0`,
/// `0 <= x <= h`; u from `(y, z) = (0, -r)` round to `(r, 0)` (middle weight 1/sqrt 2), v along
/// x (`x = h v`). The numbers of [`quarter_cylinder`] turned a quarter about y, written out so
/// that no `-0.0` appears.
pub fn quarter_cylinder_along_x(r: f64, h: f64) -> NurbsSurface {
    let ku = KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
    let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for (y, z, wi) in [(0.0, -r, 1.0), (r, -r, FRAC_1_SQRT_2), (r, 0.0, 1.0)] {
        for x in [0.0, h] {
            pts.push(Vec3::new(x, y, z));
            w.push(wi);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// Half a circular cylinder along x: radius `r`, axis at `(y, z) = (0, r)`, the section from
/// `(0, 0)` through `(r, r)` to `(0, 2r)`, two rational quadratic quarter arcs in u (knot 0.5
/// doubled); linear in v from x = 0 to `len`.
pub fn half_cylinder_along_x(r: f64, len: f64) -> NurbsSurface {
    let ku = KnotVector::try_new(2, vec![0., 0., 0., 0.5, 0.5, 1., 1., 1.]).expect("valid");
    let kv = KnotVector::try_new(1, vec![0., 0., 1., 1.]).expect("valid");
    let s = FRAC_1_SQRT_2;
    let section = [(0.0, 0.0, 1.0), (r, 0.0, s), (r, r, 1.0), (r, 2.0 * r, s), (0.0, 2.0 * r, 1.0)];
    let (mut pts, mut w) = (Vec::new(), Vec::new());
    for (y, z, wi) in section {
        for x in [0.0, len] {
            pts.push(Vec3::new(x, y, z));
            w.push(wi);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// The octant `x, y, z >= 0` of the sphere of radius `r` about the origin, as the quarter
/// meridian (pole `(0, 0, r)` at u = 0 to the equator `(r, 0, 0)` at u = 1) revolved by 90
/// degrees about z (v from the xz-plane to the yz-plane): biquadratic, weights `w_i w_j`. The
/// row `i = 0` collapses to the pole, where `S_v = 0`; `S_u x S_v` points out of the sphere.
/// `reversed_u()` gives u from the equator to the pole (the same numbers, rows reversed).
pub fn sphere_octant(r: f64) -> NurbsSurface {
    let k = || KnotVector::try_new(2, vec![0., 0., 0., 1., 1., 1.]).expect("valid");
    let s = FRAC_1_SQRT_2;
    let meridian = [(0.0, r, 1.0), (r, r, s), (r, 0.0, 1.0)]; // (radius, z, w)
    let turn = [(1.0, 0.0, 1.0), (1.0, 1.0, s), (0.0, 1.0, 1.0)]; // (cos, sin, w) of the net
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for &(rho, z, wi) in &meridian {
        for &(c, sn, wj) in &turn {
            pts.push(Vec3::new(rho * c, rho * sn, z));
            w.push(wi * wj);
        }
    }
    NurbsSurface::try_new(k(), k(), &pts, Some(&w)).expect("valid")
}

/// A full circle of radius `r` in the xy plane, 9-point rational quadratic (The NURBS Book
/// Ex. 7.2); u = 0 and u = 1 both at `(r, 0, 0)`.
pub fn circle(r: f64) -> NurbsCurve {
    let s = FRAC_1_SQRT_2;
    let pts = [(1., 0.), (1., 1.), (0., 1.), (-1., 1.), (-1., 0.), (-1., -1.), (0., -1.), (1., -1.), (1., 0.)]
        .map(|(x, y)| Vec3::new(r * x, r * y, 0.0));
    let w = [1., s, 1., s, 1., s, 1., s, 1.];
    let k = vec![0., 0., 0., 0.25, 0.25, 0.5, 0.5, 0.75, 0.75, 1., 1., 1.];
    NurbsCurve::try_new(KnotVector::try_new(2, k).expect("valid"), &pts, Some(&w)).expect("valid")
}

/// A deterministic rational surface with `nu x nv` control points, degrees `(p, q)`, non-uniform
/// knots and weights in [0.75, 1.25]; `collapse` pinches the first row to one point.
pub fn rational_surface(nu: usize, nv: usize, p: usize, q: usize, collapse: bool) -> NurbsSurface {
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

/// A wavy bicubic surface over `[0, n_u - 1] x [0, n_v - 1]` in x, y with heights `z(i, j)`,
/// uniform knots, optionally weighted, optionally with the first row collapsed to one point
/// (a pointed end).
pub fn bicubic(
    n_u: usize,
    n_v: usize,
    z: impl Fn(usize, usize) -> f64,
    w: Option<&[f64]>,
    collapse: bool,
) -> NurbsSurface {
    let ku = KnotVector::uniform(3, n_u).expect("valid");
    let kv = KnotVector::uniform(3, n_v).expect("valid");
    let mut pts = Vec::new();
    for i in 0..n_u {
        for j in 0..n_v {
            pts.push(if collapse && i == 0 {
                Vec3::new(0.0, 0.5 * n_v as f64, 0.0)
            } else {
                Vec3::new(i as f64, j as f64, z(i, j))
            });
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, w).expect("valid")
}

/// A random wavy rational [`bicubic`]: 4 to 8 by 4 to 7 control points, heights of +-0.4 on
/// the unit net, weights 0.7 to 1.4, half of them with a collapsed first row (a pointed end).
///
/// That bends the surface much more than a ship's offset table bends between its sections, yet
/// keeps every bend resolved by a projection's sampling grid. (Measured, outside the suite: with
/// +-0.6 and weights 0.5 to 2 the global closest point is still found in 79 999 of 80 000
/// queries; the miss, 0.2 % too far, was next to a collapsed edge.)
pub fn random_wavy_surface() -> impl Strategy<Value = NurbsSurface> {
    (4usize..9, 4usize..8, any::<bool>()).prop_flat_map(|(nu, nv, collapse)| {
        let n = nu * nv;
        (prop::collection::vec(-0.4f64..0.4, n), prop::collection::vec(0.7f64..1.4, n), Just((nu, nv, collapse)))
            .prop_map(|(z, w, (nu, nv, collapse))| bicubic(nu, nv, |i, j| z[i * nv + j], Some(&w), collapse))
    })
}

/// Interior knots in (0, 1), sorted, each value at most `p` times. Values come partly from
/// a coarse grid so that repeated knots (and parameters exactly on them) occur often.
pub fn interior_knots(p: usize, max: usize) -> impl Strategy<Value = Vec<f64>> {
    prop::collection::vec(prop_oneof![(1u32..10).prop_map(|k| f64::from(k) / 10.0), 0.001f64..0.999], 0..max).prop_map(
        move |mut v| {
            v.sort_by(f64::total_cmp);
            let mut out: Vec<f64> = Vec::new();
            for x in v {
                if out.iter().filter(|&&y| y == x).count() < p {
                    out.push(x);
                }
            }
            out
        },
    )
}

/// The clamped knot vector of degree `p` on [0, 1] with the given interior knots.
pub fn clamped(p: usize, interior: &[f64]) -> KnotVector {
    let mut k = vec![0.0; p + 1];
    k.extend_from_slice(interior);
    k.extend(std::iter::repeat_n(1.0, p + 1));
    KnotVector::try_new(p, k).expect("clamped by construction")
}

/// `n` random homogeneous points: coordinates in [-10, 10], weights in [0.2, 5].
fn homogeneous_points(n: usize) -> impl Strategy<Value = Vec<Homogeneous>> {
    prop::collection::vec((-10.0f64..10.0, -10.0f64..10.0, -10.0f64..10.0, 0.2f64..5.0), n)
        .prop_map(|v| v.into_iter().map(|(x, y, z, w)| [x * w, y * w, z * w, w]).collect())
}

/// Random rational curves of degree 1 to 5 with up to 8 interior knots, some repeated.
pub fn arb_curve() -> impl Strategy<Value = NurbsCurve> {
    (1usize..=5)
        .prop_flat_map(|p| (Just(p), interior_knots(p, 9)))
        .prop_flat_map(|(p, interior)| {
            let kv = clamped(p, &interior);
            let n = kv.num_basis();
            (Just(kv), homogeneous_points(n))
        })
        .prop_map(|(kv, cw)| NurbsCurve::try_from_homogeneous(kv, cw).expect("valid by construction"))
}

/// Random rational surfaces of degrees 1 to 4 with up to 5 interior knots per direction.
pub fn arb_surface() -> impl Strategy<Value = NurbsSurface> {
    (1usize..=4, 1usize..=4)
        .prop_flat_map(|(p, q)| (Just(p), Just(q), interior_knots(p, 6), interior_knots(q, 6)))
        .prop_flat_map(|(p, q, iu, iv)| {
            let (ku, kv) = (clamped(p, &iu), clamped(q, &iv));
            let n = ku.num_basis() * kv.num_basis();
            (Just(ku), Just(kv), homogeneous_points(n))
        })
        .prop_map(|(ku, kv, cw)| NurbsSurface::try_from_homogeneous(ku, kv, cw).expect("valid by construction"))
}

/// A rounded-box section at `x`: a straight run on the plane `z = 0` from `(0, 0)` to
/// `(b - r, 0)` in `n_flat` chords, a quarter circle of radius `r` in 3 chords, a straight
/// run on the plane `y = b` from `(b, r)` to `(b, h)` in `n_side` chords.
pub fn rounded_box_section(x: f64, b: f64, r: f64, h: f64, n_flat: usize, n_side: usize) -> Vec<Vec3> {
    let mut pts: Vec<Vec3> =
        (0..=n_flat).map(|i| Vec3::new(x, (b - r) * i as f64 / n_flat.max(1) as f64, 0.0)).collect();
    if n_flat == 0 {
        pts.truncate(1);
    }
    for i in 1..=3 {
        let a = std::f64::consts::FRAC_PI_2 * i as f64 / 3.0;
        pts.push(Vec3::new(x, b - r + r * a.sin(), r - r * a.cos()));
    }
    pts.extend((1..=n_side).map(|i| Vec3::new(x, b, r + (h - r) * i as f64 / n_side as f64)));
    pts
}

/// 9 sections: the middle 5 rounded boxes (on `z = 0` to `y = 2`, on `y = 3` from `z = 1`),
/// the two at each end narrower quarter ellipses.
pub fn rounded_box_sections() -> Vec<Vec<Vec3>> {
    (0..9)
        .map(|k| {
            let x = k as f64;
            if (2..7).contains(&k) {
                rounded_box_section(x, 3.0, 1.0, 4.0, 4, 3)
            } else {
                let b = 2.0 + 0.3 * (k as f64 - 4.0).abs().min(3.0).recip();
                // Round, narrower, 8 points.
                (0..8)
                    .map(|i| std::f64::consts::FRAC_PI_2 * i as f64 / 7.0)
                    .map(|a| Vec3::new(x, b * a.sin(), 4.0 * (1.0 - a.cos())))
                    .collect()
            }
        })
        .collect()
}

/// The R/V Gunnerus sections of `testdata/gunnerus_sections.csv` (`section,x,y,z`, one row per
/// point, a section's rows together; the offset table's points, see `testdata/README.md`): 62
/// sections of 8 to 16 points, bottom to top.
pub fn gunnerus_sections() -> Vec<Vec<Vec3>> {
    let text = include_str!("../../../testdata/gunnerus_sections.csv");
    let mut sections: Vec<(&str, Vec<Vec3>)> = Vec::new();
    for line in text.lines().skip(1).filter(|l| !l.trim().is_empty()) {
        let f: Vec<&str> = line.split(',').collect();
        let num = |i: usize| -> f64 { f[i].trim().parse().expect("a number") };
        let p = Vec3::new(num(1), num(2), num(3));
        match sections.last_mut() {
            Some((label, pts)) if *label == f[0] => pts.push(p),
            _ => sections.push((f[0], vec![p])),
        }
    }
    sections.into_iter().map(|(_, pts)| pts).collect()
}
