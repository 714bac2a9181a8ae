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

use crate::common::python::{assert_tool_passed, run_tool, tools_python};
use crate::common::surfaces::{self, samples, weights_changed};
use crate::common::workspace_root;

use hull::{
    curvature_colors, greville_v, mesh_name, obj_comments, polynomial_approximation, section_curves,
    section_parameters, srgb_to_linear, stl_header, tessellate, write_glb, write_iges, write_iges_model, write_obj,
    write_step, write_stl_ascii, write_stl_binary, IgesMeta, StepMeta, SurfaceFile, Tessellation, TessellationOptions,
    Units,
};
use nurbs::fixtures::quarter_cylinder_along_x as quarter_cylinder;
use nurbs::{NurbsCurve, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use serde_json::{json, Value};

fn occt_python() -> String {
    tools_python("HULLSKIN_SKIP_OCCT", "Open CASCADE check of the STEP and IGES exports")
}

// ---------------------------------------------------------------------------------------------
// Surfaces

/// The shared rational bicubic ([`surfaces::rational_bicubic`]) with u and v swapped, so that
/// it is swept along v: its sections at constant v are stations (`x = const`), as the section
/// curves and the pointed stem here need.
fn rational_bicubic() -> NurbsSurface {
    surfaces::rational_bicubic().transposed()
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

fn size(s: &NurbsSurface) -> f64 {
    let (lo, hi) = s.control_bounds();
    (hi - lo).norm()
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
        "surface": SurfaceFile::from_surface(s, units),
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
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_reads_the_step_export_exactly() {
    let python = occt_python();
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
            let s = s.scaled(1.0 / units.metres_per_unit());
            let case = format!("{name}_{}", units.symbol());
            let stp = dir.path().join(format!("{case}.stp"));
            std::fs::write(&stp, step_bytes(&s, units, &format!("{case}.stp"))).expect("write STEP");
            let exp = dir.path().join(format!("{case}.json"));
            write_expected(&exp, &s, units, None);
            let (code, summary) = run_tool(&python, "occt_check.py", &[&stp, &exp]);
            assert_tool_passed(&case, code, &summary);
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
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_step_check_detects_a_mismatch() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let s = quarter_cylinder(2.0, 3.0);
    let wrong = weights_changed(&s);
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

// ---------------------------------------------------------------------------------------------
// IGES: section curves and the polynomial approximation

fn iges_meta(units: Units, name: &str) -> IgesMeta {
    let mut m = IgesMeta::new(units.into(), name, "20240102.030405");
    m.author = "hullskin test".into();
    m
}

/// The surface and its skinned sections (entity 126) read back by OCCT: one face, then as many
/// free B-spline edges as sections, each equal to ours at 21 points; the sections of an
/// interpolated fit pass through the offsets.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_reads_iges_section_curves() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let offsets = hull::series60_sample();
    let fit = hull::fit_offsets(&offsets, &hull::FitConfig { method: hull::FitMethod::Interp, ..Default::default() })
        .expect("fits");
    let s = &fit.surface;
    let vs = section_parameters(&fit.params);
    assert_eq!(vs.len(), offsets.sections.len());
    let curves = section_curves(s, &vs);
    // The sample's stem section is one point, which no curve entity can hold.
    let collapsed = offsets.sections.iter().filter(|sec| sec.points.windows(2).all(|w| w[0] == w[1])).count();
    assert_eq!(curves.len(), vs.len() - collapsed);
    // Interpolation: the section at v_k passes through its offsets at their u.
    let size = size(s);
    let mut worst = 0.0f64;
    for (sec, params) in offsets.sections.iter().zip(&fit.params) {
        let c = s.iso_curve_u(params[0].1);
        for (p, uv) in sec.points.iter().zip(params) {
            worst = worst.max(c.point(uv.0).distance(*p) / size);
        }
    }
    assert!(worst < 1e-9, "a section curve misses its offsets by {worst:.2e} of the size");

    for (name, surface, curves) in [
        ("s60_sections", s.clone(), curves.clone()),
        (
            "rational_sections",
            rational_bicubic(),
            section_curves(&rational_bicubic(), &greville_v(&rational_bicubic())),
        ),
    ] {
        let igs = dir.path().join(format!("{name}.igs"));
        let mut out = Vec::new();
        write_iges_model(&mut out, Some(&surface), &curves, &iges_meta(Units::Metre, "c.igs")).expect("writes");
        std::fs::write(&igs, out).expect("write");
        let exp = dir.path().join(format!("{name}.json"));
        write_expected(&exp, &surface, Units::Metre, Some(&curves));
        let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
        assert_tool_passed(name, code, &summary);
        let r = &summary["reads"]["native"];
        assert_eq!(r["curves"].as_u64(), Some(curves.len() as u64));
        eprintln!(
            "{name}: OCCT read {} curves, curve point err {:.1e}, surface point err {:.1e} of the size",
            curves.len(),
            r["max_curve_point_error_rel"].as_f64().unwrap_or(f64::NAN),
            r["max_point_error_rel"].as_f64().unwrap_or(f64::NAN)
        );
    }
}

/// The polynomial approximation of rational surfaces, written as a polynomial entity 128:
/// OCCT reads it exactly, and its points are within the tolerance of the rational original.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn occt_reads_the_polynomial_approximation() {
    let python = occt_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, s60_rational) = series60();
    for (name, s, rel) in [
        ("s60_rational", s60_rational.clone(), 1e-5),
        ("rational_bicubic", rational_bicubic(), 1e-6),
        ("quarter_cylinder", quarter_cylinder(2.0, 3.0), 1e-7),
    ] {
        let tol = rel * size(&s);
        let approx = polynomial_approximation(&s, tol).expect("approximates");
        assert!(!approx.exact && !approx.surface.is_rational() && approx.max_deviation <= tol);
        let igs = dir.path().join(format!("{name}.igs"));
        let mut out = Vec::new();
        write_iges(&mut out, &approx.surface, &iges_meta(Units::Metre, "p.igs")).expect("writes");
        std::fs::write(&igs, out).expect("write");
        let exp = dir.path().join(format!("{name}.json"));
        write_expected(&exp, &approx.surface, Units::Metre, None);
        // The rational original at points off the approximation's check grid.
        let mut doc: Value = serde_json::from_str(&std::fs::read_to_string(&exp).expect("read")).expect("JSON");
        doc["reference"] = json!({"samples": samples(&s), "tolerance": tol});
        std::fs::write(&exp, doc.to_string()).expect("write");
        let (code, summary) = run_tool(&python, "occt_check.py", &[&igs, &exp]);
        assert_tool_passed(name, code, &summary);
        eprintln!(
            "{name}: {}x{} -> {}x{} polynomial poles after {} refinements; deviation {:.2e} (ours, {} points), \
             {:.2e} (OCCT, 88 points), tolerance {tol:.2e}",
            s.n_u(),
            s.n_v(),
            approx.surface.n_u(),
            approx.surface.n_v(),
            approx.refinements,
            approx.max_deviation,
            approx.check_points,
            summary["reads"]["native"]["reference_deviation"].as_f64().unwrap_or(f64::NAN)
        );
    }
}

// ---------------------------------------------------------------------------------------------
// Meshes

fn mesh_python() -> String {
    tools_python("HULLSKIN_SKIP_MESH", "trimesh/pygltflib check of the mesh exports")
}

/// The file's vertices, faces and per-vertex or per-face normals as the Python readers see
/// them, mapped back to model axes and units.
struct ReadMesh {
    vertices: Vec<Vec3>,
    faces: Vec<[usize; 3]>,
    face_normals: Vec<Vec3>,
    vertex_normals: Vec<Vec3>,
    colors: Vec<[f64; 3]>,
}

fn vec3s(v: &Value, map: impl Fn([f64; 3]) -> Vec3) -> Vec<Vec3> {
    v.as_array()
        .map(|a| {
            a.iter()
                .map(|p| {
                    let c: Vec<f64> =
                        p.as_array().expect("a triple").iter().map(|x| x.as_f64().expect("num")).collect();
                    map([c[0], c[1], c[2]])
                })
                .collect()
        })
        .unwrap_or_default()
}

fn read_mesh(python: &str, path: &Path, units: Units) -> ReadMesh {
    let (code, summary) = run_tool(python, "mesh_check.py", &[path]);
    assert_tool_passed(&path.display().to_string(), code, &summary);
    let glb = summary["format"] == "glb";
    let k = units.metres_per_unit();
    // glTF: (X, Y, Z) = (y, z, x) in metres.
    let point = |c: [f64; 3]| if glb { Vec3::new(c[2] / k, c[0] / k, c[1] / k) } else { Vec3::new(c[0], c[1], c[2]) };
    let dir = |c: [f64; 3]| if glb { Vec3::new(c[2], c[0], c[1]) } else { Vec3::new(c[0], c[1], c[2]) };
    let faces = summary["faces"]
        .as_array()
        .expect("faces")
        .iter()
        .map(|f| {
            let i: Vec<usize> =
                f.as_array().expect("a face").iter().map(|x| x.as_u64().expect("index") as usize).collect();
            [i[0], i[1], i[2]]
        })
        .collect();
    ReadMesh {
        vertices: vec3s(&summary["vertices"], point),
        faces,
        face_normals: vec3s(&summary["face_normals"], dir),
        vertex_normals: vec3s(&summary["vertex_normals"], dir),
        colors: vec3s(&summary["colors"], |c| Vec3::new(c[0], c[1], c[2])).iter().map(|c| [c.x, c.y, c.z]).collect(),
    }
}

/// Distance from `q` to the triangle `abc` (Ericson, *Real-Time Collision Detection* 5.1.5).
fn point_triangle_distance(q: Vec3, a: Vec3, b: Vec3, c: Vec3) -> f64 {
    let (ab, ac, ap) = (b - a, c - a, q - a);
    let (d1, d2) = (ab.dot(ap), ac.dot(ap));
    if d1 <= 0.0 && d2 <= 0.0 {
        return q.distance(a);
    }
    let bp = q - b;
    let (d3, d4) = (ab.dot(bp), ac.dot(bp));
    if d3 >= 0.0 && d4 <= d3 {
        return q.distance(b);
    }
    let vc = d1 * d4 - d3 * d2;
    if vc <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return q.distance(a + ab * (d1 / (d1 - d3)));
    }
    let cp = q - c;
    let (d5, d6) = (ab.dot(cp), ac.dot(cp));
    if d6 >= 0.0 && d5 <= d6 {
        return q.distance(c);
    }
    let vb = d5 * d2 - d1 * d6;
    if vb <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return q.distance(a + ac * (d2 / (d2 - d6)));
    }
    let va = d3 * d6 - d5 * d4;
    if va <= 0.0 && (d4 - d3) >= 0.0 && (d5 - d6) >= 0.0 {
        return q.distance(b + (c - b) * ((d4 - d3) / ((d4 - d3) + (d5 - d6))));
    }
    let denom = 1.0 / (va + vb + vc);
    q.distance(a + ab * (vb * denom) + ac * (vc * denom))
}

#[derive(Default, Debug)]
struct MeshDeviation {
    /// Largest |vertex read - S(u, v)| over the size.
    vertex_rel: f64,
    /// Largest distance from a triangle's centroid or edge midpoint to the surface.
    chord: f64,
    /// Largest distance from a surface sample to the mesh.
    surface_to_mesh: f64,
}

/// The surface point of mesh vertex `k`, mirrored for the port half.
fn vertex_on_surface(s: &NurbsSurface, tess: &Tessellation, mirror: bool, k: usize) -> Vec3 {
    let (u, v) = tess.params[k];
    let p = s.point(u, v);
    if mirror && k >= tess.mesh.vertices.len() / 2 {
        Vec3::new(p.x, -p.y, p.z)
    } else {
        p
    }
}

/// Compare a mesh read back with the surface it was made from: every vertex with the surface
/// at its parameters, chords (triangle centroids and edge midpoints) projected onto the
/// surface, and surface points against the triangles.
fn compare_mesh(
    s: &NurbsSurface,
    tess: &Tessellation,
    mirror: bool,
    read: &ReadMesh,
    per_corner: bool,
) -> MeshDeviation {
    let size = size(s);
    let on_surface = |k: usize| vertex_on_surface(s, tess, mirror, k);
    let mut dev = MeshDeviation::default();
    // Vertices: STL has three per triangle in triangle order; OBJ and glTF keep ours.
    let corner_ids: Vec<usize> = if per_corner {
        tess.mesh.triangles.iter().flat_map(|t| t.map(|k| k as usize)).collect()
    } else {
        (0..tess.mesh.vertices.len()).collect()
    };
    assert_eq!(read.vertices.len(), corner_ids.len(), "vertex count");
    for (q, &k) in read.vertices.iter().zip(&corner_ids) {
        dev.vertex_rel = dev.vertex_rel.max(q.distance(on_surface(k)) / size);
    }
    assert_eq!(read.faces.len(), tess.mesh.triangles.len(), "triangle count");
    // Chords: centroid and edge midpoints of every 7th triangle, projected onto the surface
    // (or its mirror image).
    let projector = SurfaceProjector::new(s, ProjectionOptions::default());
    let corners = |f: &[usize; 3]| f.map(|k| read.vertices[k]);
    let starboard_faces = read.faces.len() / if mirror { 2 } else { 1 };
    for (t, f) in read.faces.iter().enumerate().step_by(7) {
        let [a, b, c] = corners(f);
        for q in [(a + b + c) * (1.0 / 3.0), (a + b) * 0.5, (b + c) * 0.5, (c + a) * 0.5] {
            // The port half (appended after the starboard triangles) is the mirror image.
            let q = if t >= starboard_faces { Vec3::new(q.x, -q.y, q.z) } else { q };
            dev.chord = dev.chord.max(projector.project(q).distance);
        }
    }
    // Surface to mesh: 60 surface points off the grid, each against every triangle.
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    for k in 0..60 {
        let (a, b) = ((k as f64 * 0.618_034 + 0.1).fract(), (k as f64 * 0.414_214 + 0.3).fract());
        let p = s.point(u0 + (u1 - u0) * a, v0 + (v1 - v0) * b);
        let d = read.faces.iter().map(|f| {
            let [a, b, c] = corners(f);
            point_triangle_distance(p, a, b, c)
        });
        dev.surface_to_mesh = dev.surface_to_mesh.max(d.fold(f64::INFINITY, f64::min));
    }
    dev
}

/// Outward: the area-weighted y component of the normals of the starboard half is positive
/// (it is the hull's projected area on the centre plane); every stored normal agrees with
/// its triangle's winding (STL) or its vertex's surface normal (OBJ, glTF).
fn check_orientation(name: &str, s: &NurbsSurface, tess: &Tessellation, mirror: bool, read: &ReadMesh) {
    let mut ny_area = 0.0;
    let starboard_faces = read.faces.len() / if mirror { 2 } else { 1 };
    for f in &read.faces[..starboard_faces] {
        let [a, b, c] = f.map(|k| read.vertices[k]);
        ny_area += (b - a).cross(c - a).y;
    }
    assert!(ny_area > 0.0, "{name}: the starboard half faces inward");
    for (t, n) in read.face_normals.iter().enumerate() {
        let [a, b, c] = read.faces[t].map(|k| read.vertices[k]);
        let w = (b - a).cross(c - a).normalized().expect("no degenerate triangle");
        assert!(n.dot(w) > 0.99, "{name}: facet {t} normal {n:?} against its winding {w:?}");
    }
    let half = tess.mesh.vertices.len() / if mirror { 2 } else { 1 };
    for (k, n) in read.vertex_normals.iter().enumerate() {
        let (u, v) = tess.params[k];
        let Some(sn) = s.normal(u, v) else { continue };
        let sn = if tess.flipped { -sn } else { sn };
        let sn = if k >= half { Vec3::new(sn.x, -sn.y, sn.z) } else { sn };
        assert!((n.norm() - 1.0).abs() < 1e-4, "{name}: normal {k} {n:?} not unit (ours {:?})", tess.mesh.normals[k]);
        assert!(n.dot(sn) > 0.999, "{name}: vertex normal {k} {n:?} is not the surface's {sn:?}");
    }
}

/// STL (binary and ASCII), OBJ and glTF of three surfaces read back: vertices on the surface
/// within 1e-6 of its size, chords within the tolerance, normals outward, glTF colours those
/// of the Gaussian curvature, glTF in metres whatever the units.
#[test]
#[cfg_attr(skip_mesh, ignore = "HULLSKIN_SKIP_MESH=1")]
fn meshes_read_back_by_trimesh_and_pygltflib() {
    let python = mesh_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, s60_rational) = series60();
    let cases = [
        ("quarter_cylinder", quarter_cylinder(2.0, 3.0), Units::Metre, false, 1e-3),
        ("s60_rational", s60_rational.clone(), Units::Metre, true, 1e-4),
        ("pointed_ft", pointed(&rational_bicubic()).scaled(1.0 / 0.3048), Units::Foot, false, 2e-4),
    ];
    for (name, s, units, mirror, rel) in &cases {
        let tol = rel * size(s);
        let tess = tessellate(s, &TessellationOptions { tolerance: tol, mirror: *mirror }).expect("tessellates");
        for (ext, kind) in [("stl", "binary"), ("stl", "ascii"), ("obj", "obj"), ("glb", "glb")] {
            let path = dir.path().join(format!("{name}_{kind}.{ext}"));
            let mut out = Vec::new();
            match kind {
                "binary" => write_stl_binary(&mut out, &tess.mesh, &stl_header(name, *units)),
                "ascii" => write_stl_ascii(&mut out, &tess.mesh, &mesh_name(name)),
                "obj" => obj_comments(name, tess.tolerance, *units)
                    .and_then(|c| write_obj(&mut out, &tess.mesh, &c, Some(&mesh_name(name)))),
                _ => write_glb(&mut out, &tess, name, *units),
            }
            .expect("writes");
            std::fs::write(&path, out).expect("write");
            let read = read_mesh(&python, &path, *units);
            let case = format!("{name} {kind}");
            let dev = compare_mesh(s, &tess, *mirror, &read, ext == "stl");
            check_orientation(&case, s, &tess, *mirror, &read);
            eprintln!(
                "{case}: {} triangles; vertices {:.1e} of the size; chords {:.2e}, surface to mesh {:.2e}, tolerance \
                 {tol:.2e}",
                tess.mesh.triangles.len(),
                dev.vertex_rel,
                dev.chord,
                dev.surface_to_mesh
            );
            // f32 coordinates: 6e-8 of the largest coordinate, well within 1e-6 of the size.
            assert!(dev.vertex_rel <= 1e-6, "{case}: a vertex is {:.2e} of the size off the surface", dev.vertex_rel);
            // The chord bound holds to f32 rounding of the corners (1e-6 of the size).
            assert!(dev.chord <= tol + 1e-6 * size(s), "{case}: a chord deviates by {} > {tol}", dev.chord);
            assert!(dev.surface_to_mesh <= tol + 1e-6 * size(s), "{case}: surface to mesh {}", dev.surface_to_mesh);
            if kind == "glb" {
                let want = curvature_colors(&tess);
                assert_eq!(read.colors.len(), want.len());
                for (c, w) in read.colors.iter().zip(&want) {
                    assert_eq!(*c, w.map(f64::from), "{case}: colour");
                }
            }
        }
        // The cylinder's Gaussian curvature is zero: every colour is the map's white.
        if *name == "quarter_cylinder" {
            let white = srgb_to_linear(247);
            assert!(tess.gaussian.iter().all(|k| k.abs() < 1e-9));
            assert!(curvature_colors(&tess).iter().all(|c| *c == [white; 3]));
        } else {
            // A hull bends both ways: both ends of the map appear.
            assert!(tess.gaussian.iter().any(|&k| k > 0.0) && tess.gaussian.iter().any(|&k| k < 0.0));
        }
    }
}

/// Where `npm install` put the Khronos glTF-Validator (npm `gltf-validator`, pinned). Needs
/// `node` and `npm` (the npm registry the first time); fails loudly without them (its test is
/// ignored with `HULLSKIN_SKIP_GLTF_VALIDATOR=1`).
fn gltf_validator() -> PathBuf {
    const PACKAGE: &str = "gltf-validator@2.0.0-dev.3.10";
    static DIR: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    let found = DIR.get_or_init(|| {
        let dir = Path::new(env!("CARGO_TARGET_TMPDIR")).join("gltf-validator");
        if dir.join("node_modules/gltf-validator/package.json").is_file() {
            return Ok(dir);
        }
        let out = Command::new("npm")
            .args(["install", "--no-audit", "--no-fund", "--prefix"])
            .arg(&dir)
            .arg(PACKAGE)
            .output()
            .map_err(|e| format!("cannot run npm: {e}"))?;
        if out.status.success() {
            Ok(dir)
        } else {
            Err(format!("npm install {PACKAGE} failed:\n{}", String::from_utf8_lossy(&out.stderr)))
        }
    });
    match found {
        Ok(d) => d.clone(),
        Err(e) => panic!("{e}\nSet HULLSKIN_SKIP_GLTF_VALIDATOR=1 to skip the Khronos validator."),
    }
}

fn run_validator(prefix: &Path, glb: &Path) -> (i32, Value) {
    let script = workspace_root().join("tools/gltf_validate.mjs");
    let out = Command::new("node").arg(&script).arg(prefix).arg(glb).output().expect("run node");
    let stdout = String::from_utf8_lossy(&out.stdout);
    let summary = serde_json::from_str(&stdout).unwrap_or_else(|e| {
        panic!("gltf_validate.mjs printed no JSON ({e}):\n{stdout}\n{}", String::from_utf8_lossy(&out.stderr))
    });
    (out.status.code().unwrap_or(-1), summary)
}

/// Our glTF of the mirrored rational Series 60 hull (feet converted to metres) written to
/// `dir/hull.glb`, and a copy corrupted by pointing its last index past the vertices (the
/// file's last 4 bytes) to `dir/bad.glb`; with the triangle count.
fn gltf_and_corrupted(dir: &Path) -> (PathBuf, PathBuf, usize) {
    let (_, s60_rational) = series60();
    let s = s60_rational.scaled(1.0 / 0.3048);
    let tess = tessellate(&s, &TessellationOptions { tolerance: 1e-4 * size(&s), mirror: true }).expect("tessellates");
    let mut bytes = Vec::new();
    write_glb(&mut bytes, &tess, "hull", Units::Foot).expect("writes");
    let (glb, bad) = (dir.join("hull.glb"), dir.join("bad.glb"));
    std::fs::write(&glb, &bytes).expect("write");
    let n = bytes.len();
    bytes[n - 4..].copy_from_slice(&u32::MAX.wrapping_sub(7).to_le_bytes());
    std::fs::write(&bad, &bytes).expect("write");
    (glb, bad, tess.mesh.triangles.len())
}

/// The Khronos glTF-Validator finds no error, warning, info or hint in our glTF (mirrored
/// rational hull, feet converted to metres), and does find the error in a corrupted copy (an
/// index past the last vertex).
#[test]
#[cfg_attr(skip_gltf_validator, ignore = "HULLSKIN_SKIP_GLTF_VALIDATOR=1")]
fn khronos_validator_accepts_the_gltf() {
    let prefix = gltf_validator();
    let dir = tempfile::tempdir().expect("temp dir");
    let (glb, bad, triangles) = gltf_and_corrupted(dir.path());
    let (code, summary) = run_validator(&prefix, &glb);
    let issues = &summary["files"][0]["issues"];
    assert!(code == 0 && summary["ok"] == true, "{summary}");
    for k in ["numErrors", "numWarnings", "numInfos", "numHints"] {
        assert_eq!(issues[k], 0, "{k}: {issues}");
    }
    eprintln!("glTF-Validator {}: no issue in {triangles} triangles", summary["validator"]);
    let (code, summary) = run_validator(&prefix, &bad);
    assert_eq!(code, 1, "{summary}");
    assert!(summary["files"][0]["issues"]["numErrors"].as_u64() > Some(0), "{summary}");
}

/// `tools/mesh_check.py` (trimesh, pygltflib) finds the error in the corrupted glTF too.
#[test]
#[cfg_attr(skip_mesh, ignore = "HULLSKIN_SKIP_MESH=1")]
fn mesh_check_refuses_the_corrupted_gltf() {
    let python = mesh_python();
    let dir = tempfile::tempdir().expect("temp dir");
    let (_, bad, _) = gltf_and_corrupted(dir.path());
    let (code, summary) = run_tool(&python, "mesh_check.py", &[&bad]);
    assert_ne!(code, 0, "mesh_check.py accepted a corrupted file: {}", summary["failed"]);
}
