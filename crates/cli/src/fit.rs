//! `hullskin fit`: read offsets, skin a surface, measure its true error, write the outputs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use hull::{FitConfig, FitMethod};

use crate::optim_args::OptimArgs;
use crate::progress;
use crate::skin_args::SkinArgs;

/// Arguments of `hullskin fit`.
#[derive(Debug, Args)]
pub struct FitArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Output directory for surface.igs, surface.json and report.json.
    #[arg(short = 'o', long = "out", default_value = "hullskin-out")]
    pub out: PathBuf,
    /// Method: `interp` passes through every offset; `approx` is a least-squares fit with the
    /// control-point counts of --ctrl; `ga`, `pso`, `gsa`, `lm` and `gsa+lm` then optimise the
    /// approximation's weights (Genetic Algorithm, Particle Swarm, Gravitational Search,
    /// Levenberg-Marquardt, GSA then LM).
    #[arg(long, default_value = "approx", value_parser = parse_method)]
    pub method: FitMethod,
    /// Search the control-point counts for the fewest control points whose max error (true
    /// closest-point distance, in the input's units) is within T, for approx or an optimised
    /// method; report.json gets a "tolerance_search" block.
    #[arg(long, value_name = "T", conflicts_with = "ctrl")]
    pub tolerance: Option<f64>,
    #[command(flatten)]
    pub optim: OptimArgs,
}

impl Default for FitArgs {
    fn default() -> Self {
        FitArgs {
            skin: SkinArgs::default(),
            out: PathBuf::from("hullskin-out"),
            method: FitMethod::Approx,
            tolerance: None,
            optim: OptimArgs::default(),
        }
    }
}

fn parse_method(s: &str) -> Result<FitMethod, String> {
    s.parse()
}

/// Run `hullskin fit`.
pub fn run(args: &FitArgs) -> anyhow::Result<ExitCode> {
    let offsets = args.skin.offsets()?;
    let config = FitConfig {
        method: args.method,
        degree: args.skin.degree,
        ctrl: args.skin.ctrl,
        param: args.skin.param,
        optim: args.optim.settings(),
    };
    let fit = |control: &hull::optimize::Control<'_>| match args.tolerance {
        Some(t) => hull::fit_to_tolerance(&offsets, &config, &hull::ToleranceSettings::new(t), control)
            .map(|r| (r.outcome, Some(r.search))),
        None => hull::fit_offsets_with(&offsets, &config, control).map(|o| (o, None)),
    };
    let (outcome, search) = match args.method.algorithm() {
        Some(a) => progress::with_progress(a.name(), fit)?,
        None => hull::optimize::quiet(fit)?,
    };
    let mut report = hull::Report::new(&offsets, &outcome);
    report.tolerance_search = search;
    write_outputs(&args.out, &offsets, &outcome, &report)?;
    print!("{}", hull::summary_table(&offsets, &outcome));
    if let Some(s) = &report.tolerance_search {
        println!("{}", s.summary(offsets.units.symbol()));
    }
    println!("wrote {}", args.out.join("{surface.igs,surface.json,report.json}").display());
    if progress::stopped() {
        eprintln!("hullskin: interrupted: wrote the best surface found before the stop");
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

fn write_outputs(
    dir: &Path,
    offsets: &hull::Offsets,
    outcome: &hull::FitOutcome,
    report: &hull::Report,
) -> anyhow::Result<()> {
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    hull::write_fit_outputs_with_report(dir, offsets, outcome, report)
        .with_context(|| format!("cannot write outputs to {}", dir.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::parse_param;
    use nurbs::fit::{Parameterization, SkinParameterization};

    #[test]
    fn param_takes_one_name_or_one_per_direction() {
        let both = parse_param("chord").expect("one name");
        assert_eq!((both.u, both.v), (Parameterization::ChordLength, Parameterization::ChordLength));
        let pair = parse_param("centripetal,chord").expect("two names");
        assert_eq!(pair, SkinParameterization::default());
        assert_eq!(FitArgs::default().skin.param, pair);
        let err = parse_param("centripetal,bogus").expect_err("unknown name");
        assert!(err.contains("bogus") && err.contains("universal"), "{err}");
    }
}
