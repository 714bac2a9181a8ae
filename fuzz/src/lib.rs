//! What each fuzz target does with its input, one function per target (the files of
//! `fuzz_targets/` are one-line wrappers around these).
//!
//! The same functions run the regression inputs of `testdata/fuzz/<target>/` in
//! `crates/hull/tests/io/fuzz_regressions.rs` (which includes this file by path), so a crash the
//! fuzzer found is replayed exactly as it was found, on stable Rust, in every `cargo test`.
//!
//! Each function parses its input through a public entry point of `hull` and, when the input
//! parses, uses what it read the way the CLI does next (validating offsets, slicing a mesh,
//! digitising a drawing, evaluating a surface). It returns the parse error's message, so the
//! regression test can check the message names the source and a place. The contract fuzzed:
//! any input gives `Ok` or `Err`; never a panic, a hang or an unbounded allocation.

use hull::digitize::{self, CurveOrder, DigitizeOptions, DrawingScale, StationIds, StationX};
use hull::mesh::{self, MeshReadOptions, SliceOptions, Spacing, Stations};
use hull::read::{self, InputFormat, MainDimensions, ReadOptions, SuspiciousPolicy};
use hull::{HullError, Offsets, Units};
use nurbs::{ProjectionOptions, SurfaceProjector, Vec3};

/// A fuzz target: the input bytes and the name of the source for messages; the parse error,
/// if any, as text.
pub type Target = fn(&[u8], &str) -> Result<(), String>;

/// Every target by name (the name of its file in `fuzz_targets/` and of its regression
/// directory in `testdata/fuzz/`).
pub const TARGETS: &[(&str, Target)] = &[
    ("decode", decode),
    ("read_detect", read_detect),
    ("read_sections_csv", read_sections_csv),
    ("read_offset_table", read_offset_table),
    ("read_series60_table", read_series60_table),
    ("read_long_csv", read_long_csv),
    ("read_json_table", read_json_table),
    ("read_point_cloud", read_point_cloud),
    ("read_freeship_offsets", read_freeship_offsets),
    ("read_freeship_curves", read_freeship_curves),
    ("mesh_stl", mesh_stl),
    ("mesh_obj", mesh_obj),
    ("mesh_parse_slice", mesh_parse_slice),
    ("drawing_dxf", drawing_dxf),
    ("drawing_svg", drawing_svg),
    ("drawing_digitize", drawing_digitize),
    ("surface_json", surface_json),
    ("read_iges", read_iges),
    ("read_step", read_step),
];

/// The target of that name.
pub fn target(name: &str) -> Option<Target> {
    TARGETS.iter().find(|(n, _)| *n == name).map(|&(_, t)| t)
}

fn message(e: &HullError) -> String {
    e.to_string()
}

/// The input as text; the text readers take `&str`, so non-UTF-8 input is not theirs to see
/// (`decode` is fuzzed on its own).
fn text(data: &[u8]) -> Option<&str> {
    std::str::from_utf8(data).ok()
}

/// Offsets read: what the fit does first with them.
fn use_offsets(o: &Offsets) {
    for min in [0, 2, 4] {
        let _ = o.validate(min);
    }
    let _ = o.num_points();
}

/// `hull::decode`: the bytes-to-text step of every offsets reader.
pub fn decode(data: &[u8], source: &str) -> Result<(), String> {
    hull::decode(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::read::parse_offsets_with` with format detection, as `hullskin fit` reads a file.
pub fn read_detect(data: &[u8], source: &str) -> Result<(), String> {
    let text = hull::decode(data, source).map_err(|e| message(&e))?;
    let _ = read::detect_format(text);
    let mut first = Ok(());
    for min_points in [0, 4] {
        let options = ReadOptions { min_points, ..ReadOptions::default() };
        match read::parse_offsets_with(text, source, &options) {
            Ok(o) => {
                use_offsets(&o.offsets);
                let _ = o.messages();
            }
            Err(e) if min_points == 0 => first = Err(message(&e)),
            Err(_) => {}
        }
    }
    first
}

/// `hull::read::parse_sections_csv`.
pub fn read_sections_csv(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = read::parse_sections_csv(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o);
    Ok(())
}

/// `hull::read::parse_offset_table`.
pub fn read_offset_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = read::parse_offset_table(text, source, Units::Foot).map_err(|e| message(&e))?;
    use_offsets(&o);
    Ok(())
}

/// `hull::read::parse_series60_table`, with each policy for suspicious values.
pub fn read_series60_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let mut first = Ok(());
    for policy in [SuspiciousPolicy::Interpolate, SuspiciousPolicy::Omit, SuspiciousPolicy::Refuse] {
        match read::parse_series60_table(text, source, MainDimensions::SERIES60_CB060, Units::Metre, policy) {
            Ok(t) => use_offsets(&t.offsets),
            Err(e) if policy == SuspiciousPolicy::Interpolate => first = Err(message(&e)),
            Err(_) => {}
        }
    }
    first
}

/// `hull::read::long_csv::parse_long_csv`.
pub fn read_long_csv(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = read::long_csv::parse_long_csv(text, source, &ReadOptions::default()).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::read::json_table::parse_json_table`, without and with main dimensions (an OpenHull
/// table needs them for its station spacing).
pub fn read_json_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let _ = read::json_table::is_offset_json(text);
    let with_dims = ReadOptions {
        dimensions: Some(MainDimensions { lpp: 100.0, beam: 10.0, draft: 5.0 }),
        ..ReadOptions::default()
    };
    if let Ok(o) = read::json_table::parse_json_table(text, source, &with_dims, None) {
        use_offsets(&o.offsets);
    }
    let o = read::json_table::parse_json_table(text, source, &ReadOptions::default(), None).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::read::point_cloud::parse_point_cloud`.
pub fn read_point_cloud(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = read::point_cloud::parse_point_cloud(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::read::freeship::parse_freeship_offsets`, and the format's header test.
pub fn read_freeship_offsets(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    for line in text.lines().take(4) {
        let _ = read::freeship::is_header(line);
    }
    let options = ReadOptions { format: Some(InputFormat::FreeshipOffsets), ..ReadOptions::default() };
    let o = read::freeship::parse_freeship_offsets(text, source, &options).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::read::freeship::parse_freeship_curves`.
pub fn read_freeship_curves(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = read::freeship::parse_freeship_curves(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::mesh::stl::parse_stl` (ASCII and binary).
pub fn mesh_stl(data: &[u8], source: &str) -> Result<(), String> {
    let _ = (mesh::stl::looks_binary(data), mesh::stl::starts_with_solid(data));
    mesh::stl::parse_stl(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::mesh::obj::parse_obj`.
pub fn mesh_obj(data: &[u8], source: &str) -> Result<(), String> {
    mesh::obj::parse_obj(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::mesh::parse_mesh` (format sniffed, gzip inflated), then what `hullskin slice` does
/// with the mesh: slicing at a few stations, edge counts, hydrostatics at mid height.
pub fn mesh_parse_slice(data: &[u8], source: &str) -> Result<(), String> {
    let _ = mesh::MeshFormat::sniff(data);
    let m = mesh::parse_mesh(data, source, None, &MeshReadOptions::default()).map_err(|e| message(&e))?;
    let _ = m.edge_counts();
    let options = SliceOptions {
        stations: Stations::Count { n: 5, spacing: Spacing::Cosine },
        points: 8,
        ..SliceOptions::default()
    };
    if let Ok(out) = mesh::slice_mesh(&m, &options) {
        use_offsets(&out.offsets);
        let _ = out.warnings();
    }
    let options = SliceOptions { max_z: Some(0.5), points: 3, ..options };
    let _ = mesh::slice_mesh(&m, &options);
    if let Some((lo, hi)) = m.bounds() {
        let _ = mesh::mesh_hydrostatics(&m, 0.5 * (lo.z + hi.z));
    }
    Ok(())
}

/// `hull::digitize::parse_dxf` (text read lossily, as `parse_drawing` does).
pub fn drawing_dxf(data: &[u8], source: &str) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    let sketch = digitize::parse_dxf(&text, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    Ok(())
}

/// `hull::digitize::parse_svg`.
pub fn drawing_svg(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let sketch = digitize::parse_svg(text, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    Ok(())
}

/// `hull::digitize::parse_drawing` (DXF or SVG by content), then `digitize` as
/// `hullskin digitize` runs it: stations by body-plan order, by label, and by layer.
pub fn drawing_digitize(data: &[u8], source: &str) -> Result<(), String> {
    let sketch = digitize::parse_drawing(data, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    let spacing = StationX::Spacing { origin: 0.0, spacing: 1.0 };
    let ids = [StationIds::Order(CurveOrder::BodyPlan), StationIds::Labels, StationIds::Layers("*".into())];
    for stations in ids {
        let mut o = DigitizeOptions::new(DrawingScale::UnitsPerModelUnit(10.0), [0.0, 0.0], stations, spacing.clone());
        let _ = digitize::digitize(&sketch, &o);
        o.points = Some(5);
        let _ = digitize::digitize(&sketch, &o);
    }
    let mut o = DigitizeOptions::new(
        DrawingScale::Ratio { paper: 1.0, model: 50.0 },
        [1.0, -1.0],
        StationIds::Order(CurveOrder::Layer),
        StationX::List(vec![0.0, 1.0, 2.0]),
    );
    o.drawing_unit_mm = Some(1.0);
    let _ = digitize::digitize(&sketch, &o);
    Ok(())
}

/// A drawing read: its curves flattened, as `digitize` does.
fn use_sketch(sketch: &digitize::Sketch) {
    for c in &sketch.curves {
        let _ = c.points(1e-3);
        let _ = c.describe();
    }
}

/// `hull::export::read_surface_json`, then the surface used as `hullskin hydrostatics` and
/// `report` use it ([`use_surface`]).
pub fn surface_json(data: &[u8], _source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let (s, units) = hull::export::read_surface_json(text).map_err(|e| e.to_string())?;
    let _ = units.parse::<Units>();
    use_surface(&s);
    Ok(())
}

/// `hull::read::iges::parse_iges` in the file's unit and in metres, then each surface used as
/// [`surface_json`] uses it.
pub fn read_iges(data: &[u8], source: &str) -> Result<(), String> {
    let _ = read::cad::CadFormat::sniff(data);
    cad(read::iges::parse_iges, data, source)
}

/// `hull::read::step::parse_step`, as [`read_iges`].
pub fn read_step(data: &[u8], source: &str) -> Result<(), String> {
    let _ = read::cad::CadFormat::sniff(data);
    cad(read::step::parse_step, data, source)
}

type CadParser = fn(&[u8], &str, Option<Units>) -> Result<read::cad::CadSurfaces, HullError>;

fn cad(parse: CadParser, data: &[u8], source: &str) -> Result<(), String> {
    let _ = parse(data, source, Some(Units::Metre));
    let read = parse(data, source, None).map_err(|e| message(&e))?;
    for s in &read.surfaces {
        use_surface(&s.surface);
    }
    Ok(())
}

/// A surface read: points, derivatives, normals and curvatures over the domain, an iso-curve,
/// a closest point, and hydrostatics at mid draft.
fn use_surface(s: &nurbs::NurbsSurface) {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    for a in [-0.5, 0.0, 0.3, 0.5, 1.0, 1.5] {
        for b in [0.0, 0.7, 1.0] {
            let (u, v) = (u0 + a * (u1 - u0), v0 + b * (v1 - v0));
            let _ = s.point(u, v);
            let d = s.derivatives(u, v);
            let _ = (d.normal(), d.curvature());
            let _ = (s.normal(u, v), s.curvature(u, v));
        }
    }
    let _ = s.point(f64::NAN, f64::INFINITY);
    let c = s.iso_curve_u(0.5 * (v0 + v1));
    let _ = (c.point(u0), c.derivatives(u1, 2));
    let (lo, hi) = s.control_bounds();
    let _ = s.transposed();
    let q = Vec3::new(0.5 * (lo.x + hi.x), hi.y + 1.0, 0.5 * (lo.z + hi.z));
    let _ = SurfaceProjector::new(s, ProjectionOptions::default()).project(q);
    let options = hull::HydrostaticsOptions { order: 2, split: 1, ..hull::HydrostaticsOptions::default() };
    if let Ok(h) = hull::Hydrostatics::new(s, &options) {
        let _ = h.at(0.5 * (lo.z + hi.z));
    }
}
