//! The presentation of hullskin, on top of the `hull` domain: drawings (the lines plan as SVG
//! and DXF, on a format-independent [`Drawing`]), PNG pictures (any drawing rasterised, the
//! curvature maps, the optimisers' convergence plot), the self-contained 3-D viewer page and
//! the HTML report, with their assets (the DejaVu Sans subset, three.js) inside the crate.
//!
//! Axes as everywhere in hullskin: x forward, y to starboard, z up; lengths in the surface's
//! units on the model, millimetres on paper.
//!
//! Fit the built-in sample and draw its lines plan, as `hullskin export --lines` does:
//!
//! ```
//! use hull::{fit_offsets, series60_sample, FitConfig};
//! use view::{lines_plan, write_dxf, write_svg, LinesPlanOptions};
//!
//! let offsets = series60_sample();
//! let fit = fit_offsets(&offsets, &FitConfig::default())?;
//! // Profile, half-breadth plan and body plan on the smallest standard sheet that holds them,
//! // with the offsets marked in the body plan, coloured by their distance to the surface.
//! let sheet = lines_plan(&fit.surface, Some(&offsets), offsets.units, &LinesPlanOptions::default());
//! assert!(sheet.layer("stations").count() > 0 && sheet.layer("offsets").count() > 0);
//! let mut svg = Vec::new();
//! write_svg(&mut svg, &sheet)?;
//! let svg = String::from_utf8(svg)?;
//! assert!(svg.starts_with("<?xml") && svg.contains("<svg"));
//! // The same sheet for CAD, one DXF layer per drawing layer.
//! let mut dxf = Vec::new();
//! write_dxf(&mut dxf, &sheet)?;
//! assert!(String::from_utf8(dxf)?.contains("stations"));
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Cargo feature `png` (on by default): the raster renderer (tiny-skia, ttf-parser, png) and
//! what needs it, the PNG pictures and the HTML report. Without it the crate still draws the
//! lines plan (SVG, DXF) and writes the 3-D viewer.

mod drawing;
mod error;
mod markup;
#[cfg(feature = "png")]
mod render;
#[cfg(feature = "png")]
mod report_html;
/// Reading the pages in unit tests: the file the command line's tests include too.
#[cfg(test)]
#[path = "../tests/common/page.rs"]
#[cfg_attr(not(feature = "png"), allow(dead_code))] // `urls` serves the report's tests
mod test_page;
mod viewer;

pub use drawing::{
    aci, aci_rgb, layer_name, lines_3d, lines_plan, write_dxf, write_dxf_3d_lines, write_svg, Anchor, Drawing, Item,
    LinesPlanOptions, Rgb, Scale, Sheet, Stroke, CAP_HEIGHT_PER_EM, MAX_LAYER_NAME,
};
pub use error::ViewError;
#[cfg(feature = "png")]
pub use render::{
    convergence_plot, curvature_image, curvature_map_png, render_png, render_rgba, write_png, CurvatureImage,
    CurvatureImageOptions, Image, RasterOptions, ViewDirection, ViewFrame, MAX_PIXELS,
};
#[cfg(feature = "png")]
pub use report_html::{
    build_report, write_report, DraftChoice, ReportFiles, ReportInputs, ReportOptions, CONVERGENCE_PNG_FILE,
    GAUSSIAN_PNG_FILE, HYDROSTATICS_CSV_FILE, HYDROSTATICS_JSON_FILE, LINES_3D_DXF_FILE, LINES_DXF_FILE,
    LINES_PNG_FILE, LINES_PNG_MAX_PIXELS, LINES_SVG_FILE, MEAN_PNG_FILE, REPORT_FILE, VIEWER_FILE,
};
pub use viewer::{write_viewer_html, Field, Resolution, ViewerOptions};
