//! The `hullskin` binary end to end: the default run, the outputs' stable layout, bad input
//! reported with file, line and column, and earlier results never lost.

use std::fs;

use crate::common::*;

#[test]
fn no_arguments_fits_the_builtin_sample_and_prints_a_table() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &[]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    assert!(out.contains("Series 60") && out.contains("max err") && out.contains("approx"), "{out}");
    let report = read_json(&dir.path().join("hullskin-out/report.json"));
    assert_eq!(report["input"]["sections"], 25);
    assert!(dir.path().join("hullskin-out/surface.igs").is_file());
    assert!(dir.path().join("hullskin-out/surface.json").is_file());
}

#[test]
fn report_json_has_the_stable_fields() {
    let dir = temp_dir();
    let input = testdata("sections_example.csv");
    let o = hullskin(dir.path(), &["fit", input.to_str().expect("utf-8 path"), "-o", "out", "--method", "interp"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let r = read_json(&dir.path().join("out/report.json"));
    assert_eq!(r["method"], "interp");
    assert_eq!(r["input"]["sections"], 3);
    assert_eq!(r["input"]["points"], 12);
    // 3 sections cap the degree across them at 2; 4 points per section carry a cubic.
    assert_eq!(r["surface"]["degree"], serde_json::json!([3, 2]));
    assert_eq!(r["surface"]["control_points"], serde_json::json!([4, 3]));
    assert_eq!(r["surface"]["rational"], false);
    for k in ["max", "mean", "rms"] {
        // Interpolation: the true distance is round-off on a 10 m model.
        let e = r["error"][k].as_f64().expect("number");
        assert!((0.0..1e-9).contains(&e), "{k} = {e}");
    }
    assert!(r["seconds"].as_f64().expect("number") >= 0.0);
}

#[test]
fn units_reach_the_exports() {
    let dir = temp_dir();
    let input = testdata("offsets_example.csv");
    let o = hullskin(dir.path(), &["fit", input.to_str().expect("utf-8"), "-o", "mm", "--units", "mm"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let iges = fs::read_to_string(dir.path().join("mm/surface.igs")).expect("iges");
    let global: String = iges.lines().filter(|l| l.as_bytes().get(72) == Some(&b'G')).map(|l| &l[..72]).collect();
    assert!(global.contains(",2,2HMM,"), "units flag 2 and name MM in the global section: {global}");
    assert_eq!(read_json(&dir.path().join("mm/surface.json"))["units"], "mm");
    assert_eq!(read_json(&dir.path().join("mm/report.json"))["input"]["units"], "mm");
}

/// Each bad input: (file content, what the message must contain).
const BAD: &[(&str, &str, &[&str])] = &[
    ("non_numeric", "section,x,y,z\na,0,0,0\na,0,1,x1\na,0,2,2\n", &[":3:4:", "not a number"]),
    ("nan", "section,x,y,z\na,0,0,0\na,0,NaN,1\n", &[":3:3:", "finite"]),
    ("inf", "z\\x,0,1\n0,1,inf\n1,2,2\n", &[":2:3:", "finite"]),
    ("column_count", "section,x,y,z\na,0,0,0\na,0,1\n", &[":3", "fields"]),
    ("one_section", "section,x,y,z\na,0,0,0\na,0,1,1\na,0,2,2\na,0,3,3\n", &["section", "expected at least 2"]),
    ("too_few_points", "section,x,y,z\na,0,0,0\na,0,1,1\nb,1,0,0\nb,1,1,1\n", &[":2", "expected at least 4 points"]),
    (
        "repeated_point",
        "section,x,y,z\na,0,0,0\na,0,1,1\na,0,1,1\na,0,2,2\na,0,3,3\nb,1,0,0\nb,1,1,1\nb,1,2,2\nb,1,3,3\n",
        &[":4", "repeat"],
    ),
    ("stations_out_of_order", "z\\x,0,2,1,3\n0,1,1,1,1\n1,2,2,2,2\n", &[":1", "order"]),
    ("empty", "", &["empty"]),
    ("binary", "\u{0}\u{1}PNG\u{0}\u{0}", &["binary"]),
];

#[test]
fn bad_input_is_reported_with_its_place_and_a_nonzero_exit() {
    let dir = temp_dir();
    for (name, content, needles) in BAD {
        let path = dir.path().join(format!("{name}.csv"));
        fs::write(&path, content).expect("write");
        let o = hullskin(dir.path(), &["fit", path.to_str().expect("utf-8"), "-o", "out"]);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{name}: exit {:?}, stdout {out} stderr {err}", o.status);
        assert!(!err.contains("panicked"), "{name}: {err}");
        assert!(err.contains(&format!("{name}.csv")), "{name}: message names the file: {err}");
        for n in *needles {
            assert!(err.to_lowercase().contains(&n.to_lowercase()), "{name}: `{n}` missing from: {err}");
        }
        assert!(!dir.path().join("out").exists(), "{name}: nothing written on failure");
    }
}

#[test]
fn missing_file_and_bad_flags_are_clear_errors() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &["fit", "no_such_file.csv"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2));
    assert!(err.contains("no_such_file.csv"), "{err}");
    let o = hullskin(dir.path(), &["fit", "--ctrl", "40,3"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("40") && err.contains("control points"), "{err}");
    let o = hullskin(dir.path(), &["fit", "--ctrl", "4x3"]);
    assert_eq!(o.status.code(), Some(2));
    let o = hullskin(dir.path(), &["fit", "--param", "bogus"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("centripetal"), "lists the choices");
}

#[test]
fn a_failed_run_leaves_earlier_results_intact() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &["fit", "-o", "out"]);
    assert!(o.status.success());
    let before: Vec<Vec<u8>> = ["surface.igs", "surface.json", "report.json"]
        .iter()
        .map(|f| fs::read(dir.path().join("out").join(f)).expect("read"))
        .collect();
    let bad = dir.path().join("bad.csv");
    fs::write(&bad, "section,x,y,z\na,0,0,oops\n").expect("write");
    let o = hullskin(dir.path(), &["fit", bad.to_str().expect("utf-8"), "-o", "out"]);
    assert_eq!(o.status.code(), Some(2));
    let o = hullskin(dir.path(), &["fit", "-o", "out", "--ctrl", "99,99"]);
    assert_eq!(o.status.code(), Some(2));
    for (f, b) in ["surface.igs", "surface.json", "report.json"].iter().zip(&before) {
        assert_eq!(&fs::read(dir.path().join("out").join(f)).expect("read"), b, "{f} unchanged");
    }
    let leftovers: Vec<_> = fs::read_dir(dir.path().join("out")).expect("list").collect();
    assert_eq!(leftovers.len(), 3, "no temporary files left behind");
}

/// `--knuckles auto+flats` keeps the 116 m cargo ship's approximation inside its flat of side
/// and flat of bottom: every control point (hence, by the convex hull property, the surface)
/// within y <= B/2 and z >= the keel, where the plain fit's net rings past both.
#[test]
fn auto_flats_keeps_the_cargo_ship_inside_its_flats() {
    let dir = temp_dir();
    let input = testdata("cargo116_offsets.csv");
    let input = input.to_str().expect("utf-8 path");
    let table = fs::read_to_string(input).expect("read");
    let rows: Vec<[f64; 3]> = table
        .lines()
        .skip(1)
        .filter_map(|l| {
            let f: Vec<f64> = l.split(',').skip(1).filter_map(|v| v.trim().parse().ok()).collect();
            (f.len() == 3).then(|| [f[0], f[1], f[2]])
        })
        .collect();
    let half_beam = rows.iter().map(|p| p[1]).fold(f64::MIN, f64::max);
    let keel = rows.iter().map(|p| p[2]).fold(f64::MAX, f64::min);
    let net = |knuckles: &str| {
        // The plain least squares, not held within the offsets' envelope.
        let o = hullskin(
            dir.path(),
            &["fit", input, "--method", "approx", "--knuckles", knuckles, "--envelope", "free", "-o", knuckles],
        );
        assert!(o.status.success(), "{knuckles}: {:?}", text(&o));
        let s = read_json(&dir.path().join(knuckles).join("surface.json"));
        let cp = s["control_points"].as_array().expect("control points").clone();
        let y = cp.iter().filter_map(|p| p[1].as_f64()).fold(f64::MIN, f64::max);
        let z = cp.iter().filter_map(|p| p[2].as_f64()).fold(f64::MAX, f64::min);
        (y, z)
    };
    let (y_plain, z_plain) = net("auto");
    let (y_flats, z_flats) = net("auto+flats");
    // The plain net rings past the flats by centimetres (measured: the surface 83 mm past B/2
    // and 144 mm below the keel).
    assert!(y_plain > half_beam + 0.01 && z_plain < keel - 0.01, "{y_plain} {z_plain} vs {half_beam} {keel}");
    // Held on the planes: equal to round-off of the least squares on a 116 m model (1e-9 m).
    assert!(y_flats <= half_beam + 1e-9 && z_flats >= keel - 1e-9, "{y_flats} {z_flats} vs {half_beam} {keel}");
}

/// R/V Gunnerus's forecastle step (the deck jumps 3.5 m between stations 0.58 m apart) folds
/// the plain skin (`--fair 0`) back on itself near x = 16.5 m: the run says so, report.json
/// records the band, and the centripetal parameterization across the sections it suggests
/// removes it; so does the default `--fair auto` (issue 11), which smooths the skin until the
/// fold is gone.
#[test]
fn a_folded_surface_is_reported_with_its_band_and_the_cure() {
    let dir = temp_dir();
    let input = testdata("gunnerus_offsets.csv");
    let input = input.to_str().expect("utf-8 path");
    let o = hullskin(dir.path(), &["fit", input, "--method", "approx", "--held-out", "0", "-o", "auto"]);
    let (out, err) = text(&o);
    assert!(
        o.status.success(),
        "{out}
{err}"
    );
    assert!(!out.contains("folds back") && out.contains("fairing (auto): smoothing"), "{out}");
    assert!(read_json(&dir.path().join("auto/report.json")).get("folds").is_none());
    let o =
        hullskin(dir.path(), &["fit", input, "--method", "approx", "--fair", "0", "--held-out", "0", "-o", "default"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    // Warnings on standard error, the summary on standard output.
    assert!(
        err.contains("hullskin: warning: the surface folds back") && err.contains("--param centripetal,centripetal"),
        "{err}"
    );
    assert!(!out.contains("warning"), "{out}");
    let r = read_json(&dir.path().join("default/report.json"));
    let folds = r["folds"].as_array().unwrap_or_else(|| panic!("no folds in {r}"));
    assert_eq!(folds.len(), 1, "{r}");
    let x = |i: usize| folds[0]["x"][i].as_f64().expect("number");
    // Between the stations at x = 16.24 and 16.82 m around the step (the table's header).
    assert!(x(0) > 16.24 && x(1) < 16.82 && x(0) <= x(1), "{}", folds[0]);
    let o = hullskin(
        dir.path(),
        &[
            "fit",
            input,
            "--method",
            "approx",
            "--param",
            "centripetal,centripetal",
            "--fair",
            "0",
            "--held-out",
            "0",
            "-o",
            "centripetal",
        ],
    );
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    assert!(!out.contains("folds back"), "{out}");
    let r = read_json(&dir.path().join("centripetal/report.json"));
    assert!(r.get("folds").is_none(), "{r}");
}

#[test]
fn fit_reports_the_held_out_error_beside_the_error_at_the_offsets() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &["fit", "-o", "out"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    let r = read_json(&dir.path().join("out/report.json"));
    let h = &r["error"]["held_out"];
    assert_eq!((h["folds"].as_u64(), h["refits"].as_u64()), (Some(4), Some(8)), "{h}");
    for part in ["sections", "points"] {
        for k in ["max", "mean", "rms", "points"] {
            assert!(h[part][k].is_number(), "{part}.{k} in {h}");
        }
    }
    let (rms, max) = (h["rms"].as_f64().expect("number"), h["max"].as_f64().expect("number"));
    assert!(0.0 < rms && rms <= max, "{h}");
    // The line follows the error at the offsets in the summary.
    let lines: Vec<&str> = out.lines().collect();
    let at = lines.iter().position(|l| l.starts_with("approx ")).expect("method row");
    assert!(lines[at + 1].starts_with(&format!("held out (4 folds): RMS {rms:.3e} m, max {max:.3e} m")), "{out}");
    // Off: no block, no line. The default fit's held-out referee, which chose the surface, is
    // still reported: the same surface is written either way.
    let o = hullskin(dir.path(), &["fit", "-o", "off", "--held-out", "0"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let off = read_json(&dir.path().join("off/report.json"));
    assert!(off["error"].get("held_out").is_none());
    assert!(!text(&o).0.contains("held out (") && !text(&o).0.contains("worst held-out"), "{:?}", text(&o));
    assert!(text(&o).0.contains("held-out referee (4 folds)"), "{:?}", text(&o));
    assert_eq!(
        fs::read(dir.path().join("off/surface.json")).expect("written"),
        fs::read(dir.path().join("out").join("surface.json")).expect("written"),
        "--held-out 0 writes the same surface"
    );
    // One fold: refused before any work, nothing written.
    let o = hullskin(dir.path(), &["fit", "-o", "one", "--held-out", "1"]);
    assert_eq!(o.status.code(), Some(2), "{:?}", text(&o));
    assert!(text(&o).1.contains("expected 0 to turn it off, or at least 2"), "{:?}", text(&o));
    assert!(!dir.path().join("one").exists());
    // A table too small to hold anything out: the fit stands, a warning says why.
    let input = testdata("sections_example.csv");
    let o = hullskin(dir.path(), &["fit", input.to_str().expect("utf-8"), "-o", "small"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    assert!(err.contains("warning: no held-out error: no offset of") && err.contains("can be held out"), "{err}");
    assert!(read_json(&dir.path().join("small/report.json"))["error"].get("held_out").is_none());
}

/// Issue 11: `--knuckles auto+flats` on the 116 m cargo ship folds the surface inside its
/// flats, and nothing warned. Now the run prints one warning per finding (the inward-facing
/// facets on the flat bottom and side among them) and report.json lists them under
/// `validity`; the Wigley hull's list is there and empty.
#[test]
fn every_validity_finding_is_warned_of_and_recorded() {
    let dir = temp_dir();
    let input = testdata("cargo116_offsets.csv");
    // The flats' refit as it was (not held within the rest of the envelope).
    let args = [
        "fit",
        input.to_str().expect("utf-8 path"),
        "--method",
        "approx",
        "--knuckles",
        "auto+flats",
        "--envelope",
        "free",
        "-o",
        "f",
    ];
    let o = hullskin(dir.path(), &args);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    let r = read_json(&dir.path().join("f/report.json"));
    let validity = r["validity"].as_array().unwrap_or_else(|| panic!("no validity in {r}"));
    // One warning per finding, on standard error; none on standard output (the summary).
    let warnings: Vec<&str> = err.lines().filter(|l| l.starts_with("hullskin: warning: ")).collect();
    assert_eq!(warnings.len(), validity.len(), "{err}");
    assert!(!out.contains("warning"), "{out}");
    let inward: Vec<&serde_json::Value> = validity.iter().filter(|f| f["kind"] == "inward_facing").collect();
    // The largest region near the 25 m² the issue measured, of several (the flats' bottom and
    // side among them; the library's test checks them against a dense sampling).
    assert_eq!(inward.len(), 1, "{validity:?}");
    let size = inward[0]["size"].as_f64().expect("a number");
    assert!(size > 20.0 && size < 30.0 && inward[0]["places"].as_u64() >= Some(2), "{}", inward[0]);
    assert!(warnings.iter().any(|w| w.contains("faces inwards")), "{err}");
    for f in validity {
        for key in ["kind", "place", "size", "limit"] {
            assert!(f.get(key).is_some(), "{key} in {f}");
        }
    }
    let wigley = testdata("wigley_offsets.csv");
    let o = hullskin(dir.path(), &["fit", wigley.to_str().expect("utf-8 path"), "-o", "w"]);
    let (out, err) = text(&o);
    assert!(o.status.success() && !out.contains("warning") && !err.contains("warning"), "{out}\n{err}");
    assert_eq!(read_json(&dir.path().join("w/report.json"))["validity"], serde_json::json!([]));
}

/// Issue 11: bad values of `--fair` are refused before any work, naming what is expected, and
/// `--fair 0` is the plain least squares (no fairing block in report.json).
#[test]
fn fair_takes_auto_zero_or_a_positive_weight_and_refuses_the_rest() {
    let dir = temp_dir();
    for bad in ["-1", "nan", "inf", "smooth"] {
        let out = format!("bad{bad}");
        let o = hullskin(dir.path(), &["fit", "--fair", bad, "--held-out", "0", "-o", &out]);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{bad}: {err}");
        assert!(err.contains("expected auto, 0, or a finite number > 0"), "{bad}: {err}");
        assert!(!dir.path().join(&out).exists(), "{bad}");
    }
    let o = hullskin(dir.path(), &["fit", "--fair", "0", "--held-out", "0", "-o", "plain"]);
    assert!(o.status.success(), "{:?}", text(&o));
    assert!(read_json(&dir.path().join("plain/report.json")).get("fairing").is_none());
    // At the default count named (so not replaced by the held-out referee's unfaired
    // alternative, as the sample's default fit is): faired by `auto`.
    let o = hullskin(dir.path(), &["fit", "--held-out", "0", "--ctrl", "6,19", "-o", "auto"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    let r = read_json(&dir.path().join("auto/report.json"));
    assert_eq!(r["fairing"]["setting"], "auto", "{r}");
    assert!(out.contains("fairing (auto): "), "{out}");
}

/// Issue 12: `fit --json` prints the summary as JSON on standard output (report.json's
/// content, for scripts), and nothing else there; the table is the default.
#[test]
fn fit_json_prints_the_report_on_standard_output() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &["fit", "--json", "--held-out", "0", "-o", "j"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    let printed: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}"));
    assert_eq!(printed, read_json(&dir.path().join("j/report.json")));
    assert!(err.contains("wrote j"), "{err}");
}

/// Issue 12: a flag that does nothing to the input says so (on standard error), and the fit
/// is the one without it.
#[test]
fn flags_that_do_not_apply_to_the_input_say_so() {
    let dir = temp_dir();
    let input = testdata("sections_example.csv");
    let input = input.to_str().expect("utf-8 path");
    let o = hullskin(dir.path(), &["fit", input, "--lpp", "100", "--held-out", "0", "-o", "a"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    assert!(err.contains("hullskin: note: --lpp") && err.contains("does nothing to this sections CSV"), "{err}");
    let o = hullskin(dir.path(), &["fit", input, "--held-out", "0", "-o", "b"]);
    assert!(o.status.success());
    let surface = |d: &str| std::fs::read(dir.path().join(d).join("surface.json")).expect("surface.json");
    assert_eq!(surface("a"), surface("b"));
    // hydrostatics places the perpendiculars with --lpp: no note there.
    let o = hullskin(dir.path(), &["hydrostatics", input, "--lpp", "100", "--draft", "0.5"]);
    let (out, err) = text(&o);
    assert!(o.status.success() && !err.contains("--lpp"), "{out}\n{err}");
}

/// `fit SURFACE --offsets FILE` measures a surface given as a surface.json, IGES or STEP file
/// against offsets, as the fit measured it, and writes report.json alone (the surface files are
/// the user's); a surface without `--offsets`, and `--offsets` with offsets, are refused with
/// the fix.
#[test]
fn fit_measures_a_given_surface_against_offsets() {
    let dir = temp_dir();
    let d = dir.path();
    let o = hullskin(d, &["fit", "--held-out", "0", "-o", "F"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let o = hullskin(d, &["export", "F/surface.json", "-o", "F/x.stp"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let fitted = read_json(&d.join("F/report.json"));
    let igs_before = fs::read(d.join("F/surface.igs")).expect("read");
    // The sample's offsets, as a file.
    let offsets = testdata("series60_cb060_offsets.csv");
    let offsets = offsets.to_str().expect("utf-8 path");
    for (i, input) in ["F/surface.json", "F/surface.igs", "F/x.stp"].into_iter().enumerate() {
        let out_dir = format!("M{i}");
        let o = hullskin(d, &["fit", input, "--offsets", offsets, "-o", &out_dir]);
        let (out, err) = text(&o);
        assert!(o.status.success(), "{input}: {out}\n{err}");
        assert!(
            out.contains(&format!("surface: {input} (measured as it is, not fitted)")) && out.contains("given"),
            "{out}"
        );
        assert!(err.contains("is measured as it is against") && err.contains("play no part"), "{err}");
        let r = read_json(&d.join(&out_dir).join("report.json"));
        assert_eq!(r["method"], "given");
        assert_eq!(r["surface_source"], input);
        assert_eq!(r["surface"], fitted["surface"], "{input}");
        assert_eq!(r["validity"], fitted["validity"], "{input}");
        for k in ["max", "rms"] {
            let (a, b) = (r["error"][k].as_f64().expect("number"), fitted["error"][k].as_f64().expect("number"));
            // Both find the global closest points; Newton stops within 1e-9 m on this hull
            // (the JSON and IGES hold the surface to the bit, STEP to 17 digits).
            assert!((a - b).abs() < 1e-7, "{input}: {k} {a} against the fit's {b}");
        }
        let names: Vec<_> =
            fs::read_dir(d.join(&out_dir)).expect("dir").map(|e| e.expect("entry").file_name()).collect();
        assert_eq!(names, ["report.json"], "{input}: report.json alone");
    }
    assert_eq!(fs::read(d.join("F/surface.igs")).expect("read"), igs_before, "the input is untouched");
    // --json prints report.json.
    let o = hullskin(d, &["fit", "F/surface.igs", "--offsets", offsets, "--json", "-o", "J"]);
    let printed: serde_json::Value = serde_json::from_str(&text(&o).0).expect("JSON on stdout");
    assert_eq!(printed, read_json(&d.join("J/report.json")));
    // A surface without --offsets, and --offsets with offsets: refused, saying what to do.
    let o = hullskin(d, &["fit", "F/surface.igs", "-o", "X"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(
        text(&o).1.contains("F/surface.igs: a surface, not offsets") && text(&o).1.contains("--offsets FILE"),
        "{:?}",
        text(&o)
    );
    let o = hullskin(d, &["fit", offsets, "--offsets", offsets, "-o", "X"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("measures a given surface") && text(&o).1.contains("drop --offsets"), "{:?}", text(&o));
    assert!(!d.join("X").exists(), "nothing written for a refused run");
}

#[test]
fn hold_surface_holds_the_sample_within_its_envelope_closer_to_its_offsets() {
    // The built-in Series 60 sample leaves its envelope (below the centre plane at the stern,
    // beyond its side and flats) as plain least squares. Held by its control net (the default)
    // and by its surface's points, both are valid; the surface hold, which lets poles go past
    // a face where the rounded sections need them, ends closer to the offsets (measured: max
    // 116 against 144 mm when it was tried as every table's hold).
    let dir = temp_dir();
    // The count named, so the net-held fit is not replaced by the held-out referee's
    // alternative (chord-length parameters held on the surface, max 94 mm).
    let net = hullskin(dir.path(), &["fit", "-o", "net", "--held-out", "0", "--ctrl", "6,19"]);
    let surface = hullskin(dir.path(), &["fit", "-o", "surface", "--held-out", "0", "--envelope", "hold-surface"]);
    assert!(net.status.success() && surface.status.success(), "{:?} {:?}", text(&net), text(&surface));
    let (n, s) = (read_json(&dir.path().join("net/report.json")), read_json(&dir.path().join("surface/report.json")));
    for r in [&n, &s] {
        assert_eq!(r["validity"].as_array().map(Vec::len), Some(0), "{}", r["validity"]);
        assert!(r["envelope_held"].as_u64().expect("count") > 0, "the sample needs holding");
    }
    let max = |r: &serde_json::Value| r["error"]["max"].as_f64().expect("number");
    assert!(max(&s) < max(&n), "surface hold {} against net hold {}", max(&s), max(&n));
    assert!(text(&surface).0.contains("surface samples and control-point coordinates held"), "{:?}", text(&surface));
}

/// The default fit's choices are made from fits run in parallel (the smoothing weights, the
/// surface hold for fairness, the cross-validation's refits, the held-out referee's) in a fixed
/// order: the same bytes with one thread or three, on a table whose fairing takes a smoothed
/// fit (Series 60 Cb 0.70, `ν` 0.003), on one made again held on its surface (Cb 0.80), on
/// one the held-out referee replaces (Cb 0.65) and on one made again on universal parameters,
/// its smoothing searched up from the least and between the grid's weights (the trawler).
#[test]
fn the_default_fit_is_the_same_whatever_the_thread_count() {
    let dir = temp_dir();
    let tables = [
        "series60_cb070_offsets.csv",
        "series60_cb080_offsets.csv",
        "series60_cb065_offsets.csv",
        "matlab_trawler.csv",
    ];
    for table in tables {
        let path = testdata(table);
        let run = |out: &str, threads: &str| {
            let args = ["fit", path.to_str().expect("UTF-8 path"), "-o", out];
            let o = hullskin_env(dir.path(), &args, &[("HULLSKIN_THREADS", threads)]);
            assert!(o.status.success(), "{table}: {:?}", text(&o));
            let surface = fs::read(dir.path().join(out).join("surface.json")).expect("surface.json");
            (surface, without_timings(read_json(&dir.path().join(out).join("report.json"))))
        };
        let (one, three) = (run("one", "1"), run("three", "3"));
        let replaced = one.1["held_out_referee"]["tried"][0]["accepted"] == true;
        let smoothed = one.1["fairing"]["lambda"].as_f64().is_some_and(|l| l > 0.0);
        assert!(smoothed != replaced, "{table}: a smoothed fit, or the referee's alternative");
        assert_eq!(replaced, table.contains("cb065"), "{table}");
        let universal = one.1["parameterization"] == "universal,chord";
        assert_eq!(universal, table.contains("trawler"), "{table}: {}", one.1["parameterization"]);
        assert!(one == three, "{table}: one thread and three differ");
    }
}
