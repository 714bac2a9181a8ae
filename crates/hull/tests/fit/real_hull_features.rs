//! Hull features on real hulls: the flats of side and bottom of the 116 m cargo ship and the
//! Series 60 Cb 0.80 parent (kept within their planes by `Knuckles::AutoFlats`), the transom
//! and bulb of the DTC (sliced from its mesh) and of R/V Gunnerus, and the forecastle step of
//! R/V Gunnerus.

use hull::{
    cut_surface, find_flat_lines, fit_offsets, read_mesh, read_offsets, slice_mesh, CutOptions, CutPlane, FitConfig,
    FitMethod, FitOutcome, FlatKind, FlatOptions, Knuckles, MeshReadOptions, Offsets, SliceOptions, Stations, Units,
};
use nurbs::fit::CornerOptions;
use nurbs::{NurbsSurface, Vec3};

use crate::common::testdata;

/// `(beyond, below)`: how far the surface reaches past the largest half-breadth of the offsets
/// and below their lowest point, on a 201 x 201 parameter grid.
fn overshoot(s: &NurbsSurface, o: &Offsets) -> (f64, f64) {
    let pts = o.sections.iter().flat_map(|s| s.points.iter());
    let y_max = pts.clone().map(|p| p.y).fold(f64::NEG_INFINITY, f64::max);
    let z_min = pts.map(|p| p.z).fold(f64::INFINITY, f64::min);
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let (mut beyond, mut below) = (0.0f64, 0.0f64);
    for i in 0..=200 {
        for j in 0..=200 {
            let p = s.point(u0 + (u1 - u0) * i as f64 / 200.0, v0 + (v1 - v0) * j as f64 / 200.0);
            beyond = beyond.max(p.y - y_max);
            below = below.max(z_min - p.z);
        }
    }
    (beyond, below)
}

/// The least squares as they fit the features (not held within the offsets' envelope, whose
/// refit `tests/fit/validity.rs` checks).
fn fit(o: &Offsets, method: FitMethod, knuckles: Knuckles) -> FitOutcome {
    let config = FitConfig { method, knuckles, envelope: hull::EnvelopeHold::Free, ..FitConfig::default() };
    fit_offsets(o, &config).expect("fits")
}

/// The cargo ship (flat bottom at z = 0 and flat side at y = 8.25 m, in 13 and 14 of its 21
/// stations) and the Series 60 Cb 0.80 parent (flat side at B/2 = 9.38 m from 0.25 T up, in
/// the 10 stations of its parallel middle body). The plain approximation rings past the flats;
/// `AutoFlats` refits it within their planes.
#[test]
fn flats_keep_the_approximation_within_the_planes_of_side_and_bottom() {
    let auto_flats = Knuckles::AutoFlats(CornerOptions::default());
    for (name, kinds, plain_ring) in [
        ("cargo116_offsets.csv", vec![FlatKind::Bottom, FlatKind::Side], 0.1),
        ("series60_cb080_offsets.csv", vec![FlatKind::Side], 0.02),
    ] {
        let o = read_offsets(&testdata(name), Units::Metre).expect("reads");
        let plain = fit(&o, FitMethod::Approx, Knuckles::default());
        let flats = fit(&o, FitMethod::Approx, auto_flats);
        let found: Vec<FlatKind> = flats.flat_lines.iter().map(|l| l.kind).collect();
        // The bottom's line ends the flat bottom (its run's upper end), the side's starts the
        // flat side: in that order along the sections, keel up.
        assert_eq!(found, kinds, "{name}");
        let (b0, z0) = overshoot(&plain.surface, &o);
        let (b1, z1) = overshoot(&flats.surface, &o);
        eprintln!(
            "{name}: approx {}x{} max {:.4} rms {:.4} beyond {b0:.4} below {z0:.4} -> flats {}x{} max {:.4} rms {:.4} \
             beyond {b1:.2e} below {z1:.2e} m",
            plain.surface.n_u(),
            plain.surface.n_v(),
            plain.error.overall.max,
            plain.error.overall.rms,
            flats.surface.n_u(),
            flats.surface.n_v(),
            flats.error.overall.max,
            flats.error.overall.rms
        );
        // The plain fit rings (measured: cargo 83 mm beyond, 144 mm below; Series 60 36 mm
        // beyond), so the test can tell the two apart.
        assert!(b0.max(z0) > plain_ring, "{name}: {b0} {z0}");
        // Every control point within the planes of the flats found: by the convex-hull property
        // no point of the surface crosses them; what the samples may show is the round-off of
        // summing the basis functions (partition of unity to ~1e-16 relative) on a 120 m hull,
        // 1e-12 m. (The Series 60 table starts each section at the edge of the flat bottom, one
        // offset at z = 0: no bottom flat is found, and the plain fit's 3 mm dip stays.)
        let net = flats.surface.control_points();
        for line in &flats.flat_lines {
            match line.kind {
                FlatKind::Side => {
                    assert!(b1 <= 1e-12, "{name}: {b1}");
                    assert!(net.iter().all(|p| p.y <= line.plane), "{name}");
                }
                FlatKind::Bottom => {
                    assert!(z1 <= 1e-12, "{name}: {z1}");
                    assert!(net.iter().all(|p| p.z >= line.plane), "{name}");
                }
            }
        }
        // With the knots the refit adds (2 along u per line, 2 across per line's end) the true
        // error at the offsets does not grow either (measured: cargo max 108 -> 91 mm, RMS 26 ->
        // 12 mm; Series 60 max 63 -> 54 mm, RMS 16 -> 12 mm).
        assert!(flats.error.overall.max < plain.error.overall.max, "{name}");
        assert!(flats.error.overall.rms < plain.error.overall.rms, "{name}");
        // Interpolation is left alone: held on the planes it could not pass through every offset.
        let interp = fit(&o, FitMethod::Interp, auto_flats);
        assert!(interp.flat_lines.is_empty());
        assert_eq!(interp.surface, fit(&o, FitMethod::Interp, Knuckles::default()).surface, "{name}");
    }
}

/// Tables without a flat at the plane of the largest half-breadth or of the lowest offset fit
/// under `AutoFlats` exactly as under the default `Auto`, bit for bit.
#[test]
fn tables_without_flats_fit_as_before_under_auto_flats() {
    for name in ["wigley_offsets.csv", "gunnerus_offsets.csv", "matlab_wpb.csv", "matlab_dtmb5415_bow.csv"] {
        let o = read_offsets(&testdata(name), Units::Metre).expect("reads");
        let sections: Vec<Vec<Vec3>> = o.sections.iter().map(|s| s.points.clone()).collect();
        assert!(find_flat_lines(&sections, &FlatOptions::default()).expect("valid").is_empty(), "{name}");
        let plain = fit(&o, FitMethod::Approx, Knuckles::default());
        let flats = fit(&o, FitMethod::Approx, Knuckles::AutoFlats(CornerOptions::default()));
        assert!(flats.flat_lines.is_empty());
        assert_eq!(plain.surface, flats.surface, "{name}");
    }
}

/// The distance from `p` to the polyline through `pts`.
fn polyline_distance(pts: &[Vec3], p: Vec3) -> f64 {
    pts.windows(2)
        .map(|w| {
            let d = w[1] - w[0];
            let t = ((p - w[0]).dot(d) / d.dot(d)).clamp(0.0, 1.0);
            (w[0] + d * t).distance(p)
        })
        .fold(f64::INFINITY, f64::min)
}

/// The bulb's half-breadth in a station's points keel up: the first local maximum of `y`
/// (the bulb's widest), and the height of the neck above it (the first local minimum after
/// it), or `None` for a section without a bulb.
fn bulb(points: &[Vec3]) -> Option<(f64, f64)> {
    let top = (1..points.len() - 1).find(|&i| points[i].y >= points[i - 1].y && points[i].y > points[i + 1].y)?;
    let neck = (top + 1..points.len() - 1).find(|&i| points[i].y <= points[i + 1].y)?;
    Some((points[top].y, points[neck].z))
}

/// The DTC (`testdata/mesh/DTC-scaled.stl.gz`, model scale, x from the AP; PROVENANCE in
/// `shared/data/dtc/`) sliced at its 41 default stations and approximated: the transom is the
/// mesh's flat aft face at x = -0.1135 m, from z = 0.2575 m (above the design waterline 0.244)
/// to the deck; the bulbous bow the lower piece of the last stations.
#[test]
fn dtc_transom_and_bulb_are_in_the_surface() {
    let mesh = read_mesh(&testdata("mesh/DTC-scaled.stl.gz"), &MeshReadOptions::default()).expect("reads");
    let x_aft = mesh.vertices.iter().map(|p| p.x).fold(f64::INFINITY, f64::min);
    // The face: the starboard vertices within 2 mm of the aftmost (it is nearly, not exactly,
    // one plane: its lower edge lies 1.4 mm forward of its top).
    let transom: Vec<Vec3> = mesh.vertices.iter().filter(|p| p.x < x_aft + 2e-3 && p.y >= 0.0).copied().collect();
    let z_edge = transom.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
    let out = slice_mesh(&mesh, &SliceOptions::default()).expect("slices");
    let fit = fit(&out.offsets, FitMethod::Approx, Knuckles::default());
    let s = &fit.surface;
    // The aft edge v = 0 is the first station's curve: planar, and on the transom's plane within
    // the first station's offset from it (slicing keeps clear of the face by 1e-4 m).
    let x0 = out.offsets.sections[0].points[0].x;
    assert!((x0 - x_aft).abs() < 1e-4, "{x0} vs {x_aft}");
    let edge: Vec<Vec3> = (0..=200).map(|i| s.point(i as f64 / 200.0, 0.0)).collect();
    assert!(edge.iter().all(|p| (p.x - x0).abs() < 1e-9), "the aft edge leaves the station plane");
    // Its lowest point is the transom's lower edge on the centre plane (the approximation
    // interpolates the ends of every section), and it follows the transom's outline: the mesh
    // cut at the first station (30 points keel to deck edge, from the triangles), measured
    // 1.6 mm at most; the bound is the fit's own RMS error over the hull, 5 mm, as no edge
    // should be worse than the hull's typical offset.
    assert!((edge[0].z - z_edge).abs() < 1e-3 && edge[0].y == 0.0, "{:?} vs {z_edge}", edge[0]);
    let outline = &out.offsets.sections[0].points;
    let worst = edge.iter().map(|p| polyline_distance(outline, *p)).fold(0.0, f64::max);
    eprintln!(
        "DTC transom: edge z from {:.4} (mesh {z_edge:.4}), farthest from the outline {worst:.4} m (fit RMS {:.4}, max {:.4})",
        edge[0].z, fit.error.overall.rms, fit.error.overall.max
    );
    assert!(worst < 0.005, "{worst}");
    // The bulb, between the stations (x half way between the last stations): the surface's
    // station cut against the mesh's own section there.
    let xs: Vec<f64> = out.stations.iter().map(|s| s.x).collect();
    let between: Vec<f64> = (35..39).map(|k| 0.5 * (xs[k] + xs[k + 1])).collect();
    let mesh_cuts =
        slice_mesh(&mesh, &SliceOptions { stations: Stations::At(between.clone()), ..SliceOptions::default() })
            .expect("slices");
    for (x, sec) in between.iter().zip(&mesh_cuts.offsets.sections) {
        let (truth, neck) = bulb(&sec.points).expect("the mesh has a bulb there");
        let cut = cut_surface(s, CutPlane::Station(*x), &CutOptions::default());
        let width = cut
            .iter()
            .flat_map(|c| c.points.iter())
            .filter(|p| p.point.z < neck)
            .map(|p| p.point.y)
            .fold(0.0, f64::max);
        eprintln!("DTC bulb at x = {x:.4}: half-breadth {width:.4} m, mesh {truth:.4} m (neck at z = {neck:.4})");
        // Measured -1.9, +3.8, -0.8 and -3.0 mm on a bulb of 30 to 63 mm half-breadth. Bound:
        // 5 mm, a third of the fit's largest error at the offsets (16 mm): the surface follows
        // the bulb between the stations, where it narrows by 10 to 20 mm from one to the next,
        // better than it meets its worst offset.
        assert!((width - truth).abs() < 0.005, "x = {x}: {width} vs {truth}");
    }
}

/// The points of a 101 x 1001 parameter grid whose normal points inwards, on the side (y > 0.3
/// m): `n.y` of the other sign than at a midship offset, by more than 0.1.
fn inward(s: &NurbsSurface, reference: (f64, f64)) -> Vec<Vec3> {
    let sign = s.normal(reference.0, reference.1).map_or(1.0, |n| n.y.signum());
    let mut out = Vec::new();
    for i in 0..=100 {
        for j in 0..=1000 {
            let (u, v) = (i as f64 / 100.0, j as f64 / 1000.0);
            let p = s.point(u, v);
            if p.y > 0.3 && s.normal(u, v).is_some_and(|n| n.y * sign < -0.1) {
                out.push(p);
            }
        }
    }
    out
}

/// R/V Gunnerus (`testdata/gunnerus_offsets.csv`) approximated: the transom and the bulb are
/// in the surface; the forecastle step, where the stations go from 9 offsets up to z = 4 m
/// (x = 16.24 m) to 16 up to 7.5 m (x = 16.82 m), folds the surface between those two stations
/// and nowhere else with the default parameters, and not at all with centripetal parameters
/// across the sections.
#[test]
fn gunnerus_transom_bulb_and_forecastle_step() {
    let o = read_offsets(&testdata("gunnerus_offsets.csv"), Units::Metre).expect("reads");
    let out = fit(&o, FitMethod::Approx, Knuckles::default());
    let s = &out.surface;
    // The transom: the aft edge is the x = 0 section; the hull leaves the centre plane between
    // its offsets at z = 1.5 (y = 0) and 2.0 m (y = 0.708 m).
    let edge: Vec<Vec3> = (0..=400).map(|i| s.point(i as f64 / 400.0, 0.0)).collect();
    assert!(edge.iter().all(|p| p.x.abs() < 1e-9));
    let lowest_hull = edge.iter().filter(|p| p.y > 0.05).map(|p| p.z).fold(f64::INFINITY, f64::min);
    eprintln!("gunnerus approx transom: hull (y > 5 cm) from z = {lowest_hull:.3} m");
    assert!((1.5..2.0).contains(&lowest_hull), "{lowest_hull}");
    // The bulb at x = 34.22 m: offsets 0.630 m at z = 2, 0 from z = 3 to 5 m. The surface's
    // station cut there, below the neck, peaks within the fit's largest error of the offset.
    let k = o.sections.iter().position(|sec| sec.label == "34.22").expect("bulb station");
    let (truth, neck) = bulb(&o.sections[k].points).expect("a bulb");
    let cut = cut_surface(s, CutPlane::Station(34.22), &CutOptions::default());
    let width =
        cut.iter().flat_map(|c| c.points.iter()).filter(|p| p.point.z < neck).map(|p| p.point.y).fold(0.0, f64::max);
    eprintln!(
        "gunnerus approx bulb at x = 34.22 m: {width:.4} m (offset {truth:.4} m, fit max error {:.4} m)",
        out.error.overall.max
    );
    assert!((width - truth).abs() < out.error.overall.max, "{width} vs {truth}");
    // The fold: inward normals only between the two stations of the step, for both methods.
    let mid = o.sections.len() / 2;
    for method in [FitMethod::Interp, FitMethod::Approx] {
        let f = if method == FitMethod::Approx { out.clone() } else { fit(&o, method, Knuckles::default()) };
        let reference = f.params[mid][f.params[mid].len() / 2];
        let bad = inward(&f.surface, reference);
        let (lo, hi) = bad.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.x), b.max(p.x)));
        eprintln!("gunnerus {method}: {} of 102101 samples face inwards, x {lo:.3} to {hi:.3} m", bad.len());
        assert!(bad.iter().all(|p| p.x > 16.24 && p.x < 16.82), "{method}: {lo} {hi}");
        // It comes from the chord-length parameters across the sections: the deck edge's 3.5 m
        // rise between the two stations, 0.58 m apart, makes that v span long and the columns'
        // x overshoots backwards in it. Centripetal parameters across (the square roots of the
        // chords) shorten it, and no sample faces inwards (measured for the approximation: max
        // error 63 -> 92 mm, RMS 9.9 -> 11.6 mm, so not the default).
        let param = "centripetal,centripetal".parse().expect("known");
        let g =
            fit_offsets(&o, &FitConfig { method, param, envelope: hull::EnvelopeHold::Free, ..FitConfig::default() })
                .expect("fits");
        let reference = g.params[mid][g.params[mid].len() / 2];
        assert!(inward(&g.surface, reference).is_empty(), "{method} with centripetal parameters across");
    }
}
