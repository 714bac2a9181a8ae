//! The fit's hold and knuckle settings by the names the command line (`--envelope`,
//! `--knuckles`) and the Python bindings (`envelope=`, `knuckles=`) take: one table of names,
//! descriptions and settings for both, so that the same word fits the same surface.

use std::str::FromStr;

use nurbs::fit::CornerOptions;

use crate::fit::{EnvelopeHold, HoldOn, Knuckles};

/// `--envelope`: whether and how a surface that leaves the offsets' envelope is held within
/// it ([`FitConfig::envelope`](crate::FitConfig::envelope) and
/// [`FitConfig::hold_on`](crate::FitConfig::hold_on) together).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum EnvelopeChoice {
    /// Held by its control net (the default).
    #[default]
    Hold,
    /// Held by its sampled points.
    HoldSurface,
    /// Not held: the plain least squares, its findings reported.
    Free,
}

impl EnvelopeChoice {
    /// Every choice, in the order the help lists them.
    pub const ALL: [EnvelopeChoice; 3] = [EnvelopeChoice::Hold, EnvelopeChoice::HoldSurface, EnvelopeChoice::Free];

    /// `hold`, `hold-surface` or `free`.
    pub fn name(self) -> &'static str {
        match self {
            EnvelopeChoice::Hold => "hold",
            EnvelopeChoice::HoldSurface => "hold-surface",
            EnvelopeChoice::Free => "free",
        }
    }

    /// One line for the help.
    pub fn description(self) -> &'static str {
        match self {
            EnvelopeChoice::Hold => "Hold the surface within the offsets' envelope by its control net",
            EnvelopeChoice::HoldSurface => "Hold the surface within the offsets' envelope by its sampled points",
            EnvelopeChoice::Free => "Keep the plain least squares, its findings reported",
        }
    }

    /// The settings of [`FitConfig`](crate::FitConfig): the envelope held (the offsets' own,
    /// or none) and what holds it.
    pub fn settings(self) -> (EnvelopeHold, HoldOn) {
        match self {
            EnvelopeChoice::Hold => (EnvelopeHold::Own, HoldOn::Net),
            EnvelopeChoice::HoldSurface => (EnvelopeHold::Own, HoldOn::Surface),
            EnvelopeChoice::Free => (EnvelopeHold::Free, HoldOn::Net),
        }
    }
}

impl FromStr for EnvelopeChoice {
    type Err = String;

    /// A [`EnvelopeChoice::name`], exactly.
    fn from_str(s: &str) -> Result<Self, String> {
        by_name(s, &Self::ALL, Self::name)
    }
}

/// `--knuckles`: the knuckle lines (chines) kept as creases, with a corner angle given apart
/// ([`FitConfig::knuckles`](crate::FitConfig::knuckles)).
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum KnuckleChoice {
    /// Keep the knuckle lines found in the sections (the default).
    #[default]
    Auto,
    /// As `auto`, and refit an approximation within the flats of side and bottom.
    AutoFlats,
    /// One smooth surface.
    Off,
}

impl KnuckleChoice {
    /// Every choice, in the order the help lists them.
    pub const ALL: [KnuckleChoice; 3] = [KnuckleChoice::Auto, KnuckleChoice::AutoFlats, KnuckleChoice::Off];

    /// `auto`, `auto+flats` or `off`.
    pub fn name(self) -> &'static str {
        match self {
            KnuckleChoice::Auto => "auto",
            KnuckleChoice::AutoFlats => "auto+flats",
            KnuckleChoice::Off => "off",
        }
    }

    /// One line for the help.
    pub fn description(self) -> &'static str {
        match self {
            KnuckleChoice::Auto => "Keep the knuckle lines found in the sections",
            KnuckleChoice::AutoFlats => "As `auto`, and refit an approximation within the flats of side and bottom",
            KnuckleChoice::Off => "One smooth surface",
        }
    }

    /// The setting of [`FitConfig`](crate::FitConfig), corners found at `corner`.
    pub fn knuckles(self, corner: CornerOptions) -> Knuckles {
        match self {
            KnuckleChoice::Auto => Knuckles::Auto(corner),
            KnuckleChoice::AutoFlats => Knuckles::AutoFlats(corner),
            KnuckleChoice::Off => Knuckles::Off,
        }
    }
}

impl FromStr for KnuckleChoice {
    type Err = String;

    /// A [`KnuckleChoice::name`], exactly.
    fn from_str(s: &str) -> Result<Self, String> {
        by_name(s, &Self::ALL, Self::name)
    }
}

/// The choice of `all` named `s` exactly, or an error listing their names (`a, b or c`).
fn by_name<T: Copy>(s: &str, all: &[T], name: fn(T) -> &'static str) -> Result<T, String> {
    all.iter().copied().find(|&c| name(c) == s).ok_or_else(|| {
        let names: Vec<&str> = all.iter().map(|&c| name(c)).collect();
        let (last, rest) = names.split_last().expect("a choice at least");
        format!("unknown `{s}` (expected {} or {last})", rest.join(", "))
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_read_back_and_give_the_settings() {
        for c in EnvelopeChoice::ALL {
            assert_eq!(c.name().parse::<EnvelopeChoice>(), Ok(c));
        }
        let settings: Vec<(EnvelopeHold, HoldOn)> = EnvelopeChoice::ALL.iter().map(|c| c.settings()).collect();
        assert_eq!(
            settings,
            [(EnvelopeHold::Own, HoldOn::Net), (EnvelopeHold::Own, HoldOn::Surface), (EnvelopeHold::Free, HoldOn::Net)]
        );
        assert_eq!(EnvelopeChoice::default().settings(), (EnvelopeHold::default(), HoldOn::default()));
        let corner = CornerOptions { min_angle_deg: 25.0, ..CornerOptions::default() };
        for c in KnuckleChoice::ALL {
            assert_eq!(c.name().parse::<KnuckleChoice>(), Ok(c));
            assert_eq!(c.knuckles(corner).name().split('(').next(), Some(c.name()));
        }
        assert_eq!(
            "hold surface".parse::<EnvelopeChoice>(),
            Err("unknown `hold surface` (expected hold, hold-surface or free)".into())
        );
        assert_eq!("some".parse::<KnuckleChoice>(), Err("unknown `some` (expected auto, auto+flats or off)".into()));
    }
}
