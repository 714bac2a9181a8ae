//! A progress bar for long optimisations, and what SIGINT (Ctrl-C) and SIGTERM do.
//!
//! While an optimisation runs (inside [`with_progress`] or [`stoppable`]) the first signal
//! asks it to stop: the search ends at the end of its current iteration, the best surface so
//! far is measured and written, and the command exits with status 128 + the signal's number:
//! 130 for SIGINT, 143 for SIGTERM ([`stop_status`]). Any other signal (a second one, or one
//! while nothing can stop early, e.g. while the outputs are written) quits at once with the
//! same status: the outputs being staged are discarded ([`hull::discard_staged_outputs`], which
//! waits for a commit in progress to end and then holds the run until the exit, so that it
//! cannot end first with an error of its own), so an output directory holds its earlier
//! results or the complete new ones, never a mix of a half-done run.
//!
//! On Unix the signals are told apart with `signal-hook`; elsewhere `ctrlc` (with its
//! `termination` feature) reports both as an interrupt, status 130.

use std::sync::atomic::{AtomicBool, AtomicI32, AtomicUsize, Ordering};
use std::time::Duration;

use hull::{Control, Progress};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Raised by the first SIGINT or SIGTERM during an optimisation.
pub static STOP: AtomicBool = AtomicBool::new(false);

/// The number of the signal that raised [`STOP`] (0: none).
static SIGNAL: AtomicI32 = AtomicI32::new(0);

/// How many [`stoppable`] sections are running (nested sections count once each).
static STOPPABLE: AtomicUsize = AtomicUsize::new(0);

/// SIGINT's number (POSIX), the status of a stop where signals are not told apart.
const SIGINT: i32 = 2;
/// SIGTERM's number (POSIX).
#[cfg(test)]
const SIGTERM: i32 = 15;

/// The signal's name for messages.
fn signal_name(signal: i32) -> &'static str {
    match signal {
        2 => "SIGINT (Ctrl-C)",
        15 => "SIGTERM",
        _ => "a signal",
    }
}

/// The exit status after `signal`: 128 + its number (the shells' convention), clamped to a
/// byte.
fn status_of(signal: i32) -> u8 {
    u8::try_from(128 + signal.clamp(1, 127)).unwrap_or(130)
}

/// What a signal does: stop an optimisation the first time, else quit now.
fn on_signal(signal: i32) {
    if STOPPABLE.load(Ordering::SeqCst) > 0 && !STOP.swap(true, Ordering::SeqCst) {
        SIGNAL.store(signal, Ordering::SeqCst);
        eprintln!(
            "\nhullskin: stopping on {}: the search ends its iteration and its best surface so far is kept (send it \
             again to quit now)",
            signal_name(signal)
        );
        return;
    }
    let discarded = hull::discard_staged_outputs();
    let what =
        if discarded > 0 { "; the outputs being written were discarded, earlier results are untouched" } else { "" };
    eprintln!("\nhullskin: quit on {}{what}", signal_name(signal));
    std::process::exit(i32::from(status_of(signal)));
}

/// Install the handler of SIGINT and SIGTERM once (later calls do nothing). Outside a
/// [`stoppable`] section a signal quits at once, discarding staged outputs.
pub fn install_stop_handler() {
    static INSTALLED: AtomicBool = AtomicBool::new(false);
    if INSTALLED.swap(true, Ordering::SeqCst) {
        return;
    }
    install();
}

#[cfg(unix)]
fn install() {
    use signal_hook::consts::{SIGINT, SIGTERM};
    use signal_hook::iterator::Signals;
    match Signals::new([SIGINT, SIGTERM]) {
        Ok(mut signals) => {
            let spawned = std::thread::Builder::new().name("signals".into()).spawn(move || {
                for signal in signals.forever() {
                    on_signal(signal);
                }
            });
            if let Err(e) = spawned {
                eprintln!("hullskin: warning: cannot watch for SIGINT and SIGTERM: {e}");
            }
        }
        Err(e) => eprintln!("hullskin: warning: cannot install the SIGINT and SIGTERM handler: {e}"),
    }
}

#[cfg(not(unix))]
fn install() {
    if let Err(e) = ctrlc::set_handler(|| on_signal(SIGINT)) {
        eprintln!("hullskin: warning: cannot install the Ctrl-C handler: {e}");
    }
}

/// Run `f` as a section that a first SIGINT or SIGTERM stops (by raising [`STOP`], which the
/// optimisers poll) instead of quitting.
pub fn stoppable<R>(f: impl FnOnce() -> R) -> R {
    struct Section;
    impl Drop for Section {
        fn drop(&mut self) {
            STOPPABLE.fetch_sub(1, Ordering::SeqCst);
        }
    }
    install_stop_handler();
    STOPPABLE.fetch_add(1, Ordering::SeqCst);
    let _section = Section;
    f()
}

/// True if a stop was requested.
pub fn stopped() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// The exit status after a stop: 130 for SIGINT, 143 for SIGTERM; `None` without a stop.
pub fn stop_status() -> Option<u8> {
    if !stopped() {
        return None;
    }
    match SIGNAL.load(Ordering::SeqCst) {
        0 => Some(status_of(SIGINT)),
        s => Some(status_of(s)),
    }
}

/// Run `f` with a [`Control`] that draws a progress bar on stderr (hidden when stderr is not a
/// terminal) and stops on SIGINT or SIGTERM, in a [`stoppable`] section.
pub fn with_progress<R>(label: &str, f: impl FnOnce(&Control<'_>) -> R) -> R {
    let bar = ProgressBar::with_draw_target(Some(0), ProgressDrawTarget::stderr_with_hz(10));
    bar.set_style(
        ProgressStyle::with_template("{prefix} [{bar:30}] {pos}/{len} it  best {msg}  {elapsed} (eta {eta})")
            .unwrap_or_else(|_| ProgressStyle::default_bar())
            .progress_chars("=> "),
    );
    bar.set_prefix(label.to_string());
    bar.enable_steady_tick(Duration::from_millis(200));
    let progress = |p: Progress| {
        bar.set_length(p.iterations as u64);
        bar.set_position(p.iteration as u64);
        bar.set_message(format!("{:.4e}", p.best));
    };
    let control = Control { stop: &STOP, progress: &progress };
    let out = stoppable(|| f(&control));
    bar.finish_and_clear();
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statuses_follow_the_shell_convention() {
        // 128 + the signal's number: what a shell reports for a process killed by it.
        assert_eq!(status_of(SIGINT), 130);
        assert_eq!(status_of(SIGTERM), 143);
        assert_eq!(signal_name(SIGTERM), "SIGTERM");
        // Out-of-range numbers still give a status above 128.
        assert!(status_of(0) > 128 && status_of(1000) > 128);
    }

    #[test]
    fn sections_nest_and_end_even_on_a_panic() {
        // Other tests of this binary may run sections at the same time: compare with the
        // count seen inside.
        let inner = stoppable(|| {
            let outer = STOPPABLE.load(Ordering::SeqCst);
            let nested = stoppable(|| STOPPABLE.load(Ordering::SeqCst));
            (outer, nested)
        });
        assert!(inner.0 >= 1 && inner.1 >= 2, "{inner:?}");
        let r = std::panic::catch_unwind(|| stoppable(|| panic!("boom")));
        assert!(r.is_err());
        assert!(!stopped(), "no signal was sent");
        assert_eq!(stop_status(), None);
    }
}
