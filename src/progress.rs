//! Progress on standard error for work that takes more than a moment: bars over counted steps
//! (tiles, frames, figure cells, report records) and spinners over one long step (building a
//! surface, measuring it). They are drawn only when standard error is a terminal and `--quiet`
//! was not given ([`set_quiet`]), so pipes, logs and tests never see them, and they clear
//! themselves when the work is done: what stays on the terminal is the command's own output.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::Duration;

use indicatif::{ProgressBar, ProgressFinish, ProgressStyle};

/// Set by `--quiet`: no progress is drawn for the rest of the process.
static QUIET: AtomicBool = AtomicBool::new(false);

/// Turns every progress bar and spinner of this process off (`quiet = true`) or back on.
/// Warnings and errors are not progress: they are printed either way.
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether progress is drawn: standard error is a terminal and `--quiet` was not given.
pub(crate) fn shown() -> bool {
    !QUIET.load(Ordering::Relaxed) && std::io::stderr().is_terminal()
}

/// A bar over `len` steps drawn with the indicatif `template` (e.g.
/// `"render {bar:40} {percent:>3}% {elapsed}"`), or a hidden bar when progress is not
/// [`shown`]. It clears itself when finished or dropped (also on an error path).
pub(crate) fn bar(len: u64, template: &str) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let bar = ProgressBar::new(len).with_finish(ProgressFinish::AndClear);
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style);
    }
    bar
}

/// A spinner saying `message` while one long step runs (ticking by itself), or a hidden one
/// when progress is not [`shown`]. It clears itself when finished or dropped.
pub(crate) fn spinner(message: String) -> ProgressBar {
    if !shown() {
        return ProgressBar::hidden();
    }
    let spinner = ProgressBar::new_spinner().with_finish(ProgressFinish::AndClear);
    if let Ok(style) = ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
        spinner.set_style(style);
    }
    spinner.set_message(message);
    spinner.enable_steady_tick(Duration::from_millis(120));
    spinner
}

#[cfg(test)]
mod tests {
    /// Under `cargo test` standard error is captured or piped, never a terminal here, so
    /// nothing may be drawn; `--quiet` hides progress whatever standard error is.
    #[test]
    fn nothing_is_drawn_off_a_terminal_or_when_quiet() {
        use std::io::IsTerminal;
        if !std::io::stderr().is_terminal() {
            assert!(!super::shown());
            assert!(super::bar(10, "{bar}").is_hidden());
            assert!(super::spinner("building".into()).is_hidden());
        }
        super::set_quiet(true);
        assert!(!super::shown());
        assert!(super::bar(10, "{bar}").is_hidden());
        super::set_quiet(false);
    }
}
