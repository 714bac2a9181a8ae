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

use hull::{
    detect_format, digitize, is_freeship_header, is_offset_json, looks_like_binary_stl, mesh_hydrostatics,
    parse_drawing, parse_dxf, parse_freeship_curves, parse_freeship_offsets, parse_iges, parse_json_table,
    parse_long_csv, parse_mesh, parse_obj, parse_offset_table, parse_offsets_with, parse_point_cloud,
    parse_sections_csv, parse_series60_table, parse_step, parse_stl, parse_svg, parse_vrml, slice_mesh,
    starts_with_solid, CadFormat, CadSurfaces, CurveOrder, DigitizeOptions, DrawingScale, HullError, InputFormat,
    MainDimensions, MeshFormat, MeshReadOptions, Offsets, ReadOptions, Sketch, SliceOptions, Spacing, StationIds,
    StationX, Stations, SuspiciousPolicy, Units,
};
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
    ("mesh_vrml", mesh_vrml),
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

/// `hull::parse_offsets_with` with format detection, as `hullskin fit` reads a file.
pub fn read_detect(data: &[u8], source: &str) -> Result<(), String> {
    let text = hull::decode(data, source).map_err(|e| message(&e))?;
    let _ = detect_format(text);
    let mut first = Ok(());
    for min_points in [0, 4] {
        let options = ReadOptions { min_points, ..ReadOptions::default() };
        match parse_offsets_with(text, source, &options) {
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

/// `hull::parse_sections_csv`.
pub fn read_sections_csv(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = parse_sections_csv(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o);
    Ok(())
}

/// `hull::parse_offset_table`.
pub fn read_offset_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = parse_offset_table(text, source, Units::Foot).map_err(|e| message(&e))?;
    use_offsets(&o);
    Ok(())
}

/// `hull::parse_series60_table`, with each policy for suspicious values.
pub fn read_series60_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let mut first = Ok(());
    for policy in [SuspiciousPolicy::Interpolate, SuspiciousPolicy::Omit, SuspiciousPolicy::Refuse] {
        match parse_series60_table(text, source, MainDimensions::SERIES60_CB060, Units::Metre, policy) {
            Ok(t) => use_offsets(&t.offsets),
            Err(e) if policy == SuspiciousPolicy::Interpolate => first = Err(message(&e)),
            Err(_) => {}
        }
    }
    first
}

/// `hull::parse_long_csv`.
pub fn read_long_csv(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = parse_long_csv(text, source, &ReadOptions::default()).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::parse_json_table`, without and with main dimensions (an OpenHull
/// table needs them for its station spacing).
pub fn read_json_table(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let _ = is_offset_json(text);
    let with_dims = ReadOptions {
        dimensions: Some(MainDimensions { lpp: 100.0, beam: 10.0, draft: 5.0 }),
        ..ReadOptions::default()
    };
    if let Ok(o) = parse_json_table(text, source, &with_dims, None) {
        use_offsets(&o.offsets);
    }
    let o = parse_json_table(text, source, &ReadOptions::default(), None).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::parse_point_cloud`.
pub fn read_point_cloud(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = parse_point_cloud(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::parse_freeship_offsets`, and the format's header test.
pub fn read_freeship_offsets(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    for line in text.lines().take(4) {
        let _ = is_freeship_header(line);
    }
    let options = ReadOptions { format: Some(InputFormat::FreeshipOffsets), ..ReadOptions::default() };
    let o = parse_freeship_offsets(text, source, &options).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::parse_freeship_curves`.
pub fn read_freeship_curves(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let o = parse_freeship_curves(text, source, Units::Metre).map_err(|e| message(&e))?;
    use_offsets(&o.offsets);
    Ok(())
}

/// `hull::parse_stl` (ASCII and binary).
pub fn mesh_stl(data: &[u8], source: &str) -> Result<(), String> {
    let _ = (looks_like_binary_stl(data), starts_with_solid(data));
    parse_stl(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::parse_obj`.
pub fn mesh_obj(data: &[u8], source: &str) -> Result<(), String> {
    parse_obj(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::parse_vrml` (VRML 1.0 and 2.0).
pub fn mesh_vrml(data: &[u8], source: &str) -> Result<(), String> {
    parse_vrml(data, source).map(|_| ()).map_err(|e| message(&e))
}

/// `hull::parse_mesh` (format sniffed, gzip inflated), then what `hullskin slice` does
/// with the mesh: slicing at a few stations, edge counts, hydrostatics at mid height.
pub fn mesh_parse_slice(data: &[u8], source: &str) -> Result<(), String> {
    let _ = MeshFormat::sniff(data);
    let m = parse_mesh(data, source, None, &MeshReadOptions::default()).map_err(|e| message(&e))?;
    let _ = m.edge_counts();
    let options = SliceOptions {
        stations: Stations::Count { n: 5, spacing: Spacing::Cosine },
        points: 8,
        ..SliceOptions::default()
    };
    if let Ok(out) = slice_mesh(&m, &options) {
        use_offsets(&out.offsets);
        let _ = out.warnings();
    }
    let options = SliceOptions { max_z: Some(0.5), points: 3, ..options };
    let _ = slice_mesh(&m, &options);
    if let Some((lo, hi)) = m.bounds() {
        let _ = mesh_hydrostatics(&m, 0.5 * (lo.z + hi.z));
    }
    Ok(())
}

/// `hull::parse_dxf` (text read lossily, as `parse_drawing` does).
pub fn drawing_dxf(data: &[u8], source: &str) -> Result<(), String> {
    let text = String::from_utf8_lossy(data);
    let sketch = parse_dxf(&text, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    Ok(())
}

/// `hull::parse_svg`.
pub fn drawing_svg(data: &[u8], source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let sketch = parse_svg(text, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    Ok(())
}

/// `hull::parse_drawing` (DXF or SVG by content), then `digitize` as
/// `hullskin digitize` runs it: stations by body-plan order, by label, and by layer.
pub fn drawing_digitize(data: &[u8], source: &str) -> Result<(), String> {
    let sketch = parse_drawing(data, source).map_err(|e| message(&e))?;
    use_sketch(&sketch);
    let spacing = StationX::Spacing { origin: 0.0, spacing: 1.0 };
    let ids = [StationIds::Order(CurveOrder::BodyPlan), StationIds::Labels, StationIds::Layers("*".into())];
    for stations in ids {
        let mut o = DigitizeOptions::new(DrawingScale::UnitsPerModelUnit(10.0), [0.0, 0.0], stations, spacing.clone());
        let _ = digitize(&sketch, &o);
        o.points = Some(5);
        let _ = digitize(&sketch, &o);
    }
    let mut o = DigitizeOptions::new(
        DrawingScale::Ratio { paper: 1.0, model: 50.0 },
        [1.0, -1.0],
        StationIds::Order(CurveOrder::Layer),
        StationX::List(vec![0.0, 1.0, 2.0]),
    );
    o.drawing_unit_mm = Some(1.0);
    let _ = digitize(&sketch, &o);
    Ok(())
}

/// A drawing read: its curves flattened, as `digitize` does.
fn use_sketch(sketch: &Sketch) {
    for c in &sketch.curves {
        let _ = c.points(1e-3);
        let _ = c.describe();
    }
}

/// `hull::read_surface_json`, then the surface used as `hullskin hydrostatics` and
/// `report` use it ([`use_surface`]).
pub fn surface_json(data: &[u8], _source: &str) -> Result<(), String> {
    let Some(text) = text(data) else { return Ok(()) };
    let (s, units) = hull::read_surface_json(text).map_err(|e| e.to_string())?;
    let _ = units.parse::<Units>();
    use_surface(&s);
    Ok(())
}

/// `hull::parse_iges` in the file's unit and in metres, then each surface used as
/// [`surface_json`] uses it.
pub fn read_iges(data: &[u8], source: &str) -> Result<(), String> {
    let _ = CadFormat::sniff(data);
    cad(parse_iges, data, source)
}

/// `hull::parse_step`, as [`read_iges`].
pub fn read_step(data: &[u8], source: &str) -> Result<(), String> {
    let _ = CadFormat::sniff(data);
    cad(parse_step, data, source)
}

type CadParser = fn(&[u8], &str, Option<Units>) -> Result<CadSurfaces, HullError>;

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
