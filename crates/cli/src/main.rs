//! The `hullskin` command line: fit one NURBS surface to a ship's offsets.
//!
//! `main` only maps the outcome of [`run`] to an exit code; each subcommand lives in its own
//! file and turns arguments into library calls.

use std::process::ExitCode;

use clap::builder::RangedU64ValueParser;
use clap::{Parser, Subcommand};

mod compare;
mod digitize;
mod export;
mod fit;
mod hydrostatics;
mod optim_args;
mod parse;
mod progress;
mod report;
mod skin_args;
mod slice;
mod stdout;
mod surface_arg;

/// Fit one fair NURBS hull surface to offset data by skinning.
#[derive(Debug, Parser)]
#[command(name = "hullskin", version, about, long_about = None)]
struct Cli {
    #[command(subcommand)]
    command: Option<Command>,
    /// Worker threads for the parallel parts (fit-error projections, optimiser populations,
    /// hydrostatics). Default: the HULLSKIN_THREADS environment variable, else all cores.
    /// Results do not depend on it: the same input and seed give the same bytes.
    #[arg(
        long,
        global = true,
        value_name = "N",
        value_parser = RangedU64ValueParser::<usize>::new().range(1..=MAX_THREADS as u64)
    )]
    threads: Option<usize>,
}

/// Most worker threads accepted (`--threads`, `HULLSKIN_THREADS`): far above any core count
/// hullskin can use, low enough that a typo does not spawn a million threads.
const MAX_THREADS: usize = 1024;

/// Size rayon's global pool from `--threads`, else `HULLSKIN_THREADS` (unset or empty: rayon's
/// default, all cores, or `RAYON_NUM_THREADS`).
fn init_threads(flag: Option<usize>) -> anyhow::Result<()> {
    let threads = match flag {
        Some(n) => Some(n),
        None => match std::env::var("HULLSKIN_THREADS") {
            Ok(s) if s.trim().is_empty() => None,
            Ok(s) => match s.trim().parse::<usize>() {
                Ok(n) if (1..=MAX_THREADS).contains(&n) => Some(n),
                _ => {
                    anyhow::bail!("HULLSKIN_THREADS={s:?}: expected a whole number of threads from 1 to {MAX_THREADS}")
                }
            },
            Err(std::env::VarError::NotPresent) => None,
            Err(e) => anyhow::bail!("HULLSKIN_THREADS: {e}"),
        },
    };
    if let Some(n) = threads {
        rayon::ThreadPoolBuilder::new()
            .num_threads(n)
            .build_global()
            .map_err(|e| anyhow::anyhow!("cannot start {n} worker threads: {e}"))?;
    }
    Ok(())
}

#[derive(Debug, Subcommand)]
enum Command {
    /// Fit a surface to offsets (the built-in Series 60 sample when no input is given) and
    /// write surface.igs, surface.json and report.json.
    Fit(fit::FitArgs),
    /// Compare interpolation, approximation and every weight optimiser at the same control
    /// points; write compare.json and compare.md and print the table with the floors.
    Compare(compare::CompareArgs),
    /// Hydrostatics from the surface (a surface.json, or offsets fitted first) at a draft or a
    /// range of drafts: volume, displacement, centres, coefficients, waterplane, wetted
    /// surface and metacentres, as text, CSV or JSON.
    Hydrostatics(hydrostatics::HydrostaticsArgs),
    /// One self-contained HTML report of a surface (a surface.json, or offsets fitted first):
    /// particulars, fit error, hydrostatics, curvature and fairness, lines plan, curvature
    /// maps, convergence and the 3-D viewer; writes report.html and the files it is made of.
    Report(report::ReportArgs),
    /// Digitise a body plan drawn as DXF or SVG: read its station curves with the drawing's
    /// scale and datum, and write them as offsets (a sections CSV).
    Digitize(digitize::DigitizeArgs),
    /// Slice a hull mesh (STL or OBJ, optionally gzipped) at stations into sections, keel to
    /// deck edge on the starboard side, and write them as a sections CSV; optionally the
    /// mesh's hydrostatics at a draft and a fitted surface measured against the mesh.
    Slice(slice::SliceArgs),
    /// Export a surface (a surface.json, or offsets fitted first) as STEP, IGES (with section
    /// curves, or a polynomial approximation), DXF 3-D lines, STL, OBJ or binary glTF.
    Export(export::ExportArgs),
}

fn main() -> ExitCode {
    let code = match run() {
        Ok(code) => code,
        Err(err) => {
            eprintln!("hullskin: error: {err:#}");
            ExitCode::from(2)
        }
    };
    match stdout::failure() {
        Some(why) => {
            eprintln!("hullskin: error: could not write to standard output: {why}");
            ExitCode::from(2)
        }
        None => code,
    }
}

fn run() -> anyhow::Result<ExitCode> {
    let cli = Cli::parse();
    init_threads(cli.threads)?;
    match cli.command {
        Some(Command::Fit(args)) => fit::run(&args),
        Some(Command::Compare(args)) => compare::run(&args),
        Some(Command::Hydrostatics(args)) => hydrostatics::run(&args),
        Some(Command::Report(args)) => report::run(&args),
        Some(Command::Digitize(args)) => digitize::run(&args),
        Some(Command::Slice(args)) => slice::run(&args),
        Some(Command::Export(args)) => export::run(&args),
        None => fit::run(&fit::FitArgs::default()),
    }
}

/// One subcommand's arguments `A` as a parser of their own: the unit tests of each
/// subcommand's flags parse through it.
#[cfg(test)]
#[derive(Debug, clap::Parser)]
struct Wrap<A: clap::Args> {
    #[command(flatten)]
    args: A,
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::CommandFactory;

    #[test]
    fn the_command_line_definition_is_consistent() {
        Cli::command().debug_assert();
    }

    /// Every option of every subcommand, given hostile values, parses to a value or a clap
    /// error, never a panic: a value parser whose output does not match its field's type
    /// panics only when the option is used (`slice --at` did).
    #[test]
    fn every_option_takes_any_value_without_panicking() {
        let values = ["1", "0", "-1", "2,3", "1,2,3", "1e308,-1e308", "nan", "inf", "x", "", "1:50", "m", "auto"];
        let cli = Cli::command();
        let mut tried = 0;
        for sub in cli.get_subcommands() {
            for arg in sub.get_arguments() {
                let Some(long) = arg.get_long() else { continue };
                let flag = format!("--{long}");
                let takes_value = arg.get_action().takes_values();
                let runs: Vec<Vec<String>> = if takes_value {
                    values.iter().map(|v| vec![flag.clone(), v.to_string()]).collect()
                } else {
                    vec![vec![flag.clone()]]
                };
                for run in runs {
                    let mut argv = vec!["hullskin".to_string(), sub.get_name().to_string()];
                    argv.extend(run.iter().cloned());
                    // A positional input where one is required.
                    argv.push("input.csv".into());
                    let result = std::panic::catch_unwind(|| Cli::try_parse_from(&argv).map(|_| ()));
                    assert!(result.is_ok(), "panic on {argv:?}");
                    tried += 1;
                }
            }
        }
        // Every subcommand has options: the loop really ran over them.
        assert!(tried > 200, "{tried}");
    }
}
