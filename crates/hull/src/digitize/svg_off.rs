//! [`parse_svg`] in a build without the cargo feature `svg` (svgtypes, roxmltree): an SVG
//! drawing is named, not read. `svg_in.rs` is the reader.

use super::Sketch;
use crate::error::HullError;

/// Parse an SVG held in `text`; `source` names it in messages. This build leaves the SVG
/// reader out (cargo feature `svg`).
///
/// # Errors
/// Always [`HullError::FeatureDisabled`].
pub fn parse_svg(_text: &str, source: &str) -> Result<Sketch, HullError> {
    Err(HullError::FeatureDisabled { source_name: source.to_string(), input: "an SVG drawing", feature: "svg" })
}
