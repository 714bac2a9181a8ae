//! Where the repository is, for the test binaries of every crate.

use std::path::{Path, PathBuf};

/// The repository's root (every crate sits at `crates/<name>`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}
