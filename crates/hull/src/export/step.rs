//! STEP AP214 export (ISO 10303-21 exchange file, schema `AUTOMOTIVE_DESIGN`) of one NURBS
//! surface as a bounded face.
//!
//! The rest of this module's documentation is on [`write_step`], where the library's users read it.

use std::io::{self, Write};

use nurbs::{KnotVector, NurbsCurve, NurbsSurface, Vec3};

use crate::float::real;
use crate::Units;

/// The `FILE_SCHEMA` of AP214 (automotive design, IS edition), as OCCT and most CAD systems
/// write it.
pub const AP214_SCHEMA: &str = "AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }";

/// Longest line of the `DATA` section, characters; entity lists are broken between parameters.
const LINE_WIDTH: usize = 100;

/// Relative size (of the control-net diagonal) under which a boundary curve is taken as
/// collapsed to a point: well above rounding (1e-16) and well below any real edge.
pub const DEGENERATE_REL: f64 = 1e-9;

/// What the header and product say about the file.
#[derive(Clone, Debug, PartialEq)]
pub struct StepMeta {
    /// Length unit of the coordinates.
    pub units: Units,
    /// `PRODUCT` id and name.
    pub product_id: String,
    /// `FILE_DESCRIPTION` text and `PRODUCT` description.
    pub description: String,
    /// `FILE_NAME` name.
    pub file_name: String,
    pub author: String,
    pub organization: String,
    /// `FILE_NAME` preprocessor and originating system.
    pub system_id: String,
    /// `FILE_NAME` time stamp, ISO 8601 `YYYY-MM-DDThh:mm:ss`; see [`step_timestamp`]. Passed
    /// in (not read from the clock) so output is reproducible.
    pub timestamp: String,
}

impl StepMeta {
    /// Metadata with the product `hull`, the system `hullskin <version>`, and empty author and
    /// organisation.
    pub fn new(units: Units, file_name: &str, timestamp: &str) -> Self {
        StepMeta {
            units,
            product_id: "hull".to_string(),
            description: "hull surface".to_string(),
            file_name: file_name.to_string(),
            author: String::new(),
            organization: String::new(),
            system_id: format!("hullskin {}", env!("CARGO_PKG_VERSION")),
            timestamp: timestamp.to_string(),
        }
    }
}

/// ISO 8601 UTC time stamp `YYYY-MM-DDThh:mm:ss` of a Unix time in seconds, e.g.
/// `1_000_000_000 -> "2001-09-09T01:46:40"` (the civil date of [`super::iges_timestamp`]).
pub fn step_timestamp(unix_seconds: i64) -> String {
    let (y, mo, d, h, mi, s) = super::iges::civil_time(unix_seconds);
    format!("{y:04}-{mo:02}-{d:02}T{h:02}:{mi:02}:{s:02}")
}

/// A Part 21 string literal of `s` (ISO 10303-21 section 7.3.3).
pub fn step_string(s: &str) -> String {
    let mut out = String::with_capacity(s.len() + 2);
    out.push('\'');
    for c in s.chars() {
        match c {
            '\'' => out.push_str("''"),
            '\\' => out.push_str("\\\\"),
            ' '..='~' => out.push(c),
            _ => {
                out.push_str("\\X2\\");
                let mut buf = [0u16; 2];
                for unit in c.encode_utf16(&mut buf) {
                    out.push_str(&format!("{unit:04X}"));
                }
                out.push_str("\\X0\\");
            }
        }
    }
    out.push('\'');
    out
}

/// The entities of the DATA section, numbered from 1 in insertion order.
struct Data {
    bodies: Vec<String>,
}

impl Data {
    /// Add an entity; returns its instance name `#k`.
    fn add(&mut self, body: String) -> String {
        self.bodies.push(body);
        format!("#{}", self.bodies.len())
    }
}

/// `(a,b,c)` of already formatted items.
fn list<I: IntoIterator<Item = String>>(items: I) -> String {
    format!("({})", items.into_iter().collect::<Vec<_>>().join(","))
}

fn reals(xs: &[f64]) -> io::Result<String> {
    Ok(list(xs.iter().map(|&x| real(x)).collect::<io::Result<Vec<_>>>()?))
}

fn point(data: &mut Data, p: Vec3) -> io::Result<String> {
    Ok(data.add(format!("CARTESIAN_POINT('',{})", reals(&[p.x, p.y, p.z])?)))
}

fn direction(data: &mut Data, d: [f64; 3]) -> io::Result<String> {
    Ok(data.add(format!("DIRECTION('',{})", reals(&d)?)))
}

/// Distinct knot values and their multiplicities (ISO 10303-42 `knot_multiplicities`, `knots`).
pub fn knots_with_multiplicities(k: &KnotVector) -> (Vec<usize>, Vec<f64>) {
    let mut mults: Vec<usize> = Vec::new();
    let mut values: Vec<f64> = Vec::new();
    for &u in k.as_slice() {
        match values.last() {
            Some(&last) if last == u => *mults.last_mut().expect("one multiplicity per value") += 1,
            _ => {
                values.push(u);
                mults.push(1);
            }
        }
    }
    (mults, values)
}

fn mults_and_knots(k: &KnotVector) -> io::Result<(String, String)> {
    let (m, v) = knots_with_multiplicities(k);
    Ok((list(m.iter().map(|m| m.to_string())), reals(&v)?))
}

fn all_equal(w: &[f64]) -> bool {
    w.iter().all(|&x| x == w[0])
}

fn bool_flag(b: bool) -> &'static str {
    if b {
        ".T."
    } else {
        ".F."
    }
}

/// The B-spline surface entity (plain or the rational complex instance); returns its name.
fn surface_entity(data: &mut Data, s: &NurbsSurface, name: &str) -> io::Result<String> {
    let (nu, nv) = (s.n_u(), s.n_v());
    let mut rows = Vec::with_capacity(nu);
    for i in 0..nu {
        let mut row = Vec::with_capacity(nv);
        for j in 0..nv {
            row.push(point(data, s.control_point(i, j))?);
        }
        rows.push(list(row));
    }
    let net = list(rows);
    let (mu, ku) = mults_and_knots(s.knots_u())?;
    let (mv, kv) = mults_and_knots(s.knots_v())?;
    let (p, q) = (s.degree_u(), s.degree_v());
    let weights = s.weights();
    let name = step_string(name);
    let body = if all_equal(&weights) {
        format!(
            "B_SPLINE_SURFACE_WITH_KNOTS({name},{p},{q},{net},.UNSPECIFIED.,.F.,.F.,.F.,{mu},{mv},{ku},{kv},.UNSPECIFIED.)"
        )
    } else {
        let w = list((0..nu).map(|i| reals(&weights[i * nv..(i + 1) * nv])).collect::<io::Result<Vec<_>>>()?);
        format!(
            "( BOUNDED_SURFACE() B_SPLINE_SURFACE({p},{q},{net},.UNSPECIFIED.,.F.,.F.,.F.) \
             B_SPLINE_SURFACE_WITH_KNOTS({mu},{mv},{ku},{kv},.UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() \
             RATIONAL_B_SPLINE_SURFACE({w}) REPRESENTATION_ITEM({name}) SURFACE() )"
        )
    };
    Ok(data.add(body))
}

/// The B-spline curve entity (plain or the rational complex instance); returns its name.
fn curve_entity(data: &mut Data, c: &NurbsCurve) -> io::Result<String> {
    let pts = c.control_points().into_iter().map(|p| point(data, p)).collect::<io::Result<Vec<_>>>()?;
    let pts = list(pts);
    let (m, k) = mults_and_knots(c.knots())?;
    let p = c.degree();
    let weights = c.weights();
    let body = if all_equal(&weights) {
        format!("B_SPLINE_CURVE_WITH_KNOTS('',{p},{pts},.UNSPECIFIED.,.F.,.F.,{m},{k},.UNSPECIFIED.)")
    } else {
        format!(
            "( BOUNDED_CURVE() B_SPLINE_CURVE({p},{pts},.UNSPECIFIED.,.F.,.F.) \
             B_SPLINE_CURVE_WITH_KNOTS({m},{k},.UNSPECIFIED.) CURVE() GEOMETRIC_REPRESENTATION_ITEM() \
             RATIONAL_B_SPLINE_CURVE({}) REPRESENTATION_ITEM('') )",
            reals(&weights)?
        )
    };
    Ok(data.add(body))
}

/// The length unit entity (and what it needs); returns its name.
fn length_unit(data: &mut Data, units: Units) -> io::Result<String> {
    let si = |prefix: &str| format!("( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT({prefix},.METRE.) )");
    Ok(match units {
        Units::Metre => data.add(si("$")),
        Units::Millimetre => data.add(si(".MILLI.")),
        Units::Foot | Units::Inch => {
            let name = if units == Units::Foot { "FOOT" } else { "INCH" };
            let metre = data.add(si("$"));
            let measure = data
                .add(format!("LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),{metre})", real(units.metres_per_unit())?));
            let dims = data.add("DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)".to_string());
            data.add(format!("( CONVERSION_BASED_UNIT('{name}',{measure}) LENGTH_UNIT() NAMED_UNIT({dims}) )"))
        }
    })
}

/// The four boundary iso-curves in loop order with their corner indices `(start, end)` along
/// the curve and whether the loop runs along it (`true`) or against it.
fn boundary(s: &NurbsSurface) -> [(NurbsCurve, usize, usize, bool); 4] {
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let t = s.transposed();
    // Corners: 0 = (u0, v0), 1 = (u1, v0), 2 = (u1, v1), 3 = (u0, v1).
    [
        (s.iso_curve_u(v0), 0, 1, true),
        (t.iso_curve_u(u1), 1, 2, true),
        (s.iso_curve_u(v1), 3, 2, false),
        (t.iso_curve_u(u0), 0, 3, false),
    ]
}

/// True if every control point of `c` is within `tol` of the first.
fn collapsed(c: &NurbsCurve, tol: f64) -> bool {
    let pts = c.control_points();
    pts.iter().all(|p| p.distance(pts[0]) <= tol)
}

/// Write `surface` as a STEP AP214 file holding one face (see below for the layout).
///
/// The file is a clear-text encoding (ISO 10303-21:2002) with a `HEADER` (`FILE_DESCRIPTION`,
/// `FILE_NAME` with the given timestamp, `FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'))`)
/// and a `DATA` section, entities numbered `#1, #2, ...` in the order below:
///
/// * **Product structure** (AP214 / ISO 10303-41): `APPLICATION_CONTEXT('automotive_design')`,
///   `APPLICATION_PROTOCOL_DEFINITION`, `PRODUCT_CONTEXT`, `PRODUCT`,
///   `PRODUCT_RELATED_PRODUCT_CATEGORY('part', ..)`, `PRODUCT_DEFINITION_FORMATION`,
///   `PRODUCT_DEFINITION_CONTEXT`, `PRODUCT_DEFINITION`, `PRODUCT_DEFINITION_SHAPE` and the
///   `SHAPE_DEFINITION_REPRESENTATION` tying it to the shape.
/// * **Units and uncertainty** (ISO 10303-41 section 4): the length unit of [`Units`] as
///   `( LENGTH_UNIT() NAMED_UNIT(*) SI_UNIT($,.METRE.) )` (with `.MILLI.` for millimetres), or
///   for feet and inches a `CONVERSION_BASED_UNIT('FOOT' | 'INCH', ..)` of
///   `LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(0.3048 | 0.0254), metre)` with
///   `DIMENSIONAL_EXPONENTS(1.,0.,0.,0.,0.,0.,0.)`; radian and steradian; an
///   `UNCERTAINTY_MEASURE_WITH_UNIT` of `10^floor(log10(1e-7 size))` (`size` the diagonal of
///   the control-net box, the same resolution the IGES writer declares); all in one complex
///   `GEOMETRIC_REPRESENTATION_CONTEXT(3)` with `GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT` and
///   `GLOBAL_UNIT_ASSIGNED_CONTEXT`.
/// * **Shape** (ISO 10303-42): `MANIFOLD_SURFACE_SHAPE_REPRESENTATION('hull', (axis, model))`
///   with a `SHELL_BASED_SURFACE_MODEL` of one `OPEN_SHELL` of one
///   `ADVANCED_FACE((FACE_OUTER_BOUND), surface, .T.)`. The bound is an `EDGE_LOOP` around the
///   parameter rectangle, counter-clockwise in `(u, v)`: the iso-curves `v = v0` (forward),
///   `u = u1` (forward), `v = v1` (reversed) and `u = u0` (reversed), each an `EDGE_CURVE`
///   between `VERTEX_POINT`s at the corners `S(u0, v0)`, `S(u1, v0)`, `S(u1, v1)`, `S(u0, v1)`.
///   A boundary that collapses to a point (a pointed stem section, within `1e-9 size`) has no
///   edge: its two corners are one vertex, and readers add the degenerate edge themselves.
/// * **The surface** (ISO 10303-42 section 4.4.41-4.4.43): when the weights differ, the complex
///   instance `( BOUNDED_SURFACE() B_SPLINE_SURFACE(p, q, ((P_00, P_01, ..), ..), .UNSPECIFIED.,
///   .F., .F., .F.) B_SPLINE_SURFACE_WITH_KNOTS((mult_u), (mult_v), (knots_u), (knots_v),
///   .UNSPECIFIED.) GEOMETRIC_REPRESENTATION_ITEM() RATIONAL_B_SPLINE_SURFACE(((w_00, ..), ..))
///   REPRESENTATION_ITEM('hull') SURFACE() )` (a complex entity lists its partial entities in
///   alphabetical order, ISO 10303-21 section 11.2.5.3); when all weights are equal the plain
///   `B_SPLINE_SURFACE_WITH_KNOTS`. The outer list runs over `i` (along u), the inner over `j`
///   (along v): the kernel's u-major order `i * n_v + j`. Knots are written as the distinct
///   values with their multiplicities (the clamped ends have multiplicity `p + 1`). Boundary
///   curves are `B_SPLINE_CURVE_WITH_KNOTS`, or the complex rational curve likewise.
///
/// Reals are written by [`crate::float::real`] (shortest round-trip), so the file carries the
/// surface bit for bit; strings are encoded per ISO 10303-21 section 7.3.3 (`'` doubled, `\`
/// doubled, other characters outside printable ASCII as `\X2\hhhh\X0\` UTF-16 code units).
/// The output depends only on its inputs (the timestamp is passed in), so it is reproducible.
///
/// # Errors
/// Whatever `w` returns; [`io::ErrorKind::InvalidData`] if a number is not finite (cannot
/// happen for a surface built by the kernel's validating constructors);
/// [`io::ErrorKind::InvalidInput`] if every boundary of the surface collapses to a point.
pub fn write_step<W: Write>(w: &mut W, surface: &NurbsSurface, meta: &StepMeta) -> io::Result<()> {
    let mut data = Data { bodies: Vec::new() };
    let d = &mut data;
    let (lo, hi) = surface.control_bounds();
    let size = (hi - lo).norm();

    // Product structure (ISO 10303-41, AP214 application context).
    let app = d.add("APPLICATION_CONTEXT('automotive_design')".into());
    d.add(format!("APPLICATION_PROTOCOL_DEFINITION('international standard','automotive_design',2000,{app})"));
    let pctx = d.add(format!("PRODUCT_CONTEXT('',{app},'mechanical')"));
    let (id, desc) = (step_string(&meta.product_id), step_string(&meta.description));
    let product = d.add(format!("PRODUCT({id},{id},{desc},({pctx}))"));
    d.add(format!("PRODUCT_RELATED_PRODUCT_CATEGORY('part',$,({product}))"));
    let formation = d.add(format!("PRODUCT_DEFINITION_FORMATION('','',{product})"));
    let pdctx = d.add(format!("PRODUCT_DEFINITION_CONTEXT('part definition',{app},'design')"));
    let pdef = d.add(format!("PRODUCT_DEFINITION('design','',{formation},{pdctx})"));
    let pds = d.add(format!("PRODUCT_DEFINITION_SHAPE('','',{pdef})"));

    // Units and uncertainty.
    let length = length_unit(d, meta.units)?;
    let angle = d.add("( NAMED_UNIT(*) PLANE_ANGLE_UNIT() SI_UNIT($,.RADIAN.) )".into());
    let solid = d.add("( NAMED_UNIT(*) SI_UNIT($,.STERADIAN.) SOLID_ANGLE_UNIT() )".into());
    let uncertainty = d.add(format!(
        "UNCERTAINTY_MEASURE_WITH_UNIT(LENGTH_MEASURE({}),{length},'distance_accuracy_value','confusion accuracy')",
        real(super::resolution(size))?
    ));
    let ctx = d.add(format!(
        "( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNCERTAINTY_ASSIGNED_CONTEXT(({uncertainty})) \
         GLOBAL_UNIT_ASSIGNED_CONTEXT(({length},{angle},{solid})) REPRESENTATION_CONTEXT('3D','hull') )"
    ));

    // Geometry and topology.
    let surf = surface_entity(d, surface, &meta.product_id)?;
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    let corners = [surface.point(u0, v0), surface.point(u1, v0), surface.point(u1, v1), surface.point(u0, v1)];
    let tol = DEGENERATE_REL * if size > 0.0 { size } else { 1.0 };
    let edges = boundary(surface);
    // Union of corners joined by collapsed edges: vertex index of each corner.
    let mut vertex_of = [0usize, 1, 2, 3];
    let keep: Vec<bool> = edges.iter().map(|(c, ..)| !collapsed(c, tol)).collect();
    for ((_, a, b, _), &kept) in edges.iter().zip(&keep) {
        if !kept {
            let (ra, rb) = (vertex_of[*a], vertex_of[*b]);
            for v in vertex_of.iter_mut() {
                if *v == rb {
                    *v = ra;
                }
            }
        }
    }
    if !keep.iter().any(|&k| k) {
        return Err(io::Error::new(io::ErrorKind::InvalidInput, "every boundary of the surface collapses to a point"));
    }
    let mut vertices: [Option<String>; 4] = [None, None, None, None];
    for k in 0..4 {
        let root = vertex_of[k];
        if vertices[root].is_none() {
            let p = point(d, corners[root])?;
            vertices[root] = Some(d.add(format!("VERTEX_POINT('',{p})")));
        }
    }
    let vertex = |k: usize| vertices[vertex_of[k]].clone().expect("every root corner has a vertex");
    let mut oriented = Vec::new();
    for ((curve, a, b, along), kept) in edges.iter().zip(keep) {
        if !kept {
            continue;
        }
        let c = curve_entity(d, curve)?;
        let edge = d.add(format!("EDGE_CURVE('',{},{},{c},.T.)", vertex(*a), vertex(*b)));
        oriented.push(d.add(format!("ORIENTED_EDGE('',*,*,{edge},{})", bool_flag(*along))));
    }
    let edge_loop = d.add(format!("EDGE_LOOP('',{})", list(oriented)));
    let bound = d.add(format!("FACE_OUTER_BOUND('',{edge_loop},.T.)"));
    let face = d.add(format!("ADVANCED_FACE({},({bound}),{surf},.T.)", step_string(&meta.product_id)));
    let shell = d.add(format!("OPEN_SHELL('',({face}))"));
    let model = d.add(format!("SHELL_BASED_SURFACE_MODEL('',({shell}))"));
    let origin = point(d, Vec3::new(0.0, 0.0, 0.0))?;
    let z = direction(d, [0.0, 0.0, 1.0])?;
    let x = direction(d, [1.0, 0.0, 0.0])?;
    let axis = d.add(format!("AXIS2_PLACEMENT_3D('',{origin},{z},{x})"));
    let rep = d.add(format!("MANIFOLD_SURFACE_SHAPE_REPRESENTATION({id},({axis},{model}),{ctx})"));
    d.add(format!("SHAPE_DEFINITION_REPRESENTATION({pds},{rep})"));

    writeln!(w, "ISO-10303-21;")?;
    writeln!(w, "HEADER;")?;
    writeln!(w, "FILE_DESCRIPTION(({}),'2;1');", step_string(&meta.description))?;
    writeln!(
        w,
        "FILE_NAME({},{},({}),({}),{sys},{sys},'');",
        step_string(&meta.file_name),
        step_string(&meta.timestamp),
        step_string(&meta.author),
        step_string(&meta.organization),
        sys = step_string(&meta.system_id),
    )?;
    writeln!(w, "FILE_SCHEMA(({}));", step_string(AP214_SCHEMA))?;
    writeln!(w, "ENDSEC;")?;
    writeln!(w, "DATA;")?;
    for (k, body) in data.bodies.iter().enumerate() {
        for line in wrap(&format!("#{}={body};", k + 1), LINE_WIDTH) {
            writeln!(w, "{line}")?;
        }
    }
    writeln!(w, "ENDSEC;")?;
    writeln!(w, "END-ISO-10303-21;")?;
    Ok(())
}

/// Break one instance into lines of at most `width` characters where possible, only after a
/// `,` outside string literals (Part 21 ignores the line breaks between tokens).
fn wrap(text: &str, width: usize) -> Vec<String> {
    let mut lines = Vec::new();
    let mut line = String::new();
    let mut in_string = false;
    let mut last_break: Option<usize> = None;
    for c in text.chars() {
        line.push(c);
        if c == '\'' {
            in_string = !in_string;
        } else if c == ',' && !in_string {
            last_break = Some(line.len());
        }
        if line.len() > width {
            if let Some(b) = last_break {
                let rest = line.split_off(b);
                lines.push(std::mem::take(&mut line));
                line = rest;
                last_break = None;
            }
        }
    }
    lines.push(line);
    lines
}

#[cfg(test)]
mod tests {
    use super::super::sample_surface;
    use super::*;
    use nurbs::KnotVector;

    fn write(s: &NurbsSurface, units: Units) -> String {
        let mut meta = StepMeta::new(units, "test.stp", "2024-01-02T03:04:05");
        meta.author = "A. O'Author".into();
        let mut out = Vec::new();
        write_step(&mut out, s, &meta).expect("writes to memory");
        String::from_utf8(out).expect("STEP is ASCII")
    }

    /// The instances `#k=...;` joined across line breaks, by number.
    fn instances(text: &str) -> Vec<(usize, String)> {
        let data = text.split("DATA;\n").nth(1).expect("DATA section").split("ENDSEC;").next().expect("ends");
        let mut out = Vec::new();
        let mut cur = String::new();
        for line in data.lines() {
            cur.push_str(line);
            if cur.ends_with(';') {
                let (id, body) = cur.split_once('=').expect("#k=body");
                out.push((id[1..].parse().expect("instance number"), body.trim_end_matches(';').to_string()));
                cur.clear();
            }
        }
        assert!(cur.is_empty(), "unterminated instance {cur}");
        out
    }

    /// The comma-separated reals inside the first `(...)` group after `key(` in `body`, with
    /// nested parentheses flattened.
    fn numbers_after(body: &str, key: &str) -> Vec<f64> {
        let start = body.find(key).unwrap_or_else(|| panic!("{key} in {body}")) + key.len();
        let mut depth = 1;
        let mut end = start;
        for (k, c) in body[start..].char_indices() {
            match c {
                '(' => depth += 1,
                ')' => {
                    depth -= 1;
                    if depth == 0 {
                        end = start + k;
                        break;
                    }
                }
                _ => {}
            }
        }
        body[start..end]
            .split([',', '(', ')'])
            .filter(|t| !t.is_empty() && !t.starts_with('#') && !t.starts_with('.'))
            .map(|t| t.parse().unwrap_or_else(|_| panic!("not a number: {t:?}")))
            .collect()
    }

    #[test]
    fn header_and_structure() {
        let text = write(&sample_surface(true, true), Units::Metre);
        assert!(text.starts_with("ISO-10303-21;\nHEADER;\n"));
        assert!(text.ends_with("ENDSEC;\nEND-ISO-10303-21;\n"));
        assert!(text.contains("FILE_SCHEMA(('AUTOMOTIVE_DESIGN { 1 0 10303 214 1 1 1 1 }'));"));
        assert!(text.contains("'2024-01-02T03:04:05'"));
        assert!(text.contains("('A. O''Author')"), "quote doubled");
        let inst = instances(&text);
        // Numbered 1..n without gaps, and every reference points at an instance.
        for (k, (id, _)) in inst.iter().enumerate() {
            assert_eq!(*id, k + 1);
        }
        for (_, body) in &inst {
            for r in body.split('#').skip(1) {
                let n: usize = r.chars().take_while(char::is_ascii_digit).collect::<String>().parse().expect("ref");
                assert!((1..=inst.len()).contains(&n), "dangling #{n} in {body}");
            }
        }
        let count = |name: &str| inst.iter().filter(|(_, b)| b.starts_with(name)).count();
        for name in [
            "APPLICATION_CONTEXT(",
            "PRODUCT(",
            "PRODUCT_DEFINITION_FORMATION(",
            "PRODUCT_DEFINITION(",
            "PRODUCT_DEFINITION_SHAPE(",
            "SHAPE_DEFINITION_REPRESENTATION(",
            "MANIFOLD_SURFACE_SHAPE_REPRESENTATION(",
            "SHELL_BASED_SURFACE_MODEL(",
            "OPEN_SHELL(",
            "ADVANCED_FACE(",
            "EDGE_LOOP(",
        ] {
            assert_eq!(count(name), 1, "{name}");
        }
        assert_eq!(count("EDGE_CURVE("), 4);
        assert_eq!(count("VERTEX_POINT("), 4);
        // Lines are wrapped between parameters.
        let data = text.split("DATA;\n").nth(1).expect("data");
        assert!(data.lines().all(|l| l.len() <= LINE_WIDTH + MAX_TOKEN), "a line is too long");
        assert!(data.lines().count() > inst.len(), "the control net needs wrapped lines");
    }

    /// Longest token that can overhang a wrapped line (a real of at most 24 characters and
    /// its delimiters).
    const MAX_TOKEN: usize = 30;

    #[test]
    fn rational_surface_is_a_complex_instance_that_parses_back() {
        let s = sample_surface(true, true);
        let text = write(&s, Units::Metre);
        let inst = instances(&text);
        let (_, surf) = inst.iter().find(|(_, b)| b.contains("RATIONAL_B_SPLINE_SURFACE")).expect("surface");
        // Partial entities in alphabetical order (ISO 10303-21 11.2.5.3).
        // The identifiers at depth 1 (inside the outer parentheses, outside any string).
        let mut names: Vec<String> = Vec::new();
        let (mut depth, mut in_string, mut ident) = (0, false, String::new());
        for c in surf.chars() {
            match c {
                '\'' => in_string = !in_string,
                _ if in_string => {}
                '(' => {
                    if depth == 1 && !ident.is_empty() {
                        names.push(std::mem::take(&mut ident));
                    }
                    depth += 1;
                }
                ')' => depth -= 1,
                'A'..='Z' | '_' if depth == 1 => ident.push(c),
                _ => ident.clear(),
            }
        }
        let mut sorted = names.clone();
        sorted.sort();
        assert_eq!(names, sorted);
        assert_eq!(names.len(), 7, "{names:?}");
        // Knots: distinct values with multiplicities, exactly.
        let k = numbers_after(surf, "B_SPLINE_SURFACE_WITH_KNOTS(");
        assert_eq!(k, [4.0, 2.0, 4.0, 3.0, 1.0, 3.0, 0.0, 0.3, 1.0, -1.0, 0.25, 2.0]);
        // Weights: outer list along u.
        let w = numbers_after(surf, "RATIONAL_B_SPLINE_SURFACE(");
        assert_eq!(w, s.weights());
        // Control points: follow the references, outer list along u.
        let net_start = surf.find("B_SPLINE_SURFACE(").expect("net") + "B_SPLINE_SURFACE(".len();
        let refs: Vec<usize> = surf[net_start..]
            .split(".UNSPECIFIED.")
            .next()
            .expect("net")
            .split('#')
            .skip(1)
            .map(|r| r.chars().take_while(char::is_ascii_digit).collect::<String>().parse().expect("ref"))
            .collect();
        assert_eq!(refs.len(), s.n_u() * s.n_v());
        for (k, r) in refs.iter().enumerate() {
            let xyz = numbers_after(&inst[r - 1].1, "CARTESIAN_POINT('',");
            let c = s.control_point(k / s.n_v(), k % s.n_v());
            assert_eq!(xyz, [c.x, c.y, c.z], "P({}, {})", k / s.n_v(), k % s.n_v());
        }
    }

    #[test]
    fn polynomial_surface_is_plain() {
        let text = write(&sample_surface(true, false), Units::Metre);
        assert!(!text.contains("RATIONAL_B_SPLINE_SURFACE"));
        assert_eq!(text.matches("B_SPLINE_SURFACE_WITH_KNOTS('hull',3,2,((").count(), 1);
    }

    #[test]
    fn units_and_uncertainty() {
        let s = sample_surface(true, true);
        let m = write(&s, Units::Metre);
        assert!(m.contains("SI_UNIT($,.METRE.)") && !m.contains("CONVERSION_BASED_UNIT"));
        assert!(write(&s, Units::Millimetre).contains("SI_UNIT(.MILLI.,.METRE.)"));
        let ft = write(&s, Units::Foot);
        assert!(ft.contains("CONVERSION_BASED_UNIT('FOOT',") && ft.contains("LENGTH_MEASURE(0.3048)"));
        let inch = write(&s, Units::Inch);
        assert!(inch.contains("CONVERSION_BASED_UNIT('INCH',") && inch.contains("LENGTH_MEASURE(0.0254)"));
        // Resolution: a power of ten within a factor 10 below 1e-7 times the net's diagonal.
        let (lo, hi) = s.control_bounds();
        let size = (hi - lo).norm();
        let inst = instances(&m);
        let (_, u) = inst.iter().find(|(_, b)| b.starts_with("UNCERTAINTY_MEASURE_WITH_UNIT")).expect("uncertainty");
        let r = numbers_after(u, "LENGTH_MEASURE(")[0];
        crate::export::assert_resolution(r, size);
    }

    #[test]
    fn a_collapsed_boundary_has_no_edge() {
        // The v = v1 row collapses to one point (a pointed stem): three edges, three vertices.
        let ku = KnotVector::uniform(2, 4).expect("valid");
        let kv = KnotVector::uniform(1, 3).expect("valid");
        let mut pts = Vec::new();
        for i in 0..4 {
            for j in 0..3 {
                let t = 1.0 - j as f64 / 2.0;
                pts.push(Vec3::new(j as f64, t * i as f64, t * (i * i) as f64 * 0.3));
            }
        }
        let s = NurbsSurface::try_new(ku, kv, &pts, None).expect("valid");
        let text = write(&s, Units::Metre);
        let inst = instances(&text);
        let count = |name: &str| inst.iter().filter(|(_, b)| b.starts_with(name)).count();
        assert_eq!(count("EDGE_CURVE("), 3);
        assert_eq!(count("VERTEX_POINT("), 3);
    }

    #[test]
    fn strings_and_timestamps() {
        assert_eq!(step_string("a'b\\c"), "'a''b\\\\c'");
        assert_eq!(step_string("Åsa"), "'\\X2\\00C5\\X0\\sa'");
        assert_eq!(step_string("𝄞"), "'\\X2\\D834DD1E\\X0\\'");
        assert_eq!(step_timestamp(0), "1970-01-01T00:00:00");
        assert_eq!(step_timestamp(1_000_000_000), "2001-09-09T01:46:40");
        assert_eq!(step_timestamp(951_868_799), "2000-02-29T23:59:59");
    }

    #[test]
    fn deterministic() {
        let s = sample_surface(true, true);
        assert_eq!(write(&s, Units::Foot), write(&s, Units::Foot));
    }

    #[test]
    fn multiplicities_sum_to_the_knot_count() {
        let k = KnotVector::try_new(3, vec![0.0, 0.0, 0.0, 0.0, 0.5, 0.5, 0.7, 1.0, 1.0, 1.0, 1.0]).expect("valid");
        let (m, v) = knots_with_multiplicities(&k);
        assert_eq!(m, [4, 2, 1, 4]);
        assert_eq!(v, [0.0, 0.5, 0.7, 1.0]);
        assert_eq!(m.iter().sum::<usize>(), k.as_slice().len());
    }
}
