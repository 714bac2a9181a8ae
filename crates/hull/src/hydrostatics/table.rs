//! The hydrostatics table as text (aligned columns with units), CSV and JSON.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use super::HydrostaticsRow;
use crate::units::Units;

/// What a column measures, for its unit and its decimals.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Length,
    Area,
    Volume,
    Mass,
    Ratio,
}

/// The columns in order: JSON/CSV key (the FREE!ship column name in lower case), the header of
/// the text table.
pub const HYDROSTATICS_COLUMNS: [(&str, &str); 17] = [
    ("draft", "Draft"),
    ("lwl", "Lwl"),
    ("bwl", "Bwl"),
    ("vol", "Vol"),
    ("displ", "Displ"),
    ("lcb", "LCB"),
    ("vcb", "VCB"),
    ("cb", "CB"),
    ("am", "AM"),
    ("cm", "CM"),
    ("aw", "AW"),
    ("cw", "CW"),
    ("cp", "CP"),
    ("lcf", "LCF"),
    ("s", "S"),
    ("kmtrv", "KMtrv"),
    ("kmlong", "KMlong"),
];

const KINDS: [Kind; 17] = [
    Kind::Length,
    Kind::Length,
    Kind::Length,
    Kind::Volume,
    Kind::Mass,
    Kind::Length,
    Kind::Length,
    Kind::Ratio,
    Kind::Area,
    Kind::Ratio,
    Kind::Area,
    Kind::Ratio,
    Kind::Ratio,
    Kind::Length,
    Kind::Area,
    Kind::Length,
    Kind::Length,
];

impl HydrostaticsRow {
    /// The values in the order of [`HYDROSTATICS_COLUMNS`].
    pub fn values(&self) -> [f64; 17] {
        [
            self.draft,
            self.lwl,
            self.bwl,
            self.vol,
            self.displ,
            self.lcb,
            self.vcb,
            self.cb,
            self.am,
            self.cm,
            self.aw,
            self.cw,
            self.cp,
            self.lcf,
            self.s,
            self.kmtrv,
            self.kmlong,
        ]
    }
}

/// Rows with their units and the density used, ready to print or serialize.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HydrostaticsTable {
    /// Where the surface came from (a file name, or the sample's description).
    pub source: String,
    /// Length unit of the surface and of every length, area and volume.
    pub units: Units,
    /// Water density in t/m³ (displ is in tonnes).
    pub density: f64,
    /// One row per draft.
    pub rows: Vec<HydrostaticsRow>,
}

impl HydrostaticsTable {
    /// The unit label of each column: `m`, `m²`, `m³`, `t`, `-`.
    pub fn unit_labels(&self) -> [String; 17] {
        let u = self.units.symbol();
        KINDS.map(|k| match k {
            Kind::Length => u.to_string(),
            Kind::Area => format!("{u}²"),
            Kind::Volume => format!("{u}³"),
            Kind::Mass => "t".to_string(),
            Kind::Ratio => "-".to_string(),
        })
    }

    /// An aligned text table: a title line, the column names, their units in brackets, one
    /// line per draft. Lengths with 3 decimals, areas and volumes 2, coefficients 4.
    pub fn text(&self) -> String {
        let units = self.unit_labels();
        let cells: Vec<Vec<String>> = self
            .rows
            .iter()
            .map(|r| {
                r.values()
                    .iter()
                    .zip(KINDS)
                    .map(|(&v, k)| match k {
                        Kind::Length => format!("{v:.3}"),
                        Kind::Area | Kind::Volume | Kind::Mass => format!("{v:.2}"),
                        Kind::Ratio => format!("{v:.4}"),
                    })
                    .collect()
            })
            .collect();
        let widths: Vec<usize> = (0..17)
            .map(|c| {
                let head = HYDROSTATICS_COLUMNS[c].1.chars().count().max(units[c].chars().count() + 2);
                cells.iter().map(|r| r[c].chars().count()).fold(head, usize::max)
            })
            .collect();
        let mut out = String::new();
        let _ = writeln!(
            out,
            "hydrostatics of {} (both sides; density {} t/m³; AM at the middle of Lwl; CB = Vol/(Lwl Bwl T))",
            self.source, self.density
        );
        let line = |out: &mut String, items: &mut dyn Iterator<Item = String>| {
            let parts: Vec<String> = items.zip(&widths).map(|(s, &w)| format!("{s:>w$}")).collect();
            let _ = writeln!(out, "{}", parts.join("  "));
        };
        line(&mut out, &mut HYDROSTATICS_COLUMNS.iter().map(|c| c.1.to_string()));
        line(&mut out, &mut units.iter().map(|u| format!("[{u}]")));
        for r in &cells {
            line(&mut out, &mut r.iter().cloned());
        }
        out
    }

    /// CSV: the header of [`HYDROSTATICS_COLUMNS`] keys, then one line per draft, every number
    /// with the shortest digits that read back to the same `f64`.
    pub fn csv(&self) -> String {
        let mut out = HYDROSTATICS_COLUMNS.iter().map(|c| c.0).collect::<Vec<_>>().join(",");
        out.push('\n');
        for r in &self.rows {
            let vals: Vec<String> = r.values().iter().map(|v| format!("{v}")).collect();
            out.push_str(&vals.join(","));
            out.push('\n');
        }
        out
    }

    /// Pretty JSON: `{"source", "units", "density", "rows": [{"draft": .., ..}, ..]}`.
    pub fn json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a table of finite numbers and strings serializes");
        s.push('\n');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table() -> HydrostaticsTable {
        let row = |t: f64| HydrostaticsRow { draft: t, vol: 1000.0 * t, cb: 0.6, s: 12.5, ..Default::default() };
        HydrostaticsTable { source: "test".into(), units: Units::Foot, density: 1.025, rows: vec![row(1.0), row(2.5)] }
    }

    #[test]
    fn json_keys_are_the_column_names() {
        let v: serde_json::Value = serde_json::from_str(&table().json()).expect("valid JSON");
        let row = v["rows"][1].as_object().expect("a row object");
        let keys: Vec<&str> = row.keys().map(String::as_str).collect();
        let mut expected: Vec<&str> = HYDROSTATICS_COLUMNS.iter().map(|c| c.0).collect();
        expected.sort_unstable();
        let mut got = keys.clone();
        got.sort_unstable();
        assert_eq!(got, expected);
        assert_eq!(v["units"], "ft");
        assert_eq!(row["vol"], 2500.0);
        let back: HydrostaticsTable = serde_json::from_value(v).expect("reads back");
        assert_eq!(back, table());
    }

    #[test]
    fn csv_reads_back_exactly() {
        let t = table();
        let text = t.csv();
        let mut lines = text.lines();
        assert_eq!(lines.next(), Some(HYDROSTATICS_COLUMNS.map(|c| c.0).join(",").as_str()));
        for r in &t.rows {
            let vals: Vec<f64> =
                lines.next().expect("a row").split(',').map(|s| s.parse().expect("a number")).collect();
            assert_eq!(vals, r.values().to_vec());
        }
        assert_eq!(lines.next(), None);
    }

    #[test]
    fn text_columns_are_aligned_with_units() {
        let text = table().text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 5, "{text}");
        // Every line after the title has the same width (right-aligned columns).
        let w = lines[1].chars().count();
        assert!(lines[1..].iter().all(|l| l.chars().count() == w), "{text}");
        assert!(lines[2].contains("[ft]") && lines[2].contains("[ft³]") && lines[2].contains("[t]"), "{text}");
        assert!(lines[4].contains("2500.00") && lines[4].contains("0.6000"), "{text}");
        // The column names' right ends line up with the numbers' right ends.
        let end = |l: &str, pat: &str| l.find(pat).map(|i| l[..i + pat.len()].chars().count());
        assert_eq!(end(lines[1], "Vol"), end(lines[4], "2500.00"));
    }
}
