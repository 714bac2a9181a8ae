//! The offsets readers of `hull` on the real data copied into `testdata/raw/` (provenance in
//! `testdata/README.md`): each must reproduce the converted tables the generators in
//! `testdata/` made from the same sources, point for point, and say what it left out.

use hull::{
    read_offsets, read_offsets_with, InputFormat, MainDimensions, Offsets, ReadOptions, ReadOutcome, SuspiciousPolicy,
    Units, View,
};
use nurbs::Vec3;

use crate::common::testdata;

fn read(name: &str, options: &ReadOptions) -> ReadOutcome {
    read_offsets_with(&testdata(name), options).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn table(name: &str) -> Offsets {
    read_offsets(&testdata(name), Units::Metre).unwrap_or_else(|e| panic!("{name}: {e}"))
}

/// The largest distance between corresponding points; panics (with the place) when the
/// sections or their point counts differ.
fn max_gap(got: &[&hull::Section], want: &[&hull::Section]) -> f64 {
    assert_eq!(got.len(), want.len(), "section count");
    let mut worst = 0.0f64;
    for (g, w) in got.iter().zip(want) {
        assert_eq!(g.points.len(), w.points.len(), "points of section {} (want {})", g.label, w.label);
        for (p, q) in g.points.iter().zip(&w.points) {
            worst = worst.max(p.distance(*q));
        }
    }
    worst
}

fn all(o: &Offsets) -> Vec<&hull::Section> {
    o.sections.iter().collect()
}

/// The Series 60 parents' particulars used by `testdata/gen_series60_parents.py` (Lpp 121.92 m,
/// L/B from Todd, B/T 2.5, both rounded to the centimetre; `testdata/README.md`).
const SERIES60: [(&str, &str, f64, f64); 5] = [
    ("cb0p6.csv", "series60_cb060_offsets.csv", 16.26, 6.50),
    ("cb0p65.csv", "series60_cb065_offsets.csv", 16.82, 6.73),
    ("cb0p7.csv", "series60_cb070_offsets.csv", 17.42, 6.97),
    ("cb0p75.csv", "series60_cb075_offsets.csv", 18.06, 7.22),
    ("cb0p8.csv", "series60_cb080_offsets.csv", 18.76, 7.50),
];

#[test]
fn series60_tables_reproduce_the_generated_offset_tables_point_for_point() {
    for (raw, want, beam, draft) in SERIES60 {
        let options =
            ReadOptions { dimensions: Some(MainDimensions { lpp: 121.92, beam, draft }), ..ReadOptions::default() };
        let o = read(&format!("raw/series60/{raw}"), &options);
        assert_eq!(o.format, InputFormat::Series60Table, "{raw}");
        let want = table(want);
        // The generator multiplies the three-decimal figures exactly (decimal arithmetic);
        // the reader does it in f64, two roundings of products of magnitude <= 122 m:
        // a few ulps, 1e-12 m is far above them and far below any real difference.
        let gap = max_gap(&all(&o.offsets), &all(&want));
        assert!(gap < 1e-12, "{raw}: max gap {gap:e} m");
        assert!(o.offsets.validate(4).is_ok(), "{raw}");
        assert!(o.axes.contains("(1 - station/20) Lpp"), "{}", o.axes);
        // Only the Cb 0.60 transcription has the typo.
        assert_eq!(o.suspicious.len(), usize::from(raw == "cb0p6.csv"), "{raw}: {:?}", o.suspicious);
    }
}

#[test]
fn the_cb060_typo_is_reported_at_its_place_and_the_default_particulars_are_noted() {
    let o = read("raw/series60/cb0p6.csv", &ReadOptions::default());
    let s = &o.suspicious[0];
    assert!(s.at.to_string().ends_with("cb0p6.csv:2:4"), "{}", s.at);
    assert_eq!((s.value, s.replacement), (10.0, Some(0.0)));
    assert!(s.what.contains("station 0") && s.what.contains("z/T = 0.25"), "{}", s.what);
    assert!(o.notes.iter().any(|n| n.contains("Cb 0.60 parent's Lpp 121.92")), "{:?}", o.notes);
    // Without particulars the Cb 0.60 ones are used: the sample table again.
    assert!(max_gap(&all(&o.offsets), &all(&table("series60_cb060_offsets.csv"))) < 1e-12);
    // Omitted instead: the FP station loses that one offset, nothing else changes.
    let omit =
        read("raw/series60/cb0p6.csv", &ReadOptions { suspicious: SuspiciousPolicy::Omit, ..ReadOptions::default() });
    assert_eq!(omit.offsets.num_points() + 1, o.offsets.num_points());
    let refuse = read_offsets_with(
        &testdata("raw/series60/cb0p6.csv"),
        &ReadOptions { suspicious: SuspiciousPolicy::Refuse, ..ReadOptions::default() },
    );
    let e = refuse.err().map(|e| e.to_string()).unwrap_or_default();
    assert!(
        e.ends_with(
            "cb0p6.csv:2:4: half-breadth fraction 10 at station 0, waterline z/T = 0.25 (expected \
        a fraction of the waterline's maximum half-breadth in [0, 1])"
        ),
        "{e}"
    );
}

/// The sections of `o` at the x of `want`'s sections (labels differ between the formats).
fn matching<'a>(o: &'a Offsets, want: &Offsets, tol: f64) -> Vec<&'a hull::Section> {
    want.sections
        .iter()
        .map(|w| {
            let x = w.points[0].x;
            o.sections
                .iter()
                .find(|s| (s.points[0].x - x).abs() <= tol)
                .unwrap_or_else(|| panic!("no section at x = {x}"))
        })
        .collect()
}

#[test]
fn gunnerus_long_csv_and_json_reproduce_the_generated_table() {
    let want = table("gunnerus_offsets.csv");
    let long = read("raw/gunnerus/gunnerus_offsets_long.csv", &ReadOptions::default());
    assert_eq!(long.format, InputFormat::LongCsv);
    // The generator left out the two stations beyond the stem with fewer than 4 cells (a
    // cubic needs 4); the reader keeps every station with an offset.
    assert_eq!(long.offsets.sections.len(), 64);
    let extra: Vec<(f64, usize)> = long
        .offsets
        .sections
        .iter()
        .filter(|s| !want.sections.iter().any(|w| w.points[0].x == s.points[0].x))
        .map(|s| (s.points[0].x, s.points.len()))
        .collect();
    assert_eq!(extra, vec![(35.96, 2), (36.25, 1)]);
    // Same decimal text on both sides: the same f64, exactly.
    assert_eq!(max_gap(&matching(&long.offsets, &want, 0.0), &all(&want)), 0.0);
    assert!(long.notes.iter().any(|n| n.contains("empty half-breadth")), "{:?}", long.notes);

    let json = read("raw/gunnerus/gunnerus.json", &ReadOptions::default());
    assert_eq!(json.format, InputFormat::JsonTable);
    assert_eq!(json.offsets.sections.len(), 64);
    // The long CSV holds the JSON's normalised figures times LOA, Depth, BOA/2 rounded to
    // 6 decimals: half a unit of the 6th decimal apart at most, plus round-off.
    let gap = max_gap(&matching(&json.offsets, &want, 1e-9), &all(&want));
    assert!(gap <= 5.0e-7 + 1e-12, "gap {gap:e}");
    assert!(gap > 0.0, "the rounding of the long CSV shows");
}

#[test]
fn cargo_long_csv_and_json_merge_the_views_as_the_generated_sections() {
    let want = table("cargo116_offsets.csv");
    let long = read("raw/cargo116/offsets_long.csv", &ReadOptions::default());
    assert_eq!(long.format, InputFormat::LongCsv);
    assert_eq!(max_gap(&all(&long.offsets), &all(&want)), 0.0, "same text, same floats");
    // The buttock points that contradict the waterlines (the provenance's stations 1-3):
    // each reported with its place, none averaged in.
    let found: Vec<(String, f64, f64)> =
        long.disagreements.iter().map(|d| (d.station.clone(), d.waterline_y, d.z)).collect();
    assert_eq!(
        found,
        vec![("1".into(), 3.0, 5.398), ("1".into(), 7.0, 7.997), ("2".into(), 5.0, 0.958), ("3".into(), 7.0, 4.472)]
    );
    assert!(long.disagreements.iter().all(|d| d.view == View::Buttock));
    // Station 1, buttock 3000 at z = 5.398: between the 5000WL (3.372) and 6000WL (4.556)
    // half-breadths, so 3.0 lies 0.372 outside.
    let d = &long.disagreements[0];
    assert!((d.body_plan_y - 3.372).abs() < 1e-12 && (d.difference - 0.372).abs() < 1e-12, "{d}");
    assert!(d.at.to_string().ends_with("offsets_long.csv:24"), "{}", d.at);
    // Above the main deck: noted, not compared.
    assert_eq!(long.notes.iter().filter(|n| n.contains("above the deck edge")).count(), 4, "{:?}", long.notes);

    let json = read("raw/cargo116/offsets_table.json", &ReadOptions::default());
    assert!(json.notes.iter().any(|n| n.contains("principals.json")), "{:?}", json.notes);
    // x = station x 5.4 (one rounding) against the long CSV's decimal x.
    assert!(max_gap(&all(&json.offsets), &all(&want)) < 1e-12);
    assert_eq!(json.disagreements.len(), 4);
    // With Lpp given, the spacing is Lpp / 20 whatever principals.json says.
    let lpp = read(
        "raw/cargo116/offsets_table.json",
        &ReadOptions {
            dimensions: Some(MainDimensions { lpp: 216.0, beam: 1.0, draft: 1.0 }),
            ..ReadOptions::default()
        },
    );
    assert!((lpp.offsets.sections[20].points[0].x - 216.0).abs() < 1e-12);
}

#[test]
fn an_openhull_table_without_principals_asks_for_lpp() {
    let dir = tempfile::tempdir().expect("temp dir");
    let path = dir.path().join("offsets_table.json");
    std::fs::copy(testdata("raw/cargo116/offsets_table.json"), &path).expect("copy");
    let e = read_offsets_with(&path, &ReadOptions::default()).err().map(|e| e.to_string()).unwrap_or_default();
    assert!(e.contains("an OpenHull table without a station spacing (expected a principals.json"), "{e}");
}

/// Shifts as `testdata/gen_matlab_offsets.py` does: x = 0 at the aft-most point, z = 0 at the
/// lowest, both shifts rounded to the millimetre.
fn shift_as_generated(o: &mut Offsets) {
    let (lo, _) = o.bounds().expect("points");
    let (x0, z0) = ((lo.x * 1000.0).round() / 1000.0, (lo.z * 1000.0).round() / 1000.0);
    for s in &mut o.sections {
        for p in &mut s.points {
            *p = Vec3::new(p.x - x0, p.y, p.z - z0);
        }
    }
}

#[test]
fn matlab_station_clouds_reproduce_the_generated_sections() {
    for (raw, want, dropped) in [
        ("raw/bspline3d/frigate_1Surface.dat", "matlab_frigate.csv", Some(("x2", 2))),
        ("raw/bspline3d/yatch_offset3.dat", "matlab_yacht.csv", None),
    ] {
        let mut o = read(raw, &ReadOptions::default());
        assert_eq!(o.format, InputFormat::PointCloud, "{raw}");
        assert!(o.axes.contains("origin as in the file"), "{}", o.axes);
        // The generator left out the frigate's stem head (2 points: fewer than a cubic needs).
        if let Some((label, n)) = dropped {
            let i = o.offsets.sections.iter().position(|s| s.label == label).expect("stem head");
            assert_eq!(o.offsets.sections.remove(i).points.len(), n);
        }
        shift_as_generated(&mut o.offsets);
        let want = table(want);
        let labels: Vec<&str> = o.offsets.sections.iter().map(|s| s.label.as_str()).collect();
        let want_labels: Vec<&str> = want.sections.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, want_labels, "{raw}");
        // The generator subtracts in decimal, the test in f64: one rounding of numbers < 100.
        let gap = max_gap(&all(&o.offsets), &all(&want));
        assert!(gap < 1e-12, "{raw}: gap {gap:e}");
    }
    let frigate = read("raw/bspline3d/frigate_1Surface.dat", &ReadOptions::default());
    assert!(frigate.notes.iter().any(|n| n.contains("sorted by height")), "{:?}", frigate.notes);
}

/// The Wigley hull of `gen_freeship_example.py`.
fn wigley(x: f64, z: f64) -> f64 {
    let xi = 2.0 * (x - 50.0) / 100.0;
    5.0 * (1.0 - xi * xi) * (1.0 - ((6.25 - z) / 6.25).powi(2))
}

#[test]
fn the_freeship_example_reads_as_the_wigley_hull_and_its_views_agree() {
    let o = read("freeship_wigley_offsets.txt", &ReadOptions { tolerance: Some(0.05), ..ReadOptions::default() });
    assert_eq!(o.format, InputFormat::FreeshipOffsets);
    let s = &o.offsets.sections;
    assert_eq!(
        s.iter().map(|s| s.label.as_str()).collect::<Vec<_>>(),
        ["10.000", "30.000", "50.000", "70.000", "90.000"]
    );
    for sec in s {
        assert_eq!(sec.points.len(), 11);
        assert!(sec.points.windows(2).all(|w| w[1].z > w[0].z), "keel to deck: {}", sec.label);
        for p in &sec.points {
            // Printed with 4 decimals: half a unit of the 4th.
            assert!((p.y - wigley(p.x, p.z)).abs() <= 5e-5 + 1e-12, "{} {p:?}", sec.label);
        }
    }
    // Buttocks and waterline cut at the stations agree with the stations within the chord
    // error of polylines 0.625 m and 5 m apart (a few cm), below the 5 cm tolerance.
    assert!(o.disagreements.is_empty(), "{:?}", o.disagreements);
    assert!(o.notes.iter().any(|n| n.contains("control curve")), "{:?}", o.notes);
    assert!(o.offsets.validate(4).is_ok());
}

#[test]
fn a_freeship_waterline_moved_off_the_body_plan_is_reported_point_by_point() {
    let text = std::fs::read_to_string(testdata("freeship_wigley_offsets.txt")).expect("example");
    // The waterline z = 2.5 at x = 50 moved out by 0.2 m.
    let good = format!("        {:10.4} {:10.4} {:10.4}", 50.0, wigley(50.0, 2.5), 2.5);
    assert_eq!(text.matches(&good).count(), 3, "twice in the waterline's two segments, once in station 50");
    let bad_line = format!("        {:10.4} {:10.4} {:10.4}", 50.0, wigley(50.0, 2.5) + 0.2, 2.5);
    let at = text.rfind(&good).expect("the second segment's point");
    let bad = format!("{}{}{}", &text[..at], bad_line, &text[at + good.len()..]);
    let o =
        hull::parse_offsets_with(&bad, "wigley.txt", &ReadOptions { tolerance: Some(0.05), ..ReadOptions::default() })
            .expect("valid");
    assert_eq!(o.disagreements.len(), 1, "{:?}", o.disagreements);
    let d = &o.disagreements[0];
    assert_eq!((d.station.as_str(), d.view, d.z), ("50.000", View::Waterline, 2.5));
    assert!((d.difference + 0.2).abs() < 1e-9, "{d}");
    let line = 1 + bad[..at].matches('\n').count();
    assert_eq!(d.at.to_string(), format!("wigley.txt:{line}"));
}

#[test]
fn the_freeship_curve_example_reads_three_sections() {
    let o = read("freeship_curves_example.txt", &ReadOptions::default());
    assert_eq!(o.format, InputFormat::FreeshipCurves);
    assert_eq!(o.offsets.sections.len(), 3);
    assert_eq!(o.offsets.sections[1].points[2], Vec3::new(5.0, 2.5, 1.0));
    assert!(o.offsets.validate(4).is_ok());
}

#[test]
fn every_format_reports_bad_input_with_file_line_and_column() {
    let dir = tempfile::tempdir().expect("temp dir");
    let cases: [(&str, &str, &str); 7] = [
        ("s60.csv", ",0,1\n0,0,0\n20,0,x\nMaxBm,1,1\n", ":3:3: \"x\" is not a number"),
        ("long.csv", "x,z,y\n0,0,0\n0,1,-2\n", ":3:3: half-breadth -2 is negative"),
        ("t.json", "{\"structure\": {\"hull\": {\"halfBreadths\": {}}}}", ": no LOA (expected LOA as a number)"),
        ("bad.json", "{\n  \"a\": [1,, 2]\n}", ":2:11: invalid JSON: expected value"),
        ("cloud.dat", "0 0 0\n0 1 1\n1 1\n", ":3:2: 2 numbers on a line"),
        ("fs.txt", "Station 1.000\n 1.0 2.0\n", ":2:2: \"1.0 2.0\""),
        ("curves.txt", "0\n0 0 0\n0 0 x\n", ":3:3: \"x\" is not a number"),
    ];
    for (name, text, needle) in cases {
        let path = dir.path().join(name);
        std::fs::write(&path, text).expect("write");
        let e = read_offsets(&path, Units::Metre).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into());
        assert!(e.starts_with(&path.display().to_string()), "{name}: {e}");
        assert!(e.contains(needle), "{name}: `{needle}` not in: {e}");
        assert!(e.contains("(expected"), "{name}: {e}");
    }
}

#[test]
fn gunnerus_sections_csv_gives_the_tables_sections() {
    // `gunnerus_sections.csv` holds the offset table's points as a sections CSV for the kernel's
    // skinning tests (which know no offset tables): read by hull, both give the same sections,
    // point for point and bit for bit (the same decimal text).
    let want = table("gunnerus_offsets.csv");
    let got = table("gunnerus_sections.csv");
    assert_eq!(max_gap(&all(&got), &all(&want)), 0.0);
}
