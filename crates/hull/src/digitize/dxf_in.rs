//! ASCII DXF reader for drawn body plans: curves and texts of the `ENTITIES` section.
//!
//! The rest of this module's documentation is on [`parse_dxf`], where the library's users read it.

use std::collections::BTreeMap;
use std::f64::consts::PI;

use nurbs::fit::{interpolate_curve_auto, Parameterization};
use nurbs::Vec3;

use super::geom::{Affine, Segment, Spline, P2};
use super::{drawing_error, Curve, Label, Sketch, SketchFormat};
use crate::error::{HullError, Location};

/// One group: code, value (trimmed) and the 1-based line of the code.
#[derive(Clone, Copy, Debug)]
struct Pair<'a> {
    code: i32,
    value: &'a str,
    line: usize,
}

/// Split `text` into pairs, up to `0 EOF` (or the end of the text).
fn pairs<'a>(text: &'a str, source: &str) -> Result<Vec<Pair<'a>>, HullError> {
    let lines: Vec<&str> = text.lines().collect();
    let mut out = Vec::new();
    let mut i = 0;
    while i < lines.len() {
        let code_text = lines[i].trim();
        if code_text.is_empty() {
            if lines[i..].iter().all(|l| l.trim().is_empty()) {
                break;
            }
            return Err(drawing_error(
                Location::line(source, i + 1),
                "an empty line".into(),
                "a DXF group code: an integer on its own line, its value on the next",
            ));
        }
        let Ok(code) = code_text.parse::<i32>() else {
            return Err(drawing_error(
                Location::line(source, i + 1),
                format!("{code_text:?} where a group code belongs"),
                "a DXF group code: an integer on its own line, its value on the next (is this an ASCII DXF file?)",
            ));
        };
        let Some(value) = lines.get(i + 1) else {
            return Err(drawing_error(
                Location::line(source, i + 1),
                format!("the file ends after group code {code}"),
                "its value on the next line: the file may be cut short",
            ));
        };
        let value = value.trim();
        out.push(Pair { code, value, line: i + 1 });
        if code == 0 && value == "EOF" {
            break;
        }
        i += 2;
    }
    Ok(out)
}

/// Parse an ASCII DXF held in `text`; `source` names it in messages.
///
/// A DXF file is a list of *group code / value* pairs, each on two lines: an integer code,
/// then its value (AutoCAD DXF Reference; the R12 layout is a subset of every later one).
/// Entities start with code 0 (their type) and run to the next code 0; code 8 is the layer.
/// Read here, with their group codes:
///
/// | entity       | groups                                                                          |
/// |--------------|---------------------------------------------------------------------------------|
/// | `LINE`       | 10/20 start, 11/21 end (world coordinates)                                       |
/// | `ARC`        | 10/20 centre, 40 radius, 50/51 start/end angle in degrees, counter-clockwise   |
/// | `CIRCLE`     | 10/20 centre, 40 radius (a closed curve)                                        |
/// | `ELLIPSE`    | 10/20 centre, 11/21 major axis end (relative), 40 minor/major ratio, 41/42 parameters |
/// | `LWPOLYLINE` | 70 flags (1 closed), per vertex 10/20 and 42 bulge = tan(included angle / 4)    |
/// | `POLYLINE`   | 70 flags (1 closed, 8 3-D, 16/64 meshes: skipped), then `VERTEX`es (10/20, 42 bulge, 70 flags: 16 = spline frame point, skipped) and `SEQEND` |
/// | `SPLINE`     | 71 degree, 40 knots, 41 weights, 10/20 control points; or 11/21 fit points only  |
/// | `TEXT`       | 1 text, 10/20 insertion point, 11/21 alignment point when 72/73 justify it      |
/// | `MTEXT`      | 3 and 1 text chunks (formatting codes removed), 10/20 insertion point            |
///
/// Arcs, circles, polylines and texts lie in their *object coordinate system*, set by the
/// extrusion direction 210/220/230. A drawing viewed from above has extrusion (0, 0, 1), the
/// world system; mirrored entities have (0, 0, -1), whose x axis is the world's -x (the
/// "arbitrary axis algorithm" of the DXF reference for a normal along -z). Other extrusions
/// are not a plan drawing and are refused. A `SPLINE` given only by fit points is
/// interpolated by a cubic with chord-length parameters and averaging knots (The NURBS Book
/// eq. 9.5, 9.8); AutoCAD's own fit may differ slightly between the fit points.
///
/// Everything else (blocks and their `INSERT`s, hatches, dimensions, points, solids) is
/// skipped and listed in [`Sketch::notes`]. The `$INSUNITS` header variable gives
/// [`Sketch::unit_mm`]. Errors name the file and the line.
///
/// # Errors
/// [`HullError::Input`] with [`crate::InputErrorKind::Drawing`] at the line of: a line that is
/// not a group code, a group code without its value, a section without `ENDSEC` (a file cut
/// short), no `ENTITIES` section, a number that does not parse or is not finite, an entity
/// missing a group it needs (an `ARC` without its radius), a `POLYLINE` without `SEQEND`, a
/// `SPLINE` whose knot, weight and control-point counts disagree, and an entity drawn in a
/// plane other than the XY plane.
pub fn parse_dxf(text: &str, source: &str) -> Result<Sketch, HullError> {
    let pairs = pairs(text, source)?;
    let mut r = Reader {
        source,
        sketch: Sketch {
            source: source.to_string(),
            format: SketchFormat::Dxf,
            unit_mm: None,
            curves: Vec::new(),
            labels: Vec::new(),
            notes: Vec::new(),
        },
        skipped: BTreeMap::new(),
    };
    let mut saw_entities = false;
    let mut i = 0;
    while i < pairs.len() {
        let p = pairs[i];
        if p.code == 0 && p.value == "EOF" {
            break;
        }
        if !(p.code == 0 && p.value == "SECTION") {
            i += 1;
            continue;
        }
        let name = match pairs.get(i + 1) {
            Some(q) if q.code == 2 => q.value,
            _ => {
                return Err(drawing_error(
                    Location::line(source, p.line),
                    "0 SECTION without a name".into(),
                    "group 2 with the section name (HEADER, TABLES, ENTITIES, ...) after 0 SECTION",
                ))
            }
        };
        let Some(end) = (i + 2..pairs.len()).find(|&k| pairs[k].code == 0 && pairs[k].value == "ENDSEC") else {
            let last = pairs.last().map_or(p.line, |q| q.line + 1);
            return Err(drawing_error(
                Location::line(source, last),
                format!("the file ends inside the {name} section begun at line {}", p.line),
                "0 ENDSEC closing the section, then 0 EOF: the file may be cut short",
            ));
        };
        match name {
            "HEADER" => r.header(&pairs[i + 2..end]),
            "ENTITIES" => {
                saw_entities = true;
                r.entities(&pairs[i + 2..end])?;
            }
            _ => {}
        }
        i = end + 1;
    }
    if !saw_entities {
        return Err(drawing_error(
            Location::file(source),
            "no ENTITIES section".into(),
            "a DXF drawing with an ENTITIES section holding the station curves",
        ));
    }
    for (kind, (count, line)) in std::mem::take(&mut r.skipped) {
        let why = match kind.as_str() {
            "INSERT" => "block references are not expanded: explode the blocks to digitise their curves",
            "POLYLINE" => "polygon and polyface meshes are not curves",
            _ => "not a curve or a text",
        };
        r.sketch.notes.push(format!("{kind} ({count}, first at line {line}) skipped: {why}"));
    }
    Ok(r.sketch)
}

struct Reader<'s> {
    source: &'s str,
    sketch: Sketch,
    /// Skipped entity kinds: count and first line.
    skipped: BTreeMap<String, (usize, usize)>,
}

/// One entity: its type, the line of its `0 TYPE`, and its groups after that.
struct Entity<'a, 'p> {
    kind: &'a str,
    line: usize,
    groups: &'p [Pair<'a>],
}

impl<'s> Reader<'s> {
    fn header(&mut self, pairs: &[Pair<'_>]) {
        for (k, p) in pairs.iter().enumerate() {
            if p.code == 9 && p.value == "$INSUNITS" {
                let code = pairs.get(k + 1).filter(|q| q.code == 70).and_then(|q| q.value.parse::<i32>().ok());
                // DXF reference, $INSUNITS: 1 in, 2 ft, 3 mi, 4 mm, 5 cm, 6 m, 7 km, 10 yd, 14 dm.
                self.sketch.unit_mm = match code {
                    Some(1) => Some(25.4),
                    Some(2) => Some(304.8),
                    Some(3) => Some(1_609_344.0),
                    Some(4) => Some(1.0),
                    Some(5) => Some(10.0),
                    Some(6) => Some(1000.0),
                    Some(7) => Some(1e6),
                    Some(10) => Some(914.4),
                    Some(14) => Some(100.0),
                    _ => None,
                };
            }
        }
    }

    fn skip(&mut self, kind: &str, line: usize) {
        let e = self.skipped.entry(kind.to_string()).or_insert((0, line));
        e.0 += 1;
    }

    fn entities(&mut self, pairs: &[Pair<'_>]) -> Result<(), HullError> {
        let starts: Vec<usize> = (0..pairs.len()).filter(|&k| pairs[k].code == 0).collect();
        if let Some(first) = pairs.first().filter(|p| p.code != 0) {
            return Err(self.err(
                first.line,
                format!("group code {} before any entity", first.code),
                "0 and an entity type",
            ));
        }
        let ents: Vec<Entity<'_, '_>> = starts
            .iter()
            .enumerate()
            .map(|(n, &s)| {
                let end = starts.get(n + 1).copied().unwrap_or(pairs.len());
                Entity { kind: pairs[s].value, line: pairs[s].line, groups: &pairs[s + 1..end] }
            })
            .collect();
        let mut k = 0;
        while k < ents.len() {
            let e = &ents[k];
            k += 1;
            match e.kind {
                "LINE" => self.line(e)?,
                "ARC" | "CIRCLE" => self.arc(e)?,
                "ELLIPSE" => self.ellipse(e)?,
                "LWPOLYLINE" => self.lwpolyline(e)?,
                "SPLINE" => self.spline(e)?,
                "TEXT" | "MTEXT" => self.text(e)?,
                "POLYLINE" => {
                    let first = k;
                    while k < ents.len() && ents[k].kind == "VERTEX" {
                        k += 1;
                    }
                    if ents.get(k).map(|s| s.kind) != Some("SEQEND") {
                        return Err(self.err(
                            e.line,
                            format!("POLYLINE with {} VERTEX entities and no SEQEND", k - first),
                            "the POLYLINE's VERTEX entities closed by 0 SEQEND",
                        ));
                    }
                    self.polyline(e, &ents[first..k])?;
                    k += 1;
                }
                "VERTEX" | "SEQEND" => {
                    return Err(self.err(
                        e.line,
                        format!("{} outside a POLYLINE", e.kind),
                        "VERTEX and SEQEND only after a POLYLINE",
                    ))
                }
                other => self.skip(other, e.line),
            }
        }
        Ok(())
    }

    fn err(&self, line: usize, found: String, expected: &str) -> HullError {
        drawing_error(Location::line(self.source, line), found, expected)
    }

    fn push_curve(&mut self, e: &Entity<'_, '_>, segments: Vec<Segment>, closed: bool) {
        self.sketch.curves.push(Curve {
            segments,
            layer: layer(e),
            name: None,
            closed,
            at: Location::line(self.source, e.line),
            kind: e.kind.to_string(),
        });
    }

    fn num(&self, e: &Entity<'_, '_>, p: &Pair<'_>) -> Result<f64, HullError> {
        match p.value.parse::<f64>() {
            Ok(v) if v.is_finite() => Ok(v),
            Ok(_) => Err(self.err(
                p.line + 1,
                format!("{:?} (group {} of {}) is not a finite number", p.value, p.code, e.kind),
                "a finite number",
            )),
            Err(_) => Err(self.err(
                p.line + 1,
                format!("{:?} (group {} of {}) is not a number", p.value, p.code, e.kind),
                "a number written with a decimal point",
            )),
        }
    }

    /// The value of the first group `code`, as a number, if present.
    fn opt(&self, e: &Entity<'_, '_>, code: i32) -> Result<Option<f64>, HullError> {
        e.groups.iter().find(|p| p.code == code).map(|p| self.num(e, p)).transpose()
    }

    /// The value of the first group `code`, which must be there.
    fn need(&self, e: &Entity<'_, '_>, code: i32, what: &str) -> Result<f64, HullError> {
        self.opt(e, code)?.ok_or_else(|| {
            self.err(e.line, format!("{} without group {code}", e.kind), &format!("group {code}: {what}"))
        })
    }

    fn point(&self, e: &Entity<'_, '_>, code: i32, what: &str) -> Result<P2, HullError> {
        Ok([self.need(e, code, &format!("the x of {what}"))?, self.need(e, code + 10, &format!("the y of {what}"))?])
    }

    /// The map from the entity's object coordinate system to the drawing: the identity for
    /// extrusion (0, 0, 1), the mirror x -> -x for (0, 0, -1).
    fn ocs(&self, e: &Entity<'_, '_>) -> Result<Affine, HullError> {
        let n = [self.opt(e, 210)?.unwrap_or(0.0), self.opt(e, 220)?.unwrap_or(0.0), self.opt(e, 230)?.unwrap_or(1.0)];
        let len = (n[0] * n[0] + n[1] * n[1] + n[2] * n[2]).sqrt();
        if len > 0.0 && n[0].abs() <= 1e-9 * len && n[1].abs() <= 1e-9 * len {
            return Ok(if n[2] > 0.0 { Affine::IDENTITY } else { Affine { a: -1.0, ..Affine::IDENTITY } });
        }
        Err(self.err(
            e.line,
            format!("{} drawn in a plane with normal ({}, {}, {})", e.kind, n[0], n[1], n[2]),
            "a 2-D drawing in the XY plane (extrusion direction 0, 0, 1 or 0, 0, -1)",
        ))
    }

    fn line(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let a = self.point(e, 10, "its start point")?;
        let b = self.point(e, 11, "its end point")?;
        self.push_curve(e, vec![Segment::Line(a, b)], false);
        Ok(())
    }

    fn arc(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let m = self.ocs(e)?;
        let c = self.point(e, 10, "its centre")?;
        let r = self.need(e, 40, "its radius")?;
        if !(r > 0.0) {
            return Err(self.err(e.line, format!("{} of radius {r}", e.kind), "a radius greater than 0"));
        }
        let (t0, t1, closed) = if e.kind == "CIRCLE" {
            (0.0, 2.0 * PI, true)
        } else {
            let a0 = self.need(e, 50, "its start angle in degrees")?;
            let a1 = self.need(e, 51, "its end angle in degrees")?;
            // Counter-clockwise from a0 to a1; equal angles draw the whole circle.
            let mut sweep = (a1 - a0).rem_euclid(360.0);
            if sweep == 0.0 {
                sweep = 360.0;
            }
            (a0.to_radians(), (a0 + sweep).to_radians(), false)
        };
        let arc = Segment::Arc { c, u: [r, 0.0], v: [0.0, r], t0, t1 };
        self.push_curve(e, vec![arc.transformed(&m)], closed);
        Ok(())
    }

    fn ellipse(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let c = self.point(e, 10, "its centre")?;
        let u = self.point(e, 11, "its major axis end point, relative to the centre")?;
        let ratio = self.need(e, 40, "the ratio of its minor to its major axis")?;
        // Counter-clockwise from t0 to t1, as for an ARC: the sweep is taken modulo one turn
        // (a zero sweep draws the whole ellipse), so that parameters of any size give at most
        // one turn, not millions of turns to flatten.
        let t0 = self.opt(e, 41)?.unwrap_or(0.0).rem_euclid(2.0 * PI);
        let mut sweep = (self.opt(e, 42)?.unwrap_or(2.0 * PI) - t0).rem_euclid(2.0 * PI);
        if sweep == 0.0 {
            sweep = 2.0 * PI;
        }
        let t1 = t0 + sweep;
        // The minor axis is extrusion x major axis, scaled by the ratio (world coordinates).
        let sign = if self.ocs(e)?.a < 0.0 { -1.0 } else { 1.0 };
        let v = [-sign * ratio * u[1], sign * ratio * u[0]];
        let closed = (t1 - t0 - 2.0 * PI).abs() < 1e-12;
        self.push_curve(e, vec![Segment::Arc { c, u, v, t0, t1 }], closed);
        Ok(())
    }

    /// Polyline segments through `v` (point, bulge to the next), closed back to the start when
    /// `closed`.
    fn bulged(v: &[(P2, f64)], closed: bool, m: &Affine) -> Vec<Segment> {
        let n = v.len();
        let count = if closed { n } else { n.saturating_sub(1) };
        (0..count).map(|i| Segment::bulge(v[i].0, v[(i + 1) % n].0, v[i].1).transformed(m)).collect()
    }

    fn lwpolyline(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let m = self.ocs(e)?;
        let flags = self.opt(e, 70)?.unwrap_or(0.0) as i64;
        let mut v: Vec<(P2, f64)> = Vec::new();
        for p in e.groups {
            match p.code {
                10 => v.push(([self.num(e, p)?, f64::NAN], 0.0)),
                20 | 42 => {
                    let val = self.num(e, p)?;
                    let Some(last) = v.last_mut() else {
                        return Err(self.err(
                            p.line,
                            format!("group {} before the first vertex", p.code),
                            "group 10 first",
                        ));
                    };
                    if p.code == 20 {
                        last.0[1] = val;
                    } else {
                        last.1 = val;
                    }
                }
                _ => {}
            }
        }
        if let Some(k) = v.iter().position(|(q, _)| q[1].is_nan()) {
            return Err(self.err(
                e.line,
                format!("LWPOLYLINE vertex {} without its y (group 20)", k + 1),
                "10 and 20 for every vertex",
            ));
        }
        self.finish_polyline(e, &v, flags & 1 != 0, &m);
        Ok(())
    }

    fn finish_polyline(&mut self, e: &Entity<'_, '_>, v: &[(P2, f64)], closed: bool, m: &Affine) {
        if v.len() < 2 {
            self.sketch.notes.push(format!("{} at line {} has {} vertex and is skipped", e.kind, e.line, v.len()));
            return;
        }
        let segs = Self::bulged(v, closed, m);
        self.push_curve(e, segs, closed);
    }

    fn polyline(&mut self, e: &Entity<'_, '_>, vertices: &[Entity<'_, '_>]) -> Result<(), HullError> {
        let flags = self.opt(e, 70)?.unwrap_or(0.0) as i64;
        if flags & (16 | 64) != 0 {
            self.skip("POLYLINE", e.line);
            return Ok(());
        }
        let three_d = flags & 8 != 0;
        let m = if three_d { Affine::IDENTITY } else { self.ocs(e)? };
        let mut v = Vec::with_capacity(vertices.len());
        for vx in vertices {
            let vflags = self.opt(vx, 70)?.unwrap_or(0.0) as i64;
            if vflags & 16 != 0 {
                continue; // a spline frame control point, not on the drawn curve
            }
            let p = self.point(vx, 10, "the vertex")?;
            let bulge = if three_d { 0.0 } else { self.opt(vx, 42)?.unwrap_or(0.0) };
            v.push((p, bulge));
        }
        self.finish_polyline(e, &v, flags & 1 != 0, &m);
        Ok(())
    }

    fn spline(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let flags = self.opt(e, 70)?.unwrap_or(0.0) as i64;
        let degree = self.opt(e, 71)?.unwrap_or(3.0);
        let (mut knots, mut weights, mut ctrl, mut fit) = (Vec::new(), Vec::new(), Vec::<P2>::new(), Vec::<P2>::new());
        for p in e.groups {
            match p.code {
                40 => knots.push(self.num(e, p)?),
                41 => weights.push(self.num(e, p)?),
                10 => ctrl.push([self.num(e, p)?, f64::NAN]),
                11 => fit.push([self.num(e, p)?, f64::NAN]),
                20 | 21 => {
                    let list = if p.code == 20 { &mut ctrl } else { &mut fit };
                    let val = self.num(e, p)?;
                    match list.last_mut() {
                        Some(q) if q[1].is_nan() => q[1] = val,
                        _ => {
                            return Err(self.err(
                                p.line,
                                format!("group {} without the group {} before it", p.code, p.code - 10),
                                "x (10 or 11) then y (20 or 21) for every point",
                            ))
                        }
                    }
                }
                _ => {}
            }
        }
        if ctrl.iter().chain(&fit).any(|q| q[1].is_nan()) {
            return Err(self.err(
                e.line,
                "SPLINE point without its y".into(),
                "x (10 or 11) then y (20 or 21) for every point",
            ));
        }
        for (code, got, what) in
            [(72, knots.len(), "knots"), (73, ctrl.len(), "control points"), (74, fit.len(), "fit points")]
        {
            if let Some(n) = self.opt(e, code)? {
                if n as usize != got {
                    return Err(self.err(
                        e.line,
                        format!("SPLINE announces {n} {what} (group {code}) and lists {got}"),
                        &format!("as many {what} as group {code} says"),
                    ));
                }
            }
        }
        let spline = if !ctrl.is_empty() {
            if !((1.0..=25.0).contains(&degree) && degree.fract() == 0.0) {
                return Err(self.err(e.line, format!("SPLINE of degree {degree}"), "a degree (group 71) from 1 to 25"));
            }
            let w = (!weights.is_empty()).then_some(weights.as_slice());
            Spline::try_new(degree as usize, std::mem::take(&mut knots), &ctrl, w).map_err(|why| {
                self.err(
                    e.line,
                    format!("SPLINE with {why}"),
                    "a valid B-spline: knots = control points + degree + 1, non-decreasing, positive weights",
                )
            })?
        } else if fit.len() >= 2 {
            let pts: Vec<Vec3> = fit.iter().map(|q| Vec3::new(q[0], q[1], 0.0)).collect();
            let deg = (fit.len() - 1).min(3);
            let curve = interpolate_curve_auto(&pts, deg, Parameterization::ChordLength).map_err(|why| {
                self.err(e.line, format!("SPLINE fit points that cannot be interpolated: {why}"), "distinct fit points")
            })?;
            let cp: Vec<P2> = curve.control_points().iter().map(|p| [p.x, p.y]).collect();
            Spline::try_new(deg, curve.knots().as_slice().to_vec(), &cp, None).map_err(|why| {
                self.err(e.line, format!("SPLINE fit points give an invalid curve: {why}"), "distinct fit points")
            })?
        } else {
            return Err(self.err(
                e.line,
                format!("SPLINE with {} control points and {} fit points", ctrl.len(), fit.len()),
                "control points (group 10/20) with knots (40), or at least 2 fit points (11/21)",
            ));
        };
        self.push_curve(e, vec![Segment::Spline(spline)], flags & 1 != 0);
        Ok(())
    }

    fn text(&mut self, e: &Entity<'_, '_>) -> Result<(), HullError> {
        let mtext = e.kind == "MTEXT";
        let mut at = self.point(e, 10, "its insertion point")?;
        let mut raw = String::new();
        for p in e.groups.iter().filter(|p| p.code == 3) {
            raw.push_str(p.value);
        }
        if let Some(p) = e.groups.iter().find(|p| p.code == 1) {
            raw.push_str(p.value);
        }
        if !mtext {
            // A justified TEXT is placed by its alignment point.
            let justified = self.opt(e, 72)?.unwrap_or(0.0) != 0.0 || self.opt(e, 73)?.unwrap_or(0.0) != 0.0;
            if justified {
                if let (Some(x), Some(y)) = (self.opt(e, 11)?, self.opt(e, 21)?) {
                    at = [x, y];
                }
            }
            at = self.ocs(e)?.apply(at);
        }
        let text = if mtext { clean_mtext(&raw) } else { decode_text(&raw) };
        self.sketch.labels.push(Label {
            at,
            text: text.trim().to_string(),
            layer: layer(e),
            loc: Location::line(self.source, e.line),
        });
        Ok(())
    }
}

fn layer(e: &Entity<'_, '_>) -> String {
    e.groups.iter().find(|p| p.code == 8).map_or("0", |p| p.value).to_string()
}

/// DXF text escapes: `%%d` degree, `%%p` plus-minus, `%%c` diameter, `%%%` percent, `%%u` and
/// `%%o` (underline, overline toggles) dropped, `\U+XXXX` a Unicode character.
fn decode_text(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut rest = s;
    while let Some(c) = rest.chars().next() {
        if let Some(r) = rest.strip_prefix("%%") {
            let code = r.chars().next().map(|c| c.to_ascii_lowercase());
            let rep = match code {
                Some('d') => Some("°"),
                Some('p') => Some("±"),
                Some('c') => Some("⌀"),
                Some('%') => Some("%"),
                Some('u' | 'o') => Some(""),
                _ => None,
            };
            if let Some(rep) = rep {
                out.push_str(rep);
                rest = &r[1..];
                continue;
            }
        }
        if let Some(r) = rest.strip_prefix("\\U+").or_else(|| rest.strip_prefix("\\u+")) {
            if let Some(ch) = r.get(..4).and_then(|h| u32::from_str_radix(h, 16).ok()).and_then(char::from_u32) {
                out.push(ch);
                rest = &r[4..];
                continue;
            }
        }
        out.push(c);
        rest = &rest[c.len_utf8()..];
    }
    out
}

/// MTEXT formatting removed: `\P` (new paragraph) and `\~` become spaces, `\\`, `\{`, `\}` the
/// character, `\S a^b;` (stacked) `a/b`, codes with an argument up to `;` (`\f`, `\H`, `\C`,
/// `\T`, `\Q`, `\W`, `\A`, `\p`) and toggles (`\L`, `\O`, `\K`) dropped, braces dropped; then
/// [`decode_text`].
fn clean_mtext(s: &str) -> String {
    let mut out = String::with_capacity(s.len());
    let mut chars = s.chars().peekable();
    while let Some(c) = chars.next() {
        match c {
            '{' | '}' => {}
            '\\' => match chars.next() {
                Some('P' | 'X' | '~') => out.push(' '),
                Some(c @ ('\\' | '{' | '}')) => out.push(c),
                Some('S') => {
                    for c in chars.by_ref() {
                        match c {
                            ';' => break,
                            '^' | '#' => out.push('/'),
                            c => out.push(c),
                        }
                    }
                }
                Some('f' | 'F' | 'H' | 'C' | 'c' | 'T' | 'Q' | 'W' | 'A' | 'p') => {
                    for c in chars.by_ref() {
                        if c == ';' {
                            break;
                        }
                    }
                }
                Some('L' | 'l' | 'O' | 'o' | 'K' | 'k') => {}
                Some(other) => {
                    out.push('\\');
                    out.push(other);
                }
                None => out.push('\\'),
            },
            c => out.push(c),
        }
    }
    decode_text(&out)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn dxf(entities: &str) -> String {
        format!("0\nSECTION\n2\nENTITIES\n{entities}0\nENDSEC\n0\nEOF\n")
    }

    fn pts(c: &Curve) -> Vec<P2> {
        c.points(1e-6)
    }

    #[test]
    fn lines_arcs_and_layers() {
        let s = parse_dxf(
            &dxf("0\nLINE\n8\nST1\n10\n0\n20\n0\n30\n0\n11\n3\n21\n4\n31\n0\n\
                  0\nARC\n8\nST2\n10\n1\n20\n1\n40\n2\n50\n0\n51\n90\n"),
            "a.dxf",
        )
        .expect("parses");
        assert_eq!(s.curves.len(), 2);
        assert_eq!((s.curves[0].layer.as_str(), s.curves[1].layer.as_str()), ("ST1", "ST2"));
        assert_eq!(pts(&s.curves[0]), vec![[0.0, 0.0], [3.0, 4.0]]);
        // The quarter arc from (3, 1) to (1, 3) counter-clockwise about (1, 1): every point
        // at radius 2 to round-off.
        let a = pts(&s.curves[1]);
        assert!((a[0][0] - 3.0).abs() < 1e-15 && (a[a.len() - 1][1] - 3.0).abs() < 1e-15);
        for p in &a {
            assert!(((p[0] - 1.0).hypot(p[1] - 1.0) - 2.0).abs() < 1e-14);
        }
        assert_eq!(s.curves[1].at.to_string(), "a.dxf:21");
    }

    /// A mirrored arc (extrusion 0, 0, -1) is drawn at -x: its centre (1, 1) in the object
    /// system is (-1, 1) in the drawing, and counter-clockwise there runs clockwise here.
    #[test]
    fn mirrored_object_coordinates() {
        let s = parse_dxf(&dxf("0\nARC\n10\n1\n20\n1\n40\n1\n50\n0\n51\n90\n210\n0\n220\n0\n230\n-1\n"), "m.dxf")
            .expect("parses");
        let a = pts(&s.curves[0]);
        assert!((a[0][0] + 2.0).abs() < 1e-15 && (a[0][1] - 1.0).abs() < 1e-15, "{:?}", a[0]);
        let e = parse_dxf(&dxf("0\nARC\n10\n1\n20\n1\n40\n1\n50\n0\n51\n90\n210\n1\n220\n0\n230\n0\n"), "m.dxf")
            .expect_err("not in the XY plane");
        assert!(e.to_string().contains("plane with normal (1, 0, 0)"), "{e}");
    }

    /// An LWPOLYLINE with a bulge of 1 on its middle vertex: a half circle of radius 1 between
    /// (1, 0) and (1, 2) bulging to +x (clockwise going up would bulge to -x).
    #[test]
    fn lwpolyline_bulges() {
        let s = parse_dxf(
            &dxf("0\nLWPOLYLINE\n8\nS\n90\n3\n70\n0\n10\n0\n20\n0\n10\n1\n20\n0\n42\n1\n10\n1\n20\n2\n"),
            "p.dxf",
        )
        .expect("parses");
        let p = pts(&s.curves[0]);
        assert_eq!(p[0], [0.0, 0.0]);
        let far = p.iter().map(|q| q[0]).fold(f64::NEG_INFINITY, f64::max);
        assert!((far - 2.0).abs() < 1e-12, "the half circle reaches x = 2: {far}");
        assert!((p[p.len() - 1][1] - 2.0).abs() < 1e-12);
    }

    #[test]
    fn polyline_vertices_skip_frame_points() {
        let s = parse_dxf(
            &dxf("0\nPOLYLINE\n8\nA\n66\n1\n70\n0\n0\nVERTEX\n10\n0\n20\n0\n0\nVERTEX\n10\n9\n20\n9\n70\n16\n\
                  0\nVERTEX\n10\n1\n20\n1\n0\nSEQEND\n"),
            "p.dxf",
        )
        .expect("parses");
        assert_eq!(pts(&s.curves[0]), vec![[0.0, 0.0], [1.0, 1.0]]);
        let e = parse_dxf(&dxf("0\nPOLYLINE\n70\n0\n0\nVERTEX\n10\n0\n20\n0\n"), "p.dxf").expect_err("no SEQEND");
        assert_eq!(
            e.to_string(),
            "p.dxf:5: POLYLINE with 1 VERTEX entities and no SEQEND (expected the POLYLINE's VERTEX entities closed by 0 SEQEND)"
        );
    }

    /// A SPLINE given by fit points passes through them.
    #[test]
    fn spline_from_fit_points_interpolates() {
        let s = parse_dxf(
            &dxf("0\nSPLINE\n71\n3\n74\n4\n11\n0\n21\n0\n11\n1\n21\n2\n11\n3\n21\n3\n11\n6\n21\n3.5\n"),
            "f.dxf",
        )
        .expect("parses");
        let p = pts(&s.curves[0]);
        for f in [[0.0, 0.0], [1.0, 2.0], [3.0, 3.0], [6.0, 3.5]] {
            let d = super::super::geom::polyline_dist(f, &p);
            // On the curve; the polyline's chords stay within the flatness 1e-6 of it.
            assert!(d <= 1e-6, "fit point {f:?} off by {d}");
        }
    }

    #[test]
    fn texts_are_decoded() {
        let s = parse_dxf(
            &dxf("0\nTEXT\n8\nL\n10\n5\n20\n6\n1\n ST 3 %%d\n0\nMTEXT\n10\n1\n20\n2\n3\n{\\fArial|b0;Station\\P}\n1\n1\\S1^2;\n"),
            "t.dxf",
        )
        .expect("parses");
        assert_eq!(s.labels[0].text, "ST 3 °");
        assert_eq!(s.labels[0].at, [5.0, 6.0]);
        assert_eq!(s.labels[1].text, "Station 11/2");
        assert_eq!(decode_text("\\U+00B0x"), "°x");
    }

    #[test]
    fn units_and_skipped_entities() {
        let text = format!(
            "0\nSECTION\n2\nHEADER\n9\n$INSUNITS\n70\n4\n0\nENDSEC\n{}",
            dxf("0\nINSERT\n2\nB\n10\n0\n20\n0\n0\nINSERT\n2\nB\n10\n0\n20\n0\n0\nPOINT\n10\n0\n20\n0\n")
        );
        let s = parse_dxf(&text, "u.dxf").expect("parses");
        assert_eq!(s.unit_mm, Some(1.0));
        assert_eq!(s.notes.len(), 2);
        assert!(s.notes[0].starts_with("INSERT (2, first at line 15) skipped: block references"), "{:?}", s.notes);
    }

    #[test]
    fn broken_files_name_the_line() {
        let err = |t: &str| parse_dxf(t, "b.dxf").expect_err("broken").to_string();
        assert_eq!(
            err("0\nSECTION\n2\nENTITIES\nten\nLINE\n"),
            "b.dxf:5: \"ten\" where a group code belongs (expected a DXF group code: an integer on its own line, \
             its value on the next (is this an ASCII DXF file?))"
        );
        assert_eq!(
            err("0\nSECTION\n2\nENTITIES\n0\nLINE\n10\n"),
            "b.dxf:7: the file ends after group code 10 (expected its value on the next line: the file may be cut short)"
        );
        assert!(err("0\nSECTION\n2\nENTITIES\n0\nLINE\n10\n1\n")
            .starts_with("b.dxf:8: the file ends inside the ENTITIES section begun at line 1"));
        assert_eq!(
            err(&dxf("0\nLINE\n10\n1,5\n20\n0\n11\n0\n21\n0\n")),
            "b.dxf:8: \"1,5\" (group 10 of LINE) is not a number (expected a number written with a decimal point)"
        );
        assert!(err(&dxf("0\nARC\n10\n0\n20\n0\n50\n0\n51\n90\n"))
            .starts_with("b.dxf:5: ARC without group 40 (expected group 40: its radius)"));
        assert!(err(&dxf("0\nSPLINE\n71\n2\n40\n0\n40\n1\n10\n0\n20\n0\n10\n1\n20\n1\n10\n2\n20\n0\n"))
            .contains("SPLINE with 2 knots for 3 control points of degree 2"));
        assert!(err("0\nSECTION\n2\nHEADER\n0\nENDSEC\n0\nEOF\n").starts_with("b.dxf: no ENTITIES section"));
        assert!(err("<svg").contains("where a group code belongs"));
        assert!(err(&dxf("0\nLINE\n10\nnan\n20\n0\n11\n0\n21\n0\n")).contains("is not a finite number"));
    }

    /// Found by fuzzing (`testdata/fuzz/drawing_dxf/`): an ELLIPSE's parameters 41/42 of
    /// millions of radians drew at most one turn, but were flattened turn by turn (4 GiB).
    #[test]
    fn ellipse_parameters_of_any_size_draw_at_most_one_turn() {
        let ellipse = |t0: &str, t1: &str| {
            let s =
                parse_dxf(&dxf(&format!("0\nELLIPSE\n10\n0\n20\n0\n11\n2\n21\n0\n40\n0.5\n41\n{t0}\n42\n{t1}\n")), "e")
                    .expect("valid ellipse");
            s.curves[0].clone()
        };
        for (t0, t1) in [("-1e308", "1e308"), ("0", "60283185"), ("42724778", "6.283185"), ("1", "1")] {
            let c = ellipse(t0, t1);
            let p = c.points(1e-3);
            // One turn of an ellipse of semi-axes 2 and 1 flattened to 1e-3 takes about
            // pi / sqrt(2 x 1e-3 / 2) ~ 100 chords; a bound of 1000 leaves room for any start.
            assert!(p.len() < 1000, "{t0}..{t1}: {} points", p.len());
            for q in p {
                // On the ellipse (x/2)^2 + y^2 = 1, to round-off of the cos/sin evaluation.
                assert!(((q[0] / 2.0).powi(2) + q[1] * q[1] - 1.0).abs() < 1e-9, "{t0}..{t1}: {q:?}");
            }
        }
        // Equal parameters draw the whole ellipse, a closed curve, as before.
        assert!(ellipse("1", "1").closed && !ellipse("0", "3").closed);
    }
}
