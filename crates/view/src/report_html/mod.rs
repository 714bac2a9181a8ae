//! The hull report: one self-contained HTML page (`report.html`) that opens offline, and the
//! pictures and tables it is made of as separate files.
//!
//! The page holds, in order: the particulars (extent, surface, offsets, method, source); the
//! fit error (max, mean, RMS, the worst offset, per section) with the surface's validity (every
//! [`Finding`], also flagged under the title); the comparison of the methods
//! when one was run; the hydrostatics (at the design draft, or at ten drafts from the keel to
//! the top of the offsets); the curvature summary (smallest and largest Gaussian and mean
//! curvature and where) with the fairness measures (thin-plate energy, inflections per station
//! and waterline); the lines plan (inline SVG); the Gaussian and mean curvature maps (PNG as
//! `data:` URIs); the convergence plot of an optimised fit; and the 3-D viewer in an
//! `<iframe srcdoc>` (the page of [`crate::write_viewer_html`], escaped).
//!
//! Nothing is loaded from elsewhere: no `http(s)` URL, no web font, no script outside the
//! viewer's frame. The markup is polyglot XHTML5 (well-formed XML, read as HTML by browsers),
//! so tests and tools can read it with an XML parser. The same inputs give the same bytes:
//! no date, no times, no randomness (parallel work is gathered in order).
//!
//! Signs: the report's mean curvature `H` is positive where the hull is convex (the surface's
//! normal `S_u x S_v` turned toward the inside of the hull when most grid nodes say it points
//! outboard), as in the curvature picture and the viewer; `K` does not depend on the normal.
//!
//! Axes as everywhere: x forward, y to starboard, z up, lengths in the surface's units.

mod html;
mod page;
#[cfg(test)]
mod tests;

use self::page::Page;

use std::io;
use std::path::{Path, PathBuf};

use nurbs::{NurbsSurface, Vec3};

use self::html::num;
use crate::drawing::{lines_3d, lines_plan, write_dxf, write_dxf_3d_lines, write_svg, LinesPlanOptions, Sheet};
use crate::render::{self, RasterOptions};
use crate::viewer::{write_viewer_html, ViewerOptions};
use crate::ViewError;
use hull::{
    check_fit_validity, check_validity, fairness_report, measure_fit_error, Comparison, CurvatureField, CurvatureMap,
    CurvatureSummary, Envelope, FairnessOptions, FairnessReport, Finding, FitError, FitOutcome, Hydrostatics,
    HydrostaticsOptions, HydrostaticsTable, Offsets, OptimReport, Perpendiculars, Units, SEA_WATER_DENSITY,
};

/// The files of a report, in the order [`ReportFiles::files`] lists them.
pub const REPORT_FILE: &str = "report.html";
pub const VIEWER_FILE: &str = "viewer.html";
pub const LINES_SVG_FILE: &str = "lines.svg";
pub const LINES_DXF_FILE: &str = "lines.dxf";
pub const LINES_3D_DXF_FILE: &str = "lines3d.dxf";
pub const LINES_PNG_FILE: &str = "lines.png";
/// Most pixels of `lines.png` (a lines plan on A4x7 at 150 dpi has 1.5 x 10^7; on A0x3 it
/// would have 10^8).
pub const LINES_PNG_MAX_PIXELS: f64 = 2.5e7;

/// `raster` with its resolution lowered, if need be, so that `sheet` has at most
/// [`LINES_PNG_MAX_PIXELS`] pixels.
fn lines_png_raster(sheet: &crate::drawing::Drawing, raster: &RasterOptions) -> RasterOptions {
    let inches2 = sheet.width_mm * sheet.height_mm / (25.4 * 25.4);
    let cap = (LINES_PNG_MAX_PIXELS / inches2).sqrt();
    match raster.width_px {
        Some(_) => raster.clone(),
        None => RasterOptions { dpi: raster.dpi.min(cap), ..raster.clone() },
    }
}
pub const GAUSSIAN_PNG_FILE: &str = "curvature_gaussian.png";
pub const MEAN_PNG_FILE: &str = "curvature_mean.png";
pub const HYDROSTATICS_CSV_FILE: &str = "hydrostatics.csv";
pub const HYDROSTATICS_JSON_FILE: &str = "hydrostatics.json";
pub const CONVERGENCE_PNG_FILE: &str = "convergence.png";

/// What the report is about. Only the surface is required; each other input adds its
/// sections.
#[derive(Clone, Debug)]
pub struct ReportInputs<'a> {
    /// The starboard half-hull surface.
    pub surface: &'a NurbsSurface,
    /// Its length unit.
    pub units: Units,
    /// The page's title (and the pictures').
    pub title: String,
    /// Where the surface came from: a file name, or the sample's description.
    pub source: String,
    /// The offsets: the fit error, the markers of the lines plan and the viewer, and the top
    /// of the draft range. Without them the report says that no error was measured.
    pub offsets: Option<&'a Offsets>,
    /// The fit that made the surface (method, parameterization, its measured error and its
    /// optimisation); `None` for a surface read as it is, whose error (with offsets) is then
    /// measured here by closest-point projection.
    pub fit: Option<&'a FitOutcome>,
    /// The comparison of the methods, when one was run.
    pub comparison: Option<&'a Comparison>,
    /// The weight optimisation to plot; `None` takes the fit's.
    pub optimization: Option<&'a OptimReport>,
    /// The design draft (z of the waterplane); `None` tabulates a range of drafts.
    pub draft: Option<f64>,
    /// The perpendiculars, for the hydrostatics on Lpp; `None` takes the offsets' own
    /// ([`Offsets::perpendiculars`]), if any.
    pub perpendiculars: Option<Perpendiculars>,
    /// Sentences shown under the title (e.g. how the inputs were read).
    pub notes: Vec<String>,
}

impl<'a> ReportInputs<'a> {
    /// A report of `surface` alone, titled after `source`.
    pub fn new(surface: &'a NurbsSurface, units: Units, source: impl Into<String>) -> Self {
        let source = source.into();
        ReportInputs {
            surface,
            units,
            title: format!("Hull report: {source}"),
            source,
            offsets: None,
            fit: None,
            comparison: None,
            optimization: None,
            draft: None,
            perpendiculars: None,
            notes: Vec::new(),
        }
    }
}

/// How the report's pictures and figures are made.
#[derive(Clone, Debug, PartialEq)]
pub struct ReportOptions {
    /// Water density in t/m³ (the displacement is in tonnes whatever the length unit).
    pub density: f64,
    /// Drafts of the range tabulated without a design draft (at least 1).
    pub range_drafts: usize,
    /// The grid of the curvature summary.
    pub curvature: hull::CurvatureMapOptions,
    /// Stations and waterlines of the fairness measures.
    pub fairness: FairnessOptions,
    /// Width of the curvature pictures, pixels.
    pub curvature_width_px: u32,
    /// Parameter lines per direction of the curvature pictures.
    pub curvature_samples: usize,
    /// Resolution of `lines.png` and `convergence.png`; `lines.png` is rendered at less when
    /// its sheet would exceed [`LINES_PNG_MAX_PIXELS`] at this resolution.
    pub raster: RasterOptions,
    /// The lines plan's sheet; `None` chooses it ([`LinesPlanOptions::sheet`]).
    pub sheet: Option<Sheet>,
    /// The 3-D viewer (its title is the report's source).
    pub viewer: ViewerOptions,
}

impl Default for ReportOptions {
    /// Sea water, 10 drafts, the analysis defaults, pictures 1200 px wide (curvature) and at
    /// 150 dpi (a lines plan on A3: 2480 x 1754 px), the lines plan's sheet chosen for the
    /// hull, the viewer's default tessellation.
    fn default() -> Self {
        ReportOptions {
            density: SEA_WATER_DENSITY,
            range_drafts: 10,
            curvature: hull::CurvatureMapOptions::default(),
            fairness: FairnessOptions::default(),
            curvature_width_px: 1200,
            curvature_samples: 160,
            raster: RasterOptions::default(),
            sheet: None,
            viewer: ViewerOptions::default(),
        }
    }
}

/// Which drafts the hydrostatics table holds.
#[derive(Clone, Debug, PartialEq)]
pub enum DraftChoice {
    /// One row at the design draft given.
    Design(f64),
    /// `count` drafts evenly spaced above `bottom` (the keel) up to `top`, `top` included.
    Range {
        bottom: f64,
        top: f64,
        count: usize,
        /// What `top` is: `"the top of the offsets"` or `"the top of the surface"`.
        limit: &'static str,
    },
}

impl DraftChoice {
    /// A sentence for the report.
    pub fn describe(&self, units: Units) -> String {
        let u = units.symbol();
        match self {
            DraftChoice::Design(t) => format!("At the design draft T = {} {u}.", num(*t)),
            DraftChoice::Range { bottom, top, count, limit } => format!(
                "No design draft given: {count} drafts evenly spaced from the keel (z = {} {u}) to {limit} \
                 (z = {} {u}).",
                num(*bottom),
                num(*top)
            ),
        }
    }
}

/// A built report: the page and every file it is made of, in memory.
#[derive(Clone, Debug)]
pub struct ReportFiles {
    /// `report.html`.
    pub html: String,
    /// `viewer.html`: the page shown in the report's frame.
    pub viewer_html: String,
    /// `lines.svg`: the lines plan, on its sheet at its scale; the report holds it inline
    /// (without the XML declaration).
    pub lines_svg: String,
    /// `lines.dxf` (the sheet) and `lines3d.dxf` (the cuts in model space).
    pub lines_dxf: Vec<u8>,
    pub lines3d_dxf: Vec<u8>,
    /// `lines.png`: the lines plan rasterised.
    pub lines_png: Vec<u8>,
    /// `curvature_gaussian.png` and `curvature_mean.png`, as inlined in the page.
    pub curvature_gaussian_png: Vec<u8>,
    pub curvature_mean_png: Vec<u8>,
    /// `convergence.png`, for an optimised fit.
    pub convergence_png: Option<Vec<u8>>,
    /// The hydrostatics table (`hydrostatics.csv`, `hydrostatics.json`).
    pub hydrostatics: HydrostaticsTable,
    /// Which drafts it holds.
    pub drafts: DraftChoice,
    /// The curvature statistics (signs of the analysis module: `S_u x S_v`).
    pub curvature: CurvatureSummary,
    /// The sign that makes the mean curvature positive where the hull is convex (+1 or -1).
    pub convex_sign: f64,
    /// The fairness measures.
    pub fairness: FairnessReport,
    /// The fit error shown, if any.
    pub error: Option<FitError>,
    /// The surface's defects (the fit's; else checked here against the offsets' envelope and
    /// flats, or, without offsets, for folds and inward-facing facets only). Empty when valid.
    pub validity: Vec<Finding>,
}

impl ReportFiles {
    /// Every file as (name, bytes), `report.html` first.
    pub fn files(&self) -> Vec<(&'static str, Vec<u8>)> {
        let mut out = vec![
            (REPORT_FILE, self.html.as_bytes().to_vec()),
            (VIEWER_FILE, self.viewer_html.as_bytes().to_vec()),
            (LINES_SVG_FILE, self.lines_svg.as_bytes().to_vec()),
            (LINES_DXF_FILE, self.lines_dxf.clone()),
            (LINES_3D_DXF_FILE, self.lines3d_dxf.clone()),
            (LINES_PNG_FILE, self.lines_png.clone()),
            (GAUSSIAN_PNG_FILE, self.curvature_gaussian_png.clone()),
            (MEAN_PNG_FILE, self.curvature_mean_png.clone()),
            (HYDROSTATICS_CSV_FILE, self.hydrostatics.csv().into_bytes()),
            (HYDROSTATICS_JSON_FILE, self.hydrostatics.json().into_bytes()),
        ];
        if let Some(png) = &self.convergence_png {
            out.push((CONVERGENCE_PNG_FILE, png.clone()));
        }
        out
    }
}

/// Write every file of `report` into the directory `dir` (created if needed), all or nothing:
/// the files are staged beside `dir` and moved in together ([`hull::OutputDir`]), so a failure
/// leaves what was in `dir` byte for byte. Returns the paths written, `report.html` first.
///
/// # Errors
/// [`ViewError::Hull`] holding [`HullError::Io`](hull::HullError::Io) naming the file or
/// directory that could not be written (then nothing in `dir` has changed, unless the failure is
/// in the final moves: see [`hull::OutputDir`]).
pub fn write_report(dir: &Path, report: &ReportFiles) -> Result<Vec<PathBuf>, ViewError> {
    let mut out = hull::OutputDir::stage(dir)?;
    for (name, bytes) in report.files() {
        out.write_bytes(name, &bytes)?;
    }
    Ok(out.commit()?)
}

/// Build the report of `inputs`.
///
/// # Errors
/// [`ViewError::DraftAtKeel`] for a design draft at or below the keel, and [`ViewError::Hull`]
/// holding [`HullError::Draft`](hull::HullError::Draft) for one that is not finite or above the
/// top of the surface; [`ViewError::Density`] for a density that is not positive; the errors of
/// [`curvature_image`](crate::curvature_image) for a curvature picture narrower than 320 px or a
/// surface the pictures cannot show (no extent along x, non-finite points).
pub fn build_report(inputs: &ReportInputs<'_>, options: &ReportOptions) -> Result<ReportFiles, ViewError> {
    let surface = inputs.surface;
    let units = inputs.units;
    let u = units.symbol();
    if !(options.density.is_finite() && options.density > 0.0) {
        return Err(ViewError::Density { density: options.density });
    }

    // Figures.
    let (hydrostatics, drafts) = hydrostatics_table(inputs, options)?;
    let map = hull::curvature_map(surface, &options.curvature);
    let convex_sign = convex_sign(&map);
    let curvature = map.summary();
    let fairness = fairness_report(surface, &options.fairness);
    let error = match (inputs.fit, inputs.offsets) {
        (Some(fit), _) => Some(fit.error.clone()),
        (None, Some(o)) => Some(measure_fit_error(surface, o, None)),
        (None, None) => None,
    };
    let optimization = inputs.optimization.or_else(|| inputs.fit.and_then(|f| f.optimization.as_ref()));
    let validity = match (inputs.fit, inputs.offsets) {
        (Some(fit), _) => fit.validity.clone(),
        (None, Some(o)) => check_fit_validity(surface, o)?,
        (None, None) => check_validity(surface, &Envelope::unbounded(), &[]),
    };

    // Pictures and drawings.
    let lines_options = LinesPlanOptions {
        title: "Lines plan".into(),
        source: Some(inputs.source.clone()),
        sheet: options.sheet,
        ..LinesPlanOptions::default()
    };
    let sheet = lines_plan(surface, inputs.offsets, units, &lines_options);
    let lines_svg = to_string(|w| write_svg(w, &sheet), "the lines plan SVG")?;
    let lines_dxf = to_bytes(|w| write_dxf(w, &sheet), "the lines plan DXF")?;
    let curves = lines_3d(surface, inputs.offsets, &lines_options);
    let lines3d_dxf = to_bytes(|w| write_dxf_3d_lines(w, &curves, units), "the 3-D lines DXF")?;
    let lines_png = render::render_png(&sheet, &lines_png_raster(&sheet, &options.raster))?;
    let picture = |field| {
        let o = render::CurvatureImageOptions {
            width_px: options.curvature_width_px,
            units: u.to_string(),
            title: inputs.source.clone(),
            samples: options.curvature_samples,
            ..render::CurvatureImageOptions::default()
        };
        render::curvature_image(surface, field, &o)
    };
    let gaussian = picture(CurvatureField::Gaussian)?;
    let mean = picture(CurvatureField::Mean)?;
    let convergence = match optimization {
        Some(o) => {
            let plot = render::convergence_plot(
                &[(o.algorithm, &o.history)],
                &format!("Convergence of {}: best objective per iteration", o.algorithm),
                u,
            );
            let image = render::render_rgba(&plot, &options.raster)?;
            Some((image.to_png()?, image.width(), image.height()))
        }
        None => None,
    };
    let viewer_options = ViewerOptions { title: inputs.source.clone(), ..options.viewer.clone() };
    let viewer_html =
        to_string(|w| write_viewer_html(w, surface, inputs.offsets, units, &viewer_options), "the viewer page")?;

    let curvature_gaussian_png = gaussian.image.to_png()?;
    let curvature_mean_png = mean.image.to_png()?;
    let page = Page {
        inputs,
        extent: extent(&map),
        hydrostatics: &hydrostatics,
        drafts: &drafts,
        curvature: &curvature,
        convex_sign,
        fairness: &fairness,
        error: error.as_ref(),
        validity: &validity,
        optimization,
        lines_svg: &lines_svg,
        lines_sheet: Sheet::of_size(sheet.width_mm, sheet.height_mm),
        maps: [
            (&gaussian, curvature_gaussian_png.as_slice(), GAUSSIAN_PNG_FILE),
            (&mean, curvature_mean_png.as_slice(), MEAN_PNG_FILE),
        ],
        convergence: convergence.as_ref().map(|(png, w, h)| (png.as_slice(), *w, *h)),
        viewer_html: &viewer_html,
    };
    let html = page.render();
    Ok(ReportFiles {
        html,
        viewer_html,
        lines_svg,
        lines_dxf,
        lines3d_dxf,
        lines_png,
        curvature_gaussian_png,
        curvature_mean_png,
        convergence_png: convergence.map(|(png, _, _)| png),
        hydrostatics,
        drafts,
        curvature,
        convex_sign,
        fairness,
        error,
        validity,
    })
}

/// The output of a writer into a buffer; an I/O error (only a non-finite number refused by
/// the writer can occur) becomes [`ViewError::Write`] naming `what`.
fn to_bytes(f: impl FnOnce(&mut Vec<u8>) -> io::Result<()>, what: &'static str) -> Result<Vec<u8>, ViewError> {
    let mut buf = Vec::new();
    f(&mut buf).map_err(|error| ViewError::Write { what, error })?;
    Ok(buf)
}

fn to_string(f: impl FnOnce(&mut Vec<u8>) -> io::Result<()>, what: &'static str) -> Result<String, ViewError> {
    String::from_utf8(to_bytes(f, what)?).map_err(|e| ViewError::NotUtf8 { what, error: e.utf8_error() })
}

/// The hydrostatics at the design draft, or at [`ReportOptions::range_drafts`] drafts from the
/// keel up to the top of the offsets (or of the surface, if lower or without offsets).
fn hydrostatics_table(
    inputs: &ReportInputs<'_>,
    options: &ReportOptions,
) -> Result<(HydrostaticsTable, DraftChoice), ViewError> {
    // Given, or the offsets' own.
    let perpendiculars = inputs.perpendiculars.or(inputs.offsets.and_then(|o| o.perpendiculars));
    let hopts = HydrostaticsOptions {
        density: options.density,
        units: inputs.units,
        perpendiculars,
        ..HydrostaticsOptions::default()
    };
    let hydro = Hydrostatics::new(inputs.surface, &hopts)?;
    let (bottom, top) = (hydro.bottom(), hydro.top());
    let (drafts, choice) = match inputs.draft {
        Some(t) => {
            if t.is_finite() && t <= bottom {
                return Err(ViewError::DraftAtKeel { draft: t, bottom, top, units: inputs.units });
            }
            (vec![t], DraftChoice::Design(t))
        }
        None => {
            let offsets_top = inputs.offsets.and_then(Offsets::bounds).map(|(_, hi)| hi.z);
            let (top, limit) = match offsets_top {
                Some(z) if z <= top => (z, "the top of the offsets"),
                _ => (top, "the top of the surface"),
            };
            if !(top > bottom) {
                return Err(ViewError::NoDepth { top, bottom, units: inputs.units });
            }
            let n = options.range_drafts.max(1);
            let drafts = (1..=n).map(|k| if k == n { top } else { bottom + (top - bottom) * k as f64 / n as f64 });
            (drafts.collect(), DraftChoice::Range { bottom, top, count: n, limit })
        }
    };
    let rows = hydro.rows(&drafts)?;
    let source = match inputs.fit {
        Some(f) => format!("{}, fitted by {}", inputs.source, f.config.method.name()),
        None => inputs.source.clone(),
    };
    Ok((HydrostaticsTable { source, units: inputs.units, density: options.density, perpendiculars, rows }, choice))
}

/// +1 if the surface's normal `S_u x S_v` points toward the inside of the hull at most
/// regular nodes of `map` ([`CurvatureMap::outward_flip`], as the curvature picture), else
/// -1: the factor that makes the mean curvature positive where the hull is convex.
fn convex_sign(map: &CurvatureMap) -> f64 {
    if map.outward_flip() {
        -1.0
    } else {
        1.0
    }
}

/// Bounding box of the finite points (a zero box without any).
fn bounds(points: &[Vec3]) -> (Vec3, Vec3) {
    let inf = f64::INFINITY;
    let (lo, hi) = points.iter().filter(|p| p.is_finite()).fold(
        (Vec3::new(inf, inf, inf), Vec3::new(-inf, -inf, -inf)),
        |(a, b), p| {
            (Vec3::new(a.x.min(p.x), a.y.min(p.y), a.z.min(p.z)), Vec3::new(b.x.max(p.x), b.y.max(p.y), b.z.max(p.z)))
        },
    );
    if lo.x.is_finite() {
        (lo, hi)
    } else {
        (Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 0.0, 0.0))
    }
}

/// The surface's extent on the curvature grid (with its knot lines).
fn extent(map: &CurvatureMap) -> (Vec3, Vec3) {
    bounds(&map.points)
}
