//! `hullskin report` end to end: the page is read back as XML and compared with the files it
//! is made of (the inline lines plan with lines.svg, the pictures with the PNG files, the frame
//! with viewer.html, the hydrostatics with hydrostatics.json and .csv); nothing is loaded from
//! the network; the same run gives the same bytes; bad inputs fail with a message.

use std::collections::HashSet;
use std::fs;
use std::path::{Path, PathBuf};

use tempfile::TempDir;

use crate::common::*;
use crate::page::{unbase64, urls};
use view::Image;

/// The issue's floor on the size of one hull's report.
const MAX_REPORT_BYTES: u64 = 5_000_000;

/// Every file of a report of a fit that was not optimised.
const FILES: [&str; 10] = [
    "report.html",
    "viewer.html",
    "lines.svg",
    "lines.dxf",
    "lines3d.dxf",
    "lines.png",
    "curvature_gaussian.png",
    "curvature_mean.png",
    "hydrostatics.csv",
    "hydrostatics.json",
];

/// A fresh directory under Cargo's temporary directory for integration tests, of its own
/// (nextest runs each test in a process of its own: a directory shared between them was
/// wiped by one while another wrote into it), removed when the test drops it.
fn scratch(name: &str) -> TempDir {
    tempfile::Builder::new()
        .prefix(&format!("report-{name}-"))
        .tempdir_in(env!("CARGO_TARGET_TMPDIR"))
        .expect("scratch dir")
}

/// Run `hullskin report` in `dir` and require success; returns stdout.
fn report_ok(dir: &Path, args: &[&str]) -> String {
    let mut all = vec!["report"];
    all.extend_from_slice(args);
    let o = hullskin(dir, &all);
    let (out, err) = text(&o);
    assert!(o.status.success(), "hullskin {all:?}\nstdout {out}\nstderr {err}");
    out
}

/// The built-in sample's report (`hullskin report -o R`), in a scratch directory of its own.
struct Sample {
    /// Removed with the sample.
    scratch: TempDir,
    stdout: String,
}

impl Sample {
    fn run() -> Self {
        let scratch = scratch("sample");
        let stdout = report_ok(scratch.path(), &["-o", "R"]);
        Sample { scratch, stdout }
    }

    /// The report's directory.
    fn dir(&self) -> PathBuf {
        self.scratch.path().join("R")
    }
}

fn read(dir: &Path, name: &str) -> Vec<u8> {
    fs::read(dir.join(name)).unwrap_or_else(|e| panic!("{}: {e}", dir.join(name).display()))
}

fn read_text(dir: &Path, name: &str) -> String {
    String::from_utf8(read(dir, name)).expect("UTF-8")
}

/// The page as XML (it is polyglot XHTML5).
fn parse(html: &str) -> roxmltree::Document<'_> {
    let opts = roxmltree::ParsingOptions { allow_dtd: true, ..roxmltree::ParsingOptions::default() };
    roxmltree::Document::parse_with_options(html, opts).expect("report.html is well-formed XML")
}

fn by_id<'a, 'i>(doc: &'a roxmltree::Document<'i>, id: &str) -> Option<roxmltree::Node<'a, 'i>> {
    doc.descendants().find(|n| n.attribute("id") == Some(id))
}

/// The `data-value` strings of column `col` of a table's body rows.
fn column<'a>(table: roxmltree::Node<'a, '_>, col: usize) -> Vec<&'a str> {
    table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.ancestors().any(|a| a.has_tag_name("tbody")))
        .map(|tr| {
            let td = tr.children().filter(|c| c.has_tag_name("td")).nth(col).expect("cell");
            td.attribute("data-value").expect("a number cell")
        })
        .collect()
}

/// The PNG of an `<img>` with a `data:` URI, checked against its width and height attributes.
fn inline_png(doc: &roxmltree::Document<'_>, id: &str) -> (Vec<u8>, Image) {
    let img = by_id(doc, id).unwrap_or_else(|| panic!("no #{id}"));
    assert!(img.has_tag_name("img"), "#{id} is an img");
    let src = img.attribute("src").expect("src");
    let bytes = unbase64(src.strip_prefix("data:image/png;base64,").expect("a PNG data URI"));
    let image = Image::from_png(&bytes).expect("the data URI is a PNG");
    assert_eq!(img.attribute("width"), Some(image.width().to_string().as_str()), "#{id}");
    assert_eq!(img.attribute("height"), Some(image.height().to_string().as_str()), "#{id}");
    (bytes, image)
}

/// The PNG data of a curvature map: many colours, and both ends of the diverging map (blue
/// below zero, red above) on a hull whose curvature takes both signs.
fn check_curvature_picture(name: &str, image: &Image) {
    let pixels: Vec<&[u8]> = image.rgba().chunks_exact(4).collect();
    let distinct: HashSet<&[u8]> = pixels.iter().copied().collect();
    assert!(distinct.len() > 200, "{name}: {} colours", distinct.len());
    // Warm (red over blue) and cold (blue over red) tints; the grey of the text and the white
    // of the background and of zero curvature are neither.
    let reddish = pixels.iter().filter(|p| i32::from(p[0]) - i32::from(p[2]) > 40).count();
    let bluish = pixels.iter().filter(|p| i32::from(p[2]) - i32::from(p[0]) > 40).count();
    // At least 0.5 % of the pixels each way. The sample has K 3.2 % warm, 1.6 % cold, H 7.7 %
    // warm (convex), 0.9 % cold (the hollows at the ends); most of the hull is near zero and
    // white, as is the background.
    let floor = pixels.len() / 200;
    assert!(reddish > floor && bluish > floor, "{name}: red {reddish}, blue {bluish} of {}", pixels.len());
}

#[test]
fn the_sample_report_is_one_self_contained_page() {
    let sample = Sample::run();
    let (dir, stdout) = (&sample.dir(), &sample.stdout);
    for f in FILES {
        assert!(stdout.contains(f), "stdout names {f}:\n{stdout}");
    }
    assert!(!dir.join("convergence.png").exists(), "no convergence plot without optimisation");
    let html = read_text(dir, "report.html");
    let size = html.len() as u64;
    assert!(size < MAX_REPORT_BYTES, "report.html is {size} bytes");
    let doc = parse(&html);
    for id in ["particulars", "fit-error", "hydrostatics", "curvature", "lines-plan", "curvature-maps", "viewer"] {
        assert!(by_id(&doc, id).is_some_and(|n| n.has_tag_name("section")), "section #{id}");
    }
    assert!(by_id(&doc, "comparison").is_none() && by_id(&doc, "convergence").is_none());

    // Nothing to load: the only URLs are the XHTML and SVG namespace names (three.js names the
    // XHTML one too), no src or href leaves the page.
    assert_eq!(urls(&html), ["http://www.w3.org/1999/xhtml", "http://www.w3.org/2000/svg"]);
    for n in doc.descendants() {
        for a in ["src", "href"] {
            if let Some(v) = n.attribute(a) {
                assert!(v.starts_with("data:image/png;base64,") || v.starts_with('#'), "{a}={v:.60}");
            }
        }
    }
    assert!(!html.contains("<script"), "no script outside the viewer's frame");

    // The lines plan inline is lines.svg without its XML declaration.
    let svg = read_text(dir, "lines.svg");
    let body = &svg[svg.find("<svg").expect("an svg element")..];
    let start = html.find("<svg").expect("inline svg");
    assert_eq!(&html[start..start + body.trim_end().len()], body.trim_end());

    // The frame shows viewer.html, byte for byte once unescaped.
    let frame = by_id(&doc, "viewer-frame").expect("iframe");
    assert!(frame.has_tag_name("iframe"));
    assert_eq!(frame.attribute("srcdoc").map(str::as_bytes), Some(read(dir, "viewer.html").as_slice()));

    // The curvature pictures are the PNG files.
    for (id, file) in [("map-gaussian", "curvature_gaussian.png"), ("map-mean", "curvature_mean.png")] {
        let (bytes, image) = inline_png(&doc, id);
        assert_eq!(bytes, read(dir, file), "{id} is {file}");
        assert_eq!(image.width(), 1200, "{file}");
        check_curvature_picture(file, &image);
    }

    // The fit error of the default fit of the sample (README, Held-out error: max 0.0941 m, the
    // held-out referee's chord-length parameters held on the surface).
    let table = by_id(&doc, "error-sections").expect("per-section error table");
    let maxima: Vec<f64> = column(table, 3).iter().map(|s| s.parse().expect("number")).collect();
    assert_eq!(maxima.len(), 25);
    let worst = maxima.iter().copied().fold(0.0, f64::max);
    assert!((worst - 0.0941).abs() < 5e-5, "worst section max {worst}");

    // The separate drawings: the sheet chosen for the sample's long low views (an elongated
    // A4x7, 1471 x 297 mm; on A3 a third of the frame would be drawn) at 150 dpi, DXF files
    // with entities.
    let svg = read_text(dir, "lines.svg");
    assert!(svg.contains(r#"width="1471mm" height="297mm""#) && svg.contains(">Sheet A4x7<"), "sheet A4x7");
    let png = Image::from_png(&read(dir, "lines.png")).expect("lines.png decodes");
    let px = |mm: f64| (mm * 150.0 / 25.4).round() as u32;
    assert_eq!((png.width(), png.height()), (px(1471.0), px(297.0)));
    for f in ["lines.dxf", "lines3d.dxf"] {
        let dxf = read_text(dir, f);
        assert!(dxf.contains("ENTITIES") && dxf.trim_end().ends_with("EOF"), "{f}");
        assert!(dxf.matches("POLYLINE").count() > 20, "{f}: the cut curves");
    }
}

#[test]
fn the_hydrostatics_table_is_the_one_in_the_json_and_csv() {
    let sample = Sample::run();
    let dir = &sample.dir();
    let html = read_text(dir, "report.html");
    let doc = parse(&html);
    let table = by_id(&doc, "hydrostatics-table").expect("hydrostatics table");
    let json = read_json(&dir.join("hydrostatics.json"));
    let rows = json["rows"].as_array().expect("rows");
    // No --draft: 10 drafts up to the top of the offsets (the sample's 1.5 T waterline, 9.75 m).
    assert_eq!(rows.len(), 10);
    assert_eq!(rows[9]["draft"], 9.75);
    assert!(html.contains("No design draft given: 10 drafts"));
    let csv = read_text(dir, "hydrostatics.csv");
    let mut lines = csv.lines();
    let header: Vec<&str> = lines.next().expect("header").split(',').collect();
    let csv_rows: Vec<Vec<&str>> = lines.map(|l| l.split(',').collect()).collect();
    for key in ["draft", "vol", "cb", "lcb", "kmt", "cb_lpp"] {
        let col = hull::HYDROSTATICS_COLUMNS.iter().position(|c| c.0 == key).expect("a column");
        let page: Vec<f64> = column(table, col).iter().map(|s| s.parse().expect("number")).collect();
        let from_json: Vec<f64> = rows.iter().map(|r| r[key].as_f64().expect("number")).collect();
        assert_eq!(page, from_json, "{key}");
        // The page's data-value strings are the CSV's cells.
        let k = header.iter().position(|h| *h == key).expect("csv column");
        let from_csv: Vec<&str> = csv_rows.iter().map(|r| r[k]).collect();
        assert_eq!(column(table, col), from_csv, "{key}");
    }
    // Series 60 Cb 0.60 (Todd): CB = Vol / (Lwl Bwl T) near 0.6 at the design draft 6.5 m,
    // which lies between the 6th and 7th draft (5.85 and 6.825 m).
    let cb = |k: usize| rows[k]["cb"].as_f64().expect("cb");
    assert!((0.57..0.63).contains(&cb(5)) && (0.57..0.63).contains(&cb(6)), "{} {}", cb(5), cb(6));
}

#[test]
fn two_runs_give_the_same_bytes() {
    let (first, second) = (Sample::run(), Sample::run());
    for f in FILES {
        assert!(read(&first.dir(), f) == read(&second.dir(), f), "{f} differs between two runs");
    }
}

#[test]
fn an_optimised_fit_adds_the_convergence_plot() {
    let scratch = scratch("ga");
    let dir = scratch.path();
    let out = report_ok(dir, &["-o", "R", "--method", "ga", "--iterations", "5", "--population", "10"]);
    assert!(out.contains("convergence.png"), "{out}");
    let r = dir.join("R");
    let html = read_text(&r, "report.html");
    let doc = parse(&html);
    assert!(by_id(&doc, "convergence").is_some_and(|n| n.has_tag_name("section")));
    let (bytes, image) = inline_png(&doc, "convergence-plot");
    assert_eq!(bytes, read(&r, "convergence.png"));
    // A plot on white: mostly background, with the series' and the axes' colours.
    let distinct: HashSet<&[u8]> = image.rgba().chunks_exact(4).collect();
    assert!(distinct.len() > 10, "{} colours", distinct.len());
    let summary = by_id(&doc, "optimisation-summary").expect("optimisation table");
    let text: String = summary.descendants().filter_map(|n| n.text()).collect();
    assert!(text.contains("ga") && text.contains("seed 1") && text.contains("5 ("), "{text}");
    assert!(html.contains("<code>ga</code>, parameterization"));
}

#[test]
fn a_surface_json_is_reported_as_is() {
    let scratch = scratch("json");
    let dir = scratch.path();
    let o = hullskin(dir, &["fit", "-o", "F"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let fit_report = read_json(&dir.join("F/report.json"));

    // On a sheet given by name (any case): the lines plan is drawn on it.
    report_ok(dir, &["F/surface.json", "--sheet", "a3", "-o", "R"]);
    let html = read_text(&dir.join("R"), "report.html");
    let svg = read_text(&dir.join("R"), "lines.svg");
    assert!(svg.contains(r#"width="420mm" height="297mm""#) && svg.contains(">Sheet A3<"), "sheet A3");
    let o = hullskin(dir, &["report", "F/surface.json", "--sheet", "A7", "-o", "R4"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains(r#"unknown sheet "A7" (expected auto or one of A4, A3,"#), "{:?}", text(&o));
    let doc = parse(&html);
    assert!(html.contains("read from F/surface.json as it is"), "the page says how the input was read");
    assert!(html.contains("No offsets were given"));
    assert!(by_id(&doc, "error-sections").is_none());
    assert!(html.contains("to the top of the surface"));
    let json = read_json(&dir.join("R/hydrostatics.json"));
    assert!(json["source"].as_str().is_some_and(|s| s.contains("surface.json")));
    assert_eq!(json["rows"].as_array().map(Vec::len), Some(10));
    // The comparison needs offsets.
    let o = hullskin(dir, &["report", "F/surface.json", "--compare", "-o", "R3"]);
    assert_eq!(o.status.code(), Some(2));
    assert!(text(&o).1.contains("--compare needs offsets"), "{:?}", text(&o));

    // With the offsets and a design draft: the error is measured again, as the fit measured it.
    let offsets = testdata("series60_cb060_offsets.csv");
    let offsets = offsets.to_str().expect("utf-8 path");
    report_ok(dir, &["F/surface.json", "--offsets", offsets, "--draft", "6.5", "-o", "R2"]);
    let html = read_text(&dir.join("R2"), "report.html");
    let doc = parse(&html);
    let table = by_id(&doc, "error-sections").expect("per-section error table");
    let maxima: Vec<f64> = column(table, 3).iter().map(|s| s.parse().expect("number")).collect();
    let worst = maxima.iter().copied().fold(0.0, f64::max);
    let fitted = fit_report["error"]["max"].as_f64().expect("max");
    // Both find the global closest points; Newton stops within 1e-9 m on this hull.
    assert!((worst - fitted).abs() < 1e-7, "{worst} against the fit's {fitted}");
    let rows = read_json(&dir.join("R2/hydrostatics.json"))["rows"].as_array().expect("rows").clone();
    assert_eq!(rows.len(), 1);
    assert_eq!(rows[0]["draft"], 6.5);
    assert!(html.contains("At the design draft T = 6.500 m."));

    // --json: the summary as JSON on standard output, with the figures of the files.
    let o = hullskin(dir, &["report", "F/surface.json", "--offsets", offsets, "--draft", "6.5", "--json", "-o", "R5"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    let summary: serde_json::Value = serde_json::from_str(&out).unwrap_or_else(|e| panic!("not JSON ({e}): {out}"));
    assert_eq!(summary["source"], "F/surface.json");
    assert_eq!(summary["method"], serde_json::Value::Null, "measured, not fitted");
    let max = summary["error"]["max"].as_f64().expect("max");
    assert!((max - fitted).abs() < 1e-7, "{max} against the fit's {fitted}");
    assert_eq!(summary["hydrostatics"], read_json(&dir.join("R5/hydrostatics.json")));
    let files: Vec<&str> = summary["files"].as_array().expect("files").iter().filter_map(|f| f.as_str()).collect();
    assert!(files.iter().any(|f| f.ends_with("report.html")) && files.len() >= 9, "{files:?}");
}

#[test]
fn compare_adds_the_table_of_every_method() {
    let scratch = scratch("compare");
    let dir = scratch.path();
    report_ok(dir, &["-o", "R", "--compare", "--iterations", "3", "--population", "6", "--draft", "6.5"]);
    let html = read_text(&dir.join("R"), "report.html");
    let doc = parse(&html);
    let table = by_id(&doc, "comparison-table").expect("comparison table");
    let methods: Vec<String> = table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.ancestors().any(|a| a.has_tag_name("tbody")))
        .map(|tr| tr.children().find(|c| c.has_tag_name("td")).and_then(|c| c.text()).unwrap_or("").to_string())
        .collect();
    assert_eq!(methods, ["interp", "approx", "ga", "pso", "gsa", "lm", "gsa+lm", "approx+fair", "lm+fair"]);
    let rms: Vec<f64> = column(table, 5).iter().map(|s| s.parse().expect("number")).collect();
    // Interpolation passes through the offsets; every optimiser starts from the approximation.
    assert!(rms[0] < 1e-8 && rms[1] > 0.01, "{rms:?}");
    // The highlighted rows hold the lowest RMS of the methods at the common control points.
    let marked: Vec<usize> = table
        .descendants()
        .filter(|n| n.has_tag_name("tr") && n.ancestors().any(|a| a.has_tag_name("tbody")))
        .enumerate()
        .filter(|(_, tr)| tr.attribute("class") == Some("mark"))
        .map(|(k, _)| k)
        .collect();
    let best = rms[1..].iter().copied().fold(f64::INFINITY, f64::min);
    assert!(!marked.is_empty() && marked.iter().all(|&k| k > 0 && rms[k] == best), "{marked:?} of {rms:?}");
}

#[test]
fn bad_inputs_exit_with_a_message_naming_the_file() {
    let scratch = scratch("bad");
    let dir = scratch.path();
    fs::write(dir.join("other.json"), "{\"format\": \"other\"}").expect("write");
    fs::write(dir.join("broken.csv"), "section,x,y,z\na,0,0,0\na,0,x1,1\n").expect("write");
    let cases: [(&[&str], &str); 7] = [
        (&["report", "missing.csv", "-o", "R"], "missing.csv"),
        (&["report", "other.json", "-o", "R"], "other.json"),
        (&["report", "broken.csv", "-o", "R"], "broken.csv"),
        (&["report", "-o", "R", "--draft", "100"], "draft 100"),
        (&["report", "-o", "R", "--draft", "-1"], "--draft -1"),
        (&["report", "-o", "R", "--offsets", "x.csv"], "x.csv"),
        (&["report", "other.json", "--compare", "-o", "R"], "other.json"),
    ];
    for (args, needle) in cases {
        let o = hullskin(dir, args);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: stdout {out}\nstderr {err}");
        assert!(err.contains(needle) && err.starts_with("hullskin: error:"), "{args:?}: {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
    }
    // Nothing was written for a failed run.
    assert!(!dir.join("R").join("report.html").exists());
}

/// A folded surface (R/V Gunnerus's forecastle step) is flagged on the page, with its x band,
/// and the sample's page, which does not fold, says nothing of the kind.
#[test]
fn a_folded_surface_is_flagged_on_the_page() {
    let scratch = scratch("folded");
    let dir = scratch.path();
    let input = testdata("gunnerus_offsets.csv");
    // The plain skin at the default count (`--method approx --fair 0`): the default
    // `--fair auto` smooths the fold away.
    let o =
        hullskin(dir, &["report", input.to_str().expect("utf-8 path"), "--method", "approx", "--fair", "0", "-o", "R"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out}\n{err}");
    // The terminal says it too, on standard error.
    assert!(err.lines().any(|l| l.starts_with("hullskin: warning: ") && l.contains("folds back")), "{err}");
    let html = read_text(&dir.join("R"), "report.html");
    let doc = parse(&html);
    let warning = doc
        .descendants()
        .filter_map(|n| n.text())
        .find(|t| t.contains("folds back across the sections"))
        .unwrap_or_else(|| panic!("no fold warning on the page"));
    assert!(warning.contains("between x = 16.5") && warning.contains("centripetal"), "{warning}");
    // Every finding is listed in the validity table of the fit error, the fold among them.
    let kinds: Vec<&str> = doc
        .descendants()
        .find(|n| n.attribute("id") == Some("validity-table"))
        .unwrap_or_else(|| panic!("no validity table"))
        .descendants()
        .filter(|n| n.has_tag_name("td") && n.attribute("class") == Some("key"))
        .filter_map(|n| n.text())
        .filter(|t| t.chars().all(|c| c.is_ascii_lowercase() || c == '_'))
        .collect();
    assert!(kinds.contains(&"fold"), "{kinds:?}");
    let notes = doc
        .descendants()
        .filter(|n| n.has_tag_name("p") && n.text().is_some_and(|t| t.starts_with("Warning: ")))
        .count();
    assert_eq!(notes, kinds.len(), "one warning under the title per finding: {kinds:?}");
    let sample = read_text(&Sample::run().dir(), "report.html");
    assert!(!sample.contains("folds back"));
}
