//! Which reader a text is for, told by its content (the table of [`super`]).

use super::records::{records, split_lines};
use super::{freeship, long_csv, series60_table};

/// The input formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFormat {
    /// Header `section,x,y,z`, one row per point.
    SectionsCsv,
    /// Stations across, waterlines down, half-breadths in the cells.
    OffsetTable,
    /// Todd's dimensionless Series 60 table with its `MaxBm` row ([`super::parse_series60_table`]).
    Series60Table,
    /// One point a row, columns found by name ([`super::parse_long_csv`]).
    LongCsv,
    /// A JSON offset table ([`super::parse_json_table`]).
    JsonTable,
    /// Whitespace-separated `x y z` (or `y z`) points in station blocks ([`super::parse_point_cloud`]).
    PointCloud,
    /// FREE!ship's "Offsets as 3D points" export ([`super::parse_freeship_offsets`]).
    FreeshipOffsets,
    /// FREE!ship's curve-import text: a units line, then `x y z` curves ([`super::parse_freeship_curves`]).
    FreeshipCurves,
}

impl InputFormat {
    /// Every format, in the order of the enum.
    pub const ALL: [InputFormat; 8] = [
        InputFormat::SectionsCsv,
        InputFormat::OffsetTable,
        InputFormat::Series60Table,
        InputFormat::LongCsv,
        InputFormat::JsonTable,
        InputFormat::PointCloud,
        InputFormat::FreeshipOffsets,
        InputFormat::FreeshipCurves,
    ];

    /// A short name for messages.
    pub fn name(self) -> &'static str {
        match self {
            InputFormat::SectionsCsv => "sections CSV",
            InputFormat::OffsetTable => "offset table CSV",
            InputFormat::Series60Table => "Series 60 table (Todd 1963)",
            InputFormat::LongCsv => "long CSV",
            InputFormat::JsonTable => "JSON offset table",
            InputFormat::PointCloud => "station point cloud",
            InputFormat::FreeshipOffsets => "FREE!ship offsets export",
            InputFormat::FreeshipCurves => "FREE!ship curve text",
        }
    }
}

/// Tells the format from the content (see the module table). Undecodable or unrecognised
/// text is called an offset table; its reader reports the problem.
pub fn detect_format(text: &str) -> InputFormat {
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    if text.trim_start().starts_with('{') {
        return InputFormat::JsonTable;
    }
    let mut data =
        split_lines(text).map(str::trim).filter(|l| !l.is_empty() && !l.starts_with('#') && !l.starts_with('%'));
    let Some(first) = data.next() else { return InputFormat::OffsetTable };
    if first.contains(',') || first.contains(';') {
        return detect_csv(text);
    }
    let toks: Vec<&str> = first.split_whitespace().collect();
    let numeric = |t: &&str| t.parse::<f64>().is_ok_and(f64::is_finite);
    let next_is_points = |line: Option<&str>, n: std::ops::RangeInclusive<usize>| {
        line.is_some_and(|l| {
            let t: Vec<&str> = l.split_whitespace().collect();
            n.contains(&t.len()) && t.iter().all(numeric)
        })
    };
    let second = data.next();
    if (toks == ["0"] || toks == ["1"]) && next_is_points(second, 3..=3) {
        return InputFormat::FreeshipCurves;
    }
    if freeship::is_header(first) {
        return InputFormat::FreeshipOffsets;
    }
    if first.contains('\t') && !toks.iter().all(numeric) {
        return detect_csv(text); // tab-separated: a spreadsheet's text export
    }
    if (2..=3).contains(&toks.len()) && toks.iter().all(numeric) {
        return InputFormat::PointCloud;
    }
    if !toks.first().is_some_and(numeric) && next_is_points(second, 2..=3) {
        return InputFormat::PointCloud;
    }
    InputFormat::OffsetTable
}

/// The CSV family: Series 60 (a `MaxBm` row), sections CSV (`section` first), long CSV (a
/// header naming x, y and z columns), else an offset table.
pub(super) fn detect_csv(text: &str) -> InputFormat {
    let Ok(recs) = records(text, "") else { return InputFormat::OffsetTable };
    let Some(header) = recs.first() else { return InputFormat::OffsetTable };
    if series60_table::looks_like_series60(&recs) {
        return InputFormat::Series60Table;
    }
    if header.fields[0].text.eq_ignore_ascii_case("section") {
        return InputFormat::SectionsCsv;
    }
    if long_csv::Columns::find(header).is_some() {
        return InputFormat::LongCsv;
    }
    InputFormat::OffsetTable
}
