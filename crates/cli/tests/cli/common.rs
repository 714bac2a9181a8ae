//! Helpers shared by the CLI tests: run the binary, find `testdata/`, make a scratch directory.

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

use serde_json::Value;

/// A fresh scratch directory for one test, removed when dropped (`hullskin-test-` in the
/// system's temporary directory).
pub fn temp_dir() -> tempfile::TempDir {
    tempfile::Builder::new().prefix("hullskin-test-").tempdir().expect("temp dir")
}

/// Run the `hullskin` binary in `dir` with extra environment variables.
pub fn hullskin_env(dir: &Path, args: &[&str], env: &[(&str, &str)]) -> Output {
    let mut c = Command::new(env!("CARGO_BIN_EXE_hullskin"));
    c.args(args).current_dir(dir);
    for (k, v) in env {
        c.env(k, v);
    }
    c.output().expect("run hullskin")
}

/// Run the `hullskin` binary in `dir`.
pub fn hullskin(dir: &Path, args: &[&str]) -> Output {
    hullskin_env(dir, args, &[])
}

/// A file of the repository's `testdata/`.
pub fn testdata(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../testdata").join(name)
}

/// Standard output and standard error as text.
pub fn text(o: &Output) -> (String, String) {
    (String::from_utf8_lossy(&o.stdout).into_owned(), String::from_utf8_lossy(&o.stderr).into_owned())
}

/// A JSON file, parsed.
pub fn read_json(p: &Path) -> Value {
    serde_json::from_str(&fs::read_to_string(p).expect("read json")).expect("valid json")
}

/// `v` without its timings (keys naming seconds or a time), which differ from run to run.
pub fn without_timings(v: Value) -> Value {
    match v {
        Value::Object(map) => Value::Object(
            map.into_iter()
                .filter(|(k, _)| !(k.contains("seconds") || k.contains("time")))
                .map(|(k, v)| (k, without_timings(v)))
                .collect(),
        ),
        Value::Array(items) => Value::Array(items.into_iter().map(without_timings).collect()),
        other => other,
    }
}
