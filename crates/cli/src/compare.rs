//! `hullskin compare`: every method at the same control points, one table.
//!
//! Runs skinning interpolation, the plain approximation, and the approximation with its weights
//! optimised by GA, PSO, GSA, LM and GSA+LM; writes `DIR/compare.json` and `DIR/compare.md`
//! (both or neither: staged beside `DIR` and moved in together) and prints the Markdown table
//! with the floors of issue 3.
//!
//! SIGINT (Ctrl-C) or SIGTERM stops the optimiser that is running (keeping its best surface so
//! far, which is measured and marked `interrupted`) and then the whole comparison: what was done
//! is written, complete, the methods not run are listed, and the exit status is 130 (SIGINT) or
//! 143 (SIGTERM). A second signal quits at once, writing nothing.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use hull::CompareConfig;

use crate::optim_args::OptimArgs;
use crate::progress;
use crate::skin_args::SkinArgs;
use crate::stdout::{out, outln};

/// Arguments of `hullskin compare`.
#[derive(Debug, Args)]
pub struct CompareArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Output directory for compare.json and compare.md.
    #[arg(short = 'o', long = "out", default_value = "hullskin-compare")]
    pub out: PathBuf,
    #[command(flatten)]
    pub optim: OptimArgs,
    /// Folds K of each row's held-out error (cross-validation, as `hullskin fit --held-out`),
    /// with the column saying which rows over-fit; 0 turns it off.
    #[arg(long = "held-out", value_name = "K", default_value_t = hull::HeldOutOptions::DEFAULT_FOLDS, value_parser = crate::fit::parse_folds)]
    pub held_out: usize,
    /// Print compare.json on standard output instead of the table, for scripts; notes and the
    /// files written go to standard error.
    #[arg(long)]
    pub json: bool,
}

/// Run `hullskin compare`.
pub fn run(args: &CompareArgs) -> anyhow::Result<ExitCode> {
    progress::install_stop_handler();
    let offsets = args.skin.offsets()?;
    let s = &args.skin;
    let config = CompareConfig {
        degree: s.degree,
        ctrl: s.ctrl,
        param: s.param,
        optim: args.optim.settings(),
        held_out: (args.held_out > 0).then(|| hull::HeldOutOptions::with_folds(args.held_out)),
    };
    // A stop between two optimisers ends the comparison too (not the run).
    let comparison = progress::stoppable(|| {
        hull::compare_offsets_with(&offsets, &config, &mut |algorithm, fit| {
            progress::with_progress(algorithm.name(), |control| fit(control))
        })
    })?;
    let dir = &args.out;
    let markdown = hull::comparison_markdown(&comparison);
    // Both files or neither: staged beside DIR and moved in together.
    let json = hull::comparison_json(&comparison);
    let mut out = hull::OutputDir::stage(dir).with_context(|| format!("cannot write into {}", dir.display()))?;
    for (name, text) in [("compare.json", &json), ("compare.md", &markdown)] {
        out.write_bytes(name, text.as_bytes()).with_context(|| format!("cannot write {name}"))?;
    }
    out.commit().with_context(|| format!("cannot write into {}", dir.display()))?;
    let wrote = format!("wrote {}", dir.join("{compare.json,compare.md}").display());
    if args.json {
        out!("{json}");
        eprintln!("hullskin: {wrote}");
    } else {
        out!("{markdown}");
        outln!("\n{wrote}");
    }
    if !comparison.complete || progress::stopped() {
        let status = progress::stop_status().unwrap_or(130);
        eprintln!("hullskin: interrupted: wrote the methods done before the stop (exit status {status})");
        return Ok(ExitCode::from(status));
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    type Wrap = crate::Wrap<CompareArgs>;

    #[test]
    fn flags_reach_the_config() {
        let w = Wrap::try_parse_from(["x", "in.csv", "--ctrl", "5,9", "--seed", "7", "--iterations", "3"])
            .expect("valid flags");
        assert_eq!(w.args.skin.ctrl, Some((5, 9)));
        assert_eq!(w.args.out, PathBuf::from("hullskin-compare"));
        let s = w.args.optim.settings();
        assert_eq!((s.seed, s.iterations, s.population), (7, Some(3), None));
        assert!(Wrap::try_parse_from(["x", "--ctrl", "5"]).is_err());
        assert_eq!(w.args.held_out, 4, "cross-validated by default");
        let off = Wrap::try_parse_from(["x", "--held-out", "0"]).expect("valid");
        assert_eq!(off.args.held_out, 0);
        let e = Wrap::try_parse_from(["x", "--held-out", "1"]).expect_err("one fold");
        assert!(e.to_string().contains("expected 0 to turn it off, or at least 2"), "{e}");
        assert!(Wrap::try_parse_from(["x", "--held-out", "-1"]).is_err());
    }
}
