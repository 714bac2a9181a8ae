//! The hull crate's one error type.
//!
//! Input errors read like a compiler's: `path:line:col: message (expected ...)`, e.g.
//!
//! ```text
//! hull.csv:7:3: "abc" is not a number (expected the y coordinate in metres)
//! ```
//!
//! Lines are 1-based lines of the file (blank and comment lines count). Columns are 1-based
//! CSV *field* numbers (the third comma-separated field is column 3, whatever its character
//! offset), because offsets are edited in spreadsheets as often as in text editors. When a
//! place is not known (a model built in code, or a whole-file problem) the line or column is
//! left out.

use std::fmt;
use std::path::PathBuf;

use thiserror::Error;

/// Where in an input a problem lies: file (or other source name), 1-based line and 1-based
/// field column, the latter two when known.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct Location {
    /// The file path as given by the user, or a name such as `built-in sample` or `<stdin>`.
    pub file: String,
    /// 1-based line number in the file (blank and comment lines counted).
    pub line: Option<usize>,
    /// 1-based CSV field number on that line.
    pub column: Option<usize>,
}

impl Location {
    /// A place in `file` at `line`, `column` (both 1-based).
    pub fn new(file: &str, line: usize, column: usize) -> Self {
        Location { file: file.to_string(), line: Some(line), column: Some(column) }
    }

    /// A whole line of `file`.
    pub fn line(file: &str, line: usize) -> Self {
        Location { file: file.to_string(), line: Some(line), column: None }
    }

    /// The whole of `file`.
    pub fn file(file: &str) -> Self {
        Location { file: file.to_string(), line: None, column: None }
    }
}

impl fmt::Display for Location {
    /// `file:line:col`, `file:line` or `file`.
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(&self.file)?;
        if let Some(line) = self.line {
            write!(f, ":{line}")?;
            if let Some(col) = self.column {
                write!(f, ":{col}")?;
            }
        }
        Ok(())
    }
}

/// How the caller's user names the inputs the library checks, for the messages
/// ([`crate::table_drafts`], [`crate::ExportFormat::for_file`]): `--draft` on the command line,
/// `draft` as a keyword argument.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum InputNames {
    /// Command-line flags: `--draft`, `--to`, `--step`, `--density`.
    Flags,
    /// Keyword arguments: `draft`, `to`, `step`, `density`.
    Keywords,
}

impl InputNames {
    /// What goes before an input's name: `--` or nothing.
    pub fn prefix(self) -> &'static str {
        match self {
            InputNames::Flags => "--",
            InputNames::Keywords => "",
        }
    }
}

/// Everything that can go wrong in the hull crate. Variants carry the offending values.
#[derive(Debug, Error)]
pub enum HullError {
    /// A file could not be read (or written).
    #[error("{}: {error}", path.display())]
    Io {
        /// The path that failed.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// The input data are wrong at a known place: a parse error or a failed validation.
    #[error("{at}: {kind}")]
    Input {
        /// Where.
        at: Location,
        /// What, with what was expected (boxed to keep `Result<_, HullError>` small).
        kind: Box<InputErrorKind>,
    },
    /// The kernel could not fit a surface with the requested settings.
    #[error("{method} fit failed: {reason}")]
    Fit {
        /// The fitting method.
        method: &'static str,
        /// The kernel's reason (in the message; not a chained `source`, so it prints once).
        reason: nurbs::NurbsError,
    },
    /// Settings that cannot work, whatever the data.
    #[error("{0}")]
    Config(String),
    /// A units name that is none of `m`, `mm`, `ft`, `in`.
    #[error("unknown units \"{0}\" (expected m, mm, ft or in)")]
    UnknownUnits(String),
    /// A draft the hydrostatics cannot use: not finite, or above the top of the surface.
    #[error("draft {draft}: {reason}")]
    Draft {
        /// The draft asked for.
        draft: f64,
        /// Why it cannot be used, with what was expected.
        reason: String,
    },
    /// An input above one of the documented caps (README, "Limits") (boxed to keep
    /// `Result<_, HullError>` small).
    #[error("{0}")]
    Limit(Box<LimitExceeded>),
    /// No control-point count tried reached the requested max error.
    #[error(
        "no control-point count reaches max error {tolerance:.3e} {units}: the best max error is {best:.3e} {units} at {}x{} control points after {fits} fits (expected a tolerance of at least that)",
        control_points.0,
        control_points.1
    )]
    ToleranceNotReached {
        /// The tolerance asked for.
        tolerance: f64,
        /// The smallest max error found (infinite if no fit was done).
        best: f64,
        /// Where it was found `(nu, nv)`.
        control_points: (usize, usize),
        /// Fits done.
        fits: usize,
        /// Units of the distances.
        units: &'static str,
    },
    /// A surface that must not be written: a non-finite control point, a weight that is not
    /// finite and positive, or a bad knot vector ([`crate::check_finite`]).
    #[error("the surface cannot be written: {problem} (expected finite control points, finite positive weights and valid knot vectors)")]
    UnwritableSurface {
        /// What is wrong, with its place, e.g. `control point (2, 3) is (NaN, 0, 1)`.
        problem: String,
    },
}

impl HullError {
    /// An input error at `at`.
    pub(crate) fn input(at: Location, kind: InputErrorKind) -> Self {
        HullError::Input { at, kind: Box::new(kind) }
    }

    /// The place of an input error, if this is one.
    pub fn location(&self) -> Option<&Location> {
        match self {
            HullError::Input { at, .. } => Some(at),
            _ => None,
        }
    }

    /// The kind of an input error, if this is one.
    pub fn input_kind(&self) -> Option<&InputErrorKind> {
        match self {
            HullError::Input { kind, .. } => Some(kind),
            _ => None,
        }
    }
}

/// What is wrong with the input data. Each message ends with what was expected instead.
#[derive(Clone, Debug, PartialEq, Error)]
pub enum InputErrorKind {
    // ----- the file as a whole -----
    /// NUL bytes or invalid UTF-8.
    #[error("binary file, {detail} (expected a CSV text)")]
    Binary {
        /// What was found and where, e.g. "NUL byte at byte offset 12".
        detail: String,
    },
    /// A UTF-16 byte-order mark (a spreadsheet's "Unicode text").
    #[error("file is UTF-16 encoded (expected UTF-8 CSV text; save it as \"CSV UTF-8\")")]
    Utf16,
    /// Nothing but blank and comment lines.
    #[error("no data: the file is empty or holds only blank and comment lines (expected a sections CSV with the header section,x,y,z, or an offset table)")]
    Empty,

    // ----- tokenizing -----
    /// A line holding no comma but `;` or a tab, in a file whose first data line set commas.
    #[error("fields are separated by {} (expected commas, as on the file's first data line: one delimiter for the whole file)", separator_name(*.separator))]
    Separator {
        /// The separator found.
        separator: char,
    },
    /// A line with one field that holds another delimiter than the file's (set by its first
    /// data line): `;` or tab files whose later lines use commas, and the like.
    #[error("fields are separated by {} (expected {} as on line {first_line}, the file's first data line: one delimiter for the whole file)", separator_name(*.separator), separator_name(*.expected))]
    SeparatorChange {
        /// The separator found.
        separator: char,
        /// The file's delimiter.
        expected: char,
        /// The line that set it.
        first_line: usize,
    },
    /// A quoted field without its closing quote on the same line.
    #[error("quoted field has no closing quote (expected a closing \" on the same line)")]
    UnterminatedQuote,
    /// Text between a closing quote and the next comma.
    #[error("text {text:?} follows the closing quote (expected a comma or the end of the line)")]
    TextAfterQuote {
        /// The stray text.
        text: String,
    },

    // ----- fields -----
    /// A field that should be a number and is not.
    #[error("\"{text}\" is not a number (expected {expected})")]
    NotANumber {
        /// The field as written (trimmed).
        text: String,
        /// What the field should hold.
        expected: String,
    },
    /// A number written with a decimal comma, e.g. `"1,5"`.
    #[error("\"{text}\" has a decimal comma (expected {expected}, written with a decimal point)")]
    DecimalComma {
        /// The field as written.
        text: String,
        /// What the field should hold.
        expected: String,
    },
    /// `nan`, `inf`, `1e999`...: Rust would parse them, hullskin refuses them.
    #[error("\"{text}\" is not a finite number (expected {expected})")]
    NotFinite {
        /// The field as written.
        text: String,
        /// What the field should hold.
        expected: String,
    },
    /// A required field left empty.
    #[error("empty field (expected {expected})")]
    EmptyField {
        /// What the field should hold.
        expected: String,
    },
    /// A row with the wrong number of fields.
    #[error("row has {got} fields (expected {expected}: {layout}){}", decimal_comma_hint(*.got, *.expected))]
    FieldCount {
        /// Fields found (trailing empty fields not counted).
        got: usize,
        /// Fields wanted.
        expected: usize,
        /// The layout wanted, e.g. `section,x,y,z`.
        layout: String,
    },
    /// A header field other than the one required.
    #[error("header field \"{got}\" (expected \"{expected}\": a sections CSV starts with the header section,x,y,z)")]
    BadHeader {
        /// The field found.
        got: String,
        /// The field wanted.
        expected: String,
    },
    /// A first row that starts with a number: data, not a header.
    #[error("the first row starts with the number {text} (expected a header: section,x,y,z for a sections CSV, or for an offset table a corner cell such as z\\x, then the station positions)")]
    MissingHeader {
        /// The first field.
        text: String,
    },
    /// A header and no data rows.
    #[error("no data rows after the header (expected {expected})")]
    NoRows {
        /// What the rows should hold.
        expected: String,
    },

    // ----- sections CSV -----
    /// The rows of a section are not all together.
    #[error("section \"{label}\" appears again; its earlier rows end on line {previous_line} (expected the rows of each section together, one section after another along the length)")]
    NonConsecutiveSection {
        /// The section label.
        label: String,
        /// The last line of the earlier run of rows.
        previous_line: usize,
    },

    // ----- offset table -----
    /// The header has no station columns.
    #[error(
        "offset table header has no station columns (expected a corner cell then station positions x: z\\x,x1,x2,...)"
    )]
    NoStations,
    /// A station column without any half-breadth.
    #[error("station x = {x} has no half-breadth in any waterline row (expected at least one cell in its column)")]
    EmptyStation {
        /// The station position.
        x: f64,
    },
    /// Station positions not strictly monotone from left to right.
    #[error("station x = {x} is not {} x = {previous} in column {previous_column} (expected station positions strictly {} from left to right, as set by the first two stations)", if *.increasing { "greater than" } else { "less than" }, if *.increasing { "increasing" } else { "decreasing" })]
    StationOrder {
        /// The offending station.
        x: f64,
        /// The station before it.
        previous: f64,
        /// The column of the station before it.
        previous_column: usize,
        /// The direction set by the first two stations.
        increasing: bool,
    },
    /// Waterline heights not strictly monotone from top to bottom.
    #[error("waterline z = {z} is not {} z = {previous} on line {previous_line} (expected waterline heights strictly {} from top to bottom, as set by the first two waterlines)", if *.increasing { "greater than" } else { "less than" }, if *.increasing { "increasing" } else { "decreasing" })]
    WaterlineOrder {
        /// The offending waterline height.
        z: f64,
        /// The waterline before it.
        previous: f64,
        /// The line of the waterline before it.
        previous_line: usize,
        /// The direction set by the first two waterlines.
        increasing: bool,
    },
    /// A negative half-breadth.
    #[error("half-breadth {y} is negative (expected a half-breadth y >= 0; leave the cell empty where the station has no offset)")]
    NegativeHalfBreadth {
        /// The value read.
        y: f64,
    },
    /// A cell to the right of the last station column.
    #[error("cell \"{text}\" lies beyond the last station column {last_column} (expected at most {last_column} cells per row, as many as the header; numbers with decimal commas split into extra cells: use decimal points)")]
    ExtraCell {
        /// The cell's text.
        text: String,
        /// The last column of the header.
        last_column: usize,
    },

    // ----- validation of a parsed model (Offsets::validate) -----
    /// Fewer than two sections.
    #[error("{got} section(s) (expected at least 2 sections to skin a surface)")]
    TooFewSections {
        /// Sections found.
        got: usize,
    },
    /// A section with fewer points than the fit needs.
    #[error(
        "section \"{label}\" has {got} point(s) (expected at least {needed} points per section: the fit's degree + 1)"
    )]
    TooFewPoints {
        /// The section label.
        label: String,
        /// Points found.
        got: usize,
        /// Points needed.
        needed: usize,
    },
    /// Two consecutive points of a section coincide (and the section is not a single point).
    #[error("section \"{label}\": point {}{} repeats point {}{} at ({}, {}, {}) (expected distinct consecutive points; only a pointed end may collapse to one point, all its points equal)", .index + 1, line_note(*.line), .index, line_note(*.previous_line), .point[0], .point[1], .point[2])]
    RepeatedPoint {
        /// The section label.
        label: String,
        /// 0-based index of the second point of the pair in the section.
        index: usize,
        /// Its source line, when known.
        line: Option<usize>,
        /// The source line of the first point of the pair, when known.
        previous_line: Option<usize>,
        /// The repeated coordinates.
        point: [f64; 3],
    },
    /// A coordinate that is NaN or infinite.
    #[error("section \"{label}\": point {} has a non-finite coordinate ({}, {}, {}) (expected finite numbers)", .index + 1, .point[0], .point[1], .point[2])]
    NonFiniteCoordinate {
        /// The section label.
        label: String,
        /// 0-based index of the point in the section.
        index: usize,
        /// The coordinates.
        point: [f64; 3],
    },
    /// A model too large or too small for f64 arithmetic (see `hull::MIN_SIZE`).
    #[error("the model's size (bounding-box diagonal) is {size:e} with coordinates up to {largest:e}{} (expected a size between 1e-50 and 1e50 in the file's units: check the units and the exponents)", model_size_at(.at))]
    ModelSize {
        /// The bounding-box diagonal (may be infinite).
        size: f64,
        /// The largest absolute coordinate.
        largest: f64,
        /// The section label and 0-based point index of the largest coordinate, for a model too
        /// large.
        at: Option<(String, usize)>,
    },
    /// A section between the first and the last that collapses to one point.
    #[error("section \"{label}\" collapses to one point ({}, {}, {}) (expected a section of extent: only the first and last sections, a pointed stern or stem, may be one point)", .point[0], .point[1], .point[2])]
    PointSection {
        /// The section label.
        label: String,
        /// The point.
        point: [f64; 3],
    },
    /// Two segments of a section cross each other.
    #[error("section \"{label}\" crosses itself: its segment from point {} to {}{} crosses its segment from point {} to {}{} (expected the points in order along the section, keel to deck, without a loop)", .segment.0 + 1, .segment.0 + 2, lines_note(.segment.1, .segment.2), .crossed.0 + 1, .crossed.0 + 2, lines_note(.crossed.1, .crossed.2))]
    SectionCrosses {
        /// The section label.
        label: String,
        /// The later segment: 0-based index of its first point, and the source lines of its
        /// two points when known.
        segment: (usize, Option<usize>, Option<usize>),
        /// The earlier segment it crosses, the same way.
        crossed: (usize, Option<usize>, Option<usize>),
    },
    /// Sections (all planar in x) out of order along the length.
    #[error("section \"{label}\" at x = {x} is not {} section \"{previous_label}\" at x = {previous_x} (expected sections in order along the length, x strictly {} as set by the first two sections)", if *.increasing { "forward of" } else { "aft of" }, if *.increasing { "increasing" } else { "decreasing" })]
    SectionOrder {
        /// The offending section.
        label: String,
        /// Its x.
        x: f64,
        /// The section before it.
        previous_label: String,
        /// Its x.
        previous_x: f64,
        /// The direction set by the first two sections.
        increasing: bool,
    },

    // ----- meshes (STL, OBJ) -----
    /// A mesh file that breaks its format, or a mesh that cannot be sliced: what was found
    /// (with the byte offset for binary files) and what was expected.
    #[error("{found} (expected {expected})")]
    Mesh {
        /// What was found, e.g. `"vertx"` or `the header claims 1000 triangles, 3 fit`.
        found: String,
        /// What the format asks for there.
        expected: String,
    },

    // ----- offset formats of `read` (Series 60 tables, long CSV, JSON, point clouds, FREE!ship) -----
    /// A value, line or structure that the format does not allow: what was found and what the
    /// format asks for there.
    #[error("{found} (expected {expected})")]
    Unexpected {
        /// What was found, e.g. `station 21 lies beyond the AP`.
        found: String,
        /// What the format asks for there.
        expected: String,
    },

    // ----- CAD surfaces read by `read::iges` and `read::step` -----
    /// An IGES or STEP file that breaks its format, or an entity that cannot be a B-spline
    /// surface: which entity (and parameter), what was found and what was expected.
    #[error("{entity}: {found} (expected {expected})")]
    Cad {
        /// The entity and parameter, e.g. `entity 128 at D 3, parameter 12 (S(0))` or
        /// `#42 CARTESIAN_POINT`; `file` for the file as a whole.
        entity: String,
        /// What was found, e.g. `"1.0.0" is not a number`.
        found: String,
        /// What the format asks for there.
        expected: String,
    },

    // ----- drawings read by `digitize` (DXF and SVG body plans) -----
    /// A drawing that breaks its format, or a drawn curve that cannot be a station: what was
    /// found and what was expected.
    #[error("{found} (expected {expected})")]
    Drawing {
        /// What was found, e.g. `group code "abc" is not an integer`.
        found: String,
        /// What the format or the digitiser asks for there.
        expected: String,
    },
}

fn separator_name(c: char) -> String {
    match c {
        '\t' => "tabs".to_string(),
        ';' => "semicolons".to_string(),
        ',' => "commas".to_string(),
        c => format!("{c:?}"),
    }
}

fn decimal_comma_hint(got: usize, expected: usize) -> &'static str {
    if got > expected {
        "; numbers with decimal commas split into extra fields: use decimal points"
    } else {
        ""
    }
}

fn model_size_at(at: &Option<(String, usize)>) -> String {
    match at {
        Some((label, index)) => format!(" (section \"{label}\", point {})", index + 1),
        None => String::new(),
    }
}

fn lines_note(a: Option<usize>, b: Option<usize>) -> String {
    match (a, b) {
        (Some(a), Some(b)) => format!(" (lines {a}-{b})"),
        _ => String::new(),
    }
}

fn line_note(line: Option<usize>) -> String {
    match line {
        Some(l) => format!(" (line {l})"),
        None => String::new(),
    }
}

/// An input above one of the caps: what was counted, how many, the cap, and what was
/// expected. Prints as `input: 3,200,000 points exceed the cap of 2,000,000 (expected ...;
/// see README Limits)`.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct LimitExceeded {
    /// The input (a path as given, or a name such as `surface JSON`).
    pub input: String,
    /// What was counted, plural: `points`, `points in section "7"`, `bytes`.
    pub what: String,
    /// How many there are (or are claimed).
    pub value: u64,
    /// The cap.
    pub cap: u64,
    /// What is accepted, e.g. `at most 2,000,000 offsets in all`.
    pub expected: String,
}

impl LimitExceeded {
    /// `value` of `what` in `input` against `cap`; `expected` says what is accepted.
    pub fn new(input: &str, what: impl Into<String>, value: u64, cap: u64, expected: impl Into<String>) -> Self {
        LimitExceeded { input: input.to_string(), what: what.into(), value, cap, expected: expected.into() }
    }
}

impl fmt::Display for LimitExceeded {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "{}: {} {} exceed the cap of {} (expected {}; see README Limits)",
            self.input,
            crate::numfmt::thousands(self.value),
            self.what,
            crate::numfmt::thousands(self.cap),
            self.expected
        )
    }
}

impl std::error::Error for LimitExceeded {}

impl From<LimitExceeded> for HullError {
    fn from(e: LimitExceeded) -> Self {
        HullError::Limit(Box::new(e))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn location_prints_like_a_compiler() {
        assert_eq!(Location::new("hull.csv", 7, 3).to_string(), "hull.csv:7:3");
        assert_eq!(Location::line("hull.csv", 7).to_string(), "hull.csv:7");
        assert_eq!(Location::file("hull.csv").to_string(), "hull.csv");
    }

    #[test]
    fn input_error_reads_path_line_col_message_expected() {
        let e = HullError::input(
            Location::new("hull.csv", 7, 3),
            InputErrorKind::NotANumber { text: "abc".into(), expected: "the y coordinate in metres".into() },
        );
        assert_eq!(e.to_string(), "hull.csv:7:3: \"abc\" is not a number (expected the y coordinate in metres)");
        assert_eq!(e.location().map(|l| (l.line, l.column)), Some((Some(7), Some(3))));
        assert!(matches!(e.input_kind(), Some(InputErrorKind::NotANumber { .. })));
    }

    #[test]
    fn io_error_names_the_path() {
        let e = HullError::Io {
            path: PathBuf::from("dir/none.csv"),
            error: std::io::Error::new(std::io::ErrorKind::NotFound, "gone"),
        };
        assert_eq!(e.to_string(), "dir/none.csv: gone");
        assert!(e.location().is_none());
    }

    #[test]
    fn hints_appear_only_where_they_apply() {
        let more = InputErrorKind::FieldCount { got: 7, expected: 4, layout: "section,x,y,z".into() };
        assert!(more.to_string().contains("decimal commas"), "{more}");
        let fewer = InputErrorKind::FieldCount { got: 3, expected: 4, layout: "section,x,y,z".into() };
        assert!(!fewer.to_string().contains("decimal commas"), "{fewer}");
        let sep = InputErrorKind::Separator { separator: ';' };
        assert!(sep.to_string().starts_with("fields are separated by semicolons"), "{sep}");
    }

    #[test]
    fn repeated_point_counts_from_one_and_names_both_lines() {
        let k = InputErrorKind::RepeatedPoint {
            label: "7".into(),
            index: 2,
            line: Some(12),
            previous_line: Some(11),
            point: [1.0, 2.5, 0.0],
        };
        assert_eq!(
            k.to_string(),
            "section \"7\": point 3 (line 12) repeats point 2 (line 11) at (1, 2.5, 0) (expected distinct \
             consecutive points; only a pointed end may collapse to one point, all its points equal)"
        );
    }
}
