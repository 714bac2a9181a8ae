//! The 3-D viewer page opened in a real browser: headless Chromium loads the page written for
//! the built-in Series 60 hull, and we read back what it did (the DOM it left, a screenshot).
//!
//! Chromium comes from `HULLSKIN_CHROMIUM`, else `/usr/bin/chromium`, else
//! `tools/setup-chromium.sh` (Debian's package, installed by the test itself when needed). If
//! none can be had the tests fail (the check cannot vanish silently) unless
//! `HULLSKIN_SKIP_BROWSER=1`. WebGL runs without a GPU on SwiftShader. Set
//! `HULLSKIN_VIEWER_OUT=<dir>` to keep the page and the screenshots there.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

use hull::drawing::colormap::diverging_stops;
use hull::viewer::{write_viewer_html, ViewerOptions};

/// Window size of every screenshot, CSS pixels (device scale factor 1).
const WIDTH: u32 = 1280;
const HEIGHT: u32 = 800;
/// The page's background colour (`scene.background` in viewer.js, `body` in viewer.css).
const BACKGROUND: [u8; 3] = [0xe9, 0xed, 0xf2];
/// How long one browser run may take before the test gives up on it.
const BROWSER_TIMEOUT: Duration = Duration::from_secs(120);

fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The Chromium to run, or `None` if the browser checks are explicitly skipped.
fn chromium() -> Option<PathBuf> {
    static FOUND: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    if let Ok(p) = std::env::var("HULLSKIN_CHROMIUM") {
        if !p.is_empty() {
            return Some(PathBuf::from(p));
        }
    }
    if Path::new("/usr/bin/chromium").exists() {
        return Some(PathBuf::from("/usr/bin/chromium"));
    }
    if std::env::var("HULLSKIN_SKIP_BROWSER").as_deref() == Ok("1") {
        eprintln!("SKIPPED: the viewer in headless Chromium (HULLSKIN_SKIP_BROWSER=1)");
        return None;
    }
    let found = FOUND.get_or_init(|| {
        let script = workspace_root().join("tools/setup-chromium.sh");
        let out =
            Command::new("bash").arg(&script).output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        match stdout.lines().last() {
            Some(p) if out.status.success() => Ok(PathBuf::from(p.trim())),
            _ => Err(format!("{} failed:\n{}", script.display(), String::from_utf8_lossy(&out.stderr))),
        }
    });
    match found {
        Ok(p) => Some(p.clone()),
        Err(e) => panic!(
            "{e}\nThe 3-D viewer is checked in headless Chromium (Debian package chromium). Point \
             HULLSKIN_CHROMIUM at a Chromium, or set HULLSKIN_SKIP_BROWSER=1 to skip the check."
        ),
    }
}

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

/// Copy `file` into `HULLSKIN_VIEWER_OUT` when set.
fn keep(file: &Path) {
    if let Ok(dir) = std::env::var("HULLSKIN_VIEWER_OUT") {
        let dir = PathBuf::from(dir);
        std::fs::create_dir_all(&dir).expect("create HULLSKIN_VIEWER_OUT");
        std::fs::copy(file, dir.join(file.file_name().expect("a file"))).expect("copy to HULLSKIN_VIEWER_OUT");
    }
}

/// Run headless Chromium on `page` with the `#hash` options and `extra` arguments; returns
/// its standard output. Panics (with Chromium's stderr) if it fails or hangs.
fn run_chromium(page: &Path, hash: &str, extra: &[String]) -> String {
    let browser = chromium().expect("only called when not skipped");
    let profile = tempfile::tempdir().expect("temp profile dir");
    let url = format!("file://{}#{hash}", page.canonicalize().expect("page exists").display());
    let mut child = Command::new(&browser)
        .args([
            "--headless",
            "--no-sandbox",
            "--disable-gpu",
            "--disable-quic",
            "--no-first-run",
            "--disable-background-networking",
            "--disable-component-update",
            "--disable-sync",
            "--disable-extensions",
            "--hide-scrollbars",
            "--use-angle=swiftshader",
            "--enable-unsafe-swiftshader",
            "--force-device-scale-factor=1",
            &format!("--window-size={WIDTH},{HEIGHT}"),
            "--virtual-time-budget=10000",
            &format!("--user-data-dir={}", profile.path().display()),
        ])
        .args(extra)
        .arg(&url)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .unwrap_or_else(|e| panic!("cannot start {}: {e}", browser.display()));
    let mut stdout = child.stdout.take().expect("piped");
    let mut stderr = child.stderr.take().expect("piped");
    let out_reader = std::thread::spawn(move || {
        let mut s = String::new();
        stdout.read_to_string(&mut s).map(|_| s)
    });
    let err_reader = std::thread::spawn(move || {
        let mut s = String::new();
        stderr.read_to_string(&mut s).map(|_| s)
    });
    let start = Instant::now();
    let status = loop {
        if let Some(status) = child.try_wait().expect("wait for chromium") {
            break status;
        }
        if start.elapsed() > BROWSER_TIMEOUT {
            // Only the child we started, by its own handle.
            let _ = child.kill();
            let _ = child.wait();
            panic!("chromium did not finish within {BROWSER_TIMEOUT:?} on {url}");
        }
        std::thread::sleep(Duration::from_millis(100));
    };
    let out = out_reader.join().expect("stdout reader").unwrap_or_default();
    let err = err_reader.join().expect("stderr reader").unwrap_or_default();
    assert!(status.success(), "chromium failed ({status}) on {url}:\n{err}");
    out
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
    let shot = page.with_file_name(format!("{name}.png"));
    run_chromium(page, hash, &[format!("--screenshot={}", shot.display())]);
    keep(&shot);
    let file = std::fs::File::open(&shot).unwrap_or_else(|e| panic!("no screenshot {}: {e}", shot.display()));
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size fits")];
    let info = reader.next_frame(&mut buf).expect("decodes");
    let channels = info.color_type.samples();
    let px = buf[..info.buffer_size()].chunks(channels).map(|c| [c[0], c[1], c[2]]).collect();
    (info.width, info.height, px)
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
fn viewer_loads_without_errors_and_draws_the_mirrored_hull() {
    if chromium().is_none() {
        return;
    }
    let page = sample_page();
    let dom = run_chromium(page, "", &["--dump-dom".into()]);
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
}

/// The default view (panels hidden): the hull fills a sensible part of the picture, in the
/// middle, in both ends of the diverging map (K < 0 and K > 0 both occur on the hull).
#[test]
fn screenshot_shows_the_hull_coloured_by_curvature() {
    if chromium().is_none() {
        return;
    }
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
    assert!(blue > 0.01 && red > 0.01, "blue {blue}, red {red}");
    let mut distinct: Vec<[u8; 3]> = hull.iter().map(|p| [p[0] >> 3, p[1] >> 3, p[2] >> 3]).collect();
    distinct.sort_unstable();
    distinct.dedup();
    assert!(distinct.len() > 100, "only {} distinct colours", distinct.len());
}

/// Zebra stripes: the hull is drawn in dark and light bands, both a large share of it.
#[test]
fn screenshot_shows_zebra_stripes() {
    if chromium().is_none() {
        return;
    }
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
fn screenshot_shows_the_legend() {
    if chromium().is_none() {
        return;
    }
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
fn transposed_surface_gives_the_same_picture() {
    if chromium().is_none() {
        return;
    }
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
    // order, antialiasing), a few edge pixels at most; a flipped side would change most of the hull.
    assert!((differ as f64) < 0.002 * a.len() as f64, "{differ} pixels differ");
    assert!(share > 0.12, "hull covers {share}");
}
