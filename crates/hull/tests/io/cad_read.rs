//! The IGES and STEP readers (`hull::read_cad_surfaces`): hullskin's own exports read back in
//! every unit, files written by Open CASCADE (`tools/occt_write.py`), the Wigley hull's
//! hydrostatics through IGES, and malformed files refused at their place.
//!
//! The Open CASCADE test needs the Python of `tools/requirements.txt` (see
//! `common::python`); it fails without it unless `HULLSKIN_SKIP_OCCT=1`.

use std::path::Path;
use std::process::Command;

use crate::common::python::tools_python;
use crate::common::surfaces::{polynomial, rational_bicubic, wigley_patch};
use crate::common::workspace_root;
use hull::{
    parse_cad_surfaces, read_cad_surfaces, write_iges, write_step, write_surface_json, CadFormat, CadSurfaces,
    Hydrostatics, HydrostaticsOptions, HydrostaticsRow, IgesMeta, StepMeta, Units,
};
use nurbs::fixtures::quarter_cylinder;
use nurbs::{NurbsSurface, Vec3};
use serde_json::Value;

/// Relative agreement asked of every pole, weight and knot: a unit conversion is one or two
/// roundings (a few 1e-16); 1e-12 leaves room for the writer's own scaling (OCCT) and is far
/// below any real error (a transposed net, a lost weight).
const REL: f64 = 1e-12;

fn iges(s: &NurbsSurface, units: Units) -> Vec<u8> {
    let mut out = Vec::new();
    write_iges(&mut out, s, &IgesMeta::new(units.into(), "t.igs", "20240102.030405")).expect("writes");
    out
}

fn step(s: &NurbsSurface, units: Units) -> Vec<u8> {
    let mut out = Vec::new();
    write_step(&mut out, s, &StepMeta::new(units, "t.stp", "2024-01-02T03:04:05")).expect("writes");
    out
}

fn near(a: f64, b: f64, scale: f64) -> bool {
    (a - b).abs() <= REL * scale
}

/// Every pole (relative to the net's size), weight and knot of `got` within [`REL`] of `want`;
/// the first difference as an error.
fn compare(got: &NurbsSurface, want: &NurbsSurface) -> Result<(), String> {
    if (got.degree_u(), got.degree_v(), got.n_u(), got.n_v())
        != (want.degree_u(), want.degree_v(), want.n_u(), want.n_v())
    {
        return Err(format!("degrees or counts differ: {}x{} poles", got.n_u(), got.n_v()));
    }
    let (lo, hi) = want.control_bounds();
    let size = (hi - lo).norm().max(f64::MIN_POSITIVE);
    for (k, (a, b)) in got.control_points().iter().zip(want.control_points()).enumerate() {
        if a.distance(b) > REL * size {
            return Err(format!("pole {k}: {a:?} against {b:?}"));
        }
    }
    for (k, (a, b)) in got.weights().iter().zip(want.weights()).enumerate() {
        if !near(*a, b, b.abs()) {
            return Err(format!("weight {k}: {a} against {b}"));
        }
    }
    for (a, b) in [(got.knots_u(), want.knots_u()), (got.knots_v(), want.knots_v())] {
        let span = b.as_slice().last().unwrap_or(&1.0) - b.as_slice()[0];
        if a.as_slice().len() != b.as_slice().len()
            || a.as_slice().iter().zip(b.as_slice()).any(|(x, y)| !near(*x, *y, span))
        {
            return Err(format!("knots {:?} against {:?}", a.as_slice(), b.as_slice()));
        }
    }
    Ok(())
}

fn one(read: &CadSurfaces) -> &NurbsSurface {
    assert_eq!(read.surfaces.len(), 1, "{:?}", read.surfaces.iter().map(|s| &s.name).collect::<Vec<_>>());
    &read.surfaces[0].surface
}

/// The rational bicubic (non-uniform knots, a double knot), the polynomial and the quarter
/// cylinder, written in each unit by hullskin's IGES and STEP writers: read in the file's unit
/// they come back bit for bit, and converted to every other unit within [`REL`].
#[test]
fn hullskins_own_exports_read_back_in_every_unit() {
    let cases =
        [("rational", rational_bicubic()), ("polynomial", polynomial()), ("cylinder", quarter_cylinder(2.0, 3.0))];
    for (name, metres) in &cases {
        for file_units in Units::ALL {
            let in_file = metres.scaled(1.0 / file_units.metres_per_unit());
            for (format, bytes) in
                [(CadFormat::Iges, iges(&in_file, file_units)), (CadFormat::Step, step(&in_file, file_units))]
            {
                let case = format!("{name} {} in {file_units}", format.name());
                let own = parse_cad_surfaces(&bytes, "t", None).unwrap_or_else(|e| panic!("{case}: {e}"));
                assert_eq!((own.format, own.units), (format, file_units), "{case}");
                // Shortest round-trip numbers and no conversion: the very same surface.
                assert_eq!(one(&own), &in_file, "{case}");
                for target in Units::ALL {
                    let read = parse_cad_surfaces(&bytes, "t", Some(target)).unwrap_or_else(|e| panic!("{case}: {e}"));
                    assert_eq!(read.units, target);
                    let want = metres.scaled(1.0 / target.metres_per_unit());
                    compare(one(&read), &want).unwrap_or_else(|e| panic!("{case} read in {target}: {e}"));
                }
            }
        }
    }
}

/// Several surfaces in one file, a transformation matrix, and what is left out, noted.
#[test]
fn several_entities_a_transform_and_notes() {
    let a = polynomial();
    let text = String::from_utf8(iges(&a, Units::Metre)).expect("ASCII");
    // The same file with a second copy of the entity, under a 124 that swaps x and y and
    // moves z by 10, and a colour (314): rebuilt record by record.
    let lines: Vec<&str> = text.lines().collect();
    let sec = |c: char| lines.iter().filter(|l| l.as_bytes()[72] == c as u8).map(|l| l.to_string()).collect::<Vec<_>>();
    let (s, g, d, p) = (sec('S'), sec('G'), sec('D'), sec('P'));
    let np = p.len();
    let mut d2 = d.clone();
    let mut p2 = p.clone();
    let field = |v: &[String]| v.iter().map(|l| l[..72].to_string()).collect::<Vec<_>>();
    let mut dd = field(&d);
    // Entity 2 (D 3): the copy, its P data after the first's, transform at D 5.
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 128, np + 1, 0, 0, 0, 0, 5, 0, "00000000"));
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 128, 0, 0, np, 0, "", "", "MOVED", 0));
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 124, 2 * np + 1, 0, 0, 0, 0, 0, 0, "00000000"));
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 124, 0, 0, 1, 0, "", "", "", 0));
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 314, 2 * np + 2, 0, 0, 0, 0, 0, 0, "00000000"));
    dd.push(format!("{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}{:>8}", 314, 0, 0, 1, 0, "", "", "", 0));
    d2.clear();
    for (k, l) in dd.iter().enumerate() {
        d2.push(format!("{l:<72}D{:>7}", k + 1));
    }
    for (k, l) in p.iter().enumerate() {
        p2.push(format!("{}{:>8}P{:>7}", &l[..64], 3, np + k + 1));
    }
    p2.push(format!("{:<64}{:>8}P{:>7}", "124,0.,1.,0.,0.,1.,0.,0.,0.,0.,0.,1.,10.;", 5, 2 * np + 1));
    p2.push(format!("{:<64}{:>8}P{:>7}", "314,50.,0.,0.,4HBLUE;", 7, 2 * np + 2));
    let t = format!("{:<72}T{:>7}", format!("S{:>7}G{:>7}D{:>7}P{:>7}", s.len(), g.len(), d2.len(), p2.len()), 1);
    let file = [s, g, d2, p2, vec![t]].concat().join("\n") + "\n";
    let read = parse_cad_surfaces(file.as_bytes(), "two.igs", None).expect("reads");
    assert_eq!(read.surfaces.len(), 2);
    assert_eq!(read.surfaces[0].surface, a);
    assert_eq!(read.surfaces[1].name, "entity 128 at D 3 (MOVED)");
    for (p, q) in read.surfaces[1].surface.control_points().iter().zip(a.control_points()) {
        assert_eq!(*p, Vec3::new(q.y, q.x, q.z + 10.0), "x and y swapped, z + 10: exact in binary for these poles");
    }
    assert_eq!(read.notes, ["skipped 1 entity of type 314 (colour)"]);
}

#[test]
fn step_notes_name_the_geometry_left_out() {
    let read = parse_cad_surfaces(&step(&rational_bicubic(), Units::Foot), "t.stp", None).expect("reads");
    assert_eq!(read.units, Units::Foot);
    let name = &read.surfaces[0].name;
    assert!(name.starts_with('#') && name.ends_with(" 'hull'"), "the instance and the writer's name: {name}");
    assert_eq!(
        read.notes,
        [
            "the bounds of 1 face (ADVANCED_FACE) ignored: each surface is returned whole",
            "skipped 4 RATIONAL_B_SPLINE_CURVE (geometry other than B-spline surfaces)",
        ]
    );
}

/// Files written by Open CASCADE: a rational and a polynomial surface as IGES (a trimmed
/// surface 144 over the 128) and STEP (an `ADVANCED_FACE`), in mm and in m, read in mm and
/// compared with what `tools/occt_write.py` built.
#[test]
#[cfg_attr(skip_occt, ignore = "HULLSKIN_SKIP_OCCT=1")]
fn files_written_by_open_cascade() {
    let python = tools_python("HULLSKIN_SKIP_OCCT", "reading files written by Open CASCADE");
    let dir = tempfile::tempdir().expect("temp dir");
    let script = workspace_root().join("tools/occt_write.py");
    let out = Command::new(&python).arg(&script).arg(dir.path()).output().expect("runs the Python");
    assert!(out.status.success(), "occt_write.py failed: {}", String::from_utf8_lossy(&out.stderr));
    let doc: Value =
        serde_json::from_str(&std::fs::read_to_string(dir.path().join("expected.json")).expect("expected.json"))
            .expect("JSON");
    let files = doc["files"].as_array().expect("files");
    assert_eq!(files.len(), 8, "2 surfaces x 2 units x 2 formats");
    let floats =
        |v: &Value| v.as_array().expect("array").iter().map(|x| x.as_f64().expect("number")).collect::<Vec<f64>>();
    for f in files {
        let name = f["file"].as_str().expect("name");
        let path = dir.path().join(name);
        let read = read_cad_surfaces(&path, Some(Units::Millimetre)).unwrap_or_else(|e| panic!("{e}"));
        let own = read_cad_surfaces(&path, None).unwrap_or_else(|e| panic!("{e}"));
        assert_eq!(own.units.symbol(), f["unit"].as_str().expect("unit"), "{name}: the file's unit");
        let s = one(&read);
        let deg = floats(&f["degree"]);
        assert_eq!((s.degree_u() as f64, s.degree_v() as f64), (deg[0], deg[1]), "{name}");
        let poles: Vec<Vec3> = f["poles_mm"]
            .as_array()
            .expect("poles")
            .iter()
            .map(|p| {
                let c = floats(p);
                Vec3::new(c[0], c[1], c[2])
            })
            .collect();
        let ku = nurbs::KnotVector::try_new(s.degree_u(), floats(&f["knots_u"])).expect("knots");
        let kv = nurbs::KnotVector::try_new(s.degree_v(), floats(&f["knots_v"])).expect("knots");
        let want = NurbsSurface::try_new(ku, kv, &poles, Some(&floats(&f["weights"]))).expect("valid");
        compare(s, &want).unwrap_or_else(|e| panic!("{name}: {e}"));
        assert_eq!(s.is_rational(), f["rational"].as_bool() == Some(true), "{name}");
        if name.ends_with(".igs") {
            assert!(
                read.notes.iter().any(|n| n.contains("entity 144") && n.contains("trimming ignored")),
                "{name}: {:?}",
                read.notes
            );
        }
        eprintln!("{name}: {} notes: {:?}", read.notes.len(), read.notes);
    }
}

fn wigley_rows(s: &NurbsSurface, drafts: &[f64]) -> Vec<HydrostaticsRow> {
    let h = Hydrostatics::new(s, &HydrostaticsOptions::default()).expect("valid options");
    drafts.iter().map(|&t| h.at(t).expect("a draft on the hull")).collect()
}

/// The Wigley hull (L 100, B 10, T 6.25, refined so the patch has interior knots, and made
/// rational by a Moebius reparameterization): its hydrostatics from the IGES and STEP files
/// equal those from its surface.json, bit for bit in the file's unit, and within 1e-12 from a
/// file in millimetres read in metres.
#[test]
fn wigley_hydrostatics_from_iges_and_step_equal_those_from_surface_json() {
    let exact = wigley_patch(100.0, 10.0, 6.25);
    // Weights 2^i along u: a Moebius reparameterization of the Bezier patch (The NURBS Book
    // 6.1), the same geometry; then knots inserted, which keeps it too.
    let w: Vec<f64> = (0..3).flat_map(|i| [2f64.powi(i); 3]).collect();
    let rational =
        NurbsSurface::try_new(exact.knots_u().clone(), exact.knots_v().clone(), &exact.control_points(), Some(&w))
            .expect("valid");
    let wigley = rational.refine_knots_u(&[0.25, 0.5]).and_then(|s| s.refine_knots_v(&[0.3])).expect("knot insertion");
    assert!(wigley.is_rational() && wigley.n_u() == 5);
    let dir = tempfile::tempdir().expect("temp dir");
    let json_path = dir.path().join("wigley.json");
    let mut json = Vec::new();
    write_surface_json(&mut json, &wigley, hull::Units::Metre).expect("writes");
    std::fs::write(&json_path, &json).expect("write");
    let (from_json, _) = hull::read_surface_json(std::str::from_utf8(&json).expect("UTF-8")).expect("reads");
    let drafts = [6.25, 4.0, 1.5];
    let want = wigley_rows(&from_json, &drafts);
    // Cb at T: 4/9 for the Wigley hull; the rational integrands are integrated to 1e-9.
    assert!((want[0].cb - 4.0 / 9.0).abs() < 1e-9, "Cb {}", want[0].cb);
    for (name, bytes) in [("wigley.igs", iges(&wigley, Units::Metre)), ("wigley.stp", step(&wigley, Units::Metre))] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("write");
        let read = read_cad_surfaces(&path, None).expect("reads");
        assert_eq!(read.units, Units::Metre);
        assert_eq!(wigley_rows(one(&read), &drafts), want, "{name}");
    }
    let mm = wigley.scaled(1000.0);
    for (name, bytes) in [("mm.igs", iges(&mm, Units::Millimetre)), ("mm.stp", step(&mm, Units::Millimetre))] {
        let path = dir.path().join(name);
        std::fs::write(&path, bytes).expect("write");
        let rows = wigley_rows(one(&read_cad_surfaces(&path, Some(Units::Metre)).expect("reads")), &drafts);
        for (g, w) in rows.iter().zip(&want) {
            for (a, b) in g.values().iter().zip(w.values()) {
                // The poles differ by the rounding of x 1000 / 1000 (1e-16); the integrals
                // amplify it by the conditioning of the waterline search, well under 1e-12.
                // (Without perpendiculars both rows lack the figures on Lpp.)
                match (*a, b) {
                    (Some(a), Some(b)) => assert!(near(a, b, b.abs()), "{name}: {a} against {b}"),
                    (a, b) => assert_eq!(a, b, "{name}"),
                }
            }
        }
    }
}

/// `(what is changed, the file, what the message must hold)`: each an error naming the file,
/// the line, and what was expected; none a panic.
fn bad_files() -> Vec<(&'static str, Vec<u8>, &'static str)> {
    let igs = String::from_utf8(iges(&rational_bicubic(), Units::Metre)).expect("ASCII");
    let stp = String::from_utf8(step(&rational_bicubic(), Units::Metre)).expect("ASCII");
    let cut = |t: &str, frac: f64| t.as_bytes()[..(t.len() as f64 * frac) as usize].to_vec();
    // The D record of the 128 and its first P record.
    let d1 = igs.lines().find(|l| l.as_bytes()[72] == b'D').expect("D").to_string();
    let p1 = igs.lines().find(|l| l.as_bytes()[72] == b'P').expect("P").to_string();
    // Edits of the same length, so the record stays 80 columns.
    let head = "128,6,6,3,3,0,0,0,0,0,";
    let edit = |to: &str| {
        assert_eq!(to.len(), head.len(), "{to}");
        p1.replacen(head, to, 1)
    };
    assert!(p1.starts_with(head), "{p1}");
    let p1_bad_k1 = edit("128,600,6,3,3,0,0,0,,,");
    let p1_huge = edit("128,999999,6,3,3,,,,,,");
    let p1_text = edit("128,six,6,3,3,0,0,0,0,");
    let d1_ptr = d1.replacen("       1       0", "     999       0", 1);
    // The first pole of the surface (the writer adds the poles before the surface).
    let pole = stp.lines().find(|l| l.contains("=CARTESIAN_POINT(")).expect("a pole").split('=').next().expect("#n");
    let pole_def = format!("{pole}=CARTESIAN_POINT");
    vec![
        ("IGES cut in the P section", cut(&igs, 0.7), "is the file truncated"),
        (
            "IGES without its T record",
            igs.lines().filter(|l| !l.ends_with("T      1")).collect::<Vec<_>>().join("\n").into_bytes(),
            "no terminate (T) section",
        ),
        ("IGES K1 wrong", igs.replace(&p1, &p1_bad_k1).into_bytes(), "K1, K2, M1 and M2 call for"),
        ("IGES K1 huge", igs.replace(&p1, &p1_huge).into_bytes(), "control points along u exceed the cap"),
        ("IGES K1 not a number", igs.replace(&p1, &p1_text).into_bytes(), "\"six\" is not a number (expected K1"),
        ("IGES P pointer past the end", igs.replace(&d1, &d1_ptr).into_bytes(), "parameter data at P 999"),
        ("IGES T counts wrong", igs.replace("D      2P", "D      3P").into_bytes(), "the record count of each section"),
        ("STEP cut", cut(&stp, 0.6), "is the file truncated"),
        ("STEP missing point", stp.replacen(&pole_def, "#99999=CARTESIAN_POINT", 1).into_bytes(), "names no instance"),
        (
            "STEP non-numeric",
            stp.replacen("RATIONAL_B_SPLINE_SURFACE(((0.55,", "RATIONAL_B_SPLINE_SURFACE((('w',", 1).into_bytes(),
            "a real weight",
        ),
        (
            "STEP wrong multiplicities",
            stp.replacen("B_SPLINE_SURFACE_WITH_KNOTS((4,", "B_SPLINE_SURFACE_WITH_KNOTS((5,", 1).into_bytes(),
            "the multiplicities summing to",
        ),
        (
            "STEP huge multiplicity",
            stp.replacen("B_SPLINE_SURFACE_WITH_KNOTS((4,", "B_SPLINE_SURFACE_WITH_KNOTS((4000000000000,", 1)
                .into_bytes(),
            "the multiplicity",
        ),
        ("STEP unclosed string", stp.replacen("'hull'", "'hull", 1).into_bytes(), "expected"),
        ("STEP duplicate instance", stp.replacen("#2=", "#1=", 1).into_bytes(), "#1 defined twice"),
        (
            "STEP point of a wrong type",
            stp.replacen(&pole_def, &format!("{pole}=DIRECTION"), 1).into_bytes(),
            "a CARTESIAN_POINT(name, (x, y, z))",
        ),
    ]
}

#[test]
fn bad_files_are_refused_at_their_place() {
    for (what, bytes, needle) in bad_files() {
        let result = std::panic::catch_unwind(|| parse_cad_surfaces(&bytes, "bad.cad", None));
        let message = match result {
            Ok(Err(e)) => e.to_string(),
            Ok(Ok(r)) => panic!("{what}: read {} surfaces, expected an error", r.surfaces.len()),
            Err(_) => panic!("{what}: panicked"),
        };
        eprintln!("{what}: {message}");
        assert!(message.contains(needle), "{what}: {message}\n(expected it to say {needle:?})");
        let place =
            message.strip_prefix("bad.cad:").and_then(|r| r.split(':').next()).and_then(|n| n.parse::<usize>().ok());
        assert!(place.is_some() || message.contains("exceed the cap"), "{what}: no line in {message}");
    }
}

/// A STEP file whose unit chain loops: refused, naming the cycle.
#[test]
fn cyclic_unit_references_in_step_are_refused() {
    let stp = String::from_utf8(step(&rational_bicubic(), Units::Foot)).expect("ASCII");
    // The foot is a measure of the metre; make the measure's unit the foot itself.
    let conv = stp.lines().find(|l| l.contains("CONVERSION_BASED_UNIT('FOOT',")).expect("the foot").to_string();
    let foot_id = conv.split('=').next().expect("#n").to_string();
    let measure = stp
        .lines()
        .find(|l| l.contains("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(0.3048),"))
        .expect("measure")
        .to_string();
    let looped = format!("{}{foot_id});", &measure[..measure.rfind(',').expect(",") + 1]);
    let e = parse_cad_surfaces(stp.replace(&measure, &looped).as_bytes(), "loop.stp", None).expect_err("a cycle");
    let m = e.to_string();
    assert!(
        m.starts_with("loop.stp:") && m.contains("a cycle of unit references") && m.contains(&format!("{foot_id} -> ")),
        "{m}"
    );
}

#[test]
fn read_cad_surfaces_names_a_missing_file_and_dispatches_by_extension() {
    let dir = tempfile::tempdir().expect("temp dir");
    let e = read_cad_surfaces(&dir.path().join("none.igs"), None).expect_err("missing");
    assert!(e.to_string().contains("none.igs"), "{e}");
    // Content that is neither format: the extension picks the reader, which names the problem.
    let odd = dir.path().join("odd.stp");
    std::fs::write(&odd, "HEADER;\n").expect("write");
    let e = read_cad_surfaces(&odd, None).expect_err("not STEP");
    assert!(e.to_string().contains("no ISO-10303-21; at the start"), "{e}");
    assert!(Path::new("x.IGES").extension().is_some());
}
