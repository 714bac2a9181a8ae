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
#[non_exhaustive]
pub enum HullError {
    /// A file could not be read (or written).
    #[error("{}: {error}", path.display())]
    Io {
        /// The path that failed.
        path: PathBuf,
        /// The operating system's error.
        error: std::io::Error,
    },
    /// An input that needs an optional part of the crate which this build left out: a
    /// gzip-compressed mesh without the cargo feature `gzip`, an SVG drawing without `svg`.
    #[error(
        "{source_name}: {input} needs the cargo feature `{feature}` of hullskin-hull, which this build leaves out \
         (build with it, or give the input in another form)"
    )]
    FeatureDisabled {
        /// The input, as named in messages (a file name).
        source_name: String,
        /// What it is, e.g. `a gzip-compressed mesh`.
        input: &'static str,
        /// The cargo feature that reads it, e.g. `gzip`.
        feature: &'static str,
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
    /// A numeric setting out of its range: its name as the caller's user wrote it (`--density`,
    /// `density`, `weld tolerance`), the value given, and what is accepted.
    #[error("{name} {value}: expected {expected}")]
    Setting {
        /// The setting, e.g. `--density` or `hydrostatics order`.
        name: String,
        /// The value given (a count is given as a float).
        value: f64,
        /// What is accepted, e.g. `a positive density in t/m³`.
        expected: &'static str,
    },
    /// A fitting or optimiser setting out of its range (fairness, weight smoothing,
    /// regularization, search scale, the tolerance of a control-point search).
    #[error("{name} {value} is not usable (expected {expected})")]
    FitSetting {
        /// The setting, e.g. `fairness`.
        name: &'static str,
        /// The value given.
        value: f64,
        /// What is accepted, e.g. `a finite number >= 0`.
        expected: &'static str,
    },
    /// A fitting degree outside what the kernel supports.
    #[error("degree {degree} in {direction} is not supported (expected 1 to {max})")]
    Degree {
        /// The degree asked for.
        degree: usize,
        /// The direction, e.g. `u (along the sections)`.
        direction: &'static str,
        /// The highest supported degree ([`nurbs::MAX_DEGREE`]).
        max: usize,
    },
    /// A range of drafts `from, from + step, ...` up to `to` that cannot be walked.
    #[error("{}", draft_range_message(*.from, *.to, *.step, kind))]
    DraftRange {
        /// The first draft.
        from: f64,
        /// The last draft.
        to: f64,
        /// The step.
        step: f64,
        /// What is wrong with the range.
        kind: DraftRangeKind,
    },
    /// A range end (`to`) without a step or a step without a range end.
    #[error("{p}to and {p}step go together (a range of drafts from {p}draft to `{p}to` by `{p}step`)", p = names.prefix())]
    DraftStepWithoutTo {
        /// How the caller's user names them.
        names: InputNames,
    },
    /// No hull surface to compute hydrostatics of.
    #[error("hydrostatics of no surface: expected at least one patch")]
    NoSurface,
    /// The forward and aft perpendiculars cannot be placed.
    #[error("perpendiculars: AP at x = {aft}, Lpp {lpp}: expected a finite AP and a positive Lpp")]
    Perpendiculars {
        /// x of the AP.
        aft: f64,
        /// Length between perpendiculars.
        lpp: f64,
    },
    /// A main dimension (Lpp, B or T) that is missing (NaN) or not a finite positive length.
    #[error("{}", main_dimension_message(name, *.value))]
    MainDimension {
        /// `Lpp`, `B` or `T`.
        name: &'static str,
        /// The value given; NaN when it was not given.
        value: f64,
    },
    /// An export format that cannot be chosen or used as asked.
    #[error("{0}")]
    Format(FormatKind),
    /// A polynomial approximation tolerance that cannot be met (a tessellation's is a
    /// [`HullError::Kernel`] error).
    #[error("{}", export_tolerance_message(*.tolerance, kind))]
    ExportTolerance {
        /// The tolerance asked for.
        tolerance: f64,
        /// Why it cannot be met.
        kind: ExportToleranceKind,
    },
    /// An error of the kernel outside a fit, printed as the kernel words it: a tessellation
    /// tolerance that cannot be met ([`nurbs::NurbsError::TessellationFloor`],
    /// `TessellationGridLines`, `TessellationRounding`), a mesh with a non-finite vertex or a
    /// triangle index out of range (`NonFiniteVertex`, `TriangleIndex`).
    #[error("{0}")]
    Kernel(nurbs::NurbsError),
    /// A surface that cannot be mirrored into a whole hull (`--mirror`).
    #[error("--mirror: {0}")]
    Mirror(MirrorKind),
    /// A control-point search to a tolerance with the interpolation method, whose count is
    /// fixed.
    #[error("a tolerance needs a method whose control points can vary (expected approx, ga, pso, gsa, lm or gsa+lm; interp always has one control point per offset)")]
    ToleranceWithInterp,
    /// A held-out error estimate that cannot be made.
    #[error("{0}")]
    HeldOut(HeldOutKind),
    /// Weights (and control points) that cannot be optimised as asked.
    #[error("{0}")]
    Weights(WeightsKind),
    /// A mesh that cannot be sliced into sections as asked.
    #[error("{0}")]
    Slice(SliceKind),
    /// An axes mapping (`--axes`) other than a signed permutation of x, y, z.
    #[error("axes \"{text}\": expected three comma-separated axes naming each of x, y, z once, each optionally negated, giving hullskin's x (forward), y (starboard) and z (up), e.g. x,y,z or z,x,y or -x,-y,z")]
    UnknownAxes {
        /// The mapping as given.
        text: String,
    },
    /// A drawing that cannot be digitised with the settings given (scale, datum, station
    /// positions).
    #[error("{0}")]
    Digitize(DigitizeKind),
    /// An output directory that cannot be staged.
    #[error("cannot write outputs into {}: expected a directory other than the filesystem's root", path.display())]
    OutputDirectory {
        /// The directory asked for.
        path: PathBuf,
    },
    /// An output name that is not a plain file name (`../x`, `a/b`, empty).
    #[error("output name {name:?}: expected a plain file name")]
    OutputName {
        /// The name asked for.
        name: String,
    },
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

    /// Whether this is an error of the settings rather than of the data or the computation:
    /// settings that cannot work whatever the data (a degree, a tolerance, a fairness, units
    /// or a format that cannot be used), or a request that cannot be met as asked (a surface
    /// that cannot be mirrored, offsets too few to hold any out, a mesh that gives too few
    /// sections). False for input, fit, I/O, limit, draft and tolerance-search errors.
    pub fn is_setting(&self) -> bool {
        matches!(
            self,
            HullError::Setting { .. }
                | HullError::FitSetting { .. }
                | HullError::Degree { .. }
                | HullError::DraftRange { .. }
                | HullError::DraftStepWithoutTo { .. }
                | HullError::NoSurface
                | HullError::Perpendiculars { .. }
                | HullError::MainDimension { .. }
                | HullError::Format(_)
                | HullError::ExportTolerance { .. }
                | HullError::Kernel(
                    nurbs::NurbsError::TessellationFloor { .. }
                        | nurbs::NurbsError::TessellationGridLines { .. }
                        | nurbs::NurbsError::TessellationRounding { .. }
                )
                | HullError::Mirror(_)
                | HullError::ToleranceWithInterp
                | HullError::HeldOut(_)
                | HullError::Weights(_)
                | HullError::Slice(_)
                | HullError::UnknownAxes { .. }
                | HullError::UnknownUnits(_)
                | HullError::Digitize(_)
                | HullError::OutputDirectory { .. }
                | HullError::OutputName { .. }
        )
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
#[non_exhaustive]
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

    // ----- meshes (STL, OBJ, VRML) -----
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

/// What is wrong with a range of drafts ([`HullError::DraftRange`]).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
#[non_exhaustive]
pub enum DraftRangeKind {
    /// `from`, `to` or `step` is not finite.
    NotFinite,
    /// A step of 0.
    ZeroStep,
    /// A step of the wrong sign: it goes away from `to`.
    AwayFromTo,
    /// More drafts than the cap.
    TooMany {
        /// The cap ([`crate::hydrostatics::MAX_DRAFTS`]).
        max: usize,
    },
}

fn draft_range_message(from: f64, to: f64, step: f64, kind: &DraftRangeKind) -> String {
    match kind {
        DraftRangeKind::NotFinite => format!("draft range from {from} to {to} step {step}: expected finite numbers"),
        DraftRangeKind::ZeroStep => "draft step 0: expected a non-zero step".to_string(),
        DraftRangeKind::AwayFromTo => {
            format!("draft step {step} goes away from {to} (from {from}): expected a step of the sign of to - from")
        }
        DraftRangeKind::TooMany { max } => {
            format!("draft range from {from} to {to} step {step} holds more than {max} drafts: expected a larger step")
        }
    }
}

fn main_dimension_message(name: &str, value: f64) -> String {
    if value.is_nan() {
        format!("{name} not given (expected Lpp, B and T to scale a Series 60 table: --lpp, --beam, --design-draft)")
    } else {
        format!("{name} = {value} (expected a finite positive length)")
    }
}

/// Why an export format cannot be chosen or used ([`HullError::Format`]). Formats are named
/// by [`crate::ExportFormat::name`] (`stl`, `iges-polynomial`) and families by
/// [`crate::ExportFormat::family`] (`STEP`, `IGES`, `mesh`...).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum FormatKind {
    /// No format given and the output's extension names none.
    #[error("cannot tell the format from {} (expected an extension .stp, .step, .igs, .iges, .dxf, .stl, .obj or .glb, or {}format)", path.display(), names.prefix())]
    Unknown {
        /// The output path.
        path: PathBuf,
        /// How the caller's user names the inputs.
        names: InputNames,
    },
    /// A format given whose family is not the one the output's extension names.
    #[error("{p}format {format} writes a {family} file, but {} names a {named_family} file: name it {} or pass {p}format {named}", path.display(), path.with_extension(extension).display(), p = names.prefix())]
    ExtensionMismatch {
        /// The format given.
        format: &'static str,
        /// Its family.
        family: &'static str,
        /// Its file extension.
        extension: &'static str,
        /// The output path.
        path: PathBuf,
        /// The format the path's extension names.
        named: &'static str,
        /// Its family.
        named_family: &'static str,
        /// How the caller's user names the inputs.
        names: InputNames,
    },
    /// A tolerance given for a format that takes none.
    #[error("{}tolerance applies to stl, stl-ascii, obj, glb and iges-polynomial, not {format}", names.prefix())]
    NoTolerance {
        /// The format given.
        format: &'static str,
        /// How the caller's user names the inputs.
        names: InputNames,
    },
}

/// Why an export tolerance cannot be met ([`HullError::ExportTolerance`]).
#[derive(Clone, Copy, Debug, PartialEq)]
#[non_exhaustive]
pub enum ExportToleranceKind {
    /// A polynomial approximation tolerance below the floor, or not a positive finite length.
    ApproximationFloor {
        /// The smallest accepted tolerance.
        floor: f64,
        /// The floor as a fraction of the surface's size.
        relative: f64,
    },
    /// A polynomial approximation that would need more control points per direction than
    /// the cap.
    ControlPoints {
        /// The cap.
        max: usize,
        /// Refinements done.
        refinements: usize,
        /// The deviation of the best approximation.
        deviation: f64,
    },
}

fn export_tolerance_message(tol: f64, kind: &ExportToleranceKind) -> String {
    match *kind {
        ExportToleranceKind::ApproximationFloor { floor, relative } => format!(
            "approximation tolerance {tol}: expected a length of at least {floor:.3e} ({relative:e} of the surface's \
             size; below that rounding dominates)"
        ),
        ExportToleranceKind::ControlPoints { max, refinements, deviation } => format!(
            "a polynomial surface within {tol} needs more than {max} control points per direction (the best after \
             {refinements} refinements deviates by {deviation}; expected a larger tolerance)"
        ),
    }
}

/// Why a surface cannot be mirrored into a whole hull ([`HullError::Mirror`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum MirrorKind {
    /// No edge of the surface runs along the ship.
    #[error("no edge of the surface runs along the ship (over half its x extent) to join the halves along (expected a hull surface, x along the ship; a mesh format mirrors any surface)")]
    NoLongitudinalEdge,
    /// The surface lies port of the centre plane.
    #[error(
        "the surface lies port of the centre plane (largest y {largest_y:.4e}; expected the starboard half, y >= 0)"
    )]
    PortSide {
        /// The largest y of the control net.
        largest_y: f64,
    },
    /// The kernel refused the mirrored surface.
    #[error("{0}")]
    Kernel(nurbs::NurbsError),
}

/// Why a held-out error cannot be estimated ([`HullError::HeldOut`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum HeldOutKind {
    /// Fewer than 2 folds.
    #[error("held-out error with {folds} folds (expected at least 2 folds, e.g. {default}; 0 turns it off)")]
    Folds {
        /// The folds asked for.
        folds: usize,
        /// The default number of folds.
        default: usize,
    },
    /// Neither sections nor points to hold out.
    #[error("held-out error with nothing to hold out (expected sections, points or both)")]
    NothingAsked,
    /// Offsets too few to hold any out for the degrees.
    #[error("no offset of {offsets} can be held out: {sections} sections of at most {most} points leave too few for degrees {},{} (expected at least {} sections, or a section of at least {} points)", degree.0, degree.1, degree.1 + 2, degree.0 + 2)]
    TooFewOffsets {
        /// The offsets' source.
        offsets: String,
        /// Their sections.
        sections: usize,
        /// The points of the largest section.
        most: usize,
        /// The degrees `(p, q)` of the fit.
        degree: (usize, usize),
    },
    /// A run that no stop can end was stopped.
    #[error("held-out error stopped before its end")]
    Stopped,
}

/// Why weights (and control points) cannot be optimised as asked ([`HullError::Weights`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum WeightsKind {
    /// Weight bounds that do not hold 1, or not positive and finite.
    #[error("weight bounds ({lo}, {hi}) are not usable (expected 0 < lo <= 1 <= hi, finite)")]
    Bounds {
        /// The lower bound.
        lo: f64,
        /// The upper bound.
        hi: f64,
    },
    /// Not one parameter pair per offset, or no offset.
    #[error("{offsets} offsets with {params} parameters (expected as many parameters as offsets, at least one)")]
    ParameterCount {
        /// Offsets given.
        offsets: usize,
        /// Parameter pairs given.
        params: usize,
    },
    /// An offset with a non-finite coordinate.
    #[error("offset {index} is not finite (expected finite coordinates)")]
    NonFiniteOffset {
        /// Its 0-based index.
        index: usize,
    },
    /// An offset with non-finite parameters.
    #[error("parameters of offset {index} are not finite (expected finite (u, v))")]
    NonFiniteParameters {
        /// Its 0-based index.
        index: usize,
    },
    /// A fit whose parameters are not those of the offsets given.
    #[error("the fit's parameters do not match the offsets (expected the fit of these offsets)")]
    FitMismatch,
    /// A vector of variables of the wrong length or with a non-finite entry.
    #[error("{got} weight variables (expected {expected} finite numbers)")]
    Variables {
        /// Its length.
        got: usize,
        /// The problem's dimension.
        expected: usize,
    },
    /// Control points held in a box while the control points are not re-solved.
    #[error("control points held in a box need re-solved control points")]
    BoxNeedsResolved,
    /// A box with `lo > hi` in some coordinate.
    #[error("control-point box {lo:?}..{hi:?} is empty (expected lo <= hi in each coordinate)")]
    EmptyBox {
        /// The low corner.
        lo: [f64; 3],
        /// The high corner.
        hi: [f64; 3],
    },
}

/// Why a mesh cannot be sliced into sections as asked ([`HullError::Slice`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum SliceKind {
    /// A station count of 0 or above the cap.
    #[error("{count} stations: expected 1 to {max}")]
    StationCount {
        /// The count asked for.
        count: usize,
        /// The cap ([`crate::MAX_STATIONS`]).
        max: usize,
    },
    /// A range for the stations that is not finite and increasing.
    #[error("station range {min} .. {max}: expected a finite, increasing range")]
    StationRange {
        /// Its start.
        min: f64,
        /// Its end.
        max: f64,
    },
    /// Station positions not strictly increasing.
    #[error("stations at x = {previous} then {x}: expected strictly increasing positions")]
    StationOrder {
        /// The station before.
        previous: f64,
        /// The station not after it.
        x: f64,
    },
    /// A station position that is not finite.
    #[error("station at x = {x}: expected a finite position")]
    StationNotFinite {
        /// The position.
        x: f64,
    },
    /// Points per section outside 2 and the cap.
    #[error("{count} points per section: expected 2 to {max} (README, Limits)")]
    Points {
        /// The count asked for.
        count: usize,
        /// The cap ([`crate::limits::MAX_POINTS_PER_SECTION`]).
        max: usize,
    },
    /// A deck angle outside `[0, 90)` degrees.
    #[error("deck angle {degrees} degrees: expected 0 to 90 (excluded)")]
    DeckAngle {
        /// The angle asked for.
        degrees: f64,
    },
    /// A height limit that is not finite.
    #[error("max z: expected a finite height")]
    MaxZ {
        /// The height asked for.
        z: f64,
    },
    /// A mesh without triangles.
    #[error("{mesh}: the mesh has no triangles")]
    EmptyMesh {
        /// The mesh's source (its path as given).
        mesh: String,
    },
    /// Fewer than 2 stations give a section.
    #[error(
        "{mesh}: {sections} of {stations} stations give a section (expected at least 2); {}",
        dropped_list(dropped)
    )]
    TooFewSections {
        /// The mesh's source (its path as given).
        mesh: String,
        /// Sections found.
        sections: usize,
        /// Stations tried.
        stations: usize,
        /// The stations dropped: x and why.
        dropped: Vec<(f64, String)>,
    },
}

fn dropped_list(dropped: &[(f64, String)]) -> String {
    let why: Vec<String> =
        dropped.iter().map(|(x, reason)| format!("x = {}: {reason}", crate::numfmt::format_short(*x))).collect();
    why.join("; ")
}

/// Why a drawing cannot be digitised with the settings given ([`HullError::Digitize`]).
#[derive(Clone, Debug, PartialEq, Error)]
#[non_exhaustive]
pub enum DigitizeKind {
    /// A scale given as text that is neither `P:M` nor a positive number.
    #[error("scale {text:?} (expected paper:model such as 1:50, or drawing units per output unit such as 20)")]
    UnreadableScale {
        /// The text given.
        text: String,
    },
    /// A scale in drawing units per model unit that is not positive and finite.
    #[error("scale {scale} drawing units per {units} (expected a number > 0)")]
    ScalePerUnit {
        /// The scale given.
        scale: f64,
        /// The model's unit symbol.
        units: &'static str,
    },
    /// A ratio scale `paper:model` whose terms are not positive and finite.
    #[error("scale {paper}:{model} (expected two numbers > 0 such as 1:50)")]
    Ratio {
        /// Paper term.
        paper: f64,
        /// Model term.
        model: f64,
    },
    /// A ratio scale on a drawing that does not say its unit of length, none given.
    #[error("{drawing}: the drawing does not say its unit of length, so the scale {paper}:{model} cannot be applied (expected the drawing units given, e.g. --drawing-units mm, or the scale as drawing units per {units})")]
    NoDrawingUnit {
        /// The drawing's source (its path as given).
        drawing: String,
        /// Paper term.
        paper: f64,
        /// Model term.
        model: f64,
        /// The model's unit symbol.
        units: &'static str,
    },
    /// A drawing unit that is not a positive length.
    #[error("drawing unit of {mm} mm (expected a length > 0)")]
    DrawingUnit {
        /// The unit in millimetres.
        mm: f64,
    },
    /// A datum that is not two finite numbers.
    #[error("datum {x},{y} (expected two finite numbers X,Y)")]
    Datum {
        /// Drawing x of the datum.
        x: f64,
        /// Drawing y of the datum.
        y: f64,
    },
    /// Fewer than 2 points per station.
    #[error("{count} points per station (expected at least 2)")]
    Points {
        /// The count asked for.
        count: usize,
    },
    /// Not one station position per station curve.
    #[error("{drawing}: {} station curves found ({}) and {given} station positions given (expected one position per station, in that order)", found.len(), found.join(", "))]
    StationCount {
        /// The drawing's source (its path as given).
        drawing: String,
        /// The names of the station curves found, in order.
        found: Vec<String>,
        /// The positions given.
        given: usize,
    },
    /// A station position in a list that is not finite.
    #[error("station position {x} (expected finite numbers)")]
    StationPosition {
        /// The position.
        x: f64,
    },
    /// A named station position that is not finite.
    #[error("station {name}={x} (expected a finite position)")]
    NamedStation {
        /// The station's name as given.
        name: String,
        /// The position.
        x: f64,
    },
    /// Named positions for stations told apart by their order.
    #[error("stations told apart by their order have no names: give their positions as a list x1,x2,... (expected no NAME=x entries)")]
    NamesByOrder,
    /// A station spacing that is not finite and non-zero.
    #[error("station spacing {spacing} from {origin} (expected finite numbers, a spacing other than 0)")]
    Spacing {
        /// The first station's position.
        origin: f64,
        /// The spacing.
        spacing: f64,
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

impl From<nurbs::NurbsError> for HullError {
    /// [`HullError::Kernel`]: the kernel's error as it is (a fit's failure is
    /// [`HullError::Fit`] instead, which names the method).
    fn from(e: nurbs::NurbsError) -> Self {
        HullError::Kernel(e)
    }
}

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

    // ----- the settings errors carry the offending values and word the messages as before -----

    #[test]
    fn a_draft_range_going_away_from_its_end_carries_the_range() {
        let e = crate::draft_range(1.0, 2.0, -0.5).expect_err("the step points away");
        match &e {
            HullError::DraftRange { from, to, step, kind: DraftRangeKind::AwayFromTo } => {
                assert_eq!((*from, *to, *step), (1.0, 2.0, -0.5));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            e.to_string(),
            "draft step -0.5 goes away from 2 (from 1): expected a step of the sign of to - from"
        );
        let e = crate::draft_range(0.0, 1.0, 1e-9).expect_err("too many drafts");
        assert!(matches!(e, HullError::DraftRange { kind: DraftRangeKind::TooMany { max: 10_000 }, .. }), "{e:?}");
        assert_eq!(
            e.to_string(),
            "draft range from 0 to 1 step 0.000000001 holds more than 10000 drafts: expected a larger step"
        );
        assert!(e.is_setting());
    }

    #[test]
    fn a_kernel_tessellation_error_is_a_setting_with_the_kernel_message() {
        let s = nurbs::fixtures::quarter_cylinder_along_x(2.0, 3.0);
        let options = nurbs::TessellationOptions { tolerance: 1e-12, mirror: false };
        let kernel = crate::tessellate(&s, &options).expect_err("below the floor");
        let e = HullError::from(kernel.clone());
        assert!(e.is_setting() && matches!(&e, HullError::Kernel(k) if *k == kernel), "{e:?}");
        assert_eq!(e.to_string(), kernel.to_string());
        assert_eq!(
            e.to_string(),
            "tessellation tolerance 0.000000000001: expected a length of at least 4.123e-7 (1e-7 of the surface's size)"
        );
        // A mesh error is the data's, not a setting.
        let mesh = crate::TriMesh::try_new("m.obj", vec![], vec![[0, 0, 0]]).expect_err("no vertices");
        assert!(!HullError::from(mesh).is_setting());
    }

    #[test]
    fn a_setting_is_named_as_the_user_wrote_it() {
        let e = crate::table_drafts(Some(-1.0), None, None, 1.025, InputNames::Flags).expect_err("negative");
        match &e {
            HullError::Setting { name, value, expected } => {
                assert_eq!((name.as_str(), *value, *expected), ("--draft", -1.0, "a draft greater than 0"));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(e.to_string(), "--draft -1: expected a draft greater than 0");
        let e = crate::table_drafts(Some(2.0), None, None, 0.0, InputNames::Keywords).expect_err("no density");
        assert_eq!(e.to_string(), "density 0: expected a positive density in t/m³");
        let e = crate::table_drafts(Some(2.0), Some(3.0), None, 1.025, InputNames::Flags).expect_err("no step");
        assert!(matches!(e, HullError::DraftStepWithoutTo { names: InputNames::Flags }), "{e:?}");
        assert_eq!(e.to_string(), "--to and --step go together (a range of drafts from --draft to `--to` by `--step`)");
    }

    #[test]
    fn a_format_at_odds_with_the_extension_names_both() {
        let e = crate::ExportFormat::for_file(
            Some(crate::ExportFormat::Stl),
            std::path::Path::new("out/x.stp"),
            None,
            InputNames::Flags,
        )
        .expect_err("an STL named .stp");
        match &e {
            HullError::Format(FormatKind::ExtensionMismatch { format, named, path, .. }) => {
                assert_eq!((*format, *named, path.as_path()), ("stl", "step", std::path::Path::new("out/x.stp")));
            }
            other => panic!("{other:?}"),
        }
        assert_eq!(
            e.to_string(),
            "--format stl writes a STL file, but out/x.stp names a STEP file: name it out/x.stl or pass --format step"
        );
        let e = crate::ExportFormat::for_file(None, std::path::Path::new("x.txt"), None, InputNames::Keywords)
            .expect_err("no format");
        assert!(matches!(&e, HullError::Format(FormatKind::Unknown { .. })), "{e:?}");
        assert_eq!(
            e.to_string(),
            "cannot tell the format from x.txt (expected an extension .stp, .step, .igs, .iges, .dxf, .stl, .obj or \
             .glb, or format)"
        );
    }

    #[test]
    fn a_missing_main_dimension_is_told_from_a_wrong_one() {
        use crate::read::MainDimensions;
        let missing = MainDimensions { lpp: f64::NAN, beam: 16.26, draft: 6.5 }.check().expect_err("no Lpp");
        assert!(matches!(missing, HullError::MainDimension { name: "Lpp", value } if value.is_nan()), "{missing:?}");
        assert_eq!(
            missing.to_string(),
            "Lpp not given (expected Lpp, B and T to scale a Series 60 table: --lpp, --beam, --design-draft)"
        );
        let wrong = MainDimensions { lpp: 121.92, beam: -1.0, draft: 6.5 }.check().expect_err("negative B");
        assert!(matches!(wrong, HullError::MainDimension { name: "B", value: -1.0 }), "{wrong:?}");
        assert_eq!(wrong.to_string(), "B = -1 (expected a finite positive length)");
    }

    #[test]
    fn slice_and_digitize_errors_carry_their_values() {
        let e = crate::mesh::station_positions(0.0, 1.0, 0, crate::mesh::Spacing::Uniform).expect_err("no station");
        assert!(matches!(e, HullError::Slice(SliceKind::StationCount { count: 0, max: 100_000 })), "{e:?}");
        assert_eq!(e.to_string(), "0 stations: expected 1 to 100000");
        let few = HullError::Slice(SliceKind::TooFewSections {
            mesh: "hull.stl".into(),
            sections: 1,
            stations: 2,
            dropped: vec![(12.345678, "misses the mesh".into())],
        });
        assert_eq!(
            few.to_string(),
            "hull.stl: 1 of 2 stations give a section (expected at least 2); x = 12.35: misses the mesh"
        );
        let e = "1:x".parse::<crate::digitize::DrawingScale>().expect_err("not a scale");
        assert!(matches!(&e, HullError::Digitize(DigitizeKind::UnreadableScale { text }) if text == "1:x"), "{e:?}");
        assert_eq!(
            e.to_string(),
            "scale \"1:x\" (expected paper:model such as 1:50, or drawing units per output unit such as 20)"
        );
        let count = HullError::Digitize(DigitizeKind::StationCount {
            drawing: "plan.dxf".into(),
            found: vec!["1".into(), "2".into()],
            given: 3,
        });
        assert_eq!(
            count.to_string(),
            "plan.dxf: 2 station curves found (1, 2) and 3 station positions given (expected one position per \
             station, in that order)"
        );
    }

    #[test]
    fn only_settings_errors_are_settings() {
        let setting = HullError::FitSetting { name: "fairness", value: -1.0, expected: "a finite number >= 0" };
        assert_eq!(setting.to_string(), "fairness -1 is not usable (expected a finite number >= 0)");
        assert!(setting.is_setting());
        assert!(HullError::Weights(WeightsKind::Bounds { lo: 0.0, hi: 2.0 }).is_setting());
        let io = HullError::Io { path: PathBuf::from("x"), error: std::io::Error::other("gone") };
        assert!(!io.is_setting());
        let input = HullError::input(Location::file("x.csv"), InputErrorKind::Empty);
        assert!(!input.is_setting());
    }

    #[test]
    fn a_feature_left_out_is_named_with_the_input() {
        let e = HullError::FeatureDisabled {
            source_name: "hull.stl.gz".into(),
            input: "a gzip-compressed mesh",
            feature: "gzip",
        };
        assert_eq!(
            e.to_string(),
            "hull.stl.gz: a gzip-compressed mesh needs the cargo feature `gzip` of hullskin-hull, which this build \
             leaves out (build with it, or give the input in another form)"
        );
    }
}
