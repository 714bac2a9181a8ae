//! Digitising a lines plan: a body plan drawn as DXF or SVG, read back into offsets.
//!
//! The rest of this module's documentation is on [`read_drawing`], where the library's users read it.

mod dxf_in;
mod geom;
mod join;
mod map;
mod options;
mod stations;
/// The SVG reader, or in a build without the cargo feature `svg` its stand-in that refuses.
#[cfg(feature = "svg")]
mod svg_in;
#[cfg(not(feature = "svg"))]
#[path = "svg_off.rs"]
mod svg_in;

use std::path::Path;

pub use dxf_in::parse_dxf;
pub use geom::{seg_dist, Affine, Segment, Spline, P2};
pub use map::digitize;
pub use options::{CurveOrder, DigitizeOptions, Digitized, DrawingScale, Side, StationIds, StationInfo, StationX};
pub use stations::label_number;
pub use svg_in::parse_svg;

use crate::error::{HullError, InputErrorKind, Location};

/// The format a drawing was read from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SketchFormat {
    /// ASCII DXF: y axis up.
    Dxf,
    /// SVG: y axis down.
    Svg,
}

/// One drawn curve: a DXF entity (a whole polyline, a line, an arc, a spline) or one subpath
/// of an SVG element, in drawing coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Curve {
    /// Its pieces, end to end.
    pub segments: Vec<Segment>,
    /// The DXF layer, or the SVG group holding it (see [`parse_svg`]); empty when none.
    pub layer: String,
    /// A name given to it in the file: the SVG `<title>` child, else its `id`.
    pub name: Option<String>,
    /// True for a closed polyline, circle or SVG subpath ended by `Z`.
    pub closed: bool,
    /// Where it starts in the file.
    pub at: Location,
    /// The entity or element, for messages: `LWPOLYLINE`, `SPLINE`, `path`, ...
    pub kind: String,
}

impl Curve {
    /// The curve as a polyline of points on it, flattened with tolerance `tol` (drawing units,
    /// see [`Segment::flatten`]); repeated points dropped.
    pub fn points(&self, tol: f64) -> Vec<P2> {
        let mut out: Vec<P2> = Vec::new();
        let mut buf = Vec::new();
        for s in &self.segments {
            buf.clear();
            s.flatten(tol, &mut buf);
            for &p in &buf {
                if out.last() != Some(&p) {
                    out.push(p);
                }
            }
        }
        out
    }

    /// `KIND at file:line`, for messages.
    pub fn describe(&self) -> String {
        format!("{} at {}", self.kind, self.at)
    }
}

/// A text of the drawing: a DXF `TEXT`/`MTEXT` or an SVG `<text>`.
#[derive(Clone, Debug, PartialEq)]
pub struct Label {
    /// The anchor point (DXF insertion or alignment point, SVG `x`, `y`), drawing units.
    pub at: P2,
    /// The text, formatting codes removed, trimmed.
    pub text: String,
    /// The layer or group, as for [`Curve::layer`].
    pub layer: String,
    /// Where it is in the file.
    pub loc: Location,
}

/// A drawing as read: curves and labels in drawing coordinates.
#[derive(Clone, Debug, PartialEq)]
pub struct Sketch {
    /// The file path as given, or another source name.
    pub source: String,
    /// The format read.
    pub format: SketchFormat,
    /// The length of one drawing unit in millimetres when the file says it (DXF `$INSUNITS`;
    /// SVG `width` and `viewBox`), else `None`.
    pub unit_mm: Option<f64>,
    /// The curves, in file order.
    pub curves: Vec<Curve>,
    /// The texts, in file order.
    pub labels: Vec<Label>,
    /// What was read but not used, e.g. `INSERT (2, first at line 40): block references are
    /// not expanded`.
    pub notes: Vec<String>,
}

impl Sketch {
    /// True when the drawing's y axis points down (SVG).
    pub fn y_down(&self) -> bool {
        self.format == SketchFormat::Svg
    }
}

/// Read a DXF or SVG drawing from `path` (the format is told by the content, see
/// [`parse_drawing`]).
///
/// # Digitising a body plan
///
/// A body plan draws each station (the hull's cut by a plane `x = const`) as a curve from the
/// keel up to the deck, the half-breadth `y` across and the height `z` up the sheet, the aft
/// stations to the LEFT of the centreline and the fore stations to the right (mirrored, so
/// that one side of the hull shows the aft body and the other the fore body). Digitising it
/// takes three steps:
///
/// 1. **Read** ([`read_drawing`], [`parse_dxf`], [`parse_svg`]) the drawing into a [`Sketch`]:
///    its curves as exact pieces ([`Segment`]: lines, arcs, Béziers, B-splines), each with its
///    layer, name and place in the file, and its text labels. DXF (ASCII, R12 and later):
///    `LINE`, `ARC`, `CIRCLE`, `ELLIPSE`, `LWPOLYLINE` and `POLYLINE` (with bulges),
///    `SPLINE` (control points, knots and weights, or fit points), `TEXT` and `MTEXT`; SVG:
///    `<path>` (every command, relative forms included), `<polyline>`, `<polygon>`, `<line>`
///    and `<text>`, under any nesting of `transform`s.
/// 2. **Map** ([`digitize`]) with the user's scale and datum (the drawing point where the
///    centreline meets the baseline): a drawing point `(X, Y)` becomes
///    `y = |X - X0| s`, `z = (Y - Y0) s` (`(Y0 - Y) s` in SVG, whose y axis points down),
///    `s` the model length of one drawing unit. Pieces are joined into curves where their
///    ends meet, the curves are assigned to stations (by layer, by a text label next to them,
///    or by their order), each is checked to stay on one side of the centreline, and ordered
///    from keel to deck.
/// 3. **Write** ([`crate::write_sections_csv`], [`crate::Notation::Plain`]) the
///    [`Offsets`](crate::Offsets) as a sections CSV (`section,x,y,z`), which
///    [`crate::read_offsets`] reads.
///
/// # Errors
/// [`HullError::Io`] when the file cannot be read, and those of [`parse_drawing`].
pub fn read_drawing(path: &Path) -> Result<Sketch, HullError> {
    let bytes = crate::limits::read_capped(path, crate::limits::MAX_DRAWING_FILE_BYTES, "a drawing")?;
    parse_drawing(&bytes, &path.display().to_string())
}

/// Parse a drawing held in `bytes`; `source` names it in messages. A text starting with `<`
/// (after an optional byte-order mark and white space) is SVG, which must be UTF-8; anything
/// else is ASCII DXF, whose strings are read as UTF-8 with invalid bytes replaced (R12 files
/// are often in a Windows code page, which only matters for labels).
///
/// # Errors
/// [`HullError::Input`] with [`InputErrorKind::Drawing`] for a binary DXF or an SVG that is
/// not UTF-8, and the errors of [`parse_dxf`] and [`parse_svg`].
pub fn parse_drawing(bytes: &[u8], source: &str) -> Result<Sketch, HullError> {
    let body = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
    let first = body.iter().position(|b| !b.is_ascii_whitespace()).map_or(&[][..], |i| &body[i..]);
    if first.starts_with(b"AutoCAD Binary DXF") {
        return Err(drawing_error(
            Location::file(source),
            "a binary DXF file".into(),
            "an ASCII DXF: save the drawing as ASCII DXF (\"DXF\" rather than \"binary DXF\")",
        ));
    }
    let sketch = if first.starts_with(b"<") {
        let text = std::str::from_utf8(body).map_err(|e| {
            drawing_error(
                Location::file(source),
                format!("invalid UTF-8 at byte {}", e.valid_up_to()),
                "an SVG file in UTF-8",
            )
        })?;
        parse_svg(text, source)
    } else {
        parse_dxf(&String::from_utf8_lossy(body), source)
    }?;
    crate::limits::check_drawing_entities(source, sketch.curves.len() + sketch.labels.len())?;
    Ok(sketch)
}

/// An [`InputErrorKind::Drawing`] error at `at`.
pub(crate) fn drawing_error(at: Location, found: String, expected: &str) -> HullError {
    HullError::input(at, InputErrorKind::Drawing { found, expected: expected.to_string() })
}

/// Case-insensitive glob match: `*` any run of characters, `?` one character.
pub(crate) fn glob_match(pattern: &str, text: &str) -> bool {
    let p: Vec<char> = pattern.chars().flat_map(char::to_lowercase).collect();
    let t: Vec<char> = text.chars().flat_map(char::to_lowercase).collect();
    // Iterative matching with backtracking to the last `*`.
    let (mut i, mut j) = (0, 0);
    let mut star: Option<(usize, usize)> = None;
    while j < t.len() {
        if i < p.len() && (p[i] == '?' || p[i] == t[j]) {
            i += 1;
            j += 1;
        } else if i < p.len() && p[i] == '*' {
            star = Some((i, j));
            i += 1;
        } else if let Some((si, sj)) = star {
            i = si + 1;
            j = sj + 1;
            star = Some((si, sj + 1));
        } else {
            return false;
        }
    }
    p[i..].iter().all(|&c| c == '*')
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn globs_match_like_a_shell_ignoring_case() {
        assert!(glob_match("ST*", "st12"));
        assert!(glob_match("*", ""));
        assert!(glob_match("S?", "S1"));
        assert!(!glob_match("S?", "S12"));
        assert!(glob_match("*ion*", "stations"));
        assert!(!glob_match("ST*", "WL1"));
        assert!(glob_match("a*b*c", "aXbYbZc"));
        assert!(!glob_match("a*b*c", "aXbYbZ"));
    }

    #[test]
    fn format_is_told_by_the_content() {
        let e = parse_drawing(b"AutoCAD Binary DXF\r\n\x1a\x00", "b.dxf").expect_err("binary");
        assert!(e.to_string().starts_with("b.dxf: a binary DXF file (expected an ASCII DXF"), "{e}");
        let e = parse_drawing(b"  <svg \xff", "x.svg").expect_err("not UTF-8");
        assert!(e.to_string().contains("invalid UTF-8 at byte 7"), "{e}");
        let s = parse_drawing(b"\xEF\xBB\xBF<svg xmlns=\"http://www.w3.org/2000/svg\"/>", "x.svg").expect("svg");
        assert_eq!(s.format, SketchFormat::Svg);
        let s = parse_drawing(b"0\nSECTION\n2\nENTITIES\n0\nENDSEC\n0\nEOF\n", "x.dxf").expect("dxf");
        assert_eq!(s.format, SketchFormat::Dxf);
    }
}
