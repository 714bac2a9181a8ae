//! `hullskin report`: one self-contained HTML report of a hull surface, with its pictures and
//! tables as separate files.
//!
//! The input is a `surface.json` (used as it is; offsets for the fit error from `--offsets`)
//! or offsets, fitted first with the flags of `fit` (the built-in sample without input).
//! Everything is written into `DIR` all or nothing (staged beside it and moved in when the
//! whole report is built); see [`view::write_report`]. A SIGINT or SIGTERM during
//! an optimised fit stops it and reports on the best surface so far (exit status 130 or 143).

use std::path::{Path, PathBuf};
use std::process::ExitCode;
use std::time::Instant;

use anyhow::{bail, Context};
use clap::Args;
use hull::{CompareConfig, Comparison, FitOutcome, Offsets, ToleranceSearch, Units, SEA_WATER_DENSITY};
use nurbs::NurbsSurface;
use view::Sheet;
use view::{build_report, write_report, DraftChoice, ReportInputs, ReportOptions};

use crate::fit::MethodArgs;
use crate::progress;
use crate::skin_args::SkinArgs;
use crate::stdout::outln;
use crate::surface_arg::{read_input, Input};

/// Arguments of `hullskin report`.
#[derive(Debug, Args)]
#[command(mut_arg("input", |a| a
    .value_name("SURFACE_OR_INPUT")
    .help("A surface.json written by `hullskin fit` or an IGES or STEP file of one B-spline surface (used as it is), or an offsets file (sections CSV \
           or offset table) fitted first with --method and the skinning flags. Without it the built-in \
           Series 60 Cb 0.60 sample is fitted")),
    mut_arg("method", |a| a.help("Fit of an offsets input, as `hullskin fit --method`: interp, approx, or approx \
           with its weights optimised by ga, pso, gsa, lm or gsa+lm (the report then plots the convergence)")),
    mut_arg("tolerance", |a| a.help("As `hullskin fit --tolerance`: fit an offsets input with the fewest control \
           points whose max error is within T (approx or an optimised method), or `default` (0.5 % of the beam); the report \
           notes the search")))]
pub struct ReportArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Output directory for report.html and the files it is made of.
    #[arg(short = 'o', long = "out", default_value = "hullskin-report")]
    pub out: PathBuf,
    #[command(flatten)]
    pub fit: MethodArgs,
    /// Design draft T (z of the waterplane above the baseline, in the surface's length unit).
    /// Without it the hydrostatics are tabulated at 10 drafts from the keel to the top of the
    /// offsets (of the surface, without offsets).
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub draft: Option<f64>,
    /// Water density in t/m³ (displacement in tonnes whatever the length unit).
    #[arg(long, value_name = "RHO", default_value_t = SEA_WATER_DENSITY, allow_negative_numbers = true)]
    pub density: f64,
    /// Also compare every method at the same control points (as `hullskin compare`) and add
    /// the table; takes seconds on the sample.
    #[arg(long)]
    pub compare: bool,
    /// Offsets measured against a surface.json input (fit error, markers, --compare), in the
    /// surface's units.
    #[arg(long, value_name = "FILE")]
    pub offsets: Option<PathBuf>,
    /// The lines plan's sheet: `auto` (the A or ISO 5457 elongated size on which the three
    /// views fill the most of the frame, for a long hull A4x7 rather than a third-empty A3),
    /// or a size: A4, A3, A2, A1, A0, or an elongated A3x3 ... A3x7, A4x3 ... A4x9, A2x3 ...
    /// A2x5, A1x3, A1x4, A0x2, A0x3.
    #[arg(long, value_name = "SHEET", default_value = "auto", value_parser = parse_sheet)]
    pub sheet: SheetChoice,
    /// Print the summary as JSON on standard output instead of the text, for scripts: the
    /// input, the files written, the fit error (null without offsets), the validity findings
    /// and the hydrostatics table (as hydrostatics.json); warnings stay on standard error.
    #[arg(long)]
    pub json: bool,
}

/// `--sheet`: chosen for the hull, or the one named.
#[derive(Clone, Copy, Debug)]
pub struct SheetChoice(pub Option<Sheet>);

fn parse_sheet(s: &str) -> Result<SheetChoice, String> {
    if s.eq_ignore_ascii_case("auto") {
        return Ok(SheetChoice(None));
    }
    Sheet::named(s).map(|sheet| SheetChoice(Some(sheet))).ok_or_else(|| {
        let names: Vec<&str> = Sheet::standard().iter().map(|s| s.name).collect();
        format!("unknown sheet {s:?} (expected auto or one of {})", names.join(", "))
    })
}

/// The surface to report on, with what came with it.
struct Loaded {
    surface: NurbsSurface,
    units: Units,
    source: String,
    offsets: Option<Offsets>,
    fit: Option<FitOutcome>,
    /// The search of `--tolerance`.
    search: Option<ToleranceSearch>,
    notes: Vec<String>,
}

/// Run `hullskin report`.
pub fn run(args: &ReportArgs) -> anyhow::Result<ExitCode> {
    let start = Instant::now();
    progress::install_stop_handler();
    hull::table_drafts(args.draft, None, None, args.density, hull::InputNames::Flags)?;
    let loaded = load(args)?;
    hull::check_finite(&loaded.surface).with_context(|| format!("cannot report on {}", loaded.source))?;
    let comparison = match (&loaded.offsets, args.compare) {
        (Some(offsets), true) => Some(compare(args, offsets)?),
        (None, true) => bail!("--compare needs offsets: give them with --offsets FILE for a surface.json input"),
        (_, false) => None,
    };
    let inputs = ReportInputs {
        offsets: loaded.offsets.as_ref(),
        fit: loaded.fit.as_ref(),
        comparison: comparison.as_ref(),
        draft: args.draft,
        perpendiculars: args.skin.perpendiculars(None)?,
        notes: loaded.notes.clone(),
        ..ReportInputs::new(&loaded.surface, loaded.units, loaded.source.clone())
    };
    let options = ReportOptions { density: args.density, sheet: args.sheet.0, ..ReportOptions::default() };
    let report = build_report(&inputs, &options).with_context(|| format!("cannot report on {}", loaded.source))?;
    let dir = &args.out;
    // All files or none: staged beside DIR and moved in together.
    let written =
        write_report(dir, &report).with_context(|| format!("cannot write the report to {}", dir.display()))?;
    let seconds = start.elapsed().as_secs_f64();
    if args.json {
        print_json_summary(&loaded, &report, &written, seconds)?;
    } else {
        print_summary(&loaded, &report, &written, seconds);
    }
    // The page's warnings under its title, on standard error too.
    for f in &report.validity {
        eprintln!("hullskin: warning: {}", f.message(loaded.units.symbol()));
    }
    if let Some(status) = progress::stop_status() {
        eprintln!(
            "hullskin: interrupted: wrote the complete report of the best surface found before the stop (exit status \
             {status})"
        );
        return Ok(ExitCode::from(status));
    }
    Ok(ExitCode::SUCCESS)
}

/// Read the input: a surface.json as it is (with `--offsets` if given), or offsets fitted with
/// the fit flags.
fn load(args: &ReportArgs) -> anyhow::Result<Loaded> {
    let offsets = match read_input(&args.skin)? {
        Input::Surface { surface, units, source } => {
            crate::surface_arg::note_units_not_applied(&args.skin, units, &source);
            return surface_as_is(args, surface, units, source);
        }
        Input::Offsets(offsets) => offsets,
        Input::Patches { names, source, .. } => return Err(crate::surface_arg::patches_refused(&names, &source)),
    };
    if let Some(path) = &args.offsets {
        bail!(
            "--offsets {} is for a surface input (surface.json, IGES, STEP); the input is offsets already (they are \
             fitted and measured)",
            path.display()
        );
    }
    let (outcome, search) =
        args.fit.fit(&args.skin, &offsets).with_context(|| format!("cannot fit {}", offsets.source))?;
    let mut notes: Vec<String> = search
        .iter()
        .map(|s| format!("Fitted with the fewest control points within --tolerance: {}.", s.summary(offsets.units)))
        .collect();
    // What the fit decided (the fairing, an alternative made for validity, the envelope hold,
    // what was rejected), as the summary prints it.
    notes.extend(hull::fit_decisions(&offsets, &outcome).into_iter().map(|l| format!("Fit: {l}.")));
    Ok(Loaded {
        surface: outcome.surface.clone(),
        units: offsets.units,
        source: offsets.source.clone(),
        offsets: Some(offsets),
        fit: Some(outcome),
        search,
        notes,
    })
}

/// A surface.json input, with the offsets of `--offsets` when given.
fn surface_as_is(args: &ReportArgs, surface: NurbsSurface, units: Units, source: String) -> anyhow::Result<Loaded> {
    let mut notes =
        vec![format!("The surface was read from {source} as it is (not fitted here): the fit flags play no part.")];
    let offsets = match &args.offsets {
        Some(path) => {
            let (o, _) = crate::skin_args::read_offsets_for_surface(&args.skin, path, units)?;
            notes.push(format!(
                "Offsets from {}: their distances to the surface are measured here by closest-point projection.",
                path.display()
            ));
            Some(o)
        }
        None => {
            notes.push(
                "No offsets were given (--offsets FILE adds them): no fit error, and no offset markers in the \
                 lines plan and the viewer."
                    .into(),
            );
            None
        }
    };
    Ok(Loaded { surface, units, source, offsets, fit: None, search: None, notes })
}

/// Every method at the same control points, with a progress bar for the optimisers.
fn compare(args: &ReportArgs, offsets: &Offsets) -> anyhow::Result<Comparison> {
    let s = &args.skin;
    let config = CompareConfig {
        degree: s.degree,
        ctrl: s.ctrl,
        param: s.param,
        optim: args.fit.optim.settings(),
        held_out: None,
    };
    // A stop between two optimisers ends the comparison too (not the run).
    let comparison = progress::stoppable(|| {
        hull::compare_offsets_with(offsets, &config, &mut |algorithm, fit| {
            progress::with_progress(algorithm.name(), |control| fit(control))
        })
    })
    .with_context(|| format!("cannot compare the methods on {}", offsets.source))?;
    Ok(comparison)
}

fn print_summary(loaded: &Loaded, report: &view::ReportFiles, written: &[PathBuf], seconds: f64) {
    let u = loaded.units.symbol();
    outln!("report of {}", loaded.source);
    if let Some(f) = &loaded.fit {
        let e = &f.error.overall;
        outln!(
            "fit: {} {}x{} control points, error max {:.3e} {u}, RMS {:.3e} {u}",
            f.config.method.name(),
            f.surface.n_u(),
            f.surface.n_v(),
            e.max,
            e.rms
        );
        if let Some(s) = &loaded.search {
            outln!("{}", s.summary(loaded.units));
        }
    } else if let Some(e) = &report.error {
        outln!("error of the offsets: max {:.3e} {u}, RMS {:.3e} {u}", e.overall.max, e.overall.rms);
    }
    match (&report.drafts, report.hydrostatics.rows.last()) {
        (DraftChoice::Design(t), Some(r)) => {
            let f = hull::format_short;
            outln!("hydrostatics at T {t} {u}: Vol {} {u}³, CB {}, LCB {} {u}", f(r.vol), f(r.cb), f(r.lcb))
        }
        (DraftChoice::Range { count, top, limit, .. }, _) => {
            outln!("hydrostatics at {count} drafts up to {limit} ({top:.4} {u})")
        }
        _ => {}
    }
    let size = |p: &Path| std::fs::metadata(p).map(|m| m.len()).unwrap_or(0);
    let total: u64 = written.iter().map(|p| size(p)).sum();
    if let Some(html) = written.first() {
        outln!("wrote {} ({:.2} MB, self-contained) in {seconds:.1} s", html.display(), size(html) as f64 / 1e6);
    }
    let names: Vec<String> =
        written.iter().skip(1).filter_map(|p| p.file_name().map(|n| n.to_string_lossy().into_owned())).collect();
    outln!("and {} ({:.2} MB in all)", names.join(", "), total as f64 / 1e6);
}

/// `--json`: the summary as one JSON object on standard output.
fn print_json_summary(
    loaded: &Loaded,
    report: &view::ReportFiles,
    written: &[PathBuf],
    seconds: f64,
) -> anyhow::Result<()> {
    let summary = serde_json::json!({
        "source": loaded.source,
        "units": loaded.units.symbol(),
        "method": loaded.fit.as_ref().map(|f| f.config.method.name()),
        "files": written.iter().map(|p| p.display().to_string()).collect::<Vec<_>>(),
        "seconds": seconds,
        "error": report.error,
        "validity": report.validity,
        "hydrostatics": report.hydrostatics,
    });
    outln!("{}", serde_json::to_string_pretty(&summary).context("the summary as JSON")?);
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;
    use hull::FitMethod;

    type Wrap = crate::Wrap<ReportArgs>;

    #[test]
    fn flags_reach_the_arguments() {
        let w = Wrap::try_parse_from([
            "x",
            "in.csv",
            "-o",
            "R",
            "--draft",
            "6.5",
            "--method",
            "ga",
            "--iterations",
            "5",
            "--compare",
            "--ctrl",
            "5,9",
        ])
        .expect("valid flags");
        let a = &w.args;
        assert_eq!(a.skin.input, Some(PathBuf::from("in.csv")));
        assert_eq!((a.out.as_path(), a.draft, a.compare), (Path::new("R"), Some(6.5), true));
        assert_eq!(a.fit.method, FitMethod::Optimized(hull::Algorithm::Ga));
        assert_eq!((a.fit.optim.settings().iterations, a.skin.ctrl), (Some(5), Some((5, 9))));
        let d = Wrap::try_parse_from(["x"]).expect("no flags");
        assert_eq!(
            (d.args.out.as_path(), d.args.fit.method, d.args.draft),
            (Path::new("hullskin-report"), FitMethod::Approx, None)
        );
        assert!(Wrap::try_parse_from(["x", "--method", "bogus"]).is_err());
    }

    #[test]
    fn tolerance_fits_the_fewest_control_points_within_it_and_notes_the_search() {
        // 0.2 m on the 121.92 m sample: a loose tolerance, so the search is short (~40 fits).
        let w = Wrap::try_parse_from(["x", "--tolerance", "0.2"]).expect("valid flags");
        let loaded = load(&w.args).expect("the sample fits within 0.2 m");
        let fit = loaded.fit.as_ref().expect("offsets are fitted");
        let search = loaded.search.as_ref().expect("--tolerance searches");
        assert!(fit.error.overall.max <= 0.2, "max error {}", fit.error.overall.max);
        assert_eq!(search.control_points, [fit.surface.n_u(), fit.surface.n_v()]);
        assert!(search.ratio < 1.0, "fewer control points than interpolation: {}", search.ratio);
        assert!(loaded.notes.iter().any(|n| n.contains(&search.summary(Units::Metre))), "{:?}", loaded.notes);
        // No flags fits the default count: no search; the notes are the fit's decisions, as the
        // summary prints them (the sample's default fit is refereed by its held-out error and
        // held within its envelope).
        let plain = load(&Wrap::try_parse_from(["x"]).expect("no flags").args).expect("fits");
        let fit = plain.fit.as_ref().expect("offsets are fitted");
        let offsets = plain.offsets.as_ref().expect("offsets");
        let decided: Vec<String> = hull::fit_decisions(offsets, fit).iter().map(|l| format!("Fit: {l}.")).collect();
        assert!(plain.search.is_none() && plain.notes == decided, "{:?}", plain.notes);
        assert!(decided.iter().any(|n| n.starts_with("Fit: held-out referee")), "{decided:?}");
        assert!(decided.iter().any(|n| n.starts_with("Fit: envelope:")), "{decided:?}");
        // `--tolerance default`: the search, noted with its default tolerance.
        let default = load(&Wrap::try_parse_from(["x", "--tolerance", "default"]).expect("valid").args).expect("fits");
        let search = default.search.as_ref().expect("the default tolerance searches");
        assert!(search.default, "{search:?}");
        assert!(default.notes.iter().any(|n| n.contains("default tolerance")), "{:?}", default.notes);
        assert!(Wrap::try_parse_from(["x", "--tolerance", "0.2", "--ctrl", "5,9"]).is_err());
    }

    #[test]
    fn bad_values_are_refused_before_any_work() {
        for argv in
            [&["x", "--draft", "0"][..], &["x", "--draft", "-2"], &["x", "--draft", "nan"], &["x", "--density", "0"]]
        {
            let w = Wrap::try_parse_from(argv).expect("parses");
            let err = run(&w.args).expect_err("refused");
            assert!(err.to_string().contains("expected"), "{argv:?}: {err}");
        }
    }
}
