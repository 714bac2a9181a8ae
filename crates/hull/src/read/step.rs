//! STEP reader (ISO 10303-21 clear-text exchange files) of B-spline surfaces, the inverse of
//! [`crate::export::write_step`] and a reader of what CAD systems write (AP203, AP214, AP242).
//!
//! The rest of this module's documentation is on [`parse_step`], where the library's users read it.

use nurbs::Vec3;

use super::cad::{cad_error, output_scale, CadFormat, CadSurface, CadSurfaces, FileUnit, RawSurface, Skipped};
use crate::error::HullError;
use crate::limits::{self, LimitExceeded, MAX_CAD_FILE_BYTES, MAX_CONTROL_POINTS, MAX_STEP_INSTANCES};
use crate::units::Units;

/// Parameters of one instance: the poles' references and the weights of the largest surface,
/// and its knots.
const MAX_INSTANCE_PARAMS: usize = 2 * MAX_CONTROL_POINTS + 1_000_000;
/// Nesting of lists and typed parameters: a surface needs 3 (`((w))`).
const MAX_DEPTH: usize = 32;
/// Length of a chain of unit references (`CONVERSION_BASED_UNIT` of a measure of another unit).
const MAX_UNIT_CHAIN: usize = 16;

/// Geometry that is not read, by entity name (ISO 10303-42), counted in the notes.
const OTHER_GEOMETRY: &[&str] = &[
    "B_SPLINE_CURVE_WITH_KNOTS",
    "RATIONAL_B_SPLINE_CURVE",
    "BEZIER_CURVE",
    "UNIFORM_CURVE",
    "QUASI_UNIFORM_CURVE",
    "LINE",
    "CIRCLE",
    "ELLIPSE",
    "PARABOLA",
    "HYPERBOLA",
    "POLYLINE",
    "TRIMMED_CURVE",
    "COMPOSITE_CURVE",
    "OFFSET_CURVE_3D",
    "PCURVE",
    "SURFACE_CURVE",
    "SEAM_CURVE",
    "INTERSECTION_CURVE",
    "PLANE",
    "CYLINDRICAL_SURFACE",
    "CONICAL_SURFACE",
    "SPHERICAL_SURFACE",
    "TOROIDAL_SURFACE",
    "DEGENERATE_TOROIDAL_SURFACE",
    "SURFACE_OF_REVOLUTION",
    "SURFACE_OF_LINEAR_EXTRUSION",
    "OFFSET_SURFACE",
    "RECTANGULAR_TRIMMED_SURFACE",
    "CURVE_BOUNDED_SURFACE",
    "RECTANGULAR_COMPOSITE_SURFACE",
    "BEZIER_SURFACE",
    "UNIFORM_SURFACE",
    "QUASI_UNIFORM_SURFACE",
];

/// One instance of the DATA section: its name `#id`, where its body lies, its first line.
#[derive(Clone, Copy)]
struct Instance {
    id: u64,
    start: u32,
    end: u32,
    line: u32,
}

/// A parameter (ISO 10303-21 section 12.2).
#[derive(Clone, Debug, PartialEq)]
enum Param {
    Ref(u64),
    Number(f64),
    Str(String),
    Enum(String),
    List(Vec<Param>),
    /// A typed parameter `LENGTH_MEASURE(1.0)`.
    Typed(String, Box<Param>),
    /// `$`, `*`, or a binary.
    Other,
}

/// A parsed instance: its partial entities `(name, parameters)`, one for a simple instance.
struct Entity {
    parts: Vec<(String, Vec<Param>)>,
    complex: bool,
}

impl Entity {
    fn part(&self, name: &str) -> Option<&[Param]> {
        self.parts.iter().find(|(n, _)| n == name).map(|(_, p)| p.as_slice())
    }
}

/// Reads the B-spline surfaces of a STEP file (see "What is read" below), converted to `target`, or in
/// the file's unit when `None`.
///
/// # What is read
///
/// * **Exchange structure** (ISO 10303-21:2002 sections 5-8): `ISO-10303-21;`, a `HEADER`
///   section (skipped), a `DATA` section of entity instances `#n = ...;` ended by `ENDSEC;`,
///   and `END-ISO-10303-21;`. Tokens may be separated by blanks, line breaks and comments
///   `/* ... */` (section 5.6) anywhere, so an instance may span many lines. Strings are
///   `'...'` with `''` for a quote (7.3.3; the `\X2\` encodings are left as written, they only
///   name things here). An instance is simple, `NAME(params)` (11.2.2), or complex,
///   `(A(params) B(params) ...)`, one partial entity per supertype (11.2.5).
/// * **Surfaces** (ISO 10303-42 section 4.4.41-4.4.43): the simple
///   `B_SPLINE_SURFACE_WITH_KNOTS(name, p, q, ((#P00, #P01, ..), ..), form, u_closed, v_closed,
///   self_intersect, (mult_u), (mult_v), (knots_u), (knots_v), knot_spec)`, and the complex
///   rational instance with the partials `B_SPLINE_SURFACE(p, q, net, form, u_closed, v_closed,
///   self_intersect)`, `B_SPLINE_SURFACE_WITH_KNOTS(mult_u, mult_v, knots_u, knots_v, spec)`,
///   `RATIONAL_B_SPLINE_SURFACE(((w00, w01, ..), ..))` and `REPRESENTATION_ITEM(name)`. The
///   outer list of the net and of the weights runs along u, the inner along v: the kernel's
///   u-major order. Each pole is a `CARTESIAN_POINT(name, (x, y, z))`. The knots are the
///   distinct values with their multiplicities, expanded to the full knot vector.
/// * **Length unit** (ISO 10303-41 section 4.2): the `GLOBAL_UNIT_ASSIGNED_CONTEXT` of the
///   representation contexts, whose length unit is `(LENGTH_UNIT() NAMED_UNIT(*)
///   SI_UNIT(prefix, .METRE.))` (prefix `$` or `.MILLI.`, `.CENTI.`, `.KILO.`, ...) or a
///   `CONVERSION_BASED_UNIT('INCH', #m)` with `#m = LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(f),
///   #u)`, `f` units `#u` (followed to its end, cycles refused). Every context must agree (a file
///   with two length units is refused); a file without one is read in millimetres, with a note,
///   as Open CASCADE does.
///
/// Other geometry (curves, analytic and trimmed surfaces) is counted by entity name in one
/// note, and the bounds of faces (`ADVANCED_FACE`) are noted as ignored: each B-spline surface
/// is returned whole. The reader indexes the instances first (24 bytes each, at most
/// [`crate::limits::MAX_STEP_INSTANCES`]) and parses only those it needs, with a cap on the
/// parameters of one instance and on the nesting of lists.
///
/// # Errors
/// [`crate::InputErrorKind::Cad`] at the line and instance that break the format, reference a
/// missing or wrong instance, or hold a surface the kernel refuses; [`HullError::Limit`] for
/// a file or counts above the documented caps.
pub fn parse_step(bytes: &[u8], source: &str, target: Option<Units>) -> Result<CadSurfaces, HullError> {
    if bytes.len() as u64 > MAX_CAD_FILE_BYTES {
        let cap = MAX_CAD_FILE_BYTES;
        return Err(LimitExceeded::new(source, "bytes", bytes.len() as u64, cap, "a STEP file of at most 1 GiB").into());
    }
    let file = StepFile { bytes, source, instances: index(bytes, source)? };
    let mut notes = Vec::new();
    let unit = file.length_unit(&mut notes)?;
    let (scale, units) = output_scale(&unit, target, &mut notes);
    let mut surfaces = Vec::new();
    let mut skipped = Skipped::default();
    let mut faces = 0;
    for inst in &file.instances {
        let Some(first) = file.keyword(inst) else { continue };
        if first == "ADVANCED_FACE" {
            faces += 1;
            continue;
        }
        let interesting = first.is_empty() || first == "B_SPLINE_SURFACE_WITH_KNOTS" || OTHER_GEOMETRY.contains(&first);
        if !interesting {
            continue;
        }
        let entity = file.parse(inst)?;
        if entity.part("B_SPLINE_SURFACE_WITH_KNOTS").is_some() {
            let (raw, name) = file.surface(inst, &entity)?;
            let label = format!("#{}", inst.id);
            let surface =
                raw.build(scale, source, inst.line as usize, &format!("{label} B_SPLINE_SURFACE_WITH_KNOTS"))?;
            let name = if name.is_empty() { label } else { format!("{label} '{name}'") };
            surfaces.push(CadSurface { surface, name });
        } else if let Some(kind) = other_geometry(&entity) {
            skipped.add(kind.to_string());
        }
    }
    if faces > 0 {
        let s = if faces == 1 { "" } else { "s" };
        notes.push(format!("the bounds of {faces} face{s} (ADVANCED_FACE) ignored: each surface is returned whole"));
    }
    if let Some(n) = skipped.note(|n, k| format!("{n} {k}"), |n, k| format!("{n} {k}")) {
        notes.push(format!("{n} (geometry other than B-spline surfaces)"));
    }
    Ok(CadSurfaces { format: CadFormat::Step, surfaces, units, notes })
}

/// The geometry entity name a skipped instance is counted under.
fn other_geometry(e: &Entity) -> Option<&str> {
    if e.complex && e.part("RATIONAL_B_SPLINE_CURVE").is_some() {
        return Some("RATIONAL_B_SPLINE_CURVE");
    }
    e.parts.iter().map(|(n, _)| n.as_str()).find(|n| OTHER_GEOMETRY.contains(n))
}

fn is_keyword_byte(b: u8) -> bool {
    b.is_ascii_alphanumeric() || b == b'_' || b == b'-' || b == b'!'
}

/// Blanks and comments skipped from `pos`; `Err(start)` for a comment never closed.
fn skip_blank(bytes: &[u8], mut pos: usize) -> Result<usize, usize> {
    loop {
        while pos < bytes.len() && bytes[pos].is_ascii_whitespace() {
            pos += 1;
        }
        if bytes[pos..].starts_with(b"/*") {
            match bytes[pos + 2..].windows(2).position(|w| w == b"*/") {
                Some(k) => pos += k + 4,
                None => return Err(pos),
            }
        } else {
            return Ok(pos);
        }
    }
}

fn line_of(bytes: &[u8], offset: usize) -> usize {
    1 + bytes[..offset.min(bytes.len())].iter().filter(|&&b| b == b'\n').count()
}

/// Indexes the DATA section's instances, sorted by name; checks the exchange structure.
fn index(bytes: &[u8], source: &str) -> Result<Vec<Instance>, HullError> {
    let err = |line: usize, found: String, expected: &str| cad_error(source, Some(line), "file", found, expected);
    let mut out: Vec<Instance> = Vec::new();
    let (mut pos, mut line) = (0usize, 1usize);
    let (mut in_data, mut ended) = (false, false);
    let mut first = true;
    while !ended {
        // Start of the next statement, counting lines on the way.
        let start = skip_blank(bytes, pos).map_err(|at| {
            err(line_of(bytes, at), "a comment never closed".into(), "*/ to end the comment: is the file truncated?")
        })?;
        line += bytes[pos..start].iter().filter(|&&b| b == b'\n').count();
        if start >= bytes.len() {
            return Err(err(
                line,
                "the end of the file without END-ISO-10303-21;".into(),
                "the DATA section ended by ENDSEC; and END-ISO-10303-21;: is the file truncated?",
            ));
        }
        // Its end: the first `;` outside strings and comments.
        let mut k = start;
        let mut stmt_lines = 0;
        let end = loop {
            match bytes.get(k) {
                None => {
                    return Err(err(
                        line,
                        "a statement that the file ends inside".into(),
                        "every entity instance ended by ;: is the file truncated?",
                    ))
                }
                Some(b';') => break k,
                Some(b'\'') => {
                    let close = bytes[k + 1..].iter().position(|&b| b == b'\'').ok_or_else(|| {
                        err(
                            line_of(bytes, k),
                            "a string never closed".into(),
                            "' to end the string: is the file truncated?",
                        )
                    })?;
                    stmt_lines += bytes[k..k + 1 + close].iter().filter(|&&b| b == b'\n').count();
                    k += close + 2; // a doubled '' is a closed string and an open one
                }
                Some(b'/') if bytes.get(k + 1) == Some(&b'*') => {
                    let close = skip_blank(bytes, k).map_err(|at| {
                        err(line_of(bytes, at), "a comment never closed".into(), "*/ to end the comment")
                    })?;
                    stmt_lines += bytes[k..close].iter().filter(|&&b| b == b'\n').count();
                    k = close;
                }
                Some(&b) => {
                    stmt_lines += usize::from(b == b'\n');
                    k += 1;
                }
            }
        };
        let text = &bytes[start..end];
        let word_len = text.iter().take_while(|&&b| is_keyword_byte(b)).count();
        let word = &text[..word_len];
        if first && text != b"ISO-10303-21" {
            return Err(err(line, "no ISO-10303-21; at the start".into(), "a STEP file starting with ISO-10303-21;"));
        }
        first = false;
        if text.first() == Some(&b'#') {
            if !in_data {
                return Err(err(line, "an entity instance outside the DATA section".into(), "instances after DATA;"));
            }
            let digits = text[1..].iter().take_while(|b| b.is_ascii_digit()).count();
            let id = std::str::from_utf8(&text[1..1 + digits]).ok().and_then(|s| s.parse::<u64>().ok());
            let eq = skip_blank(bytes, start + 1 + digits).unwrap_or(end);
            let (Some(id), Some(b'=')) = (id, bytes.get(eq).filter(|_| eq < end)) else {
                let shown = String::from_utf8_lossy(&text[..text.len().min(40)]).into_owned();
                return Err(err(line, format!("\"{shown}\""), "an entity instance #n = ...;"));
            };
            if out.len() >= MAX_STEP_INSTANCES {
                let cap = MAX_STEP_INSTANCES as u64;
                return Err(LimitExceeded::new(
                    source,
                    "entity instances",
                    cap + 1,
                    cap,
                    "at most 10,000,000 instances",
                )
                .into());
            }
            out.push(Instance { id, start: (eq + 1) as u32, end: end as u32, line: line as u32 });
        } else if word == b"DATA" {
            in_data = true;
        } else if word == b"ENDSEC" {
            in_data = false;
        } else if word == b"END-ISO-10303-21" {
            ended = true;
        }
        line += stmt_lines;
        pos = end + 1;
    }
    out.sort_by_key(|i| i.id);
    if let Some(w) = out.windows(2).find(|w| w[0].id == w[1].id) {
        return Err(err(
            w[1].line.max(w[0].line) as usize,
            format!("#{} defined twice (lines {} and {})", w[0].id, w[0].line.min(w[1].line), w[0].line.max(w[1].line)),
            "each instance name once",
        ));
    }
    Ok(out)
}

/// The indexed file.
struct StepFile<'a> {
    bytes: &'a [u8],
    source: &'a str,
    instances: Vec<Instance>,
}

/// A cursor over one instance's body.
struct Cursor<'a> {
    bytes: &'a [u8],
    pos: usize,
    end: usize,
    params: usize,
}

impl<'a> StepFile<'a> {
    fn get(&self, id: u64) -> Option<&Instance> {
        self.instances.binary_search_by_key(&id, |i| i.id).ok().map(|k| &self.instances[k])
    }

    fn error(&self, inst: &Instance, what: &str, found: String, expected: &str) -> HullError {
        cad_error(self.source, Some(inst.line as usize), &format!("#{} {what}", inst.id), found, expected)
    }

    /// The first keyword of the body: the entity name of a simple instance, `""` for a complex
    /// one; `None` when the body starts with neither.
    fn keyword(&self, inst: &Instance) -> Option<&'a str> {
        let pos = skip_blank(&self.bytes[..inst.end as usize], inst.start as usize).ok()?;
        let rest = &self.bytes[pos..inst.end as usize];
        if rest.first() == Some(&b'(') {
            return Some("");
        }
        let n = rest.iter().take_while(|&&b| is_keyword_byte(b)).count();
        std::str::from_utf8(&rest[..n]).ok()
    }

    /// The instance parsed.
    fn parse(&self, inst: &Instance) -> Result<Entity, HullError> {
        let mut c = Cursor { bytes: self.bytes, pos: inst.start as usize, end: inst.end as usize, params: 0 };
        let fail = |c: &Cursor, found: String, expected: &str| {
            let line = inst.line as usize
                + self.bytes[inst.start as usize..c.pos.min(c.end)].iter().filter(|&&b| b == b'\n').count();
            cad_error(self.source, Some(line), &format!("#{}", inst.id), found, expected)
        };
        let mut parts = Vec::new();
        c.blank().map_err(|_| fail(&c, "a comment never closed".into(), "*/"))?;
        let complex = c.peek() == Some(b'(');
        if complex {
            c.pos += 1;
            loop {
                c.blank().map_err(|_| fail(&c, "a comment never closed".into(), "*/"))?;
                if c.peek() == Some(b')') {
                    c.pos += 1;
                    break;
                }
                parts.push(c.record().map_err(|(f, e)| fail(&c, f, e))?);
            }
        } else {
            parts.push(c.record().map_err(|(f, e)| fail(&c, f, e))?);
        }
        c.blank().map_err(|_| fail(&c, "a comment never closed".into(), "*/"))?;
        if c.pos != c.end || parts.is_empty() {
            return Err(fail(&c, format!("\"{}\" after the entity", c.shown()), "; after the last parameter list"));
        }
        Ok(Entity { parts, complex })
    }

    /// The instance `#id`, parsed, referenced from `from` as `what`.
    fn resolve(&self, id: u64, from: &Instance, what: &str) -> Result<(&Instance, Entity), HullError> {
        let inst = self.get(id).ok_or_else(|| {
            self.error(
                from,
                what,
                format!("the reference #{id} names no instance"),
                "a reference to an instance of the DATA section",
            )
        })?;
        Ok((inst, self.parse(inst)?))
    }

    /// The surface of a `B_SPLINE_SURFACE_WITH_KNOTS` instance (simple or complex) and its name.
    fn surface(&self, inst: &Instance, e: &Entity) -> Result<(RawSurface, String), HullError> {
        let what = "B_SPLINE_SURFACE_WITH_KNOTS";
        let bad = |found: String, expected: &str| self.error(inst, what, found, expected);
        let knots_part = e.part("B_SPLINE_SURFACE_WITH_KNOTS").unwrap_or(&[]);
        // (name, degrees, net, form..) and (multiplicities, knots, spec) by the form.
        let (name, surf, knots): (String, &[Param], &[Param]) = if e.complex {
            let surf = e.part("B_SPLINE_SURFACE").ok_or_else(|| {
                bad(
                    "a complex instance without B_SPLINE_SURFACE".into(),
                    "the partial B_SPLINE_SURFACE(p, q, net, ...)",
                )
            })?;
            let name = match e.part("REPRESENTATION_ITEM") {
                Some([Param::Str(s)]) => s.clone(),
                _ => String::new(),
            };
            (name, surf, knots_part)
        } else {
            if knots_part.len() != 13 {
                return Err(bad(format!("{} parameters", knots_part.len()), "13 parameters (name, p, q, net, form, u_closed, v_closed, self_intersect, mult_u, mult_v, knots_u, knots_v, spec)"));
            }
            let name = match &knots_part[0] {
                Param::Str(s) => s.clone(),
                _ => String::new(),
            };
            (name, &knots_part[1..8], &knots_part[8..])
        };
        if surf.len() != 7 || knots.len() != 5 {
            return Err(bad(
                format!("{} and {} parameters", surf.len(), knots.len()),
                "B_SPLINE_SURFACE(p, q, net, form, u_closed, v_closed, self_intersect) and B_SPLINE_SURFACE_WITH_KNOTS(mult_u, mult_v, knots_u, knots_v, spec)",
            ));
        }
        let degree = |p: &Param, dir: &str| match p {
            Param::Number(d) if d.fract() == 0.0 && (1.0..=nurbs::MAX_DEGREE as f64).contains(d) => Ok(*d as usize),
            other => Err(bad(format!("the {dir} degree {}", shown(other)), "an integer degree from 1 to 15")),
        };
        let (p, q) = (degree(&surf[0], "u")?, degree(&surf[1], "v")?);
        let rows = match &surf[2] {
            Param::List(rows) if !rows.is_empty() => rows,
            other => {
                return Err(bad(
                    format!("the control net {}", shown(other)),
                    "a list of rows of control point references",
                ))
            }
        };
        let nu = rows.len();
        let nv = match &rows[0] {
            Param::List(r) => r.len(),
            _ => 0,
        };
        let at = format!("{}:{}: #{} {what}", self.source, inst.line, inst.id);
        limits::control_points(&at, nu, nv).map_err(HullError::from)?;
        let mut points = Vec::with_capacity(nu * nv);
        for (i, row) in rows.iter().enumerate() {
            let row = match row {
                Param::List(r) if r.len() == nv => r,
                other => {
                    return Err(bad(
                        format!("row {} of the control net is {}", i + 1, shown(other)),
                        &format!("{nv} references in every row, as in the first"),
                    ))
                }
            };
            for (j, p) in row.iter().enumerate() {
                let Param::Ref(id) = p else {
                    return Err(bad(
                        format!("control point ({i}, {j}) is {}", shown(p)),
                        "a reference #n to a CARTESIAN_POINT",
                    ));
                };
                points.push(self.point(*id, inst, i, j)?);
            }
        }
        let ku = expand(&knots[0], &knots[2], nu, p).map_err(|f| {
            bad(
                format!("the u knots: {f}"),
                &format!("multiplicities and knots of equal length, the multiplicities summing to {}", nu + p + 1),
            )
        })?;
        let kv = expand(&knots[1], &knots[3], nv, q).map_err(|f| {
            bad(
                format!("the v knots: {f}"),
                &format!("multiplicities and knots of equal length, the multiplicities summing to {}", nv + q + 1),
            )
        })?;
        let weights = match e.part("RATIONAL_B_SPLINE_SURFACE") {
            None => vec![1.0; nu * nv],
            Some([Param::List(w)]) if w.len() == nu => {
                let mut out = Vec::with_capacity(nu * nv);
                for (i, row) in w.iter().enumerate() {
                    match row {
                        Param::List(r) if r.len() == nv => {
                            for (j, x) in r.iter().enumerate() {
                                match x {
                                    Param::Number(x) => out.push(*x),
                                    other => {
                                        return Err(bad(
                                            format!("the weight ({i}, {j}) is {}", shown(other)),
                                            "a real weight",
                                        ))
                                    }
                                }
                            }
                        }
                        other => {
                            return Err(bad(
                                format!("row {} of the weights is {}", i + 1, shown(other)),
                                &format!("{nv} weights per row"),
                            ))
                        }
                    }
                }
                out
            }
            Some(other) => {
                let found = other.first().map_or("nothing".to_string(), shown);
                return Err(bad(
                    format!("the weights {found}"),
                    &format!("{nu} rows of {nv} weights, as the control net"),
                ));
            }
        };
        Ok((RawSurface { degree: (p, q), knots: (ku, kv), points, weights }, name))
    }

    /// The pole `(i, j)`: the `CARTESIAN_POINT` `#id`.
    fn point(&self, id: u64, from: &Instance, i: usize, j: usize) -> Result<Vec3, HullError> {
        let (inst, e) = self.resolve(id, from, &format!("B_SPLINE_SURFACE_WITH_KNOTS, control point ({i}, {j})"))?;
        match (e.complex, e.parts[0].0.as_str(), e.parts[0].1.as_slice()) {
            (false, "CARTESIAN_POINT", [_, Param::List(c)]) => match c.as_slice() {
                [Param::Number(x), Param::Number(y), Param::Number(z)] => Ok(Vec3::new(*x, *y, *z)),
                _ => Err(self.error(
                    inst,
                    "CARTESIAN_POINT",
                    format!("coordinates {}", shown(&Param::List(c.clone()))),
                    "three real coordinates (x, y, z)",
                )),
            },
            (_, name, _) => Err(self.error(
                from,
                "B_SPLINE_SURFACE_WITH_KNOTS",
                format!(
                    "control point ({i}, {j}) #{id} is {}",
                    if name.is_empty() { "a complex instance" } else { name }
                ),
                "a CARTESIAN_POINT(name, (x, y, z))",
            )),
        }
    }

    /// The one length unit of the file's contexts.
    fn length_unit(&self, notes: &mut Vec<String>) -> Result<FileUnit, HullError> {
        let mut found: Option<(FileUnit, u64)> = None;
        for inst in &self.instances {
            // Contexts are complex instances, or simple ones named for the unit context.
            match self.keyword(inst) {
                Some("") | Some("GLOBAL_UNIT_ASSIGNED_CONTEXT") => {}
                _ => continue,
            }
            let e = self.parse(inst)?;
            let Some(params) = e.part("GLOBAL_UNIT_ASSIGNED_CONTEXT") else { continue };
            let units = match params.last() {
                Some(Param::List(u)) => u,
                _ => {
                    return Err(self.error(
                        inst,
                        "GLOBAL_UNIT_ASSIGNED_CONTEXT",
                        "no list of units".into(),
                        "(#length, #angle, ...)",
                    ))
                }
            };
            for u in units {
                let Param::Ref(id) = u else { continue };
                let mut chain = vec![inst.id];
                if let Some(unit) = self.unit_metres(*id, inst, &mut chain)? {
                    match &found {
                        Some((f, at)) if (f.metres / unit.metres - 1.0).abs() > 1e-12 => {
                            return Err(self.error(
                                inst,
                                "GLOBAL_UNIT_ASSIGNED_CONTEXT",
                                format!("the length unit {} where #{at} gives {}", unit.name, f.name),
                                "one length unit for the whole file",
                            ))
                        }
                        Some(_) => {}
                        None => found = Some((unit, inst.id)),
                    }
                }
            }
        }
        Ok(match found {
            Some((u, _)) => u,
            None => {
                notes.push("no length unit in the file (GLOBAL_UNIT_ASSIGNED_CONTEXT): millimetres assumed".into());
                FileUnit { metres: 1e-3, name: "millimetre (assumed)".into() }
            }
        })
    }

    /// Metres per unit of the unit `#id` when it is a length unit, `None` for other units.
    fn unit_metres(&self, id: u64, from: &Instance, chain: &mut Vec<u64>) -> Result<Option<FileUnit>, HullError> {
        if chain.contains(&id) || chain.len() > MAX_UNIT_CHAIN {
            let path: Vec<String> = chain.iter().chain([&id]).map(|i| format!("#{i}")).collect();
            return Err(self.error(
                from,
                "unit",
                format!("a cycle of unit references {}", path.join(" -> ")),
                "units that end in an SI_UNIT",
            ));
        }
        chain.push(id);
        let (inst, e) = self.resolve(id, from, "unit")?;
        let is_length = e.part("LENGTH_UNIT").is_some() || !e.complex;
        if let Some(si) = e.part("SI_UNIT") {
            // Complex: SI_UNIT(prefix, name); simple: SI_UNIT(dimensions, prefix, name).
            let (prefix, name) = match si {
                [p, n] | [_, p, n] => (p, n),
                _ => {
                    return Err(self.error(
                        inst,
                        "SI_UNIT",
                        format!("{} parameters", si.len()),
                        "SI_UNIT(prefix, name)",
                    ))
                }
            };
            if !is_length || *name != Param::Enum("METRE".into()) {
                return Ok(None);
            }
            let (factor, word) = match prefix {
                Param::Enum(p) => (
                    si_prefix(p).ok_or_else(|| {
                        self.error(inst, "SI_UNIT", format!("the prefix .{p}."), "an SI prefix such as .MILLI.")
                    })?,
                    p.as_str(),
                ),
                _ => (1.0, ""),
            };
            return Ok(Some(FileUnit { metres: factor, name: format!("{word}METRE").to_ascii_lowercase() }));
        }
        let Some(conv) = e.part("CONVERSION_BASED_UNIT") else { return Ok(None) };
        if e.part("LENGTH_UNIT").is_none() {
            return Ok(None);
        }
        let (name, measure) = match conv {
            [Param::Str(n), Param::Ref(m)] => (n.clone(), *m),
            _ => {
                return Err(self.error(
                    inst,
                    "CONVERSION_BASED_UNIT",
                    "parameters other than (name, #measure)".into(),
                    "CONVERSION_BASED_UNIT('INCH', #measure)",
                ))
            }
        };
        let (m_inst, m) = self.resolve(measure, inst, "CONVERSION_BASED_UNIT")?;
        chain.push(measure);
        let mwu = m.part("LENGTH_MEASURE_WITH_UNIT").filter(|p| !p.is_empty()).or(m.part("MEASURE_WITH_UNIT"));
        let (value, unit) = match mwu {
            Some([v, Param::Ref(u)]) => (number_of(v), *u),
            _ => (None, 0),
        };
        let Some(value) = value.filter(|v| v.is_finite() && *v > 0.0) else {
            return Err(self.error(
                m_inst,
                "LENGTH_MEASURE_WITH_UNIT",
                "no positive length and unit".into(),
                "LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(f), #unit)",
            ));
        };
        let Some(base) = self.unit_metres(unit, m_inst, chain)? else {
            return Err(self.error(
                m_inst,
                "LENGTH_MEASURE_WITH_UNIT",
                format!("#{unit} is not a length unit"),
                "a length unit",
            ));
        };
        Ok(Some(FileUnit { metres: value * base.metres, name }))
    }
}

/// The number of `LENGTH_MEASURE(f)` or `f`.
fn number_of(p: &Param) -> Option<f64> {
    match p {
        Param::Number(x) => Some(*x),
        Param::Typed(_, inner) => number_of(inner),
        _ => None,
    }
}

/// The factor of an SI prefix (ISO 10303-41 `si_prefix`).
fn si_prefix(p: &str) -> Option<f64> {
    Some(match p {
        "EXA" => 1e18,
        "PETA" => 1e15,
        "TERA" => 1e12,
        "GIGA" => 1e9,
        "MEGA" => 1e6,
        "KILO" => 1e3,
        "HECTO" => 1e2,
        "DECA" => 1e1,
        "DECI" => 1e-1,
        "CENTI" => 1e-2,
        "MILLI" => 1e-3,
        "MICRO" => 1e-6,
        "NANO" => 1e-9,
        "PICO" => 1e-12,
        "FEMTO" => 1e-15,
        "ATTO" => 1e-18,
        _ => return None,
    })
}

/// The full knot vector of distinct `knots` with `mults`, which must sum to `n + p + 1`.
fn expand(mults: &Param, knots: &Param, n: usize, p: usize) -> Result<Vec<f64>, String> {
    let (Param::List(m), Param::List(k)) = (mults, knots) else {
        return Err(format!("{} and {}", shown(mults), shown(knots)));
    };
    if m.len() != k.len() {
        return Err(format!("{} multiplicities for {} knots", m.len(), k.len()));
    }
    let want = n + p + 1;
    let mut total = 0usize;
    let mut pairs = Vec::with_capacity(m.len());
    for (a, b) in m.iter().zip(k) {
        match (a, b) {
            (Param::Number(a), Param::Number(b)) if a.fract() == 0.0 && *a >= 1.0 && *a <= want as f64 => {
                total += *a as usize;
                pairs.push((*a as usize, *b));
            }
            _ => return Err(format!("the multiplicity {} of the knot {}", shown(a), shown(b))),
        }
        if total > want {
            break;
        }
    }
    if total != want {
        return Err(format!("multiplicities summing to {total}{}", if total > want { " or more" } else { "" }));
    }
    Ok(pairs.into_iter().flat_map(|(m, k)| std::iter::repeat_n(k, m)).collect())
}

/// A parameter as written, short.
fn shown(p: &Param) -> String {
    let s = match p {
        Param::Ref(id) => format!("#{id}"),
        Param::Number(x) => format!("{x}"),
        Param::Str(s) => format!("'{s}'"),
        Param::Enum(e) => format!(".{e}."),
        Param::List(l) => format!("a list of {}", l.len()),
        Param::Typed(n, _) => format!("{n}(..)"),
        Param::Other => "$".into(),
    };
    s.chars().take(60).collect()
}

type Failure = (String, &'static str);

impl Cursor<'_> {
    fn peek(&self) -> Option<u8> {
        (self.pos < self.end).then(|| self.bytes[self.pos])
    }

    fn blank(&mut self) -> Result<(), ()> {
        self.pos = skip_blank(&self.bytes[..self.end], self.pos).map_err(|_| ())?;
        Ok(())
    }

    fn shown(&self) -> String {
        let rest = &self.bytes[self.pos.min(self.end)..self.end];
        String::from_utf8_lossy(&rest[..rest.len().min(30)]).into_owned()
    }

    fn keyword(&mut self) -> Result<String, Failure> {
        let n = self.bytes[self.pos..self.end].iter().take_while(|&&b| is_keyword_byte(b)).count();
        if n == 0 {
            return Err((format!("\"{}\"", self.shown()), "an entity name"));
        }
        let k = String::from_utf8_lossy(&self.bytes[self.pos..self.pos + n]).to_ascii_uppercase();
        self.pos += n;
        Ok(k)
    }

    /// `NAME(params)`.
    fn record(&mut self) -> Result<(String, Vec<Param>), Failure> {
        let name = self.keyword()?;
        self.blank().map_err(|_| ("a comment never closed".to_string(), "*/"))?;
        if self.peek() != Some(b'(') {
            return Err((format!("\"{}\" after {name}", self.shown()), "( and the parameters"));
        }
        self.pos += 1;
        Ok((name, self.list(1)?))
    }

    /// The parameters up to the closing `)`, the `(` consumed.
    fn list(&mut self, depth: usize) -> Result<Vec<Param>, Failure> {
        if depth > MAX_DEPTH {
            return Err((format!("lists nested {depth} deep"), "lists nested at most 32 deep"));
        }
        let mut out = Vec::new();
        loop {
            self.blank().map_err(|_| ("a comment never closed".to_string(), "*/"))?;
            if self.peek() == Some(b')') && out.is_empty() {
                self.pos += 1;
                return Ok(out);
            }
            out.push(self.param(depth)?);
            self.params += 1;
            if self.params > MAX_INSTANCE_PARAMS {
                return Err((
                    format!("more than {MAX_INSTANCE_PARAMS} parameters"),
                    "an instance of at most 9,000,000 parameters",
                ));
            }
            self.blank().map_err(|_| ("a comment never closed".to_string(), "*/"))?;
            match self.peek() {
                Some(b',') => self.pos += 1,
                Some(b')') => {
                    self.pos += 1;
                    return Ok(out);
                }
                _ => return Err((format!("\"{}\"", self.shown()), ", or ) after a parameter")),
            }
        }
    }

    fn param(&mut self, depth: usize) -> Result<Param, Failure> {
        let Some(b) = self.peek() else { return Err(("the end of the instance".into(), "a parameter")) };
        let rest = &self.bytes[self.pos..self.end];
        match b {
            b'(' => {
                self.pos += 1;
                Ok(Param::List(self.list(depth + 1)?))
            }
            b'#' => {
                let n = rest[1..].iter().take_while(|b| b.is_ascii_digit()).count();
                let id = std::str::from_utf8(&rest[1..1 + n]).ok().and_then(|s| s.parse().ok());
                self.pos += 1 + n;
                id.map(Param::Ref).ok_or_else(|| (format!("\"{}\"", self.shown()), "a reference #n"))
            }
            b'\'' => {
                let mut s = Vec::new();
                let mut k = 1;
                loop {
                    match rest.get(k) {
                        Some(b'\'') if rest.get(k + 1) == Some(&b'\'') => {
                            s.push(b'\'');
                            k += 2;
                        }
                        Some(b'\'') => break,
                        Some(&c) => {
                            s.push(c);
                            k += 1;
                        }
                        None => return Err(("a string never closed".into(), "' to end the string")),
                    }
                }
                self.pos += k + 1;
                Ok(Param::Str(String::from_utf8_lossy(&s).into_owned()))
            }
            b'.' if rest.get(1).is_some_and(|c| c.is_ascii_alphabetic() || *c == b'_') => {
                let n = rest[1..].iter().take_while(|&&c| c.is_ascii_alphanumeric() || c == b'_').count();
                if rest.get(1 + n) != Some(&b'.') {
                    return Err((format!("\"{}\"", self.shown()), "an enumeration .NAME."));
                }
                self.pos += n + 2;
                Ok(Param::Enum(String::from_utf8_lossy(&rest[1..1 + n]).to_ascii_uppercase()))
            }
            b'$' | b'*' => {
                self.pos += 1;
                Ok(Param::Other)
            }
            b'"' => {
                let n = rest[1..]
                    .iter()
                    .position(|&c| c == b'"')
                    .ok_or(("a binary never closed".to_string(), "\" to end it"))?;
                self.pos += n + 2;
                Ok(Param::Other)
            }
            b'0'..=b'9' | b'+' | b'-' | b'.' => {
                let n = rest
                    .iter()
                    .take_while(|c| c.is_ascii_digit() || matches!(c, b'+' | b'-' | b'.' | b'E' | b'e'))
                    .count();
                let text = String::from_utf8_lossy(&rest[..n]).into_owned();
                self.pos += n;
                match text.parse::<f64>() {
                    Ok(x) if x.is_finite() => Ok(Param::Number(x)),
                    _ => Err((format!("\"{text}\" is not a finite number"), "a number")),
                }
            }
            _ if is_keyword_byte(b) => {
                let (name, mut inner) = self.record()?;
                if inner.len() != 1 {
                    return Err((format!("{name} with {} parameters", inner.len()), "a typed parameter NAME(value)"));
                }
                Ok(Param::Typed(name, Box::new(inner.remove(0))))
            }
            _ => Err((format!("\"{}\"", self.shown()), "a parameter")),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn file(data: &str) -> String {
        format!("ISO-10303-21;\nHEADER;\nFILE_NAME('a;b',$);\nENDSEC;\nDATA;\n{data}\nENDSEC;\nEND-ISO-10303-21;\n")
    }

    const BILINEAR: &str = "#1=CARTESIAN_POINT('',(0.,0.,0.));\n#2=CARTESIAN_POINT('',(0.,1.,0.));\n\
        #3=CARTESIAN_POINT('',(2.,0.,0.));\n#4 = CARTESIAN_POINT ( 'it''s', /* a comment; */ ( 2., 1.,\n 1. ) ) ;\n\
        #5=B_SPLINE_SURFACE_WITH_KNOTS('patch',1,1,((#1,#2),(#3,#4)),.UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,2),(0.,1.),\n(0.,1.),.UNSPECIFIED.);";

    #[test]
    fn a_plain_surface_without_units_is_read_in_millimetres() {
        let got = parse_step(file(BILINEAR).as_bytes(), "t.stp", None).expect("reads");
        assert_eq!(got.units, Units::Millimetre);
        assert!(got.notes[0].contains("millimetres assumed"), "{:?}", got.notes);
        assert_eq!(got.surfaces[0].name, "#5 'patch'");
        let s = &got.surfaces[0].surface;
        assert_eq!(s.control_point(1, 1), Vec3::new(2.0, 1.0, 1.0));
        assert_eq!(s.control_point(0, 1), Vec3::new(0.0, 1.0, 0.0));
        assert_eq!(s.knots_u().as_slice(), [0.0, 0.0, 1.0, 1.0]);
    }

    #[test]
    fn references_and_cycles_are_errors_with_the_place() {
        let missing = BILINEAR.replace("(#3,#4)", "(#3,#9)");
        let e = parse_step(file(&missing).as_bytes(), "t.stp", None).expect_err("#9");
        assert!(
            e.to_string().starts_with(
                "t.stp:11: #5 B_SPLINE_SURFACE_WITH_KNOTS, control point (1, 1): the reference #9 names no instance"
            ),
            "{e}"
        );
        let cyclic = format!(
            "{BILINEAR}\n#6=( GEOMETRIC_REPRESENTATION_CONTEXT(3) GLOBAL_UNIT_ASSIGNED_CONTEXT((#7)) REPRESENTATION_CONTEXT('','') );\n\
             #7=( CONVERSION_BASED_UNIT('INCH',#8) LENGTH_UNIT() NAMED_UNIT(*) );\n#8=LENGTH_MEASURE_WITH_UNIT(LENGTH_MEASURE(25.4),#7);"
        );
        let e = parse_step(file(&cyclic).as_bytes(), "t.stp", None).expect_err("cycle");
        assert!(e.to_string().contains("a cycle of unit references #6 -> #7 -> #8 -> #7"), "{e}");
    }

    #[test]
    fn several_surfaces_in_file_order() {
        let second = "#6=B_SPLINE_SURFACE_WITH_KNOTS('',1,1,((#4,#3),(#2,#1)),.UNSPECIFIED.,.F.,.F.,.F.,(2,2),(2,2),\
                      (0.,1.),(0.,1.),.UNSPECIFIED.);";
        let got = parse_step(file(&format!("{second}\n{BILINEAR}")).as_bytes(), "t.stp", None).expect("reads");
        let names: Vec<&str> = got.surfaces.iter().map(|s| s.name.as_str()).collect();
        assert_eq!(names, ["#5 'patch'", "#6"], "by instance name");
        assert_eq!(got.surfaces[1].surface.control_point(0, 0), Vec3::new(2.0, 1.0, 1.0));
    }

    #[test]
    fn knots_expand_from_multiplicities() {
        let n = |x: f64| Param::Number(x);
        let m = Param::List(vec![n(3.0), n(1.0), n(3.0)]);
        let k = Param::List(vec![n(0.0), n(0.5), n(1.0)]);
        assert_eq!(expand(&m, &k, 4, 2), Ok(vec![0.0, 0.0, 0.0, 0.5, 1.0, 1.0, 1.0]));
        assert!(expand(&m, &k, 5, 2).is_err(), "sum 7 for 8 knots");
        let huge = Param::List(vec![n(1e18), n(1.0), n(3.0)]);
        assert!(expand(&huge, &k, 4, 2).is_err());
    }
}
