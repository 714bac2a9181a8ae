//! Static pictures for reports and terminals without a browser: any [`Drawing`] rasterised to
//! PNG ([`render_png`]), the curvature map of a surface ([`curvature_map_png`]) and the
//! convergence plot of the optimisers ([`convergence_plot`], a [`Drawing`] that the PNG and SVG
//! writers both take).
//!
//! All outputs are deterministic: the same input gives the same bytes.
//!
//! [`Drawing`]: crate::drawing::Drawing

mod convergence;
mod curvature_png;
mod raster;

pub use convergence::convergence_plot;
pub use curvature_png::{
    curvature_image, curvature_map_png, CurvatureImage, CurvatureImageOptions, ViewDirection, ViewFrame,
};
pub use raster::{render_png, render_rgba, write_png, Image, RasterOptions, MAX_PIXELS};
