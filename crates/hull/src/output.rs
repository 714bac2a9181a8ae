//! Writing outputs so that nothing is lost: one file atomically, or a run's files all or none.
//!
//! The rest of this module's documentation is on [`OutputDir`], where the library's users read it.

use std::fs;
use std::io::{self, BufWriter, Write};
use std::path::{Component, Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};
use std::sync::{Mutex, MutexGuard, PoisonError};

use nurbs::{KnotVector, NurbsSurface};

use crate::HullError;

/// Write `path` atomically: `fill` writes the content into a temporary file in the same
/// directory, which is flushed, synced and renamed onto `path` only if `fill` succeeds.
///
/// # Errors
/// Any I/O error of creating, writing, syncing or renaming, or the error `fill` returns; the
/// temporary file is removed on failure and `path` is untouched.
pub fn write_atomic<F>(path: &Path, fill: F) -> io::Result<()>
where
    F: FnOnce(&mut dyn Write) -> io::Result<()>,
{
    let dir = path.parent().filter(|p| !p.as_os_str().is_empty()).unwrap_or(Path::new("."));
    let name = path.file_name().map(|n| n.to_string_lossy().into_owned()).unwrap_or_else(|| "output".into());
    let tmp: PathBuf = dir.join(format!(".{name}.tmp-{}", std::process::id()));
    let result = (|| {
        let file = fs::File::create(&tmp)?;
        let mut w = BufWriter::new(file);
        fill(&mut w)?;
        let file = w.into_inner().map_err(|e| e.into_error())?;
        file.sync_all()?;
        fs::rename(&tmp, path)
    })();
    if result.is_err() {
        let _ = fs::remove_file(&tmp);
    }
    result
}

/// The staging directories alive in this process. Held during a commit's renames, so that
/// [`discard_staged_outputs`] (from a signal handler's thread) waits for a commit to end.
static STAGED: Mutex<Vec<PathBuf>> = Mutex::new(Vec::new());

/// Makes staging names unique within the process (with the process id across processes).
static STAGING_COUNTER: AtomicUsize = AtomicUsize::new(0);

fn staged() -> MutexGuard<'static, Vec<PathBuf>> {
    STAGED.lock().unwrap_or_else(PoisonError::into_inner)
}

/// The files of one run, staged in a hidden sibling of the output directory until
/// [`OutputDir::commit`] moves them in.
///
/// # Writing outputs so that nothing is lost
///
/// - [`write_atomic`]: one file, written to a temporary sibling and renamed over the target, so
///   a reader sees the old file or the complete new one, never half a file.
/// - [`OutputDir`]: the files of one run, written into a fresh hidden staging directory beside
///   the output directory and moved into it only when the whole run succeeded
///   ([`OutputDir::commit`]). A run that fails at any point (bad input, a fit or draft error, a
///   write error, a signal) leaves the output directory as it was, byte for byte; dropping an
///   uncommitted [`OutputDir`] removes its staging directory.
/// - [`check_finite`]: a surface is checked before any file of it is created.
///
/// The guarantee's limit: the commit moves the files one by one (each by an atomic rename), so a
/// crash or power loss in the middle of the commit itself can leave a mix of old and new
/// files, each of them complete; never a half-written one. A process killed outright (SIGKILL)
/// before its commit can leave a hidden `.NAME.hullskin-staging-PID-N` directory beside the
/// output directory; it holds nothing of the outputs and may be deleted.
///
/// ```no_run
/// # fn main() -> Result<(), hull::HullError> {
/// let mut out = hull::OutputDir::stage(std::path::Path::new("hullskin-out"))?;
/// out.write_bytes("a.txt", b"first file")?;
/// out.write_bytes("b.txt", b"second file")?;
/// // An error before this line leaves hullskin-out as it was.
/// let written = out.commit()?;
/// assert_eq!(written.len(), 2);
/// # Ok(())
/// # }
/// ```
#[derive(Debug)]
pub struct OutputDir {
    /// The output directory, as given.
    target: PathBuf,
    /// The staging directory: `PARENT/.NAME.hullskin-staging-PID-N`.
    staging: PathBuf,
    /// The files written, in order (each once).
    names: Vec<String>,
    /// Set when the commit has moved the files and removed the staging directory.
    done: bool,
}

impl OutputDir {
    /// Start a run writing into `dir`: create a fresh, empty staging directory beside it, on
    /// the same filesystem (creating `dir`'s parent if needed; `dir` itself is created by the
    /// commit).
    ///
    /// # Errors
    /// [`HullError::Io`] if `dir` exists and is not a directory, if its parent cannot be
    /// created, or if the staging directory cannot be created;
    /// [`HullError::OutputDirectory`] for a path that names no directory (such as `/`).
    pub fn stage(dir: &Path) -> Result<Self, HullError> {
        let io_err = |path: &Path| {
            let path = path.to_path_buf();
            move |error: io::Error| HullError::Io { path, error }
        };
        if dir.exists() && !dir.is_dir() {
            return Err(HullError::Io {
                path: dir.to_path_buf(),
                error: io::Error::new(io::ErrorKind::AlreadyExists, "exists and is not a directory (expected one)"),
            });
        }
        // `out`, `a/out`, or a path without a plain last component (`.`, `a/..`): canonical.
        let (parent, name) = match (dir.file_name(), dir.parent()) {
            (Some(name), Some(parent)) => {
                let parent = if parent.as_os_str().is_empty() { Path::new(".") } else { parent };
                (parent.to_path_buf(), name.to_string_lossy().into_owned())
            }
            _ => {
                let full = fs::canonicalize(dir).map_err(io_err(dir))?;
                match (full.file_name(), full.parent()) {
                    (Some(name), Some(parent)) => (parent.to_path_buf(), name.to_string_lossy().into_owned()),
                    _ => return Err(HullError::OutputDirectory { path: dir.to_path_buf() }),
                }
            }
        };
        fs::create_dir_all(&parent).map_err(io_err(&parent))?;
        let mut registry = staged();
        loop {
            let n = STAGING_COUNTER.fetch_add(1, Ordering::SeqCst);
            let staging = parent.join(format!(".{name}.hullskin-staging-{}-{n}", std::process::id()));
            match fs::create_dir(&staging) {
                Ok(()) => {
                    registry.push(staging.clone());
                    return Ok(OutputDir { target: dir.to_path_buf(), staging, names: Vec::new(), done: false });
                }
                // Left by a process of the same id long gone: try the next number.
                Err(e) if e.kind() == io::ErrorKind::AlreadyExists && n < usize::MAX => continue,
                Err(e) => return Err(io_err(&staging)(e)),
            }
        }
    }

    /// The output directory the files go to on commit.
    pub fn target(&self) -> &Path {
        &self.target
    }

    /// The staging directory (for messages and tests; write with [`OutputDir::write`]).
    pub fn staging_path(&self) -> &Path {
        &self.staging
    }

    /// Stage the file `name` (a plain file name): `fill` writes its content. Returns the path it
    /// will have after the commit. Writing a name again replaces its staged content.
    ///
    /// # Errors
    /// [`HullError::OutputName`] for a name that is not a plain file name; [`HullError::Io`] naming
    /// the file's final path for an error of writing it or of `fill`.
    pub fn write<F>(&mut self, name: &str, fill: F) -> Result<PathBuf, HullError>
    where
        F: FnOnce(&mut dyn Write) -> io::Result<()>,
    {
        let mut parts = Path::new(name).components();
        if !matches!((parts.next(), parts.next()), (Some(Component::Normal(n)), None) if n == name) {
            return Err(HullError::OutputName { name: name.to_string() });
        }
        let target = self.target.join(name);
        write_atomic(&self.staging.join(name), fill).map_err(|error| HullError::Io { path: target.clone(), error })?;
        if !self.names.iter().any(|n| n == name) {
            self.names.push(name.to_string());
        }
        Ok(target)
    }

    /// [`OutputDir::write`] of `bytes`.
    ///
    /// # Errors
    /// As [`OutputDir::write`].
    pub fn write_bytes(&mut self, name: &str, bytes: &[u8]) -> Result<PathBuf, HullError> {
        self.write(name, |w| w.write_all(bytes))
    }

    /// Move the staged files into the output directory (created if needed), in the order
    /// they were first written, each by a rename that replaces a file of the same name
    /// atomically; other files in the directory are untouched. Returns the final paths.
    ///
    /// # Errors
    /// [`HullError::Io`] if the directory cannot be created, if a staged name is a directory
    /// there (checked before anything moves), if the staged files were discarded (by a
    /// signal, [`discard_staged_outputs`]), or if a move fails (the files moved before it are
    /// in place, complete).
    pub fn commit(mut self) -> Result<Vec<PathBuf>, HullError> {
        let io_err = |path: &Path| {
            let path = path.to_path_buf();
            move |error: io::Error| HullError::Io { path, error }
        };
        fs::create_dir_all(&self.target).map_err(io_err(&self.target))?;
        let mut registry = staged();
        if !registry.contains(&self.staging) {
            return Err(HullError::Io {
                path: self.target.clone(),
                error: io::Error::new(io::ErrorKind::Interrupted, "the staged outputs were discarded (interrupted)"),
            });
        }
        for name in &self.names {
            let to = self.target.join(name);
            if to.is_dir() {
                return Err(HullError::Io {
                    path: to,
                    error: io::Error::new(io::ErrorKind::AlreadyExists, "is a directory (expected a file or nothing)"),
                });
            }
        }
        let mut written = Vec::with_capacity(self.names.len());
        for name in &self.names {
            let (from, to) = (self.staging.join(name), self.target.join(name));
            if fs::rename(&from, &to).is_err() {
                // E.g. the output directory is a mount point (another filesystem): copy, still
                // through a temporary file renamed in place.
                let mut file = fs::File::open(&from).map_err(io_err(&to))?;
                write_atomic(&to, |w| io::copy(&mut file, w).map(|_| ())).map_err(io_err(&to))?;
            }
            written.push(to);
        }
        // Make the renames durable where directories can be synced (Unix); elsewhere this
        // fails harmlessly.
        if let Ok(d) = fs::File::open(&self.target) {
            let _ = d.sync_all();
        }
        let _ = fs::remove_dir_all(&self.staging);
        registry.retain(|p| p != &self.staging);
        self.done = true;
        drop(registry);
        Ok(written)
    }
}

impl Drop for OutputDir {
    /// An uncommitted run: remove the staging directory and everything in it.
    fn drop(&mut self) {
        if self.done {
            return;
        }
        let mut registry = staged();
        let _ = fs::remove_dir_all(&self.staging);
        registry.retain(|p| p != &self.staging);
    }
}

/// Remove every staging directory of this process (for a signal handler about to exit): the
/// output directories keep their earlier content. Waits for a commit in progress to end, so
/// that one is never cut short. Returns how many were removed.
///
/// The registry of staging directories stays locked after it returns, until the process exits:
/// the run can then neither stage, commit nor drop its outputs, so it cannot end first with an
/// error of its own about a file it lost (measured under load: a report.json being written into
/// the removed staging directory failed and the run exited with status 2, "No such file or
/// directory", before the handler's 143). Call it once, just before exiting.
pub fn discard_staged_outputs() -> usize {
    let (discarded, registry) = discard_where(|_| true);
    std::mem::forget(registry);
    discarded
}

/// Remove the staging directories that `which` selects; returns how many, and the registry
/// still locked.
fn discard_where(which: impl Fn(&Path) -> bool) -> (usize, MutexGuard<'static, Vec<PathBuf>>) {
    let mut registry = staged();
    let before = registry.len();
    registry.retain(|p| {
        if which(p) {
            remove_while_written(p);
            false
        } else {
            true
        }
    });
    (before - registry.len(), registry)
}

/// Remove the staging directory `p`, into which the run may be writing a file this moment (the
/// writes do not wait for the registry): a file it creates while the directory is emptied
/// leaves it not empty, so it is emptied again, a few times at most; once it is gone, no write
/// can create it again.
fn remove_while_written(p: &Path) {
    for _ in 0..20 {
        if fs::remove_dir_all(p).is_ok() || !p.exists() {
            return;
        }
    }
}

/// Check that `surface` can be written: every control point finite (in homogeneous and in
/// Cartesian form, `P = (wx, wy, wz) / w`), every weight finite and `w > 0`, both knot vectors
/// valid (finite, non-decreasing, clamped, with a non-empty domain: the rules of
/// [`KnotVector::try_new`], The NURBS Book 2.2), `n_u x n_v` control points, and a control net
/// whose diagonal `|max - min|` is finite. Every writer of a surface calls it before creating
/// any file.
///
/// # Errors
/// [`HullError::UnwritableSurface`] naming the first problem found and its place.
pub fn check_finite(surface: &NurbsSurface) -> Result<(), HullError> {
    let bad = |problem: String| Err(HullError::UnwritableSurface { problem });
    for (dir, knots) in [("u", surface.knots_u()), ("v", surface.knots_v())] {
        if let Err(e) = KnotVector::try_new(knots.degree(), knots.as_slice().to_vec()) {
            return bad(format!("the knot vector in {dir}: {e}"));
        }
    }
    let (nu, nv) = (surface.n_u(), surface.n_v());
    let cw = surface.homogeneous();
    if cw.len() != nu * nv {
        return bad(format!("{} control points for {nu} x {nv}", cw.len()));
    }
    for (k, h) in cw.iter().enumerate() {
        let (i, j) = (k / nv, k % nv);
        let w = h[3];
        if !(w.is_finite() && w > 0.0) {
            return bad(format!("the weight of control point ({i}, {j}) is {w}"));
        }
        let p = [h[0] / w, h[1] / w, h[2] / w];
        if !h.iter().chain(&p).all(|c| c.is_finite()) {
            return bad(format!("control point ({i}, {j}) is ({}, {}, {}) with weight {w}", p[0], p[1], p[2]));
        }
    }
    let (lo, hi) = surface.control_bounds();
    let diagonal = (hi - lo).norm();
    if !diagonal.is_finite() {
        return bad(format!(
            "the control net's diagonal overflows (from ({}, {}, {}) to ({}, {}, {}))",
            lo.x, lo.y, lo.z, hi.x, hi.y, hi.z
        ));
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;
    use nurbs::Vec3;

    #[test]
    fn failed_write_keeps_the_previous_file() {
        let dir = tempfile::tempdir().expect("temp dir");
        let p = dir.path().join("a.txt");
        write_atomic(&p, |w| w.write_all(b"first")).expect("write");
        let err = write_atomic(&p, |w| {
            w.write_all(b"partial")?;
            Err(io::Error::other("boom"))
        });
        assert!(err.is_err());
        assert_eq!(fs::read_to_string(&p).expect("read"), "first");
        // No temporary file is left behind.
        assert_eq!(fs::read_dir(dir.path()).expect("list").count(), 1);
        write_atomic(&p, |w| w.write_all(b"second")).expect("write");
        assert_eq!(fs::read_to_string(&p).expect("read"), "second");
    }

    /// The names in `dir`, sorted.
    fn names(dir: &Path) -> Vec<String> {
        let mut v: Vec<String> =
            fs::read_dir(dir).expect("list").map(|e| e.expect("entry").file_name().to_string_lossy().into()).collect();
        v.sort();
        v
    }

    #[test]
    fn commit_replaces_the_run_files_and_leaves_the_others() {
        let root = tempfile::tempdir().expect("temp dir");
        let out = root.path().join("out");
        fs::create_dir(&out).expect("mkdir");
        fs::write(out.join("a.txt"), "old a").expect("write");
        fs::write(out.join("mine.txt"), "not hullskin's").expect("write");
        let mut staged = OutputDir::stage(&out).expect("stage");
        let staging = staged.staging_path().to_path_buf();
        assert!(staging.is_dir() && staging.parent() == Some(root.path()), "{}", staging.display());
        assert_eq!(staged.write_bytes("a.txt", b"new a").expect("write"), out.join("a.txt"));
        staged.write_bytes("b.txt", b"new b").expect("write");
        // Nothing is visible before the commit.
        assert_eq!(fs::read_to_string(out.join("a.txt")).expect("read"), "old a");
        assert!(!out.join("b.txt").exists());
        let written = staged.commit().expect("commit");
        assert_eq!(written, vec![out.join("a.txt"), out.join("b.txt")]);
        assert_eq!(fs::read_to_string(out.join("a.txt")).expect("read"), "new a");
        assert_eq!(fs::read_to_string(out.join("b.txt")).expect("read"), "new b");
        assert_eq!(fs::read_to_string(out.join("mine.txt")).expect("read"), "not hullskin's");
        assert!(!staging.exists());
        assert_eq!(names(root.path()), vec!["out"]);
        assert_eq!(names(&out), vec!["a.txt", "b.txt", "mine.txt"]);
    }

    #[test]
    fn dropping_without_commit_removes_the_staging_and_changes_nothing() {
        let root = tempfile::tempdir().expect("temp dir");
        let out = root.path().join("out");
        fs::create_dir(&out).expect("mkdir");
        fs::write(out.join("a.txt"), "old a").expect("write");
        {
            let mut staged = OutputDir::stage(&out).expect("stage");
            staged.write_bytes("a.txt", b"new a").expect("write");
            let err = staged.write("b.txt", |w| {
                w.write_all(b"half")?;
                Err(io::Error::other("disk full"))
            });
            assert!(matches!(&err, Err(HullError::Io { path, .. }) if path == &out.join("b.txt")), "{err:?}");
        }
        assert_eq!(names(root.path()), vec!["out"]);
        assert_eq!(names(&out), vec!["a.txt"]);
        assert_eq!(fs::read_to_string(out.join("a.txt")).expect("read"), "old a");
        // A directory that did not exist is not created by a run that does not commit.
        let fresh = root.path().join("new/deeper");
        drop(OutputDir::stage(&fresh).expect("stage"));
        assert!(!fresh.exists());
        assert!(names(&root.path().join("new")).is_empty());
        // ... and is created by one that does.
        let mut staged = OutputDir::stage(&fresh).expect("stage");
        staged.write_bytes("x", b"1").expect("write");
        staged.commit().expect("commit");
        assert_eq!(names(&fresh), vec!["x"]);
    }

    #[test]
    fn bad_names_and_targets_are_refused_before_anything_moves() {
        let root = tempfile::tempdir().expect("temp dir");
        let out = root.path().join("out");
        let mut staged = OutputDir::stage(&out).expect("stage");
        for name in ["../x", "a/b", "", ".", ".."] {
            match staged.write_bytes(name, b"x") {
                Err(HullError::OutputName { name: refused }) => assert_eq!(refused, name),
                other => panic!("{name:?}: {other:?}"),
            }
        }
        // A file where the directory should be.
        let file = root.path().join("file");
        fs::write(&file, "f").expect("write");
        assert!(matches!(OutputDir::stage(&file), Err(HullError::Io { .. })));
        // A directory where a staged file should go: refused, and the other file not moved.
        fs::create_dir_all(out.join("b.txt")).expect("mkdir");
        staged.write_bytes("a.txt", b"a").expect("write");
        staged.write_bytes("b.txt", b"b").expect("write");
        assert!(matches!(staged.commit(), Err(HullError::Io { .. })));
        assert_eq!(names(&out), vec!["b.txt"]);
        assert_eq!(names(root.path()), vec!["file", "out"]);
    }

    #[test]
    fn discarded_outputs_are_not_committed() {
        let root = tempfile::tempdir().expect("temp dir");
        let out = root.path().join("out");
        let mut staged = OutputDir::stage(&out).expect("stage");
        staged.write_bytes("a.txt", b"a").expect("write");
        // What a signal handler does, limited to this run (other tests stage at the same time).
        let mine = staged.staging_path().to_path_buf();
        assert_eq!(discard_where(|p| p == mine).0, 1);
        assert!(!staged.staging_path().exists());
        assert!(staged.commit().is_err());
        assert!(names(&out).is_empty(), "the directory is created, and stays empty");
    }

    /// A bilinear patch on the unit square with weights `w` (u-major).
    fn patch(points: [Vec3; 4], w: [f64; 4]) -> NurbsSurface {
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("knots");
        NurbsSurface::try_new(k.clone(), k, &points, Some(&w)).expect("valid patch")
    }

    #[test]
    fn finite_surfaces_pass_and_overflowing_ones_are_refused() {
        let square =
            [Vec3::new(0.0, 0.0, 0.0), Vec3::new(0.0, 1.0, 0.0), Vec3::new(1.0, 0.0, 0.0), Vec3::new(1.0, 1.0, 1.0)];
        assert!(check_finite(&patch(square, [1.0, 2.0, 0.5, 1.0])).is_ok());
        // Homogeneous coordinates the kernel accepts (all finite, w > 0) whose Cartesian
        // point 1e308 / 1e-10 overflows to infinity.
        let k = KnotVector::try_new(1, vec![0.0, 0.0, 1.0, 1.0]).expect("knots");
        let mut cw = vec![[0.0, 0.0, 0.0, 1.0], [0.0, 1.0, 0.0, 1.0], [1.0, 0.0, 0.0, 1.0], [1.0, 1.0, 1.0, 1.0]];
        cw[2] = [1e308, 0.0, 0.0, 1e-10];
        let s = NurbsSurface::try_from_homogeneous(k.clone(), k, cw).expect("the kernel accepts it");
        let err = check_finite(&s).expect_err("refused").to_string();
        assert!(err.contains("control point (1, 0)") && err.contains("inf"), "{err}");
        // Finite coordinates whose differences overflow: |1e300 - (-1e300)| = inf.
        let mut wide = square;
        wide[0] = Vec3::new(-1e300, 0.0, 0.0);
        wide[3] = Vec3::new(1e300, 1.0, 1.0);
        let err = check_finite(&patch(wide, [1.0; 4])).expect_err("refused").to_string();
        assert!(err.contains("diagonal overflows") && err.contains("expected finite"), "{err}");
        // The fitted sample passes.
        let fit = crate::fit_offsets(&crate::series60_sample(), &crate::FitConfig::default()).expect("fits");
        assert!(check_finite(&fit.surface).is_ok());
    }
}
