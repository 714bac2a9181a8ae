//! `hullskin fit` with the weight optimisers and `--tolerance`, end to end: the same seed gives
//! the same surface whatever the thread count, report.json's optimization block, Ctrl-C keeps
//! the best surface, LM beats the plain approximation, and bad flags are clear errors.
//!
//! Budgets are small (the tests run the debug binary): 5 x 8 control points with rank-one
//! weights (13 variables) and a few iterations.

use std::fs;
use std::path::Path;
use std::process::Command;

use serde_json::Value;

use crate::common::*;

fn num(v: &Value) -> f64 {
    v.as_f64().unwrap_or_else(|| panic!("not a number: {v}"))
}

/// A small optimisation of the sample: `(algorithm, iterations)`; each improves on the start
/// for most seeds at this budget (GSA needs more iterations than GA and PSO to move at all).
const SMALL: [(&str, &str); 3] = [("ga", "10"), ("pso", "30"), ("gsa", "100")];

fn small_run(dir: &Path, out: &str, alg: &str, iterations: &str, seed: &str, threads: &str) -> (Vec<u8>, Value) {
    let args = [
        "fit",
        "-o",
        out,
        "--method",
        alg,
        "--ctrl",
        "5,8",
        "--weights",
        "rank1",
        "--iterations",
        iterations,
        "--population",
        "8",
        "--seed",
        seed,
    ];
    // One thread by the global `--threads` flag, more by HULLSKIN_THREADS: both ways of sizing
    // the pool are exercised, and the bytes must not depend on either.
    let o = if threads == "1" {
        hullskin_env(dir, &[&args[..], &["--threads", threads]].concat(), &[])
    } else {
        hullskin_env(dir, &args, &[("HULLSKIN_THREADS", threads)])
    };
    assert!(o.status.success(), "{alg} seed {seed}: {:?}", text(&o));
    let surface = fs::read(dir.join(out).join("surface.json")).expect("surface.json");
    (surface, read_json(&dir.join(out).join("report.json")))
}

/// The optimization block's invariants for a run of `alg` stopped by `stop`.
fn assert_optimization_block(r: &Value, alg: &str, seed: u64, stop: &str) {
    let o = &r["optimization"];
    assert_eq!(o["algorithm"], alg);
    assert_eq!(o["seed"].as_u64(), Some(seed));
    assert_eq!(o["stop"], stop, "{alg}");
    assert_eq!(o["parameter_correction"], false);
    let iterations = o["iterations"].as_u64().expect("iterations") as usize;
    let evaluations = o["evaluations"].as_u64().expect("evaluations") as usize;
    assert!(evaluations > iterations, "{alg}: {evaluations} evaluations in {iterations} iterations");
    // history[0] is the start's value, then one best value per iteration, never rising.
    let h: Vec<f64> = o["history"].as_array().expect("history").iter().map(num).collect();
    assert_eq!(h.len(), iterations + 1, "{alg}");
    assert_eq!(h[0], num(&o["start_value"]));
    assert_eq!(*h.last().expect("non-empty"), num(&o["final_value"]));
    assert!(h.windows(2).all(|w| w[1] <= w[0]), "{alg}: {h:?}");
    // Weights within the bounds, up to the round-off of exp(ln w) (a few ulps).
    let [lo, hi] = [num(&o["weight_bounds"][0]), num(&o["weight_bounds"][1])];
    let [wmin, wmax] = [num(&o["weight_range"][0]), num(&o["weight_range"][1])];
    assert!(lo * (1.0 - 1e-12) <= wmin && wmin <= wmax && wmax <= hi * (1.0 + 1e-12), "{alg}: {wmin}..{wmax}");
    assert_eq!(r["surface"]["rational"], wmin != wmax);
}

#[test]
fn same_seed_same_surface_whatever_the_thread_count_and_seeds_differ() {
    let dir = temp_dir();
    for (alg, its) in SMALL {
        let (one, r1) = small_run(dir.path(), "t1", alg, its, "1", "1");
        let (two, r2) = small_run(dir.path(), "t2", alg, its, "1", "2");
        assert!(one == two, "{alg}: surface.json differs between 1 and 2 threads");
        assert_eq!(r1["optimization"]["history"], r2["optimization"]["history"], "{alg}");
        assert_eq!(r1["optimization"]["evaluations"], r2["optimization"]["evaluations"], "{alg}");
        // The held-out error (refits of the same optimiser, on by default) too, but its time.
        let held = |r: &Value| without_timings(r["error"]["held_out"].clone());
        assert!(held(&r1)["rms"].is_f64(), "{alg}: {}", r1["error"]);
        assert_eq!(held(&r1), held(&r2), "{alg}");
        assert_optimization_block(&r1, alg, 1, "iterations");
        assert_eq!(r1["optimization"]["iterations"].as_u64().map(|n| n.to_string()).as_deref(), Some(its));
        assert_eq!(r1["optimization"]["weight_layout"], "rank_one");
        assert_eq!(r1["optimization"]["control_points"], "resolved");
        // Other seeds search elsewhere: among three seeds at least two surfaces differ (a
        // seed whose search never beats the start returns the plain approximation's surface).
        let (s2, _) = small_run(dir.path(), "s2", alg, its, "2", "2");
        let (s3, _) = small_run(dir.path(), "s3", alg, its, "3", "2");
        assert!(!(one == s2 && one == s3), "{alg}: seeds 1, 2 and 3 gave the same surface");
    }
}

#[test]
fn bad_thread_counts_are_clear_errors() {
    let dir = temp_dir();
    let o = hullskin(dir.path(), &["fit", "--threads", "0"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("--threads") && err.contains("1..=1024"), "{err}");
    let o = hullskin_env(dir.path(), &["fit", "-o", "x"], &[("HULLSKIN_THREADS", "many")]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("HULLSKIN_THREADS=\"many\": expected a whole number of threads from 1 to 1024"), "{err}");
    assert!(!dir.path().join("x").exists(), "nothing is written after a bad setting");
}

#[test]
fn lm_beats_the_plain_approximation_and_reports_its_run() {
    let dir = temp_dir();
    // The approximation LM starts from: the default count named, so not replaced by the
    // held-out referee (which takes chord-length parameters held on the surface for the
    // sample's default fit: RMS 24.9 mm, held-out max 332.5 mm, closer than LM on both).
    let o = hullskin(dir.path(), &["fit", "--method", "approx", "--ctrl", "6,19", "-o", "approx"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let o = hullskin(dir.path(), &["fit", "-o", "lm", "--method", "lm"]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out} {err}");
    assert!(out.contains("weights by lm") && out.contains("converged"), "{out}");
    let plain = read_json(&dir.path().join("approx/report.json"));
    let lm = read_json(&dir.path().join("lm/report.json"));
    assert!(plain.get("optimization").is_none());
    assert_optimization_block(&lm, "lm", 1, "converged");
    assert_eq!(lm["surface"]["control_points"], plain["surface"]["control_points"]);
    // The true (closest-point) RMS, not the objective. On the fair objective (the default) the
    // weights are smooth and trade some of the gain at the offsets for the surface between
    // them: measured 26.5 mm against the approximation's 35.1 (held out: 333 mm against 396).
    let (a, l) = (num(&plain["error"]["rms"]), num(&lm["error"]["rms"]));
    assert!(l < 0.9 * a, "lm RMS {l} against approx {a}");
    let (ha, hl) = (num(&plain["error"]["held_out"]["max"]), num(&lm["error"]["held_out"]["max"]));
    assert!(hl < ha, "lm held-out max {hl} against approx {ha}");
    assert_eq!(lm["optimization"]["weights_at_bounds"], 0, "{}", lm["optimization"]);
    // On the plain objective, not held in the envelope (`--fair 0 --envelope free`), the
    // weights are free: measured 3.3 mm against the plain approximation's 28.1 at 6 x 19 (and
    // a held-out max of 584 mm against 374: over-fitting); half is a floor that still fails a
    // solver that barely moves.
    let o = hullskin(dir.path(), &["fit", "-o", "plain", "--fair", "0", "--envelope", "free"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let o = hullskin(dir.path(), &["fit", "-o", "lm0", "--method", "lm", "--fair", "0", "--envelope", "free"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let plain0 = read_json(&dir.path().join("plain/report.json"));
    let lm0 = read_json(&dir.path().join("lm0/report.json"));
    let (a, l) = (num(&plain0["error"]["rms"]), num(&lm0["error"]["rms"]));
    assert!(l < 0.5 * a, "lm --fair 0 RMS {l} against approx {a}");
}

#[cfg(unix)]
#[test]
fn ctrl_c_stops_the_search_and_writes_the_best_surface() {
    use std::time::{Duration, Instant};
    let dir = temp_dir();
    let mut child = Command::new(env!("CARGO_BIN_EXE_hullskin"))
        .args(["fit", "-o", "out", "--method", "gsa", "--iterations", "100000"])
        .current_dir(dir.path())
        .stdout(std::process::Stdio::piped())
        .stderr(std::process::Stdio::piped())
        .spawn()
        .expect("start hullskin");
    std::thread::sleep(Duration::from_secs(1));
    assert!(child.try_wait().expect("poll").is_none(), "100000 GSA iterations ended within 1 s");
    let kill = Command::new("kill").args(["-INT", &child.id().to_string()]).status().expect("run kill");
    assert!(kill.success());
    // The search stops at the end of its iteration; writing takes a moment in a debug build.
    let start = Instant::now();
    while child.try_wait().expect("poll").is_none() {
        if start.elapsed() > Duration::from_secs(60) {
            let _ = child.kill();
            panic!("hullskin did not stop within 60 s of SIGINT");
        }
        std::thread::sleep(Duration::from_millis(50));
    }
    let o = child.wait_with_output().expect("output");
    let (out, err) = text(&o);
    assert_eq!(o.status.code(), Some(130), "stdout {out}\nstderr {err}");
    assert!(err.contains("stopping") && err.contains("interrupted: wrote the best surface"), "{err}");
    assert!(!err.contains("panicked"), "{err}");
    for f in ["surface.igs", "surface.json", "report.json"] {
        assert!(dir.path().join("out").join(f).is_file(), "{f} written");
    }
    let r = read_json(&dir.path().join("out/report.json"));
    assert_optimization_block(&r, "gsa", 1, "interrupted");
    let its = r["optimization"]["iterations"].as_u64().expect("iterations");
    assert!(its < 100_000, "{its}");
    // Interrupted or not, never worse than the start.
    assert!(num(&r["optimization"]["final_value"]) <= num(&r["optimization"]["start_value"]));
}

#[test]
fn bad_optimiser_flags_are_clear_errors() {
    let dir = temp_dir();
    // (arguments, what the message must name)
    let cases: &[(&[&str], &[&str])] = &[
        (&["--method", "foo"], &["foo", "ga", "pso", "gsa", "lm", "gsa+lm"]),
        (&["--method", "lm", "--weights", "bogus"], &["bogus", "full", "rank1"]),
        (&["--method", "lm", "--control-points", "bogus"], &["bogus", "resolved", "fixed"]),
        (&["--method", "ga", "--seed", "-3"], &["-3"]),
        (&["--method", "ga", "--iterations", "many"], &["many"]),
        (&["--tolerance", "0.1", "--ctrl", "5,8"], &["--tolerance", "--ctrl"]),
        (&["--tolerance", "0.1", "--method", "interp"], &["interp"]),
        (&["--tolerance", "0"], &["tolerance", "positive"]),
    ];
    for (args, needles) in cases {
        let mut full = vec!["fit", "-o", "out"];
        full.extend_from_slice(args);
        let o = hullskin(dir.path(), &full);
        let (out, err) = text(&o);
        assert_eq!(o.status.code(), Some(2), "{args:?}: stdout {out} stderr {err}");
        assert!(!err.contains("panicked"), "{args:?}: {err}");
        for n in *needles {
            assert!(err.contains(n), "{args:?}: `{n}` missing from: {err}");
        }
        assert!(!dir.path().join("out").exists(), "{args:?}: nothing written");
    }
}

#[test]
fn tolerance_picks_a_count_within_it_and_reports_the_search() {
    let dir = temp_dir();
    let input = testdata("offsets_example.csv");
    let input = input.to_str().expect("utf-8 path");
    // Interpolation (5 x 4 here) then each count: the plain fit's max error at 4 x 4 is
    // the loosest tolerance worth asking for.
    // (The search measures the plain least squares: --fair 0.)
    let o = hullskin(dir.path(), &["fit", input, "-o", "c44", "--ctrl", "4,4", "--fair", "0"]);
    assert!(o.status.success(), "{:?}", text(&o));
    let t = num(&read_json(&dir.path().join("c44/report.json"))["error"]["max"]);
    let o = hullskin(dir.path(), &["fit", input, "-o", "tol", "--tolerance", &format!("{t:e}")]);
    let (out, err) = text(&o);
    assert!(o.status.success(), "{out} {err}");
    let r = read_json(&dir.path().join("tol/report.json"));
    let s = &r["tolerance_search"];
    assert_eq!(num(&s["tolerance"]), t);
    assert_eq!(s["control_points"], serde_json::json!([4, 4]));
    assert_eq!(s["control_points"], r["surface"]["control_points"]);
    assert_eq!(s["interp_control_points"], serde_json::json!([5, 4]));
    assert_eq!(num(&s["ratio"]), 16.0 / 20.0);
    assert_eq!(s["complete"], true);
    assert_eq!(s["fits"].as_u64(), s["tried"].as_array().map(|a| a.len() as u64));
    assert!(num(&r["error"]["max"]) <= t);
    assert!(out.contains("4x4 = 16 control points") && out.contains("interpolation's 5x4 = 20"), "{out}");
    // Without --tolerance there is no such block.
    assert!(read_json(&dir.path().join("c44/report.json")).get("tolerance_search").is_none());
    // Below round-off: an error naming the closest valid surface found, here the default fit
    // (faired, 4x4 at 186.0 mm, measured) rather than the search's best plain fit (held within
    // the envelope, 5x4 at 275.7 mm).
    let o = hullskin(dir.path(), &["fit", input, "-o", "none", "--tolerance", "1e-30"]);
    let (_, err) = text(&o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert!(err.contains("best max error is 1.860e-1 m at 4x4 control points"), "{err}");
    assert!(!dir.path().join("none").exists());
}
