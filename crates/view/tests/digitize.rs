//! Digitising drawn body plans back into offsets.
//!
//! - The fitted Series 60 sample's lines plan, drawn by the crate's own writers (DXF and
//!   SVG), digitised back: every point must lie on the surface to within the drawing's
//!   resolution.
//! - The exact Wigley hull's stations (parabolas in `y(z)`) drawn as DXF `SPLINE`s and as SVG
//!   cubic paths: every point must satisfy the Wigley equation.
//! - Two hand-made drawings of a small barge (`testdata/digitize/`): the offsets must be the
//!   drawn lines and arcs, whichever way the stations are identified.
//! - Bad input: clear errors.

use std::f64::consts::FRAC_PI_2;
use std::path::{Path, PathBuf};

use hull::{
    cut_surface, digitize, fit_offsets, parse_drawing, parse_sections_csv, read_drawing, series60_sample,
    write_sections_csv, CurveOrder, CutOptions, CutPlane, DigitizeOptions, Digitized, DrawingScale, FitConfig,
    Notation, Side, StationIds, StationX, Units,
};
use nurbs::{KnotVector, NurbsCurve, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use view::{lines_plan, write_dxf, write_svg, Drawing, Item, LinesPlanOptions, Rgb};

fn testdata(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata/digitize").join(name)
}

// -------------------------------------------------------------------------------------------
// The sample hull's lines plan

/// The fitted sample, its lines plan with 19 stations strictly inside the length (the end
/// stations of a pointed hull are points), the stations' x, the body plan's datum on paper
/// (y up) and the scale's model:paper ratio.
struct Plan {
    surface: NurbsSurface,
    drawing: Drawing,
    xs: Vec<f64>,
    datum: [f64; 2],
    scale: u32,
}

fn sample_plan() -> Plan {
    let fit = fit_offsets(&series60_sample(), &FitConfig::default()).expect("the sample fits");
    let s = fit.surface;
    let (mut lo, mut hi) = (f64::INFINITY, f64::NEG_INFINITY);
    for i in 0..=64 {
        for j in 0..=64 {
            let (u, v) = (f64::from(i) / 64.0, f64::from(j) / 64.0);
            let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
            let x = s.point(u0 + (u1 - u0) * u, v0 + (v1 - v0) * v).x;
            lo = lo.min(x);
            hi = hi.max(x);
        }
    }
    let xs: Vec<f64> = (1..20).map(|i| lo + (hi - lo) * f64::from(i) / 20.0).collect();
    let opts = LinesPlanOptions { stations: Some(xs.clone()), ..LinesPlanOptions::default() };
    let drawing = lines_plan(&s, None, Units::Metre, &opts);
    // The body plan's centreline is the one dashed vertical line of the grid; its baseline
    // the black horizontal line across it (the waterlines are grey).
    let grid: Vec<(&Vec<[f64; 2]>, bool)> = drawing
        .layer("grid")
        .filter_map(|i| match i {
            Item::Polyline { points, stroke, .. } if points.len() == 2 && stroke.color == Rgb::BLACK => {
                Some((points, stroke.dash.is_some()))
            }
            _ => None,
        })
        .collect();
    let cl = grid
        .iter()
        .find(|(p, dashed)| *dashed && p[0][0] == p[1][0])
        .map(|(p, _)| p[0][0])
        .expect("the body plan centreline");
    let bl = grid
        .iter()
        .find(|(p, dashed)| !*dashed && p[0][1] == p[1][1] && p[0][0].min(p[1][0]) < cl && p[0][0].max(p[1][0]) > cl)
        .map(|(p, _)| p[0][1])
        .expect("the body plan baseline");
    let scale = drawing
        .items
        .iter()
        .find_map(|i| match i {
            Item::Text { text, .. } => text.strip_prefix("Scale 1:").and_then(|m| m.parse::<u32>().ok()),
            _ => None,
        })
        .expect("the title block's scale");
    Plan { surface: s, drawing, xs, datum: [cl, bl], scale }
}

fn order_options(plan: &Plan, datum: [f64; 2]) -> DigitizeOptions {
    let mut o = DigitizeOptions::new(
        DrawingScale::Ratio { paper: 1.0, model: f64::from(plan.scale) },
        datum,
        StationIds::Order(CurveOrder::Drawn),
        StationX::List(plan.xs.clone()),
    );
    o.layers = Some("stations".into());
    o
}

/// Largest distance from a digitised point to the surface, and to the matching point of the
/// surface's own station cut (same cut as the drawing's), in metres.
fn deviations(plan: &Plan, d: &Digitized) -> (f64, f64) {
    let projector = SurfaceProjector::new(&plan.surface, ProjectionOptions::default());
    let (mut to_surface, mut to_cut) = (0.0f64, 0.0f64);
    assert_eq!(d.offsets.sections.len(), plan.xs.len());
    for (s, &x) in d.offsets.sections.iter().zip(&plan.xs) {
        let cuts = cut_surface(&plan.surface, CutPlane::Station(x), &CutOptions::default());
        assert_eq!(cuts.len(), 1, "one branch per station of the sample at x = {x}");
        let mut cut: Vec<[f64; 2]> = cuts[0].coords();
        if cut[0][1] > cut[cut.len() - 1][1] {
            cut.reverse();
        }
        assert_eq!(s.points.len(), cut.len(), "every drawn vertex of station x = {x} is read back");
        for (p, q) in s.points.iter().zip(&cut) {
            assert_eq!(p.x, x);
            to_surface = to_surface.max(projector.project(*p).distance);
            to_cut = to_cut.max((p.y - q[0]).hypot(p.z - q[1]));
        }
    }
    (to_surface, to_cut)
}

/// DXF keeps every coordinate bit for bit (shortest round-trip reals), so the digitised points
/// are the cut's points up to the round-off of the paper transform and back (about 1e-16 of
/// the sheet, 1e-13 m at 1:500): 1e-9 m bounds it with room to spare.
#[test]
fn sample_lines_plan_dxf_reads_back_onto_the_surface() {
    let plan = sample_plan();
    let mut bytes = Vec::new();
    write_dxf(&mut bytes, &plan.drawing).expect("writes DXF");
    let sketch = parse_drawing(&bytes, "sample.dxf").expect("reads its own DXF");
    assert_eq!(sketch.unit_mm, Some(1.0), "$INSUNITS millimetres");
    let d = digitize(&sketch, &order_options(&plan, plan.datum)).expect("digitises");
    let (to_surface, to_cut) = deviations(&plan, &d);
    eprintln!(
        "sample DXF at 1:{}: max {:.3e} mm to the surface, {:.3e} mm to the cut",
        plan.scale,
        to_surface * 1e3,
        to_cut * 1e3
    );
    assert!(to_surface < 1e-9 && to_cut < 1e-9, "{to_surface} {to_cut}");
    // Aft stations drawn left, fore stations right, split at the middle of the length.
    let mid = 0.5 * (plan.xs[0] + plan.xs[plan.xs.len() - 1]);
    for st in &d.stations {
        let want = if st.x < mid - 1e-9 { Side::Aft } else { Side::Fore };
        assert_eq!(st.side, want, "station x = {}", st.x);
    }
    // The body plan order (aft narrowest to widest, then fore widest to narrowest) finds the
    // same order as the file on this hull, whose sections widen towards midships.
    let mut o = order_options(&plan, plan.datum);
    o.stations = StationIds::Order(CurveOrder::BodyPlan);
    let b = digitize(&sketch, &o).expect("digitises");
    assert_eq!(b.offsets, d.offsets);
}

/// The SVG writer rounds paper coordinates to 1e-3 mm: each coordinate moves by at most
/// 5e-4 mm, a point by 5e-4 sqrt 2 mm, which at 1:S is 5e-4 sqrt 2 S mm on the ship (0.35 mm
/// at 1:500). The cut points are on the surface to 1e-12 of the size, so the digitised
/// points lie within that bound of the surface and of their cut points.
#[test]
fn sample_lines_plan_svg_reads_back_within_the_rounding() {
    let plan = sample_plan();
    let mut bytes = Vec::new();
    write_svg(&mut bytes, &plan.drawing).expect("writes SVG");
    let sketch = parse_drawing(&bytes, "sample.svg").expect("reads its own SVG");
    assert_eq!(sketch.unit_mm, Some(1.0), "width in mm over the viewBox");
    // SVG's y runs down from the top of the sheet.
    let datum = [plan.datum[0], plan.drawing.height_mm - plan.datum[1]];
    let d = digitize(&sketch, &order_options(&plan, datum)).expect("digitises");
    let bound = 5e-4 * 2f64.sqrt() * f64::from(plan.scale) * 1e-3;
    let (to_surface, to_cut) = deviations(&plan, &d);
    eprintln!(
        "sample SVG at 1:{}: max {:.3} mm to the surface, {:.3} mm to the cut (bound {:.3} mm)",
        plan.scale,
        to_surface * 1e3,
        to_cut * 1e3,
        bound * 1e3
    );
    assert!(to_surface <= bound * (1.0 + 1e-9) && to_cut <= bound * (1.0 + 1e-9), "{to_surface} {to_cut} > {bound}");
    // Rounding is not nothing: the SVG points are not the DXF's.
    assert!(to_cut > 1e-3 * bound, "{to_cut}");

    // Resampled to 12 points per station, every point still lies on a chord of the drawn
    // station: within the rounding plus the chord height of the drawn polyline, which the cut
    // keeps below 1e-3 of the model size by default (see CutOptions): checked against the
    // surface at 1 % of the breadth.
    let mut o = order_options(&plan, datum);
    o.points = Some(12);
    let r = digitize(&sketch, &o).expect("digitises");
    let projector = SurfaceProjector::new(&plan.surface, ProjectionOptions::default());
    for s in &r.offsets.sections {
        assert_eq!(s.points.len(), 12);
        for p in &s.points {
            assert!(projector.project(*p).distance < 0.01 * 16.26, "{p:?}");
        }
    }

    // And the sections CSV written from it reads back as the same offsets.
    let mut csv = Vec::new();
    write_sections_csv(&mut csv, &d.offsets, Notation::Plain).expect("writes CSV");
    let back =
        parse_sections_csv(std::str::from_utf8(&csv).expect("UTF-8"), "sample.svg", Units::Metre).expect("reads back");
    for (a, b) in back.sections.iter().zip(&d.offsets.sections) {
        assert_eq!((&a.label, &a.points), (&b.label, &b.points));
    }
}

// -------------------------------------------------------------------------------------------
// The Wigley hull

/// The Wigley hull of testdata/wigley_offsets.csv: L 100, B 10, T 6.25 m, x from the aft end,
/// z from the keel: `y = B/2 (1 - xi^2) (1 - (1 - z/T)^2)`, `xi = (x - L/2) / (L/2)`.
const L: f64 = 100.0;
const B: f64 = 10.0;
const T: f64 = 6.25;

fn wigley_y(x: f64, z: f64) -> f64 {
    let xi = (x - 0.5 * L) / (0.5 * L);
    0.5 * B * (1.0 - xi * xi) * (1.0 - (1.0 - z / T).powi(2))
}

/// The station at x as a quadratic Bézier in (y, z) from the keel (0, 0) to the deck (a, T),
/// `a = y(x, T)`: `y(z) = a (2 z/T - z^2/T^2)` has the control point (a, T/2) where the
/// tangents at both ends meet (slope dy/dz = 2a/T at the keel, 0 at the deck).
fn wigley_bezier(x: f64) -> [[f64; 2]; 3] {
    let a = wigley_y(x, T);
    [[0.0, 0.0], [a, 0.5 * T], [a, T]]
}

/// Wigley stations x = 5, 10, ..., 95 at 1:200 on an A4 sheet in mm, datum (150, 40); aft
/// stations mirrored to the left. As DXF SPLINEs, one layer per station `ST1`..`ST19`:
/// odd stations the quadratic Bézier (degree 2, knots 0 0 0 1 1 1); even ones the same curve
/// raised to degree 3, with knots 0.3 and 0.6 inserted (The NURBS Book A5.9 and A5.1, by the
/// kernel) and every weight 2 (a rational spline with equal weights is the same curve).
fn wigley_dxf() -> String {
    let k = 1000.0 / 200.0; // paper mm per metre
    let (x0, y0) = (150.0, 40.0);
    let mut e = String::new();
    for n in 1..20 {
        let x = 5.0 * f64::from(n);
        let side = if x < 0.5 * L { -1.0 } else { 1.0 };
        let paper: Vec<Vec3> =
            wigley_bezier(x).iter().map(|q| Vec3::new(x0 + side * q[0] * k, y0 + q[1] * k, 0.0)).collect();
        let knots = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
        let mut curve = NurbsCurve::try_new(knots, &paper, None).expect("valid");
        let rational = n % 2 == 0;
        if rational {
            curve = curve.elevate_degree(1).expect("elevates").insert_knot(0.3, 1).expect("inserts");
            curve = curve.insert_knot(0.6, 1).expect("inserts");
        }
        let flags = if rational { 8 + 4 } else { 8 };
        e += &format!(
            "0\nSPLINE\n8\nST{n}\n70\n{flags}\n71\n{}\n72\n{}\n73\n{}\n74\n0\n",
            curve.degree(),
            curve.knots().as_slice().len(),
            curve.num_control_points()
        );
        for t in curve.knots().as_slice() {
            e += &format!("40\n{t}\n");
        }
        for p in curve.control_points() {
            if rational {
                e += "41\n2.0\n";
            }
            e += &format!("10\n{}\n20\n{}\n30\n0.0\n", p.x, p.y);
        }
    }
    format!("0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n0\nSECTION\n2\nENTITIES\n{e}0\nENDSEC\n0\nEOF\n")
}

/// The same stations as SVG cubic paths (the quadratic raised to degree 3: control points
/// P0, (P0 + 2 P1)/3, (2 P1 + P2)/3, P2), drawn in a group `translate(150 120) scale(0.5 -0.5)`
/// whose local unit is 2 mm on paper with y up: the datum is (150, 120) in the sheet's
/// coordinates and one user unit is 1 mm (width 210mm over a viewBox 210 wide). Odd stations
/// absolute `C`, even ones relative `c`; each named by its `<title>`.
fn wigley_svg() -> String {
    let k = 1000.0 / 200.0 * 2.0; // local units per metre: 5 mm per metre, 0.5 mm per unit
    let mut paths = String::new();
    for n in 1..20 {
        let x = 5.0 * f64::from(n);
        let side = if x < 0.5 * L { -1.0 } else { 1.0 };
        let [p0, p1, p2] = wigley_bezier(x).map(|q| [side * q[0] * k, q[1] * k]);
        let c1 = [(p0[0] + 2.0 * p1[0]) / 3.0, (p0[1] + 2.0 * p1[1]) / 3.0];
        let c2 = [(2.0 * p1[0] + p2[0]) / 3.0, (2.0 * p1[1] + p2[1]) / 3.0];
        let d = if n % 2 == 1 {
            format!("M{} {} C{} {} {} {} {} {}", p0[0], p0[1], c1[0], c1[1], c2[0], c2[1], p2[0], p2[1])
        } else {
            format!(
                "m{},{} c{},{} {},{} {},{}",
                p0[0],
                p0[1],
                c1[0] - p0[0],
                c1[1] - p0[1],
                c2[0] - p0[0],
                c2[1] - p0[1],
                p2[0] - p0[0],
                p2[1] - p0[1]
            )
        };
        paths += &format!("<path d=\"{d}\" fill=\"none\" stroke=\"black\"><title>Station {n}</title></path>\n");
    }
    format!(
        "<svg xmlns=\"http://www.w3.org/2000/svg\" width=\"210mm\" height=\"148mm\" viewBox=\"0 0 210 148\">\n\
         <g id=\"body plan\" transform=\"translate(150 120) scale(0.5 -0.5)\">\n{paths}</g>\n</svg>\n"
    )
}

/// Largest |y - y_wigley(x, z)| over the digitised points, metres.
fn wigley_error(d: &Digitized) -> f64 {
    let mut worst = 0.0f64;
    for s in &d.offsets.sections {
        for p in &s.points {
            assert!((-1e-9..=T + 1e-9).contains(&p.z), "{p:?}");
            worst = worst.max((p.y - wigley_y(p.x, p.z)).abs());
        }
    }
    worst
}

/// The flattened points of the splines are points of the splines, which are the Wigley
/// stations exactly: only round-off remains (1e-9 m bounds the round-off of the de Boor
/// evaluation on 1e2 mm coordinates times the scale 200, about 1e-11 m).
#[test]
fn wigley_splines_in_dxf_are_exact_parabolas() {
    let sketch = parse_drawing(wigley_dxf().as_bytes(), "wigley.dxf").expect("reads");
    let o = DigitizeOptions::new(
        "1:200".parse().expect("scale"),
        [150.0, 40.0],
        StationIds::Layers("ST*".into()),
        StationX::Spacing { origin: 0.0, spacing: 5.0 },
    );
    let d = digitize(&sketch, &o).expect("digitises");
    let xs: Vec<f64> = d.stations.iter().map(|s| s.x).collect();
    assert_eq!(xs, (1..20).map(|n| 5.0 * f64::from(n)).collect::<Vec<_>>(), "layers ST1..ST19 sorted by number");
    let err = wigley_error(&d);
    eprintln!("Wigley DXF splines: max |y - y_exact| = {:.3e} mm", err * 1e3);
    assert!(err < 1e-9, "{err}");
    for s in &d.offsets.sections {
        // Keel at the centreline, deck at the half-breadth of the deck.
        let (first, last) = (s.points[0], s.points[s.points.len() - 1]);
        assert!(first.y.abs() < 1e-12 && first.z.abs() < 1e-12, "{first:?}");
        assert!((last.z - T).abs() < 1e-12 && (last.y - wigley_y(last.x, T)).abs() < 1e-12, "{last:?}");
        assert!(s.points.len() > 10, "the curve is flattened, not just its control points");
    }

    // Resampled to 9 points along the curve flattened to within 1e-3 mm on paper, the points
    // lie on chords within 1e-3 mm (0.2 mm at 1:200) of the curve, measured across it: along
    // y that is up to sqrt(1 + (dy/dz)^2) times more where the station slopes.
    let mut o = o;
    o.points = Some(9);
    o.flatness = Some(1e-3);
    let r = digitize(&sketch, &o).expect("digitises");
    let flat = 1e-3 * 200.0 * 1e-3;
    let mut worst = 0.0f64;
    for s in &r.offsets.sections {
        for p in &s.points {
            let a = wigley_y(p.x, T);
            let slope = a * (2.0 / T - 2.0 * p.z / (T * T));
            let across = (p.y - wigley_y(p.x, p.z)).abs() / (1.0 + slope * slope).sqrt();
            worst = worst.max(across);
        }
    }
    eprintln!("Wigley DXF splines, 9 points per station: max distance across the curve {:.3e} mm", worst * 1e3);
    assert!(worst <= flat * (1.0 + 1e-6), "{worst} > {flat}");
    assert!(r.offsets.sections.iter().all(|s| s.points.len() == 9));
}

/// The same with SVG cubic paths under a scaling, flipping group transform, named by
/// `<title>Station n</title>`, identified by those names with a station spacing.
#[test]
fn wigley_cubic_paths_in_svg_are_exact_parabolas() {
    let sketch = parse_drawing(wigley_svg().as_bytes(), "wigley.svg").expect("reads");
    assert_eq!(sketch.unit_mm, Some(1.0));
    let o = DigitizeOptions::new(
        "1:200".parse().expect("scale"),
        [150.0, 120.0],
        StationIds::Labels,
        StationX::Spacing { origin: 0.0, spacing: 5.0 },
    );
    let d = digitize(&sketch, &o).expect("digitises");
    assert_eq!(d.offsets.sections.len(), 19);
    assert_eq!(d.offsets.sections[6].label, "Station 7");
    let err = wigley_error(&d);
    eprintln!("Wigley SVG cubics: max |y - y_exact| = {:.3e} mm", err * 1e3);
    assert!(err < 1e-9, "{err}");
    for st in &d.stations {
        assert_eq!(st.side, if st.x < 50.0 { Side::Aft } else { Side::Fore }, "{}", st.label);
    }
}

// -------------------------------------------------------------------------------------------
// Hand-made drawings of a barge (see testdata/digitize/README.md)

/// The barge's stations in metres: (name, x, pieces) with pieces lines `(a, b)` and quarter
/// arcs `(centre, radius)` in (y, z).
enum Piece {
    Line([f64; 2], [f64; 2]),
    Arc([f64; 2], f64),
}

fn barge() -> Vec<(&'static str, f64, Vec<Piece>)> {
    use Piece::{Arc, Line};
    vec![
        ("ST0", 0.0, vec![Line([0.0, 0.0], [1.0, 0.0]), Arc([1.0, 1.0], 1.0), Line([2.0, 1.0], [2.0, 2.5])]),
        ("ST5", 10.0, vec![Line([0.0, 0.0], [2.0, 0.0]), Arc([2.0, 1.0], 1.0), Line([3.0, 1.0], [3.0, 3.0])]),
        ("ST10", 20.0, vec![Line([0.0, 0.0], [0.5, 1.0]), Line([0.5, 1.0], [1.0, 3.0])]),
    ]
}

/// Distance of (y, z) to a barge piece (an arc is its lower-right quarter: y >= centre,
/// z <= centre).
fn piece_dist(p: [f64; 2], piece: &Piece) -> f64 {
    match piece {
        Piece::Line(a, b) => hull::seg_dist(p, *a, *b),
        Piece::Arc(c, r) => {
            let (dy, dz) = (p[0] - c[0], p[1] - c[1]);
            let t = dz.atan2(dy).clamp(-FRAC_PI_2, 0.0);
            (dy - r * t.cos()).hypot(dz - r * t.sin())
        }
    }
}

/// Every digitised point lies on its station's drawn pieces (1e-9 m: the hand drawings'
/// coordinates are exact decimals in millimetres, so only round-off remains), each station
/// runs from the keel on the centreline to the deck edge, and passes every piece's ends.
fn check_barge(d: &Digitized) {
    let want = barge();
    assert_eq!(d.offsets.sections.len(), want.len());
    for (s, (name, x, pieces)) in d.offsets.sections.iter().zip(&want) {
        assert_eq!(&s.label, name);
        for p in &s.points {
            assert_eq!(p.x, *x);
            let dist = pieces.iter().map(|pc| piece_dist([p.y, p.z], pc)).fold(f64::INFINITY, f64::min);
            assert!(dist < 1e-9, "station {name}: {p:?} is {dist} m off the drawing");
        }
        let first = s.points[0];
        assert!(first.y.abs() < 1e-12 && first.z.abs() < 1e-12, "{name} starts at the keel: {first:?}");
        for pc in pieces {
            if let Piece::Line(a, b) = pc {
                for e in [a, b] {
                    let hit = s.points.iter().any(|p| (p.y - e[0]).hypot(p.z - e[1]) < 1e-9);
                    assert!(hit, "{name}: the piece end {e:?} is among the points");
                }
            }
        }
    }
    let sides: Vec<Side> = d.stations.iter().map(|s| s.side).collect();
    assert_eq!(sides, [Side::Aft, Side::Fore, Side::Fore]);
}

fn barge_options(stations: StationIds) -> DigitizeOptions {
    DigitizeOptions::new(
        "1:50".parse().expect("scale"),
        [100.0, 50.0],
        stations,
        StationX::Map(vec![("ST0".into(), 0.0), ("ST5".into(), 10.0), ("ST10".into(), 20.0)]),
    )
}

#[test]
fn hand_made_dxf_by_layer_and_by_label() {
    let sketch = read_drawing(&testdata("barge.dxf")).expect("reads");
    let by_layer = digitize(&sketch, &barge_options(StationIds::Layers("ST*".into()))).expect("digitises");
    check_barge(&by_layer);
    assert_eq!(
        by_layer.stations.iter().map(|s| s.curves).collect::<Vec<_>>(),
        [1, 3, 2],
        "LWPOLYLINE; LINE ARC LINE; 2 LINEs"
    );
    let mut o = barge_options(StationIds::Labels);
    o.layers = Some("ST*".into());
    let by_label = digitize(&sketch, &o).expect("digitises");
    assert_eq!(by_label.offsets.sections, by_layer.offsets.sections);
    // Without the layer filter the centreline and baseline are curves too; they carry no
    // station label and are left out, with a note.
    let all = digitize(&sketch, &barge_options(StationIds::Labels)).expect("digitises");
    assert_eq!(all.offsets.sections, by_layer.offsets.sections);
    assert!(all.notes.iter().any(|n| n.starts_with("2 curve(s) without a station label skipped")), "{:?}", all.notes);
    // A spacing of 2 m per station number gives the same x.
    let mut o = barge_options(StationIds::Layers("ST*".into()));
    o.x = StationX::Spacing { origin: 0.0, spacing: 2.0 };
    assert_eq!(digitize(&sketch, &o).expect("digitises").offsets.sections, by_layer.offsets.sections);
}

#[test]
fn hand_made_svg_by_title_and_label() {
    let sketch = read_drawing(&testdata("barge.svg")).expect("reads");
    assert_eq!(sketch.unit_mm, Some(1.0));
    let mut o = barge_options(StationIds::Labels);
    o.datum = [100.0, 100.0];
    let d = digitize(&sketch, &o).expect("digitises");
    check_barge(&d);
    // In millimetres, the same points times 1000.
    o.units = Units::Millimetre;
    o.x = StationX::Map(vec![("ST0".into(), 0.0), ("ST5".into(), 10e3), ("ST10".into(), 20e3)]);
    let mm = digitize(&sketch, &o).expect("digitises");
    for (a, b) in mm.offsets.sections.iter().zip(&d.offsets.sections) {
        for (p, q) in a.points.iter().zip(&b.points) {
            assert!((p.y - 1e3 * q.y).abs() < 1e-9 && (p.z - 1e3 * q.z).abs() < 1e-9);
        }
    }
}

// -------------------------------------------------------------------------------------------
// Bad input

fn err_of(r: Result<Digitized, hull::HullError>) -> String {
    r.expect_err("an error").to_string()
}

#[test]
fn bad_input_gives_clear_errors() {
    let path = testdata("barge.dxf");
    let sketch = read_drawing(&path).expect("reads");
    let file = path.display().to_string();

    // A station not among those given.
    let mut o = barge_options(StationIds::Layers("ST*".into()));
    o.x = StationX::Map(vec![("ST0".into(), 0.0), ("ST5".into(), 10.0)]);
    let e = err_of(digitize(&sketch, &o));
    assert!(e.starts_with(&format!("{file}:")), "{e}");
    assert!(e.contains("unknown station \"ST10\": it is not among the stations given (ST0, ST5)"), "{e}");

    // A datum off the centreline: ST5's keel line then reaches both sides.
    let mut o = barge_options(StationIds::Layers("ST*".into()));
    o.datum = [120.0, 50.0];
    let e = err_of(digitize(&sketch, &o));
    assert!(e.contains("crosses the centreline X = 120"), "{e}");
    assert!(e.contains("check the datum X"), "{e}");

    // A ratio scale on a drawing that does not say its units.
    let svg = br#"<svg xmlns="http://www.w3.org/2000/svg" viewBox="0 0 10 10"><path d="M5 5 L6 6"/></svg>"#;
    let s = parse_drawing(svg, "nounits.svg").expect("reads");
    let o = DigitizeOptions::new(
        "1:50".parse().expect("scale"),
        [5.0, 5.0],
        StationIds::Order(CurveOrder::Drawn),
        StationX::List(vec![0.0]),
    );
    let e = err_of(digitize(&s, &o));
    assert!(e.contains("the drawing does not say its unit of length") && e.contains("--drawing-units"), "{e}");

    // More stations than positions.
    let mut o = barge_options(StationIds::Layers("ST*".into()));
    o.x = StationX::List(vec![0.0, 10.0]);
    let e = err_of(digitize(&sketch, &o));
    assert!(e.contains("3 station curves found (ST0, ST5, ST10) and 2 station positions given"), "{e}");

    // No curve on the layers asked for.
    let e = err_of(digitize(&sketch, &barge_options(StationIds::Layers("WL*".into()))));
    assert!(
        e.contains("no curve on layers matching \"WL*\"; the drawing's curves are on layers: BL, CL, ST0, ST10, ST5"),
        "{e}"
    );

    // Two stations at one x.
    let mut o = barge_options(StationIds::Layers("ST*".into()));
    o.x = StationX::Map(vec![("ST0".into(), 0.0), ("ST5".into(), 10.0), ("ST10".into(), 10.0)]);
    assert!(err_of(digitize(&sketch, &o)).contains("are both at x = 10"));

    // Broken files: cut short, garbage, malformed XML; each names the file and line.
    let text = std::fs::read_to_string(&path).expect("reads");
    let cut = &text[..text.len() / 2];
    let cut = &cut[..cut.rfind('\n').expect("lines")];
    let e = parse_drawing(cut.as_bytes(), "cut.dxf").expect_err("cut short").to_string();
    assert!(e.starts_with("cut.dxf:") && (e.contains("cut short") || e.contains("ends inside")), "{e}");
    let e = parse_drawing(b"hello\nworld\n", "junk.dxf").expect_err("junk").to_string();
    assert!(e.starts_with("junk.dxf:1: \"hello\" where a group code belongs"), "{e}");
    let e = parse_drawing(b"<svg xmlns=\"http://www.w3.org/2000/svg\">\n<g>\n</svg>", "bad.svg")
        .expect_err("xml")
        .to_string();
    assert!(e.starts_with("bad.svg:3:1: malformed XML"), "{e}");
}
