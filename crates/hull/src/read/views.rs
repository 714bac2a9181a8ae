//! The three views of a lines plan merged into sections, their disagreements reported.
//!
//! The rest of this module's documentation is on [`{`], where the library's users read it.

use nurbs::Vec3;

use crate::error::Location;
use crate::numfmt::format_short;
use crate::offsets::{Offsets, Section};
use crate::units::Units;

/// Two x within `SAME_X_REL` times the model size are the same station (round-off of
/// `station x spacing` products is 1e-16 relative; 1e-9 is far above it and far below any
/// drawing precision).
pub const SAME_X_REL: f64 = 1e-9;

/// The default disagreement tolerance, relative to the model size (see [`Merged`]).
pub const DEFAULT_TOLERANCE_REL: f64 = 1e-4;

/// Which view a line belongs to.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum View {
    /// A station of the body plan.
    BodyPlan,
    /// A waterline of the half-breadth plan.
    Waterline,
    /// A buttock of the sheer plan.
    Buttock,
    /// The centre-plane profile: keel, stem and stern.
    Profile,
    /// The deck line at side.
    Deck,
}

impl View {
    /// The view's name, for messages.
    pub fn name(self) -> &'static str {
        match self {
            View::BodyPlan => "body plan",
            View::Waterline => "waterline",
            View::Buttock => "buttock",
            View::Profile => "keel profile",
            View::Deck => "deck line",
        }
    }
}

/// One line of a view: its points in hullskin's axes and where each came from.
#[derive(Clone, Debug, PartialEq)]
pub struct ViewLine {
    /// The line's name as in the source (`1000WL`, `Buttock 1.000`, `deck`).
    pub label: String,
    /// The points, in order along the line.
    pub points: Vec<Vec3>,
    /// 1-based source line of each point (empty, or as long as `points`).
    pub lines: Vec<usize>,
}

impl ViewLine {
    /// A line without source positions.
    pub fn new(label: impl Into<String>, points: Vec<Vec3>) -> Self {
        ViewLine { label: label.into(), points, lines: Vec::new() }
    }

    /// Adds a point from source line `line` (0 when unknown).
    pub fn push(&mut self, p: Vec3, line: usize) {
        self.points.push(p);
        if line > 0 {
            self.lines.push(line);
        }
    }

    /// The points of this line at station `x` (within `eps`): each point at that `x` as it
    /// is, and for each segment that crosses `x` strictly between its ends, the linear
    /// interpolation. With the source line of the nearest point.
    fn at_x(&self, x: f64, eps: f64, dense: bool) -> Vec<(Vec3, Option<usize>)> {
        let line_of = |i: usize| self.lines.get(i).copied();
        let mut out: Vec<(Vec3, Option<usize>)> = Vec::new();
        for (i, p) in self.points.iter().enumerate() {
            if (p.x - x).abs() <= eps {
                out.push((Vec3::new(x, p.y, p.z), line_of(i)));
            }
        }
        if !dense {
            return out;
        }
        for (i, w) in self.points.windows(2).enumerate() {
            let (a, b) = (w[0], w[1]);
            let (lo, hi) = if a.x < b.x { (a.x, b.x) } else { (b.x, a.x) };
            if lo + eps < x && x < hi - eps {
                let t = (x - a.x) / (b.x - a.x);
                let p = a + (b - a) * t;
                let near = if t < 0.5 { i } else { i + 1 };
                out.push((Vec3::new(x, p.y, p.z), line_of(near)));
            }
        }
        out
    }
}

/// Where the merged sections are taken: a station's label, position and body-plan curve
/// (empty for an offset table, whose stations are only positions).
#[derive(Clone, Debug, PartialEq)]
pub struct Station {
    /// The station's label as in the source.
    pub label: String,
    /// Its x.
    pub x: f64,
    /// The body-plan curve `(x, y, z)`, any direction (it is oriented keel to deck); may be
    /// empty.
    pub curve: ViewLine,
}

/// A lines plan's three views in hullskin's axes (x forward, y half-breadth >= 0, z up).
#[derive(Clone, Debug, PartialEq)]
pub struct ThreeViews {
    /// The source, for messages.
    pub source: String,
    /// The units of every coordinate.
    pub units: Units,
    /// The stations, in order along the length.
    pub stations: Vec<Station>,
    /// The waterlines (half-breadth plan).
    pub waterlines: Vec<ViewLine>,
    /// The buttocks (sheer plan).
    pub buttocks: Vec<ViewLine>,
    /// The centre-plane profile pieces (keel, stem, stern), `y = 0`.
    pub profile: Vec<ViewLine>,
    /// The deck line at side.
    pub deck: Vec<ViewLine>,
    /// True when the lines are curves, cut between their points at a station (exports of hull
    /// programs); false for the lines of a table, whose points lie at the stations and which
    /// give nothing between them.
    pub dense: bool,
}

/// Settings of [`ThreeViews::merge`].
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct MergeOptions {
    /// The largest difference between views accepted, in the offsets' units; `None`:
    /// [`DEFAULT_TOLERANCE_REL`] times the model size.
    pub tolerance: Option<f64>,
}

/// One place where two views disagree by more than the tolerance.
#[derive(Clone, Debug, PartialEq)]
pub struct Disagreement {
    /// The station's label.
    pub station: String,
    /// The station's x.
    pub x: f64,
    /// The height of the compared point.
    pub z: f64,
    /// The half-breadth the station's section allows at `z`: its body-plan curve's, or,
    /// without a body plan, the nearest bound of the range between the point's neighbours on
    /// the section made of the waterlines (see [`Merged`]).
    pub body_plan_y: f64,
    /// The half-breadth of the compared point (a waterline's half-breadth at the station, a
    /// buttock's plane, the deck edge).
    pub waterline_y: f64,
    /// `body_plan_y - waterline_y`.
    pub difference: f64,
    /// The view of the compared point.
    pub view: View,
    /// The label of its line (`1000WL`, `Buttock 1.000`).
    pub line: String,
    /// Where the compared point came from.
    pub at: Location,
}

/// `v` rounded to 9 decimals for messages, so that `5.4 x 3` prints as 16.2.
fn short(v: f64) -> f64 {
    let r = (v * 1e9).round() / 1e9;
    if r.is_finite() {
        r + 0.0
    } else {
        v
    }
}

impl std::fmt::Display for Disagreement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(
            f,
            "{}: station {} (x = {}), z = {}: {} {} gives y = {}, the section {} (difference {:+})",
            self.at,
            self.station,
            short(self.x),
            short(self.z),
            self.view.name(),
            self.line,
            short(self.waterline_y),
            short(self.body_plan_y),
            short(self.difference)
        )
    }
}

/// The merged sections with everything the merge found.
///
/// A lines plan gives a hull three times over:
///
/// - the **body plan**: the stations, each a curve `(y, z)` at one `x`;
/// - the **half-breadth plan**: the waterlines, each a curve `(x, y)` at one height `z`;
/// - the **sheer plan** (profile): the buttocks, each a curve `(x, z)` at one half-breadth `y`,
///   and the centre-plane profile (keel, stem and stern, `y = 0`) and the deck line at side
///   (`y(x)`, `z(x)`).
///
/// Offset tables carry the same lines as points at the stations (a waterline's half-breadth at
/// each station, a buttock's height at each station, the keel height, the deck edge); exports of
/// hull programs carry them as dense curves. [`ThreeViews::merge`] turns them into one
/// [`Section`] per station, from the keel or stem profile to the deck, and lists every place
/// where the views disagree by more than a tolerance; nothing is averaged.
///
/// # The merge, station by station
///
/// Each line is cut at the station's `x`: a point of the line at that `x` (within
/// `SAME_X_REL` of the model size) is taken as it is; for dense curves
/// ([`ThreeViews::dense`]) the line is also interpolated linearly between its two points on
/// either side of `x`, once per crossing.
/// A line that does not reach the station gives nothing there.
///
/// **With a body-plan curve** the curve is the section (oriented keel to deck). Every
/// waterline, buttock and deck-edge point the other views give at the station is compared
/// with it at the point's height `z` (the keel point is an end of the section, not compared): the
/// curve's half-breadth there is the crossing of the curve with the plane `z` nearest to the
/// point (a horizontal run of the curve at exactly that height, such as a flat of bottom, gives
/// the point's own `y` clamped to the run). A difference above the tolerance is a
/// [`Disagreement`]. The keel point is put before the curve when the curve does not start on
/// it (farther than the tolerance) and it is not above the curve's lowest point, the deck edge
/// after it when it lies above its highest point, and curve points
/// above the deck edge are cut off.
///
/// **Without a body-plan curve** (offset tables) the section is built from the half-breadth
/// plan and the profile: the keel point `(0, z_keel)`, the waterline points and the deck edge,
/// in order of height (ties by half-breadth), up to the deck edge. Each buttock point is then
/// checked against its neighbours in that order: a section from keel to deck whose points rise
/// in z has its half-breadth between the half-breadths of the two neighbours of any point
/// placed on it (between two offsets the section neither folds back nor bulges past them), so a
/// buttock point whose `y` lies outside that range by more than the tolerance contradicts the
/// waterlines and is a [`Disagreement`] (left out of the section, reported). This test works
/// at the coarse spacing of real tables, where a straight line between waterlines 1 m apart
/// can miss a bilge by half a metre and any distance-based test would condemn sound points. A
/// buttock point above the deck edge (on a bulwark or a raised deck) or with no neighbour below
/// it is left out and noted, not compared.
///
/// The tolerance defaults to [`DEFAULT_TOLERANCE_REL`] times the model size (1.2 cm on a
/// 116 m ship): above the 1 mm resolution of tables given in millimetres, below any real
/// disagreement worth a look.
#[derive(Clone, Debug, PartialEq)]
pub struct Merged {
    /// One section per station, keel to deck.
    pub offsets: Offsets,
    /// Each disagreement beyond the tolerance, station by station.
    pub disagreements: Vec<Disagreement>,
    /// Points left out without being compared, and why.
    pub notes: Vec<String>,
    /// The tolerance used.
    pub tolerance: f64,
}

/// A point one view gives at a station.
struct Cand {
    y: f64,
    z: f64,
    view: View,
    label: String,
    line: Option<usize>,
}

impl ThreeViews {
    /// The diagonal of the bounding box of every point of every view.
    pub fn size(&self) -> f64 {
        let all = self.stations.iter().flat_map(|s| s.curve.points.iter()).chain(
            self.waterlines
                .iter()
                .chain(&self.buttocks)
                .chain(&self.profile)
                .chain(&self.deck)
                .flat_map(|l| l.points.iter()),
        );
        let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
        let mut hi = -lo;
        let mut any = false;
        for p in all.filter(|p| p.is_finite()) {
            any = true;
            lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
            hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
        }
        if any {
            (hi - lo).norm()
        } else {
            0.0
        }
    }

    /// Merges the views into one section per station (see [`Merged`] for the rules).
    /// Stations where no view gives a point are left out with a note.
    pub fn merge(&self, options: &MergeOptions) -> Merged {
        let size = self.size();
        let tol = options.tolerance.unwrap_or(DEFAULT_TOLERANCE_REL * size).max(0.0);
        let eps = SAME_X_REL * size;
        let src = self.source.as_str();
        let mut sections = Vec::new();
        let mut disagreements = Vec::new();
        let mut notes = Vec::new();
        for st in &self.stations {
            let cut = |lines: &[ViewLine], view: View| -> Vec<Cand> {
                lines
                    .iter()
                    .flat_map(|l| {
                        l.at_x(st.x, eps, self.dense).into_iter().map(move |(p, line)| Cand {
                            y: p.y,
                            z: p.z,
                            view,
                            label: l.label.clone(),
                            line,
                        })
                    })
                    .collect()
            };
            let waterlines = cut(&self.waterlines, View::Waterline);
            let buttocks = cut(&self.buttocks, View::Buttock);
            let keel = cut(&self.profile, View::Profile).into_iter().min_by(|a, b| a.z.total_cmp(&b.z));
            let deck = cut(&self.deck, View::Deck).into_iter().max_by(|a, b| a.z.total_cmp(&b.z));
            let z_deck = deck.as_ref().map_or(f64::INFINITY, |d| d.z);
            let at = |line: Option<usize>| match line {
                Some(l) => Location::line(src, l),
                None => Location::file(src),
            };
            let mut points: Vec<(Vec3, Option<usize>)> = Vec::new();
            if st.curve.points.len() >= 2 {
                // The body plan is the section; the other views are checked against it.
                let mut curve: Vec<(Vec3, Option<usize>)> =
                    st.curve.points.iter().enumerate().map(|(i, &p)| (p, st.curve.lines.get(i).copied())).collect();
                if curve[0].0.z > curve[curve.len() - 1].0.z {
                    curve.reverse();
                }
                let yz: Vec<(f64, f64)> = curve.iter().map(|(p, _)| (p.y, p.z)).collect();
                for c in waterlines.iter().chain(&buttocks).chain(deck.iter()) {
                    let Some(y) = y_at_height(&yz, c.z, c.y) else { continue };
                    if (y - c.y).abs() > tol {
                        disagreements.push(Disagreement {
                            station: st.label.clone(),
                            x: st.x,
                            z: c.z,
                            body_plan_y: y,
                            waterline_y: c.y,
                            difference: y - c.y,
                            view: c.view,
                            line: c.label.clone(),
                            at: at(c.line),
                        });
                    }
                }
                if let Some(k) = &keel {
                    let first = curve[0].0;
                    if k.z <= first.z + tol && (k.y - first.y).hypot(k.z - first.z) > tol {
                        points.push((Vec3::new(st.x, k.y, k.z), k.line));
                    }
                }
                let before = curve.len();
                curve.retain(|(p, _)| p.z <= z_deck + tol);
                if curve.len() < before {
                    notes.push(format!(
                        "station {}: {} body-plan point(s) above the deck edge (z = {}) left out",
                        st.label,
                        before - curve.len(),
                        format_short(z_deck)
                    ));
                }
                let top = curve.last().map_or(f64::NEG_INFINITY, |(p, _)| p.z);
                points.extend(curve);
                if let Some(d) = &deck {
                    if d.z > top + tol {
                        points.push((Vec3::new(st.x, d.y, d.z), d.line));
                    }
                }
            } else {
                // The section from the half-breadth plan and the profile, buttocks checked.
                let mut frame: Vec<&Cand> = keel.iter().chain(&waterlines).chain(deck.iter()).collect();
                let before = frame.len();
                frame.retain(|c| c.z <= z_deck);
                if frame.len() < before {
                    notes.push(format!(
                        "station {}: {} waterline point(s) above the deck edge (z = {}) left out",
                        st.label,
                        before - frame.len(),
                        format_short(z_deck)
                    ));
                }
                let key = |c: &Cand| (c.z, c.y);
                frame.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal));
                let mut kept: Vec<&Cand> = frame.clone();
                for b in &buttocks {
                    if b.z > z_deck {
                        notes.push(format!(
                            "station {}: {} point (y = {}, z = {}) above the deck edge (z = {}) left out",
                            st.label,
                            b.label,
                            format_short(b.y),
                            format_short(b.z),
                            format_short(z_deck)
                        ));
                        continue;
                    }
                    let below = frame.iter().rev().find(|c| key(c) < key(b));
                    let above = frame.iter().find(|c| key(c) > key(b));
                    let (Some(lo), Some(hi)) = (below, above) else {
                        notes.push(format!(
                            "station {}: {} point (y = {}, z = {}) has no keel or waterline point {} it; left \
                                out, not compared",
                            st.label,
                            b.label,
                            format_short(b.y),
                            format_short(b.z),
                            if below.is_none() { "below" } else { "above" }
                        ));
                        continue;
                    };
                    let (ylo, yhi) = if lo.y <= hi.y { (lo.y, hi.y) } else { (hi.y, lo.y) };
                    let bound = b.y.clamp(ylo, yhi);
                    if (b.y - bound).abs() > tol {
                        disagreements.push(Disagreement {
                            station: st.label.clone(),
                            x: st.x,
                            z: b.z,
                            body_plan_y: bound,
                            waterline_y: b.y,
                            difference: bound - b.y,
                            view: View::Buttock,
                            line: b.label.clone(),
                            at: at(b.line),
                        });
                    } else {
                        kept.push(b);
                    }
                }
                kept.sort_by(|a, b| key(a).partial_cmp(&key(b)).unwrap_or(std::cmp::Ordering::Equal));
                points.extend(kept.iter().map(|c| (Vec3::new(st.x, c.y, c.z), c.line)));
            }
            if points.is_empty() {
                notes.push(format!(
                    "station {} (x = {}): no view gives a point there; left out",
                    st.label,
                    format_short(st.x)
                ));
                continue;
            }
            let lines = if points.iter().all(|(_, l)| l.is_some()) {
                points.iter().filter_map(|(_, l)| *l).collect()
            } else {
                Vec::new()
            };
            sections.push(Section {
                label: st.label.clone(),
                points: points.iter().map(|(p, _)| Vec3::new(p.x, p.y + 0.0, p.z)).collect(),
                lines,
                column: None,
            });
        }
        Merged {
            offsets: Offsets::new(self.source.clone(), self.units, sections),
            disagreements,
            notes,
            tolerance: tol,
        }
    }
}

/// The half-breadth of the polyline `yz` at height `z`: of all its crossings with the plane
/// `z`, the one nearest `y_hint` (a horizontal run at exactly `z` gives `y_hint` clamped to
/// the run). `None` when the polyline does not reach `z`.
pub fn y_at_height(yz: &[(f64, f64)], z: f64, y_hint: f64) -> Option<f64> {
    let mut best: Option<f64> = None;
    let mut consider = |y: f64| {
        if best.is_none_or(|b| (y - y_hint).abs() < (b - y_hint).abs()) {
            best = Some(y);
        }
    };
    if let [(y, z0)] = yz {
        if *z0 == z {
            consider(*y);
        }
    }
    for w in yz.windows(2) {
        let ((ya, za), (yb, zb)) = (w[0], w[1]);
        if za == zb {
            if za == z {
                consider(y_hint.clamp(ya.min(yb), ya.max(yb)));
            }
        } else if za.min(zb) <= z && z <= za.max(zb) {
            consider(ya + (z - za) / (zb - za) * (yb - ya));
        }
    }
    best
}

#[cfg(test)]
mod tests {
    use super::*;

    fn line(label: &str, pts: &[(f64, f64, f64)]) -> ViewLine {
        ViewLine::new(label, pts.iter().map(|&(x, y, z)| Vec3::new(x, y, z)).collect())
    }

    /// A box barge 10 long, half-breadth 2, depth 2, with a flat bottom and vertical sides: two
    /// stations at x = 0 and 10, waterlines at z = 1 and the deck at z = 2.
    fn barge() -> ThreeViews {
        ThreeViews {
            source: "barge".into(),
            units: Units::Metre,
            stations: [("A", 0.0), ("B", 10.0)]
                .iter()
                .map(|&(l, x)| Station { label: l.into(), x, curve: ViewLine::new(l, vec![]) })
                .collect(),
            waterlines: vec![line("WL1", &[(0.0, 2.0, 1.0), (10.0, 2.0, 1.0)])],
            buttocks: vec![line("B1", &[(0.0, 1.0, 0.0), (10.0, 1.0, 0.0)])],
            profile: vec![line("keel", &[(0.0, 0.0, 0.0), (10.0, 0.0, 0.0)])],
            deck: vec![line("deck", &[(0.0, 2.0, 2.0), (10.0, 2.0, 2.0)])],
            dense: false,
        }
    }

    #[test]
    fn crossing_heights_pick_the_nearest_and_handle_flats() {
        let section = [(0.0, 0.0), (2.0, 0.0), (2.0, 2.0)];
        assert_eq!(y_at_height(&section, 1.0, 0.0), Some(2.0));
        // On the flat of bottom, the hint itself (clamped to the run).
        assert_eq!(y_at_height(&section, 0.0, 1.3), Some(1.3));
        assert_eq!(y_at_height(&section, 0.0, 5.0), Some(2.0));
        assert_eq!(y_at_height(&section, 3.0, 0.0), None);
        // A bulb: two crossings at z = 1; the one nearest the hint wins.
        let bulb = [(0.0, 0.0), (1.0, 1.0), (0.5, 2.0), (1.5, 3.0)];
        assert_eq!(y_at_height(&bulb, 2.5, 0.0), Some(1.0));
    }

    #[test]
    fn a_table_merges_keel_waterlines_buttocks_and_deck_in_height_order() {
        let m = barge().merge(&MergeOptions::default());
        assert!(m.disagreements.is_empty(), "{:?}", m.disagreements);
        assert_eq!(m.offsets.sections.len(), 2);
        // keel (0, 0), buttock (1, 0), waterline (2, 1), deck (2, 2).
        let yz: Vec<(f64, f64)> = m.offsets.sections[0].points.iter().map(|p| (p.y, p.z)).collect();
        assert_eq!(yz, vec![(0.0, 0.0), (1.0, 0.0), (2.0, 1.0), (2.0, 2.0)]);
        assert!(m.offsets.validate(4).is_ok());
    }

    #[test]
    fn a_buttock_that_contradicts_the_waterlines_is_reported_not_averaged() {
        let mut v = barge();
        // The buttock at y = 1 put at z = 1.5, between the waterline (2, 1) and the deck
        // (2, 2): its y lies 1 outside the range [2, 2].
        v.buttocks[0].points[1].z = 1.5;
        v.buttocks[0].lines = vec![7, 8];
        let m = v.merge(&MergeOptions { tolerance: Some(0.01) });
        assert_eq!(m.disagreements.len(), 1);
        let d = &m.disagreements[0];
        assert_eq!((d.station.as_str(), d.z, d.body_plan_y, d.waterline_y, d.difference), ("B", 1.5, 2.0, 1.0, 1.0));
        assert_eq!(d.view, View::Buttock);
        assert_eq!(d.at.to_string(), "barge:8");
        // Station B keeps its other points; the bad one is not averaged in.
        assert_eq!(m.offsets.sections[1].points.len(), 3);
        // A tolerance above the difference accepts it.
        assert!(v.merge(&MergeOptions { tolerance: Some(1.5) }).disagreements.is_empty());
    }

    #[test]
    fn a_body_plan_is_the_section_and_the_other_views_are_checked_against_it() {
        let mut v = barge();
        // Station A's body plan: bottom and side from (0.5, 0) to the deck, 2 wide.
        v.stations[0].curve = line("A", &[(0.0, 2.0, 2.0), (0.0, 2.0, 0.5), (0.0, 1.5, 0.0), (0.0, 0.5, 0.0)]);
        // The waterline at z = 1 says 2.1 at x = 0: 0.1 off the body plan.
        v.waterlines[0].points[0].y = 2.1;
        let m = v.merge(&MergeOptions { tolerance: Some(0.05) });
        assert_eq!(m.disagreements.len(), 1, "{:?}", m.disagreements);
        let d = &m.disagreements[0];
        assert_eq!(d.view, View::Waterline);
        assert!((d.difference + 0.1).abs() < 1e-12, "{d}");
        // Reversed to run keel to deck; the keel point (0, 0) added below it; the deck edge
        // (2, 2) is the curve's own last point, not repeated.
        let yz: Vec<(f64, f64)> = m.offsets.sections[0].points.iter().map(|p| (p.y, p.z)).collect();
        assert_eq!(yz, vec![(0.0, 0.0), (0.5, 0.0), (1.5, 0.0), (2.0, 0.5), (2.0, 2.0)]);
    }

    #[test]
    fn dense_lines_are_interpolated_at_the_stations() {
        let wl = line("WL", &[(0.0, 1.0, 1.0), (4.0, 2.0, 1.0), (10.0, 2.0, 1.0)]);
        assert!(wl.at_x(2.0, 1e-12, false).is_empty(), "a table's line gives nothing between its points");
        let cut = wl.at_x(2.0, 1e-12, true);
        assert_eq!(cut.len(), 1);
        assert_eq!(cut[0].0, Vec3::new(2.0, 1.5, 1.0));
        assert_eq!(wl.at_x(4.0, 1e-12, true).len(), 1, "a point at the station is not counted twice");
        assert!(wl.at_x(11.0, 1e-12, true).is_empty());
    }

    #[test]
    fn buttocks_above_the_deck_are_noted_and_stations_without_points_dropped() {
        let mut v = barge();
        v.buttocks.push(line("B2", &[(0.0, 1.0, 3.0)]));
        v.stations.push(Station { label: "C".into(), x: 20.0, curve: ViewLine::new("C", vec![]) });
        let m = v.merge(&MergeOptions::default());
        assert_eq!(m.offsets.sections.len(), 2);
        assert!(m.notes.iter().any(|n| n.contains("B2") && n.contains("above the deck")), "{:?}", m.notes);
        assert!(m.notes.iter().any(|n| n.starts_with("station C")), "{:?}", m.notes);
    }
}
