//! From drawn curves to offsets: scale, datum, station identification, sides, joining.
//!
//! # The mapping
//!
//! With `s` the model length of one drawing unit and `(X0, Y0)` the datum (the drawing point
//! where the body plan's centreline meets its baseline), a drawing point `(X, Y)` of a
//! station curve becomes
//!
//! ```text
//! y = |X - X0| s              (half-breadth: aft stations drawn left, fore ones right)
//! z = (Y - Y0) s              (DXF, y up)      z = (Y0 - Y) s     (SVG, y down)
//! ```
//!
//! and its station's `x`. For a scale `paper:model` (1:50 is `1:50`), `s = u / 1000 / m * model
//! / paper` with `u` the millimetres per drawing unit (from the file, or given) and `m` the
//! metres per output unit; for a scale given as drawing units per output unit `k`, `s = 1 / k`.
//!
//! # Tolerances (drawing units)
//!
//! `D` is the diagonal of the box of the curves considered. Curved pieces are flattened to
//! within [`DigitizeOptions::flatness`] (default `1e-6 D`, half a micrometre on an A3 sheet:
//! below the 1 µm the SVG writers round to). Two piece ends within
//! [`DigitizeOptions::join_tol`] (default `1e-4 D`) are the same point; a point within it of
//! the centreline `X = X0` is on the centreline, on neither side.
//!
//! # Joining
//!
//! A station may be drawn in pieces (a `LINE` for the flat of bottom, an `ARC` for the bilge,
//! a `LINE` up the side). Two pieces are joined where an end of one meets an end of the other
//! and no third end is there: several stations often start at one keel point, where nothing is
//! joined. Nor are two ends where the path would turn back by more than 150° (a cusp): that
//! is two stations meeting head on, e.g. at a common deck edge in a parallel middle body.
//! Before the pieces are sorted into stations (by label or by order) ends on the centreline
//! are not joined either, since every station may start there; within a layer or a
//! label, which is one station, they are. A station's curves that stay apart are put one above
//! the other (they must not overlap in height), each from its lower end up.

use std::cmp::Ordering;
use std::str::FromStr;

use nurbs::Vec3;

use super::geom::{polyline_dist, P2};
use super::{drawing_error, glob_match, Curve, Sketch};
use crate::error::{HullError, Location};
use crate::offsets::{Offsets, Section, COINCIDENT_REL};
use crate::units::Units;

/// The drawing's scale.
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum DrawingScale {
    /// `paper:model`, e.g. 1:50 is `{ paper: 1, model: 50 }`: a paper length in the drawing's
    /// units of length (see [`DigitizeOptions::drawing_unit_mm`]) stands for `model / paper`
    /// times it on the ship.
    Ratio { paper: f64, model: f64 },
    /// Drawing units per output unit (per metre for output in metres).
    UnitsPerModelUnit(f64),
}

impl FromStr for DrawingScale {
    type Err = HullError;

    /// `P:M` (e.g. `1:50`, `2:1`) or a plain number of drawing units per output unit.
    fn from_str(s: &str) -> Result<Self, HullError> {
        let bad = || {
            HullError::Config(format!(
                "scale {s:?} (expected paper:model such as 1:50, or drawing units per output unit such as 20)"
            ))
        };
        let num = |t: &str| t.trim().parse::<f64>().ok().filter(|v| v.is_finite() && *v > 0.0).ok_or_else(bad);
        match s.split_once(':') {
            Some((p, m)) => Ok(DrawingScale::Ratio { paper: num(p)?, model: num(m)? }),
            None => Ok(DrawingScale::UnitsPerModelUnit(num(s)?)),
        }
    }
}

/// How the station curves are told apart.
#[derive(Clone, Debug, PartialEq)]
pub enum StationIds {
    /// Each layer matching this glob (`*`, `?`; case-insensitive) holds one station, named by
    /// the layer.
    Layers(String),
    /// Each station curve has a text label next to it (the nearest curve to a label is its
    /// curve), or an SVG `<title>`/`id`, naming the station.
    Labels,
    /// The curves themselves, in this order, are the stations, named `0`, `1`, ...
    Order(CurveOrder),
}

/// The order of the station curves for [`StationIds::Order`].
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum CurveOrder {
    /// As they come in the file.
    Drawn,
    /// By layer name (numbers in names compared as numbers: `ST2` before `ST10`), then as
    /// drawn.
    Layer,
    /// The body plan's own order, from aft to fore: the curves left of the centreline from
    /// the narrowest (the aft end) to the widest, then those right of it from the widest to
    /// the narrowest (the bow). Curves on the centreline come first. Holds for hulls whose
    /// sections grow towards midships.
    BodyPlan,
}

/// The stations' x positions.
#[derive(Clone, Debug, PartialEq)]
pub enum StationX {
    /// One x per station: in the curve order for [`StationIds::Order`], else in the order of
    /// the station names (by their station number when they have one, see
    /// [`label_number`], else alphabetically).
    List(Vec<f64>),
    /// x by station name (layer or label; compared trimmed, case-insensitively).
    Map(Vec<(String, f64)>),
    /// `x = origin + n spacing`, `n` the station number of the name ([`label_number`]; the
    /// ordinal for [`StationIds::Order`]).
    Spacing { origin: f64, spacing: f64 },
}

/// Settings of [`digitize`].
#[derive(Clone, Debug, PartialEq)]
pub struct DigitizeOptions {
    /// The drawing's scale.
    pub scale: DrawingScale,
    /// Millimetres per drawing unit, overriding what the file says (needed for a
    /// [`DrawingScale::Ratio`] when the file does not say it).
    pub drawing_unit_mm: Option<f64>,
    /// The drawing point where the body plan's centreline meets the baseline.
    pub datum: P2,
    /// The length unit of the output offsets.
    pub units: Units,
    /// Only curves on layers matching this glob (all when `None`).
    pub layers: Option<String>,
    /// How stations are told apart.
    pub stations: StationIds,
    /// Where the stations are.
    pub x: StationX,
    /// Resample each station to this many points evenly spaced along it (at least 2); `None`
    /// keeps the drawn points (polyline vertices, and points on curved pieces at the
    /// flatness tolerance).
    pub points: Option<usize>,
    /// Piece ends closer than this are joined, and points this close to the centreline are on
    /// it (drawing units; default `1e-4` of the drawing's diagonal).
    pub join_tol: Option<f64>,
    /// Curved pieces are flattened to within this (drawing units; default `1e-6` of the
    /// drawing's diagonal).
    pub flatness: Option<f64>,
    /// Labels farther than this from every curve are ignored (drawing units; default no limit).
    pub label_distance: Option<f64>,
}

impl DigitizeOptions {
    /// Options with the defaults: output in metres, every layer, drawn points kept, default
    /// tolerances.
    pub fn new(scale: DrawingScale, datum: P2, stations: StationIds, x: StationX) -> Self {
        DigitizeOptions {
            scale,
            drawing_unit_mm: None,
            datum,
            units: Units::Metre,
            layers: None,
            stations,
            x,
            points: None,
            join_tol: None,
            flatness: None,
            label_distance: None,
        }
    }
}

/// The side of the centreline a station is drawn on.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Side {
    /// Left of the centreline: the aft body, by the body plan convention.
    Aft,
    /// Right of the centreline: the fore body.
    Fore,
    /// On the centreline (a station with no breadth).
    Centreline,
}

/// What was found for one station.
#[derive(Clone, Debug, PartialEq)]
pub struct StationInfo {
    /// The station's name (layer, label, or ordinal).
    pub label: String,
    /// Its x.
    pub x: f64,
    /// The side it is drawn on.
    pub side: Side,
    /// The drawn curves (entities, subpaths) it was made of.
    pub curves: usize,
    /// Its points in the offsets.
    pub points: usize,
    /// Where its first curve is in the file.
    pub at: Location,
}

/// The result of [`digitize`].
#[derive(Clone, Debug, PartialEq)]
pub struct Digitized {
    /// The sections, in order of x, each from keel to deck.
    pub offsets: Offsets,
    /// One entry per section, same order.
    pub stations: Vec<StationInfo>,
    /// What was skipped and why (the reader's notes first).
    pub notes: Vec<String>,
}

/// The station number in a name: a number, optionally after `station`, `stn`, `sta`, `st`,
/// `s` or `#` (any case) and a space, `.` or `_`; the number may be negative, decimal, or
/// have a fraction (`9 1/2`, `9½`, `9¼`, `9¾`). `ST10` is 10, `Station 7.5` is 7.5, `9 1/2`
/// is 9.5; `path12` and `WL1` have none.
pub fn label_number(name: &str) -> Option<f64> {
    let lower = name.trim().to_lowercase();
    let mut t = lower.as_str();
    for prefix in ["station", "stn", "sta", "st", "s", "#"] {
        if let Some(r) = t.strip_prefix(prefix) {
            t = r;
            break;
        }
    }
    let t = t.trim_start_matches(['.', '_', ' ']);
    let (t, frac) = match t.char_indices().last() {
        Some((i, '½')) => (&t[..i], 0.5),
        Some((i, '¼')) => (&t[..i], 0.25),
        Some((i, '¾')) => (&t[..i], 0.75),
        _ => (t, 0.0),
    };
    let whole = |w: &str| if w.is_empty() && frac > 0.0 { Some(0.0) } else { w.parse::<f64>().ok() };
    let v = match t.split_once(' ') {
        Some((w, f)) if frac == 0.0 => {
            let (a, b) = f.trim().split_once('/')?;
            let (a, b) = (a.parse::<u32>().ok()?, b.parse::<u32>().ok()?);
            if b == 0 || a >= b {
                return None;
            }
            let w = w.parse::<f64>().ok()?;
            let sign = if w.is_sign_negative() { -1.0 } else { 1.0 };
            w + sign * f64::from(a) / f64::from(b)
        }
        Some(_) => return None,
        None => {
            let w = whole(t)?;
            w + if t.starts_with('-') { -frac } else { frac }
        }
    };
    v.is_finite().then_some(v)
}

/// Compare station names: by station number when both have one, else alphabetically
/// (case-insensitive).
fn name_order(a: &str, b: &str) -> Ordering {
    match (label_number(a), label_number(b)) {
        (Some(x), Some(y)) => x.total_cmp(&y),
        _ => a.to_lowercase().cmp(&b.to_lowercase()),
    }
}

/// `cos 30°`: pieces whose joint would turn the path by more than 150° are not joined.
const CUSP_COS: f64 = 0.866_025_403_784_438_6;

/// A run of joined pieces: its points and, per point, the index of the curve it came from.
#[derive(Clone, Debug)]
struct Chain {
    pts: Vec<P2>,
    src: Vec<usize>,
}

impl Chain {
    fn first_curve(&self) -> usize {
        self.src.iter().copied().min().unwrap_or(0)
    }
    fn curves(&self) -> Vec<usize> {
        let mut c = self.src.clone();
        c.sort_unstable();
        c.dedup();
        c
    }
}

/// Join chains end to end where exactly two ends meet within `tol` (see the module docs);
/// ends within `tol` of `x = cl` are left alone unless `cl` is `None`. Chains that close on
/// themselves are returned in `loops`.
fn join(chains: Vec<Chain>, tol: f64, cl: Option<f64>) -> (Vec<Chain>, Vec<Chain>) {
    let n = chains.len();
    let end = |e: usize| {
        let c = &chains[e / 2];
        if e.is_multiple_of(2) {
            c.pts[0]
        } else {
            c.pts[c.pts.len() - 1]
        }
    };
    // Candidates of each end: the ends of other chains within tol (sweep along x).
    let mut order: Vec<usize> = (0..2 * n).collect();
    order.sort_by(|&a, &b| end(a)[0].total_cmp(&end(b)[0]));
    let mut cand: Vec<Vec<usize>> = vec![Vec::new(); 2 * n];
    for (k, &a) in order.iter().enumerate() {
        let pa = end(a);
        for &b in &order[k + 1..] {
            let pb = end(b);
            if pb[0] - pa[0] > tol {
                break;
            }
            if a / 2 != b / 2 && (pa[0] - pb[0]).hypot(pa[1] - pb[1]) <= tol {
                cand[a].push(b);
                cand[b].push(a);
            }
        }
    }
    let on_cl = |e: usize| cl.is_some_and(|x0| (end(e)[0] - x0).abs() <= tol);
    // The direction along the chain into end e (from its neighbouring point).
    let into = |e: usize| {
        let p = &chains[e / 2].pts;
        let (a, b) = if e.is_multiple_of(2) { (p[1], p[0]) } else { (p[p.len() - 2], p[p.len() - 1]) };
        [b[0] - a[0], b[1] - a[1]]
    };
    // Joining e to f turns the path from into(e) to -into(f); a turn of more than 150 degrees
    // is a cusp: two curves meeting head on (two stations ending at one deck point), not the
    // pieces of one.
    let cusp = |e: usize, f: usize| {
        let (a, b) = (into(e), into(f));
        let (na, nb) = (a[0].hypot(a[1]), b[0].hypot(b[1]));
        na > 0.0 && nb > 0.0 && -(a[0] * b[0] + a[1] * b[1]) / (na * nb) < -CUSP_COS
    };
    let link: Vec<Option<usize>> = (0..2 * n)
        .map(|e| match cand[e][..] {
            [f] if cand[f][..] == [e] && !on_cl(e) && !on_cl(f) && !cusp(e, f) => Some(f),
            _ => None,
        })
        .collect();
    let mut used = vec![false; n];
    let mut out = Vec::new();
    let walk = |start_end: usize, used: &mut Vec<bool>| {
        let mut chain = Chain { pts: Vec::new(), src: Vec::new() };
        let mut e_in = start_end;
        loop {
            let i = e_in / 2;
            if used[i] {
                break;
            }
            used[i] = true;
            let c = &chains[i];
            let idx: Vec<usize> =
                if e_in.is_multiple_of(2) { (0..c.pts.len()).collect() } else { (0..c.pts.len()).rev().collect() };
            let skip = usize::from(!chain.pts.is_empty());
            for &k in &idx[skip..] {
                chain.pts.push(c.pts[k]);
                chain.src.push(c.src[k]);
            }
            match link[e_in ^ 1] {
                Some(f) => e_in = f,
                None => break,
            }
        }
        chain
    };
    // Open runs start at an end without a link.
    for e in 0..2 * n {
        if !used[e / 2] && link[e].is_none() {
            out.push(walk(e, &mut used));
        }
    }
    // What is left is closed.
    let mut loops = Vec::new();
    for i in 0..n {
        if !used[i] {
            loops.push(walk(2 * i, &mut used));
        }
    }
    (out, loops)
}

/// Model length per drawing unit.
fn model_per_unit(sketch: &Sketch, o: &DigitizeOptions) -> Result<f64, HullError> {
    let s = match o.scale {
        DrawingScale::UnitsPerModelUnit(k) => {
            if !(k.is_finite() && k > 0.0) {
                return Err(HullError::Config(format!(
                    "scale {k} drawing units per {} (expected a number > 0)",
                    o.units.symbol()
                )));
            }
            1.0 / k
        }
        DrawingScale::Ratio { paper, model } => {
            if !(paper.is_finite() && paper > 0.0 && model.is_finite() && model > 0.0) {
                return Err(HullError::Config(format!(
                    "scale {paper}:{model} (expected two numbers > 0 such as 1:50)"
                )));
            }
            let Some(u) = o.drawing_unit_mm.or(sketch.unit_mm) else {
                return Err(HullError::Config(format!(
                    "{}: the drawing does not say its unit of length, so the scale {paper}:{model} cannot be applied \
                     (expected the drawing units given, e.g. --drawing-units mm, or the scale as drawing units per {})",
                    sketch.source,
                    o.units.symbol()
                )));
            };
            if !(u.is_finite() && u > 0.0) {
                return Err(HullError::Config(format!("drawing unit of {u} mm (expected a length > 0)")));
            }
            u / 1000.0 / o.units.metres_per_unit() * model / paper
        }
    };
    Ok(s)
}

/// A station found in the drawing, before its x is known.
struct Found {
    label: String,
    chains: Vec<Chain>,
}

/// Digitise the station curves of `sketch` into offsets (see the module docs).
///
/// # Errors
/// [`HullError::Config`] for a scale or datum that cannot work (a ratio scale on a drawing
/// that does not say its units and none given, non-positive values), a station count other
/// than the list of positions, station names with [`StationX::Map`] for
/// [`StationIds::Order`], or a resampling count below 2. [`HullError::Input`] with
/// [`crate::InputErrorKind::Drawing`], located at the drawn curve, for: no curve on the
/// selected layers, no station found, a station not among the given names ("unknown
/// station"), a name without a station number with [`StationX::Spacing`], a curve that
/// crosses the centreline, a station drawn on both sides, two curves of one station that
/// overlap in height, two labels on one curve, and two stations at the same x. Then those of
/// [`Offsets::validate`].
pub fn digitize(sketch: &Sketch, o: &DigitizeOptions) -> Result<Digitized, HullError> {
    let s = model_per_unit(sketch, o)?;
    let [x0, y0] = o.datum;
    if !(x0.is_finite() && y0.is_finite()) {
        return Err(HullError::Config(format!("datum {x0},{y0} (expected two finite numbers X,Y)")));
    }
    if let Some(n) = o.points {
        if n < 2 {
            return Err(HullError::Config(format!("{n} points per station (expected at least 2)")));
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

/// The labelled stations of [`StationIds::Labels`].
fn by_labels(
    sketch: &Sketch,
    o: &DigitizeOptions,
    chains: Vec<Chain>,
    tol: f64,
    notes: &mut Vec<String>,
) -> Result<Vec<Found>, HullError> {
    let accepted = |t: &str| match &o.x {
        StationX::Map(m) => m.iter().any(|(k, _)| k.trim().eq_ignore_ascii_case(t.trim())),
        _ => label_number(t).is_some(),
    };
    // Names of the curves themselves (SVG titles and ids) first.
    let mut label: Vec<Option<(String, Location)>> = chains
        .iter()
        .map(|c| {
            c.curves().into_iter().find_map(|i| {
                let cv = &sketch.curves[i];
                cv.name.as_ref().filter(|n| accepted(n)).map(|n| (n.clone(), cv.at.clone()))
            })
        })
        .collect();
    let named: Vec<bool> = label.iter().map(Option::is_some).collect();
    let limit = o.label_distance.filter(|d| d.is_finite() && *d >= 0.0).unwrap_or(f64::INFINITY);
    let mut far = 0;
    for l in sketch.labels.iter().filter(|l| accepted(&l.text)) {
        let nearest = chains
            .iter()
            .enumerate()
            .filter(|(k, _)| !named[*k])
            .map(|(k, c)| (k, polyline_dist(l.at, &c.pts)))
            .min_by(|a, b| a.1.total_cmp(&b.1));
        match nearest {
            Some((k, d)) if d <= limit => match &label[k] {
                Some((t, at)) if !t.trim().eq_ignore_ascii_case(l.text.trim()) => {
                    return Err(drawing_error(
                        l.loc.clone(),
                        format!(
                            "label {:?} and label {t:?} (at {at}) are both nearest to {}",
                            l.text,
                            sketch.curves[chains[k].first_curve()].describe()
                        ),
                        "one label per station curve: move each label next to its curve, or limit --label-distance",
                    ))
                }
                Some(_) => {}
                None => label[k] = Some((l.text.clone(), l.loc.clone())),
            },
            _ => far += 1,
        }
    }
    if far > 0 {
        notes.push(format!("{far} station label(s) farther than {limit} drawing units from every curve ignored"));
    }
    let mut groups: Vec<(String, Vec<Chain>)> = Vec::new();
    let mut unlabelled = Vec::new();
    for (c, l) in chains.into_iter().zip(label) {
        match l {
            Some((t, _)) => match groups.iter_mut().find(|g| g.0.trim().eq_ignore_ascii_case(t.trim())) {
                Some(g) => g.1.push(c),
                None => groups.push((t.trim().to_string(), vec![c])),
            },
            None => unlabelled.push(c.first_curve()),
        }
    }
    if let Some(first) = unlabelled.iter().min() {
        notes.push(format!(
            "{} curve(s) without a station label skipped, first {}",
            unlabelled.len(),
            sketch.curves[*first].describe()
        ));
    }
    let mut found = Vec::new();
    for (label, chains) in groups {
        let (chains, loops) = join(chains, tol, None);
        for l in loops {
            notes.push(format!(
                "station {label:?}: closed loop skipped, first {}",
                sketch.curves[l.first_curve()].describe()
            ));
        }
        if !chains.is_empty() {
            found.push(Found { label, chains });
        }
    }
    Ok(found)
}

/// Sort the chains of [`StationIds::Order`].
fn order_chains(sketch: &Sketch, chains: &mut [Chain], order: CurveOrder, x0: f64, tol: f64) {
    match order {
        CurveOrder::Drawn => chains.sort_by_key(Chain::first_curve),
        CurveOrder::Layer => chains.sort_by(|a, b| {
            name_order(&sketch.curves[a.first_curve()].layer, &sketch.curves[b.first_curve()].layer)
                .then(a.first_curve().cmp(&b.first_curve()))
        }),
        CurveOrder::BodyPlan => {
            // Signed reach: -(widest) for the left (aft), +(widest) for the right; aft from
            // the narrowest (closest to 0 from below... i.e. reach -small first), fore widest first.
            let key = |c: &Chain| {
                let left = c.pts.iter().map(|p| x0 - p[0]).fold(0.0, f64::max);
                let right = c.pts.iter().map(|p| p[0] - x0).fold(0.0, f64::max);
                if right > tol {
                    (2, -right)
                } else if left > tol {
                    (1, left)
                } else {
                    (0, 0.0)
                }
            };
            chains.sort_by(|a, b| {
                let (ka, kb) = (key(a), key(b));
                ka.0.cmp(&kb.0).then(ka.1.total_cmp(&kb.1)).then(a.first_curve().cmp(&b.first_curve()))
            });
        }
    }
}

/// The x of each found station (and `found` sorted to the list's order for lists).
fn station_xs(
    sketch: &Sketch,
    o: &DigitizeOptions,
    found: &mut [Found],
    notes: &mut Vec<String>,
) -> Result<Vec<f64>, HullError> {
    let by_order = matches!(o.stations, StationIds::Order(_));
    let at = |f: &Found| sketch.curves[f.chains[0].first_curve()].at.clone();
    match &o.x {
        StationX::List(xs) => {
            if !by_order {
                found.sort_by(|a, b| name_order(&a.label, &b.label));
            }
            if xs.len() != found.len() {
                let names: Vec<&str> = found.iter().map(|f| f.label.as_str()).collect();
                return Err(HullError::Config(format!(
                    "{}: {} station curves found ({}) and {} station positions given (expected one position per station, in that order)",
                    sketch.source,
                    found.len(),
                    names.join(", "),
                    xs.len()
                )));
            }
            if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
                return Err(HullError::Config(format!("station position {x} (expected finite numbers)")));
            }
            Ok(xs.clone())
        }
        StationX::Map(map) => {
            if by_order {
                return Err(HullError::Config(
                    "stations told apart by their order have no names: give their positions as a list x1,x2,... (expected no NAME=x entries)".into(),
                ));
            }
            let mut out = Vec::with_capacity(found.len());
            for f in found.iter() {
                match map.iter().find(|(k, _)| k.trim().eq_ignore_ascii_case(f.label.trim())) {
                    Some((_, x)) if x.is_finite() => out.push(*x),
                    Some((k, x)) => {
                        return Err(HullError::Config(format!("station {k}={x} (expected a finite position)")))
                    }
                    None => {
                        let names: Vec<&str> = map.iter().map(|(k, _)| k.as_str()).collect();
                        return Err(drawing_error(
                            at(f),
                            format!(
                                "unknown station {:?}: it is not among the stations given ({})",
                                f.label,
                                names.join(", ")
                            ),
                            "a position for every station drawn: add it to the station list, or narrow the layers",
                        ));
                    }
                }
            }
            for (k, _) in map {
                if !found.iter().any(|f| f.label.trim().eq_ignore_ascii_case(k.trim())) {
                    notes.push(format!("station {k:?} was given but is not in the drawing"));
                }
            }
            Ok(out)
        }
        StationX::Spacing { origin, spacing } => {
            if !(origin.is_finite() && spacing.is_finite() && *spacing != 0.0) {
                return Err(HullError::Config(format!(
                    "station spacing {spacing} from {origin} (expected finite numbers, a spacing other than 0)"
                )));
            }
            found
                .iter()
                .enumerate()
                .map(|(k, f)| {
                    let n = if by_order { Some(k as f64) } else { label_number(&f.label) };
                    n.map(|n| origin + n * spacing).ok_or_else(|| {
                        drawing_error(
                            at(f),
                            format!("station {:?} has no station number", f.label),
                            "names such as 7, ST7, Station 7.5 or 9 1/2 with a station spacing, or the positions listed",
                        )
                    })
                })
                .collect()
        }
    }
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

    #[test]
    fn station_numbers_in_names() {
        for (name, n) in [
            ("7", Some(7.0)),
            ("ST10", Some(10.0)),
            ("st 3", Some(3.0)),
            ("Station 7.5", Some(7.5)),
            ("STN_2", Some(2.0)),
            ("St. 4", Some(4.0)),
            ("9 1/2", Some(9.5)),
            ("9½", Some(9.5)),
            ("½", Some(0.5)),
            ("-1", Some(-1.0)),
            ("ST-1", Some(-1.0)),
            ("#12", Some(12.0)),
            ("path12", None),
            ("WL1", None),
            ("CL", None),
            ("9 1/0", None),
            ("", None),
        ] {
            assert_eq!(label_number(name), n, "{name:?}");
        }
        assert_eq!(name_order("ST2", "ST10"), Ordering::Less);
        assert_eq!(name_order("aft", "Bow"), Ordering::Less);
    }

    #[test]
    fn scales_parse() {
        assert_eq!("1:50".parse::<DrawingScale>().ok(), Some(DrawingScale::Ratio { paper: 1.0, model: 50.0 }));
        assert_eq!("20".parse::<DrawingScale>().ok(), Some(DrawingScale::UnitsPerModelUnit(20.0)));
        for bad in ["1:0", "x", "-3", "1:", "inf"] {
            assert!(bad.parse::<DrawingScale>().is_err(), "{bad}");
        }
    }

    fn chain(pts: &[P2], id: usize) -> Chain {
        Chain { pts: pts.to_vec(), src: vec![id; pts.len()] }
    }

    /// Three pieces of one curve, shuffled and reversed, join into one run; two runs that
    /// start at one centreline point stay apart when the centreline is guarded, and a third
    /// end at a point blocks joining there.
    #[test]
    fn joining_pieces() {
        let a = chain(&[[0.0, 0.0], [1.0, 0.0]], 0);
        let b = chain(&[[2.0, 1.0], [1.0, 0.0]], 1);
        let c = chain(&[[2.0, 1.0], [2.0, 3.0]], 2);
        let (runs, loops) = join(vec![c, a, b], 1e-9, None);
        assert!(loops.is_empty());
        assert_eq!(runs.len(), 1);
        let p = &runs[0].pts;
        let ends = [p[0], p[p.len() - 1]];
        assert!(ends.contains(&[0.0, 0.0]) && ends.contains(&[2.0, 3.0]), "{p:?}");
        assert_eq!(p.len(), 4);

        let l = chain(&[[0.0, 0.0], [-1.0, 1.0]], 0);
        let r = chain(&[[0.0, 0.0], [1.0, 1.0]], 1);
        assert_eq!(join(vec![l.clone(), r.clone()], 1e-9, Some(0.0)).0.len(), 2);
        assert_eq!(join(vec![l.clone(), r.clone()], 1e-9, None).0.len(), 1);
        let third = chain(&[[0.0, 0.0], [0.0, 2.0]], 2);
        assert_eq!(join(vec![l, r, third], 1e-9, None).0.len(), 3);

        let sq = vec![
            chain(&[[0.0, 0.0], [1.0, 0.0]], 0),
            chain(&[[1.0, 0.0], [0.0, 1.0]], 1),
            chain(&[[0.0, 1.0], [0.0, 0.0]], 2),
        ];
        let (runs, loops) = join(sq, 1e-9, None);
        assert!(runs.is_empty());
        assert_eq!(loops.len(), 1);
    }

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
