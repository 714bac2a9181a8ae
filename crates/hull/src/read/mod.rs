//! Readers of offset data, told apart by their content.
//!
//! The rest of this module's documentation is on [`read_offsets`], where the library's users read it.

mod cad;
mod freeship;
mod iges;
mod json_table;
mod long_csv;
mod offset_table;
mod point_cloud;
mod sections_csv;
mod sense;
mod series60_table;
mod step;
mod views;

mod detect;
mod records;
#[cfg(test)]
mod tests;
mod text;

use std::path::Path;

use crate::error::{HullError, Location};
use crate::offsets::Offsets;
use crate::units::Units;

pub use cad::{parse_as, parse_cad_surfaces, read_cad_surfaces, CadFormat, CadSurface, CadSurfaces};
pub use detect::{detect_format, InputFormat};
pub use freeship::{is_header, parse_freeship_curves, parse_freeship_offsets};
pub use iges::parse_iges;
pub use json_table::{is_offset_json, parse_json_table};
pub use long_csv::parse_long_csv;
pub use offset_table::parse_offset_table;
pub use point_cloud::parse_point_cloud;
pub(crate) use records::{parse_number, records, shown, split_lines, Record};
pub use sections_csv::{parse_sections_csv, write_sections_csv};
pub use sense::{OutlierPolicy, SenseKind, SenseWarning, OUTLIER_SHARE};
pub use series60_table::{parse_series60_table, MainDimensions, Series60Table};
pub use step::parse_step;
pub use text::decode;
pub use views::{Disagreement, MergeOptions, Merged, Station, ThreeViews, View, ViewLine, DEFAULT_TOLERANCE_REL};

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
    /// What to do with outlier cells (README, "Plausible mistakes (sense checks)").
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
    /// Plausible mistakes found by the sense checks (README, "Plausible mistakes"): units, size,
    /// transposition,
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
/// | format | reader | recognised by |
/// |---|---|---|
/// | sections CSV `section,x,y,z` | [`parse_sections_csv`] | first field `section` |
/// | offset table (stations across, waterlines down) | [`parse_offset_table`] | any other CSV |
/// | Todd's Series 60 table (fractions, `MaxBm` row) | [`parse_series60_table`] | a `MaxBm` row |
/// | long CSV, one point a row, columns by name (`x,z,y`, ...) | [`parse_long_csv`] | a header naming x, y and z columns |
/// | JSON offset tables (vessel.js ship, OpenHull table) | [`parse_json_table`] | first character `{` |
/// | station point clouds (`x y z` or `y z` blocks) | [`parse_point_cloud`] | whitespace-separated numbers |
/// | FREE!ship offsets export and curve import text | [`parse_freeship_offsets`] | a `Station 1.000` line, or a first line `0`/`1` |
///
/// B-spline *surfaces* (not offsets) are read from IGES and STEP files by [`parse_cad_surfaces`] ([`parse_iges`],
/// [`parse_step`]), through [`read_cad_surfaces`].
///
/// The CSV formats are delimited text, UTF-8 (a byte-order mark is skipped; UTF-16 is refused
/// with a message saying so), with `\n`, `\r\n` or `\r` line ends, mixed as they come.
/// Fields are trimmed of spaces and tabs; a field may be quoted with `"` (a doubled `""` inside
/// stands for one quote; a quoted field ends on its own line). Blank lines, lines of empty
/// fields only (`,,,` as spreadsheets export them), and lines whose first non-blank character is
/// `#` are skipped. `nan` and `inf` are refused.
///
/// The delimiter is the file's, set by its first data line (the first line neither blank nor a
/// comment): a semicolon when that line holds one and none of the pieces between them holds more
/// than one comma or starts or ends with one (a European spreadsheet's CSV: `z\x;0;2,5;5`), else
/// a tab by the same rule (a spreadsheet's text export), else a comma (so `"a;b",1,2` and
/// `0,<tab>1.5,<tab>2` are comma files). Every later line must use the same delimiter (a line that uses
/// another is refused at its place). With a comma delimiter numbers use a decimal point (a
/// decimal comma splits the number into two fields, and the messages say so). With a `;` or
/// tab delimiter, and only then, a field that is a number written with one decimal comma and
/// no point (`1,5`, `-0,25`, `1,5e-3`) is read as that number with a decimal point (`1.5`);
/// a field with both (`1.000,5`, thousands grouped) is not a number.
///
/// Errors point at `file:line:column`, with 1-based line numbers of the file and 1-based
/// field numbers as columns (CSV fields; whitespace-separated tokens in the text formats;
/// characters in JSON) (see [`crate::Location`]).
///
/// Every reader converts to hullskin's axes (x forward from the aft end or AP, y the
/// half-breadth >= 0, z up from the baseline) and [`read_offsets_with`] says in
/// [`ReadOutcome::axes`] which axes it assumed or how it converted, with notes, suspicious
/// values and disagreements between the views of a lines plan.
///
/// The readers parse; they do not check the data can be skinned: call
/// [`Offsets::validate`] with the fit's degree + 1 for that.
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
