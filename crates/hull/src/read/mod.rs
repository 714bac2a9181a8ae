//! Readers of offset data, told apart by their content.
//!
//! | format | module | recognised by |
//! |---|---|---|
//! | sections CSV `section,x,y,z` | [`sections_csv`] | first field `section` |
//! | offset table (stations across, waterlines down) | [`offset_table`] | any other CSV |
//! | Todd's Series 60 table (fractions, `MaxBm` row) | [`series60_table`] | a `MaxBm` row |
//! | long CSV, one point a row, columns by name (`x,z,y`, ...) | [`long_csv`] | a header naming x, y and z columns |
//! | JSON offset tables (vessel.js ship, OpenHull table) | [`json_table`] | first character `{` |
//! | station point clouds (`x y z` or `y z` blocks) | [`point_cloud`] | whitespace-separated numbers |
//! | FREE!ship offsets export and curve import text | [`freeship`] | a `Station 1.000` line, or a first line `0`/`1` |
//!
//! B-spline *surfaces* (not offsets) are read from IGES and STEP files by [`cad`] ([`iges`],
//! [`step`]), through [`read_cad_surfaces`].
//!
//! The CSV formats are delimited text, UTF-8 (a byte-order mark is skipped; UTF-16 is refused
//! with a message saying so), with `\n`, `\r\n` or `\r` line ends, mixed as they come.
//! Fields are trimmed of spaces and tabs; a field may be quoted with `"` (a doubled `""` inside
//! stands for one quote; a quoted field ends on its own line). Blank lines, lines of empty
//! fields only (`,,,` as spreadsheets export them), and lines whose first non-blank character is
//! `#` are skipped. `nan` and `inf` are refused.
//!
//! The delimiter is the file's, set by its first data line (the first line neither blank nor a
//! comment): a semicolon when that line holds one and none of the pieces between them holds more
//! than one comma or starts or ends with one (a European spreadsheet's CSV: `z\x;0;2,5;5`), else
//! a tab by the same rule (a spreadsheet's text export), else a comma (so `"a;b",1,2` and
//! `0,<tab>1.5,<tab>2` are comma files). Every later line must use the same delimiter (a line that uses
//! another is refused at its place). With a comma delimiter numbers use a decimal point (a
//! decimal comma splits the number into two fields, and the messages say so). With a `;` or
//! tab delimiter, and only then, a field that is a number written with one decimal comma and
//! no point (`1,5`, `-0,25`, `1,5e-3`) is read as that number with a decimal point (`1.5`);
//! a field with both (`1.000,5`, thousands grouped) is not a number.
//!
//! Errors point at `file:line:column`, with 1-based line numbers of the file and 1-based
//! field numbers as columns (CSV fields; whitespace-separated tokens in the text formats;
//! characters in JSON) (see [`crate::Location`]).
//!
//! Every reader converts to hullskin's axes (x forward from the aft end or AP, y the
//! half-breadth >= 0, z up from the baseline) and [`read_offsets_with`] says in
//! [`ReadOutcome::axes`] which axes it assumed or how it converted, with notes, suspicious
//! values and disagreements between the views of a lines plan.
//!
//! The readers parse; they do not check the data can be skinned: call
//! [`Offsets::validate`] with the fit's degree + 1 for that.

pub mod cad;
pub mod freeship;
pub mod iges;
pub mod json_table;
pub mod long_csv;
pub mod offset_table;
pub mod point_cloud;
pub mod sections_csv;
pub mod sense;
pub mod series60_table;
pub mod step;
pub mod views;

use std::borrow::Cow;
use std::path::Path;

use crate::error::{HullError, InputErrorKind, Location};
use crate::offsets::Offsets;
use crate::units::Units;

pub use cad::{parse_cad_surfaces, read_cad_surfaces, CadFormat, CadSurface, CadSurfaces};
pub use offset_table::parse_offset_table;
pub use sections_csv::{parse_sections_csv, write_sections_csv};
pub use sense::{find_outliers, Outlier, OutlierPolicy, SenseKind, SenseWarning};
pub use series60_table::{parse_series60_table, MainDimensions, Series60Table};
pub use views::{Disagreement, MergeOptions, Merged, Station, ThreeViews, View, ViewLine};

/// The input formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputFormat {
    /// Header `section,x,y,z`, one row per point.
    SectionsCsv,
    /// Stations across, waterlines down, half-breadths in the cells.
    OffsetTable,
    /// Todd's dimensionless Series 60 table with its `MaxBm` row ([`series60_table`]).
    Series60Table,
    /// One point a row, columns found by name ([`long_csv`]).
    LongCsv,
    /// A JSON offset table ([`json_table`]).
    JsonTable,
    /// Whitespace-separated `x y z` (or `y z`) points in station blocks ([`point_cloud`]).
    PointCloud,
    /// FREE!ship's "Offsets as 3D points" export ([`freeship`]).
    FreeshipOffsets,
    /// FREE!ship's curve-import text: a units line, then `x y z` curves ([`freeship`]).
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
fn detect_csv(text: &str) -> InputFormat {
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

/// What a reader does with a value it finds suspicious (a Series 60 fraction above 1).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum SuspiciousPolicy {
    /// Replace it by the linear interpolation of its sound neighbours along its station, and
    /// report it (the default).
    #[default]
    Interpolate,
    /// Leave it out (a missing offset), and report it.
    Omit,
    /// Stop with an error at its place.
    Refuse,
}

/// A value read that cannot be right, where it is, and what was done with it.
#[derive(Clone, Debug, PartialEq)]
pub struct SuspiciousValue {
    /// Its place in the file.
    pub at: Location,
    /// What it is (`station 0, waterline z/T = 0.25`).
    pub what: String,
    /// The value as read.
    pub value: f64,
    /// Why it is suspicious.
    pub reason: String,
    /// The value used instead, `None` when it was left out.
    pub replacement: Option<f64>,
    /// What was done, in words.
    pub action: String,
}

impl std::fmt::Display for SuspiciousValue {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}: suspicious value {} at {}: {}; {}", self.at, self.value, self.what, self.reason, self.action)
    }
}

/// How to read an input: [`ReadOptions::default`] reads any format in metres.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct ReadOptions {
    /// The units of the coordinates (for formats whose units the file states, the unit the
    /// coordinates are converted to).
    pub units: Units,
    /// The format; `None` to detect it ([`detect_format`]).
    pub format: Option<InputFormat>,
    /// Lpp, B, T: the scale of a Series 60 table (default [`MainDimensions::SERIES60_CB060`],
    /// right for the Cb 0.60 parent only, with a note) and the station spacing `Lpp / 20` of an
    /// OpenHull table when no `principals.json` lies beside it.
    pub dimensions: Option<MainDimensions>,
    /// What to do with suspicious values.
    pub suspicious: SuspiciousPolicy,
    /// What to do with outlier cells ([`sense::find_outliers`]).
    pub outliers: OutlierPolicy,
    /// The disagreement tolerance of the three-view merge ([`MergeOptions::tolerance`]).
    pub tolerance: Option<f64>,
    /// Sections with fewer points are left out, with a note (0: keep all). Applies to the
    /// formats other than the sections CSV and the offset table, whose short sections are
    /// reported by [`Offsets::validate`] as before: end stations beyond the stem of a table
    /// (Gunnerus) or a stem head of two points (the frigate cloud) are a property of those
    /// sources, not a typing error. Pass the fit's degree + 1.
    pub min_points: usize,
}

/// Offsets read, with what the reader assumed and found.
#[derive(Clone, Debug, PartialEq)]
pub struct ReadOutcome {
    /// The sections, in hullskin's axes.
    pub offsets: Offsets,
    /// The format read.
    pub format: InputFormat,
    /// The axes assumed or the conversion made, in words.
    pub axes: String,
    /// What was left out or assumed, in words.
    pub notes: Vec<String>,
    /// Values that cannot be right, and what was done with them.
    pub suspicious: Vec<SuspiciousValue>,
    /// Places where the views of a lines plan disagree (left out of the sections).
    pub disagreements: Vec<Disagreement>,
    /// Plausible mistakes found by the sense checks ([`sense`]): units, size, transposition,
    /// outlier cells. The offsets are as read.
    pub warnings: Vec<SenseWarning>,
}

impl ReadOutcome {
    /// Offsets read as written, nothing to note.
    pub(crate) fn plain(offsets: Offsets, format: InputFormat, axes: impl Into<String>) -> Self {
        ReadOutcome {
            offsets,
            format,
            axes: axes.into(),
            notes: Vec::new(),
            suspicious: Vec::new(),
            disagreements: Vec::new(),
            warnings: Vec::new(),
        }
    }

    /// The outcome of merging three views.
    pub(crate) fn merged(m: Merged, format: InputFormat, axes: impl Into<String>, mut notes: Vec<String>) -> Self {
        notes.extend(m.notes);
        ReadOutcome {
            offsets: m.offsets,
            format,
            axes: axes.into(),
            notes,
            suspicious: Vec::new(),
            disagreements: m.disagreements,
            warnings: Vec::new(),
        }
    }

    /// Every note, suspicious value and disagreement, one line each, for a user.
    pub fn messages(&self) -> Vec<String> {
        let mut out = vec![format!("{}: read as {}; axes: {}", self.offsets.source, self.format.name(), self.axes)];
        out.extend(self.notes.iter().map(|n| format!("{}: {n}", self.offsets.source)));
        out.extend(self.suspicious.iter().map(ToString::to_string));
        out.extend(self.disagreements.iter().map(|d| format!("views disagree: {d}")));
        out
    }
}

/// The axes note of the formats read as they are written.
pub(crate) const AS_WRITTEN: &str = "as written: x forward, y half-breadth >= 0, z up (no conversion)";

/// Reads the offsets in `path`, any format (see [`detect_format`]), in `units`.
/// The `source` of the result is `path` as given. Notes and reports are dropped: see
/// [`read_offsets_with`] for them.
///
/// # Errors
///
/// As [`read_offsets_with`].
pub fn read_offsets(path: &Path, units: Units) -> Result<Offsets, HullError> {
    read_offsets_with(path, &ReadOptions { units, ..ReadOptions::default() }).map(|o| o.offsets)
}

/// Reads the offsets in `path` with `options`, with what the reader assumed and found.
/// An OpenHull JSON table takes its station spacing from a `principals.json` beside it when
/// [`ReadOptions::dimensions`] is not given.
///
/// # Errors
///
/// [`HullError::Io`] when the file cannot be read; [`HullError::Input`] for a binary or
/// UTF-16 file and for every parse error of the format's reader.
pub fn read_offsets_with(path: &Path, options: &ReadOptions) -> Result<ReadOutcome, HullError> {
    let bytes = crate::limits::read_capped(path, crate::limits::MAX_OFFSETS_FILE_BYTES, "an offsets file")?;
    let source = path.display().to_string();
    let text = decode(&bytes, &source)?;
    parse_with(text, &source, options, path.parent())
}

/// Parses offsets held in a string, any format (see [`detect_format`]); `source` names
/// the input in messages.
///
/// # Errors
///
/// Every error of the format's reader.
pub fn parse_offsets(text: &str, source: &str, units: Units) -> Result<Offsets, HullError> {
    parse_offsets_with(text, source, &ReadOptions { units, ..ReadOptions::default() }).map(|o| o.offsets)
}

/// Parses offsets held in a string with `options`, with what the reader assumed and found.
///
/// # Errors
///
/// Every error of the format's reader.
pub fn parse_offsets_with(text: &str, source: &str, options: &ReadOptions) -> Result<ReadOutcome, HullError> {
    parse_with(text, source, options, None)
}

fn parse_with(text: &str, source: &str, options: &ReadOptions, dir: Option<&Path>) -> Result<ReadOutcome, HullError> {
    let mut out = parse_format(text, source, options, dir)?;
    crate::limits::check_offsets(&out.offsets)?;
    out.warnings = sense::sense_check(text, &out.offsets, out.format, options.outliers)?;
    if options.min_points > 0 && !matches!(out.format, InputFormat::SectionsCsv | InputFormat::OffsetTable) {
        let short: Vec<String> = out
            .offsets
            .sections
            .iter()
            .filter(|s| s.points.len() < options.min_points)
            .map(|s| format!("{} ({})", s.label, s.points.len()))
            .collect();
        if !short.is_empty() {
            out.offsets.sections.retain(|s| s.points.len() >= options.min_points);
            out.notes.push(format!(
                "sections with fewer than {} points left out: {}",
                options.min_points,
                short.join(", ")
            ));
        }
    }
    Ok(out)
}

fn parse_format(text: &str, source: &str, options: &ReadOptions, dir: Option<&Path>) -> Result<ReadOutcome, HullError> {
    let units = options.units;
    let format = options.format.unwrap_or_else(|| detect_format(text));
    match format {
        InputFormat::SectionsCsv => {
            Ok(ReadOutcome::plain(parse_sections_csv(text, source, units)?, format, AS_WRITTEN))
        }
        InputFormat::OffsetTable => {
            Ok(ReadOutcome::plain(parse_offset_table(text, source, units)?, format, AS_WRITTEN))
        }
        InputFormat::Series60Table => {
            let (dims, mut notes) = match options.dimensions {
                Some(d) => (d, Vec::new()),
                None => (
                    MainDimensions::SERIES60_CB060,
                    vec![format!(
                        "no Lpp, B, T given: the Cb 0.60 parent's Lpp {} m, B {} m, T {} m assumed (L/B 7.5, \
                            B/T 2.5; right for the Cb 0.60 parent only)",
                        MainDimensions::SERIES60_CB060.lpp,
                        MainDimensions::SERIES60_CB060.beam,
                        MainDimensions::SERIES60_CB060.draft
                    )],
                ),
            };
            let t = parse_series60_table(text, source, dims, units, options.suspicious)?;
            notes.push("the SAR column (sectional area ratios) is not an offset and is not read".into());
            Ok(ReadOutcome {
                offsets: t.offsets,
                format,
                axes: format!(
                    "converted from Todd's stations: x = (1 - station/20) Lpp from the AP, forward; y = cell \
                        x MaxBm x B/2; z = (z/T) T; with Lpp {}, B {}, T {} {}",
                    dims.lpp, dims.beam, dims.draft, units
                ),
                notes,
                suspicious: t.suspicious,
                disagreements: Vec::new(),
                warnings: Vec::new(),
            })
        }
        InputFormat::LongCsv => long_csv::parse_long_csv(text, source, options),
        InputFormat::JsonTable => json_table::parse_json_table(text, source, options, dir),
        InputFormat::PointCloud => point_cloud::parse_point_cloud(text, source, units),
        InputFormat::FreeshipOffsets => freeship::parse_freeship_offsets(text, source, options),
        InputFormat::FreeshipCurves => freeship::parse_freeship_curves(text, source, units),
    }
}

/// Checks raw bytes are UTF-8 text and returns them as a `&str`.
///
/// # Errors
///
/// [`InputErrorKind::Utf16`] for a UTF-16 byte-order mark, [`InputErrorKind::Binary`] for
/// invalid UTF-8 or a NUL byte, located at the line of the first bad byte.
pub fn decode<'a>(bytes: &'a [u8], source: &str) -> Result<&'a str, HullError> {
    if bytes.starts_with(&[0xFF, 0xFE]) || bytes.starts_with(&[0xFE, 0xFF]) || looks_utf16(bytes) {
        return Err(HullError::input(Location::line(source, 1), InputErrorKind::Utf16));
    }
    let line_of = |pos: usize| 1 + bytes[..pos].iter().filter(|&&b| b == b'\n').count();
    let text = std::str::from_utf8(bytes).map_err(|e| {
        let pos = e.valid_up_to();
        HullError::input(
            Location::line(source, line_of(pos)),
            InputErrorKind::Binary { detail: format!("invalid UTF-8 at byte offset {pos}") },
        )
    })?;
    check_no_nul(text, source)?;
    Ok(text)
}

/// UTF-16 without a byte-order mark: ASCII text in UTF-16 has a NUL in every other byte. True
/// when, over the first 64 bytes (at least 4), all the odd bytes or all the even bytes are NUL
/// and none of the others is.
fn looks_utf16(bytes: &[u8]) -> bool {
    let head = &bytes[..bytes.len().min(64) & !1];
    if head.len() < 4 {
        return false;
    }
    let nul_at = |parity: usize| head.iter().skip(parity).step_by(2).all(|&b| b == 0);
    let none_at = |parity: usize| head.iter().skip(parity).step_by(2).all(|&b| b != 0);
    (nul_at(1) && none_at(0)) || (nul_at(0) && none_at(1))
}

/// A NUL character never occurs in a CSV text: its presence means a binary file.
fn check_no_nul(text: &str, source: &str) -> Result<(), HullError> {
    match text.find('\0') {
        Some(pos) => Err(HullError::input(
            Location::line(source, 1 + text[..pos].matches('\n').count()),
            InputErrorKind::Binary { detail: format!("NUL byte at byte offset {pos}") },
        )),
        None => Ok(()),
    }
}

/// One field of a record: its trimmed (and unquoted) text and 1-based column.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Field<'a> {
    pub text: Cow<'a, str>,
    pub column: usize,
}

/// One data line: its 1-based line number and all its fields (at least one not empty).
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct Record<'a> {
    pub line: usize,
    pub fields: Vec<Field<'a>>,
}

impl Record<'_> {
    /// The number of fields up to the last non-empty one: spreadsheets often append empty
    /// fields, which carry nothing.
    pub fn significant_len(&self) -> usize {
        self.fields.iter().rposition(|f| !f.text.is_empty()).map_or(0, |i| i + 1)
    }

    /// The place of field `column` (1-based).
    pub fn at(&self, source: &str, column: usize) -> Location {
        Location::new(source, self.line, column)
    }
}

/// Splits a text into records (see the module docs for the rules).
///
/// # Errors
///
/// Binary text (NUL), an unterminated quote, text after a closing quote, or a line that uses
/// another delimiter than the file's first data line (`;` or tabs in a comma file,
/// [`InputErrorKind::Separator`]; any other, [`InputErrorKind::SeparatorChange`]).
pub(crate) fn records<'a>(text: &'a str, source: &str) -> Result<Vec<Record<'a>>, HullError> {
    check_no_nul(text, source)?;
    let text = text.strip_prefix('\u{FEFF}').unwrap_or(text);
    let mut out = Vec::new();
    let mut delimiter = None;
    for (i, line) in split_lines(text).enumerate() {
        let lineno = i + 1;
        let trimmed = line.trim();
        if trimmed.is_empty() || trimmed.starts_with('#') {
            continue;
        }
        let (sep, first_line) = *delimiter.get_or_insert((delimiter_of(trimmed), lineno));
        let mut fields = split_fields(line, sep, source, lineno)?;
        if fields.iter().all(|f| f.text.is_empty()) {
            continue; // ",,,": an empty spreadsheet row
        }
        if sep != ',' {
            for f in &mut fields {
                if let Some(number) = decimal_comma_number(&f.text) {
                    f.text = Cow::Owned(number);
                }
            }
        }
        if fields.len() == 1 {
            let other = [',', ';', '\t'].into_iter().find(|&c| c != sep && fields[0].text.contains(c));
            match other {
                Some(separator) if sep == ',' => {
                    return Err(HullError::input(
                        Location::line(source, lineno),
                        InputErrorKind::Separator { separator },
                    ))
                }
                Some(separator) => {
                    return Err(HullError::input(
                        Location::line(source, lineno),
                        InputErrorKind::SeparatorChange { separator, expected: sep, first_line },
                    ))
                }
                None => {}
            }
        }
        out.push(Record { line: lineno, fields });
    }
    Ok(out)
}

/// The delimiter a file's first data line sets (see the module docs): `;`, else a tab, when the
/// line holds it and every piece between them holds at most one comma, not at either end (a
/// decimal comma); else `,`.
fn delimiter_of(first: &str) -> char {
    let splits_cleanly = |sep: char| {
        first.contains(sep)
            && first
                .split(sep)
                .map(str::trim)
                .all(|p| p.matches(',').count() <= 1 && !p.starts_with(',') && !p.ends_with(','))
    };
    [';', '\t'].into_iter().find(|&sep| splits_cleanly(sep)).unwrap_or(',')
}

/// `1,5` as `1.5`: a field holding one comma, no point, that reads as a finite number once the
/// comma is a point; `None` for anything else (labels, `1.000,5`, `1,2,3`).
fn decimal_comma_number(text: &str) -> Option<String> {
    if text.matches(',').count() != 1 || text.contains('.') {
        return None;
    }
    let number = text.replacen(',', ".", 1);
    // The digits around the comma must be digits: `,5` and `5,` are written by no spreadsheet.
    let (before, after) = text.split_once(',')?;
    let digit_ends = before.ends_with(|c: char| c.is_ascii_digit()) && after.starts_with(|c: char| c.is_ascii_digit());
    (digit_ends && number.parse::<f64>().is_ok_and(f64::is_finite)).then_some(number)
}

/// Lines of `text`, ended by `\r\n`, `\n` or a lone `\r`; a final line end does not start
/// one more (empty) line.
pub(crate) fn split_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut rest = Some(text);
    std::iter::from_fn(move || {
        let s = rest?;
        match s.find(['\r', '\n']) {
            Some(i) => {
                let skip = if s[i..].starts_with("\r\n") { 2 } else { 1 };
                let after = &s[i + skip..];
                rest = if after.is_empty() { None } else { Some(after) };
                Some(&s[..i])
            }
            None => {
                rest = None;
                Some(s)
            }
        }
    })
}

/// Splits one line at `sep` into trimmed fields, unquoting `"..."` fields.
fn split_fields<'a>(line: &'a str, sep: char, source: &str, lineno: usize) -> Result<Vec<Field<'a>>, HullError> {
    // A tab delimiter is not a blank to trim.
    let is_blank = |c: char| c == ' ' || (c == '\t' && sep != '\t');
    let mut fields = Vec::new();
    let mut rest = line;
    loop {
        let column = fields.len() + 1;
        let start = rest.trim_start_matches(is_blank);
        if let Some(quoted) = start.strip_prefix('"') {
            // A quoted field: up to the first quote not doubled.
            let mut value = String::new();
            let mut chars = quoted.char_indices();
            let end = loop {
                match chars.next() {
                    None => {
                        return Err(HullError::input(
                            Location::new(source, lineno, column),
                            InputErrorKind::UnterminatedQuote,
                        ))
                    }
                    Some((i, '"')) => {
                        if quoted[i + 1..].starts_with('"') {
                            value.push('"');
                            chars.next();
                        } else {
                            break i + 1;
                        }
                    }
                    Some((_, c)) => value.push(c),
                }
            };
            let after = &quoted[end..];
            let (stray, next) = match after.find(sep) {
                Some(i) => (&after[..i], Some(&after[i + sep.len_utf8()..])),
                None => (after, None),
            };
            if !stray.trim_matches(is_blank).is_empty() {
                return Err(HullError::input(
                    Location::new(source, lineno, column),
                    InputErrorKind::TextAfterQuote { text: stray.trim_matches(is_blank).to_string() },
                ));
            }
            fields.push(Field { text: Cow::Owned(value.trim_matches(is_blank).to_string()), column });
            match next {
                Some(n) => rest = n,
                None => break,
            }
        } else {
            match start.find(sep) {
                Some(i) => {
                    fields.push(Field { text: Cow::Borrowed(start[..i].trim_matches(is_blank)), column });
                    rest = &start[i + sep.len_utf8()..];
                }
                None => {
                    fields.push(Field { text: Cow::Borrowed(start.trim_matches(is_blank)), column });
                    break;
                }
            }
        }
    }
    Ok(fields)
}

/// Parses a finite decimal number from a field, saying what it should have been otherwise.
///
/// # Errors
///
/// [`InputErrorKind::EmptyField`], [`InputErrorKind::DecimalComma`],
/// [`InputErrorKind::NotFinite`] (`nan`, `inf`, overflow) or [`InputErrorKind::NotANumber`].
pub(crate) fn parse_number(
    text: &str,
    at: impl FnOnce() -> Location,
    expected: impl FnOnce() -> String,
) -> Result<f64, HullError> {
    if text.is_empty() {
        return Err(HullError::input(at(), InputErrorKind::EmptyField { expected: expected() }));
    }
    let text_ = shown(text);
    let kind = match text.parse::<f64>() {
        Ok(v) if v.is_finite() => return Ok(v),
        // Rust's parser takes "nan", "inf", "infinity" in any case, and overflows to inf.
        Ok(_) => InputErrorKind::NotFinite { text: text_, expected: expected() },
        Err(_) if text.contains(',') && text.replacen(',', ".", 1).parse::<f64>().is_ok_and(f64::is_finite) => {
            InputErrorKind::DecimalComma { text: text_, expected: expected() }
        }
        Err(_) => InputErrorKind::NotANumber { text: text_, expected: expected() },
    };
    Err(HullError::input(at(), kind))
}

/// A field as quoted in a message: whole up to 64 characters, else its first 64 and its length,
/// so that a runaway field (a file of one 100 MB line) does not flood the terminal.
pub(crate) fn shown(text: &str) -> String {
    const MAX: usize = 64;
    match text.char_indices().nth(MAX) {
        None => text.to_string(),
        Some((end, _)) => format!("{}... ({} characters)", &text[..end], text.chars().count()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn texts(recs: &[Record<'_>]) -> Vec<(usize, Vec<String>)> {
        recs.iter().map(|r| (r.line, r.fields.iter().map(|f| f.text.to_string()).collect())).collect()
    }

    fn err_of<T: std::fmt::Debug>(r: Result<T, HullError>) -> String {
        r.err().map(|e| e.to_string()).unwrap_or_else(|| "no error".into())
    }

    #[test]
    fn line_ends_bom_comments_and_blank_lines() {
        let text = "\u{FEFF}a, b ,c\r\n\r\n# comment\n  \n, ,\r4,5\n";
        let recs = records(text, "t").expect("valid text");
        assert_eq!(
            texts(&recs),
            vec![(1, vec!["a".into(), "b".into(), "c".into()]), (6, vec!["4".into(), "5".into()])]
        );
    }

    #[test]
    fn line_numbers_count_every_line_whatever_the_line_ends() {
        for nl in ["\n", "\r\n", "\r"] {
            let text = ["x", "", "y", "", "", "z"].join(nl) + nl;
            let lines: Vec<usize> = records(&text, "t").expect("valid").iter().map(|r| r.line).collect();
            assert_eq!(lines, vec![1, 3, 6], "line end {nl:?}");
        }
    }

    #[test]
    fn quoted_fields() {
        let recs = records("\"a,b\", \"say \"\"hi\"\"\" ,\"\"\n", "t").expect("valid");
        assert_eq!(texts(&recs), vec![(1, vec!["a,b".into(), "say \"hi\"".into(), "".into()])]);
        assert_eq!(
            err_of(records("a,\"open\n", "q.csv")),
            "q.csv:1:2: quoted field has no closing quote (expected a closing \" on the same line)"
        );
        assert!(
            err_of(records("x\na,\"b\"c,d\n", "q.csv")).starts_with("q.csv:2:2: text \"c\" follows the closing quote")
        );
    }

    #[test]
    fn trailing_empty_fields_are_kept_but_not_significant() {
        let recs = records("1,,3,,\n", "t").expect("valid");
        assert_eq!(texts(&recs), vec![(1, vec!["1".into(), "".into(), "3".into(), "".into(), "".into()])]);
        assert_eq!(recs[0].fields[2].column, 3);
        assert_eq!(recs[0].significant_len(), 3);
    }

    #[test]
    fn other_separators_are_named() {
        assert_eq!(
            err_of(records("# c\nsection,x,y,z\na;1;2;3\n", "s.csv")),
            "s.csv:3: fields are separated by semicolons (expected commas, as on the file's first data line: one \
             delimiter for the whole file)"
        );
        assert!(err_of(records("a,b\nc\td\n", "s.csv")).contains("separated by tabs"));
        assert_eq!(
            err_of(records("\n# c\na;b\nc;d\ne,1,2\n", "s.csv")),
            "s.csv:5: fields are separated by commas (expected semicolons as on line 3, the file's first data \
             line: one delimiter for the whole file)"
        );
        assert!(err_of(records("a\tb\nc,d,e\n", "s.csv")).contains("expected tabs as on line 1"));
    }

    #[test]
    fn semicolon_and_tab_files_take_decimal_commas() {
        let want = vec![
            (1, vec!["s".to_string(), "x".into(), "y".into()]),
            (2, vec!["a".into(), "1.5".into(), "-0.25".into()]),
        ];
        // A European spreadsheet's CSV, with CRLF and a BOM.
        assert_eq!(texts(&records("\u{FEFF}s;x;y\r\na;1,5;-0,25\r\n", "t").expect("valid")), want);
        // Tabs (a spreadsheet's text export); the tab is the delimiter, not a blank to trim.
        assert_eq!(texts(&records("s\tx\ty\na\t1,5\t-0,25\n", "t").expect("valid")), want);
        assert_eq!(texts(&records("s\tx\ty\na\t1.5 \t -0.25\n", "t").expect("valid")), want);
        // A quoted cell, exponents, a label that is no number, and grouped thousands left alone
        // (the reader then says that "1.000,5" is not a number).
        let recs = records("s;x\na;\"2,45\";1,5E-3;B,C;1.000,5;1,2,3\n", "t").expect("valid");
        assert_eq!(texts(&recs)[1].1, vec!["a", "2.45", "1.5E-3", "B,C", "1.000,5", "1,2,3"]);
        // Only a `;` or tab file converts: in a comma file `1,5` is two fields.
        assert_eq!(texts(&records("a,1,5\n", "t").expect("valid"))[0].1, vec!["a", "1", "5"]);
        // The first data line sets the delimiter, even a line of decimal commas only; a comma
        // file aligned with tabs, or with a `;` in a label, stays a comma file.
        assert_eq!(delimiter_of("z\\x;0;2,5;5"), ';');
        assert_eq!(delimiter_of("0,5;1,5;2,5"), ';');
        assert_eq!(delimiter_of("z\\x\t0\t2,5\t5"), '\t');
        assert_eq!(delimiter_of("0,\t1.5,\t2"), ',');
        assert_eq!(delimiter_of("\"a;b\",1,2,3"), ',');
        assert_eq!(delimiter_of("section,x,y,z"), ',');
    }

    #[test]
    fn long_fields_are_shortened_in_messages() {
        let long = "9".repeat(10_000) + "x";
        let e = err_of(parse_number(&long, || Location::new("n.csv", 1, 1), || "a number".into()));
        assert!(e.len() < 200, "{e}");
        assert!(e.contains(&format!("\"{}... (10001 characters)\" is not a number", "9".repeat(64))), "{e}");
        assert_eq!(shown("é".repeat(64).as_str()), "é".repeat(64));
    }

    #[test]
    fn binary_input_is_recognised() {
        assert_eq!(
            err_of(decode(b"ab\ncd\0", "b.bin")),
            "b.bin:2: binary file, NUL byte at byte offset 5 (expected a CSV text)"
        );
        assert_eq!(
            err_of(decode(b"a\nb\nc\xff", "b.bin")),
            "b.bin:3: binary file, invalid UTF-8 at byte offset 5 (expected a CSV text)"
        );
        assert!(err_of(decode(b"\xff\xfes\0e\0", "u.csv")).contains("UTF-16"));
        // Without a byte-order mark, little- and big-endian, told by the NUL of every other byte.
        assert_eq!(err_of(decode(b"s\0e\0c\0\n\0", "u.csv")), err_of(decode(b"\xff\xfes\0", "u.csv")));
        assert!(err_of(decode(b"\0s\0e\0c\0\n", "u.csv")).contains("UTF-16"));
        assert!(err_of(decode(b"ab\0\0", "b.bin")).contains("NUL byte"));
        assert!(err_of(records("a\0", "s")).contains("binary file"));
        assert_eq!(decode(b"ok", "s").ok(), Some("ok"));
    }

    #[test]
    fn numbers() {
        let at = || Location::new("n.csv", 3, 2);
        let what = || "the x coordinate in metres".to_string();
        for (t, v) in [("1", 1.0), ("-2.5", -2.5), ("+.5", 0.5), ("1e3", 1000.0), ("7.", 7.0), ("-0", 0.0)] {
            assert_eq!(parse_number(t, at, what).ok(), Some(v), "{t}");
        }
        for t in ["nan", "NaN", "inf", "-Infinity", "1e999"] {
            assert_eq!(
                err_of(parse_number(t, at, what)),
                format!("n.csv:3:2: \"{t}\" is not a finite number (expected the x coordinate in metres)")
            );
        }
        assert_eq!(
            err_of(parse_number("abc", at, what)),
            "n.csv:3:2: \"abc\" is not a number (expected the x coordinate in metres)"
        );
        assert_eq!(
            err_of(parse_number("1,5", at, what)),
            "n.csv:3:2: \"1,5\" has a decimal comma (expected the x coordinate in metres, written with a decimal point)"
        );
        assert_eq!(err_of(parse_number("", at, what)), "n.csv:3:2: empty field (expected the x coordinate in metres)");
        assert!(err_of(parse_number("0x10", at, what)).contains("is not a number"));
    }

    #[test]
    fn format_detection() {
        assert_eq!(detect_format("\u{FEFF}# c\n Section , X,y,z\n"), InputFormat::SectionsCsv);
        assert_eq!(detect_format("z\\x,0,1\n0,1,2\n"), InputFormat::OffsetTable);
        assert_eq!(detect_format(""), InputFormat::OffsetTable);
        assert_eq!(detect_format(",,\n\n# section,x,y,z\nsection,x,y,z\n"), InputFormat::SectionsCsv);
        // A header naming x, y and z columns (and a label column) is a long CSV.
        assert_eq!(detect_format("sections,x,y,z\n"), InputFormat::LongCsv);
        assert_eq!(detect_format("x,z,y\n1,2,3\n"), InputFormat::LongCsv);
        assert_eq!(detect_format(",0,0.5,1,SAR\n0,0,0,0,0\nMaxBm,1,1,1\n"), InputFormat::Series60Table);
        assert_eq!(detect_format("{\"a\": 1}"), InputFormat::JsonTable);
        assert_eq!(detect_format("  1.0  2.0  3.0\n"), InputFormat::PointCloud);
        assert_eq!(detect_format("station 3 x = 1\n0 0\n1 1\n"), InputFormat::PointCloud);
        assert_eq!(detect_format("0\n1 2 3\n"), InputFormat::FreeshipCurves);
        assert_eq!(detect_format("Station 12.000\n  12.0 0.0 1.0\n"), InputFormat::FreeshipOffsets);
        assert_eq!(detect_format("section\tx\ty\tz\n"), InputFormat::SectionsCsv);
        assert_eq!(detect_format("section;x;y;z\n"), InputFormat::SectionsCsv);
        assert_eq!(detect_format("z\\x\t0\t2,5\n0\t1,5\t2\n"), InputFormat::OffsetTable);
    }

    fn testdata(name: &str) -> std::path::PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(name)
    }

    #[test]
    fn read_offsets_sniffs_both_example_files() {
        let s = read_offsets(&testdata("sections_example.csv"), Units::Metre).expect("sections example");
        assert_eq!((s.sections.len(), s.num_points()), (3, 12));
        assert!(s.source.ends_with("sections_example.csv"));
        let t = read_offsets(&testdata("offsets_example.csv"), Units::Foot).expect("offsets example");
        assert_eq!((t.sections.len(), t.num_points(), t.units), (4, 19, Units::Foot));
    }

    #[test]
    fn an_offset_table_rewritten_as_a_sections_csv_reads_back_the_same() {
        let table = read_offsets(&testdata("offsets_example.csv"), Units::Metre).expect("offsets example");
        let mut text = String::from("section,x,y,z\n");
        for s in &table.sections {
            for p in &s.points {
                // `{}` prints the shortest decimal that parses back to the same f64.
                text.push_str(&format!("{},{},{},{}\n", s.label, p.x, p.y, p.z));
            }
        }
        let csv = parse_offsets(&text, "rewritten.csv", Units::Metre).expect("rewritten");
        assert_eq!(csv.sections.len(), table.sections.len());
        for (a, b) in csv.sections.iter().zip(&table.sections) {
            assert_eq!((&a.label, &a.points), (&b.label, &b.points));
        }
    }

    #[test]
    fn min_points_drops_short_sections_of_the_new_formats_only() {
        let cloud = "0 0 0\n0 1 1\n0 2 2\n5 0 0\n5 1 1\n";
        let options = ReadOptions { min_points: 3, ..ReadOptions::default() };
        let o = parse_offsets_with(cloud, "c.dat", &options).expect("valid");
        assert_eq!(o.offsets.sections.len(), 1);
        assert!(o.notes.iter().any(|n| n == "sections with fewer than 3 points left out: x5 (2)"), "{:?}", o.notes);
        let csv = "section,x,y,z\na,0,0,0\na,0,1,1\na,0,2,2\nb,5,0,0\nb,5,1,1\n";
        let o = parse_offsets_with(csv, "s.csv", &options).expect("valid");
        assert_eq!(o.offsets.sections.len(), 2, "a sections CSV keeps them for validate to report");
    }

    #[test]
    fn read_offsets_reports_a_missing_file_with_its_path() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("missing.csv");
        let e = err_of(read_offsets(&path, Units::Metre));
        assert!(e.starts_with(&format!("{}: ", path.display())), "{e}");
    }

    #[test]
    fn read_offsets_reports_a_binary_file() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("hull.png");
        std::fs::write(&path, b"\x89PNG\r\n\x1a\n\0\0\0\rIHDR").expect("write");
        let e = err_of(read_offsets(&path, Units::Metre));
        assert_eq!(
            e,
            format!("{}:1: binary file, invalid UTF-8 at byte offset 0 (expected a CSV text)", path.display())
        );
    }
}

#[cfg(test)]
mod fuzz {
    //! The readers never panic: any input gives `Ok` or `Err`.

    use super::*;
    use proptest::prelude::*;

    fn all_readers(text: &str) {
        for units in Units::ALL {
            let _ = parse_sections_csv(text, "f", units);
            let _ = parse_offset_table(text, "f", units);
            let _ = parse_offsets(text, "f", units);
        }
        for format in InputFormat::ALL {
            let options = ReadOptions {
                format: Some(format),
                dimensions: Some(MainDimensions { lpp: 100.0, beam: 10.0, draft: 5.0 }),
                ..ReadOptions::default()
            };
            let _ = parse_offsets_with(text, "f", &options);
        }
        if let Ok(o) = parse_offsets(text, "f", Units::Metre) {
            let _ = o.validate(4);
            let _ = o.validate(0);
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig { cases: 2000, ..ProptestConfig::default() })]

        #[test]
        fn arbitrary_strings_never_panic(text in any::<String>()) {
            all_readers(&text);
        }

        #[test]
        fn arbitrary_bytes_never_panic(bytes in proptest::collection::vec(any::<u8>(), 0..300)) {
            if let Ok(text) = decode(&bytes, "f") {
                all_readers(text);
            }
            all_readers(&String::from_utf8_lossy(&bytes));
        }

        /// Text of the whitespace formats reaches their deeper paths.
        #[test]
        fn point_text_never_panics(
            head in prop_oneof![Just("0\n"), Just("Station 1.000\n"), Just("station x = 2\n"), Just("")],
            body in "([0-9\\. \\-e]{0,14}(\n|SEGMENT 1\n|2 segments.\n|Waterline 1.0\n|Buttock 0.5\n)){0,12}",
        ) {
            all_readers(&format!("{head}{body}"));
        }

        /// JSON-like text reaches the JSON readers' deeper paths.
        #[test]
        fn json_like_text_never_panics(
            body in "\\{(\"[0-9a-zA-Z站号WL]{0,5}\": ?(\\[[0-9null, .\\-]{0,12}\\]|[0-9.\\-]{0,4}|\\{\\}),? ?){0,6}\\}",
        ) {
            all_readers(&body);
            all_readers(&format!("{{\"structure\": {{\"hull\": {{\"attributes\": {{\"LOA\": 1, \"BOA\": 1, \"Depth\": 1}}, \"halfBreadths\": {body}}}}}}}"));
        }

        /// CSV-like text reaches the deeper paths (numbers, order checks, validation).
        #[test]
        fn csv_like_text_never_panics(
            head in prop_oneof![Just("section,x,y,z\n"), Just("z\\x,0,1,2\n"), Just(",0,0.5,1,SAR\nMaxBm,1,1,1\n"), Just("x,z,y,kind\n"), Just("")],
            body in "([0-9a-z\\.,\"# \\-+e]{0,12}(\n|\r\n|\r)){0,12}",
        ) {
            all_readers(&format!("{head}{body}"));
            all_readers(&format!("\u{FEFF}{head}{body}"));
        }

        /// Well-formed sections CSVs parse, keep every point, and report lines that exist.
        #[test]
        fn generated_sections_csv_round_trips(
            sections in proptest::collection::vec(proptest::collection::vec((-1e3f64..1e3, 0f64..1e3, -1e3f64..1e3), 1..6), 1..6),
        ) {
            let mut text = String::from("section,x,y,z\n");
            for (i, s) in sections.iter().enumerate() {
                for (x, y, z) in s {
                    text.push_str(&format!("s{i},{x},{y},{z}\n"));
                }
            }
            let o = parse_sections_csv(&text, "f", Units::Metre).map_err(|e| TestCaseError::fail(e.to_string()))?;
            prop_assert_eq!(o.sections.len(), sections.len());
            let n_lines = text.lines().count();
            for (s, want) in o.sections.iter().zip(&sections) {
                // `{}` of an f64 prints the shortest text that parses back to the same value.
                let pts: Vec<(f64, f64, f64)> = s.points.iter().map(|p| (p.x, p.y, p.z)).collect();
                prop_assert_eq!(&pts, want);
                prop_assert!(s.lines.iter().all(|&l| (2..=n_lines).contains(&l)));
            }
        }
    }
}
