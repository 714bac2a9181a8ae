//! Every export read back by a real reader: STEP and IGES (with section curves, and the
//! polynomial approximation) by Open CASCADE through `tools/occt_check.py`; STL, OBJ and glTF
//! by trimesh and pygltflib through `tools/mesh_check.py`; the 3-D DXF lines by ezdxf through
//! `tools/dxf_check.py`. Geometry must agree with our evaluator within 1e-6 of the model size
//! (1e-9 for the exact B-spline formats).
//!
//! The checks need the Python of `tools/requirements.txt`: `HULLSKIN_PYTHON`, or else `.venv`
//! made by `tools/setup-python.sh` (run by the test itself when needed). If that fails the
//! tests fail (a check cannot vanish silently) unless `HULLSKIN_SKIP_OCCT=1` (STEP, IGES) or
//! `HULLSKIN_SKIP_MESH=1` (STL, OBJ, glTF) or `HULLSKIN_SKIP_DXF=1` is set.

use std::path::{Path, PathBuf};
use std::process::Command;
use std::sync::OnceLock;

use hull::export::{write_step, StepMeta, SurfaceFile};
use hull::Units;
use nurbs::{KnotVector, NurbsCurve, NurbsSurface, Vec3};
use serde_json::{json, Value};

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The Python with the tools' requirements, or `None` if `skip_var` is set to 1.
fn tools_python(skip_var: &str, what: &str) -> Option<String> {
    static PYTHON: OnceLock<Result<String, String>> = OnceLock::new();
    if let Ok(p) = std::env::var("HULLSKIN_PYTHON") {
        if !p.is_empty() {
            return Some(p);
        }
    }
    if std::env::var(skip_var).as_deref() == Ok("1") {
        eprintln!("SKIPPED: {what} ({skip_var}=1)");
        return None;
    }
    let found = PYTHON.get_or_init(|| {
        let script = workspace_root().join("tools/setup-python.sh");
        let out =
            Command::new("bash").arg(&script).output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        match stdout.lines().last() {
            Some(p) if out.status.success() => Ok(p.trim().to_string()),
            _ => Err(format!("{} failed:\n{}", script.display(), String::from_utf8_lossy(&out.stderr))),
        }
    });
    match found {
        Ok(p) => Some(p.clone()),
        Err(e) => panic!(
            "{e}\n{what} needs the Python of tools/requirements.txt. Point HULLSKIN_PYTHON at a Python that has \
             it, or set {skip_var}=1 to skip the check."
        ),
    }
}

fn occt_python() -> Option<String> {
    tools_python("HULLSKIN_SKIP_OCCT", "Open CASCADE check of the STEP and IGES exports")
}

/// Run `tools/<script>` with `args`; returns (exit code, parsed JSON summary).
fn run_tool(python: &str, script: &str, args: &[&Path]) -> (i32, Value) {
    let script = workspace_root().join("tools").join(script);
    let out = Command::new(python)
        .arg(&script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python} {}: {e}", script.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let summary: Value = serde_json::from_str(&stdout).unwrap_or_else(|e| {
        panic!(
            "{} did not print a JSON summary ({e}); status {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
            script.display(),
            out.status
        )
    });
    (out.status.code().unwrap_or(-1), summary)
}

fn assert_passed(case: &str, code: i32, summary: &Value) {
    assert!(
        code == 0 && summary["ok"] == true,
        "{case}: the reader disagrees with the export (exit {code}):\n{}",
        serde_json::to_string_pretty(&summary["failed"]).unwrap_or_default()
    );
}

// ---------------------------------------------------------------------------------------------
// Surfaces

/// Rational bicubic, non-uniform knots with a double knot in v, v domain not [0, 1], weights
/// from 0.6 to 1.9: a hull-like half section swept along x.
fn rational_bicubic() -> NurbsSurface {
    let ku = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.2, 0.45, 0.5, 1.0, 1.0, 1.0, 1.0]).expect("valid");
    let kv = KnotVector::try_new(3, vec![-2.0, -2.0, -2.0, -2.0, 0.5, 0.5, 1.5, 3.0, 3.0, 3.0, 3.0]).expect("valid");
    let (nu, nv) = (ku.num_basis(), kv.num_basis());
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for i in 0..nu {
        for j in 0..nv {
            let (a, b) = (i as f64 / (nu - 1) as f64, j as f64 / (nv - 1) as f64);
            let beam = 7.0 * (1.0 - (2.0 * b - 1.0).powi(4));
            pts.push(Vec3::new(110.0 * b, beam * (a * 1.4).sin().min(1.0) + 0.02 * j as f64, 6.0 * a - 0.3 * b));
            w.push(0.6 + 1.3 * ((i * 5 + j * 3) % 7) as f64 / 6.0);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// The exact quarter cylinder of radius `r` and length `h`: rational quadratic in u (middle
/// weight 1/sqrt 2), linear in v.
fn quarter_cylinder(r: f64, h: f64) -> NurbsSurface {
    let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
    let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
    let s = std::f64::consts::FRAC_1_SQRT_2;
    let mut pts = Vec::new();
    let mut w = Vec::new();
    for (y, z, wi) in [(0.0, -r, 1.0), (r, -r, s), (r, 0.0, 1.0)] {
        for x in [0.0, h] {
            pts.push(Vec3::new(x, y, z));
            w.push(wi);
        }
    }
    NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid")
}

/// The built-in Series 60 hull fitted by approximation (polynomial), and the same net with
/// weights between 0.7 and 1.3 (a rational hull, as the weight optimisers make).
fn series60() -> &'static (NurbsSurface, NurbsSurface) {
    static S: OnceLock<(NurbsSurface, NurbsSurface)> = OnceLock::new();
    S.get_or_init(|| {
        let s = hull::fit_offsets(&hull::series60_sample(), &hull::FitConfig::default()).expect("fits").surface;
        let w: Vec<f64> = (0..s.n_u() * s.n_v()).map(|k| 1.0 + 0.3 * ((k * 7 % 13) as f64 / 6.0 - 1.0)).collect();
        let r = NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &s.control_points(), Some(&w))
            .expect("valid");
        (s, r)
    })
}

/// `s` with its last control column (`v = v1`) collapsed onto one point: a pointed stem, whose
/// boundary edge degenerates.
fn pointed(s: &NurbsSurface) -> NurbsSurface {
    let (nu, nv) = (s.n_u(), s.n_v());
    let tip = s.control_point(nu / 2, nv - 1);
    let mut pts = s.control_points();
    for i in 0..nu {
        pts[i * nv + nv - 1] = tip;
    }
    NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, Some(&s.weights())).expect("valid")
}

/// The same surface with every control point multiplied by `k` (a change of length unit).
fn scaled(s: &NurbsSurface, k: f64) -> NurbsSurface {
    let pts: Vec<Vec3> = s.control_points().iter().map(|&p| p * k).collect();
    NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &pts, Some(&s.weights())).expect("valid")
}

fn size(s: &NurbsSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    (hi - lo).norm()
}

/// A 9 x 9 grid over the domain, boundaries included, plus 7 irregular interior points: 88.
fn samples(s: &NurbsSurface) -> Vec<[f64; 5]> {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut uv: Vec<(f64, f64)> = Vec::new();
    for a in 0..=8 {
        for b in 0..=8 {
            uv.push((u0 + (u1 - u0) * a as f64 / 8.0, v0 + (v1 - v0) * b as f64 / 8.0));
        }
    }
    for k in 1..=7 {
        let (a, b) = ((k as f64 * 0.618_034).fract(), (k as f64 * 0.414_214).fract());
        uv.push((u0 + (u1 - u0) * a, v0 + (v1 - v0) * b));
    }
    uv.into_iter()
        .map(|(u, v)| {
            let p = s.point(u, v);
            [u, v, p.x, p.y, p.z]
        })
        .collect()
}

/// A curve as the checker expects it, with 21 samples over its domain.
fn curve_json(c: &NurbsCurve) -> Value {
    let (t0, t1) = c.domain();
    let samples: Vec<[f64; 4]> = (0..=20)
        .map(|k| {
            let t = t0 + (t1 - t0) * k as f64 / 20.0;
            let p = c.point(t);
            [t, p.x, p.y, p.z]
        })
        .collect();
    json!({
        "degree": c.degree(),
        "knots": c.knots().as_slice(),
        "control_points": c.control_points().iter().map(|p| [p.x, p.y, p.z]).collect::<Vec<_>>(),
        "weights": c.weights(),
        "samples": samples,
    })
}

fn write_expected(path: &Path, s: &NurbsSurface, units: Units, curves: Option<&[NurbsCurve]>) {
    let mut expected = json!({
        "surface": SurfaceFile::from_surface(s, units.symbol()),
        "units": units.symbol(),
        "samples": samples(s),
    });
    if let Some(curves) = curves {
        expected["curves"] = curves.iter().map(curve_json).collect();
    }
    std::fs::write(path, serde_json::to_string_pretty(&expected).expect("serializes")).expect("write JSON");
}

// ---------------------------------------------------------------------------------------------
// STEP

fn step_bytes(s: &NurbsSurface, units: Units, name: &str) -> Vec<u8> {
    let mut meta = StepMeta::new(units, name, "2024-01-02T03:04:05");
    meta.author = "hullskin test".into();
    let mut out = Vec::new();
    write_step(&mut out, s, &meta).expect("writes to memory");
    out
}

/// One B-spline face per file, equal to ours in degrees, knots, poles, weights and 88 points,
/// in every unit (OCCT scales feet and inches by the file's conversion-based unit).
#[test]
fn occt_reads_the_step_export_exactly() {
    let Some(python) = occt_python() else { return };
    let dir = tempfile::tempdir().expect("temp dir");
    let (s60, s60_rational) = series60();
    let cases: Vec<(&str, NurbsSurface, Vec<Units>)> = vec![
        ("rational_bicubic", rational_bicubic(), vec![Units::Metre, Units::Millimetre]),
        ("quarter_cylinder", quarter_cylinder(2.0, 3.0), Units::ALL.to_vec()),
        ("pointed_stem", pointed(&rational_bicubic()), vec![Units::Metre]),
        ("series60", s60.clone(), vec![Units::Metre, Units::Foot]),
        ("series60_rational", s60_rational.clone(), vec![Units::Metre, Units::Inch]),
    ];
    let mut worst = 0.0f64;
    for (name, s, units) in &cases {
        for &units in units {
            // The same physical size in every unit.
            let s = scaled(s, 1.0 / units.metres_per_unit());
            let case = format!("{name}_{}", units.symbol());
            let stp = dir.path().join(format!("{case}.stp"));
            std::fs::write(&stp, step_bytes(&s, units, &format!("{case}.stp"))).expect("write STEP");
            let exp = dir.path().join(format!("{case}.json"));
            write_expected(&exp, &s, units, None);
            let (code, summary) = run_tool(&python, "occt_check.py", &[&stp, &exp]);
            assert_passed(&case, code, &summary);
            for read in ["native", "default_mm"] {
                let r = &summary["reads"][read];
                assert_eq!(r["samples"].as_u64(), Some(88), "{case} {read}");
                worst = worst.max(r["max_point_error_rel"].as_f64().expect("an error"));
                worst = worst.max(r["max_pole_error_rel"].as_f64().expect("an error"));
            }
            eprintln!(
                "{case}: OCCT {} units {} scale {} (expected {}) point err {:.1e}",
                summary["ocp_version"],
                summary["reads"]["native"]["file_length_units"],
                summary["reads"]["default_mm"]["measured_scale"],
                summary["reads"]["default_mm"]["expected_scale"],
                summary["reads"]["native"]["max_point_error_rel"].as_f64().unwrap_or(f64::NAN),
            );
        }
    }
    eprintln!("STEP: largest pole or point deviation read by OCCT: {worst:.2e} of the model size");
}

/// The checker must fail on a wrong expectation: the STEP file of one surface against the
/// samples of another (a changed weight), and a file in feet expected in metres.
#[test]
fn occt_step_check_detects_a_mismatch() {
    let Some(python) = occt_python() else { return };
    let dir = tempfile::tempdir().expect("temp dir");
    let s = quarter_cylinder(2.0, 3.0);
    let mut w = s.weights();
    w[2] = 0.9;
    w[3] = 0.9;
    let wrong =
        NurbsSurface::try_new(s.knots_u().clone(), s.knots_v().clone(), &s.control_points(), Some(&w)).expect("valid");
    let stp = dir.path().join("a.stp");
    std::fs::write(&stp, step_bytes(&s, Units::Metre, "a.stp")).expect("write");
    let exp = dir.path().join("wrong.json");
    write_expected(&exp, &wrong, Units::Metre, None);
    let (code, summary) = run_tool(&python, "occt_check.py", &[&stp, &exp]);
    assert_eq!(code, 1, "{summary}");
    assert!(summary["failed"].to_string().contains("points at"), "{}", summary["failed"]);

    std::fs::write(&stp, step_bytes(&s, Units::Foot, "a.stp")).expect("write");
    write_expected(&exp, &s, Units::Metre, None);
    let (code, summary) = run_tool(&python, "occt_check.py", &[&stp, &exp]);
    assert_eq!(code, 1, "{summary}");
    let failed = summary["failed"].to_string();
    assert!(failed.contains("length unit") && failed.contains("default_mm: poles"), "{failed}");
}
