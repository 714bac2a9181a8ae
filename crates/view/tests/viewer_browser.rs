//! The 3-D viewer page opened in a real browser: headless Chromium loads the page written for
//! the built-in Series 60 hull, and we read back what it did (the DOM it left, a screenshot).
//!
//! Chromium is found and run by `common::browser` (`HULLSKIN_CHROMIUM`, `/usr/bin/chromium` or
//! `tools/setup-chromium.sh`; the tests fail without one unless `HULLSKIN_SKIP_BROWSER=1`).
//! WebGL runs without a GPU on SwiftShader. Set `HULLSKIN_VIEWER_OUT=<dir>` to keep the page
//! and the screenshots there.

mod common;

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use common::browser::{keep, run_chromium};
use hull::diverging_stops;
use view::{write_viewer_html, ViewerOptions};

/// Window size of every screenshot, CSS pixels (device scale factor 1).
const WIDTH: u32 = 1280;
const HEIGHT: u32 = 800;
/// The page's background colour (`scene.background` in viewer.js, `body` in viewer.css).
const BACKGROUND: [u8; 3] = [0xe9, 0xed, 0xf2];

/// The sample hull fitted by the default method.
fn sample_surface() -> &'static (nurbs::NurbsSurface, hull::Offsets) {
    static FIT: OnceLock<(nurbs::NurbsSurface, hull::Offsets)> = OnceLock::new();
    FIT.get_or_init(|| {
        let offsets = hull::series60_sample();
        let surface = hull::fit_offsets(&offsets, &hull::FitConfig::default()).expect("the sample fits").surface;
        (surface, offsets)
    })
}

/// Write the viewer page of `surface` to `dir/name.html` with `write_atomic`.
fn write_page(dir: &Path, name: &str, surface: &nurbs::NurbsSurface) -> PathBuf {
    let offsets = &sample_surface().1;
    let options = ViewerOptions {
        title: "Series 60, Cb 0.60 (built-in sample)".into(),
        notes: vec![("Lpp".into(), format!("{} m", hull::SAMPLE_PARTICULARS.lpp))],
        ..ViewerOptions::default()
    };
    let path = dir.join(format!("{name}.html"));
    hull::write_atomic(&path, |w| write_viewer_html(w, surface, Some(offsets), offsets.units, &options))
        .expect("write the page");
    eprintln!("{name}.html: {} bytes", std::fs::metadata(&path).expect("written").len());
    keep(&path);
    path
}

/// The viewer page of the built-in sample hull, written once into a directory that lives as
/// long as the test binary.
fn sample_page() -> &'static Path {
    static PAGE: OnceLock<(tempfile::TempDir, PathBuf)> = OnceLock::new();
    let (_, path) = PAGE.get_or_init(|| {
        let dir = tempfile::tempdir().expect("temp dir");
        let path = write_page(dir.path(), "viewer", &sample_surface().0);
        (dir, path)
    });
    path
}

/// The attributes of the page's `<output id="status" ...>` element in a DOM dump.
fn status_attributes(dom: &str) -> Vec<(String, String)> {
    let start = dom.find("<output id=\"status\"").unwrap_or_else(|| panic!("no status element in the DOM:\n{dom}"));
    let tag = &dom[start..start + dom[start..].find('>').expect("tag closed")];
    let mut attrs = Vec::new();
    let mut rest = tag;
    while let Some(eq) = rest.find("=\"") {
        let name = rest[..eq].rsplit(' ').next().unwrap_or_default().to_string();
        let value_end = rest[eq + 2..].find('"').expect("attribute closed");
        attrs.push((name, rest[eq + 2..eq + 2 + value_end].to_string()));
        rest = &rest[eq + 2 + value_end + 1..];
    }
    attrs
}

fn attr<'a>(attrs: &'a [(String, String)], name: &str) -> &'a str {
    attrs.iter().find(|(n, _)| n == name).map(|(_, v)| v.as_str()).unwrap_or_else(|| panic!("no {name} in {attrs:?}"))
}

/// Take a screenshot of the sample page with `hash` and decode it to RGB rows.
fn screenshot(name: &str, hash: &str) -> (u32, u32, Vec<[u8; 3]>) {
    screenshot_of(sample_page(), name, hash)
}

fn screenshot_of(page: &Path, name: &str, hash: &str) -> (u32, u32, Vec<[u8; 3]>) {
    let (shot, _) = common::browser::screenshot(page, name, hash, [WIDTH, HEIGHT], &[]);
    (shot.width, shot.height, shot.px)
}

fn is_background(p: [u8; 3]) -> bool {
    p.iter().zip(BACKGROUND).all(|(&a, b)| (a as i32 - b as i32).abs() <= 3)
}

/// Pixel statistics of a screenshot: the share of non-background pixels and their bounding box
/// (x0, y0, x1, y1) as fractions of the picture.
fn coverage(w: u32, h: u32, px: &[[u8; 3]]) -> (f64, [f64; 4]) {
    let (mut n, mut bb) = (0usize, [u32::MAX, u32::MAX, 0, 0]);
    for (k, &p) in px.iter().enumerate() {
        if !is_background(p) {
            let (x, y) = (k as u32 % w, k as u32 / w);
            n += 1;
            bb = [bb[0].min(x), bb[1].min(y), bb[2].max(x), bb[3].max(y)];
        }
    }
    let (wf, hf) = (w as f64, h as f64);
    (n as f64 / px.len() as f64, [bb[0] as f64 / wf, bb[1] as f64 / hf, bb[2] as f64 / wf, bb[3] as f64 / hf])
}

fn hex(s: &str) -> [u8; 3] {
    let n = u32::from_str_radix(s.trim_start_matches('#'), 16).expect("hex colour");
    [(n >> 16) as u8, (n >> 8) as u8, n as u8]
}

/// The page loads with no error or warning, draws both halves of the grid, loads nothing, and
/// the hull it shows spans the full beam (the mirror) and the hull's length and depth.
#[test]
#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]
fn viewer_loads_without_errors_and_draws_the_mirrored_hull() {
    let page = sample_page();
    let dom = run_chromium(page, "", [WIDTH, HEIGHT], &["--dump-dom".into()]).stdout;
    let a = status_attributes(&dom);
    let errors = dom.find("<pre id=\"errors\"").map(|k| &dom[k..k + dom[k..].find("</pre>").unwrap_or(0)]);
    assert_eq!(attr(&a, "data-state"), "ok", "the page reported errors: {errors:?}\n{a:?}");
    assert_eq!(attr(&a, "data-errors"), "0");
    assert_eq!(attr(&a, "data-warnings"), "0", "three.js warned: {a:?}");
    assert_eq!(attr(&a, "data-resources"), "0", "the page loaded something from outside");
    assert_eq!(attr(&a, "data-field"), "gaussian");

    let html = std::fs::read_to_string(page).expect("page");
    let start = html.find("id=\"hull-data\">").expect("data block") + "id=\"hull-data\">".len();
    let data: serde_json::Value =
        serde_json::from_str(&html[start..start + html[start..].find("</script>").expect("closed")]).expect("JSON");
    let (nu, nv) = (data["grid"]["nu"].as_u64().expect("nu"), data["grid"]["nv"].as_u64().expect("nv"));
    assert_eq!(attr(&a, "data-vertices").parse::<u64>().expect("number"), nu * nv);
    // Two halves of 2 (nu - 1)(nv - 1) triangles each, drawn in the first frame.
    assert_eq!(attr(&a, "data-triangles").parse::<u64>().expect("number"), 4 * (nu - 1) * (nv - 1));

    // The world box of what is drawn: symmetric in y (the mirror), as long and deep as the
    // sample (Lpp 121.92 m, half-breadth 8.13 m, depth of the data 9.75 m), within 3 %: the
    // fit's own error and its ends beyond the perpendiculars.
    let b: Vec<f64> = attr(&a, "data-box").split(' ').map(|s| s.parse().expect("number")).collect();
    assert_eq!(b.len(), 6);
    assert!((b[1] + b[4]).abs() < 1e-3, "not symmetric in y: {b:?}");
    let bounds = hull::series60_sample().bounds().expect("points");
    let size = bounds.1 - bounds.0;
    for (axis, shown, data) in [("x", b[3] - b[0], size.x), ("y", b[4], bounds.1.y), ("z", b[5] - b[2], size.z)] {
        assert!((shown - data).abs() <= 0.03 * data, "{axis}: shown {shown}, offsets {data}");
    }
    // The first view: from the bow quarter (forward of the bow, to starboard) and above the
    // hull's top (not up from below the keel), looking down.
    let c: Vec<f64> = attr(&a, "data-camera").split(' ').map(|s| s.parse().expect("number")).collect();
    assert_eq!(c.len(), 6);
    let (eye, target) = ([c[0], c[1], c[2]], [c[3], c[4], c[5]]);
    assert!(eye[0] > b[3] && eye[1] > b[4] && eye[2] > b[5] && eye[2] > target[2], "camera at {eye:?}, box {b:?}");
}

/// The default view (panels hidden): the hull fills a sensible part of the picture, in the
/// middle, in both ends of the diverging map (K < 0 and K > 0 both occur on the hull).
#[test]
#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]
fn screenshot_shows_the_hull_coloured_by_curvature() {
    let (w, h, px) = screenshot("gaussian", "bare=1&offsets=0");
    assert_eq!((w, h), (WIDTH, HEIGHT));
    let (share, bb) = coverage(w, h, &px);
    eprintln!("gaussian: {:.1} % of the picture, box {bb:.3?}", 100.0 * share);
    // A long slender hull seen three-quarters: well under the whole picture, well over a speck.
    assert!((0.12..0.7).contains(&share), "hull covers {share}");
    // Framed (viewer.js `frame`): the hull's vertices fill FILL = 86 % of the width or the height,
    // whichever binds, centred. Pixels add a little: antialiased edges, every other vertex used.
    let fill = (bb[2] - bb[0]).max(bb[3] - bb[1]);
    assert!((fill - 0.86).abs() < 0.03, "hull fills {fill} of the picture: {bb:?}");
    let (cx, cy) = (0.5 * (bb[0] + bb[2]), 0.5 * (bb[1] + bb[3]));
    assert!((cx - 0.5).abs() < 0.02 && (cy - 0.5).abs() < 0.02, "hull off centre: {bb:?}");

    // Colours: blue-ish (K < 0) and red-ish (K > 0) pixels, each a real share of the hull, and
    // many distinct colours (shading times the map).
    let hull: Vec<[u8; 3]> = px.iter().copied().filter(|&p| !is_background(p)).collect();
    let blue = hull.iter().filter(|p| p[2] as i32 > p[0] as i32 + 40).count() as f64 / hull.len() as f64;
    let red = hull.iter().filter(|p| p[0] as i32 > p[2] as i32 + 40).count() as f64 / hull.len() as f64;
    eprintln!("gaussian: blue {:.1} %, red {:.1} %", 100.0 * blue, 100.0 * red);
    // From above the bow quarter the hull's hollows (K < 0: the forefoot, the run) show less
    // than its bilges: measured 0.9 % and 2.1 %.
    assert!(blue > 0.005 && red > 0.01, "blue {blue}, red {red}");
    let mut distinct: Vec<[u8; 3]> = hull.iter().map(|p| [p[0] >> 3, p[1] >> 3, p[2] >> 3]).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert!(distinct.len() > 100, "only {} distinct colours", distinct.len());
}

/// Zebra stripes: the hull is drawn in dark and light bands, both a large share of it.
#[test]
#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]
fn screenshot_shows_zebra_stripes() {
    let (w, h, px) = screenshot("zebra", "bare=1&zebra=1&offsets=0");
    let (share, _) = coverage(w, h, &px);
    let hull: Vec<[u8; 3]> = px.iter().copied().filter(|&p| !is_background(p)).collect();
    let lum = |p: &[u8; 3]| (p[0] as u32 + p[1] as u32 + p[2] as u32) / 3;
    let dark = hull.iter().filter(|p| lum(p) < 70).count() as f64 / hull.len() as f64;
    let light = hull.iter().filter(|p| lum(p) > 170).count() as f64 / hull.len() as f64;
    eprintln!("zebra: {:.1} % of the picture, dark {:.1} %, light {:.1} %", 100.0 * share, 100.0 * dark, 100.0 * light);
    assert!(share > 0.12, "hull covers {share}");
    // Half the environment is dark and half light; shading and the stripes' blur move it.
    assert!(dark > 0.2 && light > 0.2, "dark {dark}, light {light}");
    // Grey, not coloured: no pixel of the hull far from grey.
    let coloured = hull.iter().filter(|p| p.iter().max().unwrap_or(&0) - p.iter().min().unwrap_or(&0) > 40).count();
    assert!((coloured as f64) < 0.02 * hull.len() as f64, "{coloured} coloured pixels");
}

/// The full page with its side panel: the legend's colour bar shows the diverging stops, its ends
/// at the outer stops' colours.
#[test]
#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]
fn screenshot_shows_the_legend() {
    let (w, _, px) = screenshot("page", "");
    let stops: Vec<[u8; 3]> = diverging_stops().iter().map(|s| hex(s)).collect();
    // The legend sits in the side panel, the right-most 290 px; look for the outer stops there.
    let near = |p: [u8; 3], c: [u8; 3]| p.iter().zip(c).all(|(&a, b)| (a as i32 - b as i32).abs() <= 4);
    let corner = |c: [u8; 3]| px.iter().enumerate().filter(|&(k, &p)| (k as u32 % w) >= w - 290 && near(p, c)).count();
    let (lo, hi) = (corner(stops[0]), corner(stops[4]));
    eprintln!("legend: {lo} pixels of the low stop, {hi} of the high stop");
    // The bar is 14 px high; its ends show each outer stop over a few pixels' width.
    assert!(lo >= 14 && hi >= 14, "legend bar ends not found: {lo}, {hi}");
}

/// The same hull with u and v swapped (so the other normal orientation, `S_v x S_u`, and the
/// other triangle winding) gives the same picture: the page shades the outward side whichever
/// way the surface runs. A wrong winding would shade the near side as seen from inside (dark).
#[test]
#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]
fn transposed_surface_gives_the_same_picture() {
    let dir = tempfile::tempdir().expect("temp dir");
    let plain = write_page(dir.path(), "plain", &sample_surface().0);
    let transposed = write_page(dir.path(), "transposed", &sample_surface().0.transposed());
    let hash = "bare=1&field=none&offsets=0";
    let (w, h, a) = screenshot_of(&plain, "plain", hash);
    let (_, _, b) = screenshot_of(&transposed, "transposed", hash);
    assert_eq!(a.len(), b.len());
    let differ = a.iter().zip(&b).filter(|(p, q)| p.iter().zip(q.iter()).any(|(&x, &y)| x.abs_diff(y) > 24)).count();
    let (share, _) = coverage(w, h, &a);
    eprintln!("transposed: {differ} of {} pixels differ, hull {:.1} %", a.len(), 100.0 * share);
    // Same vertices and the same cell diagonals: only rounding differs (f32 sums in another
    // order, antialiasing) and, seen from above, the depth ties where the two halves meet at
    // the stem and along the flat of keel seen through the open deck (measured 0.46 % of the
    // picture); a flipped side would change most of the hull (18 % of the picture).
    assert!((differ as f64) < 0.008 * a.len() as f64, "{differ} pixels differ");
    assert!(share > 0.12, "hull covers {share}");
}
