//! `hullskin export` end to end: every format written by the binary and read back by a real
//! reader (Open CASCADE for STEP and IGES through `tools/occt_check.py`, trimesh and pygltflib
//! for STL, OBJ and glTF through `tools/mesh_check.py`, ezdxf for DXF through
//! `tools/dxf_check.py`), compared with the surface the command started from; the format from
//! the extension; the same command giving the same bytes; bad flags refused with a message and
//! nothing written.
//!
//! The readers need the Python of `tools/requirements.txt`: `HULLSKIN_PYTHON`, or else `.venv`
//! made by `tools/setup-python.sh` (run here when needed); the tests fail without it unless
//! `HULLSKIN_SKIP_OCCT=1` (STEP, IGES), `HULLSKIN_SKIP_MESH=1` or `HULLSKIN_SKIP_DXF=1` is set.

use std::fs;
use std::path::{Path, PathBuf};

use hull::{polynomial_approximation, read_surface_json, write_surface_json, SurfaceFile};
use nurbs::{NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use serde_json::{json, Value};

use tempfile::TempDir;

use crate::common::*;
use crate::python::{assert_tool_passed, run_tool, tools_python};

/// Run `hullskin` in `dir` and require success; returns stdout.
fn run_ok(dir: &Path, args: &[&str]) -> String {
    let o = hullskin(dir, args);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{args:?}\nstdout {out}\nstderr {err}");
    out
}

/// The sample fitted by `hullskin fit` (its surface.json), and a rational version of it
/// (weights 0.7 to 1.3) written as a surface JSON in feet, in a temporary directory of the
/// test's own (nextest runs each test in a process of its own: a directory shared between them
/// was wiped by one while another read from it), removed when the test drops it.
struct Inputs {
    _dir: TempDir,
    plain: PathBuf,
    rational: PathBuf,
}

fn inputs() -> Inputs {
    let dir = tempfile::Builder::new().prefix("export-inputs-").tempdir_in(env!("CARGO_TARGET_TMPDIR")).expect("dir");
    run_ok(dir.path(), &["fit", "-o", "fit"]);
    let plain = dir.path().join("fit/surface.json");
    let (s, _) = surface(&plain);
    let w: Vec<f64> = (0..s.n_u() * s.n_v()).map(|k| 1.0 + 0.3 * ((k * 7 % 13) as f64 / 6.0 - 1.0)).collect();
    let r =
        NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &s.control_points(), Some(&w)).expect("valid");
    let rational = dir.path().join("rational_ft.json");
    let mut out = Vec::new();
    write_surface_json(&mut out, &r, hull::Units::Foot).expect("writes");
    fs::write(&rational, out).expect("write");
    Inputs { _dir: dir, plain, rational }
}

fn surface(path: &Path) -> (NurbsSurface, String) {
    read_surface_json(&fs::read_to_string(path).expect("read")).expect("a surface")
}

fn size(s: &NurbsSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    (hi - lo).norm()
}

/// 88 points of `s`: a 9 x 9 grid with the boundaries and 7 irregular interior points.
fn samples(s: &NurbsSurface) -> Vec<[f64; 5]> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut uv: Vec<(f64, f64)> =
        (0..81).map(|k| (u0 + (u1 - u0) * (k / 9) as f64 / 8.0, v0 + (v1 - v0) * (k % 9) as f64 / 8.0)).collect();
    uv.extend(
        (1..=7).map(|k| {
            (u0 + (u1 - u0) * (k as f64 * 0.618_034).fract(), v0 + (v1 - v0) * (k as f64 * 0.414_214).fract())
        }),
    );
    uv.into_iter()
        .map(|(u, v)| {
            let p = s.point(u, v);
            [u, v, p.x, p.y, p.z]
        })
        .collect()
}

fn expected(dir: &Path, name: &str, s: &NurbsSurface, units: &str, extra: Value) -> PathBuf {
    let mut e = json!({"surface": SurfaceFile::from_surface(s, units.parse().expect("units")), "units": units, "samples": samples(s)});
    if let (Some(e), Some(extra)) = (e.as_object_mut(), extra.as_object()) {
        e.extend(extra.clone());
    }
    let path = dir.join(format!("{name}.expected.json"));
    fs::write(&path, e.to_string()).expect("write");
    path
}

#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn step_and_iges_exports_are_read_by_occt() {
    let python = tools_python("HULLSKIN_SKIP_OCCT", "Open CASCADE check of the exported STEP and IGES");
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let (plain, rational) = (&inputs.plain, &inputs.rational);
    let (s, _) = surface(plain);
    let (r, _) = surface(rational);
    let plain = plain.to_str().expect("utf-8 path");
    let rational = rational.to_str().expect("utf-8 path");

    // STEP and IGES of the surface as it is, from the extension; the rational one in feet.
    for (input, out, s, units) in [
        (plain, "hull.stp", &s, "m"),
        (rational, "hull_ft.step", &r, "ft"),
        (plain, "hull.igs", &s, "m"),
        (rational, "hull_ft.iges", &r, "ft"),
    ] {
        let said = run_ok(d, &["export", input, "-o", out, "--timestamp", "0"]);
        assert!(said.contains(&format!("wrote {out}")), "{said}");
        let exp = expected(d, out, s, units, json!({}));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&d.join(out), &exp]);
        assert_tool_passed(out, code, &summary);
        assert_eq!(summary["reads"]["native"]["samples"], 88);
    }

    // Section curves of offsets fitted here: at the sections' v, one per section.
    let said = run_ok(d, &["export", "--method", "interp", "--format", "iges-curves", "-o", "curves.igs"]);
    assert!(said.contains("at the sections' v"), "{said}");
    let sample = hull::series60_sample();
    let fit = hull::fit_offsets(&sample, &hull::FitConfig { method: hull::FitMethod::Interp, ..Default::default() })
        .expect("fits");
    let curves = hull::section_curves(&fit.surface, &hull::section_parameters(&fit.params));
    assert!(said.contains(&format!("{} section curves", curves.len())), "{said}");
    let curve_docs: Vec<Value> = curves
        .iter()
        .map(|c| {
            let (t0, t1) = c.domain();
            let pts: Vec<[f64; 4]> = (0..=10)
                .map(|k| {
                    let t = t0 + (t1 - t0) * k as f64 / 10.0;
                    let p = c.point(t);
                    [t, p.x, p.y, p.z]
                })
                .collect();
            json!({"degree": c.degree(), "knots": c.knots().as_slice(), "weights": c.weights(),
                   "control_points": c.control_points().iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
                   "samples": pts})
        })
        .collect();
    let exp = expected(d, "curves", &fit.surface, "m", json!({"curves": curve_docs}));
    let (code, summary) = run_tool(&python, "occt_check.py", &[&d.join("curves.igs"), &exp]);
    assert_tool_passed("curves.igs", code, &summary);
    assert_eq!(summary["reads"]["native"]["curves"].as_u64(), Some(curves.len() as u64));
    // A surface input has no sections: one curve per control column.
    let said = run_ok(d, &["export", plain, "--format", "iges-curves", "-o", "greville.igs"]);
    assert!(said.contains(&format!("{} section curves at the Greville", s.n_v())), "{said}");

    // The polynomial approximation of the rational surface: OCCT reads a polynomial surface
    // within the tolerance of the rational one.
    let tol = 1e-3;
    let said =
        run_ok(d, &["export", rational, "--format", "iges-polynomial", "--tolerance", "0.001", "-o", "poly.igs"]);
    assert!(said.contains("largest deviation") && said.contains("tolerance 1.000e-3 ft"), "{said}");
    let approx = polynomial_approximation(&r, tol).expect("approximates");
    let exp =
        expected(d, "poly", &approx.surface, "ft", json!({"reference": {"samples": samples(&r), "tolerance": tol}}));
    let (code, summary) = run_tool(&python, "occt_check.py", &[&d.join("poly.igs"), &exp]);
    assert_tool_passed("poly.igs", code, &summary);
    eprintln!(
        "iges-polynomial: {}, OCCT measures {:.2e} ft from the rational surface",
        said.trim(),
        summary["reads"]["native"]["reference_deviation"].as_f64().unwrap_or(f64::NAN)
    );
    // Equal weights: the same surface, said to be exact.
    let said = run_ok(d, &["export", plain, "--format", "iges-polynomial", "-o", "exact.igs"]);
    assert!(said.contains("exact"), "{said}");
}

/// Issue 12: `--mirror` writes the full hull as one surface in STEP and IGES (each half the
/// fitted half or its mirror image, the flat of keel bridged), and `--units` converts a
/// surface.json, written in the file's unit field; both read by OCCT, point for point.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn mirrored_and_converted_exports_are_read_by_occt() {
    let python = tools_python("HULLSKIN_SKIP_OCCT", "Open CASCADE check of the exported STEP and IGES");
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let plain = &inputs.plain;
    let (s, _) = surface(plain);
    let plain = plain.to_str().expect("utf-8 path");
    let full = hull::mirrored_full_hull(&s).expect("mirrors");
    // Both halves: the full hull spans -B/2 to B/2.
    let (lo, hi) = (full.control_bounds().0, full.control_bounds().1);
    assert!((lo.y + hi.y).abs() <= 1e-12 * hi.y && hi.y > 8.0, "{lo:?} {hi:?}");
    for out in ["full.stp", "full.igs"] {
        let said = run_ok(d, &["export", plain, "-o", out, "--mirror", "--timestamp", "0"]);
        assert!(
            said.contains(&format!("wrote {out}")) && said.contains(&format!("{}x{}", full.n_u(), full.n_v())),
            "{said}"
        );
        let exp = expected(d, out, &full, "m", json!({}));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&d.join(out), &exp]);
        assert_tool_passed(out, code, &summary);
    }
    // A surface.json in metres written in millimetres: every pole times 1000, the unit MM.
    let mm = {
        let pts: Vec<Vec3> = s.control_points().into_iter().map(|p| p * 1000.0).collect();
        NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, Some(&s.weights())).expect("valid")
    };
    for out in ["mm.stp", "mm.igs"] {
        run_ok(d, &["export", plain, "-o", out, "--units", "mm", "--timestamp", "0"]);
        let exp = expected(d, out, &mm, "mm", json!({}));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&d.join(out), &exp]);
        assert_tool_passed(out, code, &summary);
    }
}

/// The mesh read back by `tools/mesh_check.py`: vertices, faces, and the JSON summary.
fn read_mesh(python: &str, path: &Path) -> (Vec<Vec3>, usize, Value) {
    let (code, summary) = run_tool(python, "mesh_check.py", &[path]);
    assert_tool_passed(&path.display().to_string(), code, &summary);
    let v = summary["vertices"]
        .as_array()
        .expect("vertices")
        .iter()
        .map(|p| {
            let c: Vec<f64> = p.as_array().expect("triple").iter().map(|x| x.as_f64().expect("number")).collect();
            Vec3::new(c[0], c[1], c[2])
        })
        .collect();
    let faces = summary["faces"].as_array().expect("faces").len();
    (v, faces, summary)
}

#[test]
#[cfg_attr(skip_mesh, ignore = "HULLSKIN_SKIP_MESH=1")]
fn mesh_exports_are_read_by_trimesh_and_pygltflib() {
    let python = tools_python("HULLSKIN_SKIP_MESH", "trimesh/pygltflib check of the exported meshes");
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let rational = &inputs.rational;
    let (r, _) = surface(rational);
    let input = rational.to_str().expect("utf-8 path");
    let tol = 0.05; // feet, about 4e-4 of the hull's size
    let projector = SurfaceProjector::new(&r, ProjectionOptions::default());
    let mut triangles = Vec::new();
    for (format, out) in
        [("stl", "hull.stl"), ("stl-ascii", "hull_ascii.stl"), ("obj", "hull.obj"), ("glb", "hull.glb")]
    {
        let said =
            run_ok(d, &["export", input, "--format", format, "--tolerance", &tol.to_string(), "--mirror", "-o", out]);
        assert!(said.contains("triangles, chord tolerance 5.000e-2 ft"), "{said}");
        let (vertices, faces, summary) = read_mesh(&python, &d.join(out));
        triangles.push(faces);
        // glTF is in metres with (X, Y, Z) = (y, z, x).
        let model = |p: Vec3| if format == "glb" { Vec3::new(p.z, p.x, p.y) * (1.0 / 0.3048) } else { p };
        // Both halves, mirror images.
        assert!(vertices.iter().any(|p| model(*p).y < -1.0) && vertices.iter().any(|p| model(*p).y > 1.0));
        // Every 23rd vertex on the surface (or its mirror image) within 1e-6 of the size.
        let mut worst = 0.0f64;
        for p in vertices.iter().step_by(23) {
            let q = model(*p);
            let d1 = projector.project(q).distance;
            let d2 = projector.project(Vec3::new(q.x, -q.y, q.z)).distance;
            worst = worst.max(d1.min(d2) / size(&r));
        }
        assert!(worst < 1e-6, "{format}: a vertex is {worst:.2e} of the size off the surface");
        if format == "glb" {
            assert_eq!(summary["asset"]["version"], "2.0");
            let colors = summary["colors"].as_array().expect("colours");
            assert_eq!(colors.len(), vertices.len());
        }
        eprintln!("{format}: {faces} triangles, vertices within {worst:.1e} of the size");
    }
    // One tessellation, four files.
    assert!(triangles.windows(2).all(|w| w[0] == w[1]), "{triangles:?}");
}

#[test]
#[cfg_attr(skip_dxf, ignore = "HULLSKIN_SKIP_DXF=1")]
fn dxf_export_is_read_by_ezdxf() {
    let python = tools_python("HULLSKIN_SKIP_DXF", "ezdxf check of the exported DXF");
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let plain = &inputs.plain;
    let (s, _) = surface(plain);
    let input = plain.to_str().expect("utf-8 path");
    run_ok(d, &["export", input, "-o", "lines.dxf"]);
    run_ok(d, &["export", input, "--mirror", "-o", "full.dxf"]);
    let projector = SurfaceProjector::new(&s, ProjectionOptions::default());
    let mut counts = Vec::new();
    for name in ["lines.dxf", "full.dxf"] {
        let (code, summary) = run_tool(&python, "dxf_check.py", &[&d.join(name)]);
        assert_tool_passed(name, code, &summary);
        assert_eq!(summary["header"]["$INSUNITS"], 6, "metres");
        let polylines: Vec<&Value> =
            summary["entities"].as_array().expect("entities").iter().filter(|e| e["type"] == "POLYLINE").collect();
        for layer in ["stations", "waterlines", "buttocks"] {
            assert!(polylines.iter().any(|e| e["layer"] == layer), "{name}: no {layer}");
        }
        // Stations are planar at one x; every vertex (mirrored back) on the surface.
        let mut worst = 0.0f64;
        // The port copies follow the starboard polylines in the mirrored file.
        let starboard = if name == "full.dxf" { polylines.len() / 2 } else { polylines.len() };
        for (k, e) in polylines.iter().enumerate() {
            let pts: Vec<Vec3> = e["vertices"]
                .as_array()
                .expect("vertices")
                .iter()
                .map(|p| Vec3::new(p[0].as_f64().expect("x"), p[1].as_f64().expect("y"), p[2].as_f64().expect("z")))
                .collect();
            if e["layer"] == "stations" {
                assert!(pts.iter().all(|p| (p.x - pts[0].x).abs() < 1e-9 * size(&s)), "a station is not planar");
            }
            for p in pts.iter().step_by(5) {
                let q = if k < starboard { *p } else { Vec3::new(p.x, -p.y, p.z) };
                worst = worst.max(projector.project(q).distance / size(&s));
            }
        }
        assert!(worst < 1e-6, "{name}: a vertex is {worst:.2e} of the size off the surface");
        counts.push(polylines.len());
    }
    // The mirrored file holds every polyline twice.
    assert_eq!(counts[1], 2 * counts[0]);
}

#[test]
fn same_command_same_bytes() {
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let plain = &inputs.plain;
    let input = plain.to_str().expect("utf-8 path");
    for out in ["a.stp", "a.igs", "a.glb"] {
        run_ok(d, &["export", input, "--timestamp", "86400", "-o", out]);
        let first = fs::read(d.join(out)).expect("read");
        run_ok(d, &["export", input, "--timestamp", "86400", "-o", out]);
        assert!(first == fs::read(d.join(out)).expect("read"), "{out}: a second run wrote other bytes");
    }
    // The timestamp reaches the headers; SOURCE_DATE_EPOCH stands in for the flag.
    assert!(fs::read_to_string(d.join("a.stp")).expect("read").contains("'1970-01-02T00:00:00'"));
    let other = temp_dir();
    let o = hullskin_env(other.path(), &["export", input, "-o", "a.stp"], &[("SOURCE_DATE_EPOCH", "86400")]);
    assert!(o.status.success());
    let same = fs::read(d.join("a.stp")).expect("a") == fs::read(other.path().join("a.stp")).expect("b");
    assert!(same, "SOURCE_DATE_EPOCH gave other bytes than --timestamp");
}

/// Issue 12, item 7: `export --json` says what was written, for scripts.
#[test]
fn json_summary_names_the_file_format_units_and_size() {
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let (plain, rational) = (&inputs.plain, &inputs.rational);
    let (s, _) = surface(plain);
    let out = run_ok(d, &["export", plain.to_str().expect("utf-8 path"), "-o", "a.igs", "--json"]);
    let doc: Value = serde_json::from_str(&out).expect("stdout is one JSON object");
    assert_eq!(
        (doc["wrote"].as_str(), doc["format"].as_str(), doc["units"].as_str()),
        (Some("a.igs"), Some("iges"), Some("m"))
    );
    assert_eq!(doc["poles"], serde_json::json!([s.n_u(), s.n_v()]));
    assert!(d.join("a.igs").is_file());
    // A mesh: its triangles and tolerance; the feet surface stays in feet.
    let out =
        run_ok(d, &["export", rational.to_str().expect("utf-8 path"), "-o", "r.stl", "--tolerance", "0.01", "--json"]);
    let doc: Value = serde_json::from_str(&out).expect("stdout is one JSON object");
    assert_eq!(
        (doc["format"].as_str(), doc["units"].as_str(), doc["tolerance"].as_f64()),
        (Some("stl"), Some("ft"), Some(0.01))
    );
    let triangles = doc["triangles"].as_u64().expect("a count");
    // Binary STL: 84 header bytes and 50 per triangle.
    assert_eq!(fs::metadata(d.join("r.stl")).expect("written").len(), 84 + 50 * triangles);
}

#[test]
fn bad_requests_fail_with_a_message_and_write_nothing() {
    let dir = temp_dir();
    let d = dir.path();
    let inputs = inputs();
    let plain = &inputs.plain;
    let input = plain.to_str().expect("utf-8 path");
    for (args, says) in [
        (vec!["export", input, "-o", "x.txt"], "--format"),
        (vec!["export", input, "--tolerance", "0.1", "-o", "x.stp"], "--tolerance applies"),
        (vec!["export", input, "--format", "stl", "-o", "x.stp"], "name it x.stl or pass --format step"),
        (vec!["export", input, "--tolerance", "-1", "-o", "x.stl"], "positive"),
        // The kernel's message, as it was when the tessellation lived in hull.
        (
            vec!["export", input, "--tolerance", "1e-30", "-o", "x.obj"],
            "hullskin: error: tessellation tolerance 0.000000000000000000000000000001: expected a length of at least ",
        ),
        (vec!["export", "missing.json", "-o", "x.stp"], "missing.json"),
    ] {
        let o = hullskin(d, &args);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: {err}");
        assert!(err.contains(says), "{args:?}: {err}");
    }
    assert_eq!(fs::read_dir(d).expect("list").count(), 0, "a failed export left a file");
}
