//! B-spline surfaces read from CAD exchange files: IGES 5.3 ([`super::iges`], entity 128) and
//! STEP ISO 10303-21 ([`super::step`], `B_SPLINE_SURFACE_WITH_KNOTS` and its rational complex
//! instance), behind one front: [`read_cad_surfaces`] and [`parse_cad_surfaces`].
//!
//! The rest of this module's documentation is on [`parse_cad_surfaces`], where the library's users read it.

use std::collections::BTreeMap;
use std::path::Path;

use nurbs::{KnotVector, NurbsError, NurbsSurface, Vec3};

use crate::error::{HullError, InputErrorKind, Location};
use crate::limits::{read_capped, MAX_CAD_FILE_BYTES};
use crate::units::Units;

/// The two CAD exchange formats read.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CadFormat {
    /// IGES 5.3, fixed 80-column ASCII form.
    Iges,
    /// STEP, ISO 10303-21 clear-text encoding.
    Step,
}

impl CadFormat {
    /// A short name for messages.
    pub fn name(self) -> &'static str {
        match self {
            CadFormat::Iges => "IGES",
            CadFormat::Step => "STEP",
        }
    }

    /// The format a file name's extension stands for: `.igs`/`.iges` or `.stp`/`.step`, any case.
    pub fn from_path(path: &Path) -> Option<Self> {
        let ext = path.extension()?.to_str()?.to_ascii_lowercase();
        match ext.as_str() {
            "igs" | "iges" => Some(CadFormat::Iges),
            "stp" | "step" => Some(CadFormat::Step),
            _ => None,
        }
    }

    /// The format the content shows: an IGES start record (`S` in column 73 of the first line
    /// and sequence number 1 in columns 74-80, IGES 5.3 section 2.2.4.1) or the STEP exchange-structure keyword `ISO-10303-21;` first
    /// (ISO 10303-21 section 5.2), after blanks and comments.
    pub fn sniff(bytes: &[u8]) -> Option<Self> {
        let first = bytes.split(|&b| b == b'\n').next().unwrap_or(&[]);
        let first = first.strip_suffix(b"\r").unwrap_or(first);
        // Also the sequence number 1 in columns 74-80, so a long CSV line with an S there is not taken.
        let seq = first.get(73..80).and_then(|s| std::str::from_utf8(s).ok()).map(str::trim);
        if first.get(72) == Some(&b'S') && seq.is_some_and(|s| s.parse() == Ok(1u32)) {
            return Some(CadFormat::Iges);
        }
        let mut rest = bytes.strip_prefix(b"\xEF\xBB\xBF").unwrap_or(bytes);
        loop {
            rest = rest.trim_ascii_start();
            match rest.strip_prefix(b"/*") {
                Some(r) => match r.windows(2).position(|w| w == b"*/") {
                    Some(end) => rest = &r[end + 2..],
                    None => return None,
                },
                None => break,
            }
        }
        rest.starts_with(b"ISO-10303-21;").then_some(CadFormat::Step)
    }
}

/// One surface read, with the name that tells it apart in messages.
#[derive(Clone, Debug, PartialEq)]
pub struct CadSurface {
    /// The surface, in [`CadSurfaces::units`].
    pub surface: NurbsSurface,
    /// Where it was in the file and its label, e.g. `entity 128 at D 1 (SURFACE)` or
    /// `#27 'hull'`.
    pub name: String,
}

/// What a CAD file held: its B-spline surfaces in one length unit, and notes on what was
/// converted or left out.
#[derive(Clone, Debug, PartialEq)]
pub struct CadSurfaces {
    /// The format read.
    pub format: CadFormat,
    /// The surfaces, in file order.
    pub surfaces: Vec<CadSurface>,
    /// The length unit of the surfaces' coordinates.
    pub units: Units,
    /// What the reader converted or left out, e.g. `skipped 3 entities of type 126 (rational
    /// B-spline curve)`.
    pub notes: Vec<String>,
}

/// Reads the B-spline surfaces of the IGES or STEP file at `path` (format from the content,
/// else the extension), converted to `target`, or in the file's unit when `None`.
///
/// # Errors
/// [`HullError::Io`] if the file cannot be read, [`HullError::Limit`] above
/// [`MAX_CAD_FILE_BYTES`], and every error of [`parse_cad_surfaces`].
pub fn read_cad_surfaces(path: &Path, target: Option<Units>) -> Result<CadSurfaces, HullError> {
    let bytes = read_capped(path, MAX_CAD_FILE_BYTES, "an IGES or STEP file")?;
    let source = path.display().to_string();
    let format = CadFormat::sniff(&bytes).or_else(|| CadFormat::from_path(path));
    parse_as(&bytes, &source, format, target)
}

/// Reads the B-spline surfaces of IGES or STEP text (format from the content), converted to
/// `target`, or in the file's unit when `None`; `source` names the input in messages.
///
/// ```
/// use hull::{parse_cad_surfaces, write_iges, CadFormat, IgesMeta, Units};
/// use nurbs::{KnotVector, NurbsSurface, Vec3};
///
/// let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).unwrap();
/// let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(2.0, 0.0, 0.0), Vec3::new(2.0, 1.0, 1.0)];
/// let s = NurbsSurface::try_new(k.clone(), k, &pts, None).unwrap();
/// let mut iges = Vec::new();
/// write_iges(&mut iges, &s, &IgesMeta::new(Units::Millimetre.into(), "a.igs", "20240101.000000")).unwrap();
/// // Read in the file's unit (None), or converted to metres.
/// let read = parse_cad_surfaces(&iges, "a.igs", None).unwrap();
/// assert_eq!((read.format, read.units, read.surfaces.len()), (CadFormat::Iges, Units::Millimetre, 1));
/// assert_eq!(read.surfaces[0].surface, s);
/// let metres = parse_cad_surfaces(&iges, "a.igs", Some(Units::Metre)).unwrap();
/// assert_eq!(metres.surfaces[0].surface.control_point(1, 1), Vec3::new(2e-3, 1e-3, 1e-3));
/// ```
///
/// The format is told by the content (an IGES start record, `S` in column 73 of the first
/// line; a STEP file opening with `ISO-10303-21;`), else by the extension (`.igs`, `.iges`,
/// `.stp`, `.step`, any case). Coordinates are converted from the file's length unit to the
/// caller's, or kept in the file's unit when it is one of [`Units`] (else converted to metres,
/// with a note). What the readers do not read (curves, other surface types, trimming, colours)
/// is listed in [`CadSurfaces::notes`]. Every malformed file gives [`HullError::Input`] with
/// [`InputErrorKind::Cad`] at `file:line`, naming the entity and parameter; counts are checked
/// against the caps (crate docs, Limits) before anything is allocated for them.
///
/// # Errors
/// [`HullError::Input`] with [`InputErrorKind::Cad`] when the content is neither format or
/// breaks it, at `source:line`; [`HullError::Limit`] for counts above the documented caps.
pub fn parse_cad_surfaces(bytes: &[u8], source: &str, target: Option<Units>) -> Result<CadSurfaces, HullError> {
    parse_as(bytes, source, CadFormat::sniff(bytes), target)
}

/// [`parse_cad_surfaces`] in the given format (`None`: neither, an error), for a caller that
/// has the bytes and told the format itself (e.g. [`CadFormat::sniff`], else
/// [`CadFormat::from_path`]).
///
/// # Errors
/// As [`parse_cad_surfaces`].
pub fn parse_as(
    bytes: &[u8],
    source: &str,
    format: Option<CadFormat>,
    target: Option<Units>,
) -> Result<CadSurfaces, HullError> {
    match format {
        Some(CadFormat::Iges) => super::iges::parse_iges(bytes, source, target),
        Some(CadFormat::Step) => super::step::parse_step(bytes, source, target),
        None => Err(cad_error(
            source,
            Some(1),
            "file",
            "neither an IGES start record nor a STEP header".into(),
            "an IGES 5.3 file (S in column 73 of the first line) or a STEP file starting with ISO-10303-21;",
        )),
    }
}

/// The error of a CAD reader at `line` (1-based) of `source`.
pub(crate) fn cad_error(source: &str, line: Option<usize>, entity: &str, found: String, expected: &str) -> HullError {
    let at = match line {
        Some(l) => Location::line(source, l),
        None => Location::file(source),
    };
    HullError::input(at, InputErrorKind::Cad { entity: entity.to_string(), found, expected: expected.to_string() })
}

/// A file's length unit: metres per unit and the name the file gives it.
#[derive(Clone, Debug, PartialEq)]
pub(crate) struct FileUnit {
    pub metres: f64,
    pub name: String,
}

/// Relative difference under which a unit's size is taken as one of [`Units`]: well above the
/// rounding of a factor written in decimal (1e-16), well below any two distinct units.
const SAME_UNIT_REL: f64 = 1e-12;

/// The scale from the file's unit to the output unit and the output unit: `target`, or the
/// file's own when it is one of [`Units`], else metres (with a note in `notes`).
pub(crate) fn output_scale(file: &FileUnit, target: Option<Units>, notes: &mut Vec<String>) -> (f64, Units) {
    let own = Units::ALL.into_iter().find(|u| (u.metres_per_unit() / file.metres - 1.0).abs() <= SAME_UNIT_REL);
    let units = match (target, own) {
        (Some(t), _) => t,
        (None, Some(u)) => u,
        (None, None) => {
            notes.push(format!(
                "the file's length unit {} ({} m) is none of m, mm, ft, in: coordinates converted to metres",
                file.name, file.metres
            ));
            Units::Metre
        }
    };
    // Exactly 1 when the units agree, so a file in the target unit reads back bit for bit.
    let scale = if own == Some(units) { 1.0 } else { file.metres / units.metres_per_unit() };
    (scale, units)
}

/// One B-spline surface as a reader found it, before validation: degrees, full knot vectors,
/// u-major control points (index `i * n_v + j`) and weights in the file's unit.
pub(crate) struct RawSurface {
    pub degree: (usize, usize),
    pub knots: (Vec<f64>, Vec<f64>),
    pub points: Vec<Vec3>,
    pub weights: Vec<f64>,
}

impl RawSurface {
    /// Validate and build the surface with every control point scaled by `scale`; an error
    /// names `entity` at `line` and what the kernel refused.
    pub fn build(self, scale: f64, source: &str, line: usize, entity: &str) -> Result<NurbsSurface, HullError> {
        let err = |what: &str, e: NurbsError| {
            cad_error(source, Some(line), entity, format!("{what}: {e}"), "a valid clamped B-spline surface")
        };
        let ku = KnotVector::try_new(self.degree.0, self.knots.0).map_err(|e| err("the u knots", e))?;
        let kv = KnotVector::try_new(self.degree.1, self.knots.1).map_err(|e| err("the v knots", e))?;
        let points: Vec<Vec3> =
            if scale == 1.0 { self.points } else { self.points.into_iter().map(|p| p * scale).collect() };
        NurbsSurface::try_new(ku, kv, &points, Some(&self.weights)).map_err(|e| err("the control net", e))
    }
}

/// Counts of skipped entities by kind, for one note: `skipped 3 entities of type 126
/// (rational B-spline curve), 1 of type 314 (colour)` (IGES) or `skipped 4
/// B_SPLINE_CURVE_WITH_KNOTS, 1 PLANE` (STEP).
#[derive(Default)]
pub(crate) struct Skipped {
    counts: BTreeMap<String, usize>,
}

impl Skipped {
    pub fn add(&mut self, kind: String) {
        *self.counts.entry(kind).or_insert(0) += 1;
    }

    /// The note, `None` when nothing was skipped; `first` words the first count, e.g.
    /// `|n, kind| format!("{n} entities of type {kind}")`, and later ones `|n, kind| ...`.
    pub fn note(&self, first: impl Fn(usize, &str) -> String, rest: impl Fn(usize, &str) -> String) -> Option<String> {
        let mut parts = self.counts.iter().map(|(k, &n)| (n, k.as_str()));
        let (n, k) = parts.next()?;
        let mut text = format!("skipped {}", first(n, k));
        for (n, k) in parts {
            text.push_str(", ");
            text.push_str(&rest(n, k));
        }
        Some(text)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn formats_are_sniffed_from_the_content_then_the_extension() {
        let iges = format!("{:<72}S{:>7}\n", "start", 1);
        assert_eq!(CadFormat::sniff(iges.as_bytes()), Some(CadFormat::Iges));
        assert_eq!(CadFormat::sniff(b"/* a comment */\n ISO-10303-21;\nHEADER;"), Some(CadFormat::Step));
        assert_eq!(CadFormat::sniff(b"\xEF\xBB\xBFISO-10303-21;"), Some(CadFormat::Step));
        assert_eq!(CadFormat::sniff(b"/* never closed ISO-10303-21;"), None);
        assert_eq!(CadFormat::sniff(b"section,x,y,z\n"), None);
        let csv = format!("{}S,1,2\n", "x".repeat(72));
        assert_eq!(CadFormat::sniff(csv.as_bytes()), None, "an S in column 73 alone is not IGES");
        assert_eq!(CadFormat::from_path(Path::new("a/HULL.IGS")), Some(CadFormat::Iges));
        assert_eq!(CadFormat::from_path(Path::new("hull.Step")), Some(CadFormat::Step));
        assert_eq!(CadFormat::from_path(Path::new("hull.csv")), None);
        let e = parse_cad_surfaces(b"x,y\n", "t.txt", None).expect_err("neither format");
        assert!(e.to_string().starts_with("t.txt:1: file: neither an IGES start record"), "{e}");
    }

    #[test]
    fn the_output_unit_is_the_target_or_the_files_own() {
        let mut notes = Vec::new();
        let mm = FileUnit { metres: 1e-3, name: "MM".into() };
        assert_eq!(output_scale(&mm, None, &mut notes), (1.0, Units::Millimetre));
        assert_eq!(output_scale(&mm, Some(Units::Millimetre), &mut notes), (1.0, Units::Millimetre));
        assert_eq!(output_scale(&mm, Some(Units::Metre), &mut notes), (1e-3, Units::Metre));
        assert!(notes.is_empty());
        let km = FileUnit { metres: 1e3, name: "KM".into() };
        assert_eq!(output_scale(&km, None, &mut notes), (1e3, Units::Metre));
        assert_eq!(notes.len(), 1, "{notes:?}");
        assert!(notes[0].contains("KM (1000 m)"), "{notes:?}");
    }

    #[test]
    fn skipped_kinds_make_one_note() {
        let mut s = Skipped::default();
        assert_eq!(s.note(|n, k| format!("{n} {k}"), |n, k| format!("{n} {k}")), None);
        for k in ["126", "314", "126"] {
            s.add(k.into());
        }
        let note = s.note(|n, k| format!("{n} entities of type {k}"), |n, k| format!("{n} of type {k}"));
        assert_eq!(note.as_deref(), Some("skipped 2 entities of type 126, 1 of type 314"));
    }
}
