//! The settings of [`super::digitize`] and what it returns.

use std::str::FromStr;

use super::geom::P2;
use crate::error::{DigitizeKind, HullError, Location};
use crate::offsets::Offsets;
use crate::units::Units;

/// The drawing's scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DrawingScale {
    /// `paper:model`, e.g. 1:50 is `{ paper: 1, model: 50 }`: a paper length in the drawing's
    /// units of length (see [`DigitizeOptions::drawing_unit_mm`]) stands for `model / paper`
    /// times it on the ship.
    Ratio { paper: f64, model: f64 },
    /// Drawing units per output unit (per metre for output in metres).
    UnitsPerModelUnit(f64),
}

impl FromStr for DrawingScale {
    type Err = HullError;

    /// `P:M` (e.g. `1:50`, `2:1`) or a plain number of drawing units per output unit.
    fn from_str(s: &str) -> Result<Self, HullError> {
        let bad = || HullError::Digitize(DigitizeKind::UnreadableScale { text: s.to_string() });
        let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0).ok_or_else(bad);
        match s.split_once(':') {
            Some((p, m)) => Ok(DrawingScale::Ratio { paper: num(p)?, model: num(m)? }),
            None => Ok(DrawingScale::UnitsPerModelUnit(num(s)?)),
        }
    }
}

/// How the station curves are told apart.
#[derive(Clone, Debug, PartialEq)]
pub enum StationIds {
    /// Each layer matching this glob (`*`, `?`; case-insensitive) holds one station, named by
    /// the layer.
    Layers(String),
    /// Each station curve has a text label next to it (the nearest curve to a label is its
    /// curve), or an SVG `<title>`/`id`, naming the station.
    Labels,
    /// The curves themselves, in this order, are the stations, named `0`, `1`, ...
    Order(CurveOrder),
}

/// The order of the station curves for [`StationIds::Order`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveOrder {
    /// As they come in the file.
    Drawn,
    /// By layer name (numbers in names compared as numbers: `ST2` before `ST10`), then as
    /// drawn.
    Layer,
    /// The body plan's own order, from aft to fore: the curves left of the centreline from
    /// the narrowest (the aft end) to the widest, then those right of it from the widest to
    /// the narrowest (the bow). Curves on the centreline come first. Holds for hulls whose
    /// sections grow towards midships.
    BodyPlan,
}

/// The stations' x positions.
#[derive(Clone, Debug, PartialEq)]
pub enum StationX {
    /// One x per station: in the curve order for [`StationIds::Order`], else in the order of
    /// the station names (by their station number when they have one, see
    /// [`label_number`](super::label_number), else alphabetically).
    List(Vec<f64>),
    /// x by station name (layer or label; compared trimmed, case-insensitively).
    Map(Vec<(String, f64)>),
    /// `x = origin + n spacing`, `n` the station number of the name ([`label_number`](super::label_number); the
    /// ordinal for [`StationIds::Order`]).
    Spacing { origin: f64, spacing: f64 },
}

/// Settings of [`digitize`](super::digitize()).
#[derive(Clone, Debug, PartialEq)]
pub struct DigitizeOptions {
    /// The drawing's scale.
    pub scale: DrawingScale,
    /// Millimetres per drawing unit, overriding what the file says (needed for a
    /// [`DrawingScale::Ratio`] when the file does not say it).
    pub drawing_unit_mm: Option<f64>,
    /// The drawing point where the body plan's centreline meets the baseline.
    pub datum: P2,
    /// The length unit of the output offsets.
    pub units: Units,
    /// Only curves on layers matching this glob (all when `None`).
    pub layers: Option<String>,
    /// How stations are told apart.
    pub stations: StationIds,
    /// Where the stations are.
    pub x: StationX,
    /// Resample each station to this many points evenly spaced along it (at least 2); `None`
    /// keeps the drawn points (polyline vertices, and points on curved pieces at the
    /// flatness tolerance).
    pub points: Option<usize>,
    /// Piece ends closer than this are joined, and points this close to the centreline are on
    /// it (drawing units; default `1e-4` of the drawing's diagonal).
    pub join_tol: Option<f64>,
    /// Curved pieces are flattened to within this (drawing units; default `1e-6` of the
    /// drawing's diagonal).
    pub flatness: Option<f64>,
    /// Labels farther than this from every curve are ignored (drawing units; default no limit).
    pub label_distance: Option<f64>,
}

impl DigitizeOptions {
    /// Options with the defaults: output in metres, every layer, drawn points kept, default
    /// tolerances.
    pub fn new(scale: DrawingScale, datum: P2, stations: StationIds, x: StationX) -> Self {
        DigitizeOptions {
            scale,
            drawing_unit_mm: None,
            datum,
            units: Units::Metre,
            layers: None,
            stations,
            x,
            points: None,
            join_tol: None,
            flatness: None,
            label_distance: None,
        }
    }
}

/// The side of the centreline a station is drawn on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Left of the centreline: the aft body, by the body plan convention.
    Aft,
    /// Right of the centreline: the fore body.
    Fore,
    /// On the centreline (a station with no breadth).
    Centreline,
}

/// What was found for one station.
#[derive(Clone, Debug, PartialEq)]
pub struct StationInfo {
    /// The station's name (layer, label, or ordinal).
    pub label: String,
    /// Its x.
    pub x: f64,
    /// The side it is drawn on.
    pub side: Side,
    /// The drawn curves (entities, subpaths) it was made of.
    pub curves: usize,
    /// Its points in the offsets.
    pub points: usize,
    /// Where its first curve is in the file.
    pub at: Location,
}

/// The result of [`digitize`](super::digitize()).
#[derive(Clone, Debug, PartialEq)]
pub struct Digitized {
    /// The sections, in order of x, each from keel to deck.
    pub offsets: Offsets,
    /// One entry per section, same order.
    pub stations: Vec<StationInfo>,
    /// What was skipped and why (the reader's notes first).
    pub notes: Vec<String>,
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn scales_parse() {
        assert_eq!("1:50".parse::<DrawingScale>().ok(), Some(DrawingScale::Ratio { paper: 1.0, model: 50.0 }));
        assert_eq!("20".parse::<DrawingScale>().ok(), Some(DrawingScale::UnitsPerModelUnit(20.0)));
        for bad in ["1:0", "x", "-3", "1:", "inf"] {
            assert!(bad.parse::<DrawingScale>().is_err(), "{bad}");
        }
    }
}
