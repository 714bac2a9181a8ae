//! The hydrostatics table as text (aligned columns with units), CSV and JSON.

use std::fmt::Write as _;

use serde::{Deserialize, Serialize};

use super::{HydrostaticsRow, Perpendiculars};
use crate::numfmt::{format_figure, format_short};
use crate::units::Units;

/// What a column measures, for its unit.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Kind {
    Length,
    Area,
    Volume,
    Mass,
    Ratio,
    /// A percentage of Lpp.
    PercentLpp,
    /// Tonnes per centimetre.
    TonnesPerCm,
    /// Tonne-metres per centimetre.
    MomentPerCm,
}

/// Number of columns of the table.
pub const NUM_COLUMNS: usize = 26;

/// The columns in order: JSON/CSV key, the header of the text table. The keys of FREE!ship's
/// columns are its names in lower case.
pub const HYDROSTATICS_COLUMNS: [(&str, &str); NUM_COLUMNS] = [
    ("draft", "Draft"),
    ("lwl", "Lwl"),
    ("bwl", "Bwl"),
    ("vol", "Vol"),
    ("displ", "Displ"),
    ("lcb", "LCB"),
    ("lcb_pct_lpp", "LCB"),
    ("vcb", "VCB"),
    ("cb", "CB"),
    ("cb_lpp", "CB(Lpp)"),
    ("am", "AM"),
    ("cm", "CM"),
    ("cm_lpp", "CM(Lpp)"),
    ("aw", "AW"),
    ("cw", "CW"),
    ("cp", "CP"),
    ("cp_lpp", "CP(Lpp)"),
    ("lcf", "LCF"),
    ("lcf_pct_lpp", "LCF"),
    ("s", "S"),
    ("tpc", "TPC"),
    ("mct", "MCT"),
    ("bmt", "BMt"),
    ("bml", "BMl"),
    ("kmt", "KMt"),
    ("kml", "KMl"),
];

const KINDS: [Kind; NUM_COLUMNS] = [
    Kind::Length,
    Kind::Length,
    Kind::Length,
    Kind::Volume,
    Kind::Mass,
    Kind::Length,
    Kind::PercentLpp,
    Kind::Length,
    Kind::Ratio,
    Kind::Ratio,
    Kind::Area,
    Kind::Ratio,
    Kind::Ratio,
    Kind::Area,
    Kind::Ratio,
    Kind::Ratio,
    Kind::Ratio,
    Kind::Length,
    Kind::PercentLpp,
    Kind::Area,
    Kind::TonnesPerCm,
    Kind::MomentPerCm,
    Kind::Length,
    Kind::Length,
    Kind::Length,
    Kind::Length,
];

impl HydrostaticsRow {
    /// The values in the order of [`HYDROSTATICS_COLUMNS`]; `None` for the figures on Lpp
    /// when the perpendiculars were not known.
    pub fn values(&self) -> [Option<f64>; NUM_COLUMNS] {
        let s = Some;
        [
            s(self.draft),
            s(self.lwl),
            s(self.bwl),
            s(self.vol),
            s(self.displ),
            s(self.lcb),
            self.lcb_pct_lpp,
            s(self.vcb),
            s(self.cb),
            self.cb_lpp,
            s(self.am),
            s(self.cm),
            self.cm_lpp,
            s(self.aw),
            s(self.cw),
            s(self.cp),
            self.cp_lpp,
            s(self.lcf),
            self.lcf_pct_lpp,
            s(self.s),
            s(self.tpc),
            s(self.mct),
            s(self.bmt),
            s(self.bml),
            s(self.kmt),
            s(self.kml),
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
    /// The perpendiculars the figures on Lpp were taken with (`None`: not known, and those
    /// columns are left out).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub perpendiculars: Option<Perpendiculars>,
    /// One row per draft.
    pub rows: Vec<HydrostaticsRow>,
}

impl HydrostaticsTable {
    /// The unit label of each column: `m`, `m²`, `m³`, `t`, `-`, `% Lpp`, `t/cm`, `t·m/cm`.
    pub fn unit_labels(&self) -> [String; NUM_COLUMNS] {
        let u = self.units.symbol();
        KINDS.map(|k| match k {
            Kind::Length => u.to_string(),
            Kind::Area => format!("{u}²"),
            Kind::Volume => format!("{u}³"),
            Kind::Mass => "t".to_string(),
            Kind::Ratio => "-".to_string(),
            Kind::PercentLpp => "% Lpp".to_string(),
            Kind::TonnesPerCm => "t/cm".to_string(),
            Kind::MomentPerCm => "t·m/cm".to_string(),
        })
    }

    /// The columns shown: all of them with the perpendiculars, else those with a value.
    pub fn shown_columns(&self) -> Vec<usize> {
        (0..NUM_COLUMNS).filter(|&c| self.rows.iter().all(|r| r.values()[c].is_some())).collect()
    }

    /// What the table's conventions are, in a line: the density, where AM is taken, CB's
    /// definition, Lpp and amidships, the sign of the percentages, MCT's length.
    pub fn conventions(&self) -> String {
        let u = self.units.symbol();
        let sig = format_short;
        let mut s =
            format!("both sides; density {} t/m³; CB = Vol/(Lwl Bwl T), AM at the middle of Lwl", sig(self.density));
        match self.perpendiculars {
            Some(p) => s.push_str(&format!(
                "; Lpp {} {u} (AP x = {}, FP x = {}), amidships x = {}: CB(Lpp) = Vol/(Lpp Bwl T), \
                 CM(Lpp) and CP(Lpp) with the section at amidships, LCB and LCF in % Lpp from amidships, \
                 + forward; MCT = Displ BMl/(100 Lpp)",
                sig(p.lpp()),
                sig(p.aft),
                sig(p.fore),
                sig(p.midship())
            )),
            None => s.push_str("; MCT = Displ BMl/(100 Lwl) (Lpp not given: --lpp)"),
        }
        s.push_str("; GMl taken as BMl");
        s
    }

    /// An aligned text table: a title line, the conventions, the column names, their units in
    /// brackets, one line per draft; numbers to 5 significant digits.
    pub fn text(&self) -> String {
        let units = self.unit_labels();
        let cols = self.shown_columns();
        let cells: Vec<Vec<String>> = self
            .rows
            .iter()
            .map(|r| {
                let v = r.values();
                cols.iter().map(|&c| v[c].map_or_else(String::new, format_figure)).collect()
            })
            .collect();
        let widths: Vec<usize> = cols
            .iter()
            .enumerate()
            .map(|(k, &c)| {
                let head = HYDROSTATICS_COLUMNS[c].1.chars().count().max(units[c].chars().count() + 2);
                cells.iter().map(|r| r[k].chars().count()).fold(head, usize::max)
            })
            .collect();
        let mut out = String::new();
        let _ = writeln!(out, "hydrostatics of {}", self.source);
        let _ = writeln!(out, "({})", self.conventions());
        let line = |out: &mut String, items: &mut dyn Iterator<Item = String>| {
            let parts: Vec<String> = items.zip(&widths).map(|(s, &w)| format!("{s:>w$}")).collect();
            let _ = writeln!(out, "{}", parts.join("  "));
        };
        line(&mut out, &mut cols.iter().map(|&c| HYDROSTATICS_COLUMNS[c].1.to_string()));
        line(&mut out, &mut cols.iter().map(|&c| format!("[{}]", units[c])));
        for r in &cells {
            line(&mut out, &mut r.iter().cloned());
        }
        out
    }

    /// CSV: the header of the shown [`HYDROSTATICS_COLUMNS`] keys, then one line per draft,
    /// every number with the shortest digits that read back to the same `f64`.
    pub fn csv(&self) -> String {
        let cols = self.shown_columns();
        let mut out = cols.iter().map(|&c| HYDROSTATICS_COLUMNS[c].0).collect::<Vec<_>>().join(",");
        out.push('\n');
        for r in &self.rows {
            let v = r.values();
            let vals: Vec<String> = cols.iter().map(|&c| v[c].map_or_else(String::new, |x| format!("{x}"))).collect();
            out.push_str(&vals.join(","));
            out.push('\n');
        }
        out
    }

    /// Pretty JSON: `{"source", "units", "density", "perpendiculars"?, "rows": [{"draft": ..,
    /// ..}, ..]}`, the keys on Lpp only with the perpendiculars.
    pub fn json(&self) -> String {
        let mut s = serde_json::to_string_pretty(self).expect("a table of finite numbers and strings serializes");
        s.push('\n');
        s
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn table(perpendiculars: Option<Perpendiculars>) -> HydrostaticsTable {
        let lpp = perpendiculars.map(|_| 0.61);
        let row = |t: f64| HydrostaticsRow {
            draft: t,
            vol: 1000.0 * t,
            cb: 0.6,
            cb_lpp: lpp,
            cm_lpp: lpp,
            cp_lpp: lpp,
            lcb_pct_lpp: lpp.map(|_| -1.5),
            lcf_pct_lpp: lpp.map(|_| -2.25),
            s: 12.5,
            ..Default::default()
        };
        HydrostaticsTable {
            source: "test".into(),
            units: Units::Foot,
            density: 1.025,
            perpendiculars,
            rows: vec![row(1.0), row(2.5)],
        }
    }

    fn with_lpp() -> HydrostaticsTable {
        table(Some(Perpendiculars::try_new(0.0, 400.0).expect("valid")))
    }

    #[test]
    fn json_keys_are_the_column_names_and_the_lpp_ones_only_with_lpp() {
        for (t, n) in [(table(None), NUM_COLUMNS - 5), (with_lpp(), NUM_COLUMNS)] {
            let v: serde_json::Value = serde_json::from_str(&t.json()).expect("valid JSON");
            let row = v["rows"][1].as_object().expect("a row object");
            let mut got: Vec<&str> = row.keys().map(String::as_str).collect();
            let mut expected: Vec<&str> = t.shown_columns().iter().map(|&c| HYDROSTATICS_COLUMNS[c].0).collect();
            expected.sort_unstable();
            got.sort_unstable();
            assert_eq!((got.len(), &got), (n, &expected));
            assert_eq!(v["units"], "ft");
            assert_eq!(row["vol"], 2500.0);
            let back: HydrostaticsTable = serde_json::from_value(v).expect("reads back");
            assert_eq!(back, t);
        }
        let v: serde_json::Value = serde_json::from_str(&with_lpp().json()).expect("valid JSON");
        assert_eq!((v["perpendiculars"]["aft"].as_f64(), v["rows"][0]["cb_lpp"].as_f64()), (Some(0.0), Some(0.61)));
        // FREE!ship's names of the metacentres still read.
        let old: HydrostaticsRow = serde_json::from_str(
            r#"{"draft": 1, "lwl": 0, "bwl": 0, "vol": 0, "displ": 0,
            "lcb": 0, "vcb": 0, "cb": 0, "am": 0, "cm": 0, "aw": 0, "cw": 0, "cp": 0, "lcf": 0, "s": 0, "tpc": 0,
            "mct": 0, "bmt": 0, "bml": 0, "kmtrv": 3.5, "kmlong": 90}"#,
        )
        .expect("old keys");
        assert_eq!((old.kmt, old.kml, old.cb_lpp), (3.5, 90.0, None));
    }

    #[test]
    fn csv_reads_back_exactly() {
        for t in [table(None), with_lpp()] {
            let text = t.csv();
            let mut lines = text.lines();
            let cols = t.shown_columns();
            let header: Vec<&str> = cols.iter().map(|&c| HYDROSTATICS_COLUMNS[c].0).collect();
            assert_eq!(lines.next(), Some(header.join(",").as_str()));
            for r in &t.rows {
                let vals: Vec<f64> =
                    lines.next().expect("a row").split(',').map(|s| s.parse().expect("a number")).collect();
                let want: Vec<f64> = cols.iter().map(|&c| r.values()[c].expect("a shown value")).collect();
                assert_eq!(vals, want);
            }
            assert_eq!(lines.next(), None);
        }
        assert!(!table(None).csv().contains("cb_lpp") && with_lpp().csv().contains("lcb_pct_lpp"));
    }

    #[test]
    fn text_columns_are_aligned_with_units_and_five_digits() {
        let text = with_lpp().text();
        let lines: Vec<&str> = text.lines().collect();
        assert_eq!(lines.len(), 6, "{text}");
        assert!(lines[1].contains("Lpp 400 ft") && lines[1].contains("+ forward"), "{text}");
        // Every line after the title and the conventions has the same width.
        let w = lines[2].chars().count();
        assert!(lines[2..].iter().all(|l| l.chars().count() == w), "{text}");
        for unit in ["[ft]", "[ft³]", "[t]", "[% Lpp]", "[t/cm]", "[t·m/cm]"] {
            assert!(lines[3].contains(unit), "{unit}: {text}");
        }
        // Five significant digits: 2500.0, 0.60000, -1.5000; zeros as 0.
        assert!(lines[5].contains("2500.0") && lines[5].contains("0.60000") && lines[5].contains("-1.5000"), "{text}");
        // The column names' right ends line up with the numbers' right ends.
        let end = |l: &str, pat: &str| l.find(pat).map(|i| l[..i + pat.len()].chars().count());
        assert_eq!(end(lines[2], "Vol"), end(lines[5], "2500.0"));
        let plain = table(None).text();
        assert!(!plain.contains("CB(Lpp)") && plain.contains("Lpp not given"), "{plain}");
    }
}
