//! `hullskin digitize`: a body plan drawn as DXF or SVG read back into offsets, written as a
//! sections CSV (`section,x,y,z`) that `fit` and the other subcommands read.

use std::path::PathBuf;
use std::process::ExitCode;

use anyhow::{bail, Context};
use clap::{Args, ValueEnum};
use hull::{
    digitize, read_drawing, write_atomic, write_sections_csv, CurveOrder, DigitizeOptions, DrawingScale, Notation,
    Side, StationIds, StationX, Units,
};

use crate::parse::parse_units;
use crate::stdout::outln;

/// The order of the station curves when neither layers nor labels name them.
#[derive(Clone, Copy, Debug, PartialEq, Eq, ValueEnum)]
pub enum OrderArg {
    /// As they come in the file.
    Drawn,
    /// By layer name (ST2 before ST10), then as drawn.
    Layer,
    /// Aft to fore by the body plan convention: left of the centreline narrowest to widest,
    /// then right of it widest to narrowest.
    BodyPlan,
}

/// Arguments of `hullskin digitize`.
#[derive(Debug, Args)]
pub struct DigitizeArgs {
    /// The drawing: an ASCII DXF (R12 or later) or an SVG file.
    #[arg(value_name = "DRAWING")]
    pub drawing: PathBuf,
    /// The drawing's scale: paper:model such as 1:50 (needs the drawing's units: from the
    /// file, or --drawing-units), or drawing units per output unit such as 20.
    #[arg(long, value_name = "SCALE")]
    pub scale: String,
    /// Drawing coordinates X,Y of the point where the body plan's centreline meets the
    /// baseline (SVG: the viewBox coordinates, y down).
    #[arg(long, value_name = "X,Y", allow_hyphen_values = true)]
    pub datum: String,
    /// The unit of the drawing's coordinates when the file does not say it (or says it
    /// wrongly): mm, cm, m, in, ft, pt or px.
    #[arg(long, value_name = "UNIT")]
    pub drawing_units: Option<String>,
    /// Length unit of the output offsets: m, mm, ft or in.
    #[arg(long, default_value = "m", value_parser = parse_units)]
    pub units: Units,
    /// Read only curves on layers (SVG: groups) matching this pattern (`*`, `?`,
    /// case-insensitive).
    #[arg(long, value_name = "GLOB")]
    pub layer: Option<String>,
    /// Each layer matching this pattern holds one station, named by the layer, e.g. 'ST*'.
    #[arg(long, value_name = "GLOB", conflicts_with = "labels")]
    pub station_layer_pattern: Option<String>,
    /// Stations are named by text labels next to their curves (the nearest curve to a
    /// label), or by an SVG `<title>`.
    #[arg(long)]
    pub labels: bool,
    /// Without --station-layer-pattern or --labels, the curves in this order are the
    /// stations.
    #[arg(long, value_enum, default_value = "drawn")]
    pub order: OrderArg,
    /// Station positions: x1,x2,... in station order (the curve order, or the station names
    /// sorted by number), or NAME=x,... by name.
    #[arg(long, value_name = "LIST", allow_hyphen_values = true)]
    pub stations: Option<String>,
    /// Station spacing: x = origin + n * spacing, n the station number in the name (ST7,
    /// Station 7.5, 9 1/2), or the curve's ordinal with --order.
    #[arg(long, value_name = "DX", conflicts_with = "stations", allow_negative_numbers = true)]
    pub station_spacing: Option<f64>,
    /// x of station 0, with --station-spacing.
    #[arg(long, value_name = "X0", default_value_t = 0.0, allow_negative_numbers = true)]
    pub station_origin: f64,
    /// Resample every station to N points evenly spaced along it (default: keep the drawn
    /// points).
    #[arg(long, value_name = "N")]
    pub points: Option<usize>,
    /// Piece ends closer than this are joined, points this close to the centreline are on it
    /// (drawing units; default 1e-4 of the drawing's diagonal).
    #[arg(long, value_name = "T")]
    pub join_tol: Option<f64>,
    /// Curves are flattened to within this (drawing units; default 1e-6 of the drawing's
    /// diagonal).
    #[arg(long, value_name = "T")]
    pub flatness: Option<f64>,
    /// With --labels, ignore labels farther than this from every curve (drawing units).
    #[arg(long, value_name = "D")]
    pub label_distance: Option<f64>,
    /// The sections CSV to write.
    #[arg(short = 'o', long = "out", value_name = "FILE", default_value = "sections.csv")]
    pub out: PathBuf,
    /// Print the stations found and the file written as one JSON object on standard output,
    /// for scripts; notes stay on standard error.
    #[arg(long)]
    pub json: bool,
}

/// Millimetres per drawing unit of a unit name.
fn unit_mm(s: &str) -> anyhow::Result<f64> {
    Ok(match s.trim().to_ascii_lowercase().as_str() {
        "mm" => 1.0,
        "cm" => 10.0,
        "m" => 1000.0,
        "in" => 25.4,
        "ft" => 304.8,
        "pt" => 25.4 / 72.0,
        "px" => 25.4 / 96.0,
        _ => bail!("--drawing-units {s:?}: expected mm, cm, m, in, ft, pt or px"),
    })
}

/// `X,Y`.
fn parse_datum(s: &str) -> anyhow::Result<[f64; 2]> {
    let parsed = s.split_once(',').and_then(|(x, y)| {
        let x = x.trim().parse::<f64>().ok().filter(|v| v.is_finite())?;
        let y = y.trim().parse::<f64>().ok().filter(|v| v.is_finite())?;
        Some([x, y])
    });
    parsed.with_context(|| format!("--datum {s:?}: expected two numbers X,Y such as 100,50"))
}

/// `x1,x2,...` or `NAME=x,...`.
fn parse_stations(s: &str) -> anyhow::Result<StationX> {
    let items: Vec<&str> = s.split(',').map(str::trim).filter(|t| !t.is_empty()).collect();
    if items.is_empty() {
        bail!("--stations {s:?}: expected x1,x2,... or NAME=x,...");
    }
    let number = |t: &str| {
        t.trim()
            .parse::<f64>()
            .ok()
            .filter(|v| v.is_finite())
            .with_context(|| format!("--stations: {t:?} is not a number (expected x1,x2,... or NAME=x,...)"))
    };
    if items.iter().any(|t| t.contains('=')) {
        let mut map = Vec::with_capacity(items.len());
        for t in items {
            let (name, x) = t.split_once('=').with_context(|| {
                format!("--stations: {t:?} has no '=' (expected every entry as NAME=x once one is)")
            })?;
            map.push((name.trim().to_string(), number(x)?));
        }
        Ok(StationX::Map(map))
    } else {
        Ok(StationX::List(items.into_iter().map(number).collect::<anyhow::Result<_>>()?))
    }
}

/// The library options from the arguments.
fn options(args: &DigitizeArgs) -> anyhow::Result<DigitizeOptions> {
    let scale: DrawingScale = args.scale.parse()?;
    let datum = parse_datum(&args.datum)?;
    let stations = match (&args.station_layer_pattern, args.labels) {
        (Some(g), _) => StationIds::Layers(g.clone()),
        (None, true) => StationIds::Labels,
        (None, false) => StationIds::Order(match args.order {
            OrderArg::Drawn => CurveOrder::Drawn,
            OrderArg::Layer => CurveOrder::Layer,
            OrderArg::BodyPlan => CurveOrder::BodyPlan,
        }),
    };
    let x = match (&args.stations, args.station_spacing) {
        (Some(s), _) => parse_stations(s)?,
        (None, Some(spacing)) => StationX::Spacing { origin: args.station_origin, spacing },
        (None, None) => bail!(
            "the stations' positions are not given (expected --stations x1,x2,... or NAME=x,..., or --station-spacing DX)"
        ),
    };
    let mut o = DigitizeOptions::new(scale, datum, stations, x);
    o.drawing_unit_mm = args.drawing_units.as_deref().map(unit_mm).transpose()?;
    o.units = args.units;
    o.layers.clone_from(&args.layer);
    o.points = args.points;
    o.join_tol = args.join_tol;
    o.flatness = args.flatness;
    o.label_distance = args.label_distance;
    Ok(o)
}

/// Run `hullskin digitize`.
///
/// # Errors
/// Unreadable or malformed drawings, settings that cannot work, stations that cannot be
/// digitised, and write errors.
pub fn run(args: &DigitizeArgs) -> anyhow::Result<ExitCode> {
    let o = options(args)?;
    let sketch = read_drawing(&args.drawing)?;
    let d = digitize(&sketch, &o)?;
    for n in &d.notes {
        eprintln!("hullskin: note: {n}");
    }
    let side_name = |side: Side| match side {
        Side::Aft => "aft",
        Side::Fore => "fore",
        Side::Centreline => "centreline",
    };
    write_atomic(&args.out, |w| write_sections_csv(w, &d.offsets, Notation::Plain))
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    if args.json {
        let stations: Vec<_> = d
            .stations
            .iter()
            .map(|s| {
                serde_json::json!({
                    "label": s.label, "x": s.x, "side": side_name(s.side), "curves": s.curves, "points": s.points,
                })
            })
            .collect();
        let summary = serde_json::json!({
            "source": sketch.source,
            "curves": sketch.curves.len(),
            "labels": sketch.labels.len(),
            "units": o.units.symbol(),
            "stations": stations,
            "wrote": args.out.display().to_string(),
            "sections": d.offsets.sections.len(),
            "points": d.offsets.num_points(),
        });
        outln!("{}", serde_json::to_string_pretty(&summary).context("the summary as JSON")?);
        return Ok(ExitCode::SUCCESS);
    }
    let units = o.units.symbol();
    outln!("{}: {} curves, {} labels", sketch.source, sketch.curves.len(), sketch.labels.len());
    outln!("{:<12} {:>14} {:<10} {:>6} {:>6}", "station", format!("x ({units})"), "side", "curves", "points");
    for s in &d.stations {
        outln!(
            "{:<12} {:>14} {:<10} {:>6} {:>6}",
            s.label,
            hull::format_figure(s.x),
            side_name(s.side),
            s.curves,
            s.points
        );
    }
    outln!(
        "wrote {}: {} sections, {} points ({})",
        args.out.display(),
        d.offsets.sections.len(),
        d.offsets.num_points(),
        o.units.plural_name()
    );
    Ok(ExitCode::SUCCESS)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn station_lists_and_maps() {
        assert_eq!(parse_stations("0, 2.5,-5").ok(), Some(StationX::List(vec![0.0, 2.5, -5.0])));
        assert_eq!(
            parse_stations("ST0=0,ST5=10").ok(),
            Some(StationX::Map(vec![("ST0".into(), 0.0), ("ST5".into(), 10.0)]))
        );
        assert!(parse_stations("ST0=0,5").is_err());
        assert!(parse_stations("a,b").is_err());
        assert!(parse_stations(",").is_err());
        assert_eq!(parse_datum(" 100 , -5.5").ok(), Some([100.0, -5.5]));
        assert!(parse_datum("100").is_err());
        assert_eq!(unit_mm("IN").ok(), Some(25.4));
        assert!(unit_mm("furlong").is_err());
    }
}
