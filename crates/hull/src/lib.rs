//! The hull domain of hullskin, on top of the `nurbs` kernel: the offset data model and its
//! readers, the offsets -> surface pipeline, fit error, and exports.
//!
//! Axes everywhere: x forward (aft to fore), y to starboard (half-breadth, >= 0), z up from
//! the baseline; coordinates stay in the user's [`Units`].

mod error;
pub mod export;
mod offsets;
pub mod read;
mod sample;
mod units;

pub use error::{HullError, InputErrorKind, Location};
pub use offsets::{Offsets, Section, COINCIDENT_REL, PLANAR_REL};
pub use read::{
    decode, detect_format, parse_offset_table, parse_offsets, parse_sections_csv, read_offsets, InputFormat,
};
pub use sample::{series60_sample, Particulars, SAMPLE_PARTICULARS, SERIES60_CB060_CSV, SERIES60_SOURCE};
pub use units::Units;
