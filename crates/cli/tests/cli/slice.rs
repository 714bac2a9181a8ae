//! `hullskin slice` end to end: a mesh sliced into a sections CSV that `fit` reads, the mesh's
//! hydrostatics, the fitted surface checked against the mesh, and bad meshes refused with the
//! place of the problem.

use std::fs;

use crate::common::*;

/// The OpenFOAM Wigley mesh (testdata/mesh/wigley.stl.gz): L = 1 m, B = 0.1 m, T = 0.0625 m,
/// x from -L/2, z = 0 at the waterline; shifted to x from the aft end and z from the keel.
const SHIFT: &str = "0.5,0,0.0625";
const T: f64 = 0.0625;

/// The number in `text` right after `label` (up to the next space, comma or parenthesis).
fn number_after(text: &str, label: &str) -> f64 {
    let start = text.find(label).unwrap_or_else(|| panic!("no `{label}` in:\n{text}")) + label.len();
    let rest = text[start..].trim_start();
    let end = rest.find([' ', ',', ')', '\n']).unwrap_or(rest.len());
    rest[..end].parse().unwrap_or_else(|_| panic!("not a number after `{label}`: {rest}"))
}

/// The percentage in parentheses after `label`: `label 1.23 (+0.012 %)`.
fn percent_after(text: &str, label: &str) -> f64 {
    let start = text.find(label).unwrap_or_else(|| panic!("no `{label}` in:\n{text}"));
    let open = start + text[start..].find('(').expect("a percentage");
    number_after(text, &text[start..=open])
}

#[test]
fn slice_writes_sections_that_fit_reads_and_the_fit_checks_against_the_mesh() {
    let dir = temp_dir();
    let mesh = testdata("mesh/wigley.stl.gz");
    let mesh = mesh.to_str().expect("utf-8 path");
    let args = ["slice", mesh, "--shift", SHIFT, "--stations", "21", "--points", "12", "--draft", "0.0625"];
    let o = hullskin(dir.path(), &[&args[..], &["-o", "sections.csv"]].concat());
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    assert!(out.contains("12896 triangles, 6645 vertices"), "{out}");
    // The mesh's own volume at T: (4/9) L B T = 0.0027778 less its faceting (-0.32 %).
    let v_mesh = number_after(&out, "volume");
    assert!((v_mesh / (4.0 / 9.0 * 0.1 * T) - 1.0).abs() < 0.0065, "{v_mesh}");

    // The CSV: header, 21 sections of 12 points, each keel (y = 0) to the top, at one x.
    let csv = fs::read_to_string(dir.path().join("sections.csv")).expect("written");
    let mut lines = csv.lines();
    assert_eq!(lines.next(), Some("section,x,y,z"));
    let rows: Vec<(String, [f64; 3])> = lines
        .map(|l| {
            let f: Vec<&str> = l.split(',').collect();
            (f[0].to_string(), [f[1], f[2], f[3]].map(|v| v.parse().expect("number")))
        })
        .collect();
    assert_eq!(rows.len(), 21 * 12);
    for chunk in rows.chunks(12) {
        assert!(chunk.iter().all(|(label, p)| label == &chunk[0].0 && p[0] == chunk[0].1[0] && p[1] >= 0.0));
        assert_eq!(chunk[0].1[1], 0.0, "starts on the centre plane");
        assert!(chunk.windows(2).all(|w| w[1].1[2] > w[0].1[2]), "keel to top: z increases on a Wigley section");
    }

    let o = hullskin(dir.path(), &["fit", "sections.csv", "--method", "interp", "-o", "fit"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    let surface = dir.path().join("fit/surface.json");
    let o =
        hullskin(dir.path(), &[&args[..], &["-o", "again.csv", "--check", surface.to_str().expect("utf-8")]].concat());
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    // The same slicing writes the same bytes.
    assert_eq!(fs::read(dir.path().join("again.csv")).expect("written"), csv.as_bytes());
    // The surface through 21 x 12 sections of the mesh keeps its volume and wetted surface
    // within 0.1 % (measured +0.05 % and -0.05 %), and lies within 2 mm of every wetted vertex
    // (measured 1.3 mm at most, at the keel near the bow; L = 1 m).
    let check = &out[out.find("against the mesh").expect("the check block")..];
    for label in ["volume", "wetted surface"] {
        let pct = percent_after(check, label);
        assert!(pct.abs() < 0.1, "{label}: {pct} %\n{out}");
    }
    let max = number_after(check, "max");
    assert!(max > 0.0 && max < 2e-3, "{max}\n{out}");
    assert!(out.contains("wetted starboard mesh vertices"), "{out}");

    // --json: the same figures at full precision; the text rounds them to 5 digits.
    let text_out = out;
    let o = hullskin(
        dir.path(),
        &[&args[..], &["-o", "json.csv", "--check", surface.to_str().expect("utf-8"), "--json"]].concat(),
    );
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    let doc: serde_json::Value = serde_json::from_str(&out).expect("stdout is one JSON object");
    assert_eq!((doc["mesh"]["triangles"].as_u64(), doc["sections"].as_u64()), (Some(12896), Some(21)));
    let volume = doc["hydrostatics"]["volume"].as_f64().expect("volume");
    assert_eq!(number_after(&text_out, "volume"), hull::format_figure(volume).parse::<f64>().expect("a number"));
    assert_eq!(doc["check"]["distance"]["max"].as_f64().map(|m| format!("{m:.3e}")), Some(format!("{max:.3e}")));
    assert_eq!(fs::read(dir.path().join("json.csv")).expect("written"), csv.as_bytes());
}

#[test]
fn bad_meshes_are_refused_naming_the_file_and_the_place() {
    let dir = temp_dir();
    let mut binary = b"binary hull".to_vec();
    binary.resize(80, b' ');
    binary.extend(1000u32.to_le_bytes());
    binary.extend([0u8; 50]);
    fs::write(dir.path().join("short.stl"), &binary).expect("write");
    fs::write(dir.path().join("bad.obj"), "v 0 0 0\nv 1 0 0\nv 1 1 x\nf 1 2 3\n").expect("write");
    for (file, expected) in [
        ("short.stl", "short.stl: binary STL: the header (byte offset 80) claims 1000 triangles"),
        ("bad.obj", "bad.obj:3: \"x\" is not a number (expected the vertex z coordinate)"),
    ] {
        let o = hullskin(dir.path(), &["slice", file]);
        let (_, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{err}");
        assert!(err.contains(expected), "{err}");
        assert!(!dir.path().join("sections.csv").exists());
    }
    let o = hullskin(dir.path(), &["slice", "bad.obj", "--axes", "x,y"]);
    assert!(!o.status.success());
    assert!(text(&o).1.contains("each of x, y, z once"), "{}", text(&o).1);
}

#[test]
fn fit_and_hydrostatics_slice_a_mesh_input_with_the_mesh_flags() {
    let dir = temp_dir();
    let mesh = testdata("mesh/wigley.stl.gz");
    let mesh = mesh.to_str().expect("utf-8 path");
    let flags = ["--shift", SHIFT, "--stations", "15", "--spacing", "uniform", "--points", "10"];
    let o = hullskin(dir.path(), &[&["fit", mesh, "--method", "interp", "-o", "out"][..], &flags].concat());
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    let r = read_json(&dir.path().join("out/report.json"));
    assert_eq!((r["input"]["sections"].as_u64(), r["input"]["points"].as_u64()), (Some(15), Some(150)), "{r}");
    // The fit of a mesh is measured against the mesh: the distance of its starboard vertices
    // over the surface. Measured mean 5.5e-5 m: below 2e-4 m (0.2 % of the beam) bounds the
    // mesh's faceting plus 15 stations' interpolation error; the vertices left out (the stem
    // and keel edges, where the mesh normal turns) are a few per cent of the hull's.
    // (Read on the mesh line: the summary's held-out line has numbers and "m (" too.)
    let line = out.lines().find(|l| l.starts_with("mesh ")).unwrap_or_else(|| panic!("no mesh line in {out}"));
    let over = number_after(line, "starboard vertices over the surface: max");
    let mean = number_after(line, "m, mean");
    let count = number_after(line, "distance of");
    let left_out = number_after(line, "m (");
    assert!(over < 0.01 && mean < 2e-4 && count > 3000.0 && left_out < 0.05 * count, "{out}");
    // The same sections as `slice` writes: fitting its CSV gives the same surface, bit for bit.
    let o = hullskin(dir.path(), &[&["slice", mesh, "-o", "s.csv"][..], &flags].concat());
    assert!(o.status.success(), "{}", text(&o).1);
    let o = hullskin(dir.path(), &["fit", "s.csv", "--method", "interp", "-o", "csv"]);
    assert!(o.status.success(), "{}", text(&o).1);
    let surface = |d: &str| read_json(&dir.path().join(d).join("surface.json"));
    assert_eq!(surface("out")["control_points"], surface("csv")["control_points"]);
    // `hydrostatics` fits a mesh input too: the Wigley's volume at T within its faceting.
    let o =
        hullskin(dir.path(), &[&["hydrostatics", mesh, "--draft", "0.0625", "--format", "json"][..], &flags].concat());
    let (out, err) = text(&o);
    assert!(o.status.success(), "stdout {out}\nstderr {err}");
    let v: serde_json::Value = serde_json::from_str(&out).expect("json");
    let vol = v["rows"][0]["vol"].as_f64().unwrap_or_else(|| panic!("{v}"));
    assert!((vol / (4.0 / 9.0 * 0.1 * T) - 1.0).abs() < 0.0065, "{vol}");
}

/// `--at` gives the stations' positions: one section at each (it used to panic in the
/// argument parser), and hostile positions or point counts are refused with exit status 2.
#[test]
fn stations_at_given_positions_and_hostile_slicing_flags() {
    let dir = temp_dir();
    let mesh = testdata("mesh/wigley.stl.gz");
    let mesh = mesh.to_str().expect("utf-8 path");
    let o = hullskin(dir.path(), &["slice", mesh, "--shift", SHIFT, "--at", "0.2,0.5,0.8", "-o", "at.csv"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let csv = fs::read_to_string(dir.path().join("at.csv")).expect("read");
    let mut xs: Vec<String> = csv.lines().skip(1).filter_map(|l| l.split(',').nth(1).map(str::to_string)).collect();
    xs.dedup();
    assert_eq!(xs.len(), 3, "{csv}");
    for (x, want) in xs.iter().zip([0.2, 0.5, 0.8]) {
        let x: f64 = x.parse().expect("number");
        // A station plane's x is written as given (shortest round-trip float).
        assert_eq!(x, want, "{csv}");
    }
    for bad in [&["--at", "1e308,-1e308"][..], &["--at", "0.5,nan"], &["--points", "100000000"], &["--stations", "0"]] {
        let o = hullskin(dir.path(), &[&["slice", mesh, "-o", "bad.csv"][..], bad].concat());
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{bad:?}: {out}\n{err}");
        assert!(!err.contains("panicked") && err.contains("error:"), "{bad:?}: {err}");
    }
    assert!(!dir.path().join("bad.csv").exists());
}
