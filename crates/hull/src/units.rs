//! Length units of the input data.
//!
//! hullskin keeps coordinates in the user's units: nothing is converted on reading. The units
//! are metadata, carried from the reader to the exports (IGES global section, STEP, reports),
//! and used to word error messages ("expected the y coordinate in metres").

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

use crate::error::HullError;

/// The length unit of a set of offsets.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq, Hash, Serialize, Deserialize)]
pub enum Units {
    /// Metres (`m`), the default.
    #[default]
    #[serde(rename = "m")]
    Metre,
    /// Millimetres (`mm`).
    #[serde(rename = "mm")]
    Millimetre,
    /// International feet (`ft`), 0.3048 m.
    #[serde(rename = "ft")]
    Foot,
    /// International inches (`in`), 0.0254 m.
    #[serde(rename = "in")]
    Inch,
}

impl Units {
    /// Every unit, in the order of the enum.
    pub const ALL: [Units; 4] = [Units::Metre, Units::Millimetre, Units::Foot, Units::Inch];

    /// The short symbol accepted by [`FromStr`]: `m`, `mm`, `ft`, `in`.
    pub fn symbol(self) -> &'static str {
        match self {
            Units::Metre => "m",
            Units::Millimetre => "mm",
            Units::Foot => "ft",
            Units::Inch => "in",
        }
    }

    /// The plural English name, for messages: "metres", "millimetres", "feet", "inches".
    pub fn plural_name(self) -> &'static str {
        match self {
            Units::Metre => "metres",
            Units::Millimetre => "millimetres",
            Units::Foot => "feet",
            Units::Inch => "inches",
        }
    }

    /// Length of one unit in metres (exact by definition of the international foot and inch).
    pub fn metres_per_unit(self) -> f64 {
        match self {
            Units::Metre => 1.0,
            Units::Millimetre => 1e-3,
            Units::Foot => 0.3048,
            Units::Inch => 0.0254,
        }
    }

    /// The IGES unit flag (global parameter 14, IGES 5.3 section 2.2.4.3): 1 inch, 2 mm,
    /// 4 ft, 6 m.
    pub fn iges_flag(self) -> u8 {
        match self {
            Units::Metre => 6,
            Units::Millimetre => 2,
            Units::Foot => 4,
            Units::Inch => 1,
        }
    }

    /// The IGES unit name (global parameter 15) matching [`Units::iges_flag`]:
    /// `M`, `MM`, `FT`, `INCH`.
    pub fn iges_name(self) -> &'static str {
        match self {
            Units::Metre => "M",
            Units::Millimetre => "MM",
            Units::Foot => "FT",
            Units::Inch => "INCH",
        }
    }
}

impl fmt::Display for Units {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.symbol())
    }
}

impl FromStr for Units {
    type Err = HullError;

    /// Parses `m`, `mm`, `ft` or `in` (case-insensitive, surrounding spaces ignored).
    ///
    /// # Errors
    ///
    /// [`HullError::UnknownUnits`] for anything else.
    fn from_str(s: &str) -> Result<Self, Self::Err> {
        let t = s.trim();
        Units::ALL
            .into_iter()
            .find(|u| u.symbol().eq_ignore_ascii_case(t))
            .ok_or_else(|| HullError::UnknownUnits(s.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn symbols_round_trip_through_from_str() {
        for u in Units::ALL {
            assert_eq!(u.symbol().parse::<Units>().ok(), Some(u));
            assert_eq!(u.to_string().to_uppercase().parse::<Units>().ok(), Some(u));
            assert_eq!(format!("  {u} ").parse::<Units>().ok(), Some(u));
        }
    }

    #[test]
    fn unknown_units_are_an_error_naming_the_choices() {
        let err = "yd".parse::<Units>().err().map(|e| e.to_string()).unwrap_or_default();
        assert!(err.contains("\"yd\""), "{err}");
        assert!(err.contains("m, mm, ft or in"), "{err}");
        assert!("".parse::<Units>().is_err());
        assert!("metre".parse::<Units>().is_err());
    }

    #[test]
    fn conversion_factors_agree_with_each_other() {
        // 1 ft = 12 in and 1 m = 1000 mm, exactly by definition; the factors are stored as
        // decimal literals, so allow one rounding of the product (relative 1e-15).
        let ft = Units::Foot.metres_per_unit();
        let inch = Units::Inch.metres_per_unit();
        assert!((ft - 12.0 * inch).abs() <= 1e-15 * ft);
        assert!((Units::Metre.metres_per_unit() - 1000.0 * Units::Millimetre.metres_per_unit()).abs() <= 1e-15);
    }

    #[test]
    fn iges_flags_and_names_follow_the_standard() {
        let table: Vec<(u8, &str)> = Units::ALL.iter().map(|u| (u.iges_flag(), u.iges_name())).collect();
        assert_eq!(table, vec![(6, "M"), (2, "MM"), (4, "FT"), (1, "INCH")]);
    }

    #[test]
    fn serde_uses_the_symbols() {
        for u in Units::ALL {
            let json = serde_json::to_string(&u).unwrap_or_default();
            assert_eq!(json, format!("\"{}\"", u.symbol()));
            let back: Option<Units> = serde_json::from_str(&json).ok();
            assert_eq!(back, Some(u));
        }
    }
}
