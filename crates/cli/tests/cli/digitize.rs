//! `hullskin digitize` end to end: the hand-made barge drawings (testdata/digitize/) read
//! into a sections CSV that `read_offsets` reads back, the sample's lines plan digitised and
//! fitted again, and bad input refused with a clear message and a non-zero exit.

use std::path::Path;

use hull::{fit_offsets, read_offsets, series60_sample, FitConfig, Offsets, Units};
use view::{lines_plan, write_dxf, Item, LinesPlanOptions, Rgb};

use crate::common::*;

fn run_ok(dir: &Path, args: &[&str]) -> (String, String) {
    let o = hullskin(dir, args);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{args:?}\nstdout {out}\nstderr {err}");
    (out, err)
}

fn run_err(dir: &Path, args: &[&str]) -> String {
    let o = hullskin(dir, args);
    let (out, err) = text(&o);
    assert!(!o.status.success(), "{args:?} should fail\nstdout {out}");
    assert!(!err.contains("panicked"), "{err}");
    err
}

/// The barge's deck edges (y, z) in metres: ST0 (2, 2.5), ST5 (3, 3), ST10 (1, 3); every
/// station starts at the keel on the centreline (see testdata/digitize/README.md).
fn check_barge(o: &Offsets) {
    let labels: Vec<&str> = o.sections.iter().map(|s| s.label.as_str()).collect();
    assert_eq!(labels, ["ST0", "ST5", "ST10"]);
    for (s, (x, deck)) in o.sections.iter().zip([(0.0, [2.0, 2.5]), (10.0, [3.0, 3.0]), (20.0, [1.0, 3.0])]) {
        let (first, last) = (s.points[0], s.points[s.points.len() - 1]);
        // Exact decimals in the drawings; 1e-12 m leaves room for the arcs' round-off.
        assert!(first.y.abs() < 1e-12 && first.z.abs() < 1e-12, "{}: {first:?}", s.label);
        assert!((last.y - deck[0]).abs() < 1e-12 && (last.z - deck[1]).abs() < 1e-12, "{}: {last:?}", s.label);
        assert!(s.points.iter().all(|p| p.x == x));
    }
}

#[test]
fn hand_made_dxf_by_layers_to_a_sections_csv() {
    let dir = temp_dir();
    let dxf = testdata("digitize/barge.dxf");
    let args = [
        "digitize",
        dxf.to_str().expect("UTF-8 path"),
        "--scale",
        "1:50",
        "--datum",
        "100,50",
        "--station-layer-pattern",
        "ST*",
        "--stations",
        "ST0=0,ST5=10,ST10=20",
    ];
    let (out, err) = run_ok(dir.path(), &[&args[..], &["-o", "barge.csv"]].concat());
    let csv = dir.path().join("barge.csv");
    let text = std::fs::read_to_string(&csv).expect("written");
    assert!(text.starts_with("section,x,y,z\nST0,0,0,0\n"), "{text}");
    check_barge(&read_offsets(&csv, Units::Metre).expect("reads back"));
    assert!(out.contains("wrote barge.csv: 3 sections"), "{out}");
    let st0 = out.lines().find(|l| l.starts_with("ST0 ")).expect("a row for ST0");
    assert!(st0.contains("aft"), "{st0}");
    assert!(err.is_empty(), "no notes with the layers picked: {err}");

    // --json: the same stations and file, for scripts, on standard output.
    let (out, _) = run_ok(dir.path(), &[&args[..], &["-o", "again.csv", "--json"]].concat());
    let doc: serde_json::Value = serde_json::from_str(&out).expect("stdout is one JSON object");
    assert_eq!(
        (doc["sections"].as_u64(), doc["wrote"].as_str(), doc["units"].as_str()),
        (Some(3), Some("again.csv"), Some("m"))
    );
    let stations = doc["stations"].as_array().expect("stations");
    let rows: Vec<(&str, f64, &str)> = stations
        .iter()
        .map(|s| (s["label"].as_str().expect("label"), s["x"].as_f64().expect("x"), s["side"].as_str().expect("side")))
        .collect();
    assert_eq!(rows, [("ST0", 0.0, "aft"), ("ST5", 10.0, "fore"), ("ST10", 20.0, "fore")]);
    assert_eq!(std::fs::read(dir.path().join("again.csv")).expect("written"), text.as_bytes());
}

#[test]
fn hand_made_svg_by_labels_with_a_station_spacing() {
    let dir = temp_dir();
    let svg = testdata("digitize/barge.svg");
    let (_, err) = run_ok(
        dir.path(),
        &[
            "digitize",
            svg.to_str().expect("UTF-8 path"),
            "--scale",
            "1:50",
            "--datum",
            "100,100",
            "--labels",
            "--station-spacing",
            "2",
            "--points",
            "7",
        ],
    );
    let o = read_offsets(&dir.path().join("sections.csv"), Units::Metre).expect("reads back");
    check_barge(&o);
    assert!(o.sections.iter().all(|s| s.points.len() == 7));
    // The frame rectangle is skipped and the centreline line has no station label.
    assert!(err.contains("note: <rect> (1, first at"), "{err}");
    assert!(err.contains("note: 1 curve(s) without a station label skipped, first line at"), "{err}");
}

/// The sample's lines plan, written as DXF by the crate, digitised by the command line with
/// the scale from its title block, resampled to 15 points per station, and fitted again: the
/// approximating refit passes within 2 cm of the digitised points (1.2 cm measured; the
/// default approximation of the sample itself is of that order), so the digitised offsets
/// make a usable hull.
#[test]
fn sample_lines_plan_digitised_and_fitted_again() {
    let dir = temp_dir();
    let fit = fit_offsets(&series60_sample(), &FitConfig::default()).expect("fits");
    let n = 19;
    let (lo, hi) = (0.0f64, 121.92f64);
    let xs: Vec<f64> = (1..=n).map(|i| lo + (hi - lo) * f64::from(i) / 20.0).collect();
    let opts = LinesPlanOptions { stations: Some(xs.clone()), ..LinesPlanOptions::default() };
    let d = lines_plan(&fit.surface, None, Units::Metre, &opts);
    let path = dir.path().join("lines.dxf");
    let mut bytes = Vec::new();
    write_dxf(&mut bytes, &d).expect("writes");
    std::fs::write(&path, bytes).expect("writes");
    // Datum: the body plan's dashed centreline and its black baseline; scale from the title.
    let lines: Vec<&Vec<[f64; 2]>> = d
        .layer("grid")
        .filter_map(|i| match i {
            Item::Polyline { points, stroke, .. } if points.len() == 2 && stroke.color == Rgb::BLACK => Some(points),
            _ => None,
        })
        .collect();
    let cl = lines.iter().find(|p| p[0][0] == p[1][0]).map(|p| p[0][0]).expect("centreline");
    let bl = lines
        .iter()
        .find(|p| p[0][1] == p[1][1] && p[0][0].min(p[1][0]) < cl && p[0][0].max(p[1][0]) > cl)
        .map(|p| p[0][1])
        .expect("baseline");
    let scale = d
        .items
        .iter()
        .find_map(|i| match i {
            Item::Text { text, .. } => text.strip_prefix("Scale ").map(str::to_string),
            _ => None,
        })
        .expect("scale");
    let stations: Vec<String> = xs.iter().map(|x| x.to_string()).collect();
    let datum = format!("{cl},{bl}");
    run_ok(
        dir.path(),
        &[
            "digitize",
            "lines.dxf",
            "--scale",
            &scale,
            "--datum",
            &datum,
            "--layer",
            "stations",
            "--stations",
            &stations.join(","),
            "--points",
            "15",
            "-o",
            "digitised.csv",
        ],
    );
    let o = read_offsets(&dir.path().join("digitised.csv"), Units::Metre).expect("reads back");
    assert_eq!(o.sections.len(), n as usize);
    let refit = fit_offsets(&o, &FitConfig::default()).expect("the digitised offsets fit");
    eprintln!("refit of the digitised sample: max error {:.3e} m", refit.error.overall.max);
    assert!(refit.error.overall.max < 0.02, "{}", refit.error.overall.max);
}

#[test]
fn bad_input_is_refused_clearly() {
    let dir = temp_dir();
    let dxf = testdata("digitize/barge.dxf");
    let dxf = dxf.to_str().expect("UTF-8 path");
    let base = ["digitize", dxf, "--datum", "100,50", "--station-layer-pattern", "ST*"];

    let err = run_err(dir.path(), &[&base[..], &["--stations", "ST0=0,ST5=10"]].concat());
    assert!(err.contains("--scale"), "missing scale: {err}");

    let with_scale = [&base[..], &["--scale", "1:50"]].concat();
    let err = run_err(dir.path(), &[&with_scale[..], &["--stations", "ST0=0,ST5=10"]].concat());
    assert!(err.contains("barge.dxf:") && err.contains("unknown station \"ST10\""), "{err}");

    let err = run_err(dir.path(), &with_scale);
    assert!(err.contains("stations' positions are not given"), "{err}");

    let err = run_err(
        dir.path(),
        &[
            "digitize",
            dxf,
            "--scale",
            "1:50",
            "--datum",
            "120,50",
            "--station-layer-pattern",
            "ST*",
            "--station-spacing",
            "2",
        ],
    );
    assert!(err.contains("crosses the centreline X = 120"), "{err}");

    let err = run_err(dir.path(), &[&base[..], &["--stations", "ST0=0,ST5=10,ST10=20", "--scale", "1:0"]].concat());
    assert!(err.contains("scale \"1:0\" (expected paper:model such as 1:50"), "{err}");

    std::fs::write(dir.path().join("cut.dxf"), "0\nSECTION\n2\nENTITIES\n0\nLINE\n8\nST1\n10\n").expect("writes");
    let err =
        run_err(dir.path(), &["digitize", "cut.dxf", "--scale", "1:50", "--datum", "0,0", "--station-spacing", "1"]);
    assert!(err.contains("cut.dxf:9: the file ends after group code 10"), "{err}");
    assert!(!dir.path().join("sections.csv").exists(), "nothing written on failure");
}
