//! The lines plan of a hull surface: body plan, half-breadth plan and profile on one sheet at
//! one standard scale, with grid, outline, the offsets coloured by their fit error, optional
//! curvature combs, a colour legend and a title block.
//!
//! # Views
//!
//! All three views share one scale `k` (paper millimetres per model unit):
//!
//! - **profile** (top left): buttocks cut `y = c`, drawn in `(x, z)`; station and waterline
//!   grid lines; the baseline `z = 0`;
//! - **half-breadth plan** (below the profile, same x): waterlines cut `z = c`, drawn in
//!   `(x, y)` with the centreline at the bottom and starboard up (looking down on the hull with
//!   x forward, right-handed axes put +y up the page); buttocks as straight grid lines;
//! - **body plan** (right of the profile, same z): stations cut `x = c`, drawn in `(y, z)`;
//!   the aft stations (`x <` midship, the middle of the surface's x range) mirrored to the
//!   LEFT of the centreline, the fore stations on the right, as naval architects draw it.
//!
//! Every view also shows the surface's four boundary curves (keel or flat-of-bottom edge,
//! deck edge, stern and stem profiles) projected onto its plane (layer `outline`).
//!
//! # Sheet, scale and layout
//!
//! The scale is one of the standard scales 10:1, 5:1, 2:1, 1:1, 1:2, 1:5, 1:10, 1:20, 1:25,
//! 1:50, 1:100, 1:200, 1:250, 1:500, 1:1000, ... (`{1, 2, 2.5, 5} x 10^n`, ISO 5455 with the
//! 1:25 family of ship drawings). Three arrangements are tried, each at the largest scale at
//! which the views, their labels, the legend and the title block fit inside the frame
//! (margins of ISO 5457: 20 mm left, 10 mm elsewhere):
//!
//! - the body plan right of the profile, the title block (legend above it) right of the
//!   half-breadth plan;
//! - the same with the title block below the half-breadth plan;
//! - the body plan below the half-breadth plan, the title block right of it (long slender
//!   hulls).
//!
//! Of these the one drawing the largest share of the frame is taken. The drawn area counts
//! the three views' boxes (profile `L x H`, half-breadth plan `L x B/2`, body plan `B x H`, with
//! `H` from the baseline or keel to the top), the title block and the legend.
//!
//! The sheet is the one given ([`LinesPlanOptions::sheet`]), else chosen among the A sizes and
//! the elongated sizes of ISO 5457 ([`Sheet::standard`]): a ship's views are 5 to 10 times
//! longer than high, so on an A sheet most of the frame would stay empty at any scale. Of the
//! sheets, the smallest whose drawn share is within 90 % of the best sheet's is taken.
//!
//! # Curvature combs
//!
//! On each cut curve, each point `p` with in-plane unit normal `n_L` (the tangent turned
//! counter-clockwise in the plane's 2-D coordinates) and signed curvature `kappa` (positive
//! when turning counter-clockwise, [`CutPoint::curvature`]) gets the tooth
//! `p -> p - g kappa n_L`: it points away from the centre of curvature `p + n_L / kappa`, onto
//! the convex side, with length proportional to `|kappa|`. One factor `g` for the whole sheet
//! makes a tooth at the 95th percentile of `|kappa|` over the sheet
//! [`LinesPlanOptions::comb_length_mm`] long on paper; longer teeth are clipped at 1.5 times
//! that (on fitted hulls a few points at the stem foot or the keel curve far more sharply than
//! the rest, and scaling by the largest left every other tooth invisible). The teeth's ends
//! are joined by the comb's envelope.
//!
//! The output is deterministic: no date, no randomness, parallel work gathered in order.

use std::fmt;

use nurbs::{AxisPlane, NurbsSurface, ProjectionOptions, SurfaceProjector, Vec3};
use rayon::prelude::*;

use super::model::{Anchor, Drawing, Item, Rgb, Stroke};
use super::sheet::Sheet;
use hull::{cut_surface_many, sequential, CutCurve, CutOptions, CutPlane, CutPoint, Offsets, Units, PLANAR_REL};

/// Settings of [`lines_plan`]. `None` lists take the defaults described on each field;
/// non-finite values in a given list are ignored.
#[derive(Clone, Debug, PartialEq)]
pub struct LinesPlanOptions {
    /// Station x values. Default: the x of the offsets' sections when every section lies in
    /// one x plane (labelled with the sections' labels), else 21 stations evenly spaced over
    /// the surface's x range, ends included (labelled 0 to 20).
    pub stations: Option<Vec<f64>>,
    /// Waterline z values. Default: the offsets' own waterlines (heights shared by at least
    /// half the sections, as a table's rows) strictly between the bottom and the top of the
    /// surface, else about 9 round values between them.
    pub waterlines: Option<Vec<f64>>,
    /// Buttock y values. Default: about 4 round values between the centre plane and the
    /// largest half-breadth.
    pub buttocks: Option<Vec<f64>>,
    /// Draw curvature combs on every station, waterline and buttock.
    pub combs: bool,
    /// Length on paper of a comb tooth at the 95th percentile of |curvature| (longer teeth
    /// are clipped at 1.5 times this), mm.
    pub comb_length_mm: f64,
    /// The sheet. Default (`None`): chosen from [`Sheet::standard`], the A sizes and the
    /// elongated sizes of ISO 5457, for the largest share of the frame drawn (see the module
    /// documentation).
    pub sheet: Option<Sheet>,
    /// Title of the drawing and the title block's first line.
    pub title: String,
    /// The source named in the title block; default: the offsets' source, else `surface`.
    pub source: Option<String>,
    /// How the cuts are computed.
    pub cut: CutOptions,
}

impl Default for LinesPlanOptions {
    fn default() -> Self {
        LinesPlanOptions {
            stations: None,
            waterlines: None,
            buttocks: None,
            combs: false,
            comb_length_mm: 8.0,
            sheet: None,
            title: "Lines plan".into(),
            source: None,
            cut: CutOptions::default(),
        }
    }
}

/// A drawing scale `paper : model`, e.g. 1:500 (`paper = 1, model = 500`) or 2:1.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Scale {
    pub paper: u32,
    pub model: u32,
}

impl Scale {
    /// Paper length per model length.
    pub fn ratio(self) -> f64 {
        f64::from(self.paper) / f64::from(self.model)
    }

    /// The standard scales from the largest (10:1) down, `{1, 2, 2.5, 5} x 10^n` for
    /// reductions, to 1:10^9.
    pub fn standard() -> Vec<Scale> {
        let mut v = vec![Scale { paper: 10, model: 1 }, Scale { paper: 5, model: 1 }, Scale { paper: 2, model: 1 }];
        let mut decade: u32 = 1;
        while decade <= 100_000_000 {
            for m in [1, 2, 5] {
                v.push(Scale { paper: 1, model: m * decade });
            }
            if decade >= 10 {
                // 1:25, 1:250, ... go between 1:20 and 1:50 of the same decade.
                let n = v.len();
                v.insert(n - 1, Scale { paper: 1, model: 25 * decade / 10 });
            }
            decade *= 10;
        }
        v.push(Scale { paper: 1, model: 1_000_000_000 });
        v
    }
}

impl fmt::Display for Scale {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:{}", self.paper, self.model)
    }
}

/// The lines plan of `surface` (a starboard half hull, axes x forward, y to starboard, z up,
/// lengths in `units`), with `offsets`, when given, drawn in the body plan as markers coloured
/// by their distance to the surface ([`sequential`] from the smallest to the largest
/// distance, with a legend in millimetres).
///
/// Layers: `frame`, `title`, `grid`, `stations`, `waterlines`, `buttocks`, `outline`,
/// `offsets` and `legend` (with offsets), `combs` (with [`LinesPlanOptions::combs`]). Every
/// branch of every cut is one polyline; a view's grid line is labelled with its value (station
/// labels above the profile, waterline values beside the profile and the body plan, buttock
/// values beside the half-breadth plan); the centrelines carry `CL`, the baselines `BL`.
pub fn lines_plan(
    surface: &NurbsSurface,
    offsets: Option<&Offsets>,
    units: Units,
    options: &LinesPlanOptions,
) -> Drawing {
    let bx = surface_box(surface);
    let lines = Lines::new(bx, offsets, options);
    let combs_mm = if options.combs { options.comb_length_mm.max(0.0) } else { 0.0 };
    let errors = offsets.map(|o| offset_errors(surface, o));
    let needs = LayoutNeeds {
        units,
        comb: combs_mm,
        legend: errors.is_some(),
        label_chars: lines.label_chars(),
        station_chars: lines.station_chars(),
    };
    let layout = Layout::choose(bx, options.sheet, needs);
    let (w, h) = (layout.sheet.width_mm, layout.sheet.height_mm);
    let mut d = Drawing::new(w, h, options.title.clone());

    draw_frame(&mut d, (w, h));
    draw_grid(&mut d, &layout, bx, &lines);
    let cuts = cut_all(surface, &lines, &options.cut);
    draw_cuts(&mut d, &layout, bx, &cuts);
    draw_outline(&mut d, &layout, bx, surface);
    if let (Some(o), Some(e)) = (offsets, errors.as_ref()) {
        draw_offsets(&mut d, &layout, bx, o, e);
        draw_legend(&mut d, &layout, e, units);
    }
    if options.combs {
        draw_combs(&mut d, &layout, bx, surface, &cuts, combs_mm);
    }
    let source =
        options.source.clone().or_else(|| offsets.map(|o| o.source.clone())).unwrap_or_else(|| "surface".into());
    draw_title_block(&mut d, &layout, &options.title, &source, units, &lines);
    d
}

/// The station, waterline and buttock polylines of the lines plan in model coordinates, one
/// entry per cut branch, layers `stations`, `waterlines`, `buttocks` (for
/// [`super::write_dxf_3d_lines`]). Same stations, waterlines and buttocks as [`lines_plan`].
pub fn lines_3d(
    surface: &NurbsSurface,
    offsets: Option<&Offsets>,
    options: &LinesPlanOptions,
) -> Vec<(&'static str, Vec<Vec3>)> {
    let lines = Lines::new(surface_box(surface), offsets, options);
    let cuts = cut_all(surface, &lines, &options.cut);
    let mut out = Vec::new();
    for (layer, curves) in
        [("stations", &cuts.stations), ("waterlines", &cuts.waterlines), ("buttocks", &cuts.buttocks)]
    {
        for c in curves.iter().flatten() {
            out.push((layer, c.points.iter().map(|p| p.point).collect()));
        }
    }
    out
}

// ---------------------------------------------------------------------------------------------
// Styles

const GRID: Rgb = Rgb(150, 150, 150);
const STATION: Rgb = Rgb(0, 70, 160);
const WATERLINE: Rgb = Rgb(0, 120, 60);
const BUTTOCK: Rgb = Rgb(170, 40, 40);
const COMB: Rgb = Rgb(220, 110, 0);
const LABEL_MM: f64 = 1.8;
const MARKER_MM: f64 = 1.0;
/// Centreline dash-dot, mm.
const DASH_DOT: [f64; 4] = [6.0, 1.5, 0.5, 1.5];

/// Average advance of a character of a sans-serif face, in cap heights (0.6 em / 0.72).
const CHAR_WIDTH_PER_CAP: f64 = 0.85;

fn line(points: Vec<[f64; 2]>, color: Rgb, width: f64, layer: &str) -> Item {
    Item::Polyline { points, closed: false, stroke: Stroke::solid(color, width), layer: layer.into() }
}

fn text(at: [f64; 2], s: impl Into<String>, size: f64, anchor: Anchor, layer: &str) -> Item {
    Item::Text { at, text: s.into(), size_mm: size, anchor, color: Rgb::BLACK, layer: layer.into() }
}

/// A number for a label: at most 3 decimals, trailing zeros dropped.
fn label_num(x: f64) -> String {
    let mut s = format!("{x:.3}");
    if s.contains('.') {
        let n = s.trim_end_matches('0').trim_end_matches('.').len();
        s.truncate(n);
    }
    if s == "-0" {
        "0".into()
    } else {
        s
    }
}

// ---------------------------------------------------------------------------------------------
// Geometry of the surface

/// Axis-aligned box of the surface: its points on a 65 x 65 parameter grid (boundaries
/// included). Finer than any drawing needs: between grid lines a hull surface bulges by far
/// less than a line width at the scales that fit a sheet.
#[derive(Clone, Copy, Debug)]
struct Box3 {
    lo: Vec3,
    hi: Vec3,
}

impl Box3 {
    /// Middle of the x range: the midship that splits the body plan.
    fn x_mid(&self) -> f64 {
        0.5 * (self.lo.x + self.hi.x)
    }
    /// The body plan side of x: -1 (aft, drawn left) below midship, +1 (fore, right) from
    /// midship on. A station within 1e-9 of the length of midship (round-off of the box) is
    /// the midship station and drawn fore.
    fn side(&self, x: f64) -> f64 {
        if x < self.x_mid() - 1e-9 * (self.hi.x - self.lo.x) {
            -1.0
        } else {
            1.0
        }
    }
    /// The lowest z drawn: the baseline z = 0 or the bottom of the surface if lower.
    fn z0(&self) -> f64 {
        self.lo.z.min(0.0)
    }
    /// The largest half-breadth (|y|; the surface is one side).
    fn half_breadth(&self) -> f64 {
        self.hi.y.abs().max(self.lo.y.abs())
    }
}

fn surface_box(s: &NurbsSurface) -> Box3 {
    const N: usize = 64;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let mut lo = Vec3::new(f64::INFINITY, f64::INFINITY, f64::INFINITY);
    let mut hi = -lo;
    for i in 0..=N {
        for j in 0..=N {
            let p = s.point(u0 + (u1 - u0) * i as f64 / N as f64, v0 + (v1 - v0) * j as f64 / N as f64);
            if p.is_finite() {
                lo = Vec3::new(lo.x.min(p.x), lo.y.min(p.y), lo.z.min(p.z));
                hi = Vec3::new(hi.x.max(p.x), hi.y.max(p.y), hi.z.max(p.z));
            }
        }
    }
    if lo.x > hi.x {
        lo = Vec3::new(0.0, 0.0, 0.0);
        hi = lo;
    }
    Box3 { lo, hi }
}

/// The stations, waterlines and buttocks to draw, with their labels.
struct Lines {
    stations: Vec<(f64, String)>,
    waterlines: Vec<f64>,
    buttocks: Vec<f64>,
}

impl Lines {
    fn new(bx: Box3, offsets: Option<&Offsets>, o: &LinesPlanOptions) -> Self {
        let finite = |v: &Vec<f64>| v.iter().copied().filter(|x| x.is_finite()).collect::<Vec<f64>>();
        let stations = match &o.stations {
            Some(v) => finite(v).into_iter().enumerate().map(|(i, x)| (x, i.to_string())).collect(),
            None => offsets.and_then(section_stations).unwrap_or_else(|| {
                (0..=20).map(|i| (bx.lo.x + (bx.hi.x - bx.lo.x) * f64::from(i) / 20.0, i.to_string())).collect()
            }),
        };
        let waterlines = match &o.waterlines {
            Some(v) => finite(v),
            None => offsets.and_then(|o| table_waterlines(o, bx)).unwrap_or_else(|| round_inside(bx.lo.z, bx.hi.z, 9)),
        };
        let buttocks = match &o.buttocks {
            Some(v) => finite(v),
            None => round_inside(0.0, bx.half_breadth(), 4),
        };
        Lines { stations, waterlines, buttocks }
    }

    /// The widest station label, in characters.
    fn station_chars(&self) -> usize {
        self.stations.iter().map(|s| s.1.chars().count()).max().unwrap_or(0)
    }

    /// The widest label beside a view, in characters: a waterline or buttock value, `BL`,
    /// `CL`.
    fn label_chars(&self) -> usize {
        self.waterlines.iter().chain(&self.buttocks).map(|&v| label_num(v).chars().count()).fold(2, usize::max)
    }
}

/// Round values (`{1, 2, 5} x 10^k` steps, about `target` of them) strictly between `lo` and
/// `hi`, as a draughtsman spaces waterlines and buttocks.
fn round_inside(lo: f64, hi: f64, target: usize) -> Vec<f64> {
    let (ticks, step) = super::nice_ticks(lo, hi, target + 1);
    // Half a step clear of the ends: a line on the keel or the deck edge is no line.
    ticks.into_iter().filter(|&t| t > lo + 0.25 * step && t < hi - 0.25 * step).collect()
}

/// The offsets' own waterlines: the heights shared by at least half the sections (a table's
/// rows), strictly between the bottom and the top of the drawing's box; `None` when fewer
/// than 3 (offsets given as sections at their own heights).
fn table_waterlines(o: &Offsets, bx: Box3) -> Option<Vec<f64>> {
    let tol = 1e-9 * o.size();
    let mut levels: Vec<(f64, usize)> = Vec::new();
    for s in &o.sections {
        let mut seen: Vec<f64> = Vec::new();
        for p in &s.points {
            if seen.iter().any(|z| (z - p.z).abs() <= tol) {
                continue;
            }
            seen.push(p.z);
            match levels.iter_mut().find(|(z, _)| (z - p.z).abs() <= tol) {
                Some((_, n)) => *n += 1,
                None => levels.push((p.z, 1)),
            }
        }
    }
    let mut zs: Vec<f64> = levels
        .into_iter()
        .filter(|&(z, n)| 2 * n >= o.sections.len() && z > bx.lo.z + tol && z < bx.hi.z - tol)
        .map(|(z, _)| z)
        .collect();
    zs.sort_by(f64::total_cmp);
    (zs.len() >= 3).then_some(zs)
}

/// The sections' x and labels when every section lies in one x plane (within
/// [`PLANAR_REL`] of the model size), else `None`.
fn section_stations(o: &Offsets) -> Option<Vec<(f64, String)>> {
    let tol = PLANAR_REL * o.size();
    let mut out = Vec::new();
    for s in &o.sections {
        let x = s.mean_x()?;
        if !x.is_finite() || s.points.iter().any(|p| (p.x - x).abs() > tol) {
            return None;
        }
        out.push((x, s.label.clone()));
    }
    (!out.is_empty()).then_some(out)
}

/// The cut branches of every station, waterline and buttock, in the order of [`Lines`].
struct Cuts {
    stations: Vec<Vec<CutCurve>>,
    waterlines: Vec<Vec<CutCurve>>,
    buttocks: Vec<Vec<CutCurve>>,
}

fn cut_all(surface: &NurbsSurface, lines: &Lines, options: &CutOptions) -> Cuts {
    let mut planes: Vec<CutPlane> = lines.stations.iter().map(|s| CutPlane::Station(s.0)).collect();
    planes.extend(lines.waterlines.iter().map(|&z| CutPlane::Waterline(z)));
    planes.extend(lines.buttocks.iter().map(|&y| CutPlane::Buttock(y)));
    let mut all = cut_surface_many(surface, &planes, options).into_iter();
    let stations = all.by_ref().take(lines.stations.len()).collect();
    let waterlines = all.by_ref().take(lines.waterlines.len()).collect();
    let buttocks = all.collect();
    Cuts { stations, waterlines, buttocks }
}

/// Distance of every offset to the surface (closest-point projection), in section order.
fn offset_errors(surface: &NurbsSurface, o: &Offsets) -> Vec<f64> {
    let projector = SurfaceProjector::new(surface, ProjectionOptions::default());
    let points: Vec<Vec3> = o.sections.iter().flat_map(|s| s.points.iter().copied()).collect();
    points.par_iter().map(|&q| if q.is_finite() { projector.project(q).distance } else { f64::NAN }).collect()
}

// ---------------------------------------------------------------------------------------------
// Layout

/// Margins of the frame (ISO 5457: 20 mm on the binding edge, 10 mm elsewhere).
const MARGIN_LEFT: f64 = 20.0;
const MARGIN: f64 = 10.0;
/// Room above the profile for two rows of station labels (and above the body plan for `CL`).
const LABEL_H: f64 = 7.0;
/// Space between a view and its labels.
const LABEL_PAD: f64 = 1.5;
/// Room beside a view for its labels, at least: labels of up to 5 characters fit in it, so
/// the layout does not move with the unit of their numbers (`0.625` m, `625` mm).
const LABEL_W_MIN: f64 = 12.0;
/// Space between views.
const GAP: f64 = 10.0;
const TITLE_W: f64 = 150.0;
const TITLE_H: f64 = 32.0;
const LEGEND_W: f64 = 70.0;
const LEGEND_H: f64 = 16.0;
/// The legend's distance from the frame.
const LEGEND_PAD: f64 = 3.0;
/// With the sheet chosen automatically, the smallest sheet whose drawn share is at least this
/// share of the best sheet's is taken (a plot on A3x4 rather than on A0 for a few per cent).
const SMALLER_SHEET_SHARE: f64 = 0.9;

/// Where the body plan goes (and with it the title block and the legend).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
enum Arrangement {
    /// Body plan right of the profile; title block (legend above it) right of the
    /// half-breadth plan.
    Beside,
    /// Body plan right of the profile; title block below the half-breadth plan, legend left
    /// of it.
    BesideTitleBelow,
    /// Body plan below the half-breadth plan, title block (legend above it) right of it: long
    /// slender hulls, whose body plan is narrow.
    Below,
}

const ARRANGEMENTS: [Arrangement; 3] = [Arrangement::Beside, Arrangement::BesideTitleBelow, Arrangement::Below];

/// The sizes of the parts on paper at one scale, mm.
#[derive(Clone, Copy, Debug)]
struct Parts {
    /// Length, height (keel or baseline to top) and half-breadth of the hull.
    lp: f64,
    zp: f64,
    yp: f64,
    /// Comb teeth beyond the views.
    e: f64,
    /// Width of the widest waterline or buttock label beside a view.
    label_w: f64,
    /// Half the widest station label (the end stations' labels reach past the profile).
    station_half: f64,
    title_w: f64,
    legend: bool,
}

impl Parts {
    fn profile(&self) -> (f64, f64) {
        (
            self.label_w.max(self.station_half) + self.e + self.lp + self.e + self.station_half,
            LABEL_H + self.zp + 2.0 * self.e,
        )
    }
    fn plan(&self) -> (f64, f64) {
        (self.label_w + 2.0 * self.e + self.lp, self.yp + 2.0 * self.e)
    }
    /// The body plan with its waterline labels on the right.
    fn body(&self) -> (f64, f64) {
        (2.0 * self.e + 2.0 * self.yp + self.label_w, LABEL_H + self.zp + 2.0 * self.e)
    }
    /// The legend (if any) above the title block.
    fn stack(&self) -> (f64, f64) {
        let (lw, lh) = self.legend_size();
        (self.title_w.max(lw), TITLE_H + if self.legend { lh + 4.0 } else { 0.0 })
    }
    fn legend_size(&self) -> (f64, f64) {
        if self.legend {
            (LEGEND_W + LEGEND_PAD, LEGEND_H + LEGEND_PAD)
        } else {
            (0.0, 0.0)
        }
    }

    /// Width and height of everything in `arrangement`.
    fn extent(&self, arrangement: Arrangement) -> (f64, f64) {
        let ((pw, ph), (qw, qh), (bw, bh), (sw, sh)) = (self.profile(), self.plan(), self.body(), self.stack());
        match arrangement {
            Arrangement::Beside => ((pw + GAP + bw).max(qw + GAP + sw), ph + GAP + qh.max(sh)),
            Arrangement::BesideTitleBelow => {
                let (lw, lh) = self.legend_size();
                ((pw + GAP + bw).max(qw).max(self.title_w + GAP + lw), ph + GAP + qh + GAP + TITLE_H.max(lh))
            }
            Arrangement::Below => {
                (pw.max(self.label_w.max(self.station_half) + bw + GAP + sw), ph + GAP + qh + GAP + bh.max(sh))
            }
        }
    }

    /// The area drawn: the three views' boxes (profile `L x H`, plan `L x B/2`, body plan
    /// `B x H`), the title block and the legend, mm².
    fn drawn_area(&self) -> f64 {
        let legend = if self.legend { LEGEND_W * LEGEND_H } else { 0.0 };
        self.lp * self.zp + self.lp * self.yp + 2.0 * self.yp * self.zp + self.title_w * TITLE_H + legend
    }
}

/// Width and height inside the frame of `sheet`, mm.
fn inner(sheet: Sheet) -> (f64, f64) {
    (sheet.width_mm - MARGIN_LEFT - MARGIN, sheet.height_mm - 2.0 * MARGIN)
}

/// Where the views go: paper positions of the model origins of each view, the scale, and the
/// title block and legend rectangles `[x, y, w, h]`.
#[derive(Clone, Debug)]
struct Layout {
    sheet: Sheet,
    scale: Scale,
    /// Paper mm per model unit.
    k: f64,
    /// Paper point of `(x = lo.x, z = z0)` in the profile.
    profile: [f64; 2],
    /// Paper point of `(x = lo.x, y = 0)` in the half-breadth plan.
    plan: [f64; 2],
    /// Paper point of `(y = 0, z = z0)` in the body plan.
    body: [f64; 2],
    title: [f64; 4],
    legend: Option<[f64; 4]>,
    /// The drawn area ([`Parts::drawn_area`]) as a share of the frame's.
    drawn_share: f64,
}

/// What the layout needs to know of the drawing besides the hull's box.
#[derive(Clone, Copy, Debug)]
struct LayoutNeeds {
    units: Units,
    comb: f64,
    legend: bool,
    /// Widest waterline or buttock label and widest station label, in characters.
    label_chars: usize,
    station_chars: usize,
}

impl Layout {
    /// The layout on `sheet`, or on the sheet chosen from [`Sheet::standard`] when `None`:
    /// the smallest whose drawn share is at least [`SMALLER_SHEET_SHARE`] of the best one's.
    fn choose(bx: Box3, sheet: Option<Sheet>, needs: LayoutNeeds) -> Layout {
        match sheet {
            Some(s) => Layout::on_sheet(bx, s, needs).unwrap_or_else(|| Layout::fallback(bx, s, needs)),
            None => {
                let all: Vec<Layout> =
                    Sheet::standard().iter().filter_map(|&s| Layout::on_sheet(bx, s, needs)).collect();
                let best = all.iter().map(|l| l.drawn_share).fold(0.0, f64::max);
                all.into_iter()
                    .find(|l| l.drawn_share >= SMALLER_SHEET_SHARE * best)
                    .unwrap_or_else(|| Layout::fallback(bx, Sheet::A3, needs))
            }
        }
    }

    /// The best layout on `sheet`: for each arrangement the largest standard scale at which it
    /// fits the frame; of those, the one that draws the largest share of the frame.
    fn on_sheet(bx: Box3, sheet: Sheet, needs: LayoutNeeds) -> Option<Layout> {
        let (inner_w, inner_h) = inner(sheet);
        let mm_per_unit = needs.units.metres_per_unit() * 1000.0;
        let mut best: Option<Layout> = None;
        for arrangement in ARRANGEMENTS {
            for scale in Scale::standard() {
                let k = scale.ratio() * mm_per_unit;
                let parts = Layout::parts(bx, k, needs, inner_w);
                let (w, h) = parts.extent(arrangement);
                if w <= inner_w && h <= inner_h {
                    let l = Layout::place(sheet, scale, k, parts, arrangement, (inner_w - w, inner_h - h));
                    if best.as_ref().is_none_or(|b| l.drawn_share > b.drawn_share) {
                        best = Some(l);
                    }
                    break;
                }
            }
        }
        best
    }

    /// Nothing fits (a sheet smaller than the title block): the smallest scale, placed as well
    /// as it goes.
    fn fallback(bx: Box3, sheet: Sheet, needs: LayoutNeeds) -> Layout {
        let scale = *Scale::standard().last().expect("the list of scales is not empty");
        let k = scale.ratio() * needs.units.metres_per_unit() * 1000.0;
        let parts = Layout::parts(bx, k, needs, inner(sheet).0);
        Layout::place(sheet, scale, k, parts, Arrangement::BesideTitleBelow, (0.0, 0.0))
    }

    fn parts(bx: Box3, k: f64, needs: LayoutNeeds, inner_w: f64) -> Parts {
        let text_w = |chars: usize| chars as f64 * CHAR_WIDTH_PER_CAP * LABEL_MM;
        Parts {
            lp: (bx.hi.x - bx.lo.x) * k,
            zp: (bx.hi.z - bx.z0()) * k,
            yp: bx.half_breadth() * k,
            e: needs.comb,
            label_w: (text_w(needs.label_chars) + 2.0 * LABEL_PAD).max(LABEL_W_MIN),
            station_half: 0.5 * text_w(needs.station_chars),
            title_w: TITLE_W.min(inner_w),
            legend: needs.legend,
        }
    }

    /// Place the parts of `arrangement`, shifted right and down by half the slack so the
    /// drawing sits in the middle of the free space; the title block is in the frame's
    /// bottom-right corner.
    fn place(
        sheet: Sheet,
        scale: Scale,
        k: f64,
        p: Parts,
        arrangement: Arrangement,
        (slack_x, slack_y): (f64, f64),
    ) -> Layout {
        let (x0, y0, x1, y1) = (MARGIN_LEFT, MARGIN, sheet.width_mm - MARGIN, sheet.height_mm - MARGIN);
        let left = x0 + 0.5 * slack_x.max(0.0);
        let top = y1 - 0.5 * slack_y.max(0.0);
        // The profile's and the plan's x origin: after the labels on their left.
        let x_start = left + p.label_w.max(p.station_half) + p.e;
        let profile = [x_start, top - LABEL_H - p.e - p.zp];
        let plan = [x_start, profile[1] - p.e - GAP - p.e - p.yp];
        let body = match arrangement {
            Arrangement::Beside | Arrangement::BesideTitleBelow => {
                [left + p.profile().0 + GAP + p.e + p.yp, profile[1]]
            }
            // Below midship, unless that runs into the legend and title block: then as far
            // right as they leave room for.
            Arrangement::Below => {
                // The body plan reaches e + B/2 + its labels right of its centreline.
                let clear = x1 - p.stack().0 - GAP - (p.body().0 - p.e - p.yp);
                let mid = x_start + 0.5 * p.lp;
                [mid.min(clear).max(x_start + p.yp), plan[1] - p.e - GAP - LABEL_H - p.e - p.zp]
            }
        };
        let title = [x1 - p.title_w, y0, p.title_w, TITLE_H];
        let legend_at = match arrangement {
            Arrangement::BesideTitleBelow => [x1 - p.title_w - GAP - LEGEND_W, y0 + LEGEND_PAD, LEGEND_W, LEGEND_H],
            _ => [x1 - LEGEND_W - LEGEND_PAD, y0 + TITLE_H + 4.0, LEGEND_W, LEGEND_H],
        };
        let legend = p.legend.then_some(legend_at);
        let (iw, ih) = inner(sheet);
        Layout { sheet, scale, k, profile, plan, body, title, legend, drawn_share: p.drawn_area() / (iw * ih) }
    }

    fn profile_pt(&self, bx: Box3, x: f64, z: f64) -> [f64; 2] {
        [self.profile[0] + (x - bx.lo.x) * self.k, self.profile[1] + (z - bx.z0()) * self.k]
    }

    fn plan_pt(&self, bx: Box3, x: f64, y: f64) -> [f64; 2] {
        [self.plan[0] + (x - bx.lo.x) * self.k, self.plan[1] + y * self.k]
    }

    /// `side` -1 for the aft half (drawn left), +1 for the fore half.
    fn body_pt(&self, bx: Box3, y: f64, z: f64, side: f64) -> [f64; 2] {
        [self.body[0] + side * y * self.k, self.body[1] + (z - bx.z0()) * self.k]
    }
}

// ---------------------------------------------------------------------------------------------
// Drawing the parts

fn draw_frame(d: &mut Drawing, (w, h): (f64, f64)) {
    let (x0, y0, x1, y1) = (MARGIN_LEFT, MARGIN, w - MARGIN, h - MARGIN);
    d.push(Item::Polyline {
        points: vec![[x0, y0], [x1, y0], [x1, y1], [x0, y1]],
        closed: true,
        stroke: Stroke::solid(Rgb::BLACK, 0.5),
        layer: "frame".into(),
    });
}

/// Keep the labels that do not overlap the previous kept one (greedy, from the lowest
/// position up), `(paper position, text)` along x (`vertical` false: extent the estimated text
/// width) or along y (extent the cap height), with 0.8 cap height of clearance.
fn spaced(labels: Vec<(f64, String)>, size: f64, vertical: bool) -> Vec<(f64, String)> {
    let mut sorted = labels;
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    let mut edge = f64::NEG_INFINITY;
    for (x, s) in sorted {
        let half = if vertical { 0.5 * size } else { 0.5 * s.chars().count() as f64 * CHAR_WIDTH_PER_CAP * size };
        if x - half >= edge + 0.8 * size {
            edge = x + half;
            out.push((x, s));
        }
    }
    out
}

/// The station labels above the profile, `(row, x, text)`: one row when they all fit in one
/// without overlapping, else alternately in two rows (the second above the first), each row
/// dropping any label that would still overlap its neighbour ([`spaced`]).
fn station_rows(labels: Vec<(f64, String)>) -> Vec<(usize, f64, String)> {
    let one = spaced(labels.clone(), LABEL_MM, false);
    if one.len() == labels.len() {
        return one.into_iter().map(|(x, s)| (0, x, s)).collect();
    }
    let mut sorted = labels;
    sorted.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut out = Vec::new();
    for row in 0..2 {
        let mine = sorted.iter().skip(row).step_by(2).cloned().collect();
        out.extend(spaced(mine, LABEL_MM, false).into_iter().map(|(x, s)| (row, x, s)));
    }
    out
}

fn draw_grid(d: &mut Drawing, l: &Layout, bx: Box3, lines: &Lines) {
    let g = "grid";
    let (x0, x1, z0, z1, yb) = (bx.lo.x, bx.hi.x, bx.z0(), bx.hi.z, bx.half_breadth());
    let thin = 0.13;
    let centreline = |points: Vec<[f64; 2]>| Item::Polyline {
        points,
        closed: false,
        stroke: Stroke { color: Rgb::BLACK, width_mm: 0.18, dash: Some(DASH_DOT.to_vec()) },
        layer: g.into(),
    };
    // Profile: stations, waterlines, baseline.
    for &(x, _) in &lines.stations {
        d.push(line(vec![l.profile_pt(bx, x, z0), l.profile_pt(bx, x, z1)], GRID, thin, g));
        d.push(line(vec![l.plan_pt(bx, x, 0.0), l.plan_pt(bx, x, yb)], GRID, thin, g));
    }
    let labels: Vec<(f64, String)> =
        lines.stations.iter().map(|(x, s)| (l.profile_pt(bx, *x, z0)[0], s.clone())).collect();
    let label_y = l.profile_pt(bx, x0, z1)[1] + LABEL_PAD;
    for (row, px, s) in station_rows(labels) {
        let y = label_y + row as f64 * (LABEL_MM + 1.2);
        d.push(text([px, y], s, LABEL_MM, Anchor::Middle, g));
    }
    for &z in &lines.waterlines {
        d.push(line(vec![l.profile_pt(bx, x0, z), l.profile_pt(bx, x1, z)], GRID, thin, g));
        d.push(line(vec![l.body_pt(bx, yb, z, -1.0), l.body_pt(bx, yb, z, 1.0)], GRID, thin, g));
    }
    let base = [l.profile_pt(bx, x0, 0.0), l.profile_pt(bx, x1, 0.0)];
    d.push(line(base.to_vec(), Rgb::BLACK, 0.25, g));
    let (b0, b1) = (l.body_pt(bx, yb, 0.0, -1.0), l.body_pt(bx, yb, 0.0, 1.0));
    d.push(line(vec![b0, b1], Rgb::BLACK, 0.25, g));
    // Waterline values left of the profile and right of the body plan, the baseline's BL first.
    let mut labels = vec![(base[0][1], "BL".to_string())];
    labels.extend(lines.waterlines.iter().map(|&z| (l.profile_pt(bx, x0, z)[1], label_num(z))));
    // The body plan shares the profile's scale: its heights are the profile's shifted.
    let body_shift = l.body[1] - l.profile[1];
    for (py, s) in spaced(labels, LABEL_MM, true) {
        let y = py - 0.5 * LABEL_MM;
        d.push(text([base[0][0] - LABEL_PAD, y], s.clone(), LABEL_MM, Anchor::End, g));
        d.push(text([b1[0] + LABEL_PAD, y + body_shift], s, LABEL_MM, Anchor::Start, g));
    }
    // Half-breadth plan: buttocks (also in the body plan), centreline.
    for &y in &lines.buttocks {
        d.push(line(vec![l.plan_pt(bx, x0, y), l.plan_pt(bx, x1, y)], GRID, thin, g));
        for side in [-1.0, 1.0] {
            d.push(line(vec![l.body_pt(bx, y, z0, side), l.body_pt(bx, y, z1, side)], GRID, thin, g));
        }
    }
    let cl = [l.plan_pt(bx, x0, 0.0), l.plan_pt(bx, x1, 0.0)];
    d.push(centreline(cl.to_vec()));
    let mut labels = vec![(cl[0][1], "CL".to_string())];
    labels.extend(lines.buttocks.iter().map(|&y| (l.plan_pt(bx, x0, y)[1], label_num(y))));
    for (py, s) in spaced(labels, LABEL_MM, true) {
        d.push(text([cl[0][0] - LABEL_PAD, py - 0.5 * LABEL_MM], s, LABEL_MM, Anchor::End, g));
    }
    // Body plan: centreline, labelled CL at its top (anchored on it).
    let (top, bottom) = (l.body_pt(bx, 0.0, z1, 1.0), l.body_pt(bx, 0.0, z0, 1.0));
    d.push(centreline(vec![bottom, top]));
    d.push(text([top[0], top[1] + LABEL_PAD], "CL", LABEL_MM, Anchor::Middle, g));
}

/// A cut branch as paper points: its 2-D coordinates mapped into its view. A closed loop
/// drops its repeated last point (the polyline is marked closed instead).
fn cut_paper(l: &Layout, bx: Box3, c: &CutCurve) -> (Vec<[f64; 2]>, bool) {
    let closed = c.is_closed();
    let n = if closed { c.points.len() - 1 } else { c.points.len() };
    let pts = c.points[..n].iter().map(|p| view_pt(l, bx, c.plane, c.plane.coords(p.point))).collect();
    (pts, closed)
}

/// Paper point of the 2-D plane coordinates `q` of a cut of `plane` (the body plan side from
/// the plane's x).
fn view_pt(l: &Layout, bx: Box3, plane: AxisPlane, q: [f64; 2]) -> [f64; 2] {
    match CutPlane::from(plane) {
        CutPlane::Station(x) => l.body_pt(bx, q[0], q[1], bx.side(x)),
        CutPlane::Waterline(_) => l.plan_pt(bx, q[0], q[1]),
        CutPlane::Buttock(_) => l.profile_pt(bx, q[0], q[1]),
    }
}

fn draw_cuts(d: &mut Drawing, l: &Layout, bx: Box3, cuts: &Cuts) {
    for (layer, color, curves) in [
        ("stations", STATION, &cuts.stations),
        ("waterlines", WATERLINE, &cuts.waterlines),
        ("buttocks", BUTTOCK, &cuts.buttocks),
    ] {
        for c in curves.iter().flatten() {
            let (points, closed) = cut_paper(l, bx, c);
            if points.len() >= 2 {
                d.push(Item::Polyline { points, closed, stroke: Stroke::solid(color, 0.25), layer: layer.into() });
            }
        }
    }
}

/// The four boundary curves, sampled at 129 parameter values each: u = u0, u = u1, v = v0,
/// v = v1. A boundary collapsed to a point (a pointed end) is dropped.
fn boundaries(s: &NurbsSurface) -> Vec<Vec<Vec3>> {
    const N: usize = 128;
    let ((u0, u1), (v0, v1)) = (s.domain_u(), s.domain_v());
    let at = |a: f64, b: f64, t: usize| a + (b - a) * t as f64 / N as f64;
    let curves = [
        (0..=N).map(|t| s.point(u0, at(v0, v1, t))).collect::<Vec<_>>(),
        (0..=N).map(|t| s.point(u1, at(v0, v1, t))).collect(),
        (0..=N).map(|t| s.point(at(u0, u1, t), v0)).collect(),
        (0..=N).map(|t| s.point(at(u0, u1, t), v1)).collect(),
    ];
    curves
        .into_iter()
        .filter(|c| c.iter().all(|p| p.is_finite()) && c.windows(2).any(|w| w[0].distance(w[1]) > 0.0))
        .collect()
}

/// Split a 3-D polyline where it crosses `x = x_mid`, inserting the crossing point (linear
/// interpolation) in both pieces; each piece is tagged with its side (-1 aft, +1 fore).
fn split_at_midship(points: &[Vec3], x_mid: f64) -> Vec<(f64, Vec<Vec3>)> {
    let side = |p: &Vec3| if p.x < x_mid { -1.0 } else { 1.0 };
    let mut out: Vec<(f64, Vec<Vec3>)> = Vec::new();
    for (i, p) in points.iter().enumerate() {
        let s = side(p);
        match out.last_mut() {
            Some((cur, piece)) if *cur == s => piece.push(*p),
            Some((_, piece)) => {
                let a = points[i - 1];
                let t = if p.x != a.x { (x_mid - a.x) / (p.x - a.x) } else { 0.0 };
                let m = a + (*p - a) * t.clamp(0.0, 1.0);
                piece.push(m);
                out.push((s, vec![m, *p]));
            }
            None => out.push((s, vec![*p])),
        }
    }
    out.retain(|(_, p)| p.len() >= 2);
    out
}

fn draw_outline(d: &mut Drawing, l: &Layout, bx: Box3, s: &NurbsSurface) {
    let o = "outline";
    for b in boundaries(s) {
        d.push(line(b.iter().map(|p| l.profile_pt(bx, p.x, p.z)).collect(), Rgb::BLACK, 0.35, o));
        d.push(line(b.iter().map(|p| l.plan_pt(bx, p.x, p.y)).collect(), Rgb::BLACK, 0.35, o));
        for (side, piece) in split_at_midship(&b, bx.x_mid()) {
            d.push(line(piece.iter().map(|p| l.body_pt(bx, p.y, p.z, side)).collect(), Rgb::BLACK, 0.35, o));
        }
    }
}

/// The error range `(lo, hi)` of the finite errors, `(0, 0)` without any.
fn error_range(errors: &[f64]) -> (f64, f64) {
    let finite = errors.iter().copied().filter(|e| e.is_finite());
    let lo = finite.clone().fold(f64::INFINITY, f64::min);
    let hi = finite.fold(f64::NEG_INFINITY, f64::max);
    if lo <= hi {
        (lo, hi)
    } else {
        (0.0, 0.0)
    }
}

fn draw_offsets(d: &mut Drawing, l: &Layout, bx: Box3, o: &Offsets, errors: &[f64]) {
    let (lo, hi) = error_range(errors);
    let points = o.sections.iter().flat_map(|s| s.points.iter());
    for (p, &e) in points.zip(errors) {
        if !p.is_finite() {
            continue;
        }
        let side = bx.side(p.x);
        d.push(Item::Marker {
            at: l.body_pt(bx, p.y, p.z, side),
            size_mm: MARKER_MM,
            fill: sequential(e, lo, hi),
            layer: "offsets".into(),
        });
    }
}

/// The colour bar from the smallest to the largest offset error: the two ends labelled (the
/// largest to 4 significant digits, the smallest to one decimal more than the ticks, so a
/// round-off error of 1e-13 mm reads `0`), round ticks between them (about 4, `{1, 2, 5} x
/// 10^n` mm) marked on the bar and labelled where they leave room beside the end labels.
fn draw_legend(d: &mut Drawing, l: &Layout, errors: &[f64], units: Units) {
    let Some([x, y, w, _]) = l.legend else { return };
    let g = "legend";
    let (lo, hi) = error_range(errors);
    let mm = units.metres_per_unit() * 1000.0;
    let (lo_mm, hi_mm) = (lo * mm, hi * mm);
    const STEPS: usize = 32;
    let (bar_y, bar_h) = (y + 5.0, 4.0);
    for i in 0..STEPS {
        let (a, b) = (x + w * i as f64 / STEPS as f64, x + w * (i + 1) as f64 / STEPS as f64);
        let t = (i as f64 + 0.5) / STEPS as f64;
        d.push(Item::Polygon {
            points: vec![[a, bar_y], [b, bar_y], [b, bar_y + bar_h], [a, bar_y + bar_h]],
            fill: sequential(t, 0.0, 1.0),
            layer: g.into(),
        });
    }
    d.push(Item::Polyline {
        points: vec![[x, bar_y], [x + w, bar_y], [x + w, bar_y + bar_h], [x, bar_y + bar_h]],
        closed: true,
        stroke: Stroke::solid(Rgb::BLACK, 0.13),
        layer: g.into(),
    });
    d.push(text([x, bar_y + bar_h + 2.0], "Offset fit error (mm)", 2.2, Anchor::Start, g));
    let (ticks, step) = super::nice_ticks(lo_mm, hi_mm, 4);
    let low = super::format_tick(lo_mm, step / 10.0);
    let high = hull::format_short(hi_mm);
    let label_w = |s: &str| s.chars().count() as f64 * CHAR_WIDTH_PER_CAP * LABEL_MM;
    d.push(text([x, y + 1.0], low.clone(), LABEL_MM, Anchor::Start, g));
    if hi_mm > lo_mm {
        d.push(text([x + w, y + 1.0], high.clone(), LABEL_MM, Anchor::End, g));
        // Ticks clear of the end labels by a character.
        let (free_lo, free_hi) = (x + label_w(&low) + LABEL_MM, x + w - label_w(&high) - LABEL_MM);
        let mut edge = free_lo;
        for t in ticks {
            let px = x + w * (t - lo_mm) / (hi_mm - lo_mm);
            if px <= x || px >= x + w {
                continue;
            }
            d.push(line(vec![[px, bar_y], [px, bar_y + 0.35 * bar_h]], Rgb::BLACK, 0.13, g));
            let s = super::format_tick(t, step);
            let half = 0.5 * label_w(&s);
            if px - half >= edge && px + half <= free_hi {
                d.push(text([px, y + 1.0], s, LABEL_MM, Anchor::Middle, g));
                edge = px + half + LABEL_MM;
            }
        }
    }
}

/// Left normal (the unit tangent turned counter-clockwise) of a cut at each point, in the
/// plane's 2-D coordinates. The tangent is the exact one, `axis x N(u, v)` (perpendicular to
/// the plane normal and to the surface normal), oriented along the polyline; where the surface
/// normal is undefined or lies along the plane normal, the chord through the neighbours
/// (one-sided at the ends) stands in. Zero where the neighbours coincide too.
fn left_normals(surface: &NurbsSurface, c: &CutCurve, q: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let n = q.len();
    (0..n)
        .map(|i| {
            let (a, b) = (q[i.saturating_sub(1)], q[(i + 1).min(n - 1)]);
            let chord = [b[0] - a[0], b[1] - a[1]];
            let exact =
                surface.normal(c.points[i].uv.0, c.points[i].uv.1).map(|nn| c.plane.coords(c.plane.normal().cross(nn)));
            let t = match exact {
                Some(t) if t[0].hypot(t[1]) > 1e-6 => {
                    let sign = if t[0] * chord[0] + t[1] * chord[1] < 0.0 { -1.0 } else { 1.0 };
                    [sign * t[0], sign * t[1]]
                }
                _ => chord,
            };
            let len = t[0].hypot(t[1]);
            if len > 0.0 {
                [-t[1] / len, t[0] / len]
            } else {
                [0.0, 0.0]
            }
        })
        .collect()
}

/// Quantile of |curvature| over the sheet that gets a tooth of the comb length.
const COMB_PERCENTILE: f64 = 0.95;
/// Longest tooth, in comb lengths.
const COMB_CLIP: f64 = 1.5;

fn draw_combs(d: &mut Drawing, l: &Layout, bx: Box3, surface: &NurbsSurface, cuts: &Cuts, comb_mm: f64) {
    let all: Vec<&CutCurve> = cuts
        .stations
        .iter()
        .chain(&cuts.waterlines)
        .chain(&cuts.buttocks)
        .flatten()
        .filter(|c| c.points.len() >= 2)
        .collect();
    let mut kappas: Vec<f64> = all
        .iter()
        .flat_map(|c| c.points.iter())
        .map(|p: &CutPoint| p.curvature.abs())
        .filter(|k| k.is_finite())
        .collect();
    kappas.sort_by(f64::total_cmp);
    // The comb's scale: the 95th percentile of |kappa| (a few sharp points at the stem foot or
    // the keel would otherwise shrink every other tooth to nothing); teeth above it are
    // clipped at COMB_CLIP times the comb length, so those points still stand out.
    let reference = kappas.get(((kappas.len() as f64 - 1.0) * COMB_PERCENTILE).round() as usize).copied();
    let reference = match reference {
        Some(r) if r > 0.0 => r,
        _ => kappas.last().copied().unwrap_or(0.0),
    };
    if !(reference > 0.0) || !(comb_mm > 0.0) {
        return;
    }
    // g kappa_ref k = comb_mm: tooth lengths in model units are g |kappa|, at most
    // COMB_CLIP comb_mm / k.
    let g = comb_mm / (l.k * reference);
    let longest = COMB_CLIP * comb_mm / l.k;
    for c in all {
        let q = c.coords();
        let normals = left_normals(surface, c, &q);
        let mut envelope = Vec::with_capacity(q.len());
        let mut teeth = Vec::with_capacity(3 * q.len());
        for ((p, qi), nl) in c.points.iter().zip(&q).zip(&normals) {
            let kappa = if p.curvature.is_finite() { p.curvature } else { 0.0 };
            let len = (g * kappa).clamp(-longest, longest);
            let tip = [qi[0] - len * nl[0], qi[1] - len * nl[1]];
            let (a, b) = (view_pt(l, bx, c.plane, *qi), view_pt(l, bx, c.plane, tip));
            // Out along the tooth and back: one polyline draws all teeth.
            teeth.extend([a, b, a]);
            envelope.push(b);
        }
        d.push(line(teeth, COMB, 0.1, "combs"));
        d.push(line(envelope, COMB, 0.18, "combs"));
    }
}

/// Cut `s` to at most `width` mm of text of cap height `size`, ending in `...` when cut.
fn fit_text(s: &str, width: f64, size: f64) -> String {
    let max = (width / (CHAR_WIDTH_PER_CAP * size)).floor().max(4.0) as usize;
    if s.chars().count() <= max {
        s.to_string()
    } else {
        let head: String = s.chars().take(max - 3).collect();
        format!("{head}...")
    }
}

fn draw_title_block(d: &mut Drawing, l: &Layout, title: &str, source: &str, units: Units, lines: &Lines) {
    let [x, y, w, h] = l.title;
    let t = "title";
    let rule = |d: &mut Drawing, yy: f64| d.push(line(vec![[x, yy], [x + w, yy]], Rgb::BLACK, 0.25, t));
    d.push(Item::Polyline {
        points: vec![[x, y], [x + w, y], [x + w, y + h], [x, y + h]],
        closed: true,
        stroke: Stroke::solid(Rgb::BLACK, 0.5),
        layer: t.into(),
    });
    // Rows from the top: title 12 mm, source 7, units and scale 7, counts and maker 6.
    let (r1, r2, r3) = (y + h - 12.0, y + h - 19.0, y + h - 26.0);
    rule(d, r1);
    rule(d, r2);
    rule(d, r3);
    d.push(line(vec![[x + 0.5 * w, r3], [x + 0.5 * w, r2]], Rgb::BLACK, 0.25, t));
    let pad = 2.5;
    d.push(text([x + pad, r1 + 3.5], fit_text(title, w - 2.0 * pad, 5.0), 5.0, Anchor::Start, t));
    d.push(text(
        [x + pad, r2 + 2.25],
        fit_text(&format!("Source: {source}"), w - 2.0 * pad, 2.5),
        2.5,
        Anchor::Start,
        t,
    ));
    d.push(text([x + pad, r3 + 2.25], format!("Units: {}", units.plural_name()), 2.5, Anchor::Start, t));
    d.push(text([x + 0.5 * w + pad, r3 + 2.25], format!("Scale {}", l.scale), 2.5, Anchor::Start, t));
    d.push(text([x + w - pad, r3 + 2.25], format!("Sheet {}", l.sheet.name), 2.5, Anchor::End, t));
    let counts = format!(
        "Stations {}, waterlines {}, buttocks {}",
        lines.stations.len(),
        lines.waterlines.len(),
        lines.buttocks.len()
    );
    d.push(text([x + pad, y + 1.75], fit_text(&counts, 0.75 * w, 2.5), 2.5, Anchor::Start, t));
    d.push(text([x + w - pad, y + 1.75], "hullskin", 2.5, Anchor::End, t));
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::KnotVector;

    #[test]
    fn standard_scales_are_ordered_and_include_the_ship_scales() {
        let s = Scale::standard();
        for w in s.windows(2) {
            assert!(w[0].ratio() > w[1].ratio(), "{} before {}", w[0], w[1]);
        }
        let names: Vec<String> = s.iter().take(16).map(|s| s.to_string()).collect();
        assert_eq!(
            names,
            [
                "10:1", "5:1", "2:1", "1:1", "1:2", "1:5", "1:10", "1:20", "1:25", "1:50", "1:100", "1:200", "1:250",
                "1:500", "1:1000", "1:2000"
            ]
        );
    }

    #[test]
    fn label_numbers() {
        assert_eq!(label_num(3.25), "3.25");
        assert_eq!(label_num(2.0), "2");
        assert_eq!(label_num(-0.0001), "0");
    }

    #[test]
    fn split_at_midship_inserts_the_crossing() {
        let pts = [Vec3::new(0.0, 1.0, 0.0), Vec3::new(4.0, 3.0, 0.0), Vec3::new(6.0, 5.0, 0.0)];
        let pieces = split_at_midship(&pts, 2.0);
        assert_eq!(pieces.len(), 2);
        assert_eq!(pieces[0].0, -1.0);
        // The crossing x = 2 lies halfway along the first segment: y = 2.
        assert_eq!(pieces[0].1.last(), Some(&Vec3::new(2.0, 2.0, 0.0)));
        assert_eq!(pieces[1].1.first(), Some(&Vec3::new(2.0, 2.0, 0.0)));
        assert_eq!(pieces[1].1.len(), 3);
    }

    #[test]
    fn spaced_labels_do_not_overlap() {
        let labels: Vec<(f64, String)> =
            [(0.0, "10"), (1.0, "11"), (5.0, "12"), (5.5, "13"), (20.0, "14")].map(|(x, s)| (x, s.to_string())).into();
        let names = |v: Vec<(f64, String)>| v.into_iter().map(|k| k.1).collect::<Vec<_>>();
        // Two-character labels of cap 2 mm are 3.4 mm wide; 0.8 cap of clearance: 1.6 mm.
        assert_eq!(names(spaced(labels.clone(), 2.0, false)), ["10", "12", "14"]);
        // Stacked, each takes its cap height 2 mm plus the 1.6 mm clearance.
        assert_eq!(names(spaced(labels, 2.0, true)), ["10", "12", "14"]);
        let stacked: Vec<(f64, String)> = (0..6).map(|i| (1.9 * i as f64, i.to_string())).collect();
        assert_eq!(names(spaced(stacked, 2.0, true)), ["0", "2", "4"]);
    }

    /// The quarter circle of radius 2 swept along x as a rational quadratic: every station is
    /// that circle, so the comb teeth all have the same length, the comb length, and point
    /// away from the centre.
    #[test]
    fn combs_of_a_circle_have_equal_teeth_pointing_outward() {
        let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let s = std::f64::consts::FRAC_1_SQRT_2;
        let mut pts = Vec::new();
        let mut w = Vec::new();
        // Section in (y, z): from (0, 0) (keel) round to (2, 2), centre (0, 2).
        for (y, z, wi) in [(0.0, 0.0, 1.0), (2.0, 0.0, s), (2.0, 2.0, 1.0)] {
            for x in [0.0, 10.0] {
                pts.push(Vec3::new(x, y, z));
                w.push(wi);
            }
        }
        let surf = NurbsSurface::try_new(ku, kv, &pts, Some(&w)).expect("valid");
        let opts = LinesPlanOptions {
            stations: Some(vec![7.5]),
            waterlines: Some(vec![]),
            buttocks: Some(vec![]),
            combs: true,
            comb_length_mm: 5.0,
            ..LinesPlanOptions::default()
        };
        let d = lines_plan(&surf, None, Units::Metre, &opts);
        let teeth: Vec<&Item> = d.layer("combs").collect();
        assert_eq!(teeth.len(), 2, "teeth and envelope of the one station");
        let Item::Polyline { points, .. } = teeth[0] else { panic!("a polyline") };
        let station = d.layer("stations").next().expect("the station");
        let Item::Polyline { points: st, .. } = station else { panic!("a polyline") };
        // Paper centre of the circle: the station's points are at distance R k from it; the
        // centre is at (y, z) = (0, 2), i.e. above the keel point, which is the first point.
        let keel = st[0];
        let r = (st.last().expect("points")[1] - keel[1]) / 1.0; // the top is 2 m = R above the keel
        let centre = [keel[0], keel[1] + r];
        for tooth in points.chunks(3) {
            let (a, b) = (tooth[0], tooth[1]);
            // Curvature 1/R everywhere: every tooth is comb_length_mm long. The cut's
            // analytic curvature and the exact tangent are right to round-off; 1e-6 mm leaves
            // room for the cut points' distance from the plane (a hundredth of 1e-12 x size).
            let len = (b[0] - a[0]).hypot(b[1] - a[1]);
            assert!((len - 5.0).abs() < 1e-6, "tooth length {len}");
            // Radially away from the centre: the tip is R + 5 mm from it.
            let rb = (b[0] - centre[0]).hypot(b[1] - centre[1]);
            let ra = (a[0] - centre[0]).hypot(a[1] - centre[1]);
            assert!((rb - ra - 5.0).abs() < 1e-6, "tip {b:?} at {rb}, foot at {ra}");
        }
    }

    /// Default lines: a table's own waterlines (the sample's rows strictly between its keel
    /// and its top, 0.325 m .. 8.125 m of 9.75) and round buttocks (2, 4, 6 m: within a
    /// quarter step of the 8.13 m half-breadth is no buttock); offsets at their own heights
    /// (no shared rows) get round waterlines.
    #[test]
    fn default_lines_are_the_tables_waterlines_and_round_buttocks() {
        let o = hull::series60_sample();
        let fit = hull::fit_offsets(&o, &hull::FitConfig::default()).expect("fits");
        let bx = surface_box(&fit.surface);
        let lines = Lines::new(bx, Some(&o), &LinesPlanOptions::default());
        let mut rows: Vec<f64> =
            o.sections[12].points.iter().map(|p| p.z).filter(|&z| z > bx.lo.z + 1e-9 && z < bx.hi.z - 1e-9).collect();
        rows.dedup();
        assert_eq!(lines.waterlines, rows);
        assert!(lines.waterlines.len() >= 5, "{:?}", lines.waterlines);
        assert_eq!(lines.buttocks, vec![2.0, 4.0, 6.0]);
        // Without offsets: round heights, every one a multiple of its step.
        let round = Lines::new(bx, None, &LinesPlanOptions::default());
        let step = round.waterlines[1] - round.waterlines[0];
        assert!(round.waterlines.len() >= 5, "{:?}", round.waterlines);
        assert!(
            round.waterlines.iter().all(|z| (z / step - (z / step).round()).abs() < 1e-9),
            "{:?}",
            round.waterlines
        );
    }

    /// On the fitted sample hull the curvature ranges over orders of magnitude (the stem foot
    /// and the bilge): about 5 % of the teeth reach the comb length (those at or above the 95th
    /// percentile of |curvature|), none is longer than 1.5 comb lengths, and the median tooth
    /// is still visible (above a tenth of the comb length).
    #[test]
    fn comb_teeth_scale_by_the_95th_percentile_and_are_clipped() {
        let fit = hull::fit_offsets(&hull::series60_sample(), &hull::FitConfig::default()).expect("fits");
        // The lines at tenths of the depth and fifths of the half-breadth (the comb scaling is
        // what is tested, on a fixed set of lines).
        let (lo, hi) = fit.surface.control_bounds();
        let opts = LinesPlanOptions {
            combs: true,
            comb_length_mm: 8.0,
            waterlines: Some((1..=9).map(|i| lo.z + (hi.z - lo.z) * f64::from(i) / 10.0).collect()),
            buttocks: Some((1..=4).map(|i| hi.y * f64::from(i) / 5.0).collect()),
            ..LinesPlanOptions::default()
        };
        let d = lines_plan(&fit.surface, None, Units::Metre, &opts);
        let mut lens: Vec<f64> = d
            .layer("combs")
            .filter_map(|i| match i {
                Item::Polyline { points, stroke, .. } if stroke.width_mm < 0.15 => Some(points),
                _ => None,
            })
            .flat_map(|pts| pts.chunks(3).map(|t| (t[1][0] - t[0][0]).hypot(t[1][1] - t[0][1])).collect::<Vec<_>>())
            .collect();
        lens.sort_by(f64::total_cmp);
        let n = lens.len() as f64;
        assert!(n > 1000.0, "{n} teeth");
        let longest = *lens.last().expect("teeth");
        assert!(longest <= 12.0 + 1e-9, "longest tooth {longest} mm");
        // Teeth at or above the reference (8 mm, to round-off of the paper transform).
        let full = lens.iter().filter(|&&l| l >= 8.0 - 1e-6).count() as f64 / n;
        assert!((0.03..=0.08).contains(&full), "{full} of the teeth at full length");
        let median = lens[lens.len() / 2];
        assert!(median > 0.8, "median tooth {median} mm");
    }
}
