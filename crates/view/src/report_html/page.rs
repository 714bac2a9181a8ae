//! The page itself: the template filled with its sections, each written from the report's
//! figures (see the module docs of [`super`] for what it holds and in which order).

use nurbs::Vec3;

use super::html::{
    esc, esc_srcdoc, fixed, kv_table, num, png_img, point, table, td, td_html, td_key, td_num, th, th_key,
};
use super::{
    DraftChoice, ReportInputs, CONVERGENCE_PNG_FILE, GAUSSIAN_PNG_FILE, HYDROSTATICS_CSV_FILE, HYDROSTATICS_JSON_FILE,
    LINES_3D_DXF_FILE, LINES_DXF_FILE, LINES_PNG_FILE, LINES_SVG_FILE, MEAN_PNG_FILE, VIEWER_FILE,
};
use crate::drawing::Sheet;
use crate::render;
use hull::{
    format_figure, Comparison, CurvatureField, CurvatureSummary, Extreme, FairnessReport, FieldStats, Finding,
    FitError, HydrostaticsTable, OptimReport, RowStatus, HYDROSTATICS_COLUMNS,
};

const TEMPLATE: &str = include_str!("report.html");
const STYLE: &str = include_str!("report.css");
/// Everything one page shows.
pub(super) struct Page<'p, 'a> {
    pub(super) inputs: &'p ReportInputs<'a>,
    pub(super) extent: (Vec3, Vec3),
    pub(super) hydrostatics: &'p HydrostaticsTable,
    pub(super) drafts: &'p DraftChoice,
    pub(super) curvature: &'p CurvatureSummary,
    pub(super) convex_sign: f64,
    pub(super) fairness: &'p FairnessReport,
    pub(super) error: Option<&'p FitError>,
    pub(super) validity: &'p [Finding],
    pub(super) optimization: Option<&'p OptimReport>,
    pub(super) lines_svg: &'p str,
    /// The lines plan's sheet.
    pub(super) lines_sheet: Sheet,
    pub(super) maps: [(&'p render::CurvatureImage, &'p [u8], &'static str); 2],
    pub(super) convergence: Option<(&'p [u8], u32, u32)>,
    pub(super) viewer_html: &'p str,
}

impl Page<'_, '_> {
    fn u(&self) -> &'static str {
        self.inputs.units.symbol()
    }

    /// The whole page: the template with its markers filled.
    pub(super) fn render(&self) -> String {
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
            let id = format!("map-{}", if field == CurvatureField::Gaussian { "gaussian" } else { "mean" });
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
pub(super) fn signed(st: &FieldStats, sign: f64) -> FieldStats {
    if sign >= 0.0 {
        return *st;
    }
    let neg = |e: Extreme| Extreme { value: -e.value, ..e };
    FieldStats {
        min: neg(st.max),
        max: neg(st.min),
        percentiles: [100.0 - st.percentiles[1], 100.0 - st.percentiles[0]],
        low: -st.high,
        high: -st.low,
        average: -st.average,
    }
}

pub(super) fn capitalise(s: &str) -> String {
    let mut c = s.chars();
    c.next().map_or_else(String::new, |f| f.to_uppercase().chain(c).collect())
}

/// The comparison table and its floors.
pub(super) fn comparison(c: &Comparison) -> String {
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
            cells.push(td_key(&r.validity.as_ref().map_or_else(|| "-".to_string(), hull::RowValidity::label)));
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
