//! A progress bar for long optimisations and a Ctrl-C handler that stops them: the search ends
//! at the end of its current iteration and the best surface so far is written.

use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use hull::optimize::{Control, Progress};
use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

/// Raised by Ctrl-C (SIGINT) or SIGTERM.
pub static STOP: AtomicBool = AtomicBool::new(false);

/// Install the handler once; a second Ctrl-C while stopping exits at once (status 130).
pub fn install_stop_handler() {
    static INSTALLED: AtomicBool = AtomicBool::new(false);
    if INSTALLED.swap(true, Ordering::SeqCst) {
        return;
    }
    let _ = ctrlc::set_handler(|| {
        if STOP.swap(true, Ordering::SeqCst) {
            std::process::exit(130);
        }
        eprintln!("\nhullskin: stopping: the best surface so far will be written (Ctrl-C again to quit now)");
    });
}

/// True if a stop was requested.
pub fn stopped() -> bool {
    STOP.load(Ordering::SeqCst)
}

/// Run `f` with a [`Control`] that draws a progress bar on stderr (hidden when stderr is not a
/// terminal) and stops on Ctrl-C.
pub fn with_progress<R>(label: &str, f: impl FnOnce(&Control<'_>) -> R) -> R {
    install_stop_handler();
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
    let out = f(&control);
    bar.finish_and_clear();
    out
}
