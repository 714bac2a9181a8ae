//! The bad-input corpus (`testdata/bad/`, issue 6): the CLI on every hostile or broken file
//! exits non-zero with a message that names the file and the place, never panics, never hangs
//! and stays within a memory cap; and the files a user expects to work (`testdata/bad/accepted/`:
//! decimal commas with `;`, BOMs, CRLF and mixed line ends, tabs) fit exactly like their clean
//! counterparts.
//!
//! What each file holds and what the CLI must say is in `testdata/bad/manifest.csv` (and, for
//! people, `testdata/bad/README.md`); `testdata/bad/gen.py` writes them all.

use std::fs::{self, File};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitStatus, Stdio};
use std::time::{Duration, Instant};

use crate::common::{self, read_json, temp_dir, testdata};

/// A run longer than this is a hang. The slowest file (a mesh sliced and fitted) takes about a
/// second in a debug build; 60 s leaves room for a loaded two-core machine.
const TIMEOUT: Duration = Duration::from_secs(60);

/// The address-space cap of each run (`prlimit --as`), and the resident-set cap checked by
/// polling `/proc/PID/status` (VmHWM). Measured in a debug build: a small fit runs in under
/// 50 MB of address space, and the corpus's largest legitimate allocation, the 32 MiB gzip of
/// zeros decompressed, peaks at about 185 MB. A reader that trusted a header (4 billion
/// triangles, a 4e9 x 4e9 control net, 4e9 knots) would ask for tens of GiB and be stopped
/// here (an allocation failure aborts: a signal, reported as such).
const MEMORY_CAP: u64 = 1 << 30;

/// One line of `manifest.csv` (see `testdata/bad/gen.py` for the columns).
struct Case {
    file: String,
    command: String,
    args: Vec<String>,
    must_succeed: bool,
    at: String,
    says: String,
}

fn bad_dir() -> PathBuf {
    testdata("bad")
}

/// The first `n` comma-separated fields of each data line of a manifest; the last column
/// (`why`, quoted) is not needed and may hold commas, so it is left unsplit.
fn manifest(path: &Path, n: usize) -> Vec<Vec<String>> {
    let text = fs::read_to_string(path).expect("read the manifest");
    text.lines()
        .skip(1)
        .filter(|l| !l.is_empty())
        .map(|l| l.splitn(n + 1, ',').take(n).map(String::from).collect())
        .collect()
}

fn cases() -> Vec<Case> {
    manifest(&bad_dir().join("manifest.csv"), 6)
        .into_iter()
        .map(|f| Case {
            file: f[0].clone(),
            command: f[1].clone(),
            args: f[2].split_whitespace().map(String::from).collect(),
            must_succeed: match f[3].as_str() {
                "ok" => true,
                "fail" => false,
                other => panic!("manifest.csv: exit \"{other}\" for {} (expected ok or fail)", f[0]),
            },
            at: f[4].clone(),
            says: f[5].clone(),
        })
        .collect()
}

/// How a run ended.
struct Run {
    status: Option<ExitStatus>,
    stderr: String,
    stdout: String,
    /// Peak resident set seen while polling, bytes (0 when /proc is not there or the run was
    /// too quick to be seen).
    peak_rss: u64,
    seconds: f64,
}

/// True if `prlimit` (util-linux) can run a command here.
fn have_prlimit() -> bool {
    Command::new("prlimit").arg("--version").output().is_ok_and(|o| o.status.success())
}

/// VmHWM of a running process, bytes.
fn vm_hwm(pid: u32) -> Option<u64> {
    let status = fs::read_to_string(format!("/proc/{pid}/status")).ok()?;
    let line = status.lines().find(|l| l.starts_with("VmHWM:"))?;
    let kb: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
    Some(kb * 1024)
}

/// Runs the CLI with `args` in `dir` under the memory cap and the timeout; the output goes to
/// files (a pipe could fill and stall a chatty run).
fn run_capped(dir: &Path, args: &[String], prlimit: bool) -> Run {
    let bin = env!("CARGO_BIN_EXE_hullskin");
    let mut cmd = if prlimit {
        let mut c = Command::new("prlimit");
        c.arg(format!("--as={MEMORY_CAP}")).arg(bin);
        c
    } else {
        Command::new(bin)
    };
    let (out_path, err_path) = (dir.join("stdout.txt"), dir.join("stderr.txt"));
    cmd.args(args)
        .current_dir(dir)
        .stdin(Stdio::null())
        .stdout(File::create(&out_path).expect("stdout file"))
        .stderr(File::create(&err_path).expect("stderr file"));
    let start = Instant::now();
    let mut child = cmd.spawn().expect("run hullskin");
    let mut peak_rss = 0;
    let status = loop {
        // prlimit execs the command: the pid is the CLI's.
        peak_rss = peak_rss.max(vm_hwm(child.id()).unwrap_or(0));
        match child.try_wait().expect("wait for hullskin") {
            Some(status) => break Some(status),
            None if start.elapsed() > TIMEOUT => {
                let _ = child.kill();
                let _ = child.wait();
                break None;
            }
            None => std::thread::sleep(Duration::from_millis(5)),
        }
    };
    let read = |p: &Path| String::from_utf8_lossy(&fs::read(p).unwrap_or_default()).into_owned();
    Run { status, stderr: read(&err_path), stdout: read(&out_path), peak_rss, seconds: start.elapsed().as_secs_f64() }
}

/// The place `at` of the manifest after `path` in `text`: `""` the path alone, `":"` the path
/// then `:` and a line number, `":L"` or `":L:C"` exactly that (not followed by a digit, so
/// `:1` does not match `:12`).
fn names_place(text: &str, path: &str, at: &str) -> bool {
    let prefix = format!("{path}{at}");
    text.match_indices(&prefix).any(|(i, _)| {
        let next = text[i + prefix.len()..].chars().next();
        match at {
            "" => true,
            ":" => next.is_some_and(|c| c.is_ascii_digit()),
            _ => !next.is_some_and(|c| c.is_ascii_digit()),
        }
    })
}

/// What is wrong with a run of `case`, if anything.
fn judge(case: &Case, path: &str, run: &Run) -> Option<String> {
    let Some(status) = run.status else {
        return Some(format!("hang: killed after {} s", TIMEOUT.as_secs()));
    };
    #[cfg(unix)]
    {
        use std::os::unix::process::ExitStatusExt;
        if let Some(sig) = status.signal() {
            return Some(format!("killed by signal {sig} (a crash, a stack overflow, or the memory cap)"));
        }
    }
    if run.stderr.contains("panicked") || status.code() == Some(101) {
        return Some(format!("panic (exit code {:?})", status.code()));
    }
    if run.peak_rss > MEMORY_CAP {
        return Some(format!("resident set {} MiB above the cap of {} MiB", run.peak_rss >> 20, MEMORY_CAP >> 20));
    }
    if case.must_succeed {
        if !status.success() {
            return Some(format!("exit code {:?}, expected success (a tolerated file)", status.code()));
        }
    } else if status.success() {
        return Some("exit code 0, expected failure".into());
    } else if !names_place(&run.stderr, path, &case.at) {
        return Some(format!("the message does not name `{path}{}`", if case.at == ":" { "LINE" } else { &case.at }));
    }
    if !run.stderr.contains(&case.says) && !run.stdout.contains(&case.says) {
        return Some(format!("the message does not say \"{}\"", case.says));
    }
    None
}

fn args_for(case: &Case, path: &str, out: &Path) -> Vec<String> {
    let out = |name: &str| out.join(name).display().to_string();
    let mut args: Vec<String> = match case.command.as_str() {
        "fit" => vec!["fit".into(), path.into(), "-o".into(), out("fit")],
        "hydrostatics" => vec!["hydrostatics".into(), path.into(), "--draft".into(), "1".into()],
        "export" => vec!["export".into(), path.into(), "-o".into(), out("surface.stl")],
        "slice" => vec!["slice".into(), path.into(), "-o".into(), out("sections.csv")],
        "report" => vec!["report".into(), path.into(), "-o".into(), out("report")],
        "digitize" => vec![
            "digitize".into(),
            path.into(),
            "--scale".into(),
            "1".into(),
            "--datum".into(),
            "0,0".into(),
            "--station-spacing".into(),
            "1".into(),
            "-o".into(),
            out("sections.csv"),
        ],
        other => panic!(
            "manifest.csv: command \"{other}\" for {} (expected fit, hydrostatics, export, report, slice or digitize)",
            case.file
        ),
    };
    args.extend(case.args.iter().cloned());
    args
}

#[test]
fn every_bad_input_is_refused_by_file_and_place_without_panic_hang_or_runaway_memory() {
    let cases = cases();
    // The corpus: at least 60 files, every one of them in the manifest and the other way round.
    assert!(cases.len() >= 60, "{} files in manifest.csv, expected at least 60", cases.len());
    let mut listed: Vec<&str> = cases.iter().map(|c| c.file.as_str()).collect();
    listed.sort_unstable();
    let mut on_disk: Vec<String> = fs::read_dir(bad_dir())
        .expect("testdata/bad")
        .map(|e| e.expect("entry").file_name().to_string_lossy().into_owned())
        .filter(|n| !["gen.py", "manifest.csv", "README.md", "accepted"].contains(&n.as_str()))
        .collect();
    on_disk.sort_unstable();
    assert_eq!(listed, on_disk, "testdata/bad and its manifest.csv list different files");
    for command in ["fit", "hydrostatics", "export", "report", "slice", "digitize"] {
        assert!(cases.iter().any(|c| c.command == command), "no file runs `hullskin {command}`");
    }

    let prlimit = have_prlimit();
    let tmp = temp_dir();
    let mut failures = Vec::new();
    let (mut slowest, mut peak) = ((0.0, String::new()), (0, String::new()));
    for (k, case) in cases.iter().enumerate() {
        let dir = tmp.path().join(format!("{k}"));
        fs::create_dir_all(&dir).expect("case dir");
        let path = bad_dir().join(&case.file).display().to_string();
        let run = run_capped(&dir, &args_for(case, &path, &dir), prlimit);
        if run.seconds > slowest.0 {
            slowest = (run.seconds, case.file.clone());
        }
        if run.peak_rss > peak.0 {
            peak = (run.peak_rss, case.file.clone());
        }
        if let Some(problem) = judge(case, &path, &run) {
            failures.push(format!(
                "{} (hullskin {}): {problem}\n  stderr: {}",
                case.file,
                case.command,
                run.stderr.trim().chars().take(2000).collect::<String>()
            ));
        }
    }
    eprintln!(
        "bad inputs: {} files, memory cap {} MiB (prlimit {}), slowest {:.2} s ({}), peak resident set {} MiB ({})",
        cases.len(),
        MEMORY_CAP >> 20,
        if prlimit { "on" } else { "not found: VmHWM polled only" },
        slowest.0,
        slowest.1,
        peak.0 >> 20,
        peak.1
    );
    assert!(
        failures.is_empty(),
        "{} of {} bad inputs handled wrongly:\n{}",
        failures.len(),
        cases.len(),
        failures.join("\n")
    );
}

#[test]
fn spreadsheet_exports_fit_exactly_like_the_clean_files() {
    let dir = bad_dir().join("accepted");
    let rows = manifest(&dir.join("manifest.csv"), 2);
    assert!(rows.len() >= 8, "{} accepted files, expected the eight kinds of the README", rows.len());
    let tmp = temp_dir();
    let fit = |name: &str| {
        let out = tmp.path().join(name);
        let o = common::hullskin(
            tmp.path(),
            &["fit", &dir.join(name).display().to_string(), "-o", &out.display().to_string()],
        );
        let (_, stderr) = common::text(&o);
        assert!(o.status.success(), "{name} must fit: {stderr}");
        let report = read_json(&out.join("report.json"));
        (
            fs::read(out.join("surface.json")).expect("surface.json"),
            report["input"]["sections"].clone(),
            report["input"]["points"].clone(),
        )
    };
    let mut failures = Vec::new();
    let mut clean_fits = std::collections::BTreeMap::new();
    for row in rows.iter().filter(|r| r[0] != r[1]) {
        let (file, clean) = (&row[0], &row[1]);
        let (surface, sections, points) = fit(file);
        let (want_surface, want_sections, want_points) =
            clean_fits.entry(clean.clone()).or_insert_with(|| fit(clean)).clone();
        // The same offsets give the same surface to the last bit: the fit is deterministic and
        // surface.json writes shortest round-trip floats.
        if (sections.clone(), points.clone()) != (want_sections.clone(), want_points.clone()) {
            failures
                .push(format!("{file}: {sections} sections, {points} points; {clean}: {want_sections}, {want_points}"));
        } else if surface != want_surface {
            failures.push(format!("{file}: surface.json differs from that of {clean}"));
        }
    }
    assert!(failures.is_empty(), "accepted files read differently:\n{}", failures.join("\n"));
}

/// A plausible mistake in a clean table (a decimal point shifted in one cell) is fitted as read
/// but named on standard error and in `report.json` at its file, line and field; `--outliers
/// refuse` stops with that place, `--outliers keep` fits silently; the clean table fits with
/// no warning to the same surface as before the checks (they only read).
#[test]
fn a_typo_in_one_cell_is_named_at_its_place_and_refused_on_request() {
    let tmp = temp_dir();
    let clean = fs::read_to_string(testdata("series60_cb060_offsets.csv")).expect("the sample table");
    // Line 6 (the 1.0 WL), field 14 (station x = 60.96): 8.13 m typed 81.3.
    let mut lines: Vec<String> = clean.lines().map(str::to_string).collect();
    let mut cells: Vec<String> = lines[5].split(',').map(str::to_string).collect();
    let value: f64 = cells[13].parse().expect("a number");
    cells[13] = format!("{}", value * 10.0);
    lines[5] = cells.join(",");
    let bad = tmp.path().join("s60.csv");
    fs::write(&bad, lines.join("\n") + "\n").expect("write");
    let bad = bad.display().to_string();
    let o = common::hullskin(tmp.path(), &["fit", &bad, "-o", "out", "--ctrl", "8,12"]);
    let (_, stderr) = common::text(&o);
    assert!(o.status.success(), "{stderr}");
    let place = format!("{bad}:6:14:");
    let warning =
        stderr.lines().find(|l| l.contains(&place)).unwrap_or_else(|| panic!("no warning at {place}: {stderr}"));
    assert!(warning.starts_with("hullskin: warning: ") && warning.contains("--outliers"), "{warning}");
    let report = read_json(&tmp.path().join("out/report.json"));
    let warnings = report["input"]["warnings"].as_array().expect("input.warnings");
    assert_eq!(warnings.len(), 1, "{warnings:?}");
    assert_eq!(warnings[0]["at"].as_str(), Some(place.trim_end_matches(':')));
    assert_eq!((warnings[0]["kind"].as_str(), warnings[0]["value"].as_f64()), (Some("outlier"), Some(value * 10.0)));

    let o = common::hullskin(tmp.path(), &["fit", &bad, "-o", "refused", "--outliers", "refuse"]);
    let (_, stderr) = common::text(&o);
    assert!(!o.status.success() && stderr.contains(&place), "{stderr}");
    assert!(!tmp.path().join("refused").exists(), "a refused input writes nothing");
    let o = common::hullskin(tmp.path(), &["fit", &bad, "-o", "kept", "--ctrl", "8,12", "--outliers", "keep"]);
    let (_, stderr) = common::text(&o);
    assert!(o.status.success() && !stderr.contains("warning"), "{stderr}");

    // The clean table: no warning, an empty list.
    let path = testdata("series60_cb060_offsets.csv").display().to_string();
    let o = common::hullskin(tmp.path(), &["fit", &path, "-o", "clean", "--ctrl", "8,12"]);
    let (_, stderr) = common::text(&o);
    assert!(o.status.success() && !stderr.contains("warning"), "{stderr}");
    let report = read_json(&tmp.path().join("clean/report.json"));
    assert_eq!(report["input"]["warnings"].as_array().map(Vec::len), Some(0));
}
