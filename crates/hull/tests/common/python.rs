//! The Python of `tools/requirements.txt` (Open CASCADE, ezdxf, trimesh, pygltflib) that the
//! export checks run: `HULLSKIN_PYTHON`, or else `.venv` made by `tools/setup-python.sh` (once
//! per test binary). If that fails the checks fail (they cannot vanish silently) unless the
//! check's skip variable is set to 1.
//!
//! One helper for the workspace: `crates/cli/tests/cli/main.rs` includes this file too (`#[path]`),
//! so it names nothing outside itself.

use std::path::Path;
use std::process::Command;
use std::sync::OnceLock;

/// The Python with the tools' requirements (`HULLSKIN_PYTHON`, else made by
/// `tools/setup-python.sh`); panics, naming `skip_var`, when there is none. A test that calls
/// it carries `#[cfg_attr(skip_…, ignore = "…")]`, so that `skip_var=1` reports it as ignored
/// (the build script turns the variable into the cfg), never as passed.
pub fn tools_python(skip_var: &str, what: &str) -> String {
    static PYTHON: OnceLock<Result<String, String>> = OnceLock::new();
    if let Ok(p) = std::env::var("HULLSKIN_PYTHON") {
        if !p.is_empty() {
            return p;
        }
    }
    let found = PYTHON.get_or_init(|| {
        // Every crate of the workspace sits at `crates/<name>`.
        let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools/setup-python.sh");
        let out =
            Command::new("bash").arg(&script).output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        match stdout.lines().last() {
            Some(p) if out.status.success() => Ok(p.trim().to_string()),
            _ => Err(format!("{} failed:\n{}", script.display(), String::from_utf8_lossy(&out.stderr))),
        }
    });
    match found {
        Ok(p) => p.clone(),
        Err(e) => panic!(
            "{e}\n{what} needs the Python of tools/requirements.txt. Point HULLSKIN_PYTHON at a Python that has \
             it, or set {skip_var}=1 to skip the check."
        ),
    }
}

/// Run `tools/<script>` with `python` on `args`: its exit code and the JSON summary it printed
/// (panics, with its output, when it printed none).
pub fn run_tool(python: &str, script: &str, args: &[&Path]) -> (i32, serde_json::Value) {
    let script = Path::new(env!("CARGO_MANIFEST_DIR")).join("../../tools").join(script);
    let out = Command::new(python)
        .arg(&script)
        .args(args)
        .output()
        .unwrap_or_else(|e| panic!("cannot run {python} {}: {e}", script.display()));
    let stdout = String::from_utf8_lossy(&out.stdout);
    let stderr = String::from_utf8_lossy(&out.stderr);
    let summary = serde_json::from_str(&stdout).unwrap_or_else(|e| {
        panic!(
            "{} did not print a JSON summary ({e}); status {:?}\nstdout:\n{stdout}\nstderr:\n{stderr}",
            script.display(),
            out.status
        )
    });
    (out.status.code().unwrap_or(-1), summary)
}

/// A check of [`run_tool`] passed: exit 0 and `"ok": true`; else panics naming `case` and
/// printing what failed.
pub fn assert_tool_passed(case: &str, code: i32, summary: &serde_json::Value) {
    assert!(
        code == 0 && summary["ok"] == true,
        "{case}: the reader disagrees with the export (exit {code}):\n{}",
        serde_json::to_string_pretty(&summary["failed"]).unwrap_or_default()
    );
}
