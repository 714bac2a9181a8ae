//! The input of the commands that work on a fitted surface (`hydrostatics`, `report`,
//! `export`): a `surface.json` written by `hullskin fit`, an IGES or STEP file holding one
//! B-spline surface, or offsets to be fitted first with the skinning flags of [`SkinArgs`] (the
//! built-in Series 60 sample when no input is given).

use anyhow::{bail, Context};
use hull::{Offsets, SurfaceInput, Units};
use nurbs::NurbsSurface;

use crate::skin_args::SkinArgs;

/// What the input holds.
pub(crate) enum Input {
    /// A surface read from a JSON, IGES or STEP file as it is (`--units` and the skinning
    /// flags play no part).
    Surface {
        /// The starboard half-hull surface.
        surface: NurbsSurface,
        /// Its length unit: the JSON's `units`, the IGES or STEP file's length unit.
        units: Units,
        /// The input's path, for titles and messages.
        source: String,
    },
    /// Offsets (a file read in `--units`, or the built-in sample), to be fitted.
    Offsets(Offsets),
    /// Several surfaces of one IGES or STEP file: the patches of one hull (hydrostatics
    /// integrates them together; the other commands take one surface).
    Patches {
        /// The patches, in the file's order.
        surfaces: Vec<NurbsSurface>,
        /// Their names (the entity's label, or its place).
        names: Vec<String>,
        /// Their length unit: the file's.
        units: Units,
        /// The input's path.
        source: String,
    },
}

/// The error of a command that takes one surface given the patches `names` of `source`.
pub(crate) fn patches_refused(names: &[String], source: &str) -> anyhow::Error {
    anyhow::anyhow!(
        "{source}: {} B-spline surfaces ({}); this command takes one surface (expected a file holding one: export \
         the patches one by one, or join them into one surface; hydrostatics integrates them together)",
        names.len(),
        names.join(", ")
    )
}

/// Read `skin.input`: a surface JSON (recognised by its first non-blank character, `{`, unless
/// it holds a JSON offset table, see `hull::json_table`), an IGES or STEP file (by its
/// content, else its extension, see `hull::CadFormat`) holding exactly one B-spline surface,
/// or anything else as offsets in `skin.units`; without an input, the built-in sample's offsets.
///
/// # Errors
/// A file that cannot be read or is not text, a JSON that is not a surface (or has unknown
/// units), an IGES or STEP file that breaks its format or holds no or several surfaces, and
/// every parse error of the offsets; each names the file.
pub(crate) fn read_input(skin: &SkinArgs) -> anyhow::Result<Input> {
    let Some(path) = &skin.input else {
        return Ok(Input::Offsets(hull::series60_sample()));
    };
    if hull::is_mesh_path(path) {
        return Ok(Input::Offsets(crate::slice::mesh_offsets(path, &skin.mesh, skin.units())?));
    }
    let source = path.display().to_string();
    hull::check_file_size(path, hull::MAX_SURFACE_JSON_BYTES, "a surface.json or offsets file")?;
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {source}"))?;
    match hull::detect_surface_input(path, &bytes)? {
        SurfaceInput::Cad(format) => return cad_surface(&bytes, &source, format),
        SurfaceInput::SurfaceJson(text) => {
            let (surface, units) = hull::read_surface_json(text).map_err(|e| surface_json_error(e, &source))?;
            // Finite coordinates can still overflow every length, area and volume computed from
            // them (a control net of 1e308): refused here for every command, not only the writers.
            hull::check_finite(&surface).with_context(|| format!("cannot use the surface {source}"))?;
            let units: Units = units.parse().with_context(|| format!("{source}: \"units\""))?;
            return Ok(Input::Surface { surface, units, source });
        }
        SurfaceInput::Offsets => {}
    }
    let outcome = hull::read_offsets_with(path, &skin.read_options())?;
    // hydrostatics and report take --lpp as the perpendiculars too.
    skin.note_flags_not_applied(outcome.format, true);
    Ok(Input::Offsets(crate::skin_args::report_reading(outcome)))
}

/// Whether `path` holds a surface ([`hull::holds_surface`]).
pub(crate) use hull::holds_surface;

/// A note on standard error when `--units` was given for a surface.json input in other units
/// (a command that does not convert: the surface keeps its own).
pub(crate) fn note_units_not_applied(skin: &SkinArgs, units: Units, source: &str) {
    if let Some(given) = skin.units.filter(|u| *u != units) {
        eprintln!(
            "hullskin: note: --units {} does not apply to {source}: a surface.json carries its units ({}), kept here \
             (hullskin export --units {} converts it)",
            given.symbol(),
            units.symbol(),
            given.symbol()
        );
    }
}

/// The B-spline surfaces of an IGES or STEP file, in the file's length unit: one surface, or
/// the patches of one hull; the reader's notes go to stderr.
fn cad_surface(bytes: &[u8], source: &str, format: hull::CadFormat) -> anyhow::Result<Input> {
    let read = hull::parse_cad_surfaces_as(bytes, source, Some(format), None)?;
    for note in &read.notes {
        eprintln!("hullskin: note: {source}: {note}");
    }
    let mut surfaces = read.surfaces;
    let surface = match surfaces.len() {
        1 => surfaces.remove(0).surface,
        0 => bail!(
            "{source}: no B-spline surface in the {} file (expected one rational B-spline surface: IGES entity 128, \
             STEP B_SPLINE_SURFACE_WITH_KNOTS)",
            format.name()
        ),
        _ => {
            for s in &surfaces {
                hull::check_finite(&s.surface)
                    .with_context(|| format!("cannot use the surface {} of {source}", s.name))?;
            }
            let names = surfaces.iter().map(|s| s.name.clone()).collect();
            let surfaces = surfaces.into_iter().map(|s| s.surface).collect();
            return Ok(Input::Patches { surfaces, names, units: read.units, source: source.to_string() });
        }
    };
    hull::check_finite(&surface).with_context(|| format!("cannot use the surface {source}"))?;
    Ok(Input::Surface { surface, units: read.units, source: source.to_string() })
}

/// A surface JSON error naming the file, and for a syntax error its line and column as
/// `file:line:col:` (serde_json's " at line L column C" suffix dropped).
fn surface_json_error(e: hull::SurfaceJsonError, source: &str) -> anyhow::Error {
    use hull::SurfaceJsonError;
    match e {
        SurfaceJsonError::Syntax { line, column, message } => {
            let suffix = format!(" at line {line} column {column}");
            let message = message.strip_suffix(&suffix).unwrap_or(&message);
            anyhow::anyhow!(
                "{source}:{line}:{column}: {message} (expected a hullskin surface JSON, as hullskin fit writes it)"
            )
        }
        e => anyhow::Error::new(e).context(format!("cannot read the surface {source}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn skin(input: Option<PathBuf>) -> SkinArgs {
        SkinArgs { input, ..SkinArgs::default() }
    }

    fn offsets(input: Input) -> Offsets {
        match input {
            Input::Offsets(o) => o,
            Input::Surface { source, .. } | Input::Patches { source, .. } => {
                panic!("{source} read as a surface, expected offsets")
            }
        }
    }

    #[test]
    fn a_surface_json_reads_back_the_fitted_surface() {
        let dir = tempfile::tempdir().expect("temp dir");
        let sample = offsets(read_input(&skin(None)).expect("the sample"));
        assert!(sample.source.contains("Series 60"));
        let fitted = hull::fit_offsets(&sample, &hull::FitConfig::default()).expect("the sample fits");
        let path = dir.path().join("surface.json");
        // Leading blanks and a byte-order mark do not hide the JSON.
        let mut text = "\u{FEFF}\n  ".as_bytes().to_vec();
        hull::write_surface_json(&mut text, &fitted.surface, Units::Foot).expect("writes");
        std::fs::write(&path, text).expect("write");
        match read_input(&skin(Some(path.clone()))).expect("reads") {
            Input::Surface { surface, units, source } => {
                // The JSON keeps the surface exactly (shortest round-trip floats).
                assert_eq!(surface, fitted.surface);
                assert_eq!(units, Units::Foot);
                assert_eq!(source, path.display().to_string());
            }
            Input::Offsets(_) | Input::Patches { .. } => panic!("a surface.json read as offsets or patches"),
        }
    }

    #[test]
    fn an_offsets_file_is_read_in_the_units_flag() {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = dir.path().join("s60.csv");
        std::fs::write(&path, hull::SERIES60_CB060_CSV).expect("write");
        let args = SkinArgs { units: Some(Units::Foot), ..skin(Some(path.clone())) };
        let read = offsets(read_input(&args).expect("reads"));
        let sample = hull::series60_sample();
        assert_eq!((read.units, read.source), (Units::Foot, path.display().to_string()));
        assert_eq!(read.sections.len(), sample.sections.len());
        // The same table as the sample: only the unit label differs.
        for (a, b) in read.sections.iter().zip(&sample.sections) {
            assert_eq!(a.points, b.points);
        }
    }

    #[test]
    fn bad_inputs_say_what_is_wrong() {
        let dir = tempfile::tempdir().expect("temp dir");
        let missing = dir.path().join("none.json");
        let err = read_input(&skin(Some(missing))).err().expect("missing file");
        assert!(format!("{err:#}").contains("none.json"), "{err:#}");
        let bad = dir.path().join("bad.json");
        std::fs::write(&bad, "{\"format\": \"other\"}").expect("write");
        let err = read_input(&skin(Some(bad))).err().expect("not a surface");
        assert!(format!("{err:#}").contains("bad.json"), "{err:#}");
        let cut = dir.path().join("cut.json");
        std::fs::write(&cut, "{\n  \"format\": \"hullskin-surface\",\n  \"version\": \"1\"").expect("write");
        let err = format!("{:#}", read_input(&skin(Some(cut.clone()))).err().expect("a string version"));
        assert_eq!(
            err,
            format!(
                "{}:3:16: invalid type: string \"1\", expected u32 (expected a hullskin surface JSON, as hullskin fit \
                 writes it)",
                cut.display()
            )
        );
        let broken = dir.path().join("broken.csv");
        std::fs::write(&broken, "section,x,y,z\nA,1,2\n").expect("write");
        let err = read_input(&skin(Some(broken))).err().expect("not offsets");
        assert!(format!("{err:#}").contains("broken.csv"), "{err:#}");
    }
}
