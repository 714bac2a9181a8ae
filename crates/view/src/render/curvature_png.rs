//! The curvature map of a hull surface as a PNG picture: the surface in orthographic profile
//! (x right, z up) and bottom view (x right, y down from the centre line at the top, as seen
//! from below), each point coloured by Gaussian or mean curvature on the diverging map
//! ([`diverging`]: blue negative, white zero, red positive), with a colour bar, scales and a
//! title.
//!
//! How it is drawn:
//! 1. The surface is sampled by [`hull::curvature_map`] (the one sampling of curvature;
//!    this module only paints it) on the grid [`GridLines::Spans`]: a line at every distinct
//!    knot and each knot span split in proportion to its length, about `samples` lines per
//!    direction. At each vertex: the point, and the curvature from the first and second
//!    fundamental forms (`K = (LN - M²)/(EG - F²)`, `H = (EN - 2FM + GL)/(2(EG - F²))`, The
//!    NURBS Book / do Carmo §3-3; `nurbs::SurfaceDerivatives::curvature`). Where the normal is
//!    undefined or `|S_u x S_v|` is round-off ([`Degeneracy::RoundOff`], as in
//!    [`hull::gaussian_curvature_range`]) the vertex has no value and is drawn grey.
//! 2. Colour limits are symmetric, `±L` with `L` the 98th percentile (nearest rank,
//!    [`abs_quantile`], by default) of `|value|` over the defined grid vertices, so that a few spikes at a stem or
//!    knuckle do not wash out the rest; values beyond are drawn in the end colours. `L` is at
//!    least `(1e-3 / D)^p` (`D` the diagonal of the sampled points' box, `p` = 2 for K, 1 for H),
//!    so that a developable surface, whose curvature is round-off, reads white and not as noise
//!    stretched to full colour.
//! 3. Each grid cell is split into two triangles, projected orthographically and filled pixel by
//!    pixel with a depth buffer (the outer side wins: largest y in profile, lowest z from below),
//!    the value interpolated linearly between the vertices (Gouraud) and mapped to colour per
//!    pixel (a triangle with an undefined vertex interpolates colours, grey for the undefined),
//!    optionally shaded by `0.6 + 0.4 |n . d|` (`d` the viewing direction).
//!
//! Mean and principal curvatures are signed with the normal turned toward the inside of the
//! hull ([`hull::CurvatureMap::outward_flip`]: the side of the centre-plane axis
//! `y = y_min`, `z` = mid-depth), so `H > 0` where the hull is convex (bilge) and `H < 0`
//! where it is hollow.

use nurbs::{NurbsSurface, Vec3};
use tiny_skia::Pixmap;

use crate::drawing::{Anchor, Item, Rgb, Stroke};
use crate::ViewError;
use hull::{abs_quantile, diverging, point_bounds, CurvatureField, Degeneracy, GridLines};

use super::raster::{canvas, draw_items, pixels_per_metre, text_width_mm, Image, Mapping};
use crate::drawing::{format_tick, nice_ticks};
use hull::format_sig;

/// Colour of points where the curvature is undefined.
const UNDEFINED: Rgb = Rgb(150, 150, 150);
/// Colour of the surface's boundary curves drawn over the views.
const OUTLINE: Rgb = Rgb(60, 60, 60);
/// Most grid lines per direction asked for (2000 x 2000 vertices are 4 million curvature
/// evaluations, several seconds; a finer grid than the pixels adds nothing).
const MAX_SAMPLES: usize = 2000;
/// Least image width in pixels: the three views, the colour bar and their labels need it.
const MIN_WIDTH_PX: u32 = 320;
/// Paper resolution used to size the annotations (pixels per millimetre at 150 dpi).
const PX_PER_MM: f64 = 150.0 / 25.4;

/// Settings of a curvature picture ([`curvature_image`]): how [`hull::curvature_map`]'s
/// sampling is painted.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvatureImageOptions {
    /// Image width in pixels (at least 320); the height follows from the hull's proportions.
    pub width_px: u32,
    /// Percentile of `|value|` taken as the colour limit, in `(0, 100]`.
    pub percentile: f64,
    /// A fixed colour limit `L` (colours span `±L`) instead of the percentile, e.g. to compare
    /// two hulls on one scale.
    pub limit: Option<f64>,
    /// Length units of the surface, for the legend (`m`); empty for `unit`.
    pub units: String,
    /// Shown before the field's name in the title (e.g. the input file); may be empty.
    pub title: String,
    /// Shade by the angle between normal and viewing direction (reveals the form, but the
    /// colours then no longer match the colour bar exactly).
    pub shading: bool,
    /// About how many grid lines per parameter direction, 2 to 2000 (at least 2 per knot span).
    pub samples: usize,
}

impl Default for CurvatureImageOptions {
    /// 1600 px wide, 98th percentile, unshaded, about 160 x 160 samples.
    fn default() -> Self {
        CurvatureImageOptions {
            width_px: 1600,
            percentile: 98.0,
            limit: None,
            units: String::new(),
            title: String::new(),
            shading: false,
            samples: 160,
        }
    }
}

/// The direction of one of the picture's two orthographic views (hull's `View` is something
/// else: which view of a lines plan an offsets line belongs to).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ViewDirection {
    /// x right, z up; the outer (largest y) side visible.
    Profile,
    /// x right, y down from the centre line; seen from below (lowest z visible).
    Bottom,
}

impl ViewDirection {
    fn label(self) -> &'static str {
        match self {
            ViewDirection::Profile => "Profile (x, z), side view",
            ViewDirection::Bottom => "Bottom (x, y), seen from below, centre line at the top",
        }
    }

    /// `(horizontal, vertical, depth)` coordinates of a point in this view; larger depth is
    /// nearer the viewer.
    fn coords(self, p: Vec3) -> (f64, f64, f64) {
        match self {
            ViewDirection::Profile => (p.x, p.z, p.y),
            ViewDirection::Bottom => (p.x, p.y, -p.z),
        }
    }

    /// The viewing direction's axis, for shading.
    fn axis(self) -> Vec3 {
        match self {
            ViewDirection::Profile => Vec3::new(0.0, 1.0, 0.0),
            ViewDirection::Bottom => Vec3::new(0.0, 0.0, 1.0),
        }
    }
}

/// Where a view sits in the image: the model box `[h_min, h_max] x [v_min, v_max]` (horizontal
/// and vertical model coordinates of the view: x and z, or x and y) maps onto the pixel
/// rectangle `rect_px = [left, top, right, bottom]` at `scale` pixels per model unit.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ViewFrame {
    pub view: ViewDirection,
    pub rect_px: [f64; 4],
    pub h_range: (f64, f64),
    pub v_range: (f64, f64),
    pub scale: f64,
}

impl ViewFrame {
    /// Pixel position (column, row; continuous) of a model point in this view.
    pub fn project(&self, p: Vec3) -> [f64; 2] {
        let (h, v, _) = self.view.coords(p);
        let col = self.rect_px[0] + (h - self.h_range.0) * self.scale;
        let row = match self.view {
            ViewDirection::Profile => self.rect_px[1] + (self.v_range.1 - v) * self.scale,
            ViewDirection::Bottom => self.rect_px[1] + (v - self.v_range.0) * self.scale,
        };
        [col, row]
    }
}

/// A curvature picture: [`hull::curvature_map`]'s sampling painted as an image, and what it
/// shows.
#[derive(Clone, Debug, PartialEq)]
pub struct CurvatureImage {
    pub image: Image,
    pub field: CurvatureField,
    /// The colour limit `L`: colours span `[-L, L]`.
    pub limit: f64,
    /// Smallest and largest value over the defined grid vertices (`None` if there is none).
    pub range: Option<(f64, f64)>,
    /// Grid size (u lines, v lines).
    pub grid: (usize, usize),
    /// Vertices where the curvature is undefined (drawn grey).
    pub undefined: usize,
    /// Defined vertices with `|value| > L` (drawn in the end colours).
    pub clipped: usize,
    /// Pixels per model unit, the same in both views and both directions.
    pub scale: f64,
    /// Profile, then bottom view.
    pub views: [ViewFrame; 2],
}

/// One grid vertex: point, value (None where undefined) and unit normal.
#[derive(Clone, Copy)]
struct Sample {
    p: Vec3,
    value: Option<f64>,
    normal: Option<Vec3>,
}

/// Paint the curvature map of `surface` (sampled by [`hull::curvature_map`]) as a picture.
///
/// # Errors
/// [`ViewError::CurvatureImageWidth`], [`ViewError::Percentile`], [`ViewError::ColourLimit`] or
/// [`ViewError::Samples`] for unusable options (width under 320 px, percentile outside
/// `(0, 100]`, a limit that is not finite and positive, samples outside 2..=2000),
/// [`ViewError::NoLength`] for a surface without extent along x, or
/// [`ViewError::TooManyPixels`] for an image above [`super::MAX_PIXELS`].
pub fn curvature_image(
    surface: &NurbsSurface,
    field: CurvatureField,
    options: &CurvatureImageOptions,
) -> Result<CurvatureImage, ViewError> {
    check_options(options)?;
    let (samples, nu, nv) = evaluate(surface, field, options.samples);

    let (lo, hi) = bounds(&samples);
    let diag = (hi - lo).norm();
    if !(hi.x - lo.x > 1e-9 * diag.max(f64::MIN_POSITIVE)) {
        return Err(ViewError::NoLength { lo: lo.x, hi: hi.x });
    }
    let values: Vec<f64> = samples.iter().filter_map(|s| s.value).collect();
    let floor = (1e-3 / diag).powi(field.power());
    let limit = match options.limit {
        Some(l) => l,
        None => abs_quantile(&values, options.percentile / 100.0).map_or(floor, |p| p.max(floor)),
    };
    let defined = samples.iter().filter_map(|s| s.value);
    let range =
        defined.clone().fold(None, |r: Option<(f64, f64)>, v| Some(r.map_or((v, v), |(a, b)| (a.min(v), b.max(v)))));
    let clipped = defined.filter(|v| v.abs() > limit).count();
    let undefined = samples.iter().filter(|s| s.value.is_none()).count();

    let layout = Layout::new(options.width_px, lo, hi);
    let mut pixmap = canvas(options.width_px, layout.height, Rgb::WHITE)?;
    for frame in &layout.views {
        paint_view(&mut pixmap, frame, &samples, nu, nv, limit, options.shading);
    }
    paint_colour_bar(&mut pixmap, layout.bar, limit);
    let mapping = Mapping { k: PX_PER_MM, height_mm: layout.height as f64 / PX_PER_MM };
    let info = Info { field, limit, range, undefined, n: nu * nv, options, clipped };
    let items = annotations(&layout, &info, &samples, nu, nv);
    draw_items(&mut pixmap, &items, mapping);
    Ok(CurvatureImage {
        image: Image::from_pixmap(pixmap, pixels_per_metre(PX_PER_MM)),
        field,
        limit,
        range,
        grid: (nu, nv),
        undefined,
        clipped,
        scale: layout.scale,
        views: layout.views,
    })
}

/// [`curvature_image`] encoded as PNG.
///
/// # Errors
/// As [`curvature_image`].
pub fn curvature_map_png(
    surface: &NurbsSurface,
    field: CurvatureField,
    options: &CurvatureImageOptions,
) -> Result<Vec<u8>, ViewError> {
    curvature_image(surface, field, options)?.image.to_png()
}

fn check_options(o: &CurvatureImageOptions) -> Result<(), ViewError> {
    if o.width_px < MIN_WIDTH_PX {
        return Err(ViewError::CurvatureImageWidth { width_px: o.width_px, min: MIN_WIDTH_PX });
    }
    if !(o.percentile > 0.0 && o.percentile <= 100.0) {
        return Err(ViewError::Percentile { percentile: o.percentile });
    }
    if let Some(l) = o.limit {
        if !(l.is_finite() && l > 0.0) {
            return Err(ViewError::ColourLimit { limit: l });
        }
    }
    if !(2..=MAX_SAMPLES).contains(&o.samples) {
        return Err(ViewError::Samples { samples: o.samples, max: MAX_SAMPLES });
    }
    Ok(())
}

/// Points, values of `field` and normals on the grid of [`hull::curvature_map`]
/// (u-major), with the grid's size. Mean and principal curvatures are turned to the inward
/// normal (see the module doc).
fn evaluate(surface: &NurbsSurface, field: CurvatureField, lines: usize) -> (Vec<Sample>, usize, usize) {
    let options = hull::CurvatureMapOptions {
        grid: (lines, lines),
        lines: GridLines::Spans,
        degeneracy: Degeneracy::RoundOff,
        ..hull::CurvatureMapOptions::default()
    };
    let map = hull::curvature_map(surface, &options);
    let flip = field != CurvatureField::Gaussian && map.outward_flip();
    let samples = map
        .points
        .iter()
        .zip(&map.samples)
        .map(|(&p, s)| Sample { p, value: s.map(|s| s.oriented(flip).get(field)), normal: s.map(|s| s.normal) })
        .collect();
    (samples, map.us.len(), map.vs.len())
}

fn bounds(samples: &[Sample]) -> (Vec3, Vec3) {
    let points: Vec<Vec3> = samples.iter().map(|s| s.p).collect();
    point_bounds(&points)
}

/// Pixel layout of the picture (all in pixels, rows down).
struct Layout {
    width: u32,
    height: u32,
    scale: f64,
    views: [ViewFrame; 2],
    /// Colour bar `[left, top, right, bottom]`, integer pixel edges.
    bar: [f64; 4],
    /// Capital heights of the title and of the labels.
    title_px: f64,
    label_px: f64,
    margin: f64,
}

impl Layout {
    fn new(width: u32, lo: Vec3, hi: Vec3) -> Layout {
        let w = width as f64;
        let margin = (w / 40.0).max(12.0).round();
        let title_px = (w / 55.0).max(9.0);
        let label_px = (w / 85.0).max(7.0);
        let axis = 5.0 * label_px; // room for the vertical scale's labels
        let avail = w - 2.0 * margin - axis;
        let (lx, lz, ly) = (hi.x - lo.x, hi.z - lo.z, hi.y - lo.y);
        // Equal scales everywhere; views no taller than 1.6 times the width in all.
        let scale = (avail / lx).min(1.6 * w / (lz + ly).max(f64::MIN_POSITIVE));
        let left = (margin + axis + 0.5 * (avail - lx * scale)).round();
        let mut y = margin + title_px * 1.3 + label_px * 3.2; // title, subtitle
        let mut frames = Vec::with_capacity(2);
        for (view, vlo, vhi) in [(ViewDirection::Profile, lo.z, hi.z), (ViewDirection::Bottom, lo.y, hi.y)] {
            y += label_px * 2.6; // the view's label
            let top = y.round();
            let rect = [left, top, left + lx * scale, top + (vhi - vlo) * scale];
            frames.push(ViewFrame { view, rect_px: rect, h_range: (lo.x, hi.x), v_range: (vlo, vhi), scale });
            y = rect[3] + label_px * 1.5;
        }
        y += label_px * 3.5; // x scale under the bottom view
        let bar_w = (0.45 * w).round();
        let bar_left = (0.5 * (w - bar_w)).round();
        let bar_top = (y + label_px * 2.5).round();
        let bar = [bar_left, bar_top, bar_left + bar_w, bar_top + (1.8 * label_px).round()];
        y = bar[3] + label_px * 3.2 + label_px * 2.4 + margin; // tick labels, notes line
        let views = [frames[0], frames[1]];
        Layout { width, height: y.ceil() as u32, scale, views, bar, title_px, label_px, margin }
    }
}

/// Vertex of a projected triangle.
#[derive(Clone, Copy)]
struct Vert {
    x: f64,
    y: f64,
    depth: f64,
    value: Option<f64>,
    shade: f64,
}

/// Fill the view's triangles with a depth buffer.
fn paint_view(
    pixmap: &mut Pixmap,
    frame: &ViewFrame,
    samples: &[Sample],
    nu: usize,
    nv: usize,
    limit: f64,
    shading: bool,
) {
    let verts: Vec<Vert> = samples
        .iter()
        .map(|s| {
            let [x, y] = frame.project(s.p);
            let (_, _, depth) = frame.view.coords(s.p);
            let shade = match (shading, s.normal) {
                (true, Some(n)) => 0.6 + 0.4 * n.dot(frame.view.axis()).abs(),
                _ => 1.0,
            };
            Vert { x, y, depth, value: s.value, shade }
        })
        .collect();
    // The depth buffer covers the view's pixel rectangle plus one pixel around.
    let (w, h) = (pixmap.width() as i64, pixmap.height() as i64);
    let x0 = (frame.rect_px[0].floor() as i64 - 1).clamp(0, w);
    let y0 = (frame.rect_px[1].floor() as i64 - 1).clamp(0, h);
    let x1 = (frame.rect_px[2].ceil() as i64 + 1).clamp(0, w);
    let y1 = (frame.rect_px[3].ceil() as i64 + 1).clamp(0, h);
    let mut target = Target {
        data: pixmap.data_mut(),
        stride: w as usize,
        clip: [x0, y0, x1, y1],
        depth: vec![f64::NEG_INFINITY; ((x1 - x0) * (y1 - y0)).max(0) as usize],
        limit,
    };
    for i in 0..nu.saturating_sub(1) {
        for j in 0..nv.saturating_sub(1) {
            let a = verts[i * nv + j];
            let b = verts[(i + 1) * nv + j];
            let c = verts[(i + 1) * nv + j + 1];
            let d = verts[i * nv + j + 1];
            target.triangle(a, b, c);
            target.triangle(a, c, d);
        }
    }
}

/// Pixels and depth buffer of one view.
struct Target<'a> {
    data: &'a mut [u8],
    stride: usize,
    clip: [i64; 4],
    depth: Vec<f64>,
    limit: f64,
}

fn colour_of(value: Option<f64>, limit: f64) -> [f64; 3] {
    let c = value.map_or(UNDEFINED, |v| diverging(v, limit));
    [c.0 as f64, c.1 as f64, c.2 as f64]
}

impl Target<'_> {
    /// Fill triangle `abc`: pixels whose centre lies inside (edge functions `>= 0` after
    /// orienting the triangle counter-clockwise in pixel space), nearer than what is there.
    fn triangle(&mut self, a: Vert, b: Vert, c: Vert) {
        let edge = |p: &Vert, q: &Vert, x: f64, y: f64| (q.x - p.x) * (y - p.y) - (q.y - p.y) * (x - p.x);
        let area = edge(&a, &b, c.x, c.y);
        if !(area.abs() > 1e-12) {
            return; // edge-on or degenerate (also NaN)
        }
        let (b, c, area) = if area > 0.0 { (b, c, area) } else { (c, b, -area) };
        let [cx0, cy0, cx1, cy1] = self.clip;
        let xmin = (a.x.min(b.x).min(c.x) - 0.5).ceil().max(cx0 as f64) as i64;
        let xmax = (a.x.max(b.x).max(c.x) - 0.5).floor().min((cx1 - 1) as f64) as i64;
        let ymin = (a.y.min(b.y).min(c.y) - 0.5).ceil().max(cy0 as f64) as i64;
        let ymax = (a.y.max(b.y).max(c.y) - 0.5).floor().min((cy1 - 1) as f64) as i64;
        let all_defined = a.value.is_some() && b.value.is_some() && c.value.is_some();
        let colours = [colour_of(a.value, self.limit), colour_of(b.value, self.limit), colour_of(c.value, self.limit)];
        for py in ymin..=ymax {
            let y = py as f64 + 0.5;
            for px in xmin..=xmax {
                let x = px as f64 + 0.5;
                let (wa, wb, wc) = (edge(&b, &c, x, y), edge(&c, &a, x, y), edge(&a, &b, x, y));
                if wa < 0.0 || wb < 0.0 || wc < 0.0 {
                    continue;
                }
                let (la, lb, lc) = (wa / area, wb / area, wc / area);
                let depth = la * a.depth + lb * b.depth + lc * c.depth;
                let di = ((py - cy0) * (cx1 - cx0) + (px - cx0)) as usize;
                if !(depth > self.depth[di]) {
                    continue;
                }
                self.depth[di] = depth;
                let shade = la * a.shade + lb * b.shade + lc * c.shade;
                let rgb = match (all_defined, a.value, b.value, c.value) {
                    (true, Some(va), Some(vb), Some(vc)) => colour_of(Some(la * va + lb * vb + lc * vc), self.limit),
                    _ => {
                        let mix = |k: usize| la * colours[0][k] + lb * colours[1][k] + lc * colours[2][k];
                        [mix(0), mix(1), mix(2)]
                    }
                };
                let i = 4 * (py as usize * self.stride + px as usize);
                for k in 0..3 {
                    self.data[i + k] = (rgb[k] * shade).round().clamp(0.0, 255.0) as u8;
                }
                self.data[i + 3] = 255;
            }
        }
    }
}

/// Fill the colour bar: column `i` shows the value at its centre, `L (2 t - 1)`.
fn paint_colour_bar(pixmap: &mut Pixmap, bar: [f64; 4], limit: f64) {
    let stride = pixmap.width() as usize;
    let (x0, y0, x1, y1) = (bar[0] as usize, bar[1] as usize, bar[2] as usize, bar[3] as usize);
    let data = pixmap.data_mut();
    for x in x0..x1 {
        let t = (x - x0) as f64 + 0.5;
        let c = diverging(limit * (2.0 * t / (x1 - x0) as f64 - 1.0), limit);
        for y in y0..y1 {
            let i = 4 * (y * stride + x);
            if i + 3 < data.len() {
                data[i..i + 4].copy_from_slice(&[c.0, c.1, c.2, 255]);
            }
        }
    }
}

/// What the annotations report.
struct Info<'a> {
    field: CurvatureField,
    limit: f64,
    range: Option<(f64, f64)>,
    undefined: usize,
    n: usize,
    options: &'a CurvatureImageOptions,
    clipped: usize,
}

/// Title, view labels, scales, boundary outlines and colour bar legend, in paper mm.
fn annotations(layout: &Layout, info: &Info, samples: &[Sample], nu: usize, nv: usize) -> Vec<Item> {
    let h_mm = layout.height as f64 / PX_PER_MM;
    let mm = |x: f64, y: f64| [x / PX_PER_MM, h_mm - y / PX_PER_MM];
    let (title_mm, label_mm) = (layout.title_px / PX_PER_MM, layout.label_px / PX_PER_MM);
    let o = info.options;
    let mut items = Vec::new();
    let text = |at: [f64; 2], s: String, size: f64, anchor: Anchor, layer: &str| Item::Text {
        at,
        text: s,
        size_mm: size,
        anchor,
        color: Rgb::BLACK,
        layer: layer.into(),
    };
    let line = |pts: Vec<[f64; 2]>, color: Rgb, width_px: f64, layer: &str| Item::Polyline {
        points: pts,
        closed: false,
        stroke: Stroke::solid(color, width_px / PX_PER_MM),
        layer: layer.into(),
    };
    let units = info.field.units(&o.units);
    let length_units = if o.units.is_empty() { "unit".to_string() } else { o.units.clone() };

    // Title and subtitle.
    let name = info.field.name();
    let mut title = format!("{}{} {}", name[..1].to_uppercase(), &name[1..], info.field.symbol());
    if !o.title.is_empty() {
        title = format!("{}: {title}", o.title);
    }
    let m = layout.margin;
    items.push(text(mm(m, m + layout.title_px), title, title_mm, Anchor::Start, "title"));
    let how = match o.limit {
        Some(_) => "fixed limit".to_string(),
        None => format!("{} percentile of |{}| over the grid", ordinal(o.percentile), info.field.symbol()),
    };
    let subtitle = format!(
        "colours ±{} {units} ({how}); orthographic views, {} px per {length_units}",
        format_sig(info.limit, 3),
        format_sig(layout.scale, 3)
    );
    items.push(text(
        mm(m, m + layout.title_px * 1.3 + layout.label_px * 2.0),
        subtitle,
        label_mm,
        Anchor::Start,
        "title",
    ));

    for frame in &layout.views {
        let [l, t, _, _] = frame.rect_px;
        items.push(text(mm(l, t - layout.label_px * 0.9), frame.view.label().into(), label_mm, Anchor::Start, "views"));
        // Vertical scale at the left.
        let (ticks, step) = spaced_ticks(frame.v_range, frame.scale, 2.5 * layout.label_px, 4);
        for v in ticks {
            let row = match frame.view {
                ViewDirection::Profile => t + (frame.v_range.1 - v) * frame.scale,
                ViewDirection::Bottom => t + (v - frame.v_range.0) * frame.scale,
            };
            items.push(line(vec![mm(l - 10.0, row), mm(l - 4.0, row)], Rgb::BLACK, 1.0, "scales"));
            let label = format_tick(v, step);
            items.push(text(mm(l - 13.0, row + 0.5 * layout.label_px), label, label_mm, Anchor::End, "scales"));
        }
        // Boundary curves of the surface.
        let rows = (0..nu).map(|i| (0..nv).map(move |j| i * nv + j).collect::<Vec<_>>());
        let edges: Vec<Vec<usize>> = vec![
            (0..nv).collect(),
            ((nu - 1) * nv..nu * nv).collect(),
            rows.clone().map(|r| r[0]).collect(),
            rows.map(|r| r[nv - 1]).collect(),
        ];
        for edge in edges {
            let pts = edge.iter().map(|&k| frame.project(samples[k].p)).map(|[x, y]| mm(x, y)).collect();
            items.push(line(pts, OUTLINE, 1.2, "outline"));
        }
    }
    // x scale under the bottom view.
    let bottom = layout.views[1];
    let (ticks, step) = spaced_ticks(bottom.h_range, bottom.scale, 6.0 * layout.label_px, 10);
    let y = bottom.rect_px[3] + layout.label_px * 0.8;
    for x in ticks {
        let col = bottom.rect_px[0] + (x - bottom.h_range.0) * bottom.scale;
        items.push(line(vec![mm(col, y), mm(col, y + 6.0)], Rgb::BLACK, 1.0, "scales"));
        items.push(text(mm(col, y + 8.0 + layout.label_px), format_tick(x, step), label_mm, Anchor::Middle, "scales"));
    }
    items.push(text(
        mm(bottom.rect_px[2], y + 8.0 + layout.label_px * 2.6),
        format!("x ({length_units})"),
        label_mm,
        Anchor::End,
        "scales",
    ));

    // Colour bar: frame, ticks at -L, -L/2, 0, L/2, L, caption, the grey swatch.
    let [bl, bt, br, bb] = layout.bar;
    let frame = vec![mm(bl, bt), mm(br, bt), mm(br, bb), mm(bl, bb), mm(bl, bt)];
    items.push(line(frame, Rgb::BLACK, 1.0, "legend"));
    for k in -2..=2 {
        let v = info.limit * k as f64 / 2.0;
        let col = bl + (br - bl) * (k as f64 + 2.0) / 4.0;
        items.push(line(vec![mm(col, bb), mm(col, bb + 6.0)], Rgb::BLACK, 1.0, "legend"));
        let label = if k == 0 { "0".to_string() } else { format_sig(v, 3) };
        items.push(text(mm(col, bb + 8.0 + layout.label_px), label, label_mm, Anchor::Middle, "legend"));
    }
    let caption = format!("{} ({units})", info.field.symbol());
    items.push(text(mm(bl - 12.0, bb - 0.3 * (bb - bt)), caption, label_mm, Anchor::End, "legend"));
    let sw = bb - bt;
    let swatch_l = br + 2.0 * layout.label_px;
    items.push(Item::Polygon {
        points: vec![mm(swatch_l, bt), mm(swatch_l + sw, bt), mm(swatch_l + sw, bb), mm(swatch_l, bb)],
        fill: UNDEFINED,
        layer: "legend".into(),
    });
    items.push(text(
        mm(swatch_l + sw + 0.6 * layout.label_px, bb - 0.3 * sw),
        "undefined".into(),
        label_mm,
        Anchor::Start,
        "legend",
    ));
    // Notes: range, clipped and undefined counts.
    let range = match info.range {
        Some((lo, hi)) => format!("{} to {} {units}", format_sig(lo, 3), format_sig(hi, 3)),
        None => "none defined".into(),
    };
    let notes = format!(
        "{} on {} grid points: range {range}; {} beyond ±limit, {} undefined (normal not defined)",
        info.field.symbol(),
        info.n,
        info.clipped,
        info.undefined
    );
    let notes_y = bb + layout.label_px * 3.2 + layout.label_px * 2.0;
    let notes_w = text_width_mm(&notes, label_mm) * PX_PER_MM;
    let notes_x = (0.5 * (layout.width as f64 - notes_w)).max(m);
    items.push(text(mm(notes_x, notes_y), notes, label_mm, Anchor::Start, "legend"));
    items
}

/// Round ticks over `range`, as many as fit up to `most` with at least `gap_px` pixels between
/// them at `scale` pixels per unit.
fn spaced_ticks(range: (f64, f64), scale: f64, gap_px: f64, most: usize) -> (Vec<f64>, f64) {
    let mut target = most.max(1);
    loop {
        let (ticks, step) = nice_ticks(range.0, range.1, target);
        if target == 1 || step * scale >= gap_px {
            return (ticks, step);
        }
        target -= 1;
    }
}

/// `98th`, `99.5th`, `1st`, `2nd`, `3rd`, `11th`.
fn ordinal(p: f64) -> String {
    let s = if p.fract() == 0.0 { format!("{}", p as i64) } else { format!("{p}") };
    let teen = s.ends_with("11") || s.ends_with("12") || s.ends_with("13");
    let suffix = match s.chars().last() {
        Some('1') if !teen => "st",
        Some('2') if !teen => "nd",
        Some('3') if !teen => "rd",
        _ => "th",
    };
    format!("{s}{suffix}")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nearest_rank_percentile() {
        // Nearest rank: the 98th percentile of 1..=100 is the 98th value; of 1..=10 the 10th.
        // (The colour limit is `abs_quantile` of the values at `percentile / 100`.)
        let v: Vec<f64> = (1..=100).rev().map(f64::from).collect();
        assert_eq!(abs_quantile(&v, 98.0 / 100.0), Some(98.0));
        let v: Vec<f64> = (1..=10).map(|i| -f64::from(i)).collect();
        assert_eq!(abs_quantile(&v, 98.0 / 100.0), Some(10.0));
        assert_eq!(abs_quantile(&v, 50.0 / 100.0), Some(5.0));
        assert_eq!(abs_quantile(&[], 98.0 / 100.0), None);
    }

    #[test]
    fn views_project_with_one_scale() {
        let frame = ViewFrame {
            view: ViewDirection::Profile,
            rect_px: [100.0, 50.0, 300.0, 90.0],
            h_range: (0.0, 100.0),
            v_range: (0.0, 20.0),
            scale: 2.0,
        };
        // x right, z up: (0, *, 20) is the top-left corner, (100, *, 0) the bottom-right.
        assert_eq!(frame.project(Vec3::new(0.0, 5.0, 20.0)), [100.0, 50.0]);
        assert_eq!(frame.project(Vec3::new(100.0, 5.0, 0.0)), [300.0, 90.0]);
        let bottom = ViewFrame { view: ViewDirection::Bottom, v_range: (0.0, 8.0), ..frame };
        // Seen from below: the centre line y = 0 is the top edge, y grows downward.
        assert_eq!(bottom.project(Vec3::new(50.0, 0.0, 3.0)), [200.0, 50.0]);
        assert_eq!(bottom.project(Vec3::new(50.0, 8.0, 3.0)), [200.0, 66.0]);
    }

    #[test]
    fn ticks_keep_their_distance() {
        // 10 units at 11 px per unit with 30 px between ticks: step 5 (55 px), not 2 (22 px).
        let (ticks, step) = spaced_ticks((0.0, 10.0), 11.0, 30.0, 5);
        assert_eq!(step, 5.0);
        assert_eq!(ticks, vec![0.0, 5.0, 10.0]);
    }

    #[test]
    fn ordinals() {
        assert_eq!(ordinal(98.0), "98th");
        assert_eq!(ordinal(99.5), "99.5th");
        assert_eq!(ordinal(91.0), "91st");
        assert_eq!(ordinal(92.0), "92nd");
        assert_eq!(ordinal(11.0), "11th");
        assert_eq!(ordinal(100.0), "100th");
    }

    #[test]
    fn units_of_the_fields() {
        assert_eq!(CurvatureField::Gaussian.units("m"), "1/m²");
        assert_eq!(CurvatureField::Mean.units(""), "1/unit");
    }
}
