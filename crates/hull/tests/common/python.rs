//! The Python of `tools/requirements.txt` (Open CASCADE, ezdxf, trimesh, pygltflib) that the
//! export checks run: `HULLSKIN_PYTHON`, or else `.venv` made by `tools/setup-python.sh` (once
//! per test binary). If that fails the checks fail (they cannot vanish silently) unless the
//! check's skip variable is set to 1.

use std::process::Command;
use std::sync::OnceLock;

use super::browser::workspace_root;

/// The Python with the tools' requirements, or `None` if `skip_var` is set to 1.
pub fn tools_python(skip_var: &str, what: &str) -> Option<String> {
    static PYTHON: OnceLock<Result<String, String>> = OnceLock::new();
    if let Ok(p) = std::env::var("HULLSKIN_PYTHON") {
        if !p.is_empty() {
            return Some(p);
        }
    }
    if std::env::var(skip_var).as_deref() == Ok("1") {
        eprintln!("SKIPPED: {what} ({skip_var}=1)");
        return None;
    }
    let found = PYTHON.get_or_init(|| {
        let script = workspace_root().join("tools/setup-python.sh");
        let out =
            Command::new("bash").arg(&script).output().map_err(|e| format!("cannot run {}: {e}", script.display()))?;
        let stdout = String::from_utf8_lossy(&out.stdout);
        match stdout.lines().last() {
            Some(p) if out.status.success() => Ok(p.trim().to_string()),
            _ => Err(format!("{} failed:\n{}", script.display(), String::from_utf8_lossy(&out.stderr))),
        }
    });
    match found {
        Ok(p) => Some(p.clone()),
        Err(e) => panic!(
            "{e}\n{what} needs the Python of tools/requirements.txt. Point HULLSKIN_PYTHON at a Python that has \
             it, or set {skip_var}=1 to skip the check."
        ),
    }
}
