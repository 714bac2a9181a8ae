//! Shape analysis against closed forms: planar cuts (stations, waterlines, buttocks),
//! curvature maps and fairness measures on the exact Wigley hull, a cylinder, a sphere and the
//! fitted Series 60 sample. The cuts of the cylinder, the sphere and a flat-bottomed patch,
//! which need no hull type, are the kernel's tests (`crates/nurbs/src/cut/tests.rs`).

use hull::{
    bending_energy, curvature_map, cut_surface, cut_surface_many, default_quadrature, fairness_report, gauss_legendre,
    CurvatureField, CurvatureMapOptions, CutCurve, CutOptions, CutPlane, FairnessOptions, PlaneSelection,
};

use hull::{fit_offsets, series60_sample, FitConfig};
use nurbs::fixtures::half_cylinder_along_x as half_cylinder;
use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};

// ---------------------------------------------------------------------------------------
// Test surfaces
// ---------------------------------------------------------------------------------------

const L: f64 = 100.0;
const B: f64 = 10.0;
const T: f64 = 6.25;

/// The exact Wigley hull `y = (B/2) (1 - (2x'/L)^2) (1 - (z'/T)^2)` in hullskin axes: x from
/// the aft end (`x' = x - L/2`), z from the keel (`z' = z - T`), so
/// `y = (B/2) g(x/L) h(z/T)` with `g(s) = 4 s (1 - s)` and `h(t) = t (2 - t)`: zero at the
/// ends and at the keel, B/2 amidships at the waterline `z = T` (the top edge).
///
/// As a degree (2, 2) Bezier patch: `u` along z (keel to deck), `v` along x (aft to fore),
/// `x = L v`, `z = T u` (equally spaced control points of a linear function), and `y` the
/// tensor product of the Bernstein coefficients of `g`, `(0, 2, 0)`, and of `h`, `(0, 1, 1)`.
fn wigley() -> NurbsSurface {
    crate::common::surfaces::wigley_patch(L, B, T)
}

/// Wigley half-breadth `F(x, z)` and its partial derivatives
/// `(F, F_x, F_z, F_xx, F_xz, F_zz)`.
fn wigley_f(x: f64, z: f64) -> [f64; 6] {
    let (s, t) = (x / L, z / T);
    let (g, g1, g2) = (4.0 * s * (1.0 - s), (4.0 - 8.0 * s) / L, -8.0 / (L * L));
    let (h, h1, h2) = (t * (2.0 - t), (2.0 - 2.0 * t) / T, -2.0 / (T * T));
    let a = 0.5 * B;
    [a * g * h, a * g1 * h, a * g * h1, a * g2 * h, a * g1 * h1, a * g * h2]
}

/// The octant `x, y, z >= 0` of a sphere of radius `r` about the origin, as a surface of
/// revolution: u along the meridian quarter circle from the equator `(r, 0, 0)` to the pole
/// `(0, 0, r)` (the edge `u = 1` collapses to the pole), v around z from the xz-plane to the
/// yz-plane. Rational biquadratic. `S_u x S_v` points into the sphere. The kernel's octant
/// (pole at u = 0) with u reversed: the same numbers, rows in the other order.
fn sphere_octant(r: f64) -> NurbsSurface {
    nurbs::fixtures::sphere_octant(r).reversed_u()
}

/// Every point of every branch lies on the plane to `rel` of the model size.
fn assert_on_plane(cuts: &[CutCurve], size: f64, rel: f64) -> f64 {
    let mut worst: f64 = 0.0;
    for c in cuts {
        for p in &c.points {
            let d = c.plane.signed_distance(p.point).abs();
            worst = worst.max(d / size);
            assert!(d <= rel * size, "{:?}: point {:?} is {d:e} off the plane", c.plane, p.point);
        }
    }
    worst
}

/// Largest relative difference between the analytic curvature and the discrete curvature
/// of the polyline (circle through each interior point and its neighbours), over points
/// where `|kappa|` exceeds `floor`.
fn discrete_vs_analytic(c: &CutCurve, floor: f64) -> f64 {
    let xy = c.coords();
    let mut worst: f64 = 0.0;
    for k in 1..xy.len() - 1 {
        let (a, b, p) = (xy[k - 1], xy[k], xy[k + 1]);
        let (ab, bp, ap) = ([b[0] - a[0], b[1] - a[1]], [p[0] - b[0], p[1] - b[1]], [p[0] - a[0], p[1] - a[1]]);
        let denom = ab[0].hypot(ab[1]) * bp[0].hypot(bp[1]) * ap[0].hypot(ap[1]);
        let disc = 2.0 * (ab[0] * bp[1] - ab[1] * bp[0]) / denom;
        let an = c.points[k].curvature;
        if an.abs() > floor {
            worst = worst.max((disc - an).abs() / an.abs());
        }
    }
    worst
}

// ---------------------------------------------------------------------------------------
// Cuts
// ---------------------------------------------------------------------------------------

#[test]
fn wigley_stations_are_parabolas_with_the_closed_form_curvature() {
    let s = wigley();
    let size = s.model_size().expect("a finite net");
    let (mut worst_k, mut worst_y, mut worst_disc): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for x in [5.0, 20.0, 37.5, 50.0, 71.0, 96.0] {
        let cuts = cut_surface(&s, CutPlane::Station(x), &CutOptions::default());
        assert_eq!(cuts.len(), 1, "x = {x}");
        let c = &cuts[0];
        // Points on the plane to 1e-12 of the model size (refined to 1e-14, round-off of x ~ 1e-16 L).
        assert_on_plane(&cuts, size, 1e-12);
        // Keel (z = 0, y = 0) to deck (z = T).
        let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
        assert!(first.z.abs() <= 1e-12 * size && first.y.abs() <= 1e-12 * size, "{first:?}");
        assert!((last.z - T).abs() <= 1e-12 * size, "{last:?}");
        assert!(c.points.windows(2).all(|w| w[1].point.z > w[0].point.z));
        for p in &c.points {
            let [f, _, fz, _, _, fzz] = wigley_f(x, p.point.z);
            worst_y = worst_y.max((p.point.y - f).abs() / size);
            // The curve (y, z) = (f(z), z) traversed with z increasing:
            // kappa = (y' z'' - z' y'') / (y'^2 + z'^2)^1.5 = -f'' / (1 + f'^2)^1.5 > 0.
            let want = -fzz / (1.0 + fz * fz).powf(1.5);
            worst_k = worst_k.max((p.curvature - want).abs() / want.abs());
        }
        worst_disc = worst_disc.max(discrete_vs_analytic(c, 0.0));
    }
    eprintln!("wigley stations: y {worst_y:e} (rel size), kappa {worst_k:e} (rel), discrete {worst_disc:e} (rel)");
    // The analytic formula in exact arithmetic is the closed form; round-off only.
    assert!(worst_k <= 1e-9, "{worst_k:e}");
    assert!(worst_y <= 1e-12, "{worst_y:e}");
    // The discrete curvature through neighbours at most 2 deg apart on a parabola: its error
    // is O(h kappa') with unequal spacing; 2 % bounds it with margin.
    assert!(worst_disc <= 0.02, "{worst_disc:e}");
}

#[test]
fn wigley_waterlines_are_parabolas_with_the_closed_form_curvature() {
    let s = wigley();
    let size = s.model_size().expect("a finite net");
    let (mut worst_k, mut worst_disc): (f64, f64) = (0.0, 0.0);
    // z = T is the top edge: the surface lies on one side of the plane only.
    for z in [0.3, 1.0, 3.125, 5.0, 6.0, T] {
        let cuts = cut_surface(&s, CutPlane::Waterline(z), &CutOptions::default());
        assert_eq!(cuts.len(), 1, "z = {z}");
        let c = &cuts[0];
        assert_on_plane(&cuts, size, 1e-12);
        // Aft (x = 0) to fore (x = L).
        let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
        assert!(first.x.abs() <= 1e-9 && (last.x - L).abs() <= 1e-9, "{first:?} {last:?}");
        assert!(c.points.windows(2).all(|w| w[1].point.x > w[0].point.x));
        for p in &c.points {
            let [_, fx, _, fxx, _, _] = wigley_f(p.point.x, z);
            // (x, f(x)) traversed with x increasing: kappa = f'' / (1 + f'^2)^1.5 < 0.
            let want = fxx / (1.0 + fx * fx).powf(1.5);
            worst_k = worst_k.max((p.curvature - want).abs() / want.abs());
        }
        worst_disc = worst_disc.max(discrete_vs_analytic(c, 0.0));
    }
    eprintln!("wigley waterlines: kappa {worst_k:e} (rel), discrete {worst_disc:e} (rel)");
    assert!(worst_k <= 1e-9, "{worst_k:e}");
    assert!(worst_disc <= 0.02, "{worst_disc:e}");
}

#[test]
fn wigley_buttocks_follow_the_implicit_curve_curvature() {
    let s = wigley();
    let size = s.model_size().expect("a finite net");
    let mut worst_k: f64 = 0.0;
    for y in [0.5, 2.0, 4.0, 4.9] {
        let cuts = cut_surface(&s, CutPlane::Buttock(y), &CutOptions::default());
        // A U from the deck edge down and back up to it.
        assert_eq!(cuts.len(), 1, "y = {y}");
        let c = &cuts[0];
        assert_on_plane(&cuts, size, 1e-12);
        let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
        assert!(first.x < last.x && (first.z - T).abs() <= 1e-9 && (last.z - T).abs() <= 1e-9);
        for (k, p) in c.points.iter().enumerate() {
            let [_, fx, fz, fxx, fxz, fzz] = wigley_f(p.point.x, p.point.z);
            // Level curve G = F - y = 0 in (x, z): traversed along (G_z, -G_x) its signed
            // curvature is -div(grad G / |grad G|)
            //   = -(G_xx G_z^2 - 2 G_xz G_x G_z + G_zz G_x^2) / |grad G|^3.
            let mut want = -(fxx * fz * fz - 2.0 * fxz * fx * fz + fzz * fx * fx) / (fx * fx + fz * fz).powf(1.5);
            let next = &c.points[(k + 1).min(c.points.len() - 1)].point;
            let prev = &c.points[k.saturating_sub(1)].point;
            if fz * (next.x - prev.x) - fx * (next.z - prev.z) < 0.0 {
                want = -want;
            }
            worst_k = worst_k.max((p.curvature - want).abs() / want.abs());
        }
    }
    eprintln!("wigley buttocks: kappa {worst_k:e} (rel)");
    assert!(worst_k <= 1e-9, "{worst_k:e}");
}

#[test]
fn several_planes_at_once_equal_one_at_a_time() {
    let s = wigley();
    let planes = [CutPlane::Station(30.0), CutPlane::Waterline(2.0), CutPlane::Buttock(3.0), CutPlane::Station(-1.0)];
    let opts = CutOptions::default();
    let many = cut_surface_many(&s, &planes, &opts);
    assert_eq!(many.len(), planes.len());
    for (plane, cuts) in planes.iter().zip(&many) {
        assert_eq!(cuts, &cut_surface(&s, *plane, &opts));
    }
    assert!(many[3].is_empty(), "x = -1 misses the hull");
}

/// Every station cut at the offsets' x runs keel to deck and passes within the fit error of
/// that station's offsets: for an offset at 3-D distance `e` from the surface, whose foot has
/// the unit normal `N`, the distance within the station plane to the cut is `e / |N_yz|`
/// to first order (the surface leans out of the plane by `N_x`).
#[test]
fn series60_stations_run_keel_to_deck_through_the_offsets() {
    let offsets = series60_sample();
    let out = fit_offsets(&offsets, &FitConfig::default()).expect("the sample fits");
    let s = &out.surface;
    let projector = SurfaceProjector::new(s, ProjectionOptions::default());
    let planes: Vec<CutPlane> =
        offsets.sections.iter().map(|sec| CutPlane::Station(sec.mean_x().expect("points"))).collect();
    let all = cut_surface_many(s, &planes, &CutOptions::default());
    let mut worst_excess = f64::NEG_INFINITY;
    for (sec, cuts) in offsets.sections.iter().zip(&all) {
        assert_eq!(cuts.len(), 1, "station {}", sec.label);
        let c = &cuts[0];
        let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
        // Keel (z = 0) to deck (z = 1.5 T = 9.75 m): the section's ends are interpolated.
        assert!(first.z.abs() <= 1e-9 && (last.z - 9.75).abs() <= 1e-9, "{}: {first:?} {last:?}", sec.label);
        let xy = c.coords();
        for q in &sec.points {
            let foot = projector.project(*q);
            let n = s.normal(foot.u, foot.v).expect("regular foot");
            let bound = foot.distance / n.y.hypot(n.z);
            let d = polyline_distance(&xy, c.plane.coords(*q));
            // 1 mm slack for chord sag of 2-degree segments and the second-order terms.
            assert!(d <= 1.05 * bound + 1e-3, "station {}: {q:?} at {d} > {bound}", sec.label);
            worst_excess = worst_excess.max(d - bound);
        }
    }
    eprintln!("series 60 stations: in-plane distance - e / |N_yz| <= {worst_excess:e} m");
}

/// The lines plan of the fitted sample (21 stations end to end, 10 waterlines, 5 buttocks):
/// every point on its plane, every branch oriented as documented, turning by at most the
/// asked angle at every point, curvature finite.
#[test]
fn series60_lines_plan_cuts_are_on_their_planes_oriented_and_dense() {
    let out = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits");
    let s = &out.surface;
    let size = s.model_size().expect("a finite net");
    let (lpp, b2, d) = (121.92, 8.13, 9.75);
    let mut planes: Vec<CutPlane> = (0..=20).map(|k| CutPlane::Station(lpp * k as f64 / 20.0)).collect();
    planes.extend((1..=10).map(|k| CutPlane::Waterline(d * k as f64 / 11.0)));
    planes.extend((1..=5).map(|k| CutPlane::Buttock(b2 * k as f64 / 6.0)));
    let opts = CutOptions::default();
    let all = cut_surface_many(s, &planes, &opts);
    let mut worst_turn: f64 = 0.0;
    for (plane, cuts) in planes.iter().zip(&all) {
        assert!(!cuts.is_empty(), "{plane:?} misses the hull");
        assert_on_plane(cuts, size, 1e-12);
        for c in cuts {
            let (first, last) = (c.points[0].point, c.points[c.points.len() - 1].point);
            match plane {
                CutPlane::Station(_) => assert!(last.z > first.z, "{plane:?}"),
                _ => assert!(last.x > first.x, "{plane:?}"),
            }
            assert!(c.points.iter().all(|p| p.curvature.is_finite()));
            let xy = c.coords();
            for w in xy.windows(3) {
                let (a, b) = ([w[1][0] - w[0][0], w[1][1] - w[0][1]], [w[2][0] - w[1][0], w[2][1] - w[1][1]]);
                let turn = (a[0] * b[1] - a[1] * b[0]).abs().atan2(a[0] * b[0] + a[1] * b[1]);
                worst_turn = worst_turn.max(turn.to_degrees());
            }
        }
        // Branches in order of their first point's drawing coordinates.
        let firsts: Vec<[f64; 2]> = cuts.iter().map(|c| c.plane.coords(c.points[0].point)).collect();
        assert!(firsts.windows(2).all(|w| w[0] <= w[1]), "{plane:?}: {firsts:?}");
    }
    let counts: Vec<usize> = all.iter().map(Vec::len).collect();
    eprintln!("series 60 lines plan: branches per plane {counts:?}, largest turn {worst_turn:.3} deg");
    // The densification's contract, to round-off of the angle.
    assert!(worst_turn <= opts.max_segment_angle_deg + 1e-9, "{worst_turn}");
}

fn polyline_distance(xy: &[[f64; 2]], q: [f64; 2]) -> f64 {
    xy.windows(2)
        .map(|w| {
            let (a, b) = (w[0], w[1]);
            let (ab, aq) = ([b[0] - a[0], b[1] - a[1]], [q[0] - a[0], q[1] - a[1]]);
            let t = ((aq[0] * ab[0] + aq[1] * ab[1]) / (ab[0] * ab[0] + ab[1] * ab[1])).clamp(0.0, 1.0);
            (aq[0] - t * ab[0]).hypot(aq[1] - t * ab[1])
        })
        .fold(f64::INFINITY, f64::min)
}

// ---------------------------------------------------------------------------------------
// Curvature maps
// ---------------------------------------------------------------------------------------

#[test]
fn sphere_map_has_k_one_over_r_squared_and_h_one_over_r_with_the_pole_flagged() {
    let r = 3.0;
    let map = curvature_map(&sphere_octant(r), &CurvatureMapOptions::default());
    // The pole row u = 1 is one point: flagged, every other node regular.
    assert_eq!(map.flagged(), map.vs.len());
    let (mut wk, mut wh, mut wp): (f64, f64, f64) = (0.0, 0.0, 0.0);
    for s in map.samples.iter().flatten() {
        wk = wk.max((s.gaussian * r * r - 1.0).abs());
        // S_u x S_v points inward, toward which the sphere bends: H = k1 = k2 = +1/R.
        wh = wh.max((s.mean * r - 1.0).abs());
        wp = wp.max((s.k1 * r - 1.0).abs()).max((s.k2 * r - 1.0).abs());
    }
    eprintln!("sphere map: K {wk:e}, H {wh:e}, k1/k2 {wp:e} (rel)");
    // Round-off, amplified next to the pole where |S_v| ~ (1 - u) |S_u| (the nearest row is
    // 1/64 of the domain away): 1e-10 bounds it. k1, k2 = H +- sqrt(H^2 - K) lose half the
    // digits where H^2 = K (an umbilic): sqrt(1e-15) ~ 3e-8.
    assert!(wk <= 1e-10 && wh <= 1e-10 && wp <= 1e-7, "{wk:e} {wh:e} {wp:e}");
    let summary = map.summary();
    let json = serde_json::to_string(&summary).expect("serializes");
    assert!(!json.contains("null") && !json.contains("NaN"), "{json}");
    let g = summary.gaussian.expect("regular nodes");
    assert!(g.low >= g.min.value && g.high <= g.max.value);
}

#[test]
fn cylinder_map_has_zero_k_and_h_minus_one_over_two_r() {
    let r = 2.5;
    let map = curvature_map(&half_cylinder(r, 12.0), &CurvatureMapOptions::default());
    assert_eq!(map.flagged(), 0);
    for (k, s) in map.samples.iter().enumerate() {
        let s = s.expect("regular");
        // S_u x S_v points away from the axis (y = 0, z = r), the side the cylinder bends
        // away from: H = -1/(2R), k1 = 0, k2 = -1/R.
        let p = map.points[k];
        assert!(s.normal.dot(Vec3::new(0.0, p.y, p.z - r)) > 0.0);
        assert!(s.gaussian.abs() <= 1e-14, "K {}", s.gaussian);
        assert!((s.mean + 0.5 / r).abs() <= 1e-14, "H {}", s.mean);
        assert!(s.k1.abs() <= 1e-7 && (s.k2 + 1.0 / r).abs() <= 1e-7, "{s:?}");
    }
}

#[test]
fn wigley_map_matches_the_graph_curvature_formulas() {
    let s = wigley();
    let map = curvature_map(&s, &CurvatureMapOptions { grid: (40, 40), ..Default::default() });
    assert_eq!(map.flagged(), 0);
    let (mut wk, mut wh): (f64, f64) = (0.0, 0.0);
    for (k, c) in map.samples.iter().enumerate() {
        let c = c.expect("regular");
        let p = map.points[k];
        let [_, fx, fz, fxx, fxz, fzz] = wigley_f(p.x, p.z);
        let w = 1.0 + fx * fx + fz * fz;
        // Graph y = F(x, z): K = (F_xx F_zz - F_xz^2) / (1 + F_x^2 + F_z^2)^2.
        let kk = (fxx * fzz - fxz * fxz) / (w * w);
        // H = ((1 + F_z^2) F_xx - 2 F_x F_z F_xz + (1 + F_x^2) F_zz) / (2 w^1.5) for the normal
        // (-F_x, 1, -F_z) / sqrt(w) (positive y: outboard); the map's normal decides the sign.
        let hh = ((1.0 + fz * fz) * fxx - 2.0 * fx * fz * fxz + (1.0 + fx * fx) * fzz) / (2.0 * w.powf(1.5));
        let hh = if c.normal.y > 0.0 { hh } else { -hh };
        // Relative to the largest |K| (at the keel amidships, where K ~ 1e-3 1/m^2).
        wk = wk.max((c.gaussian - kk).abs());
        wh = wh.max((c.mean - hh).abs());
    }
    let st = map.stats(CurvatureField::Gaussian, (0.0, 100.0)).expect("regular");
    let kscale = st.min.value.abs().max(st.max.value.abs());
    eprintln!("wigley map: K error {:e} (rel to max |K| {kscale:e}), H error {wh:e} 1/m", wk / kscale);
    assert!(wk <= 1e-12 * kscale && wh <= 1e-13, "{wk:e} {wh:e}");
}

#[test]
fn series60_map_is_nan_free_and_summarised() {
    let out = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits");
    let map = curvature_map(&out.surface, &CurvatureMapOptions::default());
    let summary = map.summary();
    let json = serde_json::to_string(&summary).expect("serializes");
    assert!(!json.contains("NaN") && !json.contains("null"), "{json}");
    // Fairness at the offsets' stations and waterlines (both ends excluded: edges of the
    // surface), for the record.
    let offsets = series60_sample();
    let xs: Vec<f64> = offsets.sections.iter().filter_map(|s| s.mean_x()).collect();
    let zs: Vec<f64> = offsets.sections[12].points.iter().map(|p| p.z).collect();
    let opts = FairnessOptions {
        stations: PlaneSelection::At(xs[1..xs.len() - 1].to_vec()),
        waterlines: PlaneSelection::At(zs[1..zs.len() - 1].to_vec()),
        ..FairnessOptions::default()
    };
    let fairness = fairness_report(&out.surface, &opts);
    assert!(fairness.energy.thin_plate.is_finite() && fairness.energy.thin_plate > 0.0);
    assert!(!serde_json::to_string(&fairness).expect("serializes").contains("NaN"));
    eprintln!(
        "series 60 fairness: E_tp {:.4}, E_p {:.4e} m^2, inflections: stations {:?}, waterlines {:?}",
        fairness.energy.thin_plate,
        fairness.energy.parametric,
        fairness.stations.iter().map(|p| p.inflections).collect::<Vec<_>>(),
        fairness.waterlines.iter().map(|p| p.inflections).collect::<Vec<_>>(),
    );
    for field in CurvatureField::ALL {
        let st = map.stats(field, (1.0, 99.0)).expect("regular nodes");
        assert!(st.min.value <= st.low && st.low <= st.high && st.high <= st.max.value, "{field:?}");
        // The extremes lie on the surface at their parameters.
        let p = out.surface.point(st.max.u, st.max.v);
        assert_eq!([p.x, p.y, p.z], st.max.point);
    }
    eprintln!(
        "series 60 map: {} nodes, {} flagged, K in [{:e}, {:e}], 1-99 % [{:e}, {:e}]",
        summary.samples + summary.flagged,
        summary.flagged,
        summary.gaussian.map_or(0.0, |g| g.min.value),
        summary.gaussian.map_or(0.0, |g| g.max.value),
        summary.gaussian.map_or(0.0, |g| g.low),
        summary.gaussian.map_or(0.0, |g| g.high),
    );
}

// ---------------------------------------------------------------------------------------
// Fairness
// ---------------------------------------------------------------------------------------

#[test]
fn thin_plate_energy_of_sphere_and_cylinder_is_closed_form() {
    // Sphere octant: (k1^2 + k2^2) = 2/R^2 over an eighth of 4 pi R^2: pi, whatever R.
    for r in [0.5, 3.0, 40.0] {
        let e = bending_energy(&sphere_octant(r), default_quadrature(&sphere_octant(r)));
        eprintln!("sphere r {r}: thin plate {} (pi), area {} (pi r^2 / 2)", e.thin_plate, e.area);
        // A rational integrand on one span, 32 Gauss points per direction: converged to
        // round-off (8 points leave 2e-10).
        assert!((e.thin_plate - std::f64::consts::PI).abs() <= 1e-12, "{}", e.thin_plate);
        assert!((e.area / (std::f64::consts::PI * r * r / 2.0) - 1.0).abs() <= 1e-12);
    }
    // Half cylinder: 1/R^2 over pi R len: pi len / R.
    let (r, len) = (2.5, 12.0);
    let e = bending_energy(&half_cylinder(r, len), default_quadrature(&half_cylinder(r, len)));
    assert!((e.thin_plate - std::f64::consts::PI * len / r).abs() <= 1e-12 * e.thin_plate, "{}", e.thin_plate);
}

#[test]
fn wigley_energies_match_closed_form_integrals() {
    let s = wigley();
    let e = bending_energy(&s, (3, 3));
    // S_uu = (0, (B/2) g h'', 0) with h'' = -2, S_vv = (0, (B/2) g'' h, 0) with g'' = -8,
    // S_uv = (0, (B/2) g' h', 0) (u, v in [0, 1]): integral = B^2 (8/15 + 32/9 + 128/15)
    // = 568 B^2 / 45. A polynomial of degree 4 per direction: 3 Gauss points are exact.
    let want = 568.0 * B * B / 45.0;
    assert!((e.parametric - want).abs() <= 1e-12 * want, "{} vs {want}", e.parametric);
    // Thin plate from the closed-form K and H of the graph, integrated independently in
    // (x, z) with 40 x 40 Gauss points.
    let gl = gauss_legendre(40);
    let mut want_tp = 0.0;
    for &(a, wa) in &gl {
        for &(b, wb) in &gl {
            let (x, z) = (0.5 * L * (a + 1.0), 0.5 * T * (b + 1.0));
            let [_, fx, fz, fxx, fxz, fzz] = wigley_f(x, z);
            let w = 1.0 + fx * fx + fz * fz;
            let kk = (fxx * fzz - fxz * fxz) / (w * w);
            let hh = ((1.0 + fz * fz) * fxx - 2.0 * fx * fz * fxz + (1.0 + fx * fx) * fzz) / (2.0 * w.powf(1.5));
            want_tp += wa * wb * 0.25 * L * T * (4.0 * hh * hh - 2.0 * kk) * w.sqrt();
        }
    }
    let got = bending_energy(&s, default_quadrature(&s)).thin_plate;
    eprintln!("wigley thin plate {got} vs {want_tp}, parametric {} vs {want}", e.parametric);
    // The same smooth integrand on one span, 32 and 40 Gauss points: both converged (30
    // points agree with 60 to 1e-14 relative); 12 points would leave 1.3e-7.
    assert!((got - want_tp).abs() <= 1e-12 * want_tp, "{got} vs {want_tp}");
    assert!((bending_energy(&s, (12, 12)).thin_plate - want_tp).abs() > 1e-8 * want_tp, "the test can fail");
}

/// The Wigley hull raised to bicubic with eight spans per direction (the same surface), and
/// the same with the control point (5, 6) of 11 x 11 pushed outboard by `bump`. Its basis
/// functions' support is knots u in [2/8, 6/8], v in [3/8, 7/8]: x in [37.5, 87.5] m,
/// z in [1.5625, 4.6875] m.
fn wigley_cubic(bump: f64) -> NurbsSurface {
    let s = wigley().elevate_degree_u(1).and_then(|s| s.elevate_degree_v(1)).expect("elevates");
    let eighths: Vec<f64> = (1..8).map(|k| k as f64 / 8.0).collect();
    let s = s.refine_knots_u(&eighths).and_then(|s| s.refine_knots_v(&eighths)).expect("refines");
    let (nu, nv) = (s.n_u(), s.n_v());
    assert_eq!((nu, nv), (11, 11));
    let mut pts = s.control_points();
    pts[5 * nv + 6].y += bump;
    NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, None).expect("valid")
}

#[test]
fn a_pushed_out_control_point_adds_inflections_and_energy() {
    let opts = FairnessOptions {
        stations: PlaneSelection::Count(19),
        waterlines: PlaneSelection::Count(9),
        ..FairnessOptions::default()
    };
    let fair = fairness_report(&wigley_cubic(0.0), &opts);
    // One metre outboard, a fifth of the half-breadth.
    let bumped = fairness_report(&wigley_cubic(1.0), &opts);
    let count = |r: &hull::FairnessReport| {
        (
            r.stations.iter().map(|p| p.inflections).sum::<usize>(),
            r.waterlines.iter().map(|p| p.inflections).sum::<usize>(),
        )
    };
    let (fs, fw) = count(&fair);
    let (bs, bw) = count(&bumped);
    eprintln!(
        "fairness: fair {fs} + {fw} inflections, E_tp {}; bump {bs} + {bw}, E_tp {}",
        fair.energy.thin_plate, bumped.energy.thin_plate
    );
    // The Wigley hull's stations and waterlines are parabolas: no inflection at all.
    assert_eq!((fs, fw), (0, 0));
    assert!(fair.stations.iter().chain(&fair.waterlines).all(|p| p.branches.len() == 1));
    // The bump shows in both views, and raises the bending energy.
    assert!(bs > fs && bw > fw, "{bs} {bw}");
    assert!(bumped.energy.thin_plate > fair.energy.thin_plate);
    assert_eq!(bumped.inflections, bs + bw);
    // Every inflection is recorded where it is, under the bump (the support of the moved
    // control point's basis functions, see `wigley_cubic`), to within one segment of the cut
    // (the recorded zero is interpolated between two of its points).
    for p in bumped.stations.iter().chain(&bumped.waterlines) {
        for (b, cut) in p.branches.iter().zip(cut_surface(&wigley_cubic(1.0), p.plane, &opts.cut)) {
            assert_eq!(b.inflections_at.len(), b.inflections);
            let seg = cut.points.windows(2).map(|w| w[0].point.distance(w[1].point)).fold(0.0, f64::max);
            let under = |q: &[f64; 3]| {
                (0.375 * L - seg..=0.875 * L + seg).contains(&q[0]) && (0.25 * T - seg..=0.75 * T + seg).contains(&q[2])
            };
            assert!(b.inflections_at.iter().all(under), "{:?} (segments up to {seg})", b.inflections_at);
        }
    }
    let json = serde_json::to_string(&bumped).expect("serializes");
    assert!(!json.contains("NaN"));
}
