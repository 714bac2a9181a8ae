//! `hullskin hydrostatics`: the hydrostatic table of a surface (a `surface.json` from `fit`, or
//! offsets fitted first), one draft or a range, as text, CSV or JSON.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::Context;
use clap::{Args, ValueEnum};
use hull::{
    FitMethod, Hydrostatics, HydrostaticsOptions, HydrostaticsTable, InputNames, OptimSettings, SEA_WATER_DENSITY,
};

use crate::fit::fit_with_progress;
use crate::parse::parse_skin_method;
use crate::skin_args::SkinArgs;
use crate::stdout::{out, outln};
use crate::surface_arg::{read_input, Input};

/// Output format of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum Format {
    /// Aligned columns with their units.
    Text,
    /// A header of the column keys, then one line per draft.
    Csv,
    /// `{"source", "units", "density", "rows": [{"draft": .., ...}]}`.
    Json,
}

/// Arguments of `hullskin hydrostatics`.
#[derive(Debug, Args)]
#[command(mut_arg("input", |a| a
    .value_name("SURFACE")
    .help("A surface.json written by `hullskin fit`, an IGES or STEP file (one B-spline surface, or the patches of one hull, integrated together), or an offsets file (sections CSV or offset table) \
           fitted first with --method and the skinning flags. Without it the built-in Series 60 \
           Cb 0.60 sample is fitted")))]
pub struct HydrostaticsArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Fit of an offsets input: interp or approx.
    #[arg(long, default_value = "approx", value_parser = parse_skin_method)]
    pub method: FitMethod,
    /// Draft T (z of the waterplane above the baseline, in the surface's length unit); the
    /// first draft of a range with --to and --step.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub draft: f64,
    /// Last draft of a range (included when the steps land on it).
    #[arg(long, value_name = "T2", requires = "step", allow_negative_numbers = true)]
    pub to: Option<f64>,
    /// Step of a range, of the sign of T2 - T.
    #[arg(long, value_name = "DT", requires = "to", allow_negative_numbers = true)]
    pub step: Option<f64>,
    /// Water density in t/m³ (displacement in tonnes whatever the length unit).
    #[arg(long, value_name = "RHO", default_value_t = SEA_WATER_DENSITY, allow_negative_numbers = true)]
    pub density: f64,
    /// Output format.
    #[arg(long, value_enum, default_value = "text")]
    pub format: Format,
    /// The table as JSON on standard output, for scripts (the same as --format json, as
    /// `fit`, `report` and the other commands spell it).
    #[arg(long, conflicts_with = "format")]
    pub json: bool,
    /// Write the table to FILE instead of standard output.
    #[arg(short = 'o', long = "out", value_name = "FILE")]
    pub out: Option<PathBuf>,
}

/// The drafts asked for: `--draft`, or the range to `--to` by `--step`, with `--density`
/// checked too ([`hull::table_drafts`]).
fn drafts(args: &HydrostaticsArgs) -> anyhow::Result<Vec<f64>> {
    Ok(hull::table_drafts(Some(args.draft), args.to, args.step, args.density, InputNames::Flags)?)
}

/// Run `hullskin hydrostatics`.
pub fn run(args: &HydrostaticsArgs) -> anyhow::Result<ExitCode> {
    let drafts = drafts(args)?;
    let (surfaces, units, source, data_pp) = match read_input(&args.skin)? {
        Input::Surface { surface, units, source } => {
            crate::surface_arg::note_units_not_applied(&args.skin, units, &source);
            (vec![surface], units, source, None)
        }
        Input::Patches { surfaces, names, units, source } => {
            eprintln!(
                "hullskin: note: {source}: {} surfaces ({}) integrated together as the patches of one hull",
                surfaces.len(),
                names.join(", ")
            );
            (surfaces, units, source, None)
        }
        Input::Offsets(offsets) => {
            let config = args.skin.fit_config(args.method, OptimSettings::default());
            let (outcome, _) = fit_with_progress(&offsets, &config, hull::Goal::Count)
                .with_context(|| format!("cannot fit {}", offsets.source))?;
            (
                vec![outcome.surface],
                offsets.units,
                format!("{}, fitted by {}", offsets.source, args.method.name()),
                offsets.perpendiculars,
            )
        }
    };
    let perpendiculars = args.skin.perpendiculars(data_pp)?;
    let options =
        HydrostaticsOptions { density: args.density, units, perpendiculars, ..HydrostaticsOptions::default() };
    let hydro = Hydrostatics::patches(&surfaces, &options)?;
    let rows = hydro.rows(&drafts).with_context(|| format!("hydrostatics of {source}"))?;
    // Centre-plane webs (a station sliced from a mesh as two pieces joined on y = 0): their
    // area is left out of S; say how much (the largest over the drafts), on standard error so
    // the table stays clean.
    let mut web = (0.0, 0.0);
    for &t in &drafts {
        let area = hydro.web_area(t).with_context(|| format!("hydrostatics of {source}"))?;
        if area > web.0 {
            web = (area, t);
        }
    }
    if web.0 > 0.0 {
        let u = units.symbol();
        let at = if drafts.len() > 1 {
            format!(" (largest, at draft {})", hull::format_short(web.1))
        } else {
            String::new()
        };
        eprintln!("hullskin: note: centre-plane web of {} {u}² left out of S and Lwl{at}", hull::format_short(web.0));
    }
    let table = HydrostaticsTable { source, units, density: args.density, perpendiculars, rows };
    let format = if args.json { Format::Json } else { args.format };
    let text = match format {
        Format::Text => table.text(),
        Format::Csv => table.csv(),
        Format::Json => table.json(),
    };
    match &args.out {
        Some(path) => {
            hull::write_atomic(path, |w| w.write_all(text.as_bytes()))
                .with_context(|| format!("cannot write {}", path.display()))?;
            outln!("wrote {}", path.display());
        }
        None => out!("{text}"),
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    type Wrap = crate::Wrap<HydrostaticsArgs>;

    #[test]
    fn flags_reach_the_arguments() {
        let w = Wrap::try_parse_from(["x", "s.json", "--draft", "2", "--to", "6", "--step", "0.5", "--format", "csv"])
            .expect("valid flags");
        assert_eq!(w.args.skin.input, Some(PathBuf::from("s.json")));
        assert_eq!((w.args.draft, w.args.to, w.args.step), (2.0, Some(6.0), Some(0.5)));
        assert_eq!((w.args.format, w.args.density), (Format::Csv, SEA_WATER_DENSITY));
        assert_eq!(drafts(&w.args).expect("valid range").len(), 9);
        // --to needs --step and the other way round; the draft is required.
        assert!(Wrap::try_parse_from(["x", "--draft", "2", "--to", "6"]).is_err());
        assert!(Wrap::try_parse_from(["x", "--draft", "2", "--step", "1"]).is_err());
        assert!(Wrap::try_parse_from(["x"]).is_err());
        assert!(Wrap::try_parse_from(["x", "--draft", "2", "--method", "ga"]).is_err());
        let down = Wrap::try_parse_from(["x", "--draft", "6", "--to", "2", "--step", "-2"]).expect("downward");
        assert_eq!(drafts(&down.args).expect("valid"), vec![6.0, 4.0, 2.0]);
    }

    #[test]
    fn bad_drafts_are_refused_before_any_fit() {
        for argv in [
            &["x", "--draft", "0"][..],
            &["x", "--draft", "-1"],
            &["x", "--draft", "NaN"],
            &["x", "--draft", "1", "--to", "3", "--step", "0"],
            &["x", "--draft", "1", "--to", "3", "--step", "-1"],
            &["x", "--draft", "1", "--to", "-3", "--step", "-1"],
        ] {
            let w = Wrap::try_parse_from(argv).expect("parses");
            assert!(drafts(&w.args).is_err(), "{argv:?}");
        }
    }
}
