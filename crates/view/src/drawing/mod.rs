//! Drawings: a format-independent model of a sheet ([`Drawing`]) and the figures built on it
//! (their colours from hull's colour maps, [`hull::sequential`] and [`hull::diverging`]).

mod dxf;
mod lines_plan;
mod model;
mod sheet;
mod svg;
mod ticks;

pub use dxf::{aci, aci_rgb, layer_name, write_dxf, write_dxf_3d_lines, MAX_LAYER_NAME};
pub use lines_plan::{lines_3d, lines_plan, LinesPlanOptions, Scale};
pub use model::{Anchor, Drawing, Item, Rgb, Stroke};
pub use sheet::Sheet;
pub use svg::{write_svg, CAP_HEIGHT_PER_EM};
#[cfg(feature = "png")]
pub(crate) use ticks::power_of_ten;
pub(crate) use ticks::{format_tick, nice_ticks};
