//! From drawn curves to offsets: scale, datum, station identification, sides, joining.
//!
//! The rest of this module's documentation is on [`digitize`], where the library's users read it.

use nurbs::Vec3;

use super::geom::P2;
use super::join::{join, Chain};
use super::options::{DigitizeOptions, Digitized, DrawingScale, Side, StationIds, StationInfo};
use super::stations::{by_labels, order_chains, station_xs};
use super::{drawing_error, glob_match, Curve, Sketch};
use crate::error::{DigitizeKind, HullError, Location};
use crate::offsets::{Offsets, Section, COINCIDENT_REL};

/// Model length per drawing unit.
fn model_per_unit(sketch: &Sketch, o: &DigitizeOptions) -> Result<f64, HullError> {
    let s = match o.scale {
        DrawingScale::UnitsPerModelUnit(k) => {
            if !(k.is_finite() && k > 0.0) {
                return Err(HullError::Digitize(DigitizeKind::ScalePerUnit { scale: k, units: o.units.symbol() }));
            }
            1.0 / k
        }
        DrawingScale::Ratio { paper, model } => {
            if !(paper.is_finite() && paper > 0.0 && model.is_finite() && model > 0.0) {
                return Err(HullError::Digitize(DigitizeKind::Ratio { paper, model }));
            }
            let Some(u) = o.drawing_unit_mm.or(sketch.unit_mm) else {
                return Err(HullError::Digitize(DigitizeKind::NoDrawingUnit {
                    drawing: sketch.source.clone(),
                    paper,
                    model,
                    units: o.units.symbol(),
                }));
            };
            if !(u.is_finite() && u > 0.0) {
                return Err(HullError::Digitize(DigitizeKind::DrawingUnit { mm: u }));
            }
            u / 1000.0 / o.units.metres_per_unit() * model / paper
        }
    };
    Ok(s)
}

/// A station found in the drawing, before its x is known.
pub(super) struct Found {
    pub(super) label: String,
    pub(super) chains: Vec<Chain>,
}

/// Digitise the station curves of `sketch` into offsets (see below).
///
/// # The mapping
///
/// With `s` the model length of one drawing unit and `(X0, Y0)` the datum (the drawing point
/// where the body plan's centreline meets its baseline), a drawing point `(X, Y)` of a
/// station curve becomes
///
/// ```text
/// y = |X - X0| s              (half-breadth: aft stations drawn left, fore ones right)
/// z = (Y - Y0) s              (DXF, y up)      z = (Y0 - Y) s     (SVG, y down)
/// ```
///
/// and its station's `x`. For a scale `paper:model` (1:50 is `1:50`), `s = u / 1000 / m * model
/// / paper` with `u` the millimetres per drawing unit (from the file, or given) and `m` the
/// metres per output unit; for a scale given as drawing units per output unit `k`, `s = 1 / k`.
///
/// # Tolerances (drawing units)
///
/// `D` is the diagonal of the box of the curves considered. Curved pieces are flattened to
/// within [`DigitizeOptions::flatness`] (default `1e-6 D`, half a micrometre on an A3 sheet:
/// below the 1 µm the SVG writers round to). Two piece ends within
/// [`DigitizeOptions::join_tol`] (default `1e-4 D`) are the same point; a point within it of
/// the centreline `X = X0` is on the centreline, on neither side.
///
/// The pieces are joined into runs first (`join.rs`, where the rules are), then sorted into
/// stations and placed along the hull (`stations.rs`); the settings and the result are in
/// `options.rs`.
///
/// # Errors
/// [`HullError::Digitize`] for a scale or datum that cannot work (a ratio scale on a drawing
/// that does not say its units and none given, non-positive values), a station count other
/// than the list of positions, station names with [`StationX::Map`](super::StationX::Map) for
/// [`StationIds::Order`], or a resampling count below 2. [`HullError::Input`] with
/// [`crate::InputErrorKind::Drawing`], located at the drawn curve, for: no curve on the
/// selected layers, no station found, a station not among the given names ("unknown
/// station"), a name without a station number with [`StationX::Spacing`](super::StationX::Spacing), a curve that
/// crosses the centreline, a station drawn on both sides, two curves of one station that
/// overlap in height, two labels on one curve, and two stations at the same x. Then those of
/// [`Offsets::validate`].
pub fn digitize(sketch: &Sketch, o: &DigitizeOptions) -> Result<Digitized, HullError> {
    let s = model_per_unit(sketch, o)?;
    let [x0, y0] = o.datum;
    if !(x0.is_finite() && y0.is_finite()) {
        return Err(HullError::Digitize(DigitizeKind::Datum { x: x0, y: y0 }));
    }
    if let Some(n) = o.points {
        if n < 2 {
            return Err(HullError::Digitize(DigitizeKind::Points { count: n }));
        }
    }
    let mut notes = sketch.notes.clone();
    let src = sketch.source.as_str();

    // Which curves.
    let wanted = |c: &Curve| {
        o.layers.as_deref().is_none_or(|g| glob_match(g, &c.layer))
            && match &o.stations {
                StationIds::Layers(g) => glob_match(g, &c.layer),
                _ => true,
            }
    };
    let picked: Vec<usize> = (0..sketch.curves.len()).filter(|&i| wanted(&sketch.curves[i])).collect();
    if picked.is_empty() {
        let mut layers: Vec<&str> = sketch.curves.iter().map(|c| c.layer.as_str()).collect();
        layers.sort_unstable();
        layers.dedup();
        let pattern = match (&o.layers, &o.stations) {
            (_, StationIds::Layers(g)) | (Some(g), _) => format!("no curve on layers matching {g:?}"),
            _ => "no curve".to_string(),
        };
        return Err(drawing_error(
            Location::file(src),
            format!(
                "{pattern}; the drawing's curves are on layers: {}",
                if layers.is_empty() { "(none)".into() } else { layers.join(", ") }
            ),
            "the station curves: lines, arcs, polylines, splines or paths",
        ));
    }

    // Tolerances from the extent of the picked curves.
    let (mut lo, mut hi) = ([f64::INFINITY; 2], [f64::NEG_INFINITY; 2]);
    for &i in &picked {
        for seg in &sketch.curves[i].segments {
            for p in seg.hull_points() {
                lo = [lo[0].min(p[0]), lo[1].min(p[1])];
                hi = [hi[0].max(p[0]), hi[1].max(p[1])];
            }
        }
    }
    let diag = (hi[0] - lo[0]).hypot(hi[1] - lo[1]);
    let diag = if diag.is_finite() && diag > 0.0 { diag } else { 1.0 };
    let tol = o.join_tol.filter(|t| t.is_finite() && *t >= 0.0).unwrap_or(1e-4 * diag);
    let flat = o.flatness.filter(|t| t.is_finite() && *t > 0.0).unwrap_or(1e-6 * diag);

    // Pieces.
    let mut pieces = Vec::new();
    for &i in &picked {
        let c = &sketch.curves[i];
        let pts = c.points(flat);
        if c.closed {
            notes.push(format!("closed {} skipped: a station is an open curve from keel to deck", c.describe()));
        } else if pts.len() < 2 {
            notes.push(format!("{} skipped: it has no length", c.describe()));
        } else {
            pieces.push(Chain { src: vec![i; pts.len()], pts });
        }
    }

    let loop_note = |notes: &mut Vec<String>, loops: &[Chain]| {
        for l in loops {
            notes.push(format!(
                "pieces joined into a closed loop skipped, first {}: a station is an open curve",
                sketch.curves[l.first_curve()].describe()
            ));
        }
    };

    // Stations.
    let mut found: Vec<Found> = Vec::new();
    match &o.stations {
        StationIds::Layers(_) => {
            let mut groups: Vec<(String, Vec<Chain>)> = Vec::new();
            for p in pieces {
                let layer = &sketch.curves[p.src[0]].layer;
                match groups.iter_mut().find(|g| g.0.eq_ignore_ascii_case(layer)) {
                    Some(g) => g.1.push(p),
                    None => groups.push((layer.clone(), vec![p])),
                }
            }
            for (label, chains) in groups {
                let (chains, loops) = join(chains, tol, None);
                loop_note(&mut notes, &loops);
                if !chains.is_empty() {
                    found.push(Found { label, chains });
                }
            }
        }
        StationIds::Labels => {
            let (chains, loops) = join(pieces, tol, Some(x0));
            loop_note(&mut notes, &loops);
            found = by_labels(sketch, o, chains, tol, &mut notes)?;
        }
        StationIds::Order(order) => {
            let (mut chains, loops) = join(pieces, tol, Some(x0));
            loop_note(&mut notes, &loops);
            order_chains(sketch, &mut chains, *order, x0, tol);
            found =
                chains.into_iter().enumerate().map(|(k, c)| Found { label: k.to_string(), chains: vec![c] }).collect();
        }
    }
    if found.is_empty() {
        return Err(drawing_error(
            Location::file(src),
            "no station curve found".into(),
            "open station curves on the selected layers (closed curves are skipped)",
        ));
    }

    // x of each station.
    let xs = station_xs(sketch, o, &mut found, &mut notes)?;

    // Model points, side checks, keel to deck.
    let ysign = if sketch.y_down() { -1.0 } else { 1.0 };
    let mut sections = Vec::with_capacity(found.len());
    let mut infos = Vec::with_capacity(found.len());
    for (f, &x) in found.iter().zip(&xs) {
        let (pts, lines, side) = station_points(sketch, f, x, [x0, y0], s, ysign, tol)?;
        let curves: Vec<usize> = {
            let mut c: Vec<usize> = f.chains.iter().flat_map(Chain::curves).collect();
            c.sort_unstable();
            c.dedup();
            c
        };
        infos.push(StationInfo {
            label: f.label.clone(),
            x,
            side,
            curves: curves.len(),
            points: 0,
            at: sketch.curves[curves[0]].at.clone(),
        });
        sections.push((f.label.clone(), pts, lines));
    }

    // Points kept or resampled, repeated ones dropped.
    let size = model_size(&sections);
    let mut order: Vec<usize> = (0..sections.len()).collect();
    order.sort_by(|&a, &b| infos[a].x.total_cmp(&infos[b].x));
    for w in order.windows(2) {
        let (a, b) = (&infos[w[0]], &infos[w[1]]);
        if (b.x - a.x).abs() <= COINCIDENT_REL * size {
            return Err(drawing_error(
                b.at.clone(),
                format!("stations {:?} and {:?} are both at x = {}", a.label, b.label, b.x),
                "one curve per station position",
            ));
        }
    }
    let mut out_sections = Vec::with_capacity(sections.len());
    let mut out_infos = Vec::with_capacity(sections.len());
    for k in order {
        let (label, pts, lines) = &sections[k];
        let (pts, lines) = match o.points {
            Some(n) => resample(pts, lines, n),
            None => dedupe(pts, lines, 2.0 * COINCIDENT_REL * size),
        };
        let mut info = infos[k].clone();
        info.points = pts.len();
        let lines = if lines.iter().all(|&l| l > 0) { lines } else { Vec::new() };
        out_sections.push(Section { label: label.clone(), points: pts, lines, column: None });
        out_infos.push(info);
    }
    let offsets = Offsets::new(sketch.source.clone(), o.units, out_sections);
    offsets.validate(2)?;
    Ok(Digitized { offsets, stations: out_infos, notes })
}

/// The model points of a station from keel to deck, the source line of each, and its side.
#[allow(clippy::too_many_arguments)]
fn station_points(
    sketch: &Sketch,
    f: &Found,
    x: f64,
    datum: P2,
    s: f64,
    ysign: f64,
    tol: f64,
) -> Result<(Vec<Vec3>, Vec<usize>, Side), HullError> {
    struct Run {
        pts: Vec<Vec3>,
        lines: Vec<usize>,
        side: Side,
        first: usize,
    }
    let mut runs = Vec::new();
    for c in &f.chains {
        let left = c.pts.iter().map(|p| datum[0] - p[0]).fold(f64::NEG_INFINITY, f64::max);
        let right = c.pts.iter().map(|p| p[0] - datum[0]).fold(f64::NEG_INFINITY, f64::max);
        let first = c.first_curve();
        if left > tol && right > tol {
            return Err(drawing_error(
                sketch.curves[first].at.clone(),
                format!(
                    "the curve of station {:?} ({}) crosses the centreline X = {}: it reaches {} drawing units left of it and {} right",
                    f.label,
                    sketch.curves[first].describe(),
                    crate::numfmt::format_short(datum[0]),
                    crate::numfmt::format_short(left),
                    crate::numfmt::format_short(right)
                ),
                "each station on one side of the centreline (aft stations left, fore stations right): check the datum X",
            ));
        }
        let side = if right > tol {
            Side::Fore
        } else if left > tol {
            Side::Aft
        } else {
            Side::Centreline
        };
        let mut pts: Vec<Vec3> =
            c.pts.iter().map(|p| Vec3::new(x, (p[0] - datum[0]).abs() * s, ysign * (p[1] - datum[1]) * s)).collect();
        let mut lines: Vec<usize> = c.src.iter().map(|&i| sketch.curves[i].at.line.unwrap_or(0)).collect();
        let (a, b) = (pts[0], pts[pts.len() - 1]);
        if a.z > b.z || (a.z == b.z && a.y > b.y) {
            pts.reverse();
            lines.reverse();
        }
        runs.push(Run { pts, lines, side, first });
    }
    let sides: Vec<Side> = runs.iter().map(|r| r.side).filter(|&s| s != Side::Centreline).collect();
    if sides.contains(&Side::Aft) && sides.contains(&Side::Fore) {
        return Err(drawing_error(
            sketch.curves[runs[0].first].at.clone(),
            format!("station {:?} is drawn on both sides of the centreline", f.label),
            "each station once, on one side (aft stations left, fore stations right)",
        ));
    }
    let side = sides.first().copied().unwrap_or(Side::Centreline);
    let zr = |r: &Run| {
        let lo = r.pts.iter().map(|p| p.z).fold(f64::INFINITY, f64::min);
        let hi = r.pts.iter().map(|p| p.z).fold(f64::NEG_INFINITY, f64::max);
        (lo, hi)
    };
    runs.sort_by(|a, b| zr(a).0.total_cmp(&zr(b).0));
    for w in runs.windows(2) {
        if zr(&w[1]).0 < zr(&w[0]).1 - tol * s {
            return Err(drawing_error(
                sketch.curves[w[1].first].at.clone(),
                format!(
                    "station {:?} has {} separate curves, and {} overlaps {} in height",
                    f.label,
                    runs.len(),
                    sketch.curves[w[1].first].describe(),
                    sketch.curves[w[0].first].describe()
                ),
                "one curve per station, its pieces meeting end to end (raise the join tolerance if their ends almost meet)",
            ));
        }
    }
    let mut pts = Vec::new();
    let mut lines = Vec::new();
    for r in runs {
        pts.extend(r.pts);
        lines.extend(r.lines);
    }
    Ok((pts, lines, side))
}

/// The diagonal of the box of all points.
fn model_size(sections: &[(String, Vec<Vec3>, Vec<usize>)]) -> f64 {
    let mut it = sections.iter().flat_map(|s| s.1.iter());
    let Some(&first) = it.next() else { return 0.0 };
    let (lo, hi) = it.fold((first, first), |(lo, hi), p| {
        (Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z)), Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z)))
    });
    (hi - lo).norm()
}

/// Drop points within `eps` of the previous kept point.
fn dedupe(pts: &[Vec3], lines: &[usize], eps: f64) -> (Vec<Vec3>, Vec<usize>) {
    let mut p: Vec<Vec3> = Vec::with_capacity(pts.len());
    let mut l = Vec::with_capacity(pts.len());
    for (q, &line) in pts.iter().zip(lines) {
        if p.last().is_none_or(|last| last.distance(*q) > eps) {
            p.push(*q);
            l.push(line);
        }
    }
    (p, l)
}

/// `n` points evenly spaced by arc length along the polyline `pts` (ends kept), each with the
/// source line of the polyline point before it.
fn resample(pts: &[Vec3], lines: &[usize], n: usize) -> (Vec<Vec3>, Vec<usize>) {
    let mut acc = vec![0.0];
    for w in pts.windows(2) {
        acc.push(acc[acc.len() - 1] + w[0].distance(w[1]));
    }
    let total = acc[acc.len() - 1];
    let mut out = Vec::with_capacity(n);
    let mut out_lines = Vec::with_capacity(n);
    let mut k = 0;
    for i in 0..n {
        let t = total * i as f64 / (n - 1) as f64;
        while k + 2 < acc.len() && acc[k + 1] < t {
            k += 1;
        }
        if pts.len() == 1 {
            out.push(pts[0]);
            out_lines.push(lines[0]);
            continue;
        }
        let seg = acc[k + 1] - acc[k];
        let u = if seg > 0.0 { ((t - acc[k]) / seg).clamp(0.0, 1.0) } else { 0.0 };
        let p = if i == n - 1 { pts[pts.len() - 1] } else { pts[k] + (pts[k + 1] - pts[k]) * u };
        out.push(p);
        out_lines.push(lines[k]);
    }
    (out, out_lines)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Resampling a straight line of length 3 in 4 points gives points 1 apart, ends kept.
    #[test]
    fn resampling_by_arc_length() {
        let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.5, 0.0), Vec3::new(0.0, 3.0, 0.0)];
        let (p, l) = resample(&pts, &[1, 2, 3], 4);
        let ys: Vec<f64> = p.iter().map(|q| q.y).collect();
        assert_eq!(ys, [0.0, 1.0, 2.0, 3.0]);
        assert_eq!(l, [1, 2, 2, 2]);
    }
}
