//! Drawings: a format-independent model of a sheet ([`Drawing`]), colour maps, and the figures
//! built on them.

pub mod colormap;
pub mod model;

pub use model::{Anchor, Drawing, Item, Rgb, Stroke};
