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
//! `<iframe srcdoc>` (the page of [`crate::viewer`], escaped).
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

use std::io;
use std::path::{Path, PathBuf};

use nurbs::{NurbsSurface, Vec3};

use self::html::{
    esc, esc_srcdoc, fixed, kv_table, num, png_img, point, table, td, td_html, td_key, td_num, th, th_key,
};
use crate::analysis::{self, CurvatureMap, CurvatureSummary, FairnessOptions, FairnessReport, FieldStats, Finding};
use crate::drawing::{lines_3d, lines_plan, write_dxf, write_dxf_3d_lines, write_svg, LinesPlanOptions, Sheet};
use crate::numfmt::format_figure;
use crate::offsets::Perpendiculars;
use crate::optimize::OptimReport;
use crate::render::{self, RasterOptions};
use crate::viewer::{write_viewer_html, ViewerOptions};
use crate::{
    measure_fit_error, Comparison, FitError, FitOutcome, HullError, Hydrostatics, HydrostaticsOptions,
    HydrostaticsTable, Offsets, RowStatus, Units, HYDROSTATICS_COLUMNS, SEA_WATER_DENSITY,
};

const TEMPLATE: &str = include_str!("report.html");
const STYLE: &str = include_str!("report.css");

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
    pub curvature: analysis::CurvatureMapOptions,
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
            curvature: analysis::CurvatureMapOptions::default(),
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
/// the files are staged beside `dir` and moved in together ([`crate::OutputDir`]), so a failure
/// leaves what was in `dir` byte for byte. Returns the paths written, `report.html` first.
///
/// # Errors
/// [`HullError::Io`] naming the file or directory that could not be written (then nothing in
/// `dir` has changed, unless the failure is in the final moves: see [`crate::OutputDir`]).
pub fn write_report(dir: &Path, report: &ReportFiles) -> Result<Vec<PathBuf>, HullError> {
    let mut out = crate::OutputDir::stage(dir)?;
    for (name, bytes) in report.files() {
        out.write_bytes(name, &bytes)?;
    }
    out.commit()
}

/// Build the report of `inputs`.
///
/// # Errors
/// [`HullError::Draft`] for a design draft that is not finite, at or below the keel, or above
/// the top of the surface; [`HullError::Config`] for unusable options (a density that is not
/// positive, a curvature picture narrower than 320 px) or a surface the pictures cannot show
/// (no extent along x, non-finite points).
pub fn build_report(inputs: &ReportInputs<'_>, options: &ReportOptions) -> Result<ReportFiles, HullError> {
    let surface = inputs.surface;
    let units = inputs.units;
    let u = units.symbol();
    if !(options.density.is_finite() && options.density > 0.0) {
        return Err(HullError::Config(format!("density {}: expected a positive number in t/m³", options.density)));
    }

    // Figures.
    let (hydrostatics, drafts) = hydrostatics_table(inputs, options)?;
    let map = analysis::curvature_map(surface, &options.curvature);
    let convex_sign = convex_sign(&map);
    let curvature = map.summary();
    let fairness = analysis::fairness_report(surface, &options.fairness);
    let error = match (inputs.fit, inputs.offsets) {
        (Some(fit), _) => Some(fit.error.clone()),
        (None, Some(o)) => Some(measure_fit_error(surface, o, None)),
        (None, None) => None,
    };
    let optimization = inputs.optimization.or_else(|| inputs.fit.and_then(|f| f.optimization.as_ref()));
    let validity = match (inputs.fit, inputs.offsets) {
        (Some(fit), _) => fit.validity.clone(),
        (None, Some(o)) => analysis::check_fit_validity(surface, o)?,
        (None, None) => analysis::check_validity(surface, &analysis::Envelope::unbounded(), &[]),
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
        let o = render::CurvatureMapOptions {
            width_px: options.curvature_width_px,
            units: u.to_string(),
            title: inputs.source.clone(),
            samples: options.curvature_samples,
            ..render::CurvatureMapOptions::default()
        };
        render::curvature_map(surface, field, &o)
    };
    let gaussian = picture(analysis::CurvatureField::Gaussian)?;
    let mean = picture(analysis::CurvatureField::Mean)?;
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
/// the writer can occur) becomes [`HullError::Config`] naming `what`.
fn to_bytes(f: impl FnOnce(&mut Vec<u8>) -> io::Result<()>, what: &str) -> Result<Vec<u8>, HullError> {
    let mut buf = Vec::new();
    f(&mut buf).map_err(|e| HullError::Config(format!("cannot write {what}: {e}")))?;
    Ok(buf)
}

fn to_string(f: impl FnOnce(&mut Vec<u8>) -> io::Result<()>, what: &str) -> Result<String, HullError> {
    String::from_utf8(to_bytes(f, what)?).map_err(|e| HullError::Config(format!("{what} is not UTF-8: {e}")))
}

/// The hydrostatics at the design draft, or at [`ReportOptions::range_drafts`] drafts from the
/// keel up to the top of the offsets (or of the surface, if lower or without offsets).
fn hydrostatics_table(
    inputs: &ReportInputs<'_>,
    options: &ReportOptions,
) -> Result<(HydrostaticsTable, DraftChoice), HullError> {
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
    let u = inputs.units.symbol();
    let (drafts, choice) = match inputs.draft {
        Some(t) => {
            if t.is_finite() && t <= bottom {
                return Err(HullError::Draft {
                    draft: t,
                    reason: format!(
                        "at or below the keel (lowest z {bottom} {u}): nothing is immersed (expected a draft above \
                         {bottom} and at most {top})"
                    ),
                });
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
                return Err(HullError::Config(format!(
                    "the surface has no depth below z = {top} {u} (lowest z {bottom}): no draft to tabulate"
                )));
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

/// Everything one page shows.
struct Page<'p, 'a> {
    inputs: &'p ReportInputs<'a>,
    extent: (Vec3, Vec3),
    hydrostatics: &'p HydrostaticsTable,
    drafts: &'p DraftChoice,
    curvature: &'p CurvatureSummary,
    convex_sign: f64,
    fairness: &'p FairnessReport,
    error: Option<&'p FitError>,
    validity: &'p [Finding],
    optimization: Option<&'p OptimReport>,
    lines_svg: &'p str,
    /// The lines plan's sheet.
    lines_sheet: Sheet,
    maps: [(&'p render::CurvatureMap, &'p [u8], &'static str); 2],
    convergence: Option<(&'p [u8], u32, u32)>,
    viewer_html: &'p str,
}

impl Page<'_, '_> {
    fn u(&self) -> &'static str {
        self.inputs.units.symbol()
    }

    /// The whole page: the template with its markers filled.
    fn render(&self) -> String {
        let mut sections: Vec<(&str, &str, String)> =
            vec![("particulars", "Particulars", self.particulars()), ("fit-error", "Fit error", self.fit_error())];
        if let Some(c) = self.inputs.comparison {
            sections.push(("comparison", "Comparison of the methods", comparison(c)));
        }
        sections.push(("hydrostatics", "Hydrostatics", self.hydrostatics()));
        sections.push(("curvature", "Curvature and fairness", self.curvature()));
        sections.push(("lines-plan", "Lines plan", self.lines_plan()));
        sections.push(("curvature-maps", "Curvature maps", self.curvature_maps()));
        if let (Some(o), Some(c)) = (self.optimization, self.convergence) {
            sections.push(("convergence", "Weight optimisation", self.convergence(o, c)));
        }
        sections.push(("viewer", "3-D viewer", self.viewer()));

        let mut nav = String::from("<ol>\n");
        let mut body = String::new();
        for (id, heading, content) in &sections {
            nav.push_str(&format!("<li><a href=\"#{id}\">{}</a></li>\n", esc(heading)));
            body.push_str(&format!("<section id=\"{id}\">\n<h2>{}</h2>\n{content}</section>\n", esc(heading)));
        }
        nav.push_str("</ol>");
        let generator = format!("hullskin {}", env!("CARGO_PKG_VERSION"));
        let mut out = String::with_capacity(body.len() + STYLE.len() + TEMPLATE.len() + 4096);
        let mut rest = TEMPLATE;
        while let Some(start) = rest.find("{{") {
            out.push_str(&rest[..start]);
            let len = rest[start..].find("}}").expect("the template's markers are closed");
            match &rest[start + 2..start + len] {
                "TITLE" => out.push_str(&esc(&self.inputs.title)),
                "GENERATOR" => out.push_str(&esc(&generator)),
                "STYLE" => out.push_str(STYLE),
                "INTRO" => out.push_str(&self.intro()),
                "NAV" => out.push_str(&nav),
                "SECTIONS" => out.push_str(&body),
                "FOOTER" => out.push_str(&self.footer(&generator)),
                other => unreachable!("unknown template marker {other}"),
            }
            rest = &rest[start + len + 2..];
        }
        out.push_str(rest);
        out
    }

    fn intro(&self) -> String {
        let i = self.inputs;
        let mut s = format!(
            "<p>Source: <strong>{}</strong>. Lengths in {} ({}); axes x forward, y to starboard, z up from the \
             baseline.</p>\n",
            esc(&i.source),
            esc(i.units.plural_name()),
            esc(self.u())
        );
        for n in &i.notes {
            s.push_str(&format!("<p class=\"note\">{}</p>\n", esc(n)));
        }
        for f in self.validity {
            s.push_str(&format!("<p class=\"note\">Warning: {}.</p>\n", esc(&f.message(self.u()))));
        }
        s
    }

    /// The validity subsection of the fit error: a table of the findings, or what was checked.
    fn validity(&self) -> String {
        let u = self.u();
        let checked = if self.inputs.offsets.is_some() {
            "folds, the offsets' envelope (0.5 % of the half-beam, depth and length), the flats of the offsets \
             (0.05 %) and inward-facing facets"
        } else {
            "folds and inward-facing facets (without offsets there is no envelope to check)"
        };
        let mut s = String::from("<h3>Validity</h3>\n");
        if self.validity.is_empty() {
            s.push_str(&format!("<p id=\"validity-ok\">No finding: checked {checked}.</p>\n"));
            return s;
        }
        s.push_str(&format!(
            "<p>{} finding(s); checked {checked}. Size: how far past the reference ({u}; an area in {u}² for \
             inward-facing facets).</p>\n",
            self.validity.len()
        ));
        let head = vec![
            th_key("Finding"),
            th("From x", Some(u)),
            th("To x", Some(u)),
            th_key("Worst at (x, y, z)"),
            th("Size", None),
            th("Allowed", None),
        ];
        let rows: Vec<(bool, Vec<String>)> = self
            .validity
            .iter()
            .map(|f| {
                let (a, b) = f.x_band.unwrap_or((f.place.x, f.place.x));
                let p = [f.place.x, f.place.y, f.place.z];
                (true, vec![td_key(f.kind.name()), td(a), td(b), td_key(&point(p)), td(f.size), td(f.limit)])
            })
            .collect();
        s.push_str(&table("validity-table", "numbers", &head, &rows));
        s
    }

    fn footer(&self, generator: &str) -> String {
        let mut files = vec![
            VIEWER_FILE,
            LINES_SVG_FILE,
            LINES_DXF_FILE,
            LINES_3D_DXF_FILE,
            LINES_PNG_FILE,
            GAUSSIAN_PNG_FILE,
            MEAN_PNG_FILE,
            HYDROSTATICS_CSV_FILE,
            HYDROSTATICS_JSON_FILE,
        ];
        if self.convergence.is_some() {
            files.push(CONVERGENCE_PNG_FILE);
        }
        let list: Vec<String> = files.iter().map(|f| format!("<code>{f}</code>")).collect();
        format!(
            "<p class=\"muted\">Made by {}. This page needs no network. Written beside it: {}.</p>",
            esc(generator),
            list.join(", ")
        )
    }

    fn particulars(&self) -> String {
        let i = self.inputs;
        let s = i.surface;
        let u = self.u();
        let (lo, hi) = self.extent;
        let mut rows = vec![
            ("Source".to_string(), esc(&i.source)),
            ("Units".into(), format!("{} ({})", esc(i.units.plural_name()), esc(u))),
            (
                "Length (x extent of the surface)".into(),
                format!("{} {u} (x {} to {})", num(hi.x - lo.x), num(lo.x), num(hi.x)),
            ),
            ("Beam (twice the largest half-breadth)".into(), format!("{} {u}", num(2.0 * hi.y))),
            ("Depth (z extent)".into(), format!("{} {u} (z {} to {})", num(hi.z - lo.z), num(lo.z), num(hi.z))),
        ];
        if let (DraftChoice::Design(t), Some(r)) = (self.drafts, self.hydrostatics.rows.first()) {
            rows.push((
                "At the design draft".into(),
                format!("T {} {u}, Lwl {} {u}, Bwl {} {u}, CB {}", num(*t), num(r.lwl), num(r.bwl), fixed(r.cb, 4)),
            ));
        }
        rows.push((
            "Surface".into(),
            format!(
                "degrees {} (u, along the sections) and {} (v, across them); {} × {} control points; {}; \
                 {} × {} knot spans",
                s.degree_u(),
                s.degree_v(),
                s.n_u(),
                s.n_v(),
                if s.is_rational() { "rational (weights)" } else { "non-rational (all weights 1)" },
                s.knots_u().interior_breaks().len() + 1,
                s.knots_v().interior_breaks().len() + 1
            ),
        ));
        rows.push((
            "Offsets".into(),
            match i.offsets {
                Some(o) => format!("{} sections, {} points", o.sections.len(), o.num_points()),
                None => "none given".into(),
            },
        ));
        rows.push((
            "Method".into(),
            match i.fit {
                Some(f) => format!(
                    "<code>{}</code>, parameterization {}",
                    esc(f.config.method.name()),
                    esc(f.config.param.name())
                ),
                None => "none here: the surface was read as it is".into(),
            },
        ));
        kv_table("particulars-table", &rows)
    }

    fn fit_error(&self) -> String {
        let u = self.u();
        let Some(e) = self.error else {
            return format!(
                "<p class=\"note\">No offsets were given, so the distance of the offsets to the surface is not \
                 measured.</p>\n{}",
                self.validity()
            );
        };
        let how = if self.inputs.fit.is_some() {
            "Distance of every offset to the surface by closest-point projection (from the fit's parameters \
             and a global search)"
        } else {
            "Distance of every offset to the surface by closest-point projection (global search)"
        };
        let mut s = format!("<p>{how}, in {u}.</p>\n");
        let o = &e.overall;
        let mut rows = vec![
            ("Max".to_string(), format!("{} {u}", num(o.max))),
            ("Mean".into(), format!("{} {u}", num(o.mean))),
            ("RMS".into(), format!("{} {u}", num(o.rms))),
            ("Offsets measured".into(), o.points.to_string()),
        ];
        if let Some(w) = &e.worst {
            let line = w.line.map_or(String::new(), |l| format!(", input line {l}"));
            rows.push((
                "Worst offset".into(),
                format!(
                    "section {}, point {}{line}: {} {u} at {}",
                    esc(&w.section),
                    w.index + 1,
                    num(w.distance),
                    point(w.point)
                ),
            ));
        }
        if e.unconverged_projections > 0 {
            rows.push(("Projections at the iteration limit".into(), e.unconverged_projections.to_string()));
        }
        s.push_str(&kv_table("error-summary", &rows));
        s.push_str(&self.validity());
        let worst = e.per_section.iter().enumerate().fold(None, |best: Option<(usize, f64)>, (k, sec)| match best {
            Some((_, m)) if m >= sec.stats.max => best,
            _ => Some((k, sec.stats.max)),
        });
        let xs: Vec<Option<f64>> = match self.inputs.offsets {
            Some(off) if off.sections.len() == e.per_section.len() => off.sections.iter().map(|s| s.mean_x()).collect(),
            _ => vec![None; e.per_section.len()],
        };
        let head = vec![
            th_key("Section"),
            th("x (mean)", Some(u)),
            th("Points", None),
            th("Max", Some(u)),
            th("Mean", Some(u)),
            th("RMS", Some(u)),
        ];
        let rows: Vec<(bool, Vec<String>)> = e
            .per_section
            .iter()
            .zip(&xs)
            .enumerate()
            .map(|(k, (sec, x))| {
                let st = &sec.stats;
                let x = x.map_or_else(|| "<td>-</td>".to_string(), td);
                let cells = vec![
                    td_key(&sec.section),
                    x,
                    format!("<td>{}</td>", st.points),
                    td(st.max),
                    td(st.mean),
                    td(st.rms),
                ];
                (worst.is_some_and(|(w, _)| w == k), cells)
            })
            .collect();
        s.push_str("<h3>Per section</h3>\n");
        if let Some((k, _)) = worst {
            s.push_str(&format!(
                "<p class=\"muted\">Highlighted: the section with the largest error ({}).</p>\n",
                esc(&e.per_section[k].section)
            ));
        }
        s.push_str(&table("error-sections", "numbers", &head, &rows));
        s
    }

    fn hydrostatics(&self) -> String {
        let t = self.hydrostatics;
        let mut s = format!(
            "<p>{} From the surface (not the offsets): {}. CM = AM/(Bwl T), CP = Vol/(AM Lwl), CW = AW/(Lwl \
             Bwl); LCB and LCF also as x coordinates; KB = VCB, KMt = KB + BMt and KMl = KB + BMl above the \
             baseline.</p>\n",
            esc(&self.drafts.describe(self.inputs.units)),
            esc(&t.conventions())
        );
        let units = t.unit_labels();
        let cols = t.shown_columns();
        let head: Vec<String> = cols.iter().map(|&c| th(HYDROSTATICS_COLUMNS[c].1, Some(&units[c]))).collect();
        let rows: Vec<(bool, Vec<String>)> = t
            .rows
            .iter()
            .map(|r| {
                let v = r.values();
                // Every shown column has a value in every row (`shown_columns`).
                let cells = cols.iter().filter_map(|&c| v[c]).map(|x| td_num(x, &format_figure(x))).collect();
                (false, cells)
            })
            .collect();
        s.push_str(&table("hydrostatics-table", "numbers wide", &head, &rows));
        s.push_str(&format!(
            "<p class=\"muted\">Every figure to full precision in <code>{HYDROSTATICS_CSV_FILE}</code> and \
             <code>{HYDROSTATICS_JSON_FILE}</code>.</p>\n"
        ));
        s
    }

    fn curvature(&self) -> String {
        let c = self.curvature;
        let u = self.u();
        let mut s = format!(
            "<p>On a parameter grid of {} × {} nodes (uniform, with every knot line); {} degenerate nodes (a collapsed \
             edge: a pointed stem, the keel line) left out. K = k1 k2 does not depend on the side; H = (k1 + k2)/2 is \
             signed positive where the hull is convex, as in the pictures.</p>\n",
            c.grid[0], c.grid[1], c.flagged
        );
        let sign = self.convex_sign;
        let head = vec![
            th_key("Curvature"),
            th("Min", None),
            th_key("at (x, y, z)"),
            th("Max", None),
            th_key("at (x, y, z)"),
            th("Low percentile", None),
            th("High percentile", None),
            th("Average", None),
        ];
        let mut rows = Vec::new();
        for (name, unit, stats, sgn) in
            [("K (Gaussian)", format!("1/{u}²"), c.gaussian, 1.0), ("H (mean)", format!("1/{u}"), c.mean, sign)]
        {
            let Some(st) = stats else {
                rows.push((false, vec![td_key(name), td_html("every node degenerate")]));
                continue;
            };
            let st = signed(&st, sgn);
            rows.push((
                false,
                vec![
                    td_key(&format!("{name}, {unit}")),
                    td(st.min.value),
                    td_key(&point(st.min.point)),
                    td(st.max.value),
                    td_key(&point(st.max.point)),
                    td_num(st.low, &format!("{} (p{})", num(st.low), st.percentiles[0])),
                    td_num(st.high, &format!("{} (p{})", num(st.high), st.percentiles[1])),
                    td(st.average),
                ],
            ));
        }
        s.push_str(&table("curvature-table", "numbers", &head, &rows));

        let f = self.fairness;
        let e = &f.energy;
        s.push_str("<h3>Fairness</h3>\n");
        s.push_str(&kv_table(
            "fairness-summary",
            &[
                (
                    "Thin-plate energy ∫(k1² + k2²) dA".into(),
                    format!(
                        "{} (dimensionless; a sphere's is 8π ≈ 25.13; compares surfaces of one hull: a bump raises it)",
                        num(e.thin_plate)
                    ),
                ),
                (
                    "Parametric energy ∫|S_uu|² + 2|S_uv|² + |S_vv|² du dv".into(),
                    format!("{} {u}² (compares fits with the same knots only)", num(e.parametric)),
                ),
                ("Area of the surface (one side)".into(), format!("{} {u}²", num(e.area))),
                (
                    "Quadrature".into(),
                    format!(
                        "{} × {} Gauss points per knot span; {} degenerate points skipped",
                        e.points_per_span[0], e.points_per_span[1], e.skipped
                    ),
                ),
                (
                    "Inflections".into(),
                    format!(
                        "{} in all, on {} stations and {} waterlines (a sign change of the curvature beyond {} 1/{u})",
                        f.inflections,
                        f.stations.len(),
                        f.waterlines.len(),
                        num(f.curvature_threshold)
                    ),
                ),
            ],
        ));
        for (id, title, planes, axis) in [
            ("fairness-stations", "Stations", &f.stations, "x"),
            ("fairness-waterlines", "Waterlines", &f.waterlines, "z"),
        ] {
            s.push_str(&format!("<h3>{title}</h3>\n"));
            let head = vec![
                th(axis, Some(u)),
                th("Branches", None),
                th("Inflections", None),
                th("Largest |κ|", Some(&format!("1/{u}"))),
                th_key("at (x, y, z)"),
            ];
            let rows: Vec<(bool, Vec<String>)> = planes
                .iter()
                .map(|p| {
                    let at = p
                        .branches
                        .iter()
                        .find(|b| b.max_curvature == p.max_curvature)
                        .map_or_else(|| "-".to_string(), |b| point(b.max_at));
                    (
                        false,
                        vec![
                            td(p.plane.value()),
                            format!("<td>{}</td>", p.branches.len()),
                            format!("<td>{}</td>", p.inflections),
                            td(p.max_curvature.abs()),
                            td_key(&at),
                        ],
                    )
                })
                .collect();
            s.push_str(&table(id, "numbers", &head, &rows));
        }
        s
    }

    fn lines_plan(&self) -> String {
        // The inline copy is lines.svg without its XML declaration (not allowed inside a page).
        let svg = self.lines_svg.find("<svg").map_or(self.lines_svg, |k| &self.lines_svg[k..]);
        let offsets = if self.inputs.offsets.is_some() {
            " The offsets are marked in the body plan, coloured by their distance to the surface."
        } else {
            ""
        };
        // The whole sheet, as wide as the page (a vector drawing: the browser's zoom reads it).
        format!(
            "<figure id=\"lines-figure\">\n{svg}<figcaption>Body plan, profile and half-breadth plan at one standard \
             scale on {}, the sheet on which they fill the most of the frame (<code>{LINES_SVG_FILE}</code> and \
             <code>{LINES_DXF_FILE}</code> print at scale, <code>{LINES_PNG_FILE}</code>; the cuts in 3-D in \
             <code>{LINES_3D_DXF_FILE}</code>).{offsets}</figcaption>\n</figure>\n",
            esc(&self.lines_sheet.to_string())
        )
    }

    fn curvature_maps(&self) -> String {
        let u = self.u();
        let mut s = String::new();
        for (map, png, file) in self.maps {
            let field = map.field;
            let unit = field.units(u);
            let range = map.range.map_or_else(
                || "no regular point".to_string(),
                |(a, b)| format!("values from {} to {} {unit}", num(a), num(b)),
            );
            let id = format!("map-{}", if field == analysis::CurvatureField::Gaussian { "gaussian" } else { "mean" });
            let alt = format!("{} of the hull, profile and bottom view", field.name());
            s.push_str(&format!(
                "<figure>\n{}\n<figcaption>{} {} (<code>{file}</code>): profile (x right, z up) and bottom view; \
                 colours from blue (−{lim}) through white (0) to red (+{lim} {unit}), the 98th percentile of the \
                 magnitude; {range} on this picture's own {} × {} grid (the table above and the 3-D viewer sample \
                 other grids, so their extremes differ slightly); {} of {} grid points beyond the scale, {} \
                 undefined (grey).</figcaption>\n\
                 </figure>\n",
                png_img(png, map.image.width(), map.image.height(), &alt, &id),
                esc(&capitalise(field.name())),
                field.symbol(),
                map.grid.0,
                map.grid.1,
                map.clipped,
                map.grid.0 * map.grid.1,
                map.undefined,
                lim = num(map.limit),
            ));
        }
        s
    }

    fn convergence(&self, o: &OptimReport, (png, w, h): (&[u8], u32, u32)) -> String {
        let stop = o.stop.phrase();
        let rows = vec![
            ("Algorithm".to_string(), format!("<code>{}</code>, seed {}", esc(o.algorithm), o.seed)),
            ("Weights".into(), format!("layout {}, control points {}", esc(o.weight_layout), esc(o.control_points))),
            (
                "Weight bounds and result".into(),
                format!(
                    "bounds {} to {}; weights from {} to {}, {} at a bound",
                    num(o.weight_bounds[0]),
                    num(o.weight_bounds[1]),
                    num(o.weight_range[0]),
                    num(o.weight_range[1]),
                    o.weights_at_bounds
                ),
            ),
            ("Iterations".into(), format!("{} ({} objective evaluations), {stop}", o.iterations, o.evaluations)),
            (
                "Objective (parametric RMS)".into(),
                format!("{} {u} at the start, {} {u} at the end", num(o.start_value), num(o.final_value), u = self.u()),
            ),
            ("Parameter correction".into(), if o.parameter_correction { "yes" } else { "no" }.into()),
        ];
        format!(
            "{}<figure>\n{}\n<figcaption>Best objective after each iteration, log scale \
             (<code>{CONVERGENCE_PNG_FILE}</code>).</figcaption>\n</figure>\n",
            kv_table("optimisation-summary", &rows),
            png_img(png, w, h, "Convergence of the weight optimisation", "convergence-plot")
        )
    }

    fn viewer(&self) -> String {
        format!(
            "<iframe id=\"viewer-frame\" class=\"viewer\" title=\"3-D viewer\" sandbox=\"allow-scripts\" \
             srcdoc=\"{}\"></iframe>\n<p class=\"muted\">Drag to turn, wheel to zoom; the colour field, zebra \
             stripes, control net and offsets are switched in the panel. The same page, full window: \
             <code>{VIEWER_FILE}</code>.</p>\n",
            esc_srcdoc(self.viewer_html)
        )
    }
}

/// The statistics of `sign x value`: a negative sign swaps the extremes and the percentiles.
fn signed(st: &FieldStats, sign: f64) -> FieldStats {
    if sign >= 0.0 {
        return *st;
    }
    let neg = |e: analysis::Extreme| analysis::Extreme { value: -e.value, ..e };
    FieldStats {
        min: neg(st.max),
        max: neg(st.min),
        percentiles: [100.0 - st.percentiles[1], 100.0 - st.percentiles[0]],
        low: -st.high,
        high: -st.low,
        average: -st.average,
    }
}

fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

/// The comparison table and its floors.
fn comparison(c: &Comparison) -> String {
    let u = c.input.units;
    let mut s = format!(
        "<p>Every method at the same control points {} × {} (interpolation: one per offset), degrees {} and {}, \
         parameterization {}, seed {}. Errors are true closest-point distances; the parametric RMS is what the \
         optimisers minimise. Times are left out (they vary from run to run).</p>\n",
        c.control_points[0],
        c.control_points[1],
        c.degree[0],
        c.degree[1],
        esc(c.parameterization),
        c.seed
    );
    let head = vec![
        th_key("Method"),
        th_key("Status"),
        th("Control points", None),
        th("Max", Some(u)),
        th("Mean", Some(u)),
        th("RMS", Some(u)),
        th("Parametric RMS", Some(u)),
        th("Min K", Some(&format!("1/{u}²"))),
        th("Max K", Some(&format!("1/{u}²"))),
        th("Iterations", None),
        th("Evaluations", None),
        th_key("Validity"),
    ];
    // Interpolation's error is round-off by construction (with its own count): not a contender.
    let best = c
        .methods
        .iter()
        .filter(|r| r.method != "interp")
        .filter_map(|r| r.error.map(|e| e.rms))
        .fold(f64::INFINITY, f64::min);
    let rows: Vec<(bool, Vec<String>)> = c
        .methods
        .iter()
        .map(|r| {
            let status = match r.status {
                RowStatus::Done => "done".to_string(),
                RowStatus::Interrupted => "interrupted".into(),
                RowStatus::Failed => format!("failed: {}", r.failure.as_deref().unwrap_or("")),
            };
            let mut cells = vec![
                td_key(r.method),
                td_key(&status),
                format!("<td>{} × {}</td>", r.control_points[0], r.control_points[1]),
            ];
            match r.error {
                Some(e) => cells.extend([td(e.max), td(e.mean), td(e.rms), td(e.parametric_rms)]),
                None => cells.extend((0..4).map(|_| "<td>-</td>".to_string())),
            }
            match r.gaussian_curvature {
                Some(k) => cells.extend([td(k.min), td(k.max)]),
                None => cells.extend((0..2).map(|_| "<td>-</td>".to_string())),
            }
            cells.push(format!("<td>{}</td>", r.iterations));
            cells.push(format!("<td>{}</td>", r.evaluations));
            cells.push(td_key(&r.validity.as_ref().map_or_else(|| "-".to_string(), crate::RowValidity::label)));
            (r.error.is_some_and(|e| e.rms == best && r.method != "interp"), cells)
        })
        .collect();
    s.push_str(&table("comparison-table", "numbers", &head, &rows));
    s.push_str(
        "<p class=\"muted\">Highlighted: the lowest RMS error at these control points (interpolation aside).</p>\n",
    );
    if !c.complete {
        s.push_str(&format!("<p class=\"note\">Interrupted: not run: {}.</p>\n", esc(&c.not_run.join(", "))));
    }
    s.push_str("<h3>Each optimiser against the plain approximation (true RMS error)</h3>\n<ul>\n");
    for f in &c.floors.checks {
        let (class, verdict) = match f.holds {
            Some(true) => ("holds", "holds"),
            Some(false) => ("fails", "fails"),
            None => ("muted", "not checked"),
        };
        let sides = match (f.value, f.bound) {
            (Some(a), Some(b)) => format!(" ({} against {} {u})", num(a), num(b)),
            _ => String::new(),
        };
        s.push_str(&format!("<li>{}: <span class=\"{class}\">{verdict}</span>{sides}</li>\n", esc(&f.floor)));
    }
    s.push_str("</ul>\n");
    s
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::analysis::PlaneSelection;
    use crate::render::Image;
    use crate::viewer::Resolution;
    use nurbs::KnotVector;

    /// Wigley hull: length, beam, draft.
    const L: f64 = 100.0;
    const B: f64 = 10.0;
    const T: f64 = 6.25;

    /// The exact Wigley hull `y = B/2 (1 - (2x/L)²)(1 - ((T - z)/T)²)`, `|x| <= L/2`,
    /// `0 <= z <= T`, as a biquadratic Bézier patch: along x, `1 - (2t - 1)² = 4t(1 - t)` has
    /// Bernstein coefficients (0, 2, 0); along z, `s(2 - s)` has (0, 1, 1). u runs keel to
    /// deck, v aft to fore, as a hullskin fit.
    fn wigley() -> NurbsSurface {
        let k = || KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
        let (cx, cz) = ([0.0, 2.0, 0.0], [0.0, 1.0, 1.0]);
        let mut pts = Vec::new();
        for i in 0..3 {
            for j in 0..3 {
                let (x, z) = (-L / 2.0 + L * j as f64 / 2.0, T * i as f64 / 2.0);
                pts.push(Vec3::new(x, B / 2.0 * cx[j] * cz[i], z));
            }
        }
        NurbsSurface::try_new(k(), k(), &pts, None).expect("valid patch")
    }

    /// Small pictures and grids: the tests check structure, not looks (and run unoptimised).
    fn quick() -> ReportOptions {
        ReportOptions {
            curvature: analysis::CurvatureMapOptions { grid: (16, 16), ..Default::default() },
            fairness: FairnessOptions {
                stations: PlaneSelection::Count(5),
                waterlines: PlaneSelection::Count(3),
                ..FairnessOptions::default()
            },
            curvature_width_px: 400,
            curvature_samples: 40,
            raster: RasterOptions { dpi: 40.0, ..RasterOptions::default() },
            viewer: ViewerOptions {
                resolution: Resolution { per_span: 4, min_long: 20, min_short: 10, max: 100 },
                ..ViewerOptions::default()
            },
            ..ReportOptions::default()
        }
    }

    fn parse(html: &str) -> roxmltree::Document<'_> {
        let opts = roxmltree::ParsingOptions { allow_dtd: true, ..roxmltree::ParsingOptions::default() };
        roxmltree::Document::parse_with_options(html, opts).expect("the page is well-formed XML")
    }

    fn by_id<'a, 'i>(doc: &'a roxmltree::Document<'i>, id: &str) -> Option<roxmltree::Node<'a, 'i>> {
        doc.descendants().find(|n| n.attribute("id") == Some(id))
    }

    /// The `data-value`s of column `col` of a table's body.
    fn column(table: roxmltree::Node<'_, '_>, col: usize) -> Vec<f64> {
        table
            .descendants()
            .filter(|n| n.has_tag_name("tr") && n.ancestors().any(|a| a.has_tag_name("tbody")))
            .map(|tr| {
                let td = tr.children().filter(|c| c.has_tag_name("td")).nth(col).expect("cell");
                td.attribute("data-value").expect("a number cell").parse().expect("a number")
            })
            .collect()
    }

    fn unbase64(s: &str) -> Vec<u8> {
        base64::Engine::decode(&base64::engine::general_purpose::STANDARD, s).expect("base64")
    }

    /// The distinct `http(s)://` URLs of a page, sorted.
    pub(crate) fn urls(html: &str) -> Vec<&str> {
        let mut out: Vec<&str> = html
            .match_indices("http")
            .map(|(k, _)| &html[k..])
            .filter(|rest| rest.starts_with("http://") || rest.starts_with("https://"))
            .map(|rest| &rest[..rest.find(|c: char| "\"'&<> )".contains(c)).unwrap_or(rest.len())])
            .collect();
        out.sort_unstable();
        out.dedup();
        out
    }

    #[test]
    fn wigley_report_has_every_section_and_the_closed_form_coefficients() {
        let s = wigley();
        let inputs = ReportInputs { draft: Some(T), ..ReportInputs::new(&s, Units::Metre, "Wigley (exact)") };
        let r = build_report(&inputs, &quick()).expect("report");
        let doc = parse(&r.html);
        for id in ["particulars", "fit-error", "hydrostatics", "curvature", "lines-plan", "curvature-maps", "viewer"] {
            assert!(by_id(&doc, id).is_some_and(|n| n.has_tag_name("section")), "section {id}");
        }
        // No fit, no optimisation, no comparison: no convergence or comparison section.
        assert!(by_id(&doc, "convergence").is_none() && by_id(&doc, "comparison").is_none());
        assert!(r.convergence_png.is_none() && r.error.is_none());
        assert!(r.html.contains("No offsets were given"));

        // Wigley at its design draft: CB = 4/9, CM = CP = CW = 2/3 (closed forms; the hydrostatics
        // of the exact patch are within 2e-13 relative of them, so 1e-12 is round-off).
        let table = by_id(&doc, "hydrostatics-table").expect("hydrostatics table");
        let col = |key: &str| {
            let shown = r.hydrostatics.shown_columns();
            let k = shown.iter().position(|&c| HYDROSTATICS_COLUMNS[c].0 == key).expect("a column");
            column(table, k)
        };
        assert_eq!(col("draft"), vec![T]);
        for (key, want) in [("cb", 4.0 / 9.0), ("cm", 2.0 / 3.0), ("cp", 2.0 / 3.0), ("cw", 2.0 / 3.0)] {
            let got = col(key)[0];
            assert!((got - want).abs() <= 1e-12, "{key}: {got} against {want}");
        }
        // Volume 4/9 L B T, the same bits as the table returned.
        assert_eq!(col("vol"), vec![r.hydrostatics.rows[0].vol]);
        assert!((r.hydrostatics.rows[0].vol / (L * B * T) - 4.0 / 9.0).abs() <= 1e-12);
        assert_eq!(r.drafts, DraftChoice::Design(T));

        // The inline drawing is lines.svg without its XML declaration.
        let svg_at = r.html.find("<svg").expect("inline svg");
        let svg_end = r.html[svg_at..].find("</svg>").expect("closed") + svg_at + "</svg>".len();
        let file = &r.lines_svg[r.lines_svg.find("<svg").expect("svg element")..];
        assert_eq!(&r.html[svg_at..svg_end], file.trim_end());

        // The frame holds the viewer page exactly.
        let frame = by_id(&doc, "viewer-frame").expect("iframe");
        assert_eq!(frame.attribute("srcdoc"), Some(r.viewer_html.as_str()));

        // The pictures are the PNG files, of the size the tags say.
        for (id, png) in [("map-gaussian", &r.curvature_gaussian_png), ("map-mean", &r.curvature_mean_png)] {
            let img = by_id(&doc, id).expect("img");
            let src = img.attribute("src").expect("src");
            let bytes = unbase64(src.strip_prefix("data:image/png;base64,").expect("a PNG data URI"));
            assert_eq!(&bytes, png);
            let image = Image::from_png(&bytes).expect("decodes");
            assert_eq!(image.width().to_string(), img.attribute("width").expect("width"));
            assert_eq!(image.height().to_string(), img.attribute("height").expect("height"));
            assert_eq!(image.width(), 400);
        }
        // Nothing to load: every URL on the page (the viewer's frame included) is a namespace name.
        assert_eq!(urls(&r.html), vec!["http://www.w3.org/1999/xhtml", "http://www.w3.org/2000/svg"]);
    }

    #[test]
    fn without_a_draft_the_table_climbs_to_the_top_in_ten_steps() {
        let s = wigley();
        let r = build_report(&ReportInputs::new(&s, Units::Metre, "Wigley"), &quick()).expect("report");
        let drafts: Vec<f64> = r.hydrostatics.rows.iter().map(|row| row.draft).collect();
        assert_eq!(drafts.len(), 10);
        assert_eq!(drafts[9], T);
        for (k, t) in drafts.iter().enumerate() {
            // k T / 10: one rounding of the product and quotient.
            assert!((t - T * (k + 1) as f64 / 10.0).abs() <= 1e-14, "{drafts:?}");
        }
        assert!(matches!(r.drafts, DraftChoice::Range { count: 10, limit: "the top of the surface", .. }));
        assert!(r.html.contains("No design draft given: 10 drafts"));
        // Volume grows with the draft.
        assert!(r.hydrostatics.rows.windows(2).all(|w| w[1].vol > w[0].vol));
    }

    #[test]
    fn bad_drafts_are_errors() {
        let s = wigley();
        for t in [0.0, -1.0, T * 1.01, f64::NAN] {
            let inputs = ReportInputs { draft: Some(t), ..ReportInputs::new(&s, Units::Metre, "Wigley") };
            let err = build_report(&inputs, &quick()).expect_err("a bad draft");
            assert!(matches!(err, HullError::Draft { .. }), "{t}: {err}");
        }
        let options = ReportOptions { density: 0.0, ..quick() };
        assert!(matches!(build_report(&ReportInputs::new(&s, Units::Metre, "W"), &options), Err(HullError::Config(_))));
    }

    /// The quarter cylinder of radius `r` bending from the keel (y 0, z 0) to the deck edge
    /// (y r, z r) about the axis (y 0, z r), 10 long, as a rational quadratic arc (weights 1,
    /// sqrt(2)/2, 1) swept along x: `K = 0`, `|H| = 1/(2r)` everywhere, convex.
    fn bilge(r: f64) -> NurbsSurface {
        let ku = KnotVector::try_new(2, vec![0.0, 0.0, 0.0, 1.0, 1.0, 1.0]).expect("valid");
        let kv = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("valid");
        let arc = [(0.0, 0.0), (r, 0.0), (r, r)];
        let w = std::f64::consts::FRAC_1_SQRT_2;
        let mut pts = Vec::new();
        let mut weights = Vec::new();
        for (i, (y, z)) in arc.iter().enumerate() {
            for x in [0.0, 10.0] {
                pts.push(Vec3::new(x, *y, *z));
                weights.push(if i == 1 { w } else { 1.0 });
            }
        }
        NurbsSurface::try_new(ku, kv, &pts, Some(&weights)).expect("valid arc surface")
    }

    #[test]
    fn mean_curvature_is_positive_on_a_convex_bilge_whatever_the_orientation() {
        let r = 2.0;
        let s = bilge(r);
        for (name, surface) in [("u along the arc", s.clone()), ("transposed", s.transposed())] {
            let map = analysis::curvature_map(
                &surface,
                &analysis::CurvatureMapOptions { grid: (8, 8), ..Default::default() },
            );
            let st = map.summary().mean.expect("regular nodes");
            let h = signed(&st, convex_sign(&map));
            // An exact rational circle: H = 1/(2r) to round-off of the rational derivatives.
            for v in [h.min.value, h.max.value, h.low, h.high, h.average] {
                assert!((v - 0.5 / r).abs() <= 1e-9, "{name}: {v}");
            }
        }
    }

    #[test]
    fn the_same_inputs_give_the_same_bytes() {
        let s = wigley();
        let inputs = ReportInputs { draft: Some(0.5 * T), ..ReportInputs::new(&s, Units::Foot, "Wigley") };
        let a = build_report(&inputs, &quick()).expect("report");
        let b = build_report(&inputs, &quick()).expect("report");
        assert_eq!(a.files(), b.files());
        assert!(a.html.contains("Lengths in feet (ft)"));
    }

    #[test]
    fn a_fitted_sample_shows_its_error_comparison_and_convergence() {
        use crate::optimize::{Algorithm, OptimSettings};
        use crate::{compare_offsets, fit_offsets, series60_sample, CompareConfig, FitConfig, FitMethod};
        let offsets = series60_sample();
        // A few iterations: the test reads the tables, not the optimum.
        let optim = OptimSettings { iterations: Some(3), population: Some(6), ..OptimSettings::default() };
        let cfg = FitConfig { method: FitMethod::Optimized(Algorithm::Ga), optim, ..FitConfig::default() };
        let fit = fit_offsets(&offsets, &cfg).expect("the sample fits");
        let comparison = compare_offsets(&offsets, &CompareConfig { optim, ..CompareConfig::default() }).expect("runs");
        let inputs = ReportInputs {
            offsets: Some(&offsets),
            fit: Some(&fit),
            comparison: Some(&comparison),
            draft: Some(6.5),
            ..ReportInputs::new(&fit.surface, offsets.units, offsets.source.clone())
        };
        let r = build_report(&inputs, &quick()).expect("report");
        let doc = parse(&r.html);

        // The error table: one row per station, the worst one highlighted, the fit's numbers.
        let sections = by_id(&doc, "error-sections").expect("per-section table");
        let maxima = column(sections, 3);
        assert_eq!(maxima, fit.error.per_section.iter().map(|s| s.stats.max).collect::<Vec<_>>());
        let worst: Vec<usize> = sections
            .descendants()
            .filter(|n| n.has_tag_name("tr") && n.ancestors().any(|a| a.has_tag_name("tbody")))
            .enumerate()
            .filter(|(_, tr)| tr.attribute("class") == Some("mark"))
            .map(|(k, _)| k)
            .collect();
        let largest = maxima.iter().copied().fold(0.0, f64::max);
        assert_eq!(worst.len(), 1);
        assert_eq!(maxima[worst[0]], largest);
        assert_eq!(largest, fit.error.overall.max);

        // The comparison: every method, its true RMS error as compare.json has it.
        let table = by_id(&doc, "comparison-table").expect("comparison table");
        let rms = column(table, 5);
        let want: Vec<f64> = comparison.methods.iter().map(|m| m.error.expect("done").rms).collect();
        assert_eq!(rms, want);
        assert_eq!(rms.len(), crate::COMPARE_METHODS.len() + crate::FAIR_ROWS.len());

        // The convergence plot of the GA run: a PNG with more than the background's colour.
        assert!(by_id(&doc, "convergence").is_some());
        let png = r.convergence_png.as_ref().expect("convergence.png");
        let image = Image::from_png(png).expect("decodes");
        let distinct: std::collections::HashSet<&[u8]> = image.rgba().chunks_exact(4).collect();
        assert!(distinct.len() > 10, "{} colours", distinct.len());
        // Offsets were given: the viewer has the error field and the lines plan the markers.
        assert!(r.viewer_html.contains("Distance to the offsets"));
        assert!(r.lines_svg.contains("id=\"offsets\""));
    }
}
