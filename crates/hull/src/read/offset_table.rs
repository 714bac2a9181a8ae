//! The offset table: the naval architect's table of half-breadths.
//!
//! The rest of this module's documentation is on [`parse_offset_table`], where the library's users read it.

use nurbs::Vec3;

use super::{parse_number, records};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::{Offsets, Section};
use crate::units::Units;

/// Parses an offset table held in `text`; `source` names it in messages.
///
/// ```text
/// z\x,  0,   10,  20
/// 0,    0,   1.8, 0.2
/// 1,    0.5, 2.4, 1.1
/// 2,    1.0, 2.6,
/// ```
///
/// - First row: a corner cell (blank, or a label such as `z\x` or `wl`), then the station
///   positions x, strictly increasing or strictly decreasing from left to right.
/// - Then one row per waterline: its height z in the first column, strictly increasing or
///   strictly decreasing from top to bottom, then the half-breadth y >= 0 at each station.
///   An empty cell is a missing offset (the station does not reach that waterline, or it was
///   not measured).
///
/// Each station (column) becomes one [`Section`] labelled with the header cell as written, in
/// the column order; its points `(x_station, y, z)` run keel to deck (z ascending) and skip
/// the missing cells. Each point records the line of its cell, and the section its column, so
/// that [`crate::Offsets::validate`] can point at them.
///
/// # Errors
///
/// [`HullError::Input`] at `source:line:column` for: binary text, an empty input, a header
/// without stations ([`InputErrorKind::NoStations`]), no waterline rows, a station position,
/// waterline height or half-breadth that is not a finite decimal number, stations or
/// waterlines out of order ([`InputErrorKind::StationOrder`],
/// [`InputErrorKind::WaterlineOrder`]), a negative half-breadth, a cell right of the last
/// station ([`InputErrorKind::ExtraCell`]), and a station without any half-breadth
/// ([`InputErrorKind::EmptyStation`]).
pub fn parse_offset_table(text: &str, source: &str, units: Units) -> Result<Offsets, HullError> {
    let recs = records(text, source)?;
    let Some((header, rows)) = recs.split_first() else {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    };
    let unit = units.plural_name();

    // A corner cell is blank or a label: a number there means the header is missing.
    let corner = &header.fields[0].text;
    if corner.parse::<f64>().is_ok_and(f64::is_finite) {
        return Err(HullError::input(header.at(source, 1), InputErrorKind::MissingHeader { text: corner.to_string() }));
    }

    // Stations across the header.
    let n_cols = header.significant_len();
    if n_cols < 2 {
        return Err(HullError::input(header.at(source, 2), InputErrorKind::NoStations));
    }
    let mut sections: Vec<Section> = Vec::with_capacity(n_cols - 1);
    let mut xs: Vec<f64> = Vec::with_capacity(n_cols - 1);
    for f in &header.fields[1..n_cols] {
        let x = parse_number(
            &f.text,
            || header.at(source, f.column),
            || {
                format!("a station position x in {unit} (offset-table header; a sections CSV starts with the header section,x,y,z)")
            },
        )?;
        if let Some(increasing) = check_order(&xs, x) {
            let previous = xs[xs.len() - 1];
            return Err(HullError::input(
                header.at(source, f.column),
                InputErrorKind::StationOrder { x, previous, previous_column: f.column - 1, increasing },
            ));
        }
        xs.push(x);
        sections.push(Section {
            label: f.text.to_string(),
            points: Vec::new(),
            lines: Vec::new(),
            column: Some(f.column),
        });
    }
    if rows.is_empty() {
        return Err(HullError::input(
            Location::line(source, header.line),
            InputErrorKind::NoRows {
                expected: "one row per waterline: z, then the half-breadth at each station".into(),
            },
        ));
    }

    // Waterlines down the first column, half-breadths in the cells.
    let mut zs: Vec<f64> = Vec::with_capacity(rows.len());
    let mut z_lines: Vec<usize> = Vec::with_capacity(rows.len());
    for row in rows {
        let z = parse_number(
            &row.fields[0].text,
            || row.at(source, 1),
            || format!("the waterline height z in {unit} in the first column"),
        )?;
        if let Some(increasing) = check_order(&zs, z) {
            return Err(HullError::input(
                row.at(source, 1),
                InputErrorKind::WaterlineOrder {
                    z,
                    previous: zs[zs.len() - 1],
                    previous_line: z_lines[z_lines.len() - 1],
                    increasing,
                },
            ));
        }
        zs.push(z);
        z_lines.push(row.line);
        if row.significant_len() > n_cols {
            let extra = &row.fields[n_cols..];
            let cell = extra.iter().find(|f| !f.text.is_empty()).unwrap_or(&extra[0]);
            return Err(HullError::input(
                row.at(source, cell.column),
                InputErrorKind::ExtraCell { text: cell.text.to_string(), last_column: n_cols },
            ));
        }
        for (k, section) in sections.iter_mut().enumerate() {
            let Some(f) = row.fields.get(k + 1).filter(|f| !f.text.is_empty()) else { continue };
            let x = xs[k];
            let y = parse_number(
                &f.text,
                || row.at(source, f.column),
                || format!("the half-breadth y in {unit} at station x = {x}, waterline z = {z}, or an empty cell"),
            )?;
            if y < 0.0 {
                return Err(HullError::input(row.at(source, f.column), InputErrorKind::NegativeHalfBreadth { y }));
            }
            // `+ 0.0` turns a "-0" into +0.
            section.points.push(Vec3::new(x, y + 0.0, z));
            section.lines.push(row.line);
        }
    }

    // Keel to deck: z ascending along every section.
    let descending = zs.len() > 1 && zs[1] < zs[0];
    for (k, section) in sections.iter_mut().enumerate() {
        if section.points.is_empty() {
            return Err(HullError::input(header.at(source, k + 2), InputErrorKind::EmptyStation { x: xs[k] }));
        }
        if descending {
            section.points.reverse();
            section.lines.reverse();
        }
    }
    Ok(Offsets::new(source, units, sections))
}

/// Whether `next` continues the strictly monotone run `seen`, whose direction the first two
/// values set. Returns `None` when it does, `Some(increasing)` (the direction it breaks)
/// when it does not.
fn check_order(seen: &[f64], next: f64) -> Option<bool> {
    let last = *seen.last()?;
    let increasing = match seen {
        [a, b, ..] => b > a,
        _ => next >= last, // the second value sets the direction; only equality breaks it
    };
    let ok = if increasing { next > last } else { next < last };
    if ok {
        None
    } else {
        Some(increasing)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn parse(text: &str) -> Result<Offsets, HullError> {
        parse_offset_table(text, "table.csv", Units::Metre)
    }

    fn err(text: &str) -> String {
        parse(text).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    const GOOD: &str = "z\\x,0,10,20\n0,0,1.8,0.2\n1,0.5,2.4,1.1\n2,1.0,2.6,\n";

    #[test]
    fn one_section_per_station_keel_to_deck() {
        let o = parse(GOOD).expect("valid");
        assert_eq!(o.sections.len(), 3);
        let labels: Vec<&str> = o.sections.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["0", "10", "20"]);
        assert_eq!(
            o.sections[1].points,
            vec![Vec3::new(10.0, 1.8, 0.0), Vec3::new(10.0, 2.4, 1.0), Vec3::new(10.0, 2.6, 2.0)]
        );
        // The missing cell (station 20, z = 2) is skipped.
        assert_eq!(o.sections[2].points, vec![Vec3::new(20.0, 0.2, 0.0), Vec3::new(20.0, 1.1, 1.0)]);
        assert_eq!(o.sections[2].lines, vec![2, 3]);
        assert_eq!(o.sections.iter().map(|s| s.column).collect::<Vec<_>>(), vec![Some(2), Some(3), Some(4)]);
        assert!(o.validate(2).is_ok());
    }

    #[test]
    fn waterlines_listed_deck_first_still_give_keel_to_deck_sections() {
        let flipped = "wl,0,10,20\n2,1.0,2.6,\n1,0.5,2.4,1.1\n0,0,1.8,0.2\n";
        let a = parse(GOOD).expect("valid");
        let b = parse(flipped).expect("valid");
        for (sa, sb) in a.sections.iter().zip(&b.sections) {
            assert_eq!(sa.points, sb.points);
        }
        assert_eq!(b.sections[2].lines, vec![4, 3]);
    }

    #[test]
    fn stations_may_run_either_way_and_keep_their_order() {
        let o = parse(",20,10,0\n0,1,2,3\n1,1,2,3\n").expect("valid");
        let xs: Vec<f64> = o.sections.iter().map(|s| s.points[0].x).collect();
        assert_eq!(xs, vec![20.0, 10.0, 0.0]);
        assert!(o.validate(2).is_ok());
    }

    #[test]
    fn stations_out_of_order_name_both_columns() {
        assert_eq!(
            err("z\\x,0,10,5\n0,1,1,1\n"),
            "table.csv:1:4: station x = 5 is not greater than x = 10 in column 3 (expected station positions \
             strictly increasing from left to right, as set by the first two stations)"
        );
        assert!(err("z\\x,10,0,5\n0,1,1,1\n")
            .starts_with("table.csv:1:4: station x = 5 is not less than x = 0 in column 3"));
        assert!(
            err("z\\x,0,0\n0,1,1\n").starts_with("table.csv:1:3: station x = 0 is not greater than x = 0 in column 2")
        );
    }

    #[test]
    fn waterlines_out_of_order_name_both_lines() {
        assert_eq!(
            err("z\\x,0,10\n0,1,1\n2,1,1\n# gap\n1,1,1\n"),
            "table.csv:5:1: waterline z = 1 is not greater than z = 2 on line 3 (expected waterline heights \
             strictly increasing from top to bottom, as set by the first two waterlines)"
        );
        assert!(
            err("z\\x,0,10\n1,1,1\n1,1,1\n").starts_with("table.csv:3:1: waterline z = 1 is not greater than z = 1")
        );
    }

    #[test]
    fn bad_cells_are_located() {
        assert_eq!(
            err("z\\x,0,10\n0,1,1\n1,1,x1\n"),
            "table.csv:3:3: \"x1\" is not a number (expected the half-breadth y in metres at station x = 10, \
             waterline z = 1, or an empty cell)"
        );
        assert!(err("z\\x,0,10\n0,1,nan\n").starts_with("table.csv:2:3: \"nan\" is not a finite number"));
        assert!(err("z\\x,0,10\nwl1,1,1\n")
            .starts_with("table.csv:2:1: \"wl1\" is not a number (expected the waterline height z"));
        assert!(err("z\\x,0,10\n,1,1\n").starts_with("table.csv:2:1: empty field (expected the waterline height z"));
        assert_eq!(
            err("z\\x,0,abc\n0,1,1\n"),
            "table.csv:1:3: \"abc\" is not a number (expected a station position x in metres (offset-table header; \
             a sections CSV starts with the header section,x,y,z))"
        );
        assert!(err("z\\x,0,\"1,5\"\n0,1,1\n").starts_with("table.csv:1:3: \"1,5\" has a decimal comma"));
    }

    #[test]
    fn negative_half_breadths_are_refused() {
        assert_eq!(
            err("z\\x,0,10\n0,1,1\n1,-0.5,1\n"),
            "table.csv:3:2: half-breadth -0.5 is negative (expected a half-breadth y >= 0; leave the cell empty \
             where the station has no offset)"
        );
        let o = parse("z\\x,0,10\n0,-0,1\n1,1,1\n").expect("-0 is zero");
        assert!(o.sections[0].points[0].y.is_sign_positive());
    }

    #[test]
    fn a_missing_header_is_named() {
        let want = "table.csv:1:1: the first row starts with the number 1 (expected a header: section,x,y,z for a \
                    sections CSV, or for an offset table a corner cell such as z\\x, then the station positions)";
        // A sections CSV without its header...
        assert_eq!(err("1,0,0,0\n1,0,1,1\n"), want);
        // ...or an offset table without its corner cell.
        assert!(err("1,2,3\n0,1,1,1\n").starts_with("table.csv:1:1: the first row starts with the number 1"));
    }

    #[test]
    fn shape_problems() {
        assert!(err("z\\x\n0\n").starts_with("table.csv:1:2: offset table header has no station columns"));
        assert!(err("z\\x,0,10\n")
            .starts_with("table.csv:1: no data rows after the header (expected one row per waterline"));
        assert!(err("").starts_with("table.csv: no data"));
        assert!(
            err("z\\x,0,10\n0,1,1,,2\n").starts_with("table.csv:2:5: cell \"2\" lies beyond the last station column 3")
        );
        // A decimal comma splits the row: the message hints at it.
        assert!(err("z\\x,0,10\n0,1,5,1,5\n").contains("decimal commas"));
        assert_eq!(
            err("z\\x,0,10,20\n0,1,,1\n1,1,,1\n"),
            "table.csv:1:3: station x = 10 has no half-breadth in any waterline row (expected at least one cell in its column)"
        );
        // Trailing empty cells and short rows are missing offsets, not errors.
        let o = parse("z\\x,0,10,,\n0,1,1,,\n1,1\n").expect("valid");
        assert_eq!(o.sections.iter().map(|s| s.points.len()).collect::<Vec<_>>(), vec![2, 1]);
    }

    #[test]
    fn too_few_points_in_a_station_are_reported_at_its_cells() {
        let o = parse("z\\x,0,10\n0,1,\n1,1,\n2,1,2\n").expect("parses");
        let e = o.validate(2).err().map(|e| e.to_string()).unwrap_or_default();
        assert!(e.starts_with("table.csv:4:3: section \"10\" has 1 point(s) (expected at least 2"), "{e}");
    }

    #[test]
    fn bom_crlf_and_comments() {
        let o = parse("\u{FEFF}# lines plan\r\nz\\x,0,10,20\r\n0,0,1.8,0.2\r\n1,0.5,2.4,1.1\r\n2,1.0,2.6,\r\n")
            .expect("valid");
        assert_eq!(
            o.sections,
            parse(GOOD)
                .expect("valid")
                .sections
                .into_iter()
                .map(|mut s| {
                    s.lines.iter_mut().for_each(|l| *l += 1);
                    s
                })
                .collect::<Vec<_>>()
        );
    }

    #[test]
    fn the_example_file_parses_and_validates() {
        let text = include_str!("../../../../testdata/offsets_example.csv");
        let o = parse_offset_table(text, "offsets_example.csv", Units::Metre).expect("valid example");
        assert_eq!(o.sections.len(), 4);
        // 4 stations x 5 waterlines with one missing cell.
        assert_eq!(o.num_points(), 19);
        assert!(o.validate(4).is_ok());
        for s in &o.sections {
            assert!(s.points.windows(2).all(|w| w[1].z > w[0].z), "keel to deck in {}", s.label);
            assert!(s.points.iter().all(|p| p.y >= 0.0));
        }
    }
}
