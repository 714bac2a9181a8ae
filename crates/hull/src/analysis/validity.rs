//! Validity of a fitted hull surface: the defects that make a CAD system or a naval architect
//! reject it, looked for everywhere on the surface, not only at the offsets.
//!
//! The rest of this module's documentation is on [`check_validity`], where the library's users read it.

use std::collections::VecDeque;

use nurbs::{NurbsSurface, Vec3};
use rayon::prelude::*;
use serde::Serialize;

use super::fold::{folds_on_grid, Fold, PER_SPAN};
use crate::flats::{FlatKind, FlatLine};
use crate::{Offsets, COINCIDENT_REL};

/// Allowance of the envelope checks, relative to the half-beam (y), the depth (z) and the
/// length (x) of the offsets: issue 11's 0.5 %, about the spread of offsets lifted from a
/// drawing (41 mm on the Series 60 sample's 8.13 m half-beam).
pub const ENVELOPE_REL: f64 = 0.005;

/// How far, relative to its length in x, the surface may run back across its sections without
/// turning over (its normal keeping its side) before the run counts as a fold: a tenth of a
/// percent, a fifth of the envelope's allowance in x. The MATLAB trawler's keel line runs aft
/// as it drops down its stern (the offsets themselves 9 mm, the fits 22 to 33 mm: 0.05 to
/// 0.07 % of its 45.4 m), no fold; the DTMB 5415 mesh's default fit hooks 0.59 m behind its
/// transom (0.4 % of 142 m), a fold.
pub const FOLD_RUN_REL: f64 = 1e-3;

/// Allowance of the flat checks, relative to the depth (flat of bottom) or the half-beam (flat
/// of side): a tenth of [`ENVELOPE_REL`] (4 mm on an 8 m half-beam), since a flat is built to
/// its plane. A skin refitted within the flats (`--knuckles auto+flats`) keeps to the plane
/// to round-off; the plain skin of the Series 60 Cb 0.80 parent bulges 36 mm beyond its flat
/// side, which this reports and the envelope's 41 mm would not.
pub const FLAT_REL: f64 = 0.0005;

/// The least share of the surface's area that an inward-facing region must exceed to be
/// reported: 1e-4, a 20 cm square on a 400 m² hull. The grid's cells are 2e-5 to 1e-4 of the
/// area on the tables of `testdata/` (150 to 250 lines each way), so a region below it is a
/// cell or two: sampling, not a defect a CAD system would show.
pub const INWARD_SHARE: f64 = 1e-4;

/// What is wrong.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum FindingKind {
    /// The surface runs backwards across its sections.
    Fold,
    /// Below the centre plane `y = 0`.
    BelowCentrePlane,
    /// Beyond the largest half-breadth of the offsets.
    BeyondHalfBreadth,
    /// Below the lowest offset.
    BelowLowestOffset,
    /// Above the highest offset.
    AboveHighestOffset,
    /// Aft of the aft end section (x below the offsets' least x).
    PastAftEnd,
    /// Forward of the fore end section.
    PastForeEnd,
    /// Through the plane of a flat of bottom or side.
    FlatBulge,
    /// Facets whose normal points opposite to the rest of the surface.
    InwardFacing,
}

impl FindingKind {
    /// The name in `report.json` and the summaries (snake case).
    pub fn name(self) -> &'static str {
        match self {
            FindingKind::Fold => "fold",
            FindingKind::BelowCentrePlane => "below_centre_plane",
            FindingKind::BeyondHalfBreadth => "beyond_half_breadth",
            FindingKind::BelowLowestOffset => "below_lowest_offset",
            FindingKind::AboveHighestOffset => "above_highest_offset",
            FindingKind::PastAftEnd => "past_aft_end",
            FindingKind::PastForeEnd => "past_fore_end",
            FindingKind::FlatBulge => "flat_bulge",
            FindingKind::InwardFacing => "inward_facing",
        }
    }
}

/// Which flat a [`FindingKind::FlatBulge`] goes through.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Flat {
    Bottom,
    Side,
}

/// A point of the surface with its parameters.
#[derive(Clone, Copy, Debug, PartialEq, Serialize)]
pub struct Place {
    pub x: f64,
    pub y: f64,
    pub z: f64,
    pub u: f64,
    pub v: f64,
}

impl Finding {
    /// The face of the envelope the surface crossed, `(axis, upper)` (axis 0, 1, 2 for x, y,
    /// z; `upper` for the largest value's face): a flat's plane is a face too (the side's is
    /// the largest half-breadth, the bottom's the lowest offset). `None` for a fold or
    /// inward-facing facets.
    pub fn envelope_face(&self) -> Option<(usize, bool)> {
        match self.kind {
            FindingKind::Fold | FindingKind::InwardFacing => None,
            FindingKind::BelowCentrePlane => Some((1, false)),
            FindingKind::BeyondHalfBreadth => Some((1, true)),
            FindingKind::BelowLowestOffset => Some((2, false)),
            FindingKind::AboveHighestOffset => Some((2, true)),
            FindingKind::PastAftEnd => Some((0, false)),
            FindingKind::PastForeEnd => Some((0, true)),
            FindingKind::FlatBulge => match self.flat {
                Some(Flat::Side) => Some((1, true)),
                Some(Flat::Bottom) | None => Some((2, false)),
            },
        }
    }
}

impl Place {
    fn at(surface: &NurbsSurface, u: f64, v: f64) -> Self {
        let p = surface.point(u, v);
        Place { x: p.x, y: p.y, z: p.z, u, v }
    }
}

/// One defect of a surface.
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Finding {
    pub kind: FindingKind,
    /// Where the worst sample is (refined): the deepest point of a fold, the farthest point
    /// past an envelope's limit or a flat's plane, the largest inward-facing facet.
    pub place: Place,
    /// How far past the reference, in the surface's units: the length a fold runs back, the
    /// distance beyond the envelope's face or the flat's plane; for inward-facing facets their
    /// area (units squared).
    pub size: f64,
    /// The allowance `size` exceeded (for a fold: 0 where the surface turns over, else the
    /// run back allowed without turning over, [`FOLD_RUN_REL`] of its length).
    pub limit: f64,
    /// The coordinate the size is measured from: `y = 0` or the largest half-breadth, the
    /// lowest or highest z, the end sections' x, the flat's plane; absent for folds and
    /// inward-facing facets.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub reference: Option<f64>,
    /// Lowest and highest x of the samples past the limit (of the fold's band, of the region).
    #[serde(skip_serializing_if = "Option::is_none")]
    pub x_band: Option<(f64, f64)>,
    /// The flat of a flat bulge.
    #[serde(skip_serializing_if = "Option::is_none")]
    pub flat: Option<Flat>,
    /// Separate regions of the grid past the same limit, this finding the worst of them (1
    /// for folds, which are reported band by band).
    pub places: usize,
}

/// A length with three significant figures (at least three decimals from 1 up).
fn len(v: f64) -> String {
    if !v.is_finite() || v == 0.0 || v.abs() >= 1.0 {
        return format!("{v:.3}");
    }
    let decimals = (2 - v.abs().log10().floor() as i32).clamp(3, 12) as usize;
    format!("{v:.decimals$}")
}

impl Finding {
    /// The one-line warning of the summary and the report page: what, where, how much, and
    /// the cure, lengths in `units` (a symbol such as `m`).
    pub fn message(&self, units: &str) -> String {
        let u = units;
        let p = &self.place;
        let at = format!("at x = {}, y = {}, z = {} {u}", len(p.x), len(p.y), len(p.z));
        let mut band = match self.x_band {
            Some((a, b)) if len(a) != len(b) => format!(" between x = {} and {} {u}", len(a), len(b)),
            _ => String::new(),
        };
        if self.places > 1 {
            band.push_str(&format!(" (the worst of {} places)", self.places));
        }
        let r = self.reference.map_or_else(String::new, len);
        let past = |what: &str, coord: &str, allowance: &str, expected: &str, cure: &str| {
            format!(
                "{what} (the offsets' {coord} = {r} {u}) by {} {u} {at}{band}, more than the {} {u} allowed ({allowance}) \
                 (expected {expected}; {cure})",
                len(self.size),
                len(self.limit)
            )
        };
        let more_ctrl = "try more control points along the sections (--ctrl) or --method interp";
        match self.kind {
            FindingKind::Fold if self.limit > 0.0 => format!(
                "the surface hooks back across the sections{band} (it runs {} {u} back, deepest {at}, more than the \
                 {} {u} allowed (0.1 % of the length) without turning over): sections crossing each other or \
                 unevenly spaced parameters across them (expected sections that advance in x; try --param \
                 centripetal,centripetal or fewer control points across)",
                len(self.size),
                len(self.limit)
            ),
            FindingKind::Fold => format!(
                "the surface folds back across the sections{band} (it runs {} {u} back, deepest {at}; a CAD system \
                 sees it as self-intersecting): sections crossing each other or unevenly spaced parameters across \
                 them (expected sections that advance in x; try --param centripetal,centripetal or fewer control \
                 points across)",
                len(self.size)
            ),
            FindingKind::BelowCentrePlane => format!(
                "the surface crosses the centre plane (y = {r} {u}) by {} {u} {at}{band}, more than the {} {u} \
                 allowed (0.5 % of the half-beam) (expected y >= {r} {u}; {more_ctrl})",
                len(self.size),
                len(self.limit)
            ),
            FindingKind::BeyondHalfBreadth => past(
                "the surface bulges beyond the largest half-breadth",
                "y",
                "0.5 % of the half-beam",
                &format!("y <= {r} {u}"),
                "try more control points (--ctrl), or --knuckles auto+flats on a hull with a flat side",
            ),
            FindingKind::BelowLowestOffset => past(
                "the surface dips below the lowest offset",
                "z",
                "0.5 % of the depth",
                &format!("z >= {r} {u}"),
                "try more control points (--ctrl), or --knuckles auto+flats on a hull with a flat bottom",
            ),
            FindingKind::AboveHighestOffset => past(
                "the surface rises above the highest offset",
                "z",
                "0.5 % of the depth",
                &format!("z <= {r} {u}"),
                more_ctrl,
            ),
            FindingKind::PastAftEnd => past(
                "the surface runs aft of the aft end section",
                "x",
                "0.5 % of the length",
                &format!("x >= {r} {u}"),
                "try fewer control points across the sections (--ctrl) or --param centripetal,centripetal",
            ),
            FindingKind::PastForeEnd => past(
                "the surface runs forward of the fore end section",
                "x",
                "0.5 % of the length",
                &format!("x <= {r} {u}"),
                "try fewer control points across the sections (--ctrl) or --param centripetal,centripetal",
            ),
            FindingKind::FlatBulge => {
                let (name, coord, of) = match self.flat {
                    Some(Flat::Side) => ("side", "y", "half-beam"),
                    _ => ("bottom", "z", "depth"),
                };
                format!(
                    "the surface bulges through the flat of {name} ({coord} = {r} {u}) by {} {u} {at}{band}, more \
                     than the {} {u} allowed (0.05 % of the {of}) (expected the flat on its plane; try --knuckles \
                     auto+flats, which keeps the surface within the flats' planes)",
                    len(self.size),
                    len(self.limit)
                )
            }
            FindingKind::InwardFacing => format!(
                "{} {u}² of the surface{band} faces inwards (its normal S_u x S_v points opposite to the rest's; \
                 largest facet {at}), more than the {} {u}² allowed (0.01 % of the area): the surface doubles back \
                 on itself there and a CAD system sees it as self-intersecting (expected one orientation \
                 everywhere; try fewer control points (--ctrl) or another --param)",
                len(self.size),
                len(self.limit)
            ),
        }
    }
}

/// The box of the offsets that a sound surface stays in, and the x extent of each section
/// (where a flat's sections lie).
#[derive(Clone, Debug, PartialEq, Serialize)]
pub struct Envelope {
    /// Least and largest x: the aft and fore end sections.
    pub x: (f64, f64),
    /// The centre plane (`y = 0`, or the least y of the offsets if below) and the largest
    /// half-breadth.
    pub y: (f64, f64),
    /// Lowest and highest z of the offsets.
    pub z: (f64, f64),
    /// Least and largest x of each section's points, in order (empty: no flat is placed).
    pub sections_x: Vec<(f64, f64)>,
}

impl Envelope {
    /// The envelope of `offsets` (finite points only); `None` without any point.
    pub fn of_offsets(offsets: &Offsets) -> Option<Self> {
        let (lo, hi) = offsets.bounds()?;
        let sections_x = offsets
            .sections
            .iter()
            .map(|s| {
                s.points
                    .iter()
                    .filter(|p| p.is_finite())
                    .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), p| (a.min(p.x), b.max(p.x)))
            })
            .collect();
        Some(Envelope { x: (lo.x, hi.x), y: (lo.y.min(0.0), hi.y), z: (lo.z, hi.z), sections_x })
    }

    /// No limit at all: only folds and inward-facing facets can be found (a surface read
    /// without offsets).
    pub fn unbounded() -> Self {
        let all = (f64::NEG_INFINITY, f64::INFINITY);
        Envelope { x: all, y: all, z: all, sections_x: Vec::new() }
    }

    /// The envelope as a box for control points: a net within it keeps the surface within the envelope (the convex-hull
    /// property), and so inside the flats' planes too.
    pub fn bounds(&self) -> nurbs::fit::ControlBox {
        nurbs::fit::ControlBox { lo: [self.x.0, self.y.0, self.z.0], hi: [self.x.1, self.y.1, self.z.1] }
    }

    /// Largest half-breadth above the centre plane.
    pub fn half_beam(&self) -> f64 {
        self.y.1 - self.y.0
    }

    /// Extent in z.
    pub fn depth(&self) -> f64 {
        self.z.1 - self.z.0
    }

    /// Extent in x.
    pub fn length(&self) -> f64 {
        self.x.1 - self.x.0
    }

    /// The x extent of the sections where a flat is found (`None` if none of them is known).
    fn flat_band(&self, lines: &[&FlatLine]) -> Option<(f64, f64)> {
        let (a, b) = lines
            .iter()
            .flat_map(|l| l.index.iter().enumerate().filter(|(_, i)| i.is_some()).map(|(k, _)| k))
            .filter_map(|k| self.sections_x.get(k))
            .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &(x0, x1)| (a.min(x0), b.max(x1)));
        (a <= b).then_some((a, b))
    }
}

/// Rows of the grid evaluated together (the u basis functions are shared within a block).
const ROWS_PER_BLOCK: usize = 16;

/// One node of the sampling grid.
#[derive(Clone, Copy)]
struct Node {
    p: Vec3,
    su: Vec3,
    sv: Vec3,
}

/// The surface sampled on a grid refined at every knot span; nodes v-major (`j * us.len() + i`).
struct Grid {
    us: Vec<f64>,
    vs: Vec<f64>,
    nodes: Vec<Node>,
}

impl Grid {
    fn sample(surface: &NurbsSurface) -> Self {
        let us = surface.knots_u().param_grid(16, true, PER_SPAN);
        let vs = surface.knots_v().param_grid(16, true, PER_SPAN);
        // Blocks of rows in parallel, gathered in order; each node is computed the same way
        // whatever the blocks, so the grid is the same whatever the thread count.
        let blocks: Vec<Vec<Node>> = vs
            .par_chunks(ROWS_PER_BLOCK)
            .map(|block| {
                surface
                    .first_derivatives_grid(&us, block)
                    .into_iter()
                    .map(|d| Node { p: d.point, su: d.su, sv: d.sv })
                    .collect()
            })
            .collect();
        Grid { us, vs, nodes: blocks.into_iter().flatten().collect() }
    }

    fn nu(&self) -> usize {
        self.us.len()
    }

    fn uv(&self, k: usize) -> (f64, f64) {
        (self.us[k % self.nu()], self.vs[k / self.nu()])
    }
}

/// The defects of `surface` (u along the sections, v across them) against the offsets'
/// `envelope` and the flat lines `flats` of the same offsets (their `index` per section
/// matching [`Envelope::sections_x`]): folds first, then the envelope's faces (y, z, x), the
/// flats (bottom, side) and the inward-facing facets, one finding for each (the worst region,
/// with the count of regions) but folds, one per band. Empty for a valid
/// surface. Deterministic: the same surface gives the same findings whatever the thread count.
///
/// [`check_validity`] samples the surface on a parameter grid refined at every knot span
/// ([`KnotVector::param_grid`](nurbs::KnotVector::param_grid) with 8 samples per span each way, as [`find_folds`](super::find_folds)) and reports one
/// [`Finding`] per defect:
///
/// - **fold** ([`find_folds`](super::find_folds)): the surface runs backwards across its sections (`x_v` of the
///   minority's sign) and turns over there (some node running back faces the other way, as
///   the orientation below finds) or runs back by more than [`FOLD_RUN_REL`] of its length;
///   its size is how far back it runs, `max_{v_a < v_b} s (x(u, v_a) - x(u, v_b))`
///   over the band (`s` the majority's direction);
/// - **envelope**: the surface leaves the box of the offsets ([`Envelope`]): below the centre
///   plane `y = 0`, beyond the largest half-breadth, below the lowest or above the highest
///   offset, past the aft or fore end section in x, each by more than [`ENVELOPE_REL`] (0.5 %,
///   issue 11) of the half-beam (y), the depth (z) or the length (x);
/// - **flat bulge**: the surface crosses the plane of a flat of bottom or side
///   ([`FlatLine`], from `find_flat_lines`) within the x extent of the flat's sections, by more
///   than `FLAT_REL` of the depth or half-beam (a tenth of the envelope's allowance: a flat
///   is a plate, built to the plane);
/// - **inward facing**: facets whose normal `S_u x S_v` points opposite to the rest of the
///   surface, a region larger than `INWARD_SHARE` of the surface's area.
///
/// Each check gives at most one finding, its worst region (largest excess or area) with the
/// number of separate regions past the same limit ([`Finding::places`]); folds are reported
/// band by band, each with its own cure.
///
/// The worst grid sample of each envelope and flat check is refined by golden-section search
/// (Kiefer 1953), alternately in `u` and in `v`, over the grid cells around it, so the size
/// reported is that of the surface, not of the grid (an extreme on the domain's edge, as at a
/// transom or a keel, is found there: the search keeps the interval's ends).
///
/// The orientation of the normals is propagated over the grid as in Hoppe et al., "Surface
/// reconstruction from unorganized points" (SIGGRAPH 1992, section 3.3): along a minimum
/// spanning tree of the grid's edges weighted `1 - |n_a . n_b|` (unit normals), flipping across
/// an edge where `n_a . n_b < 0`. The most parallel (or antiparallel) pairs decide first, so a
/// fold's crease (normals antiparallel on either side) flips the orientation and a sharp but
/// ordinary turn of the surface (a knuckle, normals near 90 degrees apart) cannot decide
/// against the rest. Nodes whose `|S_u x S_v|` is round-off (a collapsed edge at a pointed
/// stem) are skipped. Each node carries the area `|S_u x S_v| du dv` (trapezoidal weights);
/// the smaller orientation's connected regions are the inward-facing facets.
///
/// Axes as everywhere: x forward, y to starboard, z up; sizes in the surface's units (areas
/// in units squared).
pub fn check_validity(surface: &NurbsSurface, envelope: &Envelope, flats: &[FlatLine]) -> Vec<Finding> {
    validity_and_folds(surface, envelope, flats).0
}

/// [`check_validity`] with the fold bands of [`find_folds`](super::find_folds) (the same grid,
/// sampled once).
pub(crate) fn validity_and_folds(
    surface: &NurbsSurface,
    envelope: &Envelope,
    flats: &[FlatLine],
) -> (Vec<Finding>, Vec<Fold>) {
    FaceCheck::of(surface, envelope, flats).complete(surface)
}

/// The findings of [`validity_and_folds`] against the envelope's faces and the flats' planes
/// ([`Finding::envelope_face`]), with the grid they were found on: what an envelope hold reads,
/// [`FaceCheck::complete`]d into every finding without sampling the surface again.
pub(crate) struct FaceCheck {
    grid: Grid,
    /// The findings against the faces, in [`validity_and_folds`]'s order.
    pub(crate) faces: Vec<Finding>,
}

impl FaceCheck {
    /// The findings of `surface` against `envelope`'s faces and `flats`' planes.
    pub(crate) fn of(surface: &NurbsSurface, envelope: &Envelope, flats: &[FlatLine]) -> FaceCheck {
        let grid = Grid::sample(surface);
        let faces = probes(surface, envelope, flats).iter().filter_map(|p| p.check(surface, &grid)).collect();
        FaceCheck { grid, faces }
    }

    /// Every finding of [`validity_and_folds`] of the same `surface` (the same findings in its
    /// order: folds, the faces', inward-facing facets) and its fold bands.
    pub(crate) fn complete(self, surface: &NurbsSurface) -> (Vec<Finding>, Vec<Fold>) {
        let FaceCheck { grid, faces } = self;
        let rows: Vec<Vec<(f64, f64)>> =
            grid.nodes.chunks(grid.nu()).map(|row| row.iter().map(|n| (n.p.x, n.sv.x)).collect()).collect();
        let (folds, sign) = folds_on_grid(surface, &grid.vs, &rows);
        let orientation = oriented(surface, &grid);
        // A band where x_v turns is a fold where the surface turns over with it (some node
        // running back there faces the other way), or where it runs back farther than
        // FOLD_RUN_REL of its length (a hook, as behind a transom, even with the normal keeping
        // its side). Along a steep profile (a stern or a stem whose sections' v lines run mostly
        // up and down) x_v can change sign by a little while S_u x S_v keeps its side: the skin
        // neither doubles back nor hooks there.
        let turned = |f: &Fold| {
            let Some(o) = &orientation else { return false };
            let nu = grid.nu();
            let rows = grid.vs.iter().enumerate().filter(|(_, &v)| v >= f.v.0 && v <= f.v.1).map(|(j, _)| j);
            rows.flat_map(|j| j * nu..(j + 1) * nu).any(|k| o.minority[k] && sign * grid.nodes[k].sv.x < 0.0)
        };
        let (lo, hi) = surface.control_bounds();
        let run_allowance = FOLD_RUN_REL * (hi.x - lo.x);
        let mut out: Vec<Finding> = Vec::new();
        let folds: Vec<Fold> = folds
            .into_iter()
            .filter(|f| {
                let finding = fold_finding(surface, &grid, f, sign);
                let limit = if turned(f) { 0.0 } else { run_allowance };
                let kept = finding.size > limit;
                if kept {
                    out.push(Finding { limit, ..finding });
                }
                kept
            })
            .collect();
        out.extend(faces);
        // A fold's own facets face inwards too: that region is the fold, reported once.
        let folded = |k: usize| !folds.is_empty() && sign * grid.nodes[k].sv.x < 0.0;
        if let Some(o) = &orientation {
            out.extend(inward_facing(surface, &grid, o, folded));
        }
        (out, folds)
    }
}

/// The probes of [`validity_and_folds`]: the envelope's six faces, then the flats' planes.
fn probes(surface: &NurbsSurface, envelope: &Envelope, flats: &[FlatLine]) -> Vec<Probe> {
    let floor = surface.model_size().unwrap_or(1.0) * 1e-12;
    let allowance = |extent: f64, rel: f64| (rel * extent).max(floor);
    let (hb, depth, length) = (envelope.half_beam(), envelope.depth(), envelope.length());
    let mut probes = vec![
        Probe::new(FindingKind::BelowCentrePlane, 1, false, envelope.y.0, allowance(hb, ENVELOPE_REL)),
        Probe::new(FindingKind::BeyondHalfBreadth, 1, true, envelope.y.1, allowance(hb, ENVELOPE_REL)),
        Probe::new(FindingKind::BelowLowestOffset, 2, false, envelope.z.0, allowance(depth, ENVELOPE_REL)),
        Probe::new(FindingKind::AboveHighestOffset, 2, true, envelope.z.1, allowance(depth, ENVELOPE_REL)),
        Probe::new(FindingKind::PastAftEnd, 0, false, envelope.x.0, allowance(length, ENVELOPE_REL)),
        Probe::new(FindingKind::PastForeEnd, 0, true, envelope.x.1, allowance(length, ENVELOPE_REL)),
    ];
    for (kind, flat) in [(FlatKind::Bottom, Flat::Bottom), (FlatKind::Side, Flat::Side)] {
        let lines: Vec<&FlatLine> = flats.iter().filter(|l| l.kind == kind).collect();
        let (Some(first), Some(band)) = (lines.first(), envelope.flat_band(&lines)) else { continue };
        let probe = match flat {
            Flat::Bottom => Probe::new(FindingKind::FlatBulge, 2, false, first.plane, allowance(depth, FLAT_REL)),
            Flat::Side => Probe::new(FindingKind::FlatBulge, 1, true, first.plane, allowance(hb, FLAT_REL)),
        };
        probes.push(Probe { band: Some(band), flat: Some(flat), ..probe });
    }
    probes
}

/// The findings of [`validity_and_folds`] against the envelope's faces and the flats' planes
/// only ([`FaceCheck`]), without looking for folds or inward-facing facets: what an envelope
/// hold on the control net reads.
pub(crate) fn face_findings(surface: &NurbsSurface, envelope: &Envelope, flats: &[FlatLine]) -> Vec<Finding> {
    FaceCheck::of(surface, envelope, flats).faces
}

/// [`check_validity`] of a surface fitted to `offsets`, with the flats found in them
/// ([`crate::flats::find_flat_lines`] with its default settings, as `--knuckles auto+flats`).
/// Offsets without a point have no envelope: folds and inward-facing facets only.
///
/// # Errors
/// [`crate::HullError::Fit`] when the flat detection refuses the offsets (a coordinate that
/// is not finite).
pub fn check_fit_validity(surface: &NurbsSurface, offsets: &Offsets) -> Result<Vec<Finding>, crate::HullError> {
    Ok(fit_validity_and_folds(surface, offsets)?.0)
}

/// [`check_fit_validity`] with the fold bands of [`find_folds`](super::find_folds) (offsets
/// without a point: folds only, no envelope).
///
/// # Errors
/// As [`check_fit_validity`].
pub(crate) fn fit_validity_and_folds(
    surface: &NurbsSurface,
    offsets: &Offsets,
) -> Result<(Vec<Finding>, Vec<Fold>), crate::HullError> {
    let (envelope, flats) = envelope_and_flats(offsets)?;
    Ok(validity_and_folds(surface, &envelope, &flats))
}

/// [`fit_validity_and_folds`]'s findings against the envelope's faces and the flats' planes
/// ([`FaceCheck`]).
///
/// # Errors
/// As [`check_fit_validity`].
pub(crate) fn fit_face_check(surface: &NurbsSurface, offsets: &Offsets) -> Result<FaceCheck, crate::HullError> {
    let (envelope, flats) = envelope_and_flats(offsets)?;
    Ok(FaceCheck::of(surface, &envelope, &flats))
}

/// The envelope of `offsets` (unbounded without a point) and the flats found in them, as
/// [`check_fit_validity`] checks a surface against.
fn envelope_and_flats(offsets: &Offsets) -> Result<(Envelope, Vec<FlatLine>), crate::HullError> {
    let envelope = Envelope::of_offsets(offsets).unwrap_or_else(Envelope::unbounded);
    let sections: Vec<Vec<Vec3>> = offsets.sections.iter().map(|s| s.points.clone()).collect();
    let flats = crate::flats::find_flat_lines(&sections, &crate::flats::FlatOptions::default())
        .map_err(|reason| crate::HullError::Fit { method: "validity", reason })?;
    Ok((envelope, flats))
}

/// One face of the envelope or one flat: `coordinate axis` past `reference` (above it if
/// `upper`) by more than `limit`, within the x `band` if given.
#[derive(Clone, Copy)]
struct Probe {
    kind: FindingKind,
    axis: usize,
    upper: bool,
    reference: f64,
    limit: f64,
    band: Option<(f64, f64)>,
    flat: Option<Flat>,
}

/// Rounds of golden-section search, each over `u` then `v`, and steps per search: the
/// interval shrinks by 0.618 a step, to 1e-8 of the two grid cells after 40.
const REFINE_ROUNDS: usize = 4;
const GOLDEN_STEPS: usize = 40;

impl Probe {
    fn new(kind: FindingKind, axis: usize, upper: bool, reference: f64, limit: f64) -> Self {
        Probe { kind, axis, upper, reference, limit, band: None, flat: None }
    }

    /// How far `p` is past the reference (negative inside; `-inf` outside the band).
    fn excess(&self, p: Vec3) -> f64 {
        if self.band.is_some_and(|(a, b)| !(p.x >= a && p.x <= b)) {
            return f64::NEG_INFINITY;
        }
        let c = p[self.axis];
        if self.upper {
            c - self.reference
        } else {
            self.reference - c
        }
    }

    /// Whether the surface can pass the limit near grid node `k`, over the grid cells on either
    /// side that [`refine`] searches: by the convex-hull property (positive weights), not where
    /// every control point shaping those cells is within the limit. Lets [`Probe::check`] skip
    /// refining a worst node that cannot be past the limit (most probes of a sound surface),
    /// its verdict the same.
    fn may_pass_near(&self, surface: &NurbsSurface, grid: &Grid, k: usize) -> bool {
        let (ur, vr) = (near_range(&grid.us, k % grid.nu()), near_range(&grid.vs, k / grid.nu()));
        let rows = |knots: &nurbs::KnotVector, (a, b): (f64, f64)| {
            knots.find_span(a).saturating_sub(knots.degree())..=knots.find_span(b)
        };
        let (ru, rv) = (rows(surface.knots_u(), ur), rows(surface.knots_v(), vr));
        ru.flat_map(|i| rv.clone().map(move |j| (i, j))).any(|(i, j)| {
            let c = surface.control_point(i, j)[self.axis];
            let past = if self.upper { c - self.reference } else { self.reference - c };
            !(past <= self.limit)
        })
    }

    /// The worst of the connected regions of grid nodes past the limit (4-neighbours), each
    /// from its worst node refined, with the band of its region and the count of regions;
    /// without any such node, the worst node refined, if that is past the limit.
    fn check(&self, surface: &NurbsSurface, grid: &Grid) -> Option<Finding> {
        if !(self.reference.is_finite() && self.limit.is_finite()) {
            return None;
        }
        let excess: Vec<f64> = grid.nodes.iter().map(|n| self.excess(n.p)).collect();
        let mut regions = regions(grid, |k| excess[k] > self.limit);
        if regions.is_empty() {
            match excess.iter().enumerate().max_by(|a, b| a.1.total_cmp(b.1)) {
                Some((k, &e)) if e > f64::NEG_INFINITY && self.may_pass_near(surface, grid, k) => regions.push(vec![k]),
                _ => return None,
            }
        }
        let out: Vec<Finding> = regions
            .iter()
            .filter_map(|region| {
                let &k = region.iter().max_by(|&&a, &&b| excess[a].total_cmp(&excess[b]))?;
                let (u, v, size) = refine(surface, grid, k % grid.nu(), k / grid.nu(), |p| self.excess(p));
                if !(size > self.limit) {
                    return None;
                }
                let place = Place::at(surface, u, v);
                let x_band = region
                    .iter()
                    .fold((place.x, place.x), |(a, b), &k| (a.min(grid.nodes[k].p.x), b.max(grid.nodes[k].p.x)));
                Some(Finding {
                    kind: self.kind,
                    place,
                    size,
                    limit: self.limit,
                    reference: Some(self.reference),
                    x_band: Some(x_band),
                    flat: self.flat,
                    places: 1,
                })
            })
            .collect();
        let places = out.len();
        let worst = out.into_iter().max_by(|a, b| a.size.total_cmp(&b.size))?;
        Some(Finding { places, ..worst })
    }
}

/// The connected regions (4-neighbours on the grid) of the nodes where `inside`, each as its
/// node indices, in the order of their first node.
fn regions(grid: &Grid, inside: impl Fn(usize) -> bool) -> Vec<Vec<usize>> {
    let (nu, n) = (grid.nu(), grid.nodes.len());
    let nv = n / nu.max(1);
    let mut seen = vec![false; n];
    let mut out = Vec::new();
    for start in 0..n {
        if seen[start] || !inside(start) {
            continue;
        }
        let mut region = Vec::new();
        let mut queue = VecDeque::from([start]);
        seen[start] = true;
        while let Some(k) = queue.pop_front() {
            region.push(k);
            let (i, j) = (k % nu, k / nu);
            let near =
                [(i > 0, k.wrapping_sub(1)), (i + 1 < nu, k + 1), (j > 0, k.wrapping_sub(nu)), (j + 1 < nv, k + nu)];
            for (ok, m) in near {
                if ok && !seen[m] && inside(m) {
                    seen[m] = true;
                    queue.push_back(m);
                }
            }
        }
        out.push(region);
    }
    out
}

/// The parameters of the grid lines either side of line `k` of `t` (the ends at the ends): the
/// range [`refine`] searches.
fn near_range(t: &[f64], k: usize) -> (f64, f64) {
    (t[k.saturating_sub(1)], t[(k + 1).min(t.len() - 1)])
}

/// The largest `f(S(u, v))` near grid node `(i, j)`: golden-section searches, alternately in
/// `u` and `v`, over the grid cells on either side, never worse than the node. Returns
/// `(u, v, f)`.
fn refine(surface: &NurbsSurface, grid: &Grid, i: usize, j: usize, f: impl Fn(Vec3) -> f64) -> (f64, f64, f64) {
    let (ua, ub) = near_range(&grid.us, i);
    let (va, vb) = near_range(&grid.vs, j);
    let (mut u, mut v) = (grid.us[i], grid.vs[j]);
    let mut best = f(surface.point(u, v));
    for _ in 0..REFINE_ROUNDS {
        let (t, g) = golden_max(ua, ub, |t| f(surface.point(t, v)));
        if g > best {
            (u, best) = (t, g);
        }
        let (t, g) = golden_max(va, vb, |t| f(surface.point(u, t)));
        if g > best {
            (v, best) = (t, g);
        }
    }
    (u, v, best)
}

/// The largest of `g` on `[a, b]` by golden-section search (a local maximum), the interval's
/// ends included. Returns `(t, g(t))`.
fn golden_max(a: f64, b: f64, g: impl Fn(f64) -> f64) -> (f64, f64) {
    const R: f64 = 0.618_033_988_749_894_8; // (sqrt 5 - 1) / 2
    let mut best = [(a, g(a)), (b, g(b))].into_iter().max_by(|x, y| x.1.total_cmp(&y.1)).unwrap_or((a, g(a)));
    let (mut lo, mut hi) = (a, b);
    let (mut c, mut d) = (hi - R * (hi - lo), lo + R * (hi - lo));
    let (mut gc, mut gd) = (g(c), g(d));
    for _ in 0..GOLDEN_STEPS {
        if gc > gd {
            hi = d;
            (d, gd) = (c, gc);
            c = hi - R * (hi - lo);
            gc = g(c);
        } else {
            lo = c;
            (c, gc) = (d, gd);
            d = lo + R * (hi - lo);
            gd = g(d);
        }
    }
    for (t, gt) in [(c, gc), (d, gd)] {
        if gt > best.1 {
            best = (t, gt);
        }
    }
    best
}

/// Samples along `v` per grid line `u` when measuring how far a fold runs back.
const FOLD_SAMPLES: usize = 64;

/// A fold band as a finding: the largest backward run `max_{a < b} s (x_a - x_b)` along the
/// grid's `u` lines over the band's `v` range widened by one grid line each side, at
/// [`FOLD_SAMPLES`] + 1 values of `v`; the place is the end of that run.
fn fold_finding(surface: &NurbsSurface, grid: &Grid, fold: &Fold, sign: f64) -> Finding {
    let pos = |v: f64| grid.vs.iter().position(|&t| t == v).unwrap_or(0);
    let (ja, jb) = (pos(fold.v.0).saturating_sub(1), (pos(fold.v.1) + 1).min(grid.vs.len() - 1));
    let (va, vb) = (grid.vs[ja], grid.vs[jb]);
    let mid_u = grid.us[grid.nu() / 2];
    let mut best = (0.0, (mid_u, 0.5 * (fold.v.0 + fold.v.1)));
    for &u in &grid.us {
        let mut run_max = f64::NEG_INFINITY;
        for k in 0..=FOLD_SAMPLES {
            let v = va + (vb - va) * k as f64 / FOLD_SAMPLES as f64;
            let x = sign * surface.point(u, v).x;
            run_max = run_max.max(x);
            if run_max - x > best.0 {
                best = (run_max - x, (u, v));
            }
        }
    }
    let (size, (u, v)) = best;
    Finding {
        kind: FindingKind::Fold,
        place: Place::at(surface, u, v),
        size,
        limit: 0.0,
        reference: None,
        x_band: Some(fold.x),
        flat: None,
        places: 1,
    }
}

/// Union-find with the parity of each node to its root (the orientation relative to it).
#[derive(Clone)]
struct Orientation {
    parent: Vec<usize>,
    parity: Vec<bool>,
    /// Nodes under each root (union by size keeps the trees shallow).
    size: Vec<usize>,
}

impl Orientation {
    fn new(n: usize) -> Self {
        Orientation { parent: (0..n).collect(), parity: vec![false; n], size: vec![1; n] }
    }

    /// Join the trees of roots `ra` and `rb`, the parity between them `parity`: the smaller
    /// under the larger. Which root stays does not change the orientation of any node relative
    /// to another, which is all [`oriented`] reads.
    fn join(&mut self, ra: usize, rb: usize, parity: bool) {
        let (big, small) = if self.size[ra] >= self.size[rb] { (ra, rb) } else { (rb, ra) };
        self.parent[small] = big;
        self.parity[small] = parity;
        self.size[big] += self.size[small];
    }

    /// Join the trees of `edges` `(k, m, flip)` in their order, the parity across each its
    /// `flip`, passing over an edge within one tree (Kruskal's algorithm, on edges sorted by
    /// weight). With `even`, stop at the first such edge whose flip disagrees with the trees
    /// (a cycle flipping an odd number of times) and return `false`; else `true`.
    fn join_edges(&mut self, edges: impl Iterator<Item = (usize, usize, bool)>, even: bool) -> bool {
        for (a, b, flip) in edges {
            let ((ra, pa), (rb, pb)) = (self.find(a), self.find(b));
            if ra != rb {
                self.join(ra, rb, pa ^ pb ^ flip);
            } else if even && pa ^ pb != flip {
                return false;
            }
        }
        true
    }

    /// The root of `k` and the parity of `k` to it, compressing the path.
    fn find(&mut self, k: usize) -> (usize, bool) {
        // The root, and the parity of k to it (the xor of the parities on the path).
        let (mut r, mut to_root) = (k, false);
        while self.parent[r] != r {
            to_root ^= self.parity[r];
            r = self.parent[r];
        }
        // Point the path at the root: each node's parity to the root is what is left of
        // k's once the nodes before it are taken off.
        let (mut n, mut acc) = (k, to_root);
        while self.parent[n] != r && n != r {
            let (next, own) = (self.parent[n], self.parity[n]);
            self.parent[n] = r;
            self.parity[n] = acc;
            acc ^= own;
            n = next;
        }
        (r, to_root)
    }
}

/// A grid edge from node `k` as one number that sorts as the edges are to be joined: its
/// `weight` (in the order of [`f64::total_cmp`]), then `k`, then whether it runs `across` to
/// `k + nu` (after the edge to `k + 1`), with whether it flips in the lowest bit.
fn edge_key(weight: f64, k: usize, across: bool, flip: bool) -> u128 {
    // f64::total_cmp's key, as an unsigned number in the same order.
    let bits = weight.to_bits() as i64;
    let ordered = (bits ^ (((bits >> 63) as u64) >> 1) as i64) as u64 ^ (1 << 63);
    (u128::from(ordered) << 64) | ((k as u128) << 2) | (u128::from(across) << 1) | u128::from(flip)
}

/// The edge `(k, m, flip)` of [`edge_key`] on a grid `nu` nodes wide.
fn edge_of(key: u128, nu: usize) -> (usize, usize, bool) {
    let k = ((key as u64) >> 2) as usize;
    let m = if key & 2 != 0 { k + nu } else { k + 1 };
    (k, m, key & 1 != 0)
}

/// Each of `n` grid nodes (`nu` wide) labelled by the root of its tree and its parity to that
/// root, the trees those of the minimum spanning forest of `edges` ([`edge_key`]s) by Kruskal's
/// algorithm, the parity across each edge its flip: the propagation of [`oriented`].
///
/// The minimum spanning tree decides, equal weights in the grid's order (the nodes break ties),
/// so the tree does not depend on the sort. Where no cycle of the grid flips an odd number of
/// times, every spanning forest gives each node the same parity to the others of its component
/// (a whole component flipped at most, which changes no minority in [`oriented`]): the grid's
/// order, no sort. Else only the heavy part is sorted: the edges lighter than every flipping
/// one (24 to 99.6 % of them in the checks of LM on the frigate, above 80 % in 15 of its 23)
/// come first in the sorted order and flip nowhere, so every spanning forest of them leaves
/// the components and relative parities the sorted order leaves; they are joined in the grid's
/// order, the rest after them, sorted. (The heavy edges are tried in the grid's order first:
/// the light ones cannot close a cycle of odd flips, so if the heavy ones close none either,
/// the grid has none.)
fn spanning_parities(n: usize, nu: usize, mut edges: Vec<u128>) -> Vec<(usize, bool)> {
    let lightest_flip = edges.iter().filter(|&&e| e & 1 != 0).map(|&e| e >> 64).min().unwrap_or(u128::MAX);
    let light = |e: u128| e >> 64 < lightest_flip;
    let mut orient = Orientation::new(n);
    orient.join_edges(edges.iter().filter(|&&e| light(e)).map(|&e| edge_of(e, nu)), false);
    edges.retain(|&e| !light(e));
    let mut unsorted = orient.clone();
    if unsorted.join_edges(edges.iter().map(|&e| edge_of(e, nu)), true) {
        orient = unsorted;
    } else {
        edges.sort_unstable();
        orient.join_edges(edges.iter().map(|&e| edge_of(e, nu)), false);
    }
    (0..n).map(|k| orient.find(k)).collect()
}

/// The orientation of the sampled surface's normals `S_u x S_v`, propagated over the grid
/// (see [`check_validity`]).
struct Oriented {
    /// Each node's area `|S_u x S_v| du dv` (0 where the normal is degenerate).
    area: Vec<f64>,
    /// The sum of `area`.
    total: f64,
    /// Nodes of the smaller orientation of their connected component: facing inwards.
    minority: Vec<bool>,
}

/// The orientation of the grid's normals; `None` where no grid edge flips (one orientation
/// everywhere) or the surface has no size.
fn oriented(surface: &NurbsSurface, grid: &Grid) -> Option<Oriented> {
    let (nu, nv) = (grid.nu(), grid.vs.len());
    let size = surface.model_size()?;
    let ((u0, u1), (v0, v1)) = (surface.domain_u(), surface.domain_v());
    // |S_u x S_v| at round-off of the model's area per unit parameter area: degenerate.
    let area_tol = COINCIDENT_REL * size * size / ((u1 - u0) * (v1 - v0));
    let normals: Vec<Vec3> = grid.nodes.iter().map(|n| n.su.cross(n.sv)).collect();
    let norms: Vec<f64> = normals.iter().map(|n| n.norm()).collect();
    let valid: Vec<bool> = normals.iter().zip(&norms).map(|(n, &l)| l > area_tol && n.is_finite()).collect();
    // The grid edges between regular nodes, as (k, m).
    let edge_ends = || {
        (0..nu * nv).flat_map(move |k| {
            [(k + 1, k % nu + 1 < nu), (k + nu, k / nu + 1 < nv)]
                .into_iter()
                .filter(|&(_, ok)| ok)
                .map(move |(m, _)| (k, m))
        })
    };
    // No edge flips (its normals' cosine below 0, which needs their dot product below 0):
    // every component has one orientation, nothing to find (the tree below would give every
    // node parity 0), and the areas and edges need not be formed.
    if !edge_ends().any(|(k, m)| valid[k] && valid[m] && normals[k].dot(normals[m]) < 0.0) {
        return None;
    }
    let half_steps = |t: &[f64]| -> Vec<f64> {
        (0..t.len()).map(|k| 0.5 * (t[(k + 1).min(t.len() - 1)] - t[k.saturating_sub(1)])).collect()
    };
    let (du, dv) = (half_steps(&grid.us), half_steps(&grid.vs));
    let area: Vec<f64> =
        (0..nu * nv).map(|k| if valid[k] { norms[k] * du[k % nu] * dv[k / nu] } else { 0.0 }).collect();
    let total: f64 = area.iter().sum();
    if !(total > 0.0) {
        return None;
    }
    // Grid edges between regular nodes, weighted 1 - |cos|, flipping where cos < 0.
    let mut edges: Vec<u128> = Vec::with_capacity(2 * nu * nv);
    for (k, m) in edge_ends().filter(|&(k, m)| valid[k] && valid[m]) {
        let cos = normals[k].dot(normals[m]) / (norms[k] * norms[m]);
        edges.push(edge_key(1.0 - cos.abs(), k, m != k + 1, cos < 0.0));
    }
    let label = spanning_parities(nu * nv, nu, edges);
    // Per component (by its root, a node), the area of each orientation; the smaller is the
    // inward one.
    let mut sums = vec![[0.0f64; 2]; nu * nv];
    for k in (0..nu * nv).filter(|&k| valid[k]) {
        sums[label[k].0][usize::from(label[k].1)] += area[k];
    }
    let minority = (0..nu * nv)
        .map(|k| {
            let s = sums[label[k].0];
            let inward = s[1] < s[0];
            valid[k] && label[k].1 == inward && s[usize::from(inward)] < s[usize::from(!inward)]
        })
        .collect();
    Some(Oriented { area, total, minority })
}

/// The largest inward-facing region of the sampled surface (the minority orientation of `o`,
/// larger than `INWARD_SHARE` of the area) with the count of such regions, leaving out those
/// of which most of the area is on nodes where `folded` (a fold's own facets, reported as the
/// fold). `None` when no region is past the limit.
fn inward_facing(surface: &NurbsSurface, grid: &Grid, o: &Oriented, folded: impl Fn(usize) -> bool) -> Option<Finding> {
    let Oriented { area, total, minority: flipped } = o;
    let minority = |k: usize| flipped[k];
    let limit = INWARD_SHARE * total;
    let mut out: Vec<Finding> = Vec::new();
    // Two neighbouring regular nodes share an edge, so are in one component: each region is.
    for part in regions(grid, minority) {
        let region_area: f64 = part.iter().map(|&k| area[k]).sum();
        let folded_area: f64 = part.iter().filter(|&&k| folded(k)).map(|&k| area[k]).sum();
        if !(region_area > limit) || 2.0 * folded_area > region_area {
            continue;
        }
        let Some(&largest) = part.iter().max_by(|&&a, &&b| area[a].total_cmp(&area[b])) else { continue };
        let band = part.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &k| {
            (a.min(grid.nodes[k].p.x), b.max(grid.nodes[k].p.x))
        });
        let (u, v) = grid.uv(largest);
        out.push(Finding {
            kind: FindingKind::InwardFacing,
            place: Place::at(surface, u, v),
            size: region_area,
            limit,
            reference: None,
            x_band: Some(band),
            flat: None,
            places: 1,
        });
    }
    let places = out.len();
    out.into_iter().max_by(|a, b| a.size.total_cmp(&b.size)).map(|worst| Finding { places, ..worst })
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::KnotVector;

    /// A Bezier patch of degrees `(p, q)` = `(ys.len() - 1, xs.len() - 1)`: the control point
    /// `(i, j)` is `(xs[j], ys[i], zs[i])`, so `x` depends on `v` only and `(y, z)` on `u`
    /// only (a cylinder over the section `(y(u), z(u))`, along `x(v)`).
    fn patch(ys: &[f64], zs: &[f64], xs: &[f64]) -> NurbsSurface {
        let bezier = |n: usize| {
            let p = n - 1;
            let mut k = vec![0.0; p + 1];
            k.extend(vec![1.0; p + 1]);
            KnotVector::try_new(p, k).expect("valid")
        };
        let pts: Vec<Vec3> = (0..ys.len()).flat_map(|i| xs.iter().map(move |&x| Vec3::new(x, ys[i], zs[i]))).collect();
        NurbsSurface::try_new(bezier(ys.len()), bezier(xs.len()), &pts, None).expect("valid")
    }

    /// A box with no section extents (no flat can be placed).
    fn bare(x: (f64, f64), y: (f64, f64), z: (f64, f64)) -> Envelope {
        Envelope { x, y, z, sections_x: Vec::new() }
    }

    /// The rounded bilge quarter `y = 4u - 2u^2`, `z = 2u^2` from keel (0, 0) to side (2, 2),
    /// along x from 0 to 10, exactly filling its box.
    fn sound() -> NurbsSurface {
        patch(&[0.0, 2.0, 2.0], &[0.0, 0.0, 2.0], &[0.0, 5.0, 10.0])
    }

    fn kinds(f: &[Finding]) -> Vec<FindingKind> {
        f.iter().map(|f| f.kind).collect()
    }

    #[test]
    fn a_surface_filling_its_box_has_no_finding() {
        let f = check_validity(&sound(), &bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0)), &[]);
        assert!(f.is_empty(), "{f:?}");
        // Nor without any envelope: it neither folds nor faces inwards anywhere.
        assert!(check_validity(&sound(), &Envelope::unbounded(), &[]).is_empty());
    }

    #[test]
    fn crossing_the_centre_plane_is_found_with_its_depth() {
        // y(u) = 0.5 (1-u)^2 - 2 u (1-u) + 0.5 u^2: least -0.25 at u = 1/2 (interior).
        let s = patch(&[0.5, -1.0, 0.5], &[0.0, 1.0, 2.0], &[0.0, 5.0, 10.0]);
        let f = check_validity(&s, &bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0)), &[]);
        assert_eq!(kinds(&f), [FindingKind::BelowCentrePlane], "{f:?}");
        let f = &f[0];
        // Golden-section search to 1e-8 of the cells in u: the value is quadratic near the
        // least, so exact to round-off (1e-12).
        assert!((f.size - 0.25).abs() < 1e-12, "{f:?}");
        assert!((f.place.u - 0.5).abs() < 1e-6 && (f.place.y + 0.25).abs() < 1e-12, "{f:?}");
        // 0.5 % of the 2.0 half-beam.
        assert!((f.limit - 0.01).abs() < 1e-15, "{f:?}");
        assert_eq!((f.reference, f.x_band), (Some(0.0), Some((0.0, 10.0))));
        let m = f.message("m");
        assert!(m.contains("crosses the centre plane") && m.contains("by 0.250 m") && m.contains("--ctrl"), "{m}");
    }

    #[test]
    fn two_separate_crossings_are_one_finding_at_the_worse_with_the_count() {
        // The quartic Bezier y(u) with controls 0.3, -1.2, 2, -1.2, 0.3 dips below 0 twice,
        // symmetrically (u in 0.071..0.286 and 0.714..0.929): two regions, equally deep.
        let c = [0.3, -1.2, 2.0, -1.2, 0.3];
        let s = patch(&c, &[0.0, 0.5, 1.0, 1.5, 2.0], &[0.0, 5.0, 10.0]);
        let f = check_validity(&s, &bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0)), &[]);
        assert_eq!(kinds(&f), [FindingKind::BelowCentrePlane], "{f:?}");
        assert_eq!(f[0].places, 2, "{f:?}");
        // The least by the Bernstein form on a 1e-6 grid: y'' <= 30, so within 30 (5e-7)^2 / 2
        // of the true least, below 1e-11.
        let bernstein = |u: f64| {
            let b = [1.0, 4.0, 6.0, 4.0, 1.0];
            (0..5).map(|i| b[i] * u.powi(i as i32) * (1.0 - u).powi(4 - i as i32) * c[i]).sum::<f64>()
        };
        let least = (0..=1_000_000).map(|i| bernstein(i as f64 * 1e-6)).fold(f64::INFINITY, f64::min);
        assert!((f[0].size + least).abs() < 1e-9, "{} vs {least}", f[0].size);
        assert!(f[0].message("m").contains("(the worst of 2 places)"), "{}", f[0].message("m"));
    }

    #[test]
    fn a_bulge_beyond_the_half_breadth_and_below_the_keel_are_measured() {
        // y(u) = 2 * 2.4 u (1-u) + 2 u^2 = 4.8 u - 2.8 u^2: largest 100.8 / 49 at u = 6/7,
        // past the offsets' 2.0. z(u) = -0.2 u (1-u) + 2 u^2 dips to -0.2^2 / 8.8 = -4.5 mm at
        // u = 1/22, within the 10 mm allowed (0.5 % of the depth 2): not reported.
        let s = patch(&[0.0, 2.4, 2.0], &[0.0, -0.1, 2.0], &[0.0, 5.0, 10.0]);
        let env = bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0));
        let f = check_validity(&s, &env, &[]);
        assert_eq!(kinds(&f), [FindingKind::BeyondHalfBreadth], "{f:?}");
        assert!((f[0].size - (100.8 / 49.0 - 2.0)).abs() < 1e-12, "{f:?}");
        assert!((f[0].place.u - 6.0 / 7.0).abs() < 1e-6, "{f:?}");
        // z(u) = -0.2 (2u(1-u)) + 2u^2 = -0.4 u + 2.4 u^2: least -0.4^2 / (4 * 2.4) = -1/60
        // at u = 1/12, past the 0.01 allowance.
        let s = patch(&[0.0, 2.0, 2.0], &[0.0, -0.2, 2.0], &[0.0, 5.0, 10.0]);
        let f = check_validity(&s, &env, &[]);
        assert_eq!(kinds(&f), [FindingKind::BelowLowestOffset], "{f:?}");
        assert!((f[0].size - 1.0 / 60.0).abs() < 1e-12, "{f:?}");
        // Above the top: the same surface against a box 0.1 lower (an edge maximum, u = 1).
        let f = check_validity(&sound(), &bare((0.0, 10.0), (0.0, 2.0), (0.0, 1.9)), &[]);
        assert_eq!(kinds(&f), [FindingKind::AboveHighestOffset], "{f:?}");
        assert!((f[0].size - 0.1).abs() < 1e-12 && f[0].place.u == 1.0, "{f:?}");
    }

    #[test]
    fn running_past_the_aft_end_is_a_fold_and_an_envelope_finding() {
        // x(v) = -4 v (1-v) + 10 v^2 = -4v + 14 v^2: least -2/7 at v = 1/7, running back
        // 2/7 from x(0) = 0 before it advances.
        let s = patch(&[0.0, 2.0, 2.0], &[0.0, 0.0, 2.0], &[0.0, -2.0, 10.0]);
        let f = check_validity(&s, &bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0)), &[]);
        assert_eq!(kinds(&f), [FindingKind::Fold, FindingKind::PastAftEnd], "{f:?}");
        // The run back is sampled at 65 values over the band: the least of x is quadratic, so
        // within (Δv)^2 x_vv / 8 = (0.2 / 64)^2 * 28 / 8 ≈ 3.4e-5 of it.
        assert!((f[0].size - 2.0 / 7.0).abs() < 4e-5, "{f:?}");
        assert_eq!(f[0].limit, 0.0);
        assert!((f[1].size - 2.0 / 7.0).abs() < 1e-12 && (f[1].place.v - 1.0 / 7.0).abs() < 1e-6, "{f:?}");
        assert!(f[0].message("m").contains("folds back across the sections"));
        // The bands sampled once with the rest are find_folds' own.
        let (_, folds) = validity_and_folds(&s, &Envelope::unbounded(), &[]);
        assert_eq!(folds, crate::analysis::find_folds(&s));
        assert_eq!(f[0].x_band, Some(folds[0].x));
        // Forward past the fore end: x(v) = 24 v - 14 v^2 overshoots to 72/7 at v = 6/7 and
        // runs back to 10 at v = 1, a fold there too.
        let s = patch(&[0.0, 2.0, 2.0], &[0.0, 0.0, 2.0], &[0.0, 12.0, 10.0]);
        let f = check_validity(&s, &bare((0.0, 10.0), (0.0, 2.0), (0.0, 2.0)), &[]);
        assert_eq!(kinds(&f), [FindingKind::Fold, FindingKind::PastForeEnd], "{f:?}");
        assert!((f[1].size - (72.0 / 7.0 - 10.0)).abs() < 1e-12, "{f:?}");
        assert!((f[0].size - (72.0 / 7.0 - 10.0)).abs() < 4e-5, "{f:?}");
    }

    /// Five sections from x = 0 to 10 with a flat bottom (three offsets on z = 0), then a
    /// side rising to (2, 2); their flat lines by the kernel's detection.
    fn flat_bottomed() -> (Envelope, Vec<FlatLine>) {
        let sections: Vec<Vec<Vec3>> = (0..5)
            .map(|k| {
                let x = 2.5 * k as f64;
                [(0.0, 0.0), (0.5, 0.0), (1.0, 0.0), (1.8, 0.6), (2.0, 2.0)]
                    .iter()
                    .map(|&(y, z)| Vec3::new(x, y, z))
                    .collect()
            })
            .collect();
        let flats = crate::flats::find_flat_lines(&sections, &crate::flats::FlatOptions::default()).expect("finite");
        let sections_x = (0..5).map(|k| (2.5 * k as f64, 2.5 * k as f64)).collect();
        (Envelope { x: (0.0, 10.0), y: (0.0, 2.0), z: (0.0, 2.0), sections_x }, flats)
    }

    #[test]
    fn a_flat_bottom_crossed_by_less_than_the_envelope_allowance_is_a_bulge() {
        let (env, flats) = flat_bottomed();
        assert_eq!(flats.len(), 1, "{flats:?}");
        assert_eq!((flats[0].kind, flats[0].plane), (FlatKind::Bottom, 0.0));
        // The bottom z(u) = 2 z_m u (1-u) dips z_m / 2 = 5 mm at u = 1/2: inside the envelope's
        // 10 mm (0.5 % of the depth 2), through the flat's 1 mm (0.05 %).
        let s = patch(&[0.0, 1.0, 2.0], &[0.0, -0.01, 0.0], &[0.0, 5.0, 10.0]);
        let f = check_validity(&s, &env, &flats);
        assert_eq!(kinds(&f), [FindingKind::FlatBulge], "{f:?}");
        assert!((f[0].size - 0.005).abs() < 1e-12 && (f[0].limit - 0.001).abs() < 1e-15, "{f:?}");
        assert_eq!((f[0].flat, f[0].reference), (Some(Flat::Bottom), Some(0.0)));
        assert!(f[0].message("m").contains("flat of bottom (z = 0.000 m) by 0.00500 m"), "{}", f[0].message("m"));
        // Without the flats, or with the flat's sections elsewhere (x 0 to 2.5 only, while
        // the surface is the same everywhere: still found, within that band).
        assert!(check_validity(&s, &env, &[]).is_empty());
        let mut short = flats.clone();
        short[0].index = vec![Some(2), Some(2), None, None, None];
        let f = check_validity(&s, &env, &short);
        assert_eq!(kinds(&f), [FindingKind::FlatBulge], "{f:?}");
        let (a, b) = f[0].x_band.expect("a band");
        // x = 10 v on the grid's v lines: exact to round-off.
        assert!(a.abs() < 1e-12 && (b - 2.5).abs() < 1e-12 && f[0].place.x <= 2.5 + 1e-12, "{f:?}");
    }

    #[test]
    fn a_section_doubling_back_faces_inwards_over_the_part_run_backwards() {
        // Along the line y = z: y(u) = 9 u (1-u) + u^3 out to its largest y* at
        // u* = (18 - sqrt 216) / 6, back to 1. S_u reverses at u*, so the normal of the part
        // u > u* points the other way: a strip of width sqrt 2 (y* - 1), 10 long.
        let c = [0.0, 3.0, 3.0, 1.0];
        let s = patch(&c, &c, &[0.0, 10.0]);
        let us = (18.0 - 216f64.sqrt()) / 6.0;
        let ymax = 9.0 * us * (1.0 - us) + us.powi(3);
        let f = check_validity(&s, &Envelope::unbounded(), &[]);
        assert_eq!(kinds(&f), [FindingKind::InwardFacing], "{f:?}");
        let want = 10.0 * 2f64.sqrt() * (ymax - 1.0);
        eprintln!("inward-facing strip: {} against {want} (relative {:.2e})", f[0].size, f[0].size / want - 1.0);
        // Node areas on the grid's 1/16 steps in u: the node next to u* carries half a cell on
        // the other side, at most h^2 |c''| / 2 * 10 sqrt 2 = 0.41 (|c''| <= 18), 2 % of the
        // area; the trapezoidal error elsewhere is O(h^2) smaller. Measured: 0.26 %.
        assert!((f[0].size - want).abs() < 0.02 * want, "{} vs {want}", f[0].size);
        assert!(f[0].place.u > us, "{f:?}");
        assert!(f[0].message("m").contains("faces inwards"));
    }

    #[test]
    fn the_light_edges_joined_unsorted_leave_the_trees_of_the_sorted_order() {
        use rand::{Rng, SeedableRng};
        // Each node's component (its least node) and parity to that node: what `oriented`
        // reads of the labels, whichever root the trees have.
        let canonical = |labels: &[(usize, bool)]| -> Vec<(usize, bool)> {
            let mut first = std::collections::BTreeMap::new();
            for (k, &(root, parity)) in labels.iter().enumerate() {
                first.entry(root).or_insert((k, parity));
            }
            labels.iter().map(|&(root, parity)| (first[&root].0, parity ^ first[&root].1)).collect()
        };
        let joined = |n: usize, nu: usize, edges: &[u128]| {
            let mut o = Orientation::new(n);
            o.join_edges(edges.iter().map(|&e| edge_of(e, nu)), false);
            (0..n).map(|k| o.find(k)).collect::<Vec<_>>()
        };
        let mut rng = rand_chacha::ChaCha8Rng::seed_from_u64(11);
        // Cases where the grid's order gives other trees than the sorted order: the random
        // graphs do test the order (without the sort of the heavy part, the check fails).
        let mut order_matters = 0;
        for case in 0..300 {
            let (nu, nv) = (rng.random_range(2..10usize), rng.random_range(2..10usize));
            let n = nu * nv;
            let flip_share = [0.03, 0.2, 0.5][case % 3];
            let mut edges = Vec::new();
            for k in 0..n {
                for (across, ok) in [(false, k % nu + 1 < nu), (true, k / nu + 1 < nv)] {
                    // Some edges missing (irregular nodes), weights from a few values (ties),
                    // one a little below 0 (round-off in 1 - |cos|).
                    if ok && rng.random_bool(0.9) {
                        let w = [-1e-16, 0.0, 0.1, 0.2, 0.5, 1.0][rng.random_range(0..6)];
                        edges.push(edge_key(w, k, across, rng.random_bool(flip_share)));
                    }
                }
            }
            let mut sorted = edges.clone();
            sorted.sort_unstable();
            let want = canonical(&joined(n, nu, &sorted));
            order_matters += usize::from(canonical(&joined(n, nu, &edges)) != want);
            assert_eq!(canonical(&spanning_parities(n, nu, edges)), want, "case {case}");
        }
        assert!(order_matters > 30, "{order_matters} of 300 cases depend on the order");
    }

    #[test]
    fn edge_keys_sort_as_weights_then_nodes() {
        // Weights of either sign (1 - |cos| is a little below 0 where round-off puts |cos|
        // above 1), equal weights from several nodes, both directions from one node.
        let nu = 5;
        let weights = [0.5, 0.5, 0.0, -0.0, 1.0, 0.5, 1e-300, 0.0, -1e-16, -3.0];
        let mut tuples: Vec<(f64, usize, usize, bool)> = Vec::new();
        for (i, &w) in weights.iter().enumerate() {
            let k = i / 2;
            tuples.push((w, k, k + 1 + (nu - 1) * (i % 2), i % 3 == 0));
        }
        let mut keys: Vec<u128> = tuples.iter().map(|&(w, k, m, flip)| edge_key(w, k, m != k + 1, flip)).collect();
        tuples.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.cmp(&b.1)).then(a.2.cmp(&b.2)));
        keys.sort_unstable();
        let edges: Vec<(usize, usize, bool)> = keys.iter().map(|&e| edge_of(e, nu)).collect();
        let expected: Vec<(usize, usize, bool)> = tuples.iter().map(|&(_, k, m, flip)| (k, m, flip)).collect();
        assert_eq!(edges, expected);
    }

    #[test]
    fn the_envelope_of_offsets_and_its_extents() {
        let o = crate::series60_sample();
        let e = Envelope::of_offsets(&o).expect("points");
        let (lo, hi) = o.bounds().expect("points");
        assert_eq!((e.x, e.y, e.z), ((lo.x, hi.x), (0.0, hi.y), (lo.z, hi.z)));
        assert_eq!(e.sections_x.len(), o.sections.len());
        assert_eq!((e.half_beam(), e.depth(), e.length()), (hi.y, hi.z - lo.z, hi.x - lo.x));
        let kinds = serde_json::to_value(FindingKind::BelowCentrePlane).expect("serialises");
        assert_eq!(kinds, "below_centre_plane");
        assert_eq!(FindingKind::InwardFacing.name(), "inward_facing");
    }
}
