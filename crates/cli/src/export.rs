//! `hullskin export`: write a surface (a `surface.json` from `fit`, or offsets fitted first)
//! as STEP, IGES (with section curves, or a polynomial approximation), DXF 3-D lines, STL, OBJ
//! or binary glTF.

use std::path::PathBuf;
use std::process::ExitCode;
use std::sync::LazyLock;

use anyhow::Context;
use clap::builder::PossibleValue;
use clap::{Args, ValueEnum};
use hull::{
    greville_v, mesh_name, obj_comments, polynomial_approximation, section_curves, section_parameters, stl_header,
    tessellate, write_glb, write_iges, write_iges_model, write_obj, write_step, write_stl_ascii, write_stl_binary,
    ExportFormat, FitMethod, IgesMeta, InputNames, Offsets, OptimSettings, StepMeta, TessellationOptions,
};
use nurbs::Vec3;
use serde_json::json;
use view::{lines_3d, write_dxf_3d_lines, LinesPlanOptions};

use crate::fit::fit_with_progress;
use crate::parse::parse_skin_method;
use crate::skin_args::SkinArgs;
use crate::stdout::outln;
use crate::surface_arg::{read_input, Input};

/// `--format`: a [`hull::ExportFormat`] by its name, each listed with its description.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct FormatArg(pub ExportFormat);

impl ValueEnum for FormatArg {
    fn value_variants<'a>() -> &'a [Self] {
        static ALL: LazyLock<[FormatArg; ExportFormat::ALL.len()]> = LazyLock::new(|| ExportFormat::ALL.map(FormatArg));
        &*ALL
    }

    fn to_possible_value(&self) -> Option<PossibleValue> {
        Some(PossibleValue::new(self.0.name()).help(self.0.description()))
    }
}

/// Arguments of `hullskin export`.
#[derive(Debug, Args)]
#[command(mut_arg("input", |a| a
    .value_name("SURFACE_OR_INPUT")
    .help("A surface.json written by `hullskin fit`, an IGES or STEP file holding one B-spline surface, or an offsets file fitted first with --method and \
           the skinning flags. Without it the built-in Series 60 Cb 0.60 sample is fitted")))]
pub struct ExportArgs {
    #[command(flatten)]
    pub skin: SkinArgs,
    /// Fit of an offsets input: interp or approx.
    #[arg(long, default_value = "approx", value_parser = parse_skin_method)]
    pub method: FitMethod,
    /// Output format; by default from the extension of FILE (.stp/.step, .igs/.iges, .dxf,
    /// .stl, .obj, .glb).
    #[arg(long, value_enum)]
    pub format: Option<FormatArg>,
    /// Meshes: largest distance between the triangles and the surface; iges-polynomial:
    /// largest distance between the polynomial and the rational surface. In the surface's
    /// length unit; default 1e-4 (meshes) or 1e-5 (iges-polynomial) of the control net's
    /// diagonal.
    #[arg(long, value_name = "T", allow_negative_numbers = true)]
    pub tolerance: Option<f64>,
    /// The full hull: add the port half (y -> -y). Meshes and DXF hold both halves; STEP and
    /// IGES one surface joined along the keel line (a flat strip across the centre plane
    /// where the half hull stops short of it, a flat of keel).
    #[arg(long)]
    pub mirror: bool,
    /// Date written into STEP and IGES headers, as Unix seconds (default: SOURCE_DATE_EPOCH,
    /// else now), for reproducible files.
    #[arg(long, value_name = "SECONDS", allow_negative_numbers = true)]
    pub timestamp: Option<i64>,
    /// The file to write.
    #[arg(short = 'o', long = "out", value_name = "FILE")]
    pub out: PathBuf,
    /// Print what was written as one JSON object on standard output (the file, format,
    /// units, poles or triangles), for scripts; notes stay on standard error.
    #[arg(long)]
    pub json: bool,
}

/// The format asked for, or the one of the output's extension; checks that the flags apply
/// ([`ExportFormat::for_file`]).
fn format_of(args: &ExportArgs) -> anyhow::Result<ExportFormat> {
    Ok(ExportFormat::for_file(args.format.map(|f| f.0), &args.out, args.tolerance, InputNames::Flags)?)
}

/// The header date: `--timestamp`, else `SOURCE_DATE_EPOCH`, else now ([`hull::export_timestamp`]).
fn unix_time(args: &ExportArgs) -> i64 {
    hull::export_timestamp(args.timestamp)
}

pub fn run(args: &ExportArgs) -> anyhow::Result<ExitCode> {
    let format = format_of(args)?;
    // The surface, and the offsets with the sections' v when it was fitted here.
    let (surface, units, source, fitted) = match read_input(&args.skin)? {
        Input::Surface { surface, units, source } => (surface, units, source, None),
        Input::Offsets(offsets) => {
            let config = args.skin.fit_config(args.method, OptimSettings::default());
            let (outcome, _) = fit_with_progress(&offsets, &config, hull::Goal::Count)
                .with_context(|| format!("cannot fit {}", offsets.source))?;
            let source = format!("{}, fitted by {}", offsets.source, args.method.name());
            let vs = section_parameters(&outcome.params);
            (outcome.surface, offsets.units, source, Some((offsets, vs)))
        }
        Input::Patches { names, source, .. } => return Err(crate::surface_arg::patches_refused(&names, &source)),
    };
    // --units converts a surface.json (offsets are read in --units, the surface is in them).
    let (surface, units) = match args.skin.units.filter(|u| *u != units && fitted.is_none()) {
        Some(to) => (surface.scaled(units.metres_per_unit() / to.metres_per_unit()), to),
        None => (surface, units),
    };
    // --mirror: meshes and DXF mirror their own output; the exchange formats one surface.
    let surface = if args.mirror && matches!(format.family(), "STEP" | "IGES") {
        hull::mirrored_full_hull(&surface).with_context(|| format!("cannot mirror {source}"))?
    } else {
        surface
    };
    // Nothing is created for a surface no file may hold (non-finite, bad weights or knots).
    hull::check_finite(&surface).with_context(|| format!("cannot export {source}"))?;
    let out = &args.out;
    let file_name = out.file_name().map_or_else(|| "hull".into(), |n| n.to_string_lossy().into_owned());
    let time = unix_time(args);
    let iges_meta = || {
        let mut m = IgesMeta::new(units.into(), &file_name, &hull::iges_timestamp(time));
        m.product_id = format!("hull surface ({source})");
        m
    };
    let write = |fill: &dyn Fn(&mut dyn std::io::Write) -> std::io::Result<()>| {
        hull::write_atomic(out, |w| fill(w)).with_context(|| format!("cannot write {}", out.display()))
    };
    let unit = units.symbol();
    let (note, details) = match format {
        ExportFormat::Step => {
            let mut meta = StepMeta::new(units, &file_name, &hull::step_timestamp(time));
            meta.description = format!("hull surface ({source})");
            write(&|mut w| write_step(&mut w, &surface, &meta))?;
            let poles = [surface.n_u(), surface.n_v()];
            (format!("one B-spline face, {}x{} poles", poles[0], poles[1]), json!({ "poles": poles }))
        }
        ExportFormat::Iges => {
            write(&|mut w| write_iges(&mut w, &surface, &iges_meta()))?;
            let poles = [surface.n_u(), surface.n_v()];
            (format!("one surface, {}x{} poles", poles[0], poles[1]), json!({ "poles": poles }))
        }
        ExportFormat::IgesCurves => {
            let (vs, at) = match &fitted {
                Some((_, vs)) => (vs.clone(), "the sections' v"),
                None => (greville_v(&surface), "the Greville abscissae of v (a surface input has no sections)"),
            };
            let curves = section_curves(&surface, &vs);
            write(&|mut w| write_iges_model(&mut w, Some(&surface), &curves, &iges_meta()))?;
            (
                format!("the surface and {} section curves at {at}", curves.len()),
                json!({ "poles": [surface.n_u(), surface.n_v()], "section_curves": curves.len() }),
            )
        }
        ExportFormat::IgesPolynomial => {
            let tol = args.tolerance.or(format.default_tolerance(&surface)).unwrap_or_default();
            let approx = polynomial_approximation(&surface, tol)?;
            hull::check_finite(&approx.surface).context("cannot export the polynomial approximation")?;
            write(&|mut w| write_iges(&mut w, &approx.surface, &iges_meta()))?;
            let details = json!({
                "poles": [approx.surface.n_u(), approx.surface.n_v()],
                "exact": approx.exact,
                "max_deviation": approx.max_deviation,
                "check_points": approx.check_points,
                "tolerance": tol,
            });
            let note = if approx.exact {
                "polynomial surface, exact (all weights equal)".to_string()
            } else {
                format!(
                    "polynomial surface of {}x{} poles, largest deviation {:.3e} {unit} at {} points (tolerance {tol:.3e} \
                     {unit})",
                    approx.surface.n_u(),
                    approx.surface.n_v(),
                    approx.max_deviation,
                    approx.check_points
                )
            };
            (note, details)
        }
        ExportFormat::Dxf => {
            let offsets: Option<&Offsets> = fitted.as_ref().map(|(o, _)| o);
            let mut curves = lines_3d(&surface, offsets, &LinesPlanOptions::default());
            if args.mirror {
                let port: Vec<_> = curves
                    .iter()
                    .map(|(layer, pts)| (*layer, pts.iter().map(|p| Vec3::new(p.x, -p.y, p.z)).collect::<Vec<_>>()))
                    .collect();
                curves.extend(port);
            }
            write(&|mut w| write_dxf_3d_lines(&mut w, &curves, units))?;
            (
                format!("{} polylines (stations, waterlines, buttocks)", curves.len()),
                json!({ "polylines": curves.len() }),
            )
        }
        ExportFormat::Stl | ExportFormat::StlAscii | ExportFormat::Obj | ExportFormat::Glb => {
            let mut options = TessellationOptions::for_surface(&surface);
            options.mirror = args.mirror;
            if let Some(t) = args.tolerance {
                options.tolerance = t;
            }
            let tess = tessellate(&surface, &options)?;
            let mesh = &tess.mesh;
            let name = "hull";
            match format {
                ExportFormat::Stl => write(&|mut w| write_stl_binary(&mut w, mesh, &stl_header(name, units)))?,
                ExportFormat::StlAscii => write(&|mut w| write_stl_ascii(&mut w, mesh, &mesh_name(name)))?,
                ExportFormat::Obj => {
                    let comments = obj_comments(name, tess.tolerance, units)?;
                    write(&|mut w| write_obj(&mut w, mesh, &comments, Some(&mesh_name(name))))?
                }
                _ => write(&|mut w| write_glb(&mut w, &tess, name, units))?,
            }
            (
                format!(
                    "{} triangles, chord tolerance {:.3e} {unit}{}",
                    mesh.triangles.len(),
                    options.tolerance,
                    if format == ExportFormat::Glb { ", in metres" } else { "" }
                ),
                json!({ "triangles": mesh.triangles.len(), "vertices": mesh.vertices.len(), "tolerance": options.tolerance }),
            )
        }
    };
    if args.json {
        let mut summary = json!({
            "source": source,
            "wrote": out.display().to_string(),
            "format": format.name(),
            "units": if format == ExportFormat::Glb { "m" } else { unit },
            "mirror": args.mirror,
            "note": note,
        });
        if let (Some(map), serde_json::Value::Object(more)) = (summary.as_object_mut(), details) {
            map.extend(more);
        }
        outln!("{}", serde_json::to_string_pretty(&summary).context("the summary as JSON")?);
    } else {
        outln!("wrote {} ({}: {note})", out.display(), format.name());
    }
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;
    use clap::Parser;

    type Wrap = crate::Wrap<ExportArgs>;

    fn parse(argv: &[&str]) -> Result<ExportArgs, clap::Error> {
        Wrap::try_parse_from(std::iter::once("x").chain(argv.iter().copied())).map(|w| w.args)
    }

    #[test]
    fn the_format_comes_from_the_extension_unless_given() {
        for (file, want) in [
            ("a.stp", ExportFormat::Step),
            ("a.STEP", ExportFormat::Step),
            ("a.igs", ExportFormat::Iges),
            ("a.iges", ExportFormat::Iges),
            ("a.dxf", ExportFormat::Dxf),
            ("a.stl", ExportFormat::Stl),
            ("a.obj", ExportFormat::Obj),
            ("a.glb", ExportFormat::Glb),
        ] {
            assert_eq!(format_of(&parse(&["-o", file]).expect("parses")).expect("known"), want, "{file}");
        }
        let a = parse(&["s.json", "-o", "x.igs", "--format", "iges-curves"]).expect("parses");
        assert_eq!(format_of(&a).expect("given"), ExportFormat::IgesCurves);
        let err = format_of(&parse(&["-o", "x.txt"]).expect("parses")).expect_err("unknown");
        assert!(err.to_string().contains("--format"), "{err}");
        assert!(parse(&["s.json"]).is_err(), "-o is required");
    }

    #[test]
    fn flags_that_do_not_apply_are_refused() {
        let err = |argv: &[&str]| format_of(&parse(argv).expect("parses")).expect_err("refused").to_string();
        assert!(err(&["-o", "a.stp", "--tolerance", "0.01"]).contains("--tolerance"));
        // An extension that contradicts --format names the fix.
        let e = err(&["-o", "x.stp", "--format", "stl"]);
        assert!(e.contains("name it x.stl or pass --format step"), "{e}");
        assert!(format_of(&parse(&["-o", "a.igs", "--format", "iges-curves"]).expect("ok")).is_ok());
        assert!(format_of(&parse(&["-o", "a.stl", "--format", "stl-ascii"]).expect("ok")).is_ok());
        assert!(format_of(&parse(&["-o", "a.igs", "--mirror"]).expect("ok")).is_ok());
        assert!(err(&["-o", "a.stl", "--tolerance", "0"]).contains("positive"));
        assert!(err(&["-o", "a.stl", "--tolerance", "-1"]).contains("positive"));
        assert!(format_of(&parse(&["-o", "a.stl", "--tolerance", "0.01", "--mirror"]).expect("ok")).is_ok());
        assert!(format_of(&parse(&["-o", "a.igs", "--format", "iges-polynomial", "--tolerance", "1e-3"]).expect("ok"))
            .is_ok());
        assert!(parse(&["-o", "a.stl", "--method", "ga"]).is_err());
    }

    #[test]
    fn the_timestamp_flag_wins() {
        let a = parse(&["-o", "a.stp", "--timestamp", "1000000000"]).expect("parses");
        assert_eq!(unix_time(&a), 1_000_000_000);
    }
}
