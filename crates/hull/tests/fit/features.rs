//! Hull features inside one surface, on hulls that have them: the chine of a hard-chine
//! planing hull (made here, with its exact shape to measure against), the flats of the
//! Series 60 Cb 0.80 parent and of the 116 m cargo ship, the transom and bulb of R/V Gunnerus.

use hull::{fit_offsets, read_offsets, FitConfig, FitMethod, Knuckles, Offsets, Section, Units};
use nurbs::fit::CornerOptions;
use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};

use crate::common::testdata;

/// A hard-chine planing hull, length 12 m, 13 stations from the transom (x = 0) forward, its
/// exact shape given by [`planing_point`]: keel to chine a slightly convex bottom, chine to
/// sheer a slightly convex flared side. Offsets: 5 points on the bottom (keel and chine
/// included), 4 on the side above the chine.
const PLANING_L: f64 = 12.0;
const BOTTOM_CHORDS: usize = 4;
const SIDE_CHORDS: usize = 4;

/// The exact hull at `x`: `t` in `[0, 1]` runs keel to chine, `[1, 2]` chine to sheer.
/// Chine half-beam `b = 1.9 - 1.5 (x/L)^2.5`, keel height `0.5 (x/L)^3`, deadrise from 14
/// degrees at the transom to 34 at the bow, chine height `z_k + b tan(deadrise)`, sheer at
/// 1.9 m, flare 0.2 m; both the bottom and the side bulge out by `0.03 t (1 - t)` of their
/// length.
fn planing_point(x: f64, t: f64) -> Vec3 {
    let r = x / PLANING_L;
    let b = 1.9 - 1.5 * r.powf(2.5);
    let zk = 0.5 * r.powi(3);
    let beta = (14.0 + 20.0 * r).to_radians();
    let keel = Vec3::new(x, 0.0, zk);
    let chine = Vec3::new(x, b, zk + b * beta.tan());
    let sheer = Vec3::new(x, b + 0.2, 1.9);
    let (a, c, s) = if t <= 1.0 { (keel, chine, t) } else { (chine, sheer, t - 1.0) };
    let d = c - a;
    // The outward normal of the chord in the section plane (y, z): (d.z, -d.y) for the bottom
    // (downwards and out), (d.z, -d.y) for the side as well (outwards).
    let out = Vec3::new(0.0, d.z, -d.y);
    a + d * s + out * (0.12 * s * (1.0 - s))
}

fn planing_offsets() -> Offsets {
    let sections = (0..13)
        .map(|k| {
            let x = PLANING_L * k as f64 / 12.0;
            let mut ts: Vec<f64> = (0..=BOTTOM_CHORDS).map(|i| i as f64 / BOTTOM_CHORDS as f64).collect();
            ts.extend((1..=SIDE_CHORDS).map(|i| 1.0 + i as f64 / SIDE_CHORDS as f64));
            Section::new(format!("st{k}"), ts.iter().map(|&t| planing_point(x, t)).collect())
        })
        .collect();
    Offsets::new("planing hull (made in the test)", Units::Metre, sections)
}

/// The largest distance from the exact hull to the surface near the chine: points of the two
/// chords either side of it (`t` in `[1 - 1/4, 1 + 1/4]`, 21 each) at every station and half
/// way between stations (x = 0.25 .. 11.75 m).
fn chine_deviation(s: &NurbsSurface) -> f64 {
    let projector = SurfaceProjector::new(s, ProjectionOptions::default());
    let mut worst = 0.0f64;
    for i in 1..48 {
        let x = PLANING_L * i as f64 / 48.0;
        for j in 0..=20 {
            let t = 0.75 + 0.5 * j as f64 / 20.0;
            worst = worst.max(projector.project(planing_point(x, t)).distance);
        }
    }
    worst
}

/// The angle in degrees between the surface normals just before and after `u`.
fn normal_jump(s: &NurbsSurface, u: f64, v: f64) -> f64 {
    let eps = 1e-9;
    match (s.normal(u - eps, v), s.normal(u + eps, v)) {
        (Some(a), Some(b)) => a.dot(b).clamp(-1.0, 1.0).acos().to_degrees(),
        _ => f64::NAN,
    }
}

#[test]
fn planing_hull_keeps_its_chine() {
    let o = planing_offsets();
    let off = FitConfig { knuckles: Knuckles::Off, ..FitConfig::default() };
    let auto = FitConfig::default();
    assert_eq!(auto.knuckles, Knuckles::Auto(CornerOptions::default()));
    for method in [FitMethod::Interp, FitMethod::Approx] {
        let plain = fit_offsets(&o, &FitConfig { method, ..off }).expect("fits");
        let kept = fit_offsets(&o, &FitConfig { method, ..auto }).expect("fits");
        assert!(plain.knuckle_lines.is_empty());
        // One chine line, detected in every station at the chine offset (index 4).
        assert_eq!(kept.knuckle_lines.len(), 1);
        let line = &kept.knuckle_lines[0];
        assert_eq!(line.detected_count(), 13);
        assert!(line.index.iter().all(|&i| i == Some(BOTTOM_CHORDS)), "{:?}", line.index);
        let a = kept.params[0][BOTTOM_CHORDS].0;
        let p = kept.surface.degree_u();
        assert_eq!(kept.surface.knots_u().multiplicity(a), p);
        // The tangent jumps at the chine by the exact hull's dihedral angle; the plain skin is
        // smooth there.
        for (k, sec) in o.sections.iter().enumerate() {
            let v = kept.params[k][BOTTOM_CHORDS].1;
            let x = sec.points[0].x;
            // One-sided and central differences over 1e-5 (truncation ~1e-5 rad, far below the
            // tolerance), scaled to unit size before normalizing.
            let h = 1e-5;
            let unit = |w: Vec3| (w * (1.0 / h)).normalized().expect("non-zero");
            // (one-sided at the transom: the shape is not defined aft of x = 0)
            let along = unit(planing_point(x + h, 1.0) - planing_point((x - h).max(0.0), 1.0));
            let nb = unit(planing_point(x, 1.0) - planing_point(x, 1.0 - h)).cross(along);
            let ns = unit(planing_point(x, 1.0 + h) - planing_point(x, 1.0)).cross(along);
            let (nb, ns) = (nb.normalized().expect("bottom"), ns.normalized().expect("side"));
            let truth = nb.dot(ns).clamp(-1.0, 1.0).acos().to_degrees();
            let jump = normal_jump(&kept.surface, a, v);
            // The chine's direction along the hull comes from the surface's chine iso-curve,
            // which interpolates (or, for approx, fits) the chine offsets: its slope error of
            // a degree or less moves the dihedral angle by about as much.
            assert!((jump - truth).abs() < 1.5, "{method} section {k}: jump {jump:.2}, exact {truth:.2}");
            let smooth = normal_jump(&plain.surface, plain.params[k][BOTTOM_CHORDS].0, v);
            assert!(smooth < 0.01, "{method} section {k}: {smooth}");
        }
        let (dev_plain, dev_kept) = (chine_deviation(&plain.surface), chine_deviation(&kept.surface));
        eprintln!(
            "planing hull {method}: offsets max {:.2e} -> {:.2e} m, exact hull near the chine max {:.2e} -> {:.2e} m",
            plain.error.overall.max, kept.error.overall.max, dev_plain, dev_kept
        );
        // The chine rounded off by the smooth surface against kept: at least 5 times less
        // deviation from the exact hull between the offsets near the chine.
        assert!(dev_kept * 5.0 < dev_plain, "{method}: {dev_kept} vs {dev_plain}");
        match method {
            // Both interpolate: round-off of the banded solves on a 12 m hull.
            FitMethod::Interp => {
                assert!(plain.error.overall.max < 1e-9 && kept.error.overall.max < 1e-9);
            }
            _ => assert!(kept.error.overall.max * 3.0 < plain.error.overall.max),
        }
    }
}

/// Every hull table in `testdata/` (round bilges, bulbs, transoms, flats) fits exactly as before:
/// the default knuckle detection finds no line there, and the surfaces are bit for bit those of
/// `Knuckles::Off`.
#[test]
fn tables_without_chines_fit_as_before() {
    let names = [
        "series60_cb060_offsets.csv",
        "series60_cb080_offsets.csv",
        "wigley_offsets.csv",
        "gunnerus_offsets.csv",
        "cargo116_offsets.csv",
        "matlab_wpb.csv",
        "matlab_dtmb5415_bow.csv",
    ];
    for name in names {
        let o = read_offsets(&testdata(name), Units::Metre).expect("reads");
        for method in [FitMethod::Interp, FitMethod::Approx] {
            let auto = fit_offsets(&o, &FitConfig { method, ..FitConfig::default() }).expect("fits");
            let off =
                fit_offsets(&o, &FitConfig { method, knuckles: Knuckles::Off, ..FitConfig::default() }).expect("fits");
            assert!(auto.knuckle_lines.is_empty(), "{name}: {:?}", auto.knuckle_lines);
            assert_eq!(auto.surface, off.surface, "{name} {method}");
        }
    }
}

/// R/V Gunnerus (`testdata/gunnerus_offsets.csv`): the transom is the first station (x = 0),
/// whose hull leaves the centreplane between 1.5 and 2 m above the baseline (below that the
/// section runs down the centreplane to the skeg); the bulb gives stations whose half-breadth rises and falls with height (x = 34.22
/// and 34.8 m: 0.63 m at z = 2, 0 from z = 3 to 5 m, then the flare). The interpolating skin
/// keeps both: it passes through them, the transom edge `v = 0` is the transom section, and
/// between the bulb's offsets the station curve stays within a few centimetres of them.
#[test]
fn gunnerus_transom_and_bulb_are_in_the_surface() {
    let o = read_offsets(&testdata("gunnerus_offsets.csv"), Units::Metre).expect("reads");
    let out = fit_offsets(&o, &FitConfig { method: FitMethod::Interp, ..FitConfig::default() }).expect("fits");
    let s = &out.surface;
    // Round-off of the banded solves on a 36 m hull.
    assert!(out.error.overall.max < 1e-9, "{}", out.error.overall.max);
    // The transom edge: the surface at v = 0 is the x = 0 section, from its lowest offset
    // (z = 0.5 m on the centreplane) to the deck; its half-breadth leaves the centreplane
    // between the offsets at z = 1.5 and 2.0 m.
    let transom = &o.sections[0];
    assert_eq!(transom.points[0].x, 0.0);
    let (mut lowest_hull, mut min_x, mut max_x) = (f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=400 {
        let p = s.point(i as f64 / 400.0, 0.0);
        (min_x, max_x) = (min_x.min(p.x), max_x.max(p.x));
        if p.y > 0.05 {
            lowest_hull = lowest_hull.min(p.z);
        }
    }
    // The edge is the interpolant of the section's own control points: exactly planar.
    assert!(min_x.abs() < 1e-9 && max_x.abs() < 1e-9, "{min_x} {max_x}");
    eprintln!("gunnerus transom: hull (y > 5 cm) starts at z = {lowest_hull:.3} m");
    assert!((1.5..2.0).contains(&lowest_hull), "{lowest_hull}");
    // The bulb: along the x = 34.8 m station, between its offsets at z = 1.5 and 2.5 m, the
    // half-breadth peaks near the offset at z = 2 (0.361 m).
    let k = o.sections.iter().position(|sec| sec.label == "34.8").expect("bulb station");
    let (par, pts) = (&out.params[k], &o.sections[k].points);
    let i2 = pts.iter().position(|p| p.z == 2.0).expect("z = 2 offset");
    let (ua, ub, v) = (par[i2 - 1].0, par[i2 + 1].0, par[i2].1);
    let peak = (0..=200).map(|i| s.point(ua + (ub - ua) * i as f64 / 200.0, v).y).fold(f64::NEG_INFINITY, f64::max);
    eprintln!("gunnerus bulb at x = 34.8 m: peak half-breadth {peak:.4} m (offset 0.361 m)");
    assert!(peak >= pts[i2].y - 1e-9 && peak < pts[i2].y + 0.05, "{peak}");
}
