//! The SURFACE argument of the commands that work on a fitted surface (`hydrostatics`, and
//! later `report`): a `surface.json` written by `hullskin fit`, or offsets fitted first with
//! the skinning flags of [`SkinArgs`] (the built-in Series 60 sample when no input is given).

use anyhow::{bail, Context};
use hull::{FitConfig, FitMethod, Offsets, Units};
use nurbs::NurbsSurface;

use crate::skin_args::SkinArgs;

/// A surface ready for analysis, with where it came from.
pub(crate) struct LoadedSurface {
    /// The starboard half-hull surface.
    pub surface: NurbsSurface,
    /// Its length unit (the JSON's `units`, or `--units` for offsets).
    pub units: Units,
    /// The input's name for titles: the path, or the built-in sample's description.
    pub source: String,
    /// Whether the surface was fitted here (from offsets) rather than read from a JSON.
    pub fitted: bool,
}

/// Load `skin.input`: a surface JSON (recognised by its first non-blank character, `{`) is
/// read as is (`--units` and the skinning flags then play no part); anything else is read as
/// offsets and fitted with `method` (interp or approx) and the skinning flags.
pub(crate) fn load_surface(skin: &SkinArgs, method: FitMethod) -> anyhow::Result<LoadedSurface> {
    if !matches!(method, FitMethod::Interp | FitMethod::Approx) {
        bail!(
            "method {} optimises weights; fit such a surface with `hullskin fit --method {}` and pass its surface.json",
            method.name(),
            method.name()
        );
    }
    let fit = |offsets: Offsets, source: String| -> anyhow::Result<LoadedSurface> {
        let config =
            FitConfig { method, degree: skin.degree, ctrl: skin.ctrl, param: skin.param, ..FitConfig::default() };
        let outcome = hull::fit_offsets(&offsets, &config).with_context(|| format!("cannot fit {source}"))?;
        Ok(LoadedSurface { surface: outcome.surface, units: offsets.units, source, fitted: true })
    };
    let Some(path) = &skin.input else {
        let offsets = hull::series60_sample();
        let source = offsets.source.clone();
        return fit(offsets, source);
    };
    let source = path.display().to_string();
    let bytes = std::fs::read(path).with_context(|| format!("cannot read {source}"))?;
    let text = hull::decode(&bytes, &source)?;
    if text.trim_start().starts_with('{') {
        let (surface, units) =
            hull::export::read_surface_json(text).with_context(|| format!("cannot read the surface {source}"))?;
        let units: Units = units.parse().with_context(|| format!("{source}: \"units\""))?;
        return Ok(LoadedSurface { surface, units, source, fitted: false });
    }
    let offsets = hull::parse_offsets(text, &source, skin.units)?;
    fit(offsets, source)
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn skin(input: Option<PathBuf>) -> SkinArgs {
        SkinArgs { input, ..SkinArgs::default() }
    }

    #[test]
    fn a_surface_json_reads_back_the_fitted_surface() {
        let dir = tempfile::tempdir().expect("temp dir");
        let fitted = load_surface(&skin(None), FitMethod::Approx).expect("the sample fits");
        assert!(fitted.fitted && fitted.source.contains("Series 60"));
        let path = dir.path().join("surface.json");
        let mut text = Vec::new();
        hull::export::write_surface_json(&mut text, &fitted.surface, "ft").expect("writes");
        std::fs::write(&path, text).expect("write");
        let read = load_surface(&skin(Some(path)), FitMethod::Approx).expect("reads");
        assert_eq!(read.surface, fitted.surface);
        assert_eq!(read.units, Units::Foot);
        assert!(!read.fitted);
    }

    #[test]
    fn bad_inputs_say_what_is_wrong() {
        let dir = tempfile::tempdir().expect("temp dir");
        let missing = dir.path().join("none.json");
        let err = load_surface(&skin(Some(missing)), FitMethod::Approx).err().expect("missing file");
        assert!(format!("{err:#}").contains("none.json"), "{err:#}");
        let bad = dir.path().join("bad.json");
        std::fs::write(&bad, "{\"format\": \"other\"}").expect("write");
        let err = load_surface(&skin(Some(bad)), FitMethod::Approx).err().expect("not a surface");
        assert!(format!("{err:#}").contains("bad.json"), "{err:#}");
        let err = load_surface(&skin(None), FitMethod::Optimized(hull::optimize::Algorithm::Ga)).err();
        assert!(err.is_some_and(|e| e.to_string().contains("surface.json")));
    }
}
