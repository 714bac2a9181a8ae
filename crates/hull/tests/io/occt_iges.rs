//! The IGES export read back by a real CAD kernel (Open CASCADE through `tools/occt_check.py`),
//! and the golden IGES text of a tiny surface.
//!
//! The OCCT tests need a Python with the `cadquery-ocp-novtk` package: `HULLSKIN_PYTHON`, or
//! else `.venv` made by `tools/setup-python.sh` (run by the test itself when needed). If that
//! fails the tests fail (the check cannot vanish silently) unless `HULLSKIN_SKIP_OCCT=1`.

use std::path::{Path, PathBuf};

use crate::common::python::{assert_tool_passed, run_tool, tools_python};
use crate::common::surfaces::{polynomial, rational_bicubic, samples, weights_changed};
use crate::common::{testdata, workspace_root};
use nurbs::fixtures::quarter_cylinder;

use hull::{write_iges, IgesMeta, IgesUnits, SurfaceFile};
use nurbs::NurbsSurface;
use serde_json::{json, Value};

/// The Python that has OCP, or `None` if the OCCT checks are explicitly skipped.
fn occt_python() -> String {
    tools_python("HULLSKIN_SKIP_OCCT", "OCCT check of the IGES export")
}

fn meta(units: IgesUnits, name: &str) -> IgesMeta {
    let mut m = IgesMeta::new(units, name, "20240102.030405");
    m.author = "hullskin test".into();
    m
}

fn write_case(dir: &Path, name: &str, s: &NurbsSurface, units: IgesUnits, samples: &[[f64; 5]]) -> (PathBuf, PathBuf) {
    write_case_with(dir, name, s, units, samples, None)
}

/// [`write_case`] with the checker's optional `envelope` (see `tools/occt_check.py`).
fn write_case_with(
    dir: &Path,
    name: &str,
    s: &NurbsSurface,
    units: IgesUnits,
    samples: &[[f64; 5]],
    envelope: Option<Value>,
) -> (PathBuf, PathBuf) {
    let igs = dir.join(format!("{name}.igs"));
    let mut out = Vec::new();
    write_iges(&mut out, s, &meta(units, &format!("{name}.igs"))).expect("writes to memory");
    std::fs::write(&igs, out).expect("write IGES");
    let surface_units =
        hull::Units::ALL.into_iter().find(|u| u.iges_flag() == units.flag).expect("an IGES unit of hullskin's");
    let mut expected = json!({
        "surface": SurfaceFile::from_surface(s, surface_units),
        "iges_units": {"flag": units.flag, "name": units.name},
        "samples": samples,
    });
    if let Some(e) = envelope {
        expected["envelope"] = e;
    }
    let exp = dir.join(format!("{name}.expected.json"));
    std::fs::write(&exp, serde_json::to_string_pretty(&expected).expect("serializes")).expect("write JSON");
    (igs, exp)
}

#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_reads_the_iges_export_exactly() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let cases = [
        ("rational_bicubic", rational_bicubic()),
        ("polynomial", polynomial()),
        ("quarter_cylinder", quarter_cylinder(2.0, 3.0)),
    ];
    for (name, s) in &cases {
        // Also feet and inches once, to check the other unit names OCCT must recognise.
        let mut unit_cases = vec![(IgesUnits::METRE, 1.0), (IgesUnits::MILLIMETRE, 1000.0)];
        if *name == "quarter_cylinder" {
            unit_cases.extend([(IgesUnits::FOOT, 1.0 / 0.3048), (IgesUnits::INCH, 1.0 / 0.0254)]);
        }
        for (units, k) in unit_cases {
            let s = s.scaled(k);
            let case = format!("{name}_{}", units.name.to_lowercase());
            let (igs, exp) = write_case(dir.path(), &case, &s, units, &samples(&s));
            let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
            assert_tool_passed(&case, code, &summary);
            let r = &summary["reads"];
            eprintln!(
                "{case}: OCP {} native err {:.1e}, default-mm scale {} (expected {}) err {:.1e}",
                summary["ocp_version"],
                r["native"]["max_point_error_rel"].as_f64().unwrap_or(f64::NAN),
                r["default_mm"]["measured_scale"],
                r["default_mm"]["expected_scale"],
                r["default_mm"]["max_point_error_rel"].as_f64().unwrap_or(f64::NAN),
            );
            // The checker really compared something: every sample, in both reads.
            for read in ["native", "default_mm"] {
                assert_eq!(r[read]["samples"].as_u64(), Some(samples(&s).len() as u64), "{case} {read}");
            }
        }
    }
}

/// The surfaces hullskin actually fits: the built-in Series 60 hull by interpolation (8 x 25
/// poles) and approximation, and the Gunnerus table with unequal section counts; OCCT must
/// read each as one B-spline face equal to ours.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_reads_fitted_hull_surfaces() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let gunnerus = hull::read_offsets(&testdata("gunnerus_offsets.csv"), hull::Units::Metre).expect("gunnerus reads");
    let cases = [
        ("s60_interp", hull::series60_sample(), hull::FitMethod::Interp, None),
        ("s60_approx", hull::series60_sample(), hull::FitMethod::Approx, Some((6, 15))),
        ("gunnerus_interp", gunnerus, hull::FitMethod::Interp, None),
    ];
    for (name, offsets, method, ctrl) in cases {
        let cfg = hull::FitConfig { method, ctrl, ..hull::FitConfig::default() };
        let s = hull::fit_offsets(&offsets, &cfg).expect("fits").surface;
        let (igs, exp) = write_case(dir.path(), name, &s, IgesUnits::METRE, &samples(&s));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
        assert_tool_passed(name, code, &summary);
        assert_eq!(summary["reads"]["native"]["samples"].as_u64(), Some(samples(&s).len() as u64), "{name}");
    }
}

/// The default fit (fairing auto, held within the offsets' envelope) as Open CASCADE sees it:
/// sampled by OCCT on a 301 x 301 grid of the face read from the IGES, it stays within the
/// offsets' box widened by the allowance of hullskin's validity check (`ENVELOPE_REL`, 0.5 %
/// of the length, half-beam and depth: past that is an envelope finding) on the sample and on
/// every table of `testdata/`, many of whose plain least squares leave it (the Series 60
/// sample at the transom, the cargo ship at the bulb and its flats, the Cb 0.80 parent at the
/// stern). The check can fail: the sample's
/// plain least squares (`EnvelopeHold::Free`) crosses the centre plane by 87 mm where 41 mm is
/// allowed, and OCCT must see that.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_finds_the_default_fit_within_the_offsets_envelope() {
    let default = hull::FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..hull::FitConfig::default() };
    let free = hull::FitConfig { envelope: hull::EnvelopeHold::Free, ..default };
    let mut cases = vec![("s60_sample".to_string(), hull::series60_sample(), default, true)];
    cases.extend(every_table().into_iter().map(|(name, offsets)| (name, offsets, default, true)));
    cases.push(("s60_sample_free".to_string(), hull::series60_sample(), free, false));
    check_envelope_with_occt(cases);
}

/// `--method lm` as Open CASCADE sees it, on every table of `testdata/` (issue 11 names the
/// default fit and LM): within the offsets' envelope as above, whether LM's surface is written
/// or gives way to an approximation (a validity finding, or `HOLD_SLACK`).
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_finds_the_lm_fit_within_the_offsets_envelope() {
    let lm = hull::FitConfig {
        method: hull::FitMethod::Optimized(hull::Algorithm::Lm),
        fair: hull::Fairing::Auto { tolerance: None },
        ..hull::FitConfig::default()
    };
    check_envelope_with_occt(every_table().into_iter().map(|(name, offsets)| (name, offsets, lm, true)).collect());
}

/// Every offset table of `testdata/` in name order, then its meshes sliced as `hullskin fit
/// MESH` slices them (issue 11 names the DTC and DTMB 5415 meshes; the FastShip designs of
/// `shared/data` since 2026-12-08, the two stored with z down turned up as
/// `tools/speed_common.sh` reads them).
fn every_table() -> Vec<(String, hull::Offsets)> {
    let table = |name: &str| hull::read_offsets(&testdata(name), hull::Units::Metre).expect("reads");
    let mut names: Vec<String> = std::fs::read_dir(workspace_root().join("testdata"))
        .expect("testdata/")
        .map(|e| e.expect("an entry").file_name().to_string_lossy().into_owned())
        .filter(|n| n.ends_with(".csv"))
        .collect();
    names.sort();
    assert!(names.len() >= 15, "the tables of testdata/: {names:?}");
    let mut tables: Vec<(String, hull::Offsets)> =
        names.iter().map(|n| (n.trim_end_matches(".csv").to_string(), table(n))).collect();
    let up: hull::Axes = "x,y,-z".parse().expect("axes");
    let meshes = [
        ("DTC-scaled.stl.gz", hull::Axes::default()),
        ("dtmb5415.stl.gz", hull::Axes::default()),
        ("wigley.stl.gz", hull::Axes::default()),
        ("fastship_50dragger.wrl.gz", up),
        ("fastship_70ktanker.wrl.gz", hull::Axes::default()),
        ("fastship_cont.wrl.gz", up),
    ];
    for (mesh, axes) in meshes {
        let options = hull::MeshReadOptions { axes, ..hull::MeshReadOptions::default() };
        let read = hull::read_mesh(&testdata(&format!("mesh/{mesh}")), &options);
        let sliced = hull::slice_mesh(&read.expect("reads"), &hull::SliceOptions::default()).expect("slices");
        let name = mesh.split('.').next().expect("a name");
        tables.push((format!("{name}_mesh"), sliced.offsets));
    }
    tables
}

/// Fit each case as `hullskin fit` does (with the default fit's held-out referee) and have
/// OCCT sample the IGES face on a 301 x 301 grid: within the offsets' box widened by the
/// validity allowance where `within`, past it below the centre plane where not (and
/// hullskin's own check agreeing either way).
fn check_envelope_with_occt(cases: Vec<(String, hull::Offsets, hull::FitConfig, bool)>) {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    for (name, offsets, cfg, within) in cases {
        // As `hullskin fit` fits (the default fit with its held-out referee, LM as it is).
        let fit = hull::quiet(|c| hull::fit_offsets_within(&offsets, &cfg, hull::Goal::Count, c)).expect("fits").0;
        let past: Vec<String> =
            fit.validity.iter().filter(|f| f.envelope_face().is_some()).map(|f| f.message("m")).collect();
        // hullskin's own check: the default fit has no envelope finding, the plain one has.
        assert_eq!(past.is_empty(), within, "{name}: {past:#?}");
        let s = fit.surface;
        let e = hull::Envelope::of_offsets(&offsets).expect("a hull");
        let rel = hull::ENVELOPE_REL;
        let allowance = [rel * e.length(), rel * e.half_beam(), rel * e.depth()];
        let envelope = json!({
            "lo": [e.x.0, e.y.0, e.z.0],
            "hi": [e.x.1, e.y.1, e.z.1],
            "allowance": allowance,
            "grid": 300,
        });
        let (igs, exp) = write_case_with(dir.path(), &name, &s, IgesUnits::METRE, &samples(&s), Some(envelope));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
        let excess = &summary["reads"]["native"]["envelope_excess"];
        eprintln!("{name}: OCCT's surface past the envelope's faces {excess}, allowed {allowance:?}");
        assert_eq!(excess["grid"].as_u64(), Some(300), "{name}: the grid was sampled");
        let failed = summary["failed"].to_string();
        if within {
            assert!(code == 0 && summary["ok"] == true, "{name}: (exit {code}) {failed}");
        } else {
            assert_eq!(code, 1, "{name}: the plain fit leaves the envelope, OCCT must see it: {summary}");
            assert!(failed.contains("within the envelope") && !failed.contains("poles"), "{name}: {failed}");
            let below_y = excess["below"][1].as_f64().expect("a number");
            assert!(below_y > rel * e.half_beam(), "{name}: {below_y} below the centre plane");
        }
    }
}

/// The checker must fail when the file and our evaluator disagree: samples of the quarter
/// cylinder with the middle weight changed, and a surface labelled in the wrong unit.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_check_detects_a_mismatch() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let s = quarter_cylinder(2.0, 3.0);
    let wrong = weights_changed(&s);
    let (igs, exp) = write_case(dir.path(), "wrong_weight", &s, IgesUnits::METRE, &samples(&wrong));
    let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
    assert_eq!(code, 1, "{summary}");
    let failed = summary["failed"].to_string();
    assert!(failed.contains("points at"), "{failed}");

    // Written in metres but the expectation (and so the default-mm scale) says millimetres.
    let (igs, _) = write_case(dir.path(), "unit_m", &s, IgesUnits::METRE, &samples(&s));
    let (_, exp) = write_case(dir.path(), "unit_mm", &s, IgesUnits::MILLIMETRE, &samples(&s));
    let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
    assert_eq!(code, 1, "{summary}");
    let failed = summary["failed"].to_string();
    assert!(failed.contains("global units") && failed.contains("default_mm: poles"), "{failed}");
}

/// The IGES text of a tiny surface (the quarter cylinder of radius 1 and length 1) against
/// `testdata/golden/tiny.igs`. Refresh with `UPDATE_GOLDEN=1`. Compared exactly: the writer
/// is deterministic and its numbers are shortest round-trip strings, identical on every
/// platform.
#[test]
fn golden_tiny_iges() {
    let s = quarter_cylinder(1.0, 1.0);
    let mut m = IgesMeta::new(IgesUnits::METRE, "tiny.igs", "20000101.000000");
    m.preprocessor_version = "golden".into();
    m.author = "hullskin test".into();
    m.organization = "hullskin".into();
    let mut out = Vec::new();
    write_iges(&mut out, &s, &m).expect("writes to memory");
    let text = String::from_utf8(out).expect("ASCII");
    let path = workspace_root().join("testdata/golden/tiny.igs");
    if std::env::var("UPDATE_GOLDEN").as_deref() == Ok("1") {
        std::fs::create_dir_all(path.parent().expect("has a parent")).expect("create testdata/golden");
        std::fs::write(&path, &text).expect("write golden file");
        eprintln!("updated {}", path.display());
        return;
    }
    let golden = std::fs::read_to_string(&path)
        .unwrap_or_else(|e| panic!("{}: {e}; run with UPDATE_GOLDEN=1 to create it", path.display()));
    if let Some((k, (a, b))) = text.lines().zip(golden.lines()).enumerate().find(|(_, (a, b))| a != b) {
        panic!(
            "line {} differs from {}:\n  now:    {a}\n  golden: {b}\n(UPDATE_GOLDEN=1 refreshes)",
            k + 1,
            path.display()
        );
    }
    assert_eq!(text.lines().count(), golden.lines().count(), "line count differs from {}", path.display());
    assert_eq!(text, golden, "line endings differ from {}", path.display());
}
