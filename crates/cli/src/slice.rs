//! `hullskin slice`: cut a hull mesh (STL, OBJ, optionally gzipped) at stations and write the
//! sections CSV that `hullskin fit` reads; optionally the mesh's hydrostatics at a draft, and a
//! fitted surface measured against the mesh.
//!
//! The mesh flags ([`MeshArgs`]) are shared with `fit`, which slices a mesh input the same way.

use std::path::{Path, PathBuf};
use std::process::ExitCode;

use anyhow::Context;
use clap::Args;
use hull::{
    mesh_hydrostatics, read_mesh, slice_mesh, Axes, MeshHydrostatics, MeshReadOptions, Notation, Offsets, Resample,
    SliceOptions, SliceOutcome, Spacing, Stations, TriMesh, Units,
};
use nurbs::Vec3;

use crate::parse::parse_units;
use crate::stdout::{out, outln};

/// How a mesh is read and sliced into sections.
#[derive(Debug, Clone, Args)]
pub struct MeshArgs {
    /// Mesh input: number of stations over the mesh's length (ends included, moved in by 1e-5
    /// of the length).
    #[arg(long, default_value_t = 41, value_name = "N")]
    pub stations: usize,
    /// Mesh input: station spacing, `cosine` (denser at bow and stern) or `uniform`.
    #[arg(long, default_value = "cosine", value_parser = parse_spacing)]
    pub spacing: Spacing,
    /// Mesh input: stations at these x instead (comma-separated, increasing).
    #[arg(long, value_name = "X1,X2,...", value_delimiter = ',', value_parser = parse_finite, conflicts_with = "stations")]
    pub at: Option<Vec<f64>>,
    /// Mesh input: points per section, keel to deck edge.
    #[arg(long = "points", default_value_t = 30, value_name = "M")]
    pub points: usize,
    /// Mesh input: spacing of the points along a section, `arc-length` or `adaptive` (denser
    /// at bends; can fold a skinned surface).
    #[arg(long, default_value = "arc-length", value_parser = parse_resample)]
    pub resample: Resample,
    /// Mesh input: end the sections at this height instead of the deck edge.
    #[arg(long, value_name = "Z")]
    pub max_z: Option<f64>,
    /// Mesh input: the file's axes as hullskin's x (forward), y (starboard), z (up), each a
    /// signed axis of the file, e.g. `z,x,y` for a mesh with z forward and y up.
    #[arg(long, default_value = "x,y,z", value_parser = parse_axes)]
    pub axes: Axes,
    /// Mesh input: added to every vertex after --axes, e.g. `0,0,0.0625` to put the keel of a
    /// mesh with z = 0 at the waterline at z = 0.
    #[arg(long, value_name = "DX,DY,DZ", value_parser = parse_vec3)]
    pub shift: Option<Vec3>,
    /// Mesh input: merge vertices closer than this (default: only equal ones).
    #[arg(long, default_value_t = 0.0, value_name = "TOL")]
    pub weld: f64,
}

impl Default for MeshArgs {
    fn default() -> Self {
        MeshArgs {
            stations: 41,
            spacing: Spacing::Cosine,
            at: None,
            points: 30,
            resample: Resample::ArcLength,
            max_z: None,
            axes: Axes::default(),
            shift: None,
            weld: 0.0,
        }
    }
}

impl MeshArgs {
    /// The reader's settings.
    pub fn read_options(&self) -> MeshReadOptions {
        MeshReadOptions {
            axes: self.axes,
            shift: self.shift.unwrap_or(Vec3::new(0.0, 0.0, 0.0)),
            weld_tolerance: self.weld,
        }
    }

    /// The slicer's settings, the offsets labelled in `units`.
    pub fn slice_options(&self, units: Units) -> SliceOptions {
        let stations = match &self.at {
            Some(xs) => Stations::At(xs.clone()),
            None => Stations::Count { n: self.stations, spacing: self.spacing },
        };
        SliceOptions {
            stations,
            points: self.points,
            resample: self.resample,
            max_z: self.max_z,
            units,
            ..SliceOptions::default()
        }
    }

    /// Reads the mesh at `path` and slices it; the warnings (dropped stations, joined pieces)
    /// go to standard error.
    ///
    /// # Errors
    /// Those of [`read_mesh`] and [`slice_mesh`], naming the file.
    pub fn read_and_slice(&self, path: &Path, units: Units) -> anyhow::Result<(TriMesh, SliceOutcome)> {
        let mesh = read_mesh(path, &self.read_options())?;
        let out = slice_mesh(&mesh, &self.slice_options(units))
            .with_context(|| format!("cannot slice the mesh {}", path.display()))?;
        for w in out.warnings() {
            eprintln!("hullskin: warning: {}: {w}", path.display());
        }
        Ok((mesh, out))
    }
}

/// True if `path` names a mesh ([`hull::is_mesh_path`]).
pub use hull::is_mesh_path;

/// The sections of the mesh at `path`, sliced with `args` (for `fit` and the commands that
/// fit first).
///
/// # Errors
/// Those of [`MeshArgs::read_and_slice`].
pub fn mesh_offsets(path: &Path, args: &MeshArgs, units: Units) -> anyhow::Result<Offsets> {
    Ok(args.read_and_slice(path, units)?.1.offsets)
}

/// Arguments of `hullskin slice`.
#[derive(Debug, Args)]
pub struct SliceArgs {
    /// The mesh: STL (ASCII or binary), OBJ or VRML 1.0/2.0 (.wrl), optionally gzip-compressed (.stl.gz).
    pub input: PathBuf,
    #[command(flatten)]
    pub mesh: MeshArgs,
    /// Units of the mesh's coordinates (a label carried to the sections; nothing is
    /// converted): m, mm, ft or in.
    #[arg(long, default_value = "m", value_parser = parse_units)]
    pub units: Units,
    /// The sections CSV to write (header section,x,y,z).
    #[arg(short = 'o', long = "out", default_value = "sections.csv")]
    pub out: PathBuf,
    /// Print the mesh's hydrostatics at this draft (waterplane z): volume, centres, wetted
    /// surface, waterplane.
    #[arg(long, value_name = "T")]
    pub draft: Option<f64>,
    /// A surface.json (from `hullskin fit` on these sections) to measure against the mesh at
    /// --draft: its hydrostatics beside the mesh's, and the distance of the mesh's wetted
    /// starboard vertices to it.
    #[arg(long, value_name = "SURFACE.json", requires = "draft")]
    pub check: Option<PathBuf>,
    /// Print the summary as one JSON object on standard output (full precision), for
    /// scripts; warnings stay on standard error.
    #[arg(long)]
    pub json: bool,
}

/// Run `hullskin slice`.
pub fn run(args: &SliceArgs) -> anyhow::Result<ExitCode> {
    let (mesh, out) = args.mesh.read_and_slice(&args.input, args.units)?;
    let edges = mesh.edge_counts();
    let points: usize = out.offsets.sections.iter().map(|s| s.points.len()).sum();
    let mut summary = serde_json::json!({
        "mesh": {
            "source": mesh.source,
            "triangles": mesh.triangles.len(),
            "vertices": mesh.vertices.len(),
            "degenerate_dropped": mesh.degenerate,
            "open_edges": edges.open,
            "non_manifold_edges": edges.non_manifold,
            "bounds": mesh.bounds().map(|(lo, hi)| [[lo.x, lo.y, lo.z], [hi.x, hi.y, hi.z]]),
        },
        "units": args.units.symbol(),
        "sections": out.offsets.sections.len(),
        "points": points,
        "stations_dropped": out.dropped.len(),
    });
    let mut text = String::new();
    let mut line = |l: String| {
        text.push_str(&l);
        text.push('\n');
    };
    line(format!(
        "{}: {} triangles, {} vertices ({} degenerate triangles dropped), {} open and {} non-manifold edges",
        mesh.source,
        mesh.triangles.len(),
        mesh.vertices.len(),
        mesh.degenerate,
        edges.open,
        edges.non_manifold
    ));
    if let Some((lo, hi)) = mesh.bounds() {
        let f = hull::format_short;
        line(format!("  x {} .. {}, y {} .. {}, z {} .. {}", f(lo.x), f(hi.x), f(lo.y), f(hi.y), f(lo.z), f(hi.z)));
    }
    line(format!(
        "{} sections of {} points ({} stations dropped), keel to deck edge (or the mesh's top) on the starboard side",
        out.offsets.sections.len(),
        points / out.offsets.sections.len().max(1),
        out.dropped.len()
    ));
    if let Some(t) = args.draft {
        let m = mesh_hydrostatics(&mesh, t);
        mesh_hydrostatics_text(&m, args.units).lines().for_each(|l| line(l.to_string()));
        summary["hydrostatics"] = mesh_hydrostatics_json(&m);
        if m.open_edges_below > 0 {
            eprintln!(
                "hullskin: warning: the mesh has {} open edges below the waterline: its volume is not that of a \
                 closed hull",
                m.open_edges_below
            );
        }
        if let Some(path) = &args.check {
            let (check_text, check) = check_surface(path, &mesh, &out.offsets, &m)?;
            check_text.lines().for_each(|l| line(l.to_string()));
            summary["check"] = check;
        }
    }
    // Written last, atomically: a run that fails (e.g. an unreadable --check surface) leaves
    // an earlier file as it was.
    hull::write_atomic(&args.out, |w| hull::write_sections_csv(w, &out.offsets, Notation::Exchange))
        .with_context(|| format!("cannot write {}", args.out.display()))?;
    line(format!("wrote {}", args.out.display()));
    summary["wrote"] = serde_json::json!(args.out.display().to_string());
    if args.json {
        outln!("{}", serde_json::to_string_pretty(&summary).context("the summary as JSON")?);
    } else {
        out!("{text}");
    }
    Ok(ExitCode::SUCCESS)
}

/// The mesh's hydrostatics as summary lines, figures to 5 significant digits.
fn mesh_hydrostatics_text(m: &MeshHydrostatics, units: Units) -> String {
    let u = units.symbol();
    let f = hull::format_figure;
    let mut s = format!(
        "mesh at draft {} {u}{}:\n",
        hull::format_short(m.draft),
        if m.half { " (starboard half, doubled)" } else { "" }
    );
    s += &format!("  volume {} {u}3, LCB {} {u}, KB {} {u}\n", f(m.volume), f(m.lcb), f(m.vcb));
    s += &format!("  wetted surface {} {u}2\n", f(m.wetted_surface));
    s += &format!(
        "  waterplane {} {u}2, LCF {} {u}, Lwl {} {u}, Bwl {} {u}\n",
        f(m.waterplane_area),
        f(m.lcf),
        f(m.lwl),
        f(m.bwl)
    );
    if m.inward {
        s += "  (the mesh's triangles face inward; measured as if turned outward)\n";
    }
    s
}

/// The mesh's hydrostatics at full precision, for `--json`.
fn mesh_hydrostatics_json(m: &MeshHydrostatics) -> serde_json::Value {
    serde_json::json!({
        "draft": m.draft,
        "volume": m.volume,
        "lcb": m.lcb,
        "kb": m.vcb,
        "wetted_surface": m.wetted_surface,
        "waterplane_area": m.waterplane_area,
        "lcf": m.lcf,
        "lwl": m.lwl,
        "bwl": m.bwl,
        "half": m.half,
        "inward": m.inward,
        "open_edges_below": m.open_edges_below,
    })
}

/// The surface at `path` against the mesh: summary lines and the same at full precision.
fn check_surface(
    path: &Path,
    mesh: &TriMesh,
    offsets: &Offsets,
    m: &MeshHydrostatics,
) -> anyhow::Result<(String, serde_json::Value)> {
    hull::check_file_size(path, hull::MAX_SURFACE_JSON_BYTES, "a surface.json")?;
    let text = std::fs::read_to_string(path).with_context(|| format!("cannot read {}", path.display()))?;
    let (surface, _) =
        hull::read_surface_json(&text).with_context(|| format!("cannot read the surface {}", path.display()))?;
    let c = hull::compare_mesh_and_surface(&surface, mesh, offsets, m)
        .with_context(|| format!("hydrostatics of {}", path.display()))?;
    let row = &c.surface;
    let f = hull::format_figure;
    let mut s = format!("surface {} against the mesh at draft {}:\n", path.display(), hull::format_short(m.draft));
    s += &format!(
        "  volume {} ({:+.3} %), LCB {} ({}), KB {} ({})\n",
        f(row.vol),
        c.volume_pct,
        f(row.lcb),
        signed(c.lcb_diff),
        f(row.vcb),
        signed(c.kb_diff)
    );
    s += &format!("  wetted surface {} ({:+.3} %)\n", f(row.s), c.wetted_surface_pct);
    s += &format!("  waterplane {} ({:+.3} %)\n", f(row.aw), c.waterplane_pct);
    let mut json = serde_json::json!({
        "surface": path.display().to_string(),
        "volume": row.vol,
        "lcb": row.lcb,
        "kb": row.vcb,
        "wetted_surface": row.s,
        "waterplane_area": row.aw,
    });
    if let Some(d) = &c.distance {
        let h = &d.over_hull;
        s += &format!(
            "  distance of {} wetted starboard mesh vertices to the surface: max {:.3e}, mean {:.3e}, RMS {:.3e} \
             ({} more face another way: transom, centre-plane lid or sharp edges)\n",
            h.points, h.max, h.mean, h.rms, d.left_out
        );
        json["distance"] = serde_json::json!({
            "vertices": h.points, "max": h.max, "mean": h.mean, "rms": h.rms, "left_out": d.left_out,
            "worst": d.worst.map(|(q, foot)| serde_json::json!({"vertex": [q.x, q.y, q.z], "foot": [foot.x, foot.y, foot.z]})),
        });
        if let Some((q, foot)) = d.worst {
            s += &format!(
                "  farthest vertex ({}, {}, {}), foot ({}, {}, {})\n",
                f(q.x),
                f(q.y),
                f(q.z),
                f(foot.x),
                f(foot.y),
                f(foot.z)
            );
        }
    }
    Ok((s, json))
}

/// A difference with its sign, to 4 significant digits (`+0.0012`, `-3.4e-7`).
fn signed(v: f64) -> String {
    let s = hull::format_short(v);
    if v > 0.0 {
        format!("+{s}")
    } else {
        s
    }
}

fn parse_spacing(s: &str) -> Result<Spacing, String> {
    s.parse()
}

fn parse_resample(s: &str) -> Result<Resample, String> {
    s.parse()
}

fn parse_axes(s: &str) -> Result<Axes, String> {
    s.parse().map_err(|e| format!("{e}"))
}

/// One finite number.
fn parse_finite(s: &str) -> Result<f64, String> {
    match s.trim().parse::<f64>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!("`{}` is not a finite number", s.trim())),
    }
}

/// Comma-separated finite numbers.
fn parse_list(s: &str) -> Result<Vec<f64>, String> {
    s.split(',')
        .map(|t| match t.trim().parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            _ => Err(format!("`{}` is not a finite number (in `{s}`)", t.trim())),
        })
        .collect()
}

/// `DX,DY,DZ`.
fn parse_vec3(s: &str) -> Result<Vec3, String> {
    match parse_list(s)?.as_slice() {
        &[x, y, z] => Ok(Vec3::new(x, y, z)),
        v => Err(format!("expected three numbers DX,DY,DZ, got {} in `{s}`", v.len())),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn value_parsers_accept_what_they_document_and_say_why_not() {
        assert_eq!(parse_list("0, 1.5,3").expect("list"), vec![0.0, 1.5, 3.0]);
        assert!(parse_list("0,nan").expect_err("nan").contains("`nan`"));
        assert_eq!(parse_vec3("0,0,0.0625").expect("vec"), Vec3::new(0.0, 0.0, 0.0625));
        assert!(parse_vec3("1,2").expect_err("two").contains("got 2"));
        assert_eq!(parse_axes("z,x,y").expect("axes").to_string(), "z,x,y");
        assert!(parse_axes("x,x,y").expect_err("twice").contains("each of x, y, z once"));
        assert_eq!(parse_spacing("Uniform"), Ok(Spacing::Uniform));
        assert!(parse_resample("spline").is_err());
    }

    #[test]
    fn the_flags_become_the_library_settings() {
        let args = MeshArgs { at: Some(vec![1.0, 2.0]), points: 12, ..MeshArgs::default() };
        let o = args.slice_options(Units::Foot);
        assert_eq!((o.stations, o.points, o.units), (Stations::At(vec![1.0, 2.0]), 12, Units::Foot));
        let d = MeshArgs::default().slice_options(Units::Metre);
        assert_eq!(d.stations, Stations::Count { n: 41, spacing: Spacing::Cosine });
        assert_eq!(d, SliceOptions::default());
    }
}
