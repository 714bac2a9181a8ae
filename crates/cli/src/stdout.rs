//! Standard output, where the summaries and tables go: a reader that has gone away
//! (`hullskin fit | head -1`) ends the printing, not the run (the files are still written),
//! and a write that fails otherwise (a full disk) is reported once at the end with a non-zero
//! exit, never as a panic as `println!` would.

use std::io::{self, Write};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Mutex;

/// Set once standard output has failed: nothing more is written to it.
static CLOSED: AtomicBool = AtomicBool::new(false);
/// The first failure other than a closed pipe, for [`failure`].
static FAILURE: Mutex<Option<String>> = Mutex::new(None);

/// Write `args` to standard output (the body of [`out!`] and [`outln!`]).
pub(crate) fn write(args: std::fmt::Arguments<'_>) {
    if CLOSED.load(Ordering::Relaxed) {
        return;
    }
    let mut out = io::stdout().lock();
    if let Err(e) = out.write_fmt(args).and_then(|()| out.flush()) {
        CLOSED.store(true, Ordering::Relaxed);
        if e.kind() != io::ErrorKind::BrokenPipe {
            let mut first = FAILURE.lock().unwrap_or_else(|p| p.into_inner());
            first.get_or_insert_with(|| e.to_string());
        }
    }
}

/// Why standard output could not be written, if it could not (a closed pipe is not a failure:
/// the reader asked for no more).
pub(crate) fn failure() -> Option<String> {
    FAILURE.lock().unwrap_or_else(|p| p.into_inner()).clone()
}

/// `print!` to standard output through [`write()`].
macro_rules! out {
    ($($arg:tt)*) => { $crate::stdout::write(format_args!($($arg)*)) };
}

/// `println!` to standard output through [`write()`].
macro_rules! outln {
    () => { $crate::stdout::write(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::stdout::write(format_args!("{}\n", format_args!($($arg)*))) };
}

pub(crate) use {out, outln};
