//! Drawings: a format-independent model of a sheet ([`Drawing`]), colour maps, and the figures
//! built on them.

pub mod colormap;
pub mod dxf;
pub mod lines_plan;
pub mod model;
pub mod sheet;
pub mod svg;

pub use dxf::{write_dxf, write_dxf_3d_lines};
pub use lines_plan::{lines_3d, lines_plan, LinesPlanOptions, Scale};
pub use model::{Anchor, Drawing, Item, Rgb, Stroke};
pub use sheet::Sheet;
pub use svg::write_svg;
