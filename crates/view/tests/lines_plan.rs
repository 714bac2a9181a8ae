//! The lines plan and its writers, checked on the output: the SVG parsed with roxmltree, the
//! DXF read back by ezdxf (`tools/dxf_check.py`).
//!
//! The DXF checks need a Python with `ezdxf`: `HULLSKIN_PYTHON`, or else `.venv` made by
//! `tools/setup-python.sh` (run by the test itself when needed). If that fails the tests fail
//! (the check cannot vanish silently) unless `HULLSKIN_SKIP_DXF=1`.

mod common;

use std::path::Path;
use std::process::Command;
use std::sync::OnceLock;

use common::python::tools_python;
use common::surfaces::wigley_patch;
use common::workspace_root;

use hull::Units;
use nurbs::Vec3;
use serde_json::Value;
use view::{write_dxf, write_dxf_3d_lines, Anchor, Drawing, Item, Rgb, Stroke};

/// The Python that has ezdxf, or `None` if the DXF checks are explicitly skipped.
fn dxf_python() -> String {
    tools_python("HULLSKIN_SKIP_DXF", "ezdxf check of the DXF export")
}

/// Write `bytes` to a temporary file and run `tools/dxf_check.py` on it; returns (exit code,
/// summary).
fn ezdxf_read(python: &str, bytes: &[u8]) -> (i32, Value) {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("check.dxf");
    std::fs::write(&path, bytes).expect("write DXF");
    let script = workspace_root().join("tools/dxf_check.py");
    let out = Command::new(python)
        .arg(&script)
        .arg(&path)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python} {}: {e}", script.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let summary: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| {
        panic!(
            "dxf_check.py did not print a JSON summary ({e}); status {:?}\nstdout:\n{stdout}\nstderr:\n{}",
            out.status,
            String::from_utf8_lossy(&out.stderr)
        )
    });
    (out.status.code().unwrap_or(-1), summary)
}

fn f(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// `a` equals `b` within 1e-6 relative to the larger magnitude (or 1e-9 absolute near 0).
fn near(a: f64, b: f64) -> bool {
    (a - b).abs() <= 1e-6 * a.abs().max(b.abs()).max(1e-3)
}

/// Compare ezdxf's view of a 2-D DXF with the drawing that was written: same layers (after
/// `0`) in first-appearance order, and entity by entity the same kind, layer and
/// coordinates. Returns the number of entities compared.
fn compare_dxf_with_drawing(summary: &Value, d: &Drawing) -> usize {
    assert_eq!(summary["dxfversion"], "AC1009");
    assert!(summary["audit"]["errors"].as_array().is_some_and(|e| e.is_empty()), "{}", summary["audit"]);
    let mut layer_order: Vec<&str> = Vec::new();
    for item in &d.items {
        if !layer_order.contains(&item.layer()) {
            layer_order.push(item.layer());
        }
    }
    let layers: Vec<&str> = summary["layers"]
        .as_array()
        .expect("layers")
        .iter()
        .filter_map(|l| l["name"].as_str())
        .filter(|n| *n != "0")
        .collect();
    // ezdxf may add its own defaults (e.g. `Defpoints`); ours come first, in order.
    assert_eq!(&layers[..layer_order.len()], &layer_order[..], "layer table");
    let entities = summary["entities"].as_array().expect("entities");
    let mut written: Vec<&Item> = Vec::new();
    for l in &layer_order {
        written.extend(d.items.iter().filter(|i| i.layer() == *l));
    }
    let mut k = 0;
    for item in written {
        let e = &entities[k];
        assert_eq!(e["layer"].as_str(), Some(item.layer()), "entity {k}");
        match item {
            Item::Polyline { points, closed, .. } => {
                assert_eq!(e["type"], "POLYLINE", "entity {k}");
                assert_eq!(e["closed"].as_bool(), Some(*closed), "entity {k}");
                let v = e["vertices"].as_array().expect("vertices");
                assert_eq!(v.len(), points.len(), "entity {k}");
                for (p, q) in points.iter().zip(v) {
                    assert!(near(p[0], f(&q[0])) && near(p[1], f(&q[1])), "entity {k}: {p:?} vs {q}");
                }
                k += 1;
            }
            Item::Polygon { points, .. } => {
                // Convex quads (all the drawings here use) are one SOLID, corners 1, 2, 4, 3.
                assert_eq!(points.len(), 4, "test drawings only have quads");
                assert_eq!(e["type"], "SOLID", "entity {k}");
                let v = e["vertices"].as_array().expect("vertices");
                for (p, q) in [points[0], points[1], points[3], points[2]].iter().zip(v) {
                    assert!(near(p[0], f(&q[0])) && near(p[1], f(&q[1])), "entity {k}: {p:?} vs {q}");
                }
                k += 1;
            }
            Item::Marker { at, size_mm, .. } => {
                assert_eq!(e["type"], "CIRCLE", "entity {k}");
                assert!(near(at[0], f(&e["center"][0])) && near(at[1], f(&e["center"][1])), "entity {k}");
                assert!(near(0.5 * size_mm, f(&e["radius"])), "entity {k}");
                k += 1;
            }
            Item::Text { at, text, size_mm, anchor, .. } => {
                assert_eq!(e["type"], "TEXT", "entity {k}");
                assert_eq!(e["text"].as_str(), Some(text.as_str()), "entity {k}");
                assert!(near(*size_mm, f(&e["height"])), "entity {k}");
                let halign = match anchor {
                    Anchor::Start => 0,
                    Anchor::Middle => 1,
                    Anchor::End => 2,
                };
                assert_eq!(e["halign"].as_i64(), Some(halign), "entity {k}");
                let p = if halign == 0 { &e["insert"] } else { &e["align_point"] };
                assert!(near(at[0], f(&p[0])) && near(at[1], f(&p[1])), "entity {k}: {at:?} vs {p}");
                k += 1;
            }
        }
    }
    assert_eq!(k, entities.len(), "ezdxf sees more entities than were drawn");
    k
}

/// A small drawing with every kind of item, a dashed line, colours off the layer colour and
/// non-ASCII text.
fn small_drawing() -> Drawing {
    let mut d = Drawing::new(297.0, 210.0, "small");
    d.push(Item::Polyline {
        points: vec![[10.0, 10.0], [100.0 / 3.0, 50.125], [60.0, 12.5]],
        closed: false,
        stroke: Stroke { color: Rgb(0, 0, 255), width_mm: 0.35, dash: Some(vec![4.0, 1.0, 0.5, 1.0]) },
        layer: "grid".into(),
    });
    d.push(Item::Polyline {
        points: vec![[1.0, 1.0], [2.0, 1.0], [2.0, 3.0]],
        closed: true,
        stroke: Stroke::solid(Rgb::BLACK, 0.5),
        layer: "frame".into(),
    });
    for (k, c) in [Rgb(68, 1, 84), Rgb(253, 231, 37)].into_iter().enumerate() {
        d.push(Item::Marker { at: [50.0 + k as f64, 60.0], size_mm: 1.2, fill: c, layer: "offsets".into() });
    }
    d.push(Item::Text {
        at: [200.0, 20.0],
        text: "Scale 1:50 ± 2 °".into(),
        size_mm: 3.5,
        anchor: Anchor::End,
        color: Rgb::BLACK,
        layer: "title".into(),
    });
    d.push(Item::Text {
        at: [20.0, 20.0],
        text: "CL".into(),
        size_mm: 2.5,
        anchor: Anchor::Middle,
        color: Rgb::BLACK,
        layer: "grid".into(),
    });
    d.push(Item::Polygon {
        points: vec![[300.0 - 10.0, 5.0], [295.0, 5.0], [295.0, 8.0], [290.0, 8.0]],
        fill: Rgb(33, 145, 140),
        layer: "legend".into(),
    });
    d
}

#[test]
#[cfg_attr(skip_dxf, ignore = "HULLSKIN_SKIP_DXF=1")]
fn ezdxf_reads_the_2d_writer_exactly() {
    let python = dxf_python();
    let d = small_drawing();
    let mut out = Vec::new();
    write_dxf(&mut out, &d).expect("writes to memory");
    let (code, summary) = ezdxf_read(&python, &out);
    assert_eq!(code, 0, "{summary}");
    let n = compare_dxf_with_drawing(&summary, &d);
    assert_eq!(n, 7);
    let h = &summary["header"];
    assert_eq!(h["$ACADVER"], "AC1009");
    assert_eq!(h["$INSUNITS"], 4, "millimetres");
    assert_eq!(h["$MEASUREMENT"], 1, "metric");
    // Extents: the polyline's (10, 10)... and the frame's (1, 1) to the polygon's x 295 and
    // the marker's top 60 + 0.6.
    assert!(near(f(&h["$EXTMIN"][0]), 1.0) && near(f(&h["$EXTMIN"][1]), 1.0), "{h}");
    assert!(near(f(&h["$EXTMAX"][0]), 295.0) && near(f(&h["$EXTMAX"][1]), 60.6), "{h}");
    // The dashed line uses a linetype with the dash pattern, total length 6.5 mm.
    let e0 = &summary["entities"][0];
    let lt = e0["linetype"].as_str().expect("linetype");
    assert_ne!(lt, "BYLAYER");
    let lt = summary["linetypes"].as_array().expect("linetypes").iter().find(|l| l["name"] == lt).expect("defined");
    let pattern: Vec<f64> = lt["pattern"].as_array().expect("pattern").iter().map(f).collect();
    assert_eq!(pattern, [4.0, 1.0, 0.5, 1.0], "{lt}");
    // Layer colours: grid blue (ACI 5), frame 7; the yellow marker differs from its layer's
    // purple and carries its own colour.
    let layer = |n: &str| summary["layers"].as_array().expect("layers").iter().find(|l| l["name"] == n).cloned();
    assert_eq!(layer("grid").expect("grid")["color"], 5);
    assert_eq!(layer("frame").expect("frame")["color"], 7);
    let markers: Vec<&Value> =
        summary["entities"].as_array().expect("entities").iter().filter(|e| e["type"] == "CIRCLE").collect();
    assert_eq!(markers[0]["color"], 256, "first marker sets the layer colour (BYLAYER)");
    assert_ne!(markers[1]["color"], 256);
}

#[test]
#[cfg_attr(skip_dxf, ignore = "HULLSKIN_SKIP_DXF=1")]
fn ezdxf_reads_3d_lines() {
    let python = dxf_python();
    let circle: Vec<Vec3> = (0..=16)
        .map(|k| {
            let t = k as f64 * std::f64::consts::PI / 16.0;
            Vec3::new(60.96, 8.13 * t.cos(), 3.25 + 3.25 * t.sin())
        })
        .collect();
    let wl: Vec<Vec3> = (0..=10).map(|k| Vec3::new(12.192 * k as f64, 0.1 * k as f64, 3.25)).collect();
    let curves = vec![("stations", circle.clone()), ("waterlines", wl.clone())];
    let mut out = Vec::new();
    write_dxf_3d_lines(&mut out, &curves, Units::Metre).expect("writes");
    let (code, s) = ezdxf_read(&python, &out);
    assert_eq!(code, 0, "{s}");
    assert_eq!(s["header"]["$INSUNITS"], 6, "metres");
    let e = s["entities"].as_array().expect("entities");
    assert_eq!(e.len(), 2);
    for (ent, (layer, pts)) in e.iter().zip(&curves) {
        assert_eq!(ent["type"], "POLYLINE");
        assert_eq!(ent["layer"].as_str(), Some(*layer));
        assert_eq!(ent["flags"].as_i64().map(|x| x & 8), Some(8), "3-D polyline flag");
        let v = ent["vertices"].as_array().expect("vertices");
        assert_eq!(v.len(), pts.len());
        for (p, q) in pts.iter().zip(v) {
            assert!(near(p.x, f(&q[0])) && near(p.y, f(&q[1])) && near(p.z, f(&q[2])), "{p:?} vs {q}");
        }
    }
}

// ---------------------------------------------------------------------------------------------
// The lines plan

use hull::{
    cut_surface_many, fit_offsets, measure_fit_error, series60_sample, CutOptions, CutPlane, FitConfig, Offsets,
};
use nurbs::NurbsSurface;
use view::{lines_3d, lines_plan, write_svg, LinesPlanOptions, Sheet};

const LAYERS: [&str; 10] =
    ["frame", "title", "grid", "stations", "waterlines", "buttocks", "outline", "offsets", "legend", "combs"];

/// Keep a drawing for a look when `HULLSKIN_DRAWING_OUT` names a directory.
fn keep(name: &str, bytes: &[u8]) {
    if let Ok(dir) = std::env::var("HULLSKIN_DRAWING_OUT") {
        let path = Path::new(&dir).join(name);
        std::fs::write(&path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    }
}

fn svg_bytes(d: &Drawing) -> Vec<u8> {
    let mut out = Vec::new();
    write_svg(&mut out, d).expect("writes to memory");
    out
}

/// The sample hull fitted with the default configuration, once.
fn sample_fit() -> &'static (Offsets, NurbsSurface) {
    static FIT: OnceLock<(Offsets, NurbsSurface)> = OnceLock::new();
    FIT.get_or_init(|| {
        let offsets = series60_sample();
        let surface = fit_offsets(&offsets, &FitConfig::default()).expect("the sample fits").surface;
        (offsets, surface)
    })
}

/// An SVG parsed into what the tests look at: per layer its elements.
struct Svg {
    width: f64,
    height: f64,
    elements: Vec<Element>,
}

/// One drawn element of a layer.
struct Element {
    layer: String,
    tag: String,
    attrs: Vec<(String, String)>,
    text: String,
}

impl Svg {
    fn parse(bytes: &[u8]) -> Svg {
        let text = std::str::from_utf8(bytes).expect("UTF-8");
        let doc = roxmltree::Document::parse(text).expect("well-formed SVG");
        let root = doc.root_element();
        assert_eq!(root.tag_name().name(), "svg");
        let mm = |a: &str| root.attribute(a).and_then(|v| v.strip_suffix("mm")).and_then(|v| v.parse().ok());
        let (width, height): (f64, f64) = (mm("width").expect("width in mm"), mm("height").expect("height in mm"));
        assert_eq!(root.attribute("viewBox"), Some(format!("0 0 {width} {height}").as_str()), "viewBox in mm");
        let mut elements = Vec::new();
        for g in root.children().filter(|n| n.has_tag_name("g")) {
            let layer = g.attribute("id").expect("layer id").to_string();
            for e in g.children().filter(|n| n.is_element()) {
                let attrs = e.attributes().map(|a| (a.name().to_string(), a.value().to_string())).collect();
                let (tag, text) = (e.tag_name().name().to_string(), e.text().unwrap_or("").to_string());
                elements.push(Element { layer: layer.clone(), tag, attrs, text });
            }
        }
        Svg { width, height, elements }
    }

    fn layers(&self) -> Vec<&str> {
        let mut out: Vec<&str> = Vec::new();
        for e in &self.elements {
            if !out.contains(&e.layer.as_str()) {
                out.push(&e.layer);
            }
        }
        out
    }

    fn in_layer<'a>(&'a self, layer: &'a str, tag: &'a str) -> impl Iterator<Item = &'a [(String, String)]> + 'a {
        self.elements.iter().filter(move |e| e.layer == layer && e.tag == tag).map(|e| e.attrs.as_slice())
    }

    /// Text elements (`text`, anchor) of a layer.
    fn texts<'a>(&'a self, layer: &'a str) -> impl Iterator<Item = (&'a str, [f64; 2], &'a str)> + 'a {
        self.elements.iter().filter(move |e| e.layer == layer && e.tag == "text").map(|e| {
            let a = &e.attrs;
            (e.text.as_str(), [attr_f(a, "x"), attr_f(a, "y")], attr(a, "text-anchor").unwrap_or("start"))
        })
    }

    /// Every coordinate of every element (SVG coordinates, y down).
    fn all_points(&self) -> Vec<[f64; 2]> {
        let mut out = Vec::new();
        for Element { tag, attrs: a, .. } in &self.elements {
            match tag.as_str() {
                "polyline" | "polygon" => out.extend(points(a)),
                "circle" => {
                    let (x, y, r) = (attr_f(a, "cx"), attr_f(a, "cy"), attr_f(a, "r"));
                    out.extend([[x - r, y - r], [x + r, y + r]]);
                }
                "text" => out.push([attr_f(a, "x"), attr_f(a, "y")]),
                other => panic!("unexpected element {other}"),
            }
        }
        out
    }
}

fn attr<'a>(a: &'a [(String, String)], name: &str) -> Option<&'a str> {
    a.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str())
}

fn attr_f(a: &[(String, String)], name: &str) -> f64 {
    attr(a, name).and_then(|v| v.parse().ok()).unwrap_or_else(|| panic!("attribute {name} in {a:?}"))
}

fn points(a: &[(String, String)]) -> Vec<[f64; 2]> {
    attr(a, "points")
        .expect("points")
        .split_whitespace()
        .map(|p| {
            let (x, y) = p.split_once(',').expect("x,y");
            [x.parse().expect("x"), y.parse().expect("y")]
        })
        .collect()
}

/// The scale denominator N of "Scale 1:N" in the title block.
fn title_scale(svg: &Svg) -> f64 {
    let (t, ..) = svg.texts("title").find(|(t, ..)| t.starts_with("Scale ")).expect("a scale in the title block");
    let n = t.strip_prefix("Scale 1:").unwrap_or_else(|| panic!("reduction scale expected: {t}"));
    n.parse().unwrap_or_else(|_| panic!("scale {t}"))
}

/// N = m 10^e with m in {1, 2, 2.5, 5}: the standard reduction scales.
fn is_standard_scale(n: f64) -> bool {
    let e = n.log10().floor();
    let m = n / 10f64.powf(e);
    [1.0, 2.0, 2.5, 5.0, 10.0].iter().any(|s| (m - s).abs() < 1e-9) && (n >= 1.0) && !(n > 1.0 && n < 10.0 && m == 2.5)
}

/// The body plan's centreline x: the `CL` label anchored on it.
fn body_centreline(svg: &Svg) -> f64 {
    let cl: Vec<_> = svg.texts("grid").filter(|(t, _, a)| *t == "CL" && *a == "middle").collect();
    assert_eq!(cl.len(), 1, "one centred CL label (the body plan's)");
    cl[0].1[0]
}

#[test]
fn sample_lines_plan_svg() {
    let (offsets, surface) = sample_fit();
    // On A3 (the scale checks below assume its 390 mm frame).
    let opts = LinesPlanOptions { combs: true, sheet: Some(Sheet::A3), ..LinesPlanOptions::default() };
    let d = lines_plan(surface, Some(offsets), Units::Metre, &opts);
    let bytes = svg_bytes(&d);
    keep("sample_lines_plan.svg", &bytes);
    let svg = Svg::parse(&bytes);
    assert_eq!((svg.width, svg.height), (420.0, 297.0), "A3 landscape");

    // Every layer is there.
    let layers = svg.layers();
    for l in LAYERS {
        assert!(layers.contains(&l), "layer {l} missing: {layers:?}");
    }

    // One polyline per station branch; every station of the sample cuts the hull in one branch.
    let stations: Vec<f64> = offsets.sections.iter().map(|s| s.mean_x().expect("points")).collect();
    let planes: Vec<CutPlane> = stations.iter().map(|&x| CutPlane::Station(x)).collect();
    let cuts = cut_surface_many(surface, &planes, &CutOptions::default());
    let cutting = cuts.iter().filter(|c| !c.is_empty()).count();
    let branches: usize = cuts.iter().map(Vec::len).sum();
    let drawn: Vec<Vec<[f64; 2]>> = svg.in_layer("stations", "polyline").map(points).collect();
    assert_eq!(drawn.len(), branches);
    assert_eq!(branches, cutting, "one branch per station");
    assert_eq!(cutting, stations.len(), "every station of the sample cuts the surface");

    // All geometry on the sheet.
    for p in svg.all_points() {
        assert!((0.0..=svg.width).contains(&p[0]) && (0.0..=svg.height).contains(&p[1]), "{p:?} off the sheet");
    }

    // Body plan: aft stations mirrored left of the centreline, fore stations right (one branch
    // each, in station order): every drawn point is CL -/+ y k. Midship: the middle of the
    // offsets' x range. The scale comes from the title block (checked below).
    let cl = body_centreline(&svg);
    let n = title_scale(&svg);
    let k = 1000.0 / n; // paper mm per metre
    let (x_lo, x_hi) = stations.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
    let mid = 0.5 * (x_lo + x_hi);
    let (mut left, mut right) = (0, 0);
    for ((x, pts), cut) in stations.iter().zip(&drawn).zip(&cuts) {
        let side = if *x < mid - 1e-6 { -1.0 } else { 1.0 };
        let model = &cut[0].points;
        assert_eq!(pts.len(), model.len(), "station {x}");
        for (p, m) in pts.iter().zip(model) {
            // 0.001 mm: the SVG's 3-decimal rounding.
            assert!((p[0] - (cl + side * m.point.y * k)).abs() <= 1e-3, "station {x}: {p:?} vs y = {}", m.point.y);
            // Clearly off the centreline (1 cm), a point is on its side.
            if m.point.y > 0.01 {
                assert!(side * (p[0] - cl) > 0.0, "station {x} point {p:?} on the wrong side of {cl}");
                if side < 0.0 {
                    left += 1;
                } else {
                    right += 1;
                }
            }
        }
    }
    assert!(left > 100 && right > 100, "{left} points left, {right} right");

    // Scale: a standard one; the widest station drawn is the surface's largest station
    // half-breadth at that scale, within 0.01 mm.
    assert!(is_standard_scale(n), "scale 1:{n}");
    let drawn_half = drawn.iter().flatten().map(|p| (p[0] - cl).abs()).fold(0.0, f64::max);
    let model_half = cuts.iter().flatten().flat_map(|c| c.points.iter()).map(|p| p.point.y).fold(0.0, f64::max);
    assert!((drawn_half - model_half * k).abs() < 0.01, "drawn {drawn_half} mm, B/2 {model_half} m at 1:{n}");
    // ... and that is the sample's B/2 = 8.13 m up to the fit: the default (approximating)
    // fit misses offsets by up to its max error (0.10 m here) and bulges between them by no
    // more than that (0.06 m at the midship deck).
    let err = measure_fit_error(surface, offsets, None);
    let b2 = hull::SAMPLE_PARTICULARS.beam / 2.0;
    assert!(
        (model_half - b2).abs() <= err.overall.max,
        "surface B/2 {model_half} vs {b2}, max error {}",
        err.overall.max
    );
    // The largest standard scale that fits: the next larger one (1:250 for 1:500) would make
    // the profile longer than the frame (390 mm wide).
    let length_mm = (x_hi - x_lo) * 1000.0;
    let next_larger = view::Scale::standard().into_iter().rev().find(|s| s.ratio() > 1.0 / n).expect("a larger scale");
    assert!(length_mm * next_larger.ratio() + 24.0 > 390.0, "1:{n} is not the largest scale that fits");

    // Markers: one per offset, coloured by error; the worst offset has the top colour.
    let markers: Vec<&[(String, String)]> = svg.in_layer("offsets", "circle").collect();
    assert_eq!(markers.len(), offsets.num_points());
    let colours: std::collections::BTreeSet<&str> = markers.iter().filter_map(|m| attr(m, "fill")).collect();
    assert!(colours.len() >= 10, "marker colours should vary with the error: {colours:?}");
    let worst = err.worst.as_ref().expect("a worst point");
    let k_sec = offsets.sections.iter().position(|s| s.label == worst.section).expect("worst section");
    let index = offsets.sections[..k_sec].iter().map(|s| s.points.len()).sum::<usize>() + worst.index;
    assert_eq!(attr(markers[index], "fill"), Some("#fde725"), "the worst offset gets the top colour");
    // The legend gives the error range in mm: its right label is the max error.
    let legend: Vec<_> = svg.texts("legend").collect();
    let hi = legend.iter().find(|t| t.2 == "end").expect("max label").0;
    let hi: f64 = hi.parse().expect("a number");
    assert!((hi - err.overall.max * 1000.0).abs() <= 0.005 * hi, "legend max {hi} mm vs {} m", err.overall.max);

    // Deterministic: a second run gives the same bytes.
    let again = svg_bytes(&lines_plan(surface, Some(offsets), Units::Metre, &opts));
    assert!(again == bytes, "two runs differ");
}

#[test]
#[cfg_attr(skip_dxf, ignore = "HULLSKIN_SKIP_DXF=1")]
fn sample_lines_plan_dxf_read_by_ezdxf() {
    let python = dxf_python();
    let (offsets, surface) = sample_fit();
    let opts = LinesPlanOptions { combs: true, ..LinesPlanOptions::default() };
    let d = lines_plan(surface, Some(offsets), Units::Metre, &opts);
    let mut out = Vec::new();
    write_dxf(&mut out, &d).expect("writes to memory");
    keep("sample_lines_plan.dxf", &out);
    let (code, summary) = ezdxf_read(&python, &out);
    assert_eq!(code, 0, "{}", summary["audit"]);
    let n = compare_dxf_with_drawing(&summary, &d);
    assert_eq!(n, d.items.len());
    for l in LAYERS {
        assert!(summary["counts"][l].is_object(), "layer {l} has no entities");
    }
    assert_eq!(summary["counts"]["offsets"]["CIRCLE"].as_u64(), Some(offsets.num_points() as u64));
    assert_eq!(summary["counts"]["stations"]["POLYLINE"].as_u64(), Some(d.layer("stations").count() as u64));

    // The 3-D lines of the same plan, in model coordinates.
    let lines = lines_3d(surface, Some(offsets), &opts);
    let mut out = Vec::new();
    write_dxf_3d_lines(&mut out, &lines, Units::Metre).expect("writes");
    keep("sample_lines_3d.dxf", &out);
    let (code, s) = ezdxf_read(&python, &out);
    assert_eq!(code, 0, "{}", s["audit"]);
    let e = s["entities"].as_array().expect("entities");
    assert_eq!(e.len(), lines.len());
    for (ent, (layer, pts)) in e.iter().zip(&lines) {
        assert_eq!(ent["layer"].as_str(), Some(*layer));
        let v = ent["vertices"].as_array().expect("vertices");
        assert_eq!(v.len(), pts.len());
        for (p, q) in pts.iter().zip(v) {
            assert!(near(p.x, f(&q[0])) && near(p.y, f(&q[1])) && near(p.z, f(&q[2])), "{p:?} vs {q}");
        }
    }
    // Stations lie in their planes: every vertex of a station polyline has the same x.
    let stations: Vec<&Value> = e.iter().filter(|x| x["layer"] == "stations").collect();
    assert_eq!(stations.len(), offsets.sections.len());
}

#[test]
fn wigley_midship_station_is_the_parabola() {
    let (l, b, t) = (100.0, 10.0, 6.25);
    let s = wigley_patch(l, b, t);
    // Sanity of the patch itself: y(L/2, z) at z = T/2 is (B/2)(3/4).
    let mid = s.point(0.5, 0.5);
    assert!((mid.y - 0.5 * b * 0.75).abs() < 1e-12 && (mid.x - 50.0).abs() < 1e-12, "{mid:?}");

    let d = lines_plan(&s, None, Units::Metre, &LinesPlanOptions::default());
    let bytes = svg_bytes(&d);
    keep("wigley_lines_plan.svg", &bytes);
    let svg = Svg::parse(&bytes);
    for l in ["offsets", "legend", "combs"] {
        assert!(!svg.layers().contains(&l), "no {l} without offsets and combs");
    }
    let n = title_scale(&svg);
    assert!(is_standard_scale(n));
    let k = 1000.0 / n;
    let cl = body_centreline(&svg);
    // Default stations: 21 from x = 0 to 100; the end stations lie in the plane of a collapsed
    // edge (y = 0) and may or may not give a branch. The midship station (x = 50) is the 11th
    // of the 21 and the widest: find it as the polyline reaching farthest from the centreline.
    let drawn: Vec<Vec<[f64; 2]>> = svg.in_layer("stations", "polyline").map(points).collect();
    assert!(drawn.len() >= 19, "{} stations drawn", drawn.len());
    let widest = drawn
        .iter()
        .max_by(|a, b| {
            let w = |p: &Vec<[f64; 2]>| p.iter().map(|q| (q[0] - cl).abs()).fold(0.0, f64::max);
            w(a).total_cmp(&w(b))
        })
        .expect("stations");
    // The keel point (y = 0, z = 0) is on the centreline at the baseline: the lowest point.
    let base = widest.iter().map(|p| p[1]).fold(f64::NEG_INFINITY, f64::max); // SVG y down
    assert!(widest.len() >= 10);
    // Midship is drawn on the fore (right) side.
    assert!(widest.iter().all(|p| p[0] >= cl - 1e-3));
    let mut checked = 0;
    for p in widest {
        let y = (p[0] - cl) / k;
        let z = (base - p[1]) / k;
        let want = 0.5 * b * (1.0 - (z / t - 1.0).powi(2));
        // 0.002 mm on paper: the SVG's 3-decimal rounding of both coordinates (0.0005 mm each,
        // the parabola's slope at most 2 (B/2)/T = 1.6) plus the cut's tolerance (nm).
        assert!(((y - want) * k).abs() < 0.002, "at z = {z}: drawn y = {y}, parabola {want}");
        checked += 1;
    }
    assert!(checked >= 10);
    // It reaches B/2 at the waterline z = T.
    let top = widest.iter().min_by(|a, b| a[1].total_cmp(&b[1])).expect("points");
    assert!(((top[0] - cl) - 0.5 * b * k).abs() < 0.002 && ((base - top[1]) - t * k).abs() < 0.002, "{top:?}");
}

/// The same hull in millimetres draws the same sheet: only the unit of the numbers changes.
#[test]
fn units_change_labels_not_geometry() {
    let s = wigley_patch(100.0, 10.0, 6.25);
    let pts: Vec<Vec3> = s.control_points().iter().map(|&p| p * 1000.0).collect();
    let s_mm = NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, None).expect("valid");
    let opts = LinesPlanOptions::default();
    let a = Svg::parse(&svg_bytes(&lines_plan(&s, None, Units::Metre, &opts)));
    let b = Svg::parse(&svg_bytes(&lines_plan(&s_mm, None, Units::Millimetre, &opts)));
    assert_eq!(title_scale(&a), title_scale(&b));
    for layer in ["stations", "waterlines", "buttocks", "outline"] {
        let pa: Vec<Vec<[f64; 2]>> = a.in_layer(layer, "polyline").map(points).collect();
        let pb: Vec<Vec<[f64; 2]>> = b.in_layer(layer, "polyline").map(points).collect();
        assert_eq!(pa.len(), pb.len(), "{layer}");
        for (x, y) in pa.iter().flatten().zip(pb.iter().flatten()) {
            // One unit of the 3rd decimal: the two cuts round differently.
            assert!((x[0] - y[0]).abs() <= 1.001e-3 && (x[1] - y[1]).abs() <= 1.001e-3, "{layer}: {x:?} vs {y:?}");
        }
    }
    let units: Vec<&str> = b.texts("title").map(|t| t.0).filter(|t| t.starts_with("Units")).collect();
    assert_eq!(units, ["Units: millimetres"]);
}

/// Given lines are drawn as given (those that miss the hull draw nothing), and a smaller
/// sheet takes a smaller scale: the Wigley hull (L 100 m) is 1:500 on A3, 1:1000 on A5.
#[test]
fn given_lines_and_paper() {
    let s = wigley_patch(100.0, 10.0, 6.25);
    let opts = LinesPlanOptions {
        stations: Some(vec![-10.0, 25.0, 50.0, 75.0, f64::NAN]),
        waterlines: Some(vec![2.0, 4.0]),
        buttocks: Some(vec![1.0, 2.0, 3.0, 20.0]),
        // A5 landscape: 180 mm inside the frame, too short for the 200 mm of the hull at 1:500.
        sheet: Some(Sheet::of_size(210.0, 148.0)),
        ..LinesPlanOptions::default()
    };
    let d = lines_plan(&s, None, Units::Metre, &opts);
    let svg = Svg::parse(&svg_bytes(&d));
    assert_eq!(svg.in_layer("stations", "polyline").count(), 3, "x = -10 misses, NaN is ignored");
    assert_eq!(svg.in_layer("waterlines", "polyline").count(), 2);
    assert_eq!(svg.in_layer("buttocks", "polyline").count(), 3, "y = 20 misses");
    let a5 = title_scale(&svg);
    let on_a3 = LinesPlanOptions { sheet: Some(Sheet::A3), ..LinesPlanOptions::default() };
    let a3 = title_scale(&Svg::parse(&svg_bytes(&lines_plan(&s, None, Units::Metre, &on_a3))));
    assert_eq!((a5, a3), (1000.0, 500.0));
    for p in svg.all_points() {
        assert!((0.0..=210.0).contains(&p[0]) && (0.0..=148.0).contains(&p[1]), "{p:?} off the sheet");
    }
}

// ---------------------------------------------------------------------------------------------
// Layout on the real tables

/// The frame's inner rectangle `[x0, y0, x1, y1]` in SVG coordinates (y down).
fn frame_rect(svg: &Svg) -> [f64; 4] {
    let frames: Vec<Vec<[f64; 2]>> = svg.in_layer("frame", "polygon").map(points).collect();
    assert_eq!(frames.len(), 1, "one frame");
    bbox(&frames[0])
}

fn bbox(points: &[[f64; 2]]) -> [f64; 4] {
    points.iter().fold([f64::INFINITY, f64::INFINITY, f64::NEG_INFINITY, f64::NEG_INFINITY], |b, p| {
        [b[0].min(p[0]), b[1].min(p[1]), b[2].max(p[0]), b[3].max(p[1])]
    })
}

fn area(b: [f64; 4]) -> f64 {
    (b[2] - b[0]).max(0.0) * (b[3] - b[1]).max(0.0)
}

/// The box a text element covers, estimated as the writer sizes it: cap height
/// `font-size x 0.72`, an average advance of 0.85 cap heights per character (a sans-serif face
/// such as Helvetica or DejaVu Sans runs 0.55-0.6 em per character on digits and capitals), and
/// descenders of 0.25 cap height below the baseline.
fn text_box(e: &Element) -> [f64; 4] {
    let a = &e.attrs;
    let (x, y) = (attr_f(a, "x"), attr_f(a, "y"));
    let cap = attr_f(a, "font-size") * view::CAP_HEIGHT_PER_EM;
    let w = e.text.chars().count() as f64 * 0.85 * cap;
    let x0 = match attr(a, "text-anchor").unwrap_or("start") {
        "middle" => x - 0.5 * w,
        "end" => x - w,
        _ => x,
    };
    [x0, y - cap, x0 + w, y + 0.25 * cap]
}

/// What the sheet shows, measured on the SVG: the share of the frame's inner area covered by
/// the three views (the box of each view's cuts: stations in the body plan, waterlines in the
/// half-breadth plan, buttocks in the profile), the title block and the legend; and the texts
/// outside the frame or overlapping another text of the grid.
struct SheetCheck {
    share: f64,
    body_height_mm: f64,
    outside: Vec<String>,
    collisions: Vec<String>,
}

fn check_sheet(svg: &Svg) -> SheetCheck {
    let frame = frame_rect(svg);
    let layer_box = |layer: &str| {
        let pts: Vec<[f64; 2]> = svg
            .elements
            .iter()
            .filter(|e| e.layer == layer)
            .flat_map(|e| match e.tag.as_str() {
                "polyline" | "polygon" => points(&e.attrs),
                "text" => {
                    let b = text_box(e);
                    vec![[b[0], b[1]], [b[2], b[3]]]
                }
                _ => Vec::new(),
            })
            .collect();
        if pts.is_empty() {
            [0.0; 4]
        } else {
            bbox(&pts)
        }
    };
    let body = layer_box("stations");
    let drawn: f64 = ["stations", "waterlines", "buttocks", "title", "legend"].iter().map(|l| area(layer_box(l))).sum();
    let inside = |b: [f64; 4]| b[0] >= frame[0] && b[1] >= frame[1] && b[2] <= frame[2] && b[3] <= frame[3];
    let mut outside = Vec::new();
    for e in svg.elements.iter().filter(|e| e.layer != "frame") {
        let boxes: Vec<[f64; 4]> = match e.tag.as_str() {
            "text" => vec![text_box(e)],
            "polyline" | "polygon" => vec![bbox(&points(&e.attrs))],
            "circle" => {
                let (x, y, r) = (attr_f(&e.attrs, "cx"), attr_f(&e.attrs, "cy"), attr_f(&e.attrs, "r"));
                vec![[x - r, y - r, x + r, y + r]]
            }
            _ => Vec::new(),
        };
        if boxes.iter().any(|&b| !inside(b)) {
            outside.push(format!("{} {} {:?} {:?}", e.layer, e.tag, e.text, boxes[0]));
        }
    }
    let texts: Vec<(&str, [f64; 4])> = svg
        .elements
        .iter()
        .filter(|e| e.tag == "text" && e.layer != "title")
        .map(|e| (e.text.as_str(), text_box(e)))
        .collect();
    let mut collisions = Vec::new();
    for (i, (a, ba)) in texts.iter().enumerate() {
        for (b, bb) in &texts[i + 1..] {
            let overlap = ba[0] < bb[2] && bb[0] < ba[2] && ba[1] < bb[3] && bb[1] < ba[3];
            if overlap {
                collisions.push(format!("{a:?} {ba:?} and {b:?} {bb:?}"));
            }
        }
    }
    SheetCheck { share: drawn / area(frame), body_height_mm: body[3] - body[1], outside, collisions }
}

/// The lines plan of every offsets table in `testdata/` (the files at its top level; `raw/`
/// holds the published sources they were made from), each fitted with the default
/// configuration: on the sheet chosen for it, the views, legend and title block cover at least
/// half of the frame, every element (text boxes included) lies inside the frame and no two
/// labels overlap. The rendered PNG has no ink outside the frame either.
#[test]
fn every_table_fills_half_the_frame_with_every_label_inside() {
    use common::tables::TABLES;
    let mut report = Vec::new();
    let mut failures = Vec::new();
    for name in TABLES.iter().filter(|n| !n.starts_with("raw/")) {
        let path = workspace_root().join("testdata").join(name);
        let offsets = hull::read_offsets(&path, Units::Metre).unwrap_or_else(|e| panic!("{name}: {e}"));
        let surface = fit_offsets(&offsets, &FitConfig::default()).unwrap_or_else(|e| panic!("{name}: {e}")).surface;
        let d = lines_plan(&surface, Some(&offsets), Units::Metre, &LinesPlanOptions::default());
        let bytes = svg_bytes(&d);
        keep(&format!("{}.svg", name.replace('/', "_")), &bytes);
        let svg = Svg::parse(&bytes);
        let c = check_sheet(&svg);
        let sheet = svg.texts("title").find(|t| t.0.starts_with("Sheet ")).map(|t| t.0.to_string()).unwrap_or_default();
        report.push(format!(
            "{name}: {sheet} 1:{} drawn {:.1} % body plan {:.0} mm high",
            title_scale(&svg),
            100.0 * c.share,
            c.body_height_mm
        ));
        // Every station labelled above the profile (in one row, or two when they crowd).
        let labels = svg.texts("grid").filter(|t| t.2 == "middle" && t.0 != "CL").count();
        let counts = svg.texts("title").find(|t| t.0.starts_with("Stations ")).expect("the counts").0;
        let stations: usize =
            counts["Stations ".len()..].split(',').next().and_then(|n| n.parse().ok()).expect("a count");
        if labels != stations {
            failures.push(format!("{name}: {labels} station labels for {stations} stations"));
        }
        if c.share < 0.5 || !c.outside.is_empty() || !c.collisions.is_empty() {
            failures
                .push(format!("{name}: share {:.3}, outside {:?}, collisions {:?}", c.share, c.outside, c.collisions));
        }
        // The pixels: at 60 dpi nothing but white outside the frame line (1 px of anti-aliasing
        // either side of it allowed).
        let image = view::render_rgba(&d, &view::RasterOptions { dpi: 60.0, ..Default::default() }).expect("renders");
        keep(&format!("{}.png", name.replace('/', "_")), &image.to_png().expect("encodes"));
        let px_per_mm = f64::from(image.width()) / svg.width;
        let frame = frame_rect(&svg);
        let (fx0, fy0, fx1, fy1) = (
            (frame[0] * px_per_mm).floor() as u32 - 1,
            (frame[1] * px_per_mm).floor() as u32 - 1,
            (frame[2] * px_per_mm).ceil() as u32 + 1,
            (frame[3] * px_per_mm).ceil() as u32 + 1,
        );
        let mut ink_outside = 0;
        for y in 0..image.height() {
            for x in 0..image.width() {
                let out = x < fx0 || x > fx1 || y < fy0 || y > fy1;
                if out && image.pixel(x, y) != Some(Rgb::WHITE) {
                    ink_outside += 1;
                }
            }
        }
        if ink_outside > 0 {
            failures.push(format!("{name}: {ink_outside} pixels of ink outside the frame"));
        }
    }
    eprintln!("{}", report.join("\n"));
    assert!(failures.is_empty(), "{failures:#?}");
}
