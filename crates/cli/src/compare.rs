//! `hullskin compare`: every method at the same control points, one table.
//!
//! Runs skinning interpolation, the plain approximation, and the approximation with its weights
//! optimised by GA, PSO, GSA, LM and GSA+LM; writes `DIR/compare.json` and `DIR/compare.md`
//! (each atomically) and prints the Markdown table with the floors of issue 3.
//!
//! Ctrl-C stops the optimiser that is running (keeping its best surface so far, which is
//! measured and marked `interrupted`) and then the whole comparison: what was done is written,
//! the methods not run are listed, and the exit status is 130. A second Ctrl-C quits at once.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use hull::CompareConfig;

use crate::optim_args::OptimArgs;
use crate::progress;
use crate::skin_args::SkinArgs;

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
}

/// Run `hullskin compare`.
pub fn run(args: &CompareArgs) -> anyhow::Result<ExitCode> {
    let offsets = args.skin.offsets()?;
    let s = &args.skin;
    let config = CompareConfig { degree: s.degree, ctrl: s.ctrl, param: s.param, optim: args.optim.settings() };
    let comparison = hull::compare_offsets_with(&offsets, &config, &mut |algorithm, fit| {
        progress::with_progress(algorithm.name(), |control| fit(control))
    })?;
    let dir = &args.out;
    std::fs::create_dir_all(dir).with_context(|| format!("cannot create output directory {}", dir.display()))?;
    let markdown = hull::comparison_markdown(&comparison);
    for (name, text) in [("compare.json", hull::comparison_json(&comparison)), ("compare.md", markdown.clone())] {
        let path = dir.join(name);
        hull::write_atomic(&path, |w| w.write_all(text.as_bytes()))
            .with_context(|| format!("cannot write {}", path.display()))?;
    }
    print!("{markdown}");
    println!("\nwrote {}", dir.join("{compare.json,compare.md}").display());
    if !comparison.complete || progress::stopped() {
        eprintln!("hullskin: interrupted: wrote the methods done before the stop");
        return Ok(ExitCode::from(130));
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    #[derive(Debug, Parser)]
    struct Wrap {
        #[command(flatten)]
        args: CompareArgs,
    }

    #[test]
    fn flags_reach_the_config() {
        let w = Wrap::try_parse_from(["x", "in.csv", "--ctrl", "5,9", "--seed", "7", "--iterations", "3"])
            .expect("valid flags");
        assert_eq!(w.args.skin.ctrl, Some((5, 9)));
        assert_eq!(w.args.out, PathBuf::from("hullskin-compare"));
        let s = w.args.optim.settings();
        assert_eq!((s.seed, s.iterations, s.population), (7, Some(3), None));
        assert!(Wrap::try_parse_from(["x", "--ctrl", "5"]).is_err());
    }
}
