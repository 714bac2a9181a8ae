//! Drawings: a format-independent model of a sheet ([`Drawing`]) and the figures built on it
//! (their colours from [`crate::colormap`]).

pub mod dxf;
pub mod lines_plan;
pub mod model;
pub mod sheet;
pub mod svg;
mod ticks;

pub use dxf::{write_dxf, write_dxf_3d_lines};
pub use lines_plan::{lines_3d, lines_plan, LinesPlanOptions, Scale};
pub use model::{Anchor, Drawing, Item, Rgb, Stroke};
pub use sheet::Sheet;
pub use svg::write_svg;
pub(crate) use ticks::{format_tick, nice_ticks, power_of_ten};
