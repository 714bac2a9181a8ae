//! What a file given where a fitted surface may be expected holds (the input of the commands
//! that work on a surface: hydrostatics, report, export, fit's refit of a surface): a mesh (by
//! its name), an IGES or STEP file (by its content, else its extension), a `surface.json` (a
//! JSON object that is not an offset table), or else offsets. A UTF-8 byte-order mark (a
//! Windows editor's) is no part of the text.

use std::path::Path;

use crate::error::HullError;
use crate::export::read_surface_json;
use crate::limits::{check_file_size, MAX_SURFACE_JSON_BYTES};
use crate::mesh::MeshFormat;
use crate::read::{decode, is_offset_json, CadFormat};

/// What the bytes of an input file hold, as [`detect_surface_input`] tells them apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum SurfaceInput<'a> {
    /// An IGES or STEP file, to be read for its B-spline surfaces.
    Cad(CadFormat),
    /// A `surface.json` (not yet parsed): the text, without a byte-order mark.
    SurfaceJson(&'a str),
    /// Anything else: offsets, for the offsets readers.
    Offsets,
}

/// True if `path` names a mesh: `.stl`, `.obj`, `.wrl`, `.vrml`, each optionally followed by
/// `.gz`, or `.wrz` ([`MeshFormat::from_path`]).
pub fn is_mesh_path(path: &Path) -> bool {
    MeshFormat::from_path(path).is_some()
}

/// `text` without a leading UTF-8 byte-order mark.
///
/// ```
/// assert_eq!(hull::strip_bom("\u{FEFF}{\"format\": 1}"), "{\"format\": 1}");
/// assert_eq!(hull::strip_bom("section,x,y,z"), "section,x,y,z");
/// ```
pub fn strip_bom(text: &str) -> &str {
    text.strip_prefix('\u{FEFF}').unwrap_or(text)
}

/// What `bytes`, read from `path` (not a mesh: see [`is_mesh_path`]), hold: an IGES or STEP
/// file by its content, else its extension ([`CadFormat::sniff`], [`CadFormat::from_path`]);
/// else, decoded as text, a `surface.json` when its first non-blank character is `{` and it is
/// not a JSON offset table; else offsets.
///
/// ```
/// use hull::{detect_surface_input, SurfaceInput};
/// use std::path::Path;
///
/// let json = detect_surface_input(Path::new("s.json"), "\u{FEFF}\n {\"format\": \"hullskin-surface\"}".as_bytes())?;
/// assert_eq!(json, SurfaceInput::SurfaceJson("\n {\"format\": \"hullskin-surface\"}"));
/// assert_eq!(detect_surface_input(Path::new("t.csv"), b"section,x,y,z\n")?, SurfaceInput::Offsets);
/// # Ok::<(), hull::HullError>(())
/// ```
///
/// # Errors
/// Those of [`decode`] for a file that is not text (binary, UTF-16).
pub fn detect_surface_input<'a>(path: &Path, bytes: &'a [u8]) -> Result<SurfaceInput<'a>, HullError> {
    if let Some(format) = CadFormat::sniff(bytes).or_else(|| CadFormat::from_path(path)) {
        return Ok(SurfaceInput::Cad(format));
    }
    let text = strip_bom(decode(bytes, &path.display().to_string())?);
    Ok(if text.trim_start().starts_with('{') && !is_offset_json(text) {
        SurfaceInput::SurfaceJson(text)
    } else {
        SurfaceInput::Offsets
    })
}

/// Whether `path` holds a surface: an IGES or STEP file, or a JSON that reads as a
/// `surface.json` ([`detect_surface_input`]). A mesh, a file that cannot be read or is larger
/// than [`MAX_SURFACE_JSON_BYTES`], and a broken JSON do not: the offsets readers then name
/// the error and its place.
pub fn holds_surface(path: &Path) -> bool {
    if is_mesh_path(path) || check_file_size(path, MAX_SURFACE_JSON_BYTES, "a surface file").is_err() {
        return false;
    }
    let Ok(bytes) = std::fs::read(path) else { return false };
    match detect_surface_input(path, &bytes) {
        Ok(SurfaceInput::Cad(_)) => true,
        Ok(SurfaceInput::SurfaceJson(text)) => read_surface_json(text).is_ok(),
        Ok(SurfaceInput::Offsets) | Err(_) => false,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn mesh_paths_by_extension() {
        for (p, mesh) in [
            ("a.stl", true),
            ("b/A.STL.GZ", true),
            ("c.obj", true),
            ("h.WRL", true),
            ("d.csv", false),
            ("e.json", false),
        ] {
            assert_eq!(is_mesh_path(Path::new(p)), mesh, "{p}");
        }
    }

    #[test]
    fn cad_by_content_before_extension_and_json_tables_are_offsets() {
        let mut iges = vec![b' '; 72];
        iges.extend_from_slice(b"S      1\n");
        let detect = |name: &str, bytes: &[u8]| detect_surface_input(Path::new(name), bytes).map(|k| format!("{k:?}"));
        assert_eq!(detect("hull.txt", &iges).expect("text"), "Cad(Iges)");
        assert_eq!(detect("hull.json", b"/* c */ ISO-10303-21;\nHEADER;\n").expect("text"), "Cad(Step)");
        assert_eq!(detect("x.igs", b"").expect("by extension"), "Cad(Iges)");
        let table = r#"{"stations": [0, 1], "halfBreadths": [[0, 1], [0, 1]]}"#;
        assert_eq!(detect("t.json", table.as_bytes()).expect("text"), "Offsets");
        assert_eq!(detect("s.json", b"  {\"format\": 1}").expect("text"), "SurfaceJson(\"  {\\\"format\\\": 1}\")");
        assert!(detect("b.csv", &[0xFF, 0xFE, b'a', 0]).is_err(), "UTF-16 is refused");
    }

    #[test]
    fn only_a_readable_surface_holds_one() {
        let dir = tempfile::tempdir().expect("temp dir");
        let fit = crate::fit_offsets(&crate::series60_sample(), &crate::FitConfig::default()).expect("fits");
        let good = dir.path().join("s.json");
        let mut text = "\u{FEFF}".as_bytes().to_vec();
        crate::export::write_surface_json(&mut text, &fit.surface, crate::Units::Metre).expect("writes");
        std::fs::write(&good, text).expect("write");
        let broken = dir.path().join("b.json");
        std::fs::write(&broken, "{\"format\": \"hullskin-surface\"").expect("write");
        let csv = dir.path().join("o.csv");
        std::fs::write(&csv, crate::SERIES60_CB060_CSV).expect("write");
        assert!(holds_surface(&good));
        assert!(!holds_surface(&broken) && !holds_surface(&csv) && !holds_surface(&dir.path().join("none.json")));
    }
}
