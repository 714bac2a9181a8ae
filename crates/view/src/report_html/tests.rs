use super::page::signed;
use super::*;
use crate::render::Image;
use crate::test_page::{unbase64, urls};
use crate::viewer::Resolution;
use hull::{HullError, PlaneSelection, HYDROSTATICS_COLUMNS};
use nurbs::KnotVector;

/// Wigley hull: length, beam, draft.
const L: f64 = 100.0;
const B: f64 = 10.0;
const T: f64 = 6.25;

/// The exact Wigley hull ([`hull::wigley_hull`], x from the aft end).
fn wigley() -> NurbsSurface {
    hull::wigley_hull(L, B, T)
}

/// Small pictures and grids: the tests check structure, not looks (and run unoptimised).
fn quick() -> ReportOptions {
    ReportOptions {
        curvature: hull::CurvatureMapOptions { grid: (16, 16), ..Default::default() },
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
        // At or below the keel here; not finite or above the deck in the hydrostatics.
        let at_keel = t <= 0.0;
        assert!(
            matches!(err, ViewError::DraftAtKeel { .. } if at_keel)
                || matches!(err, ViewError::Hull(HullError::Draft { .. }) if !at_keel),
            "{t}: {err}"
        );
        assert!(err.to_string().starts_with(&format!("draft {t}: ")), "{err}");
    }
    let options = ReportOptions { density: 0.0, ..quick() };
    let err = build_report(&ReportInputs::new(&s, Units::Metre, "W"), &options).expect_err("density 0");
    assert!(matches!(err, ViewError::Density { density } if density == 0.0), "{err}");
    assert_eq!(err.to_string(), "density 0: expected a positive number in t/m³");
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
        let map = hull::curvature_map(&surface, &hull::CurvatureMapOptions { grid: (8, 8), ..Default::default() });
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
    use hull::{
        compare_offsets, fit_offsets, series60_sample, Algorithm, CompareConfig, FitConfig, FitMethod, OptimSettings,
    };
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
    assert_eq!(rms.len(), hull::COMPARE_METHODS.len() + hull::FAIR_ROWS.len());

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
