//! `hullskin hydrostatics` end to end: the figures in JSON, CSV and text, a surface.json from
//! `fit` giving the same bits as fitting on the fly, ranges, units, and bad input refused with
//! a clear message and a non-zero exit.

use std::fs;
use std::path::Path;

use serde_json::Value;

use crate::common::*;

/// The column keys, in order, with the perpendiculars known (the sample's, or `--lpp`).
const KEYS: [&str; 26] = [
    "draft",
    "lwl",
    "bwl",
    "vol",
    "displ",
    "lcb",
    "lcb_pct_lpp",
    "vcb",
    "cb",
    "cb_lpp",
    "am",
    "cm",
    "cm_lpp",
    "aw",
    "cw",
    "cp",
    "cp_lpp",
    "lcf",
    "lcf_pct_lpp",
    "s",
    "tpc",
    "mct",
    "bmt",
    "bml",
    "kmt",
    "kml",
];

/// The keys only given with the perpendiculars.
const LPP_KEYS: [&str; 5] = ["lcb_pct_lpp", "cb_lpp", "cm_lpp", "cp_lpp", "lcf_pct_lpp"];

/// The index of `key` in [`KEYS`].
fn col(key: &str) -> usize {
    KEYS.iter().position(|k| *k == key).expect("a key")
}

/// The sample's particulars (Todd 1963, Series 60 Cb 0.60 as scaled in testdata/README.md).
const LPP: f64 = 121.92;
const B: f64 = 16.26;
const T: f64 = 6.5;

fn run_ok(dir: &Path, args: &[&str]) -> String {
    let o = hullskin(dir, args);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{args:?}\nstdout {out}\nstderr {err}");
    out
}

/// CSV text as rows of numbers, checking the header is all of [`KEYS`].
fn csv_rows(csv: &str) -> Vec<Vec<f64>> {
    csv_rows_of(csv, &KEYS)
}

/// CSV text as rows of numbers, checking the header is `keys`.
fn csv_rows_of(csv: &str, keys: &[&str]) -> Vec<Vec<f64>> {
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some(keys.join(",").as_str()));
    lines.map(|l| l.split(',').map(|v| v.parse().expect("a number")).collect()).collect()
}

#[test]
fn sample_at_its_draft_has_todds_block_coefficient_in_json_and_csv() {
    let dir = temp_dir();
    let out = run_ok(dir.path(), &["hydrostatics", "--draft", "6.5", "--format", "json", "-o", "h.json"]);
    assert!(out.contains("wrote h.json"), "{out}");
    let doc = read_json(&dir.path().join("h.json"));
    assert_eq!(doc["units"], "m");
    assert_eq!(doc["density"], 1.025);
    let rows = doc["rows"].as_array().expect("rows");
    assert_eq!(rows.len(), 1);
    let row = rows[0].as_object().expect("a row");
    let mut keys: Vec<&str> = row.keys().map(String::as_str).collect();
    keys.sort_unstable();
    let mut want = KEYS.to_vec();
    want.sort_unstable();
    assert_eq!(keys, want);
    let get = |k: &str| row[k].as_f64().expect("a number");
    // The sample's perpendiculars are its table's ends, AP at x = 0. Todd's Cb is
    // V / (Lpp B T): within the 1 % floor of the brief, LCB within 0.5 % Lpp from amidships
    // (positive forward: -1.5 is aft).
    assert_eq!((doc["perpendiculars"]["aft"].as_f64(), doc["perpendiculars"]["fore"].as_f64()), (Some(0.0), Some(LPP)));
    let cb_pp = get("vol") / (LPP * B * T);
    assert!((cb_pp / 0.60 - 1.0).abs() < 0.01, "Cb {cb_pp}");
    // The library's CB(Lpp) takes Bwl for B: the fitted 1.0 WL is within 0.5 % of B (the
    // default fit, chord-length parameters held on the surface by the held-out referee, is
    // 16.211 m wide there against B = 16.26 m: 24.7 mm inside each side, within its max error
    // of 94 mm at the offsets; the interpolation is 16.280 m wide, 0.12 % outside).
    assert!((get("cb_lpp") / cb_pp - 1.0).abs() < 5e-3, "CB(Lpp) {} vs {cb_pp}", get("cb_lpp"));
    assert!((get("bwl") / B - 1.0).abs() < 5e-3, "Bwl {}", get("bwl"));
    let lcb_pct = (get("lcb") - LPP / 2.0) / LPP * 100.0;
    assert!((lcb_pct + 1.5).abs() < 0.5, "LCB {lcb_pct} % Lpp");
    assert!((get("lcb_pct_lpp") - lcb_pct).abs() < 1e-12, "LCB {} % Lpp", get("lcb_pct_lpp"));
    // Displacement is the volume times the density; the coefficients are FREE!ship's.
    assert_eq!(get("displ"), get("vol") * 1.025);
    let cb = get("vol") / (get("lwl") * get("bwl") * get("draft"));
    assert!((get("cb") - cb).abs() < 1e-12, "{} vs {cb}", get("cb"));
    // TPC: AW x 1 cm x 1.025 t/m³; MCT: Displ BMl / (100 Lpp); the metacentres above KB.
    assert!((get("tpc") - get("aw") * 0.01 * 1.025).abs() < 1e-12 * get("tpc"), "TPC {}", get("tpc"));
    assert!((get("mct") - get("displ") * get("bml") / (100.0 * LPP)).abs() < 1e-12 * get("mct"));
    assert!((get("kmt") - get("vcb") - get("bmt")).abs() < 1e-12 * get("kmt"));
    assert!((get("kml") - get("vcb") - get("bml")).abs() < 1e-12 * get("kml"));

    // --json prints the same document on standard output.
    let json = run_ok(dir.path(), &["hydrostatics", "--draft", "6.5", "--json"]);
    assert_eq!(serde_json::from_str::<serde_json::Value>(&json).expect("JSON on stdout"), doc);

    // The same figures, the same bits, as CSV on standard output.
    let csv = run_ok(dir.path(), &["hydrostatics", "--draft", "6.5", "--format", "csv"]);
    let rows = csv_rows(&csv);
    assert_eq!(rows.len(), 1);
    for (k, v) in KEYS.iter().zip(&rows[0]) {
        assert_eq!(*v, get(k), "{k}");
    }
}

#[test]
fn a_surface_json_from_fit_gives_the_same_figures_as_fitting_on_the_fly() {
    let dir = temp_dir();
    run_ok(dir.path(), &["fit", "-o", "out"]);
    let range = ["--draft", "2", "--to", "6", "--step", "2", "--format", "csv"];
    let json_args = |extra: &[&'static str]| [&["hydrostatics", "out/surface.json"][..], &range, extra].concat();
    let from_json = run_ok(dir.path(), &json_args(&["--lpp", "121.92"]));
    let on_the_fly = run_ok(dir.path(), &[&["hydrostatics"][..], &range].concat());
    // surface.json is lossless: the same surface, so the same bits (its perpendiculars, which
    // the sample's offsets carry, given by --lpp).
    assert_eq!(from_json, on_the_fly);
    // Without them the figures on Lpp are left out, the rest unchanged but MCT, then taken on
    // Lwl (121.92000000000002 here, 1 ulp off Lpp).
    let plain = run_ok(dir.path(), &json_args(&[]));
    let header: Vec<&str> = plain.lines().next().expect("a header").split(',').collect();
    let want: Vec<&str> = KEYS.iter().copied().filter(|k| !LPP_KEYS.contains(k)).collect();
    assert_eq!(header, want);
    for (a, b) in csv_rows_of(&plain, &want).iter().zip(csv_rows(&from_json)) {
        for (k, v) in want.iter().zip(a) {
            let with_lpp = b[col(k)];
            if *k == "mct" {
                let on_lwl = b[col("displ")] * b[col("bml")] / (100.0 * b[col("lwl")]);
                assert!((v - on_lwl).abs() <= 1e-12 * v, "MCT {v} vs {on_lwl}");
            } else {
                assert_eq!(*v, with_lpp, "{k}");
            }
        }
    }
    let rows = csv_rows(&from_json);
    assert_eq!(rows.iter().map(|r| r[0]).collect::<Vec<_>>(), vec![2.0, 4.0, 6.0]);
    // Volume, waterplane area and wetted surface grow with the draft.
    for c in [col("vol"), col("aw"), col("s")] {
        assert!(rows.windows(2).all(|w| w[1][c] > w[0][c]), "column {}", KEYS[c]);
    }
}

/// `hullskin hydrostatics x.igs` and `x.stp`: the surface exported by `hullskin export` and
/// read back gives the very figures of its surface.json (both formats carry it bit for bit);
/// a file of two surfaces is integrated as two patches by `hydrostatics` and refused, with
/// their names, by `export` (one surface).
#[test]
fn iges_and_step_surfaces_give_the_figures_of_their_surface_json() {
    let dir = temp_dir();
    let d = dir.path();
    run_ok(d, &["fit", "-o", "out"]);
    let args =
        |input: &'static str| ["hydrostatics", input, "--draft", "2", "--to", "6", "--step", "2", "--format", "csv"];
    let from_json = run_ok(d, &args("out/surface.json"));
    for file in ["x.igs", "x.stp"] {
        run_ok(d, &["export", "out/surface.json", "-o", file, "--timestamp", "0"]);
        let o = hullskin(d, &args(file));
        let (out, err) = text(&o);
        assert!(o.status.success(), "{file}: {err}");
        assert_eq!(out, from_json, "{file}");
        if file.ends_with(".stp") {
            assert!(err.contains("hullskin: note: x.stp: the bounds of 1 face (ADVANCED_FACE) ignored"), "{err}");
        }
    }
    // A second copy of the surface instance: two surfaces, refused with their names.
    let stp = fs::read_to_string(d.join("x.stp")).expect("read");
    let start = stp.find("B_SPLINE_SURFACE_WITH_KNOTS('hull'").expect("the surface");
    let id_start = stp[..start].rfind('#').expect("its name");
    let end = id_start + stp[id_start..].find(";\n").expect("its end") + 2;
    let copy = format!("#999999{}", &stp[stp[id_start..].find('=').expect("=") + id_start..end]);
    let two = stp.replacen("ENDSEC;\nEND-ISO-10303-21;", &format!("{copy}ENDSEC;\nEND-ISO-10303-21;"), 1);
    fs::write(d.join("two.stp"), two).expect("write");
    // The same patch twice: every extensive figure twice the one patch's (the patches are
    // summed; an overlap counts twice), the coefficients on Lwl unchanged up to round-off.
    let o = hullskin(d, &["hydrostatics", "two.stp", "--draft", "4", "--format", "json"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{err}");
    assert!(err.contains("2 surfaces (#") && err.contains("integrated together"), "{err}");
    let two: Value = serde_json::from_str(&out).expect("JSON");
    let one: Value =
        serde_json::from_str(&run_ok(d, &["hydrostatics", "x.stp", "--draft", "4", "--format", "json"])).expect("JSON");
    let get = |v: &Value, k: &str| v["rows"][0][k].as_f64().expect("a number");
    for k in ["vol", "aw", "s", "displ", "tpc"] {
        assert!((get(&two, k) - 2.0 * get(&one, k)).abs() <= 1e-12 * get(&two, k), "{k}");
    }
    for k in ["lcb", "vcb", "lwl", "kmt"] {
        assert!((get(&two, k) - get(&one, k)).abs() <= 1e-12 * get(&one, k).abs().max(1.0), "{k}");
    }
    let o = hullskin(d, &["export", "two.stp", "-o", "two.igs"]);
    let (_, err) = text(&o);
    assert!(!o.status.success());
    assert!(
        err.contains("two.stp: 2 B-spline surfaces (#")
            && err.contains(", #999999 'hull'); this command takes one surface"),
        "{err}"
    );
}

#[test]
fn text_table_is_aligned_with_units_and_one_line_per_draft() {
    let dir = temp_dir();
    let out = run_ok(dir.path(), &["hydrostatics", "--draft", "1", "--to", "9", "--step", "1", "--method", "interp"]);
    let lines: Vec<&str> = out.lines().collect();
    assert!(lines[0].contains("Series 60") && lines[0].contains("interp"), "{out}");
    // The conventions: Lpp and amidships, the sign of the percentages.
    assert!(lines[1].contains("Lpp 121.9 m") && lines[1].contains("amidships x = 60.96"), "{out}");
    assert!(lines[1].contains("+ forward"), "{out}");
    assert_eq!(lines.len(), 4 + 9, "{out}");
    assert!(
        lines[2].split_whitespace().eq([
            "Draft", "Lwl", "Bwl", "Vol", "Displ", "LCB", "LCB", "VCB", "CB", "CB(Lpp)", "AM", "CM", "CM(Lpp)", "AW",
            "CW", "CP", "CP(Lpp)", "LCF", "LCF", "S", "TPC", "MCT", "BMt", "BMl", "KMt", "KMl"
        ]),
        "{}",
        lines[2]
    );
    for unit in ["[m]", "[m²]", "[m³]", "[t]", "[% Lpp]", "[t/cm]", "[t·m/cm]"] {
        assert!(lines[3].contains(unit), "{unit}: {}", lines[3]);
    }
    let width = lines[2].chars().count();
    assert!(lines[2..].iter().all(|l| l.chars().count() == width), "{out}");
    // The last line is the 9 m draft, and its block coefficient a fraction; five significant
    // digits.
    let cells: Vec<&str> = lines[12].split_whitespace().collect();
    let last: Vec<f64> = cells.iter().map(|v| v.parse().expect("a number")).collect();
    assert_eq!((cells[0], last[0]), ("9.0000", 9.0));
    assert!((0.5..0.8).contains(&last[col("cb")]), "CB {}", last[col("cb")]);
    let digits = |s: &str| s.trim_start_matches(['-', '0', '.']).chars().filter(char::is_ascii_digit).count();
    assert!(cells.iter().all(|c| *c == "0" || digits(c) >= 5), "{}", lines[12]);
}

#[test]
fn wigley_offsets_in_feet_give_four_ninths_and_tonnes() {
    let dir = temp_dir();
    let input = testdata("wigley_offsets.csv");
    let out = run_ok(
        dir.path(),
        &["hydrostatics", input.to_str().expect("utf-8"), "--units", "ft", "--draft", "6.25", "--format", "json"],
    );
    let doc: Value = serde_json::from_str(&out).expect("JSON on standard output");
    assert_eq!(doc["units"], "ft");
    let row = &doc["rows"][0];
    let get = |k: &str| row[k].as_f64().expect("a number");
    // The exact Wigley hull (L 100, B 10, T 6.25): CB 4/9 (the fit is within 1e-5 of it).
    assert!((get("cb") - 4.0 / 9.0).abs() < 1e-4, "CB {}", get("cb"));
    assert!((get("vcb") - 5.0 * 6.25 / 8.0).abs() < 1e-3, "KB {}", get("vcb"));
    // The volume is in ft³; the displacement in tonnes: 1.025 t/m³ x 0.3048³ m³/ft³.
    let ratio = get("displ") / get("vol");
    assert!((ratio - 1.025 * 0.3048f64.powi(3)).abs() < 1e-15, "{ratio}");
    // TPC in t/cm whatever the unit: AW in m² x 0.01 m x 1.025 t/m³.
    let tpc = get("aw") * 0.3048f64.powi(2) * 0.01 * 1.025;
    assert!((get("tpc") - tpc).abs() < 1e-12 * tpc, "TPC {} vs {tpc}", get("tpc"));
    // No perpendiculars in a sections CSV: no figures on Lpp.
    assert!(row.get("cb_lpp").is_none() && doc.get("perpendiculars").is_none(), "{out}");
}

#[test]
fn bad_input_is_refused_with_a_message_and_no_panic() {
    let dir = temp_dir();
    let bad_json = dir.path().join("bad.json");
    fs::write(&bad_json, "{\"format\": \"hullskin-surface\", \"version\": 1}").expect("write");
    let bad = bad_json.to_str().expect("utf-8");
    let cases: &[(&[&str], &str)] = &[
        (&["hydrostatics", "missing.json", "--draft", "2"], "missing.json"),
        (&["hydrostatics", bad, "--draft", "2"], "bad.json"),
        (&["hydrostatics", "--draft", "0"], "greater than 0"),
        (&["hydrostatics", "--draft", "-2"], "greater than 0"),
        (&["hydrostatics", "--draft", "NaN"], "greater than 0"),
        (&["hydrostatics", "--draft", "2", "--to", "4", "--step", "0"], "step"),
        (&["hydrostatics", "--draft", "2", "--to", "4", "--step", "-1"], "step"),
        (&["hydrostatics", "--draft", "2", "--to", "4"], "--step"),
        (&["hydrostatics", "--draft", "2", "--density", "-1"], "density"),
        (&["hydrostatics", "--draft", "12"], "above the top"),
        (&["hydrostatics", "--draft", "2", "--method", "ga"], "surface.json"),
        (&["hydrostatics"], "--draft"),
        (&["hydrostatics", "--draft", "2", "--lpp", "-5"], "positive Lpp"),
        (&["hydrostatics", "--draft", "2", "--ap", "3"], "--lpp"),
    ];
    for (args, message) in cases {
        let o = hullskin(dir.path(), args);
        let (out, err) = text(&o);
        assert!(!o.status.success(), "{args:?} succeeded: {out}");
        assert!(err.contains(message), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
}
