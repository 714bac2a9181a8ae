//! `hullskin fit`: read offsets, skin a surface, measure its true error, write the outputs.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::{bail, Context};
use clap::Args;
use hull::{FitConfig, FitMethod, FitOutcome, Goal, HeldOutError, HullError, Offsets, ToleranceSearch};

use crate::optim_args::OptimArgs;
use crate::progress;
use crate::skin_args::SkinArgs;
use crate::stdout::{out, outln};

/// Arguments of `hullskin fit`.
#[derive(Debug, Args)]
#[command(mut_arg("input", |a| a
    .help("Offsets file: a sections CSV (header `section,x,y,z`) or an offset table CSV (first row station \
           positions, first column waterline heights, cells half-breadths), or any format of `hull::read_offsets` (Series 60 \
           table, long CSV, JSON table, point cloud, FREE!ship text), recognised by its content; or a hull mesh \
           (`.stl`, `.obj`, `.wrl`, each optionally `.gz`), sliced at stations first (`--stations`, `--spacing`, `--at`, ...); or, with \
           --offsets FILE, a surface (surface.json, IGES, STEP) to measure against them. Without it the built-in \
           Series 60 Cb 0.60 parent hull is used")))]
pub struct FitArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Output directory for surface.igs, surface.json and report.json.
    #[arg(short = 'o', long = "out", default_value = "hullskin-out")]
    pub out: PathBuf,
    #[command(flatten)]
    pub fit: MethodArgs,
    /// Folds K of the held-out error (cross-validation: refit without every K-th section, then
    /// without every K-th point of each section, and measure the true distance of what was
    /// left out); report.json gets "error.held_out". 0 turns it off.
    #[arg(long = "held-out", value_name = "K", default_value_t = hull::HeldOutOptions::DEFAULT_FOLDS, value_parser = parse_folds)]
    pub held_out: usize,
    /// Print the summary as JSON on standard output (report.json's content) instead of the
    /// table, for scripts; warnings and notes stay on standard error.
    #[arg(long)]
    pub json: bool,
    /// Measure a given surface instead of fitting one: the input is a surface.json, IGES or
    /// STEP file, and FILE the offsets (read in the surface's units) whose distances to it are
    /// measured, with the validity checks; writes report.json only (method `given`).
    #[arg(long, value_name = "FILE")]
    pub offsets: Option<PathBuf>,
}

impl Default for FitArgs {
    fn default() -> Self {
        FitArgs {
            skin: SkinArgs::default(),
            out: PathBuf::from("hullskin-out"),
            fit: MethodArgs::default(),
            held_out: hull::HeldOutOptions::DEFAULT_FOLDS,
            json: false,
            offsets: None,
        }
    }
}

/// `--held-out K`: 0 (off) or at least 2 folds.
pub(crate) fn parse_folds(s: &str) -> Result<usize, String> {
    match s.trim().parse::<usize>() {
        Ok(1) => Err("1 fold would hold out every offset (expected 0 to turn it off, or at least 2)".into()),
        Ok(k) => Ok(k),
        Err(_) => Err(format!("`{s}` is not a whole number (expected 0 to turn it off, or a number of folds >= 2)")),
    }
}

/// How offsets are fitted: the method, `--tolerance` and the weight optimisers' flags (shared
/// by `fit` and `report`).
#[derive(Debug, Clone, Args)]
pub struct MethodArgs {
    /// Method: `interp` passes through every offset; `approx` is a least-squares fit with the
    /// control-point counts of --ctrl; `ga`, `pso`, `gsa`, `lm` and `gsa+lm` then optimise the
    /// approximation's weights (Genetic Algorithm, Particle Swarm, Gravitational Search,
    /// Levenberg-Marquardt, GSA then LM).
    #[arg(long, default_value = "approx", value_parser = parse_method)]
    pub method: FitMethod,
    /// Search the control-point counts for the fewest control points whose max error (true
    /// closest-point distance, in the input's units) is within T, for approx or an optimised
    /// method; report.json gets a "tolerance_search" block. A T no count reaches is an error.
    /// `default`: 0.5 % of the beam by a quick search, refereed by the held-out error against
    /// the default count (the closest valid surface where none reaches it).
    #[arg(long, value_name = "T|default", conflicts_with = "ctrl", value_parser = parse_tolerance)]
    pub tolerance: Option<Goal>,
    #[command(flatten)]
    pub optim: OptimArgs,
}

impl Default for MethodArgs {
    fn default() -> Self {
        MethodArgs { method: FitMethod::Approx, tolerance: None, optim: OptimArgs::default() }
    }
}

impl MethodArgs {
    /// What the fit aims at: `--tolerance`, else the count (`--ctrl` or the default count).
    pub(crate) fn goal(&self) -> Goal {
        self.tolerance.unwrap_or_default()
    }

    /// Fit `offsets` with these flags and the skinning flags `skin`: see [`fit_with_progress`].
    ///
    /// # Errors
    /// Those of [`fit_with_progress`].
    pub(crate) fn fit(
        &self,
        skin: &SkinArgs,
        offsets: &Offsets,
    ) -> Result<(FitOutcome, Option<ToleranceSearch>), HullError> {
        fit_with_progress(offsets, &skin.fit_config(self.method, self.optim.settings()), self.goal())
    }
}

fn parse_method(s: &str) -> Result<FitMethod, String> {
    s.parse()
}

fn parse_tolerance(s: &str) -> Result<Goal, String> {
    s.parse()
}

/// Run `hullskin fit`.
pub fn run(args: &FitArgs) -> anyhow::Result<ExitCode> {
    progress::install_stop_handler();
    if let Some(offsets) = &args.offsets {
        return measure(args, offsets);
    }
    if let Some(path) = args.skin.input.as_ref().filter(|p| crate::surface_arg::holds_surface(p)) {
        bail!(
            "{}: a surface, not offsets (expected offsets to fit; to measure this surface against offsets pass \
             --offsets FILE)",
            path.display()
        );
    }
    // A mesh input is kept to measure the fitted surface against it.
    let (offsets, mesh, warnings) = match &args.skin.input {
        Some(path) if crate::slice::is_mesh_path(path) => {
            let (mesh, sliced) = args.skin.mesh.read_and_slice(path, args.skin.units())?;
            (sliced.offsets, Some(mesh), Vec::new())
        }
        _ => {
            let (offsets, warnings) = args.skin.offsets_with_warnings()?;
            (offsets, None, warnings)
        }
    };
    let (mut outcome, search) = args.fit.fit(&args.skin, &offsets)?;
    let held_out = hull::HeldOutOptions::with_folds(args.held_out);
    if hull::held_out_wanted(&mut outcome, &held_out) && !progress::stopped() {
        outcome.error.held_out = held_out_with_progress(&offsets, &hull::held_out_refit_config(&outcome), &held_out);
    }
    let mut report = hull::Report::new(&offsets, &outcome);
    report.input.warnings = warnings;
    report.tolerance_search = search;
    let overfit = hull::overfitting_warning(&offsets, &outcome);
    report.overfitting = overfit.as_ref().map(|l| l.trim_start_matches("warning: ").to_string());
    write_outputs(&args.out, &offsets, &outcome, &report)?;
    print_summary(args.json, &report, || hull::summary_table(&offsets, &outcome))?;
    for w in hull::summary_warnings(&offsets, &outcome) {
        eprintln!("hullskin: warning: {w}");
    }
    if let Some(line) = overfit {
        eprintln!("hullskin: {line}");
    }
    if let Some(s) = report.tolerance_search.as_ref().filter(|_| !args.json) {
        outln!("{}", s.summary(offsets.units));
    }
    if let Some(mesh) = mesh.as_ref().filter(|_| !args.json) {
        print_mesh_distance(mesh, &offsets, &outcome.surface);
    }
    let wrote = format!("wrote {}", args.out.join("{surface.igs,surface.json,report.json}").display());
    if args.json {
        eprintln!("hullskin: {wrote}");
    } else {
        outln!("{wrote}");
    }
    if let Some(status) = progress::stop_status() {
        eprintln!("hullskin: interrupted: wrote the best surface found before the stop (exit status {status})");
        return Ok(ExitCode::from(status));
    }
    Ok(ExitCode::SUCCESS)
}

/// `fit SURFACE --offsets FILE`: the surface measured as it is against the offsets, the summary
/// printed and report.json written (the surface's own files are left alone).
fn measure(args: &FitArgs, offsets_path: &Path) -> anyhow::Result<ExitCode> {
    let (surface, units, source) = match crate::surface_arg::read_input(&args.skin)? {
        crate::surface_arg::Input::Surface { surface, units, source } => (surface, units, source),
        crate::surface_arg::Input::Patches { names, source, .. } => {
            return Err(crate::surface_arg::patches_refused(&names, &source));
        }
        crate::surface_arg::Input::Offsets(o) => bail!(
            "--offsets {} measures a given surface (expected a surface.json, IGES or STEP input); {} is offsets, \
             which fit fits: drop --offsets",
            offsets_path.display(),
            o.source
        ),
    };
    crate::surface_arg::note_units_not_applied(&args.skin, units, &source);
    eprintln!(
        "hullskin: note: {source} is measured as it is against {}, not fitted: the fit flags (--method, --ctrl, \
         --held-out ...) play no part",
        offsets_path.display()
    );
    let (offsets, warnings) = crate::skin_args::read_offsets_for_surface(&args.skin, offsets_path, units)?;
    let measured = hull::Measured::new(&surface, &source, &offsets)?;
    let mut report = hull::Report::measured(&offsets, &measured);
    report.input.warnings = warnings;
    hull::write_report_json(&args.out, &report)?;
    print_summary(args.json, &report, || hull::measured_summary_table(&offsets, &measured))?;
    for w in hull::measured_warnings(&offsets, &measured) {
        eprintln!("hullskin: warning: {w}");
    }
    let wrote = format!("wrote {}", args.out.join("report.json").display());
    if args.json {
        eprintln!("hullskin: {wrote}");
    } else {
        outln!("{wrote}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The summary on standard output: report.json's content with `--json`, else the table.
fn print_summary(json: bool, report: &hull::Report, table: impl FnOnce() -> String) -> anyhow::Result<()> {
    if json {
        outln!("{}", serde_json::to_string_pretty(report).context("the summary as JSON")?);
    } else {
        out!("{}", table());
    }
    Ok(())
}

/// The distance of the mesh's starboard vertices to the fitted surface, over the sections'
/// length and up to their highest point: how well the surface stands for the mesh between and
/// across the stations, not only at the sliced points.
fn print_mesh_distance(mesh: &hull::TriMesh, offsets: &Offsets, surface: &nurbs::NurbsSurface) {
    let Some(filter) = offsets.bounds().and_then(|(_, hi)| hull::VertexFilter::for_sections(offsets, hi.z)) else {
        return;
    };
    let d = hull::mesh_distance(mesh, surface, &filter);
    let u = offsets.units.symbol();
    let h = &d.over_hull;
    outln!(
        "mesh {}: distance of {} starboard vertices over the surface: max {:.3e} {u}, mean {:.3e} {u}, RMS {:.3e} {u} \
         ({} more face another way: deck, transom, centre-plane lid or sharp edges)",
        mesh.source,
        h.points,
        h.max,
        h.mean,
        h.rms,
        d.left_out
    );
    if let Some((q, foot)) = d.worst {
        outln!("  farthest vertex ({}, {}, {}), foot ({:.6}, {:.6}, {:.6})", q.x, q.y, q.z, foot.x, foot.y, foot.z);
    }
    if d.unconverged > 0 {
        eprintln!(
            "hullskin: warning: {} of the mesh's vertices did not converge in the closest-point search",
            d.unconverged
        );
    }
}

/// Fit `offsets` with `config` as `goal` asks ([`hull::fit_offsets_within`]: the count given,
/// or the fewest control points within a tolerance, then with the record of that search). An optimised method
/// draws a progress bar and stops on SIGINT (Ctrl-C) or SIGTERM with its best surface so far
/// ([`progress::stopped`] then says so); the others run quietly.
///
/// # Errors
/// Those of [`hull::fit_offsets_within`].
pub(crate) fn fit_with_progress(
    offsets: &Offsets,
    config: &FitConfig,
    goal: Goal,
) -> Result<(FitOutcome, Option<ToleranceSearch>), HullError> {
    let fit = |control: &hull::Control<'_>| hull::fit_offsets_within(offsets, config, goal, control);
    match config.method.algorithm() {
        Some(a) => progress::with_progress(a.name(), fit),
        None => hull::quiet(fit),
    }
}

/// The held-out error of the fit `config` with `options` ([`hull::held_out_for_config`]),
/// with a progress bar for the optimised methods (their refits take a while), stopped by
/// SIGINT or SIGTERM like them. `None` after a stop, or when it cannot be computed (then a
/// warning says why: the fit itself stands).
pub(crate) fn held_out_with_progress(
    offsets: &Offsets,
    config: &FitConfig,
    options: &hull::HeldOutOptions,
) -> Option<HeldOutError> {
    let run = |control: &hull::Control<'_>| hull::held_out_for_config_with(offsets, config, options, control);
    let result = match config.method.algorithm() {
        Some(_) => progress::with_progress("held out", run),
        None => hull::quiet(run),
    };
    result.unwrap_or_else(|e| {
        eprintln!("hullskin: warning: no held-out error: {e}");
        None
    })
}

/// Write the three files all or nothing (staged, then moved into `dir`).
fn write_outputs(dir: &Path, offsets: &Offsets, outcome: &FitOutcome, report: &hull::Report) -> anyhow::Result<()> {
    hull::write_fit_outputs_with_report(dir, offsets, outcome, report)
        .with_context(|| format!("cannot write outputs to {}", dir.display()))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::parse::parse_param;
    use nurbs::fit::{Parameterization, SkinParameterization};

    #[test]
    fn the_fit_is_the_library_fit_for_each_goal() {
        let offsets = hull::series60_sample();
        // The command line fairs by default.
        let config = FitConfig { fair: hull::Fairing::Auto { tolerance: None }, ..FitConfig::default() };
        // No flags: the default count, no search.
        let args = FitArgs::default();
        let (outcome, search) = args.fit.fit(&args.skin, &offsets).expect("the sample fits");
        let (direct, _) =
            hull::quiet(|c| hull::fit_offsets_within(&offsets, &config, Goal::Count, c)).expect("the sample fits");
        // The same deterministic fit, its held-out referee included: bit-identical surfaces.
        assert_eq!(outcome.surface, direct.surface);
        assert!(outcome.held_out_referee.is_some());
        assert!(search.is_none());
        // `--tolerance default`: the library's search with the default tolerance.
        let goal = parse_tolerance("default").expect("a goal");
        let args = FitArgs { fit: MethodArgs { tolerance: Some(goal), ..MethodArgs::default() }, ..FitArgs::default() };
        let (outcome, search) = args.fit.fit(&args.skin, &offsets).expect("the sample fits");
        let (direct, direct_search) =
            hull::quiet(|c| hull::fit_offsets_within(&offsets, &config, Goal::DefaultTolerance, c)).expect("fits");
        assert_eq!(outcome.surface, direct.surface);
        let (a, b) = (search.expect("searched"), direct_search.expect("searched"));
        assert!(a.default && b.default);
        assert_eq!((a.control_points, a.tried), (b.control_points, b.tried));
    }

    #[test]
    fn over_fitting_is_warned_of_against_the_plain_approximation() {
        // A short LM run of the sample, closer to the offsets than the plain approximation at
        // the same 5 x 8 control points; its held-out figure is then set by hand on either
        // side of the approximation's, which `overfitting` computes itself.
        let offsets = hull::series60_sample();
        let optim = hull::OptimSettings { iterations: Some(3), ..Default::default() };
        let method = FitMethod::Optimized(hull::Algorithm::Lm);
        let config = FitConfig { method, ctrl: Some((5, 8)), optim, ..FitConfig::default() };
        let mut lm = hull::fit_offsets(&offsets, &config).expect("fits");
        let plain = FitConfig { method: FitMethod::Approx, ..config };
        let base = hull::fit_offsets(&offsets, &plain).expect("fits");
        assert!(lm.error.overall.rms < base.error.overall.rms, "LM improves at the offsets");
        let base_held = hull::held_out_for_config(&offsets, &plain, &hull::HeldOutOptions::default()).expect("ok");
        assert_eq!(hull::overfitting_warning(&offsets, &lm), None, "no held-out error, no verdict");
        lm.error.held_out = Some(HeldOutError { rms: 2.0 * base_held.rms, ..base_held.clone() });
        let line = hull::overfitting_warning(&offsets, &lm).expect("over-fits");
        assert!(line.starts_with("warning: lm over-fits: RMS") && line.contains(&format!("{:.3e}", base_held.rms)));
        lm.error.held_out = Some(HeldOutError { rms: 0.5 * base_held.rms, ..base_held });
        assert_eq!(hull::overfitting_warning(&offsets, &lm), None);
    }

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
