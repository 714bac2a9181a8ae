//! Slicing a hull mesh at stations `x = const` into sections for the fit.
//!
//! The rest of this module's documentation is on [`slice_mesh`], where the library's users read it.

use std::collections::HashMap;
use std::fmt;
use std::str::FromStr;

use nurbs::Vec3;
use rayon::prelude::*;

use super::TriMesh;
use crate::error::{HullError, SliceKind};
use crate::offsets::{Offsets, Section};
use crate::units::Units;

/// End stations of [`Stations::Count`] are moved in by this fraction of the x range.
pub const END_INSET: f64 = 1e-5;
/// A point with `|y|` at most this fraction of the mesh size lies on the centre plane.
pub const CENTRE_REL: f64 = 1e-6;
/// Consecutive section points closer than this fraction of the mesh size are merged.
pub const MERGE_REL: f64 = 1e-9;
/// A section shorter than this fraction of the mesh size is degenerate and dropped.
pub const DEGENERATE_REL: f64 = 1e-6;
/// Most stations [`Stations::Count`] accepts.
pub const MAX_STATIONS: usize = 100_000;

/// How [`Stations::Count`] spaces the stations.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Spacing {
    /// Equal steps in x.
    Uniform,
    /// Cosine (Chebyshev-Lobatto) spacing, denser at the ends.
    #[default]
    Cosine,
}

impl FromStr for Spacing {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "uniform" => Ok(Spacing::Uniform),
            "cosine" => Ok(Spacing::Cosine),
            _ => Err(format!("unknown spacing `{s}` (expected uniform or cosine)")),
        }
    }
}

impl fmt::Display for Spacing {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Spacing::Uniform => "uniform",
            Spacing::Cosine => "cosine",
        })
    }
}

/// Where the stations are.
#[derive(Clone, Debug, PartialEq)]
pub enum Stations {
    /// `n` stations over the mesh's x range (see [`slice_mesh`]).
    Count {
        /// Number of stations, at least 2.
        n: usize,
        /// Their spacing.
        spacing: Spacing,
    },
    /// Stations at the given x, strictly increasing.
    At(Vec<f64>),
}

/// How the sections' points are spread along them.
#[derive(Clone, Copy, Debug, Default, PartialEq, Eq)]
pub enum Resample {
    /// Equal steps in arc length (the default).
    ///
    /// Measured on the DTC (41 cosine stations, `crates/hull/tests/io/mesh.rs`): interpolation and
    /// every approximation tried keep the wetted surface within 0.6 % of the mesh's.
    #[default]
    ArcLength,
    /// Equal steps in `s + (L/pi) theta`: arc length `s` plus the turning `theta` (radians,
    /// absolute, accumulated along the section) scaled by the section's length `L` over pi,
    /// so that a section turning through a right angle spends a third of its points on the
    /// turn: points gather at the bilge, the bulb and knuckles.
    ///
    /// Each section then gathers its points differently, so points of the same index on
    /// neighbouring sections no longer correspond, and a skinned surface can fold between
    /// them: on the DTC the wetted surface of some approximations came out 20 to 30 % too
    /// large (the volume stayed within 0.1 %). Use it for drawing sections, not for skinning.
    Adaptive,
}

impl FromStr for Resample {
    type Err = String;
    fn from_str(s: &str) -> Result<Self, String> {
        match s.trim().to_ascii_lowercase().as_str() {
            "arc" | "arclength" | "arc-length" => Ok(Resample::ArcLength),
            "adaptive" => Ok(Resample::Adaptive),
            _ => Err(format!("unknown resampling `{s}` (expected arc-length or adaptive)")),
        }
    }
}

/// Settings of [`slice_mesh`].
#[derive(Clone, Debug, PartialEq)]
pub struct SliceOptions {
    /// Where to cut.
    pub stations: Stations,
    /// Points per section after resampling, at least 2 (default 30).
    pub points: usize,
    /// How the points are spread (default [`Resample::ArcLength`]).
    pub resample: Resample,
    /// End the sections where they first rise through this height (default: at the deck edge).
    pub max_z: Option<f64>,
    /// Largest slope of the deck from the horizontal, degrees (default 30; see [`slice_mesh`]).
    pub deck_angle: f64,
    /// Units label of the offsets.
    pub units: Units,
}

impl Default for SliceOptions {
    /// 41 cosine-spaced stations of 30 points equally spaced in arc length, deck cut at 30
    /// degrees, metres.
    fn default() -> Self {
        SliceOptions {
            stations: Stations::Count { n: 41, spacing: Spacing::Cosine },
            points: 30,
            resample: Resample::ArcLength,
            max_z: None,
            deck_angle: 30.0,
            units: Units::Metre,
        }
    }
}

/// An end station whose cut is shorter than this share of the next station's is dropped
/// ([`slice_mesh`]): the hull ends in a point there (the top of a raked stern, the tip of a
/// flared deck), and the section's points, crowded into a few centimetres, hook the skin or
/// spike its curvature. The DTMB 5415 mesh's end cuts are 2.1 and 2.2 % of their neighbours'
/// (68 and 6 mm long); the DTC's and the Wigley mesh's 85 to 100 %.
pub const END_SLIVER: f64 = 0.05;

/// A station left out, and why.
#[derive(Clone, Debug, PartialEq)]
pub struct DroppedStation {
    /// Its label (its 1-based number among the stations).
    pub label: String,
    /// Its x.
    pub x: f64,
    /// Why it was dropped.
    pub reason: String,
}

/// What was done at a kept station.
#[derive(Clone, Debug, PartialEq)]
pub struct StationInfo {
    /// Its label (its 1-based number among the stations).
    pub label: String,
    /// Its x.
    pub x: f64,
    /// Open pieces joined into the section (1 for a simple section).
    pub pieces: usize,
    /// Closed loops off the centre plane that were skipped.
    pub skipped_loops: usize,
    /// True if a deck was cut off.
    pub deck_removed: bool,
    /// True if the section does not end on the centre plane or at a deck edge: the mesh is open
    /// at the top there (or has a hole).
    pub open_top: bool,
    /// Length of the section before resampling.
    pub length: f64,
}

/// The sections of a mesh, with what was dropped.
#[derive(Clone, Debug, PartialEq)]
pub struct SliceOutcome {
    /// The sections, keel to deck edge, in order along x; `source` is the mesh's.
    pub offsets: Offsets,
    /// One entry per section of `offsets`.
    pub stations: Vec<StationInfo>,
    /// Stations left out, with the reason.
    pub dropped: Vec<DroppedStation>,
}

impl SliceOutcome {
    /// One line per dropped station and per station whose pieces were joined or loops
    /// skipped, for the user; first, where most sections have their end nearer the centre
    /// plane (the keel) above their other end (the deck edge), that the mesh looks upside down:
    /// a mesh stored with z down, as FastShip's container ship and dragger are (37 and 40 of
    /// their 40 sections; none of any upright hull of `testdata/mesh/`).
    pub fn warnings(&self) -> Vec<String> {
        let f = crate::numfmt::format_short;
        let sections = &self.offsets.sections;
        let keel_on_top = |points: &[nurbs::Vec3]| match (points.first(), points.last()) {
            (Some(a), Some(b)) => {
                let (keel, edge) = if a.y <= b.y { (a, b) } else { (b, a) };
                keel.z > edge.z
            }
            _ => false,
        };
        let down = sections.iter().filter(|s| keel_on_top(&s.points)).count();
        let mut out = Vec::new();
        if 2 * down > sections.len() {
            out.push(format!(
                "{down} of {} sections have their end nearer the centre plane (the keel) above their other end \
                 (the deck edge): the mesh looks upside down (expected z up from the keel; try --axes x,y,-z)",
                sections.len()
            ));
        }
        out.extend(
            self.dropped.iter().map(|d| format!("station {} at x = {}: dropped: {}", d.label, f(d.x), d.reason)),
        );
        for s in &self.stations {
            if s.pieces > 1 {
                out.push(format!(
                    "station {} at x = {}: {} pieces joined along the centre plane (bulb, skeg or aperture)",
                    s.label,
                    f(s.x),
                    s.pieces
                ));
            }
            if s.skipped_loops > 0 {
                out.push(format!(
                    "station {} at x = {}: {} closed loop(s) off the centre plane skipped",
                    s.label,
                    f(s.x),
                    s.skipped_loops
                ));
            }
        }
        out
    }
}

/// The x of `n` stations over `[x_min, x_max]`, ends moved in by [`END_INSET`] of the range
/// (see [`slice_mesh`]); one station is put in the middle.
///
/// # Errors
/// [`HullError::Slice`] for `n == 0` or above [`MAX_STATIONS`], or a range that is not finite
/// and increasing.
pub fn station_positions(x_min: f64, x_max: f64, n: usize, spacing: Spacing) -> Result<Vec<f64>, HullError> {
    if n == 0 || n > MAX_STATIONS {
        return Err(HullError::Slice(SliceKind::StationCount { count: n, max: MAX_STATIONS }));
    }
    if !(x_min.is_finite() && x_max.is_finite() && x_max > x_min) {
        return Err(HullError::Slice(SliceKind::StationRange { min: x_min, max: x_max }));
    }
    let inset = END_INSET * (x_max - x_min);
    let (a, b) = (x_min + inset, x_max - inset);
    if n == 1 {
        return Ok(vec![0.5 * (a + b)]);
    }
    let last = (n - 1) as f64;
    Ok((0..n)
        .map(|i| {
            let t = match spacing {
                Spacing::Uniform => i as f64 / last,
                Spacing::Cosine => 0.5 * (1.0 - (std::f64::consts::PI * i as f64 / last).cos()),
            };
            // Exact end points, whatever the rounding of the formula.
            if i == 0 {
                a
            } else if i + 1 == n {
                b
            } else {
                a + (b - a) * t
            }
        })
        .collect())
}

/// Slices `mesh` into sections, keel to deck edge on the starboard side.
///
/// # What a section is
///
/// The section at station `x = c` is the cut of the mesh by that plane, kept on the starboard
/// side (`y >= 0`), as **one polyline from the keel to the deck edge**:
///
/// 1. *Cut.* Every triangle with a vertex on each side of the plane gives one segment. A vertex
///    exactly on the plane counts as lying on the forward side (`x >= c`), a symbolic
///    perturbation of the plane to `c - 0`: no triangle is ever cut through a vertex, every
///    cut triangle crosses exactly two of its edges, and each segment end is identified by the
///    mesh edge it lies on, so the segments of a closed mesh join into closed loops whatever
///    the tessellation (Hoffmann, *Geometric and Solid Modeling*, 1989, ch. 4 on symbolic
///    perturbation). A triangle lying in the plane is not cut. The cut point on edge `(i, j)`,
///    `i < j`, is `v_i + t (v_j - v_i)` with `t = (c - x_i) / (x_j - x_i)`, computed the same
///    way from both triangles that share the edge.
/// 2. *Starboard half.* A segment with both ends at `y >= 0` is kept (unless both are at
///    `y = 0`: it lies in the centre plane and bounds no half-breadth), one crossing `y = 0`
///    is clipped there, one at `y <= 0` is dropped. The clip points are chain ends.
/// 3. *Chain.* Segments sharing an edge are joined (a hash map of edge ids). Each open chain
///    is a *piece*: on a closed symmetric hull a piece runs from the centre plane to the centre
///    plane. A piece starts at its end on the centre plane (`|y| <= 1e-6` of the mesh size)
///    when it has only one, otherwise at its lower end. Closed loops (wholly off the centre
///    plane: a bilge keel, a pod, a demihull) are skipped and listed in the station's notes.
/// 4. *Join.* Pieces are joined in order of the height of their start; the joins run along
///    the centre plane where, at the bow, a bulb and the stem above it are cut in two pieces,
///    or aft, a skeg below an aperture. The section thus starts at the **keel**, the lowest
///    point of the cut on the centre plane: a cut that starts on the plane and first runs down
///    it (a sliver at a pointed end, thinner than the plane's tolerance: the OpenFOAM Wigley
///    mesh 1e-5 of its length from the stem) starts at the bottom of that run, on the plane.
/// 5. *Deck off.* When the section ends on the centre plane (a closed mesh, cut through the
///    deck), the deck is cut off: walking back from that end, segments that go outward
///    (`y` growing) and rise or fall by at most `tan(deck_angle)` times their outward run are
///    deck; the section ends at the **deck edge** (the sheer), where the side turns down. A
///    mesh open at the top ends where the cut ends.
/// 6. *Height limit.* With [`SliceOptions::max_z`], the section ends where it first rises
///    through that height.
/// 7. *Resample.* Consecutive points closer than 1e-9 of the mesh size are merged, then the
///    polyline is resampled to [`SliceOptions::points`] points, both ends kept, equally spaced
///    in arc length or in arc length plus turning ([`Resample`]).
///
/// A station is dropped, with the reason in [`SliceOutcome::dropped`], when it misses the
/// mesh, has nothing on the starboard side but closed loops, lies wholly above `max_z`, is
/// deck only, or is shorter than 1e-6 of the mesh size; and an end station (first or last of
/// those kept, again while more than two are left) whose cut is shorter than [`END_SLIVER`]
/// (5 %) of the next station's: a sliver at a point of the hull.
///
/// # Where the stations go
///
/// [`Stations::Count`] puts `n` stations over the mesh's x range, ends included but moved in
/// by 1e-5 of the length so that the end stations cut the mesh (a transom at constant x lies
/// in the plane of an end station otherwise, and a pointed end would give one point):
/// [`Spacing::Uniform`] equally spaced, [`Spacing::Cosine`] at `x_m - (L/2) cos(pi i/(n-1))`,
/// denser towards the ends where the shape changes fastest (bow, bulb, stern). [`Stations::At`]
/// takes the positions given.
///
/// # Errors
/// [`HullError::Slice`] for fewer than 2 points per section or more than
/// [`crate::limits::MAX_POINTS_PER_SECTION`], a deck angle outside 0..90
/// degrees, a non-finite `max_z`, station positions that are not finite and strictly
/// increasing, or a station count of [`station_positions`]; and when fewer than 2 stations
/// give a section (the message lists why each was dropped).
pub fn slice_mesh(mesh: &TriMesh, options: &SliceOptions) -> Result<SliceOutcome, HullError> {
    if options.points < 2 || options.points > crate::limits::MAX_POINTS_PER_SECTION {
        return Err(HullError::Slice(SliceKind::Points {
            count: options.points,
            max: crate::limits::MAX_POINTS_PER_SECTION,
        }));
    }
    if !(options.deck_angle >= 0.0 && options.deck_angle < 90.0) {
        return Err(HullError::Slice(SliceKind::DeckAngle { degrees: options.deck_angle }));
    }
    if let Some(z) = options.max_z.filter(|z| !z.is_finite()) {
        return Err(HullError::Slice(SliceKind::MaxZ { z }));
    }
    let Some((lo, hi)) = mesh.bounds() else {
        return Err(HullError::Slice(SliceKind::EmptyMesh { mesh: mesh.source.clone() }));
    };
    let xs = match &options.stations {
        Stations::Count { n, spacing } => station_positions(lo.x, hi.x, *n, *spacing)?,
        Stations::At(xs) => {
            if let Some(w) = xs.windows(2).find(|w| !(w[1] > w[0])) {
                return Err(HullError::Slice(SliceKind::StationOrder { previous: w[0], x: w[1] }));
            }
            if let Some(x) = xs.iter().find(|x| !x.is_finite()) {
                return Err(HullError::Slice(SliceKind::StationNotFinite { x: *x }));
            }
            xs.clone()
        }
    };
    let size = (hi - lo).norm();
    let buckets = triangles_per_station(mesh, &xs);
    let results: Vec<Result<(Section, StationInfo), String>> = xs
        .par_iter()
        .zip(buckets.par_iter())
        .enumerate()
        .map(|(i, (&x, tris))| section_at(mesh, x, tris, size, options, &(i + 1).to_string()))
        .collect();
    let mut sections = Vec::new();
    let mut stations = Vec::new();
    let mut dropped = Vec::new();
    for (i, r) in results.into_iter().enumerate() {
        match r {
            Ok((s, info)) => {
                sections.push(s);
                stations.push(info);
            }
            Err(reason) => dropped.push(DroppedStation { label: (i + 1).to_string(), x: xs[i], reason }),
        }
    }
    // An end station whose cut is a sliver of the next one's: the hull ends in a point there.
    let sliver = |stations: &[StationInfo], end: usize, next: usize| {
        let (a, b) = (stations[end].length, stations[next].length);
        (a < END_SLIVER * b).then(|| {
            format!(
                "an end sliver: its cut is {a:.3e} long against {b:.3e} at the next station (less than {} %): \
                 the hull ends in a point there",
                100.0 * END_SLIVER
            )
        })
    };
    while sections.len() > 2 {
        let n = sections.len();
        // The first end, then the last.
        let ends = [(0, 1), (n - 1, n - 2)];
        let Some((end, reason)) = ends.into_iter().find_map(|(end, next)| Some((end, sliver(&stations, end, next)?)))
        else {
            break;
        };
        sections.remove(end);
        let info = stations.remove(end);
        dropped.push(DroppedStation { label: info.label, x: info.x, reason });
    }
    dropped.sort_by(|a, b| a.x.total_cmp(&b.x));
    if sections.len() < 2 {
        return Err(HullError::Slice(SliceKind::TooFewSections {
            mesh: mesh.source.clone(),
            sections: sections.len(),
            stations: xs.len(),
            dropped: dropped.into_iter().map(|d| (d.x, d.reason)).collect(),
        }));
    }
    let offsets = Offsets::new(mesh.source.clone(), options.units, sections);
    Ok(SliceOutcome { offsets, stations, dropped })
}

/// For every station (sorted x), the triangles it cuts: those with `x_min < c <= x_max`
/// (a vertex at `c` counts as forward of the plane, see [`slice_mesh`]).
fn triangles_per_station(mesh: &TriMesh, xs: &[f64]) -> Vec<Vec<u32>> {
    let mut buckets = vec![Vec::new(); xs.len()];
    for (t, tri) in mesh.triangles.iter().enumerate() {
        let x = tri.map(|i| mesh.vertices[i as usize].x);
        let (lo, hi) = (x[0].min(x[1]).min(x[2]), x[0].max(x[1]).max(x[2]));
        let first = xs.partition_point(|&c| c <= lo);
        for (j, &c) in xs.iter().enumerate().skip(first) {
            if c > hi {
                break;
            }
            buckets[j].push(t as u32);
        }
    }
    buckets
}

/// Key of a clip point on the centre plane: no edge key has `u32::MAX` in its high half
/// (its low index is the smaller one).
fn clip_key(triangle: u32) -> u64 {
    (u64::from(u32::MAX) << 32) | u64::from(triangle)
}

/// One segment of a cut: its two ends and their keys.
#[derive(Clone, Copy, Debug)]
struct Segment {
    p: [Vec3; 2],
    key: [u64; 2],
}

/// The segment triangle `t` gives at plane `x = c`, clipped to `y >= 0`, if any.
fn cut_triangle(mesh: &TriMesh, t: u32, c: f64) -> Option<Segment> {
    let tri = mesh.triangles[t as usize];
    let fwd = tri.map(|i| mesh.vertices[i as usize].x >= c);
    let mut p = [Vec3::new(0.0, 0.0, 0.0); 2];
    let mut key = [0u64; 2];
    let mut n = 0;
    for k in 0..3 {
        let (a, b) = (tri[k], tri[(k + 1) % 3]);
        if fwd[k] == fwd[(k + 1) % 3] {
            continue;
        }
        if n == 2 {
            return None; // unreachable for a triangle: two sign changes at most
        }
        let (i, j) = if a < b { (a, b) } else { (b, a) };
        let (vi, vj) = (mesh.vertices[i as usize], mesh.vertices[j as usize]);
        let s = (c - vi.x) / (vj.x - vi.x);
        let mut q = vi + (vj - vi) * s;
        q.x = c;
        p[n] = q;
        key[n] = TriMesh::edge_key(i, j);
        n += 1;
    }
    if n != 2 {
        return None;
    }
    let (y0, y1) = (p[0].y, p[1].y);
    if y0 >= 0.0 && y1 >= 0.0 {
        return (y0 > 0.0 || y1 > 0.0).then_some(Segment { p, key });
    }
    if y0 > 0.0 || y1 > 0.0 {
        // One end below 0, the other above: clip the lower one at y = 0.
        let neg = usize::from(y1 < 0.0);
        let pos = 1 - neg;
        let s = p[pos].y / (p[pos].y - p[neg].y);
        let mut q = p[pos] + (p[neg] - p[pos]) * s;
        q.y = 0.0;
        p[neg] = q;
        key[neg] = clip_key(t);
        return Some(Segment { p, key });
    }
    None
}

/// Chains of segments: the open ones (ends of degree 1) first, each walked from its first
/// free end in segment order, then the closed loops. Deterministic: nothing depends on the
/// hash map's order.
fn chain(segments: &[Segment]) -> (Vec<Vec<Vec3>>, usize) {
    let mut at: HashMap<u64, Vec<u32>> = HashMap::with_capacity(2 * segments.len());
    for (s, seg) in segments.iter().enumerate() {
        for k in seg.key {
            at.entry(k).or_default().push(s as u32);
        }
    }
    let mut used = vec![false; segments.len()];
    let walk = |start: usize, end: usize, used: &mut Vec<bool>| {
        let mut pts = vec![segments[start].p[end]];
        let (mut cur, mut from) = (start, end);
        loop {
            used[cur] = true;
            let to = 1 - from;
            pts.push(segments[cur].p[to]);
            let key = segments[cur].key[to];
            let next = at[&key].iter().map(|&s| s as usize).find(|&s| !used[s]);
            match next {
                Some(s) => {
                    from = usize::from(segments[s].key[0] != key);
                    cur = s;
                }
                None => break,
            }
        }
        pts
    };
    let mut open = Vec::new();
    for s in 0..segments.len() {
        for end in 0..2 {
            if !used[s] && at[&segments[s].key[end]].len() == 1 {
                open.push(walk(s, end, &mut used));
            }
        }
    }
    let mut loops = 0;
    for s in 0..segments.len() {
        if !used[s] {
            walk(s, 0, &mut used);
            loops += 1;
        }
    }
    (open, loops)
}

/// The section at `x` from the triangles that cross it, or why there is none.
fn section_at(
    mesh: &TriMesh,
    x: f64,
    triangles: &[u32],
    size: f64,
    options: &SliceOptions,
    label: &str,
) -> Result<(Section, StationInfo), String> {
    if triangles.is_empty() {
        return Err("the plane misses the mesh".into());
    }
    let segments: Vec<Segment> = triangles.iter().filter_map(|&t| cut_triangle(mesh, t, x)).collect();
    if segments.is_empty() {
        return Err("nothing of the cut lies on the starboard side (y >= 0)".into());
    }
    let (mut pieces, skipped_loops) = chain(&segments);
    if pieces.is_empty() {
        return Err(format!("the cut is {skipped_loops} closed loop(s) off the centre plane, no section from it"));
    }
    let centre = CENTRE_REL * size;
    let on_centre = |p: Vec3| p.y.abs() <= centre;
    for piece in &mut pieces {
        let (a, b) = (piece[0], piece[piece.len() - 1]);
        let flip = match (on_centre(a), on_centre(b)) {
            (true, false) => false,
            (false, true) => true,
            _ => b.z < a.z,
        };
        if flip {
            piece.reverse();
        }
    }
    // By the height of the start, then its half-breadth: a total order on finite numbers.
    pieces.sort_by(|p, q| p[0].z.total_cmp(&q[0].z).then(p[0].y.total_cmp(&q[0].y)));
    let n_pieces = pieces.len();
    let mut pts: Vec<Vec3> = pieces.concat();
    pts.dedup_by(|b, a| b.distance(*a) <= MERGE_REL * size);
    // The keel is the lowest point of the leading run on the centre plane: a cut that starts
    // there and first runs down it (a sliver at a pointed end, thinner than the centre plane's
    // tolerance) starts at the bottom of that run instead, on the plane.
    let run = pts.iter().take_while(|&&p| on_centre(p)).count();
    if let Some(k) = (0..run).min_by(|&i, &j| pts[i].z.total_cmp(&pts[j].z)).filter(|&k| k > 0) {
        pts.drain(..k);
        pts[0].y = 0.0;
    }

    let ends_on_centre = pts.last().is_some_and(|&p| on_centre(p));
    let mut deck_removed = false;
    if ends_on_centre && pts.len() >= 2 {
        let slope = options.deck_angle.to_radians().tan();
        let mut k = pts.len() - 1;
        while k > 0 {
            let d = pts[k - 1] - pts[k];
            if d.y > 0.0 && d.z.abs() <= slope * d.y {
                k -= 1;
            } else {
                break;
            }
        }
        if k == 0 {
            return Err("the cut is deck only (no side below a deck edge)".into());
        }
        deck_removed = k < pts.len() - 1;
        pts.truncate(k + 1);
    }
    let open_top = !ends_on_centre;
    if let Some(zmax) = options.max_z {
        if pts[0].z > zmax {
            return Err(format!("the section lies wholly above max z = {zmax}"));
        }
        if let Some(k) = pts.windows(2).position(|w| w[1].z > zmax) {
            let (a, b) = (pts[k], pts[k + 1]);
            let s = (zmax - a.z) / (b.z - a.z);
            let mut q = a + (b - a) * s;
            q.z = zmax;
            pts.truncate(k + 1);
            pts.push(q);
            pts.dedup_by(|b, a| b.distance(*a) <= MERGE_REL * size);
        }
    }
    let length: f64 = pts.windows(2).map(|w| w[0].distance(w[1])).sum();
    if pts.len() < 2 || length <= DEGENERATE_REL * size {
        return Err(format!("degenerate: the section is {length:.3e} long (expected more than 1e-6 of the mesh size)"));
    }
    let points = resample(&pts, options.points, options.resample);
    let info = StationInfo {
        label: label.to_string(),
        x,
        pieces: n_pieces,
        skipped_loops,
        deck_removed,
        open_top: open_top && !deck_removed,
        length,
    };
    Ok((Section::new(label, points), info))
}

/// Resamples a polyline (distinct consecutive points, at least 2) to `m >= 2` points, both
/// ends kept, equally spaced in the measure of `how` (see [`Resample`]); segments are mapped
/// linearly, so the points are distinct.
pub fn resample(pts: &[Vec3], m: usize, how: Resample) -> Vec<Vec3> {
    let n = pts.len();
    let lengths: Vec<f64> = pts.windows(2).map(|w| w[0].distance(w[1])).collect();
    let total: f64 = lengths.iter().sum();
    let mut weights = lengths.clone();
    if how == Resample::Adaptive && n > 2 {
        // Turning at each interior vertex, half to each neighbouring segment.
        let scale = total / std::f64::consts::PI;
        for k in 1..n - 1 {
            let (a, b) = (pts[k] - pts[k - 1], pts[k + 1] - pts[k]);
            let turn = a.cross(b).norm().atan2(a.dot(b));
            weights[k - 1] += 0.5 * scale * turn;
            weights[k] += 0.5 * scale * turn;
        }
    }
    let mut cum = Vec::with_capacity(n);
    cum.push(0.0);
    for w in &weights {
        cum.push(cum[cum.len() - 1] + w);
    }
    let w_total = cum[n - 1];
    let mut out = Vec::with_capacity(m);
    let mut seg = 0;
    for j in 0..m {
        if j == 0 {
            out.push(pts[0]);
            continue;
        }
        if j + 1 == m {
            out.push(pts[n - 1]);
            continue;
        }
        let s = w_total * j as f64 / (m - 1) as f64;
        while seg + 1 < n - 1 && cum[seg + 1] < s {
            seg += 1;
        }
        let t = ((s - cum[seg]) / weights[seg]).clamp(0.0, 1.0);
        out.push(pts[seg] + (pts[seg + 1] - pts[seg]) * t);
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::assert_near;

    /// A closed box `[0, 2] x [-1, 1] x [0, 1]`: two triangles per face, outward.
    fn cube() -> TriMesh {
        let v: Vec<Vec3> = (0..8)
            .map(|i| {
                Vec3::new(if i & 1 == 0 { 0.0 } else { 2.0 }, if i & 2 == 0 { -1.0 } else { 1.0 }, f64::from(i >> 2))
            })
            .collect();
        let quads = [[0, 2, 3, 1], [4, 5, 7, 6], [0, 1, 5, 4], [2, 6, 7, 3], [0, 4, 6, 2], [1, 3, 7, 5]];
        let triangles = quads.iter().flat_map(|q| [[q[0], q[1], q[2]], [q[0], q[2], q[3]]]).collect();
        TriMesh::try_new("cube", v, triangles).expect("valid")
    }

    #[test]
    fn cosine_and_uniform_positions() {
        let u = station_positions(0.0, 10.0, 3, Spacing::Uniform).expect("valid");
        assert_eq!(u, vec![1e-4, 5.0, 10.0 - 1e-4]);
        let c = station_positions(0.0, 10.0, 5, Spacing::Cosine).expect("valid");
        // x_m - (L'/2) cos(pi i / 4) with L' = 10 - 2e-4: symmetric, denser at the ends.
        assert_near!(c[1], 5.0 - (5.0 - 1e-4) * std::f64::consts::FRAC_1_SQRT_2, 1e-12);
        assert_near!(c[2], 5.0, 1e-12);
        assert!(c[1] - c[0] < c[2] - c[1]);
        assert!(station_positions(0.0, 1.0, 0, Spacing::Uniform).is_err());
        assert!(station_positions(1.0, 1.0, 3, Spacing::Uniform).is_err());
    }

    #[test]
    fn a_box_gives_the_half_rectangle_without_its_deck() {
        let opts = SliceOptions {
            stations: Stations::At(vec![0.5, 1.0, 1.5]),
            points: 5,
            resample: Resample::ArcLength,
            ..SliceOptions::default()
        };
        let out = slice_mesh(&cube(), &opts).expect("slices");
        assert_eq!(out.offsets.sections.len(), 3);
        // x = 1.0 passes through no vertex; 0.5 and 1.5 neither: all the same section
        // (0,0) -> (1,0) -> (1,1), the deck (y from 1 back to 0 at z = 1) cut off.
        for (s, info) in out.offsets.sections.iter().zip(&out.stations) {
            assert!(info.deck_removed && !info.open_top && info.pieces == 1, "{info:?}");
            assert_near!(info.length, 2.0, 1e-12);
            let expected = [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.0, 0.5), (1.0, 1.0)];
            for (p, (y, z)) in s.points.iter().zip(expected) {
                assert_near!(*p, Vec3::new(info.x, y, z), 1e-12);
            }
        }
    }

    #[test]
    fn stations_through_vertices_follow_the_perturbed_plane() {
        // The plane x = c is taken just aft of c: at x = 2 the forward face lies forward of it
        // and the cut is the box's outline there; at x = 0 the whole box is forward of it.
        let opts = SliceOptions {
            stations: Stations::At(vec![0.0, 1.0, 2.0]),
            points: 5,
            resample: Resample::ArcLength,
            ..SliceOptions::default()
        };
        let out = slice_mesh(&cube(), &opts).expect("slices");
        assert_eq!(out.dropped.len(), 1);
        assert_eq!((out.dropped[0].x, out.dropped[0].reason.as_str()), (0.0, "the plane misses the mesh"));
        let (mid, end) = (&out.offsets.sections[0], &out.offsets.sections[1]);
        for (a, b) in mid.points.iter().zip(&end.points) {
            assert_near!(*a + Vec3::new(1.0, 0.0, 0.0), *b, 1e-12);
        }
        assert_eq!(out.stations[1].length, 2.0);
        let none = SliceOptions { stations: Stations::At(vec![-1.0, 0.0]), ..opts };
        let e = slice_mesh(&cube(), &none).expect_err("no section").to_string();
        assert!(e.contains("0 of 2 stations give a section") && e.contains("x = 0: the plane misses"), "{e}");
    }

    #[test]
    fn max_z_ends_the_section_at_that_height() {
        let opts = SliceOptions {
            stations: Stations::At(vec![0.5, 1.5]),
            points: 3,
            max_z: Some(0.25),
            resample: Resample::ArcLength,
            ..SliceOptions::default()
        };
        let out = slice_mesh(&cube(), &opts).expect("slices");
        let s = &out.offsets.sections[0];
        assert_near!(s.points[2], Vec3::new(0.5, 1.0, 0.25), 1e-12);
        assert_near!(out.stations[0].length, 1.25, 1e-12);
        let high = SliceOptions { max_z: Some(-0.5), ..opts };
        assert!(slice_mesh(&cube(), &high).is_err());
    }

    #[test]
    fn adaptive_resampling_gathers_points_at_a_corner() {
        // An L of legs 1 and 1: the right angle adds (2/pi)(pi/2) = 1 to the measure, half on
        // each leg: each leg weighs 1.5 of 3.
        let pts = [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(0.0, 1.0, 1.0)];
        let a = resample(&pts, 5, Resample::ArcLength);
        assert_near!(a[1], Vec3::new(0.0, 0.5, 0.0), 1e-12);
        let b = resample(&pts, 7, Resample::Adaptive);
        // Steps of 0.5 in the measure: along the first leg at 0.5/1.5 = 1/3 of it.
        assert_near!(b[1], Vec3::new(0.0, 1.0 / 3.0, 0.0), 1e-12);
        assert_near!(b[3], Vec3::new(0.0, 1.0, 0.0), 1e-12);
        assert_eq!((b[0], b[6]), (pts[0], pts[2]));
    }

    #[test]
    fn sections_csv_reads_back() {
        let opts = SliceOptions { stations: Stations::At(vec![0.5, 1.5]), points: 4, ..SliceOptions::default() };
        let out = slice_mesh(&cube(), &opts).expect("slices");
        let mut text = Vec::new();
        crate::write_sections_csv(&mut text, &out.offsets, crate::float::Notation::Exchange).expect("writes");
        let text = String::from_utf8(text).expect("utf-8");
        assert!(text.starts_with("section,x,y,z\n1,0.5,0.0,0.0\n"), "{text}");
        let back = crate::parse_sections_csv(&text, "s.csv", Units::Metre).expect("reads");
        for (a, b) in back.sections.iter().zip(&out.offsets.sections) {
            assert_eq!((&a.label, &a.points), (&b.label, &b.points));
        }
    }
}
