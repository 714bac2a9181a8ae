//! Long library calls run without the GIL and stop on Ctrl-C: the call runs on a worker
//! thread while the calling thread waits with the GIL released, waking every 100 ms to let
//! Python run its signal handlers. On `KeyboardInterrupt` (or any exception a handler raises)
//! the library's stop flag is raised, the call ends at the end of its current iteration (the
//! weight optimisers and the held-out refits poll it; a plain least-squares fit finishes, it
//! takes milliseconds), and the exception propagates.

use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::mpsc;
use std::time::Duration;

use hull::Control;
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;

/// How often the waiting thread looks at Python's signals.
const POLL: Duration = Duration::from_millis(100);

/// Run `f` with a [`Control`] whose stop flag Ctrl-C raises, without holding the GIL.
///
/// # Errors
/// The exception of a signal handler (`KeyboardInterrupt`), or a `RuntimeError` if `f`
/// panicked (a library bug: the panic's message is kept).
pub fn run<R: Send>(py: Python<'_>, f: impl FnOnce(&Control<'_>) -> R + Send) -> PyResult<R> {
    let stop = AtomicBool::new(false);
    std::thread::scope(|scope| {
        let (done, finished) = mpsc::channel::<()>();
        let stop = &stop;
        let worker = scope.spawn(move || {
            let control = Control { stop, progress: &|_| {} };
            let out = f(&control);
            let _ = done.send(());
            out
        });
        let mut interrupt: Option<PyErr> = None;
        let mut finished = finished;
        loop {
            // The receiver goes into the GIL-free closure and comes back (it is Send, not Sync).
            let (waited, rx) = py.detach(move || (finished.recv_timeout(POLL), finished));
            finished = rx;
            match waited {
                Ok(()) | Err(mpsc::RecvTimeoutError::Disconnected) => break,
                Err(mpsc::RecvTimeoutError::Timeout) => {
                    if interrupt.is_none() {
                        if let Err(e) = py.check_signals() {
                            stop.store(true, Ordering::SeqCst);
                            interrupt = Some(e);
                        }
                    }
                }
            }
        }
        let out = py.detach(|| worker.join());
        match (out, interrupt) {
            (_, Some(e)) => Err(e),
            (Ok(r), None) => Ok(r),
            (Err(panic), None) => {
                let what = panic
                    .downcast_ref::<&str>()
                    .map(|s| s.to_string())
                    .or_else(|| panic.downcast_ref::<String>().cloned())
                    .unwrap_or_else(|| "unknown panic".into());
                Err(PyRuntimeError::new_err(format!("hullskin panicked (a bug, please report it): {what}")))
            }
        }
    })
}
