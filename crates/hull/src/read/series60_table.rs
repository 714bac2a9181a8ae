//! Todd's Series 60 parent tables: dimensionless half-breadths, scaled by the user's Lpp, B, T.
//!
//! The rest of this module's documentation is on [`parse_series60_table`], where the library's users read it.

use nurbs::Vec3;

use super::{parse_number, records, Record, SuspiciousPolicy, SuspiciousValue};
use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::{Offsets, Perpendiculars, Section};
use crate::units::Units;

/// The number of station intervals between the FP (station 0) and the AP (station 20).
pub const SERIES60_STATIONS: f64 = 20.0;

/// A cell above `1 + FRACTION_SLACK` is suspicious: cells are fractions of their waterline's
/// maximum, printed to three decimals, so 1.000 is the largest sound value; the slack only
/// absorbs a value typed as `1.0000001`.
pub const FRACTION_SLACK: f64 = 1e-9;

/// The main dimensions that scale a dimensionless table: length between perpendiculars `lpp`,
/// moulded breadth `beam` (twice the largest half-breadth) and design draft `draft`, in the
/// offsets' units.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct MainDimensions {
    /// Length between perpendiculars.
    pub lpp: f64,
    /// Moulded breadth B.
    pub beam: f64,
    /// Design draft T (the 1.0 waterline of a Series 60 table).
    pub draft: f64,
}

impl MainDimensions {
    /// The Cb 0.60 parent's dimensions used by the built-in sample and by
    /// `testdata/series60_cb060_offsets.csv`: Lpp 121.92 m, B 16.26 m, T 6.50 m (L/B 7.5,
    /// B/T 2.5, Todd 1963; `shared/data/series60/PROVENANCE.md`). Right for the Cb 0.60
    /// parent only: the other parents have other L/B.
    pub const SERIES60_CB060: MainDimensions = MainDimensions { lpp: 121.92, beam: 16.26, draft: 6.5 };

    /// Checks every dimension is finite and positive.
    ///
    /// # Errors
    ///
    /// [`HullError::MainDimension`] naming the first bad dimension (NaN for one not given).
    pub fn check(&self) -> Result<(), HullError> {
        for (name, v) in [("Lpp", self.lpp), ("B", self.beam), ("T", self.draft)] {
            if !(v.is_finite() && v > 0.0) {
                return Err(HullError::MainDimension { name, value: v });
            }
        }
        Ok(())
    }
}

/// A Series 60 table read and scaled, with the values it found suspicious.
#[derive(Clone, Debug, PartialEq)]
pub struct Series60Table {
    /// The sections, AP first, in the offsets' units.
    pub offsets: Offsets,
    /// Cells above 1, with their place and what was done with them.
    pub suspicious: Vec<SuspiciousValue>,
}

/// True when the records hold a `MaxBm` row (first field `MaxBm`, any case): the mark of a
/// Series 60 table.
pub(crate) fn looks_like_series60(recs: &[Record<'_>]) -> bool {
    recs.iter().any(|r| r.fields.first().is_some_and(|f| f.text.eq_ignore_ascii_case("maxbm")))
}

/// Parses a Series 60 table held in `text` and scales it by `dims`; `source` names it in
/// messages.
///
/// The five parent hulls of Todd (1963), "Series 60 - Methodical Experiments with Models of
/// Single-Screw Merchant Ships", DTMB Report 1712, as transcribed in `cb0p6.csv` ..
/// `cb0p8.csv` (see `shared/data/series60/PROVENANCE.md`):
///
/// ```text
/// ,0 ,0.075,0.25,0.5,0.75,1,1.25,1.5,SAR
/// 0,0,0,10,0,0,0,0.02,0.042,0
/// 0.5,0.009,0.032,0.042,0.041,0.043,0.051,0.076,0.12,0.042
/// ...
/// 20,0,0,0,0,0,0.082,0.27,0.42,0.004
/// MaxBm,0.71,0.866,0.985,1,1,1,1,1,
/// ```
///
/// - Header: a blank corner cell, then the waterlines as z/T (z above the baseline, T the design
///   draft; 1.0 is the design waterline), then optional non-numeric columns (`SAR`, the sectional
///   area ratio), which are not offsets and are skipped.
/// - One row per station, numbered 0 (FP) to 20 (AP) in twentieths of Lpp (half stations
///   allowed): each cell the half-breadth as a FRACTION of that waterline's maximum
///   half-breadth. An empty cell is a missing offset.
/// - A `MaxBm` row: each waterline's maximum half-breadth as a fraction of B/2.
///
/// Conversion to hullskin's axes (x forward from the AP, y half-breadth, z up from the
/// baseline), with [`MainDimensions`] `Lpp`, `B`, `T` given by the user:
///
/// ```text
/// x = (1 - station / 20) Lpp        y = cell MaxBm(waterline) B / 2        z = (z/T) T
/// ```
///
/// Each station becomes one section, keel to deck (z ascending), labelled with its station
/// number as written; the sections are put AP first (x increasing), as the built-in sample.
///
/// Suspicious values: a cell is a fraction of the waterline's maximum, so a cell above 1 cannot
/// be right (the Cb 0.60 transcription reads `10` at station 0, WL 0.25, where the other
/// transcriptions have 0). Such a cell is reported as a [`SuspiciousValue`] with its place;
/// [`SuspiciousPolicy`] says what is done with it (by default it is replaced by the linear
/// interpolation in z of its station's nearest sound cells below and above, and the report says
/// so). Negative cells are errors.
///
/// Fields are trimmed (the transcriptions have trailing spaces inside fields).
///
/// # Errors
///
/// [`HullError::MainDimension`] for dimensions that are not finite and positive; [`HullError::Input`]
/// at `source:line:column` for: an empty text, a header without waterlines, a waterline z/T or
/// station number that is not a number, stations outside 0..20 or repeated, no `MaxBm` row or
/// more than one, a `MaxBm` value outside (0, 1], a negative cell, fewer than two stations,
/// and (with [`SuspiciousPolicy::Refuse`]) a cell above 1.
pub fn parse_series60_table(
    text: &str,
    source: &str,
    dims: MainDimensions,
    units: Units,
    policy: SuspiciousPolicy,
) -> Result<Series60Table, HullError> {
    dims.check()?;
    let recs = records(text, source)?;
    let Some((header, rows)) = recs.split_first() else {
        return Err(HullError::input(Location::file(source), InputErrorKind::Empty));
    };
    let unexpected = |at: Location, found: String, expected: &str| {
        HullError::input(at, InputErrorKind::Unexpected { found, expected: expected.to_string() })
    };

    // Waterlines across the header: numbers from column 2 until the first non-number (SAR).
    let mut zt: Vec<f64> = Vec::new();
    for f in &header.fields[1..] {
        match f.text.parse::<f64>() {
            Ok(v) if v.is_finite() && f.text.chars().any(|c| c.is_ascii_digit()) => {
                if let Some(&last) = zt.last() {
                    if v <= last {
                        return Err(unexpected(
                            header.at(source, f.column),
                            format!("waterline z/T = {v} after z/T = {last}"),
                            "waterlines in increasing z/T from left to right",
                        ));
                    }
                }
                zt.push(v)
            }
            _ => break,
        }
    }
    if zt.is_empty() {
        return Err(unexpected(
            header.at(source, 2),
            format!("header cell \"{}\"", header.fields.get(1).map_or("", |f| f.text.as_ref())),
            "a Series 60 header: a blank corner cell, then the waterlines as z/T (0, 0.075, 0.25, ..., 1.5)",
        ));
    }
    let n_wl = zt.len();

    // The MaxBm row.
    let mut maxbm: Option<(&Record<'_>, Vec<f64>)> = None;
    for row in rows.iter().filter(|r| r.fields[0].text.eq_ignore_ascii_case("maxbm")) {
        if let Some((first, _)) = &maxbm {
            return Err(unexpected(
                row.at(source, 1),
                format!("a second MaxBm row (the first is on line {})", first.line),
                "one MaxBm row",
            ));
        }
        let mut values = Vec::with_capacity(n_wl);
        for k in 0..n_wl {
            let col = k + 2;
            let f = row.fields.get(col - 1).map_or("", |f| f.text.as_ref());
            let v = parse_number(
                f,
                || row.at(source, col),
                || format!("the maximum half-breadth of waterline z/T = {} as a fraction of B/2", zt[k]),
            )?;
            if !(v > 0.0 && v <= 1.0 + FRACTION_SLACK) {
                return Err(unexpected(
                    row.at(source, col),
                    format!("MaxBm {v} at waterline z/T = {}", zt[k]),
                    "a fraction of B/2 in (0, 1]",
                ));
            }
            values.push(v);
        }
        maxbm = Some((row, values));
    }
    let Some((_, maxbm)) = maxbm else {
        return Err(unexpected(
            Location::file(source),
            "no MaxBm row".into(),
            "a row MaxBm,f1,f2,... giving each waterline's maximum half-breadth as a fraction of B/2",
        ));
    };

    // Station rows.
    struct Row {
        station: f64,
        label: String,
        line: usize,
        cells: Vec<Option<(f64, usize)>>, // fraction and column
    }
    let mut stations: Vec<Row> = Vec::new();
    for row in rows.iter().filter(|r| !r.fields[0].text.eq_ignore_ascii_case("maxbm")) {
        let label = row.fields[0].text.to_string();
        let station = parse_number(&label, || row.at(source, 1), || "a station number 0 (FP) .. 20 (AP)".into())?;
        if !(0.0..=SERIES60_STATIONS).contains(&station) {
            return Err(unexpected(
                row.at(source, 1),
                format!("station {station}"),
                "station numbers from 0 (FP) to 20 (AP)",
            ));
        }
        if let Some(prev) = stations.iter().find(|s| s.station == station) {
            return Err(unexpected(
                row.at(source, 1),
                format!("station {station} again (first on line {})", prev.line),
                "each station once",
            ));
        }
        let mut cells = Vec::with_capacity(n_wl);
        for k in 0..n_wl {
            let col = k + 2;
            match row.fields.get(col - 1).filter(|f| !f.text.is_empty()) {
                None => cells.push(None),
                Some(f) => {
                    let v = parse_number(
                        &f.text,
                        || row.at(source, col),
                        || {
                            format!(
                                "the half-breadth at station {label}, waterline z/T = {} as a fraction of the \
                                    waterline's maximum, or an empty cell",
                                zt[k]
                            )
                        },
                    )?;
                    if v < 0.0 {
                        return Err(HullError::input(
                            row.at(source, col),
                            InputErrorKind::NegativeHalfBreadth { y: v },
                        ));
                    }
                    cells.push(Some((v + 0.0, col)));
                }
            }
        }
        stations.push(Row { station, label, line: row.line, cells });
    }
    if stations.len() < 2 {
        return Err(HullError::input(
            Location::line(source, header.line),
            InputErrorKind::NoRows {
                expected: "one row per station: its number, then a fraction per waterline".into(),
            },
        ));
    }

    // Suspicious cells: above 1.
    let mut suspicious = Vec::new();
    for s in &mut stations {
        let sound: Vec<Option<f64>> =
            s.cells.iter().map(|c| c.and_then(|(v, _)| (v <= 1.0 + FRACTION_SLACK).then_some(v))).collect();
        for k in 0..n_wl {
            let Some((v, col)) = s.cells[k] else { continue };
            if v <= 1.0 + FRACTION_SLACK {
                continue;
            }
            let at = Location::new(source, s.line, col);
            let below = (0..k).rev().find_map(|j| sound[j].map(|u| (j, u)));
            let above = (k + 1..n_wl).find_map(|j| sound[j].map(|u| (j, u)));
            let (replacement, action) = match policy {
                SuspiciousPolicy::Refuse => {
                    return Err(HullError::input(
                        at,
                        InputErrorKind::Unexpected {
                            found: format!(
                                "half-breadth fraction {v} at station {}, waterline z/T = {}",
                                s.label, zt[k]
                            ),
                            expected: "a fraction of the waterline's maximum half-breadth in [0, 1]".into(),
                        },
                    ));
                }
                SuspiciousPolicy::Omit => (None, "left out (a missing offset)".to_string()),
                SuspiciousPolicy::Interpolate => match (below, above) {
                    (Some((j0, u0)), Some((j1, u1))) => {
                        let t = (zt[k] - zt[j0]) / (zt[j1] - zt[j0]);
                        let r = u0 + t * (u1 - u0);
                        (
                            Some(r),
                            format!(
                                "replaced by {r}, the linear interpolation in z of its station's cells {u0} \
                                    (z/T = {}) and {u1} (z/T = {})",
                                zt[j0], zt[j1]
                            ),
                        )
                    }
                    _ => (None, "left out (no sound cell on both sides to interpolate from)".to_string()),
                },
            };
            suspicious.push(SuspiciousValue {
                at,
                what: format!("station {}, waterline z/T = {}", s.label, zt[k]),
                value: v,
                reason: "a fraction of the waterline's maximum half-breadth cannot exceed 1".into(),
                replacement,
                action,
            });
            s.cells[k] = replacement.map(|r| (r, col));
        }
    }

    // Scale: AP (station 20) first, so that x increases.
    stations.sort_by(|a, b| b.station.total_cmp(&a.station));
    let half_beam = dims.beam / 2.0;
    let sections = stations
        .iter()
        .map(|s| {
            let x = (1.0 - s.station / SERIES60_STATIONS) * dims.lpp;
            let mut points = Vec::new();
            let mut lines = Vec::new();
            for (k, c) in s.cells.iter().enumerate() {
                if let Some((v, _)) = c {
                    points.push(Vec3::new(x + 0.0, v * maxbm[k] * half_beam, zt[k] * dims.draft));
                    lines.push(s.line);
                }
            }
            Section { label: s.label.clone(), points, lines, column: None }
        })
        .collect();
    let mut offsets = Offsets::new(source, units, sections);
    // x runs from the AP (station 20) to the FP (station 0).
    offsets.perpendiculars = Perpendiculars::try_new(0.0, dims.lpp).ok();
    Ok(Series60Table { offsets, suspicious })
}

#[cfg(test)]
mod tests {
    use super::*;

    const DIMS: MainDimensions = MainDimensions { lpp: 100.0, beam: 10.0, draft: 4.0 };

    fn parse(text: &str, policy: SuspiciousPolicy) -> Result<Series60Table, HullError> {
        parse_series60_table(text, "s60.csv", DIMS, Units::Metre, policy)
    }

    fn err(text: &str) -> String {
        parse(text, SuspiciousPolicy::Interpolate).err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    const SMALL: &str = ",0 ,0.5,1,SAR\n0,0,0.1,0.2,0\n10,1,1,1 ,1\n20,0,0.3,0.5,0.1\nMaxBm,0.5,1,1, \n";

    #[test]
    fn scaling_follows_the_formulas() {
        let t = parse(SMALL, SuspiciousPolicy::Interpolate).expect("valid");
        assert!(t.suspicious.is_empty());
        let labels: Vec<&str> = t.offsets.sections.iter().map(|s| s.label.as_str()).collect();
        assert_eq!(labels, ["20", "10", "0"], "AP first");
        // Station 10 is midship: x = Lpp/2; its cells are 1: y = MaxBm B/2 (0.5 x 5 at the
        // baseline, 5 above), z = (z/T) T. All products of small binary fractions: exact.
        assert_eq!(
            t.offsets.sections[1].points,
            vec![Vec3::new(50.0, 2.5, 0.0), Vec3::new(50.0, 5.0, 2.0), Vec3::new(50.0, 5.0, 4.0)]
        );
        assert_eq!(t.offsets.sections[0].points[0].x, 0.0, "station 20 is the AP");
        assert_eq!(t.offsets.sections[2].points[0].x, 100.0, "station 0 is the FP");
        // 0.3 x 1 x 5 = 1.5 up to one rounding of 0.3 (half an ulp, relative 1.1e-16).
        assert!((t.offsets.sections[0].points[1].y - 1.5).abs() < 1e-15);
        assert!(t.offsets.validate(3).is_ok());
    }

    #[test]
    fn a_cell_above_one_is_reported_and_by_default_interpolated() {
        let text = ",0,0.5,1,1.5\n0,0,10,0.2,0.4\n20,0,0.3,0.5,0.6\nMaxBm,1,1,1,1\n";
        let t = parse(text, SuspiciousPolicy::Interpolate).expect("valid");
        assert_eq!(t.suspicious.len(), 1);
        let s = &t.suspicious[0];
        assert_eq!(s.at.to_string(), "s60.csv:2:3");
        assert_eq!(s.value, 10.0);
        // Linear in z between 0 (z/T 0) and 0.2 (z/T 1): 0.1 at z/T 0.5.
        assert!((s.replacement.unwrap_or(f64::NAN) - 0.1).abs() < 1e-15);
        assert!(s.action.contains("interpolation"), "{}", s.action);
        let fp = &t.offsets.sections[1];
        assert!((fp.points[1].y - 0.1 * 5.0).abs() < 1e-14);

        let omitted = parse(text, SuspiciousPolicy::Omit).expect("valid");
        assert_eq!(omitted.offsets.sections[1].points.len(), 3);
        assert_eq!(omitted.suspicious[0].replacement, None);

        let refused = parse(text, SuspiciousPolicy::Refuse).err().map(|e| e.to_string()).unwrap_or_default();
        assert_eq!(
            refused,
            "s60.csv:2:3: half-breadth fraction 10 at station 0, waterline z/T = 0.5 (expected a fraction of the \
             waterline's maximum half-breadth in [0, 1])"
        );
    }

    #[test]
    fn a_suspicious_top_cell_without_a_neighbour_above_is_left_out() {
        let t = parse(",0,1\n0,0,3\n20,0,1\nMaxBm,1,1\n", SuspiciousPolicy::Interpolate).expect("valid");
        assert_eq!(t.suspicious[0].replacement, None);
        assert_eq!(t.offsets.sections[1].points.len(), 1);
    }

    #[test]
    fn bad_tables_are_located() {
        assert!(err("").starts_with("s60.csv: no data"));
        assert_eq!(
            err(",0,1\n0,0,0\n20,0,0\n"),
            "s60.csv: no MaxBm row (expected a row MaxBm,f1,f2,... giving each waterline's maximum half-breadth \
             as a fraction of B/2)"
        );
        assert!(err(",SAR\n0,0\nMaxBm,1\n").starts_with("s60.csv:1:2: header cell \"SAR\""));
        assert!(err(",0,1\n0,0,0\n21,0,0\nMaxBm,1,1\n").starts_with("s60.csv:3:1: station 21 (expected station"));
        assert!(err(",0,1\n0,0,0\n0,0,0\nMaxBm,1,1\n").starts_with("s60.csv:3:1: station 0 again (first on line 2)"));
        assert!(err(",0,1\n0,0,0\n20,0,x\nMaxBm,1,1\n").starts_with("s60.csv:3:3: \"x\" is not a number"));
        assert!(err(",0,1\n0,0,0\n20,0,-0.1\nMaxBm,1,1\n").starts_with("s60.csv:3:3: half-breadth -0.1 is negative"));
        assert!(err(",0,1\n0,0,0\n20,0,0\nMaxBm,1,1.5\n").starts_with("s60.csv:4:3: MaxBm 1.5 at waterline z/T = 1"));
        assert!(err(",0,1\n0,0,0\n20,0,0\nMaxBm,1\n").starts_with("s60.csv:4:3: empty field"));
        assert!(err(",0,1\n0,0,0\n20,0,0\nMaxBm,1,1\nmaxbm,1,1\n").contains("a second MaxBm row"));
        assert!(err(",1,0\n0,0,0\nMaxBm,1,1\n").starts_with("s60.csv:1:3: waterline z/T = 0 after z/T = 1"));
        assert!(err(",0,1\n0,0,0\nMaxBm,1,1\n").contains("no data rows after the header"));
        let bad =
            parse_series60_table(SMALL, "s", MainDimensions { lpp: 0.0, ..DIMS }, Units::Metre, SuspiciousPolicy::Omit);
        assert!(bad.err().map(|e| e.to_string()).unwrap_or_default().starts_with("Lpp = 0"));
    }
}
