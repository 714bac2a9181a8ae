//! Headless Chromium for the browser tests (the 3-D viewer, the HTML report): find the
//! browser, run it on a page with a time limit, read back what it left (the DOM, a screenshot
//! decoded to pixels, the console messages, the network requests the page made).
//!
//! Chromium comes from `HULLSKIN_CHROMIUM`, else `/usr/bin/chromium`, else
//! `tools/setup-chromium.sh` (Debian's package, installed by the test itself when needed). If
//! none can be had the tests fail (the check cannot vanish silently) unless
//! `HULLSKIN_SKIP_BROWSER=1`. WebGL runs without a GPU on SwiftShader. Every host name
//! resolves to nothing (`--host-resolver-rules`), so neither a page nor the browser's own
//! background services can reach the network. Set `HULLSKIN_VIEWER_OUT=<dir>` to keep the
//! pages and the screenshots there.

use std::io::Read;
use std::path::{Path, PathBuf};
use std::process::{Command, Stdio};
use std::sync::OnceLock;
use std::time::{Duration, Instant};

/// How long one browser run may take before the test gives up on it.
pub const BROWSER_TIMEOUT: Duration = Duration::from_secs(120);

/// The Chromium to run (`HULLSKIN_CHROMIUM`, Debian's, else installed by
/// `tools/setup-chromium.sh`); panics when there is none. The browser tests carry
/// `#[cfg_attr(skip_browser, ignore = "HULLSKIN_SKIP_BROWSER=1")]`: skipped, they are reported
/// as ignored.
pub fn chromium() -> PathBuf {
    static FOUND: OnceLock<Result<PathBuf, String>> = OnceLock::new();
    if let Ok(p) = std::env::var("HULLSKIN_CHROMIUM") {
        if !p.is_empty() {
            return PathBuf::from(p);
        }
    }
    if Path::new("/usr/bin/chromium").exists() {
        return PathBuf::from("/usr/bin/chromium");
    }
    let found = FOUND.get_or_init(|| {
        let script = super::workspace_root().join("tools/setup-chromium.sh");
        let out =
            Command::new("bash").arg(&script).output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        match stdout.lines().last() {
            Some(p) if out.status.success() => Ok(PathBuf::from(p.trim())),
            _ => Err(format!("{} failed:\n{}", script.display(), String::from_utf8_lossy(&out.stderr))),
        }
    });
    match found {
        Ok(p) => p.clone(),
        Err(e) => panic!(
            "{e}\nThe 3-D viewer and the HTML report are checked in headless Chromium (Debian package chromium). \
             Point HULLSKIN_CHROMIUM at a Chromium, or set HULLSKIN_SKIP_BROWSER=1 to skip the check."
        ),
    }
}

/// Copy `file` into `HULLSKIN_VIEWER_OUT` when set.
pub fn keep(file: &Path) {
    if let Ok(dir) = std::env::var("HULLSKIN_VIEWER_OUT") {
        let dir = PathBuf::from(dir);
        std::fs::create_dir_all(&dir).expect("create HULLSKIN_VIEWER_OUT");
        std::fs::copy(file, dir.join(file.file_name().expect("a file"))).expect("copy to HULLSKIN_VIEWER_OUT");
    }
}

/// What one browser run printed.
#[derive(Clone, Debug)]
pub struct Run {
    /// Standard output (the DOM with `--dump-dom`).
    pub stdout: String,
    /// Standard error: Chromium's log, with the pages' console messages (`INFO:CONSOLE`).
    pub stderr: String,
}

/// Run headless Chromium on `page` with the `#hash` options, a window of `window` = [width,
/// height] CSS pixels (device scale factor 1) and `extra` arguments. Panics (with Chromium's
/// stderr) if it fails or hangs.
pub fn run_chromium(page: &Path, hash: &str, window: [u32; 2], extra: &[String]) -> Run {
    let browser = chromium();
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
            // No host name resolves: nothing reaches the network, the page or the browser.
            "--host-resolver-rules=MAP * ~NOTFOUND",
            // The pages' console messages (every frame) on stderr, as `INFO:CONSOLE` lines.
            "--enable-logging=stderr",
            "--v=0",
            &format!("--window-size={},{}", window[0], window[1]),
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
    let stdout = out_reader.join().expect("stdout reader").unwrap_or_default();
    let stderr = err_reader.join().expect("stderr reader").unwrap_or_default();
    assert!(status.success(), "chromium failed ({status}) on {url}:\n{stderr}");
    Run { stdout, stderr }
}

/// A decoded picture: RGB pixels row by row from the top left.
#[derive(Clone, Debug)]
pub struct Picture {
    pub width: u32,
    pub height: u32,
    pub px: Vec<[u8; 3]>,
}

impl Picture {
    /// The pixel at column `x`, row `y`.
    pub fn at(&self, x: u32, y: u32) -> [u8; 3] {
        self.px[(y * self.width + x) as usize]
    }

    /// The pixels of the box `[x0, y0, x1, y1)` (clipped to the picture), row by row.
    pub fn region(&self, [x0, y0, x1, y1]: [u32; 4]) -> Vec<[u8; 3]> {
        let (x1, y1) = (x1.min(self.width), y1.min(self.height));
        (y0.min(y1)..y1).flat_map(|y| (x0.min(x1)..x1).map(move |x| (x, y))).map(|(x, y)| self.at(x, y)).collect()
    }
}

/// Decode the PNG at `path` to RGB (alpha dropped, any bit depth and palette expanded).
pub fn decode_png(path: &Path) -> Picture {
    let file = std::fs::File::open(path).unwrap_or_else(|e| panic!("no picture {}: {e}", path.display()));
    let mut decoder = png::Decoder::new(std::io::BufReader::new(file));
    decoder.set_transformations(png::Transformations::normalize_to_color8());
    let mut reader = decoder.read_info().expect("a PNG");
    let mut buf = vec![0; reader.output_buffer_size().expect("size fits")];
    let info = reader.next_frame(&mut buf).expect("decodes");
    let channels = info.color_type.samples();
    let px = buf[..info.buffer_size()].chunks(channels).map(|c| [c[0], c[1], c[2]]).collect();
    Picture { width: info.width, height: info.height, px }
}

/// Take a screenshot of `page` with `hash` in a window of `window` CSS pixels, saved beside the
/// page as `name.png` (and kept), decoded; with what Chromium printed.
pub fn screenshot(page: &Path, name: &str, hash: &str, window: [u32; 2], extra: &[String]) -> (Picture, Run) {
    let shot = page.with_file_name(format!("{name}.png"));
    let mut args = vec![format!("--screenshot={}", shot.display())];
    args.extend_from_slice(extra);
    let run = run_chromium(page, hash, window, &args);
    keep(&shot);
    (decode_png(&shot), run)
}

/// The pages' console messages in Chromium's log (`[...:INFO:CONSOLE:line] "text", source: url
/// (line)`), every frame's, whatever their level (the log does not tell `console.log` from an
/// uncaught error), less the GL driver's performance notes that SwiftShader sends to the
/// console of a WebGL page ("GL Driver Message (OpenGL, Performance, ...): GPU stall due to
/// ReadPixels"), which are not the page's.
pub fn console_messages(stderr: &str) -> Vec<String> {
    stderr
        .lines()
        .filter_map(|l| l.find(":INFO:CONSOLE").map(|k| &l[k..]))
        .filter_map(|l| l.find("] ").map(|k| l[k + 2..].to_string()))
        .filter(|m| !m.contains("GL Driver Message (OpenGL, Performance"))
        .collect()
}

/// The URLs of the requests that reached Chromium's network stack on behalf of a `file://` page
/// (any of its frames), read from a net log written with `--log-net-log=<net_log>`. Requests of
/// the browser itself (update checks, time queries) are told apart by their network isolation
/// key, which names the top frame's site only for a page's requests. `data:` and `file:` URLs
/// never reach the network stack, so they are not listed.
pub fn page_requests(net_log: &Path) -> Vec<String> {
    let text = std::fs::read_to_string(net_log).unwrap_or_else(|e| panic!("no net log {}: {e}", net_log.display()));
    let log: serde_json::Value = serde_json::from_str(&text).expect("the net log is JSON");
    let start_job = log["constants"]["logEventTypes"]["URL_REQUEST_START_JOB"]
        .as_u64()
        .expect("the net log names URL_REQUEST_START_JOB");
    let events = log["events"].as_array().expect("the net log has events");
    events
        .iter()
        .filter(|e| e["type"].as_u64() == Some(start_job))
        .filter(|e| e["params"]["network_isolation_key"].as_str().is_some_and(|k| k.starts_with("file://")))
        .map(|e| e["params"]["url"].as_str().unwrap_or("?").to_string())
        .collect()
}
