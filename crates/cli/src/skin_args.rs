//! The input and skinning flags shared by `fit`, `compare`, `hydrostatics` and `report`.

use std::path::PathBuf;

use clap::Args;
use hull::optimize::OptimSettings;
use hull::{FitConfig, FitMethod, Offsets, Units};
use nurbs::fit::SkinParameterization;

use crate::parse::{parse_pair, parse_param, parse_units};

/// Which offsets, and how the sections are skinned.
#[derive(Debug, Clone, Args)]
pub struct SkinArgs {
    /// Offsets file: a sections CSV (header `section,x,y,z`) or an offset table CSV (first row
    /// station positions, first column waterline heights, cells half-breadths). Without it the
    /// built-in Series 60 Cb 0.60 parent hull is used.
    pub input: Option<PathBuf>,
    /// Control points NU,NV of the approximation and of the weight-optimised methods (u along
    /// each section, v across sections). Default: three quarters of the offsets in each
    /// direction (of the largest section along u, of the sections along v). Interpolation has
    /// its own count: one per offset.
    #[arg(long, value_parser = parse_pair)]
    pub ctrl: Option<(usize, usize)>,
    /// Degrees P,Q in u (along sections) and v (across sections).
    #[arg(long, default_value = "3,3", value_parser = parse_pair)]
    pub degree: (usize, usize),
    /// Parameterization of the offsets: centripetal, chord, uniform or universal; one name for
    /// both directions, or U,V for along the sections (u) and across them (v).
    #[arg(long, default_value = "centripetal,chord", value_parser = parse_param)]
    pub param: SkinParameterization,
    /// Units of the input coordinates, carried to the exports and the reported errors: m, mm,
    /// ft or in.
    #[arg(long, default_value = "m", value_parser = parse_units)]
    pub units: Units,
}

impl Default for SkinArgs {
    fn default() -> Self {
        SkinArgs {
            input: None,
            ctrl: None,
            degree: (3, 3),
            param: SkinParameterization::default(),
            units: Units::Metre,
        }
    }
}

impl SkinArgs {
    /// The offsets: the input file read in `units`, or the built-in sample.
    pub fn offsets(&self) -> anyhow::Result<Offsets> {
        Ok(match &self.input {
            Some(path) => hull::read_offsets(path, self.units)?,
            None => hull::series60_sample(),
        })
    }

    /// The library's fit settings: these skinning flags with `method` and the weight
    /// optimisers' `optim`.
    pub fn fit_config(&self, method: FitMethod, optim: OptimSettings) -> FitConfig {
        FitConfig { method, degree: self.degree, ctrl: self.ctrl, param: self.param, optim }
    }
}
