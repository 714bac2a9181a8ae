//! The sections CSV: one row per point.
//!
//! The rest of this module's documentation is on [`parse_sections_csv`], where the library's users read it.

use std::collections::HashMap;
use std::io::{self, Write};

use nurbs::Vec3;

use super::{parse_number, records};
use crate::error::{HullError, InputErrorKind, Location};
use crate::float::Notation;
use crate::offsets::{Offsets, Section};
use crate::units::Units;

/// The header, field by field.
const HEADER: [&str; 4] = ["section", "x", "y", "z"];
const LAYOUT: &str = "section,x,y,z";

/// Parses a sections CSV held in `text`; `source` names it in messages (a path, `<stdin>`).
///
/// ```text
/// section,x,y,z
/// 0,0,0,0
/// 0,0,1.2,0.4
/// ...
/// 1,5,0,0
/// ```
///
/// - Header `section,x,y,z` (case-insensitive, fields trimmed): `section` first, then `x`, `y`
///   and `z` in any order, each name possibly with its unit (`x_m`, `y [mm]`, `z (ft)`: the
///   sense checks warn when that unit is not the one read in).
/// - Each row is a point `(x, y, z)` of the section named in the first field (any text or
///   number). The rows of a section are consecutive and in order along it (keel to deck);
///   sections follow each other along the length. A label that comes back after another
///   section started is an error.
/// - Blank lines and `#` comment lines are allowed anywhere (see [`crate::read_offsets`]).
///
/// [`write_sections_csv`] writes this layout (for `hullskin slice` and `hullskin digitize`),
/// quoting labels as RFC 4180 says and as the reader needs.
///
/// # Errors
///
/// [`HullError::Input`] at `source:line:column` for: binary text, an empty input
/// ([`InputErrorKind::Empty`]), a wrong header ([`InputErrorKind::BadHeader`],
/// [`InputErrorKind::FieldCount`]), no data rows, a row without 4 fields, an empty label or
/// coordinate, a coordinate that is not a finite decimal number (`nan`, `inf` and decimal
/// commas refused), and a section whose rows are not consecutive
/// ([`InputErrorKind::NonConsecutiveSection`]).
pub fn parse_sections_csv(text: &str, source: &str, units: Units) -> Result<Offsets, HullError> {
    let recs = records(text, source)?;
    let Some((header, rows)) = recs.split_first() else {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    };
    let columns = check_header(header, source)?;
    if rows.is_empty() {
        return Err(HullError::input(
            Location::line(source, header.line),
            InputErrorKind::NoRows { expected: format!("one row per point: {LAYOUT}") },
        ));
    }

    let mut sections: Vec<Section> = Vec::new();
    let mut index_of: HashMap<String, usize> = HashMap::new();
    for row in rows {
        let got = row.significant_len();
        if got > HEADER.len() {
            return Err(HullError::input(
                row.at(source, HEADER.len() + 1),
                InputErrorKind::FieldCount { got, expected: HEADER.len(), layout: LAYOUT.into() },
            ));
        }
        let label = row.fields[0].text.as_ref();
        if label.is_empty() {
            return Err(HullError::input(
                row.at(source, 1),
                InputErrorKind::EmptyField { expected: "a section label (any text or number)".into() },
            ));
        }
        let mut coord = [0.0; 3];
        for (k, c) in coord.iter_mut().enumerate() {
            let col = columns[k] + 1;
            let expected = || format!("the {} coordinate in {}", HEADER[k + 1], units.plural_name());
            match row.fields.get(col - 1) {
                Some(f) => *c = parse_number(&f.text, || row.at(source, col), expected)?,
                None => {
                    return Err(HullError::input(
                        row.at(source, col),
                        InputErrorKind::FieldCount { got, expected: HEADER.len(), layout: LAYOUT.into() },
                    ))
                }
            }
        }
        let point = Vec3::from_array(coord);
        match sections.last_mut() {
            Some(s) if s.label == label => {
                s.points.push(point);
                s.lines.push(row.line);
            }
            _ => {
                if let Some(&i) = index_of.get(label) {
                    let previous_line = sections[i].lines.last().copied().unwrap_or(row.line);
                    return Err(HullError::input(
                        row.at(source, 1),
                        InputErrorKind::NonConsecutiveSection { label: label.to_string(), previous_line },
                    ));
                }
                index_of.insert(label.to_string(), sections.len());
                sections.push(Section {
                    label: label.to_string(),
                    points: vec![point],
                    lines: vec![row.line],
                    column: None,
                });
            }
        }
    }
    Ok(Offsets::new(source, units, sections))
}

/// The base of a column name: lower case, without a unit after `_`, a blank, `[` or `(`.
pub(super) fn base_name(name: &str) -> String {
    let n = name.trim().to_ascii_lowercase();
    n.split(['_', ' ', '[', '(']).next().unwrap_or_default().to_string()
}

/// The header must read `section` then `x`, `y`, `z` in any order; returns the 0-based field
/// of x, y and z.
fn check_header(header: &super::Record<'_>, source: &str) -> Result<[usize; 3], HullError> {
    let got = header.significant_len();
    let mut columns = [usize::MAX; 3];
    for k in 0..HEADER.len() {
        let Some(f) = header.fields.get(k).filter(|f| !f.text.is_empty() || k < got) else {
            return Err(HullError::input(
                header.at(source, k + 1),
                InputErrorKind::FieldCount { got, expected: HEADER.len(), layout: LAYOUT.into() },
            ));
        };
        let name = base_name(&f.text);
        let slot = HEADER[1..].iter().position(|h| *h == name);
        let ok = match (k, slot) {
            (0, _) => name == HEADER[0],
            (_, Some(c)) => columns[c] == usize::MAX,
            (_, None) => false,
        };
        if !ok {
            // What this field should be: the canonical name, or the one still missing.
            let missing = (0..3).find(|&c| {
                columns[c] == usize::MAX
                    && !header.fields[k..got.min(HEADER.len())].iter().any(|g| base_name(&g.text) == HEADER[c + 1])
            });
            let expected = if k == 0 { HEADER[0] } else { missing.map_or(HEADER[k], |c| HEADER[c + 1]) };
            return Err(HullError::input(
                header.at(source, k + 1),
                InputErrorKind::BadHeader { got: f.text.to_string(), expected: expected.into() },
            ));
        }
        if let Some(c) = slot.filter(|_| k > 0) {
            columns[c] = k;
        }
    }
    if got > HEADER.len() {
        return Err(HullError::input(
            header.at(source, HEADER.len() + 1),
            InputErrorKind::FieldCount { got, expected: HEADER.len(), layout: LAYOUT.into() },
        ));
    }
    Ok(columns)
}

/// Writes `offsets` as a sections CSV: the header `section,x,y,z`, then one row per point,
/// sections in order, numbers in `notation` (both read back to the same `f64`, so the file
/// reads back exactly). The label is quoted, its quotes doubled, when it holds a comma, a
/// quote or a line break (RFC 4180), a leading `#`, surrounding spaces, or nothing.
///
/// # Errors
/// Any error of `w`; [`io::ErrorKind::InvalidData`] for a non-finite coordinate.
pub fn write_sections_csv<W: Write + ?Sized>(w: &mut W, offsets: &Offsets, notation: Notation) -> io::Result<()> {
    writeln!(w, "{LAYOUT}")?;
    for s in &offsets.sections {
        let label = csv_field(&s.label);
        for p in &s.points {
            let [x, y, z] = [p.x, p.y, p.z].map(|v| notation.format(v));
            writeln!(w, "{label},{},{},{}", x?, y?, z?)?;
        }
    }
    Ok(())
}

/// A CSV field: quoted, its quotes doubled, when it holds a comma, a quote or a line break
/// (RFC 4180, section 2), and also when the reader would otherwise not read it back: a
/// leading `#` (a comment line), surrounding spaces (trimmed) or nothing at all (an empty
/// label).
fn csv_field(s: &str) -> String {
    if s.contains([',', '"', '\n', '\r']) || s.starts_with('#') || s.trim() != s || s.is_empty() {
        format!("\"{}\"", s.replace('"', "\"\""))
    } else {
        s.to_string()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Labels that need quoting and numbers without a short decimal form read back exactly.
    #[test]
    fn round_trip_through_the_reader() {
        let o = Offsets {
            source: "t".into(),
            units: Units::Metre,
            perpendiculars: None,
            sections: vec![
                Section::new(
                    "ST, \"0\"",
                    vec![Vec3::new(0.1 + 0.2, 0.0, -0.0), Vec3::new(0.1 + 0.2, 1.0 / 3.0, 2.5e-7)],
                ),
                Section::new("#5", vec![Vec3::new(12.0, 1e-30, 0.0), Vec3::new(12.0, 2.0, 1e21)]),
            ],
        };
        let mut out = Vec::new();
        write_sections_csv(&mut out, &o, Notation::Plain).expect("writes");
        let text = String::from_utf8(out).expect("UTF-8");
        assert!(text.starts_with("section,x,y,z\n\"ST, \"\"0\"\"\",0.30000000000000004,0,0\n"), "{text}");
        let back = parse_sections_csv(&text, "t", Units::Metre).expect("reads back");
        assert_eq!(back.sections.len(), 2);
        for (a, b) in back.sections.iter().zip(&o.sections) {
            assert_eq!(a.label, b.label);
            assert_eq!(a.points, b.points);
        }
        let bad = Offsets { sections: vec![Section::new("a", vec![Vec3::new(f64::NAN, 0.0, 0.0)])], ..o };
        let e = write_sections_csv(&mut Vec::new(), &bad, Notation::Plain).expect_err("NaN");
        assert_eq!(e.kind(), io::ErrorKind::InvalidData);
    }

    fn parse(text: &str) -> Result<Offsets, HullError> {
        parse_sections_csv(text, "hull.csv", Units::Metre)
    }

    fn err(text: &str) -> String {
        parse(text).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    const GOOD: &str = "section,x,y,z\nA,0,0,0\nA,0,1,0.5\n\n# next\nB,2.5,0,0\nB,2.5,1.5,1\n";

    #[test]
    fn columns_are_found_by_name_in_any_order_with_their_units() {
        let reordered = "Section,z,Y_m,x [m]\nA,0,0,0\nA,0.5,1,0\n\n# next\nB,0,0,2.5\nB,1,1.5,2.5\n";
        let (a, b) = (parse(GOOD).expect("valid"), parse(reordered).expect("valid"));
        assert_eq!(a.sections, b.sections);
        assert!(
            err("section,x,x,z\nA,0,0,0\n").contains("\"x\" (expected \"y\""),
            "{}",
            err("section,x,x,z\nA,0,0,0\n")
        );
        assert!(err("label,x,y,z\nA,0,0,0\n").contains("expected \"section\""));
    }

    #[test]
    fn groups_consecutive_rows_into_sections_with_their_lines() {
        let o = parse(GOOD).expect("valid");
        assert_eq!(o.source, "hull.csv");
        assert_eq!(o.units, Units::Metre);
        let labels: Vec<&str> = o.sections.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["A", "B"]);
        assert_eq!(o.sections[0].points, vec![Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.5)]);
        assert_eq!(o.sections[1].points, vec![Vec3::new(2.5, 0.0, 0.0), Vec3::new(2.5, 1.5, 1.0)]);
        assert_eq!(o.sections[0].lines, vec![2, 3]);
        assert_eq!(o.sections[1].lines, vec![6, 7]);
        assert_eq!(o.sections[1].column, None);
    }

    #[test]
    fn bom_crlf_spaces_quotes_and_header_case_are_accepted() {
        let text = "\u{FEFF} Section , X ,Y,Z\r\n\"A\", 0 ,0,0\r\nA,0,1,0.5\r\n\r\nB,2.5,0,0,,\r\nB,2.5,1.5,1";
        let o = parse(text).expect("valid");
        let want = parse(GOOD).expect("valid");
        assert_eq!(
            o.sections.iter().map(|s| &s.points).collect::<Vec<_>>(),
            want.sections.iter().map(|s| &s.points).collect::<Vec<_>>()
        );
        assert_eq!(o.sections[1].lines, vec![5, 6]);
    }

    #[test]
    fn units_are_carried_and_worded_in_messages() {
        let o = parse_sections_csv(GOOD, "h", Units::Foot).expect("valid");
        assert_eq!(o.units, Units::Foot);
        let e = parse_sections_csv("section,x,y,z\nA,0,abc,0\n", "h", Units::Millimetre).err().map(|e| e.to_string());
        assert_eq!(e.as_deref(), Some("h:2:3: \"abc\" is not a number (expected the y coordinate in millimetres)"));
    }

    #[test]
    fn empty_input() {
        let want = "hull.csv: no data: the file is empty or holds only blank and comment lines";
        for text in ["", "\u{FEFF}", "\n\n", "# only a comment\r\n", ",,,\n"] {
            assert!(err(text).starts_with(want), "{text:?}: {}", err(text));
        }
    }

    #[test]
    fn header_problems() {
        assert_eq!(
            err("section,x,w,z\n"),
            "hull.csv:1:3: header field \"w\" (expected \"y\": a sections CSV starts with the header section,x,y,z)"
        );
        assert_eq!(err("section,x,y\nA,0,0\n"), "hull.csv:1:4: row has 3 fields (expected 4: section,x,y,z)");
        assert!(err("section,x,y,z,w\n").starts_with("hull.csv:1:5: row has 5 fields (expected 4"));
        assert_eq!(
            err("section,x,y,z\n# nothing\n"),
            "hull.csv:1: no data rows after the header (expected one row per point: section,x,y,z)"
        );
    }

    #[test]
    fn field_counts() {
        assert_eq!(err("section,x,y,z\nA,0,0\n"), "hull.csv:2:4: row has 3 fields (expected 4: section,x,y,z)");
        assert_eq!(
            err("section,x,y,z\nA,0,0,0\nA,1,5,2,5,3,5\n"),
            "hull.csv:3:5: row has 7 fields (expected 4: section,x,y,z); numbers with decimal commas split into extra fields: use decimal points"
        );
        // Trailing empty fields carry nothing and are accepted.
        assert!(parse("section,x,y,z,,\nA,0,0,0,\nA,0,1,1,,,\nB,1,0,0\nB,1,1,1\n").is_ok());
    }

    #[test]
    fn empty_fields() {
        assert_eq!(err("section,x,y,z\nA,0,,0\n"), "hull.csv:2:3: empty field (expected the y coordinate in metres)");
        assert_eq!(err("section,x,y,z\nA,0,0,\n"), "hull.csv:2:4: empty field (expected the z coordinate in metres)");
        assert_eq!(
            err("section,x,y,z\n,0,0,0\n"),
            "hull.csv:2:1: empty field (expected a section label (any text or number))"
        );
    }

    #[test]
    fn numbers_must_be_finite_decimals() {
        assert_eq!(
            err("section,x,y,z\nA,0,0,0\n\nA,1,abc,0\n"),
            "hull.csv:4:3: \"abc\" is not a number (expected the y coordinate in metres)"
        );
        for bad in ["nan", "NaN", "inf", "-inf", "infinity", "1e400"] {
            assert_eq!(
                err(&format!("section,x,y,z\nA,{bad},0,0\n")),
                format!("hull.csv:2:2: \"{bad}\" is not a finite number (expected the x coordinate in metres)")
            );
        }
        assert_eq!(
            err("section,x,y,z\nA,0,\"1,5\",0\n"),
            "hull.csv:2:3: \"1,5\" has a decimal comma (expected the y coordinate in metres, written with a decimal point)"
        );
    }

    #[test]
    fn a_section_must_not_come_back() {
        assert_eq!(
            err("section,x,y,z\nA,0,0,0\nA,0,1,1\nB,1,0,0\nA,2,0,0\n"),
            "hull.csv:5:1: section \"A\" appears again; its earlier rows end on line 3 (expected the rows of each \
             section together, one section after another along the length)"
        );
    }

    #[test]
    fn numeric_labels_are_text() {
        let o = parse("section,x,y,z\n1,0,0,0\n1.0,1,0,0\n").expect("valid");
        assert_eq!(o.sections.len(), 2, "labels are compared as written");
    }

    #[test]
    fn the_example_file_parses_and_validates() {
        let text = include_str!("../../../../testdata/sections_example.csv");
        let o = parse_sections_csv(text, "sections_example.csv", Units::Metre).expect("valid example");
        assert_eq!(o.sections.len(), 3);
        assert!(o.sections.iter().all(|s| s.points.len() == 4));
        assert!(o.validate(4).is_ok());
        // Every point of a section lies at its station's x (the example is station data).
        for s in &o.sections {
            assert!(s.points.iter().all(|p| p.x == s.points[0].x), "{}", s.label);
        }
    }
}
