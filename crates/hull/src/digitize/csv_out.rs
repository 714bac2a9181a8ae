//! Writing offsets as a sections CSV (`section,x,y,z`, one row per point), the layout
//! [`crate::parse_sections_csv`] reads.

use std::io::{self, Write};

use crate::offsets::Offsets;

/// Write `offsets` as a sections CSV: the header `section,x,y,z`, then one row per point,
/// sections in order. Numbers are written in the shortest form that reads back to the same
/// `f64` (Rust's `Display`, never an exponent; `-0` as `0`), so the file reads back exactly.
/// A label holding a comma, a quote, a leading `#` or surrounding spaces is quoted, quotes
/// doubled.
///
/// # Errors
/// Any error of `w`; [`io::ErrorKind::InvalidData`] for a non-finite coordinate.
pub fn write_sections_csv<W: Write + ?Sized>(w: &mut W, offsets: &Offsets) -> io::Result<()> {
    writeln!(w, "section,x,y,z")?;
    for s in &offsets.sections {
        let label = csv_field(&s.label);
        for p in &s.points {
            writeln!(w, "{label},{},{},{}", num(p.x)?, num(p.y)?, num(p.z)?)?;
        }
    }
    Ok(())
}

fn num(x: f64) -> io::Result<String> {
    if !x.is_finite() {
        return Err(io::Error::new(io::ErrorKind::InvalidData, format!("cannot write the non-finite number {x}")));
    }
    Ok(if x == 0.0 { "0".to_string() } else { format!("{x}") })
}

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
    use crate::{parse_sections_csv, Section, Units};
    use nurbs::Vec3;

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
        write_sections_csv(&mut out, &o).expect("writes");
        let text = String::from_utf8(out).expect("UTF-8");
        assert!(text.starts_with("section,x,y,z\n\"ST, \"\"0\"\"\",0.30000000000000004,0,0\n"), "{text}");
        let back = parse_sections_csv(&text, "t", Units::Metre).expect("reads back");
        assert_eq!(back.sections.len(), 2);
        for (a, b) in back.sections.iter().zip(&o.sections) {
            assert_eq!(a.label, b.label);
            assert_eq!(a.points, b.points);
        }
        let bad = Offsets { sections: vec![Section::new("a", vec![Vec3::new(f64::NAN, 0.0, 0.0)])], ..o };
        assert_eq!(write_sections_csv(&mut Vec::new(), &bad).expect_err("NaN").kind(), io::ErrorKind::InvalidData);
    }
}
