//! Where the repository is, for the test binaries of every crate.

use std::path::{Path, PathBuf};

/// The repository's root (every crate sits at `crates/<name>`).
pub fn workspace_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The file `name` of the repository's `testdata/`.
pub fn testdata(name: &str) -> PathBuf {
    workspace_root().join("testdata").join(name)
}
