//! The sense checks on real tables: the clean tables of `testdata/` give no warning and the
//! same offsets as before, and plausible mistakes made in them (units, transposition, one
//! cell typed wrong) are each caught at the right file, line and field.

use crate::common::tables::TABLES;

use hull::{parse_offsets_with, OutlierPolicy, ReadOptions, SenseKind, SenseWarning, Units};

use crate::common::testdata;

fn read_text(name: &str) -> String {
    std::fs::read_to_string(testdata(name)).unwrap_or_else(|e| panic!("{name}: {e}"))
}

fn warnings(text: &str, source: &str, options: &ReadOptions) -> Vec<SenseWarning> {
    parse_offsets_with(text, source, options).unwrap_or_else(|e| panic!("{source}: {e}")).warnings
}

#[test]
fn clean_tables_give_no_warning() {
    for name in TABLES {
        let path = testdata(name);
        if !path.is_file() {
            panic!("{name} missing from testdata");
        }
        // The OpenHull table takes its station spacing from the principals.json beside it.
        let w =
            hull::read_offsets_with(&path, &ReadOptions::default()).unwrap_or_else(|e| panic!("{name}: {e}")).warnings;
        assert!(w.is_empty(), "{name}: {:#?}", w.iter().map(ToString::to_string).collect::<Vec<_>>());
    }
}

/// The offset table `text` with the cell at (row `line`, field `column`), 1-based, replaced.
fn with_cell(text: &str, line: usize, column: usize, value: &str) -> (String, String) {
    let mut lines: Vec<String> = text.lines().map(str::to_string).collect();
    let mut fields: Vec<String> = lines[line - 1].split(',').map(str::to_string).collect();
    let old = std::mem::replace(&mut fields[column - 1], value.to_string());
    lines[line - 1] = fields.join(",");
    (lines.join("\n") + "\n", old)
}

/// The largest half-breadth of an offset table.
fn y_max(text: &str) -> f64 {
    text.lines().skip(1).flat_map(|l| l.split(',').skip(1)).filter_map(|c| c.parse::<f64>().ok()).fold(0.0, f64::max)
}

fn outliers(w: &[SenseWarning]) -> Vec<String> {
    w.iter().filter(|w| w.kind == SenseKind::Outlier).map(|w| w.at.to_string()).collect()
}

#[test]
fn one_cell_typed_wrong_is_named_at_its_line_and_field() {
    // Series 60 Cb 0.60 and 0.80 offset tables (9 lines: header, 8 waterlines), the Wigley
    // table, Gunnerus: a shifted decimal point both ways and a lost or changed digit, in
    // cells over the body, the bilge and the ends' neighbours.
    let mut caught = 0;
    let mut tried = 0;
    for name in ["series60_cb060_offsets.csv", "series60_cb080_offsets.csv", "wigley_offsets.csv"] {
        let text = read_text(name);
        let n_lines = text.lines().count();
        let n_fields = text.lines().next().expect("a header").split(',').count();
        for line in 3..n_lines {
            for column in (3..n_fields).step_by(3) {
                let cell: f64 = text
                    .lines()
                    .nth(line - 1)
                    .expect("a line")
                    .split(',')
                    .nth(column - 1)
                    .expect("a cell")
                    .parse()
                    .expect("a number");
                // Typos that move the cell by more than twice the outlier share of the
                // largest half-breadth (the neighbours' predictions may be off by up to one
                // share on a clean table; a smaller slip is within the hull's own shape and
                // is not claimed).
                for typo in [cell * 10.0, cell / 10.0, (cell - 6.0).abs(), cell + 3.0] {
                    if (typo - cell).abs() <= 2.0 * hull::OUTLIER_SHARE * y_max(&text) {
                        continue;
                    }
                    let (bad, _) = with_cell(&text, line, column, &format!("{typo}"));
                    let w = warnings(&bad, name, &ReadOptions::default());
                    tried += 1;
                    let at = format!("{name}:{line}:{column}");
                    if outliers(&w) == [at.clone()] {
                        caught += 1;
                    } else {
                        println!("{at}: {cell} -> {typo}: {:?}", outliers(&w));
                    }
                }
            }
        }
    }
    println!("caught {caught} of {tried}");
    assert!(tried > 50, "{tried}");
    assert_eq!(caught, tried);
}

#[test]
fn the_issues_typos_are_caught_and_refused_on_request() {
    // Series 60 Cb 0.60, station x = 60.96 (field 14), the 1.0 WL (line 6): 8.13 read.
    let text = read_text("series60_cb060_offsets.csv");
    for typo in ["81.3", "0.813", "1.04"] {
        let (bad, old) = with_cell(&text, 6, 14, typo);
        let w = warnings(&bad, "s60.csv", &ReadOptions::default());
        assert_eq!(outliers(&w), ["s60.csv:6:14"], "{old} -> {typo}: {w:#?}");
        let m = &w.iter().find(|w| w.kind == SenseKind::Outlier).expect("an outlier").message;
        assert!(m.contains(&format!("half-breadth {typo} m")) && m.contains("--outliers keep"), "{m}");
        let refuse = ReadOptions { outliers: OutlierPolicy::Refuse, ..ReadOptions::default() };
        let err = parse_offsets_with(&bad, "s60.csv", &refuse).expect_err("refused").to_string();
        assert!(err.starts_with("s60.csv:6:14:"), "{err}");
        let keep = ReadOptions { outliers: OutlierPolicy::Keep, ..ReadOptions::default() };
        assert!(outliers(&warnings(&bad, "s60.csv", &keep)).is_empty());
    }
}

#[test]
fn a_typo_in_an_end_station_or_waterline_is_named_at_its_place() {
    let text = read_text("series60_cb060_offsets.csv");
    // The last waterline (line 9, 9.75 m) typed 97.5, and the FP's x (field 26, 121.92) typed
    // 1219.2: still in order, so the readers take them; the spacing gives them away.
    let n_fields = text.lines().next().expect("a header").split(',').count();
    let (z_typo, _) = with_cell(&text, 9, 1, "97.5");
    let w = warnings(&z_typo, "s60.csv", &ReadOptions::default());
    let spacing: Vec<String> = w.iter().filter(|w| w.kind == SenseKind::Spacing).map(|w| w.at.to_string()).collect();
    assert_eq!(spacing, ["s60.csv:9:1"], "{w:#?}");
    let (x_typo, _) = with_cell(&text, 1, n_fields, "1219.2");
    let w = warnings(&x_typo, "s60.csv", &ReadOptions::default());
    let spacing: Vec<&SenseWarning> = w.iter().filter(|w| w.kind == SenseKind::Spacing).collect();
    assert_eq!(spacing.len(), 1, "{w:#?}");
    // Its place: the header's field, where the x is written.
    assert_eq!(spacing[0].at.to_string(), format!("s60.csv:1:{n_fields}"), "{}", spacing[0]);
    assert!(spacing[0].message.contains("station 1219.2 at x = 1219"), "{}", spacing[0]);
}

#[test]
fn millimetres_and_transposed_tables_are_named() {
    // The sample table in millimetres, read as metres: a 121,920 m ship.
    let text = read_text("series60_cb060_offsets.csv");
    let mm: String = text
        .lines()
        .enumerate()
        .map(|(i, l)| {
            let f: Vec<String> = l
                .split(',')
                .enumerate()
                .map(|(j, c)| {
                    if i == 0 && j == 0 {
                        c.to_string()
                    } else {
                        format!("{}", c.parse::<f64>().expect("a number") * 1000.0)
                    }
                })
                .collect();
            f.join(",") + "\n"
        })
        .collect();
    let w = warnings(&mm, "mm.csv", &ReadOptions::default());
    let size: Vec<&SenseWarning> = w.iter().filter(|w| w.kind == SenseKind::Size).collect();
    assert_eq!(size.len(), 1, "{w:#?}");
    assert!(size[0].message.contains("121920 m long") && size[0].message.contains("--units mm"), "{}", size[0]);
    // Read in millimetres, the same table is a ship.
    let ok = ReadOptions { units: Units::Millimetre, ..ReadOptions::default() };
    assert!(warnings(&mm, "mm.csv", &ok).is_empty());

    // Transposed: waterlines across, stations down.
    let rows: Vec<Vec<&str>> = text.lines().map(|l| l.split(',').collect()).collect();
    let transposed: String =
        (0..rows[0].len()).map(|j| rows.iter().map(|r| r[j]).collect::<Vec<_>>().join(",") + "\n").collect();
    let w = warnings(&transposed, "t.csv", &ReadOptions::default());
    assert!(w.iter().any(|w| w.kind == SenseKind::Transposed && w.message.contains("transposed")), "{w:#?}");

    // A long CSV header naming millimetres, read in metres.
    let long = "x_mm,halfbreadth_mm,z_mm\n0,0,0\n0,1000,1000\n0,2000,2000\n5000,0,0\n5000,1500,1000\n5000,2500,2000\n";
    let w = warnings(long, "long.csv", &ReadOptions::default());
    let named: Vec<String> =
        w.iter().filter(|w| w.kind == SenseKind::UnitsInHeader).map(|w| w.at.to_string()).collect();
    assert_eq!(named, ["long.csv:1:1", "long.csv:1:2", "long.csv:1:3"], "{w:#?}");
    assert!(w[0].message.contains("--units mm"), "{}", w[0]);
    assert!(warnings(long, "long.csv", &ok).is_empty());
}
