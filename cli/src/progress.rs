//! The one progress bar of `ccss`, used by every long-running verb
//! (`voxelize`, `tessellate`, `bench eval`, `bench tessellate`).
//!
//! The bar is drawn on stderr, and only when stderr is a terminal: pipes,
//! files and tests never see it, and stdout is never touched. It appears
//! either at once ([`Progress::new`], for work the caller knows to be long)
//! or only after a phase has run for half a second ([`Progress::delayed`],
//! for work whose length is not known beforehand). Steps may be counted
//! from any thread.

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};
use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

/// How long a delayed bar stays hidden.
const DELAY: Duration = Duration::from_millis(500);

/// A progress bar on stderr (hidden when stderr is not a terminal).
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    /// A delayed bar not drawn yet (on a terminal).
    pending: AtomicBool,
}

/// `bar` with `template` (indicatif syntax) and the `=> ` bar characters.
fn styled(bar: ProgressBar, template: &str) -> ProgressBar {
    if let Ok(style) = ProgressStyle::with_template(template) {
        bar.set_style(style.progress_chars("=> "));
    }
    bar
}

impl Progress {
    /// A bar of `len` steps, drawn at once when `long` (the caller expects
    /// the work to take a while) and stderr is a terminal; hidden otherwise.
    pub fn new(template: &str, len: u64, long: bool) -> Progress {
        let target = if long && std::io::stderr().is_terminal() {
            ProgressDrawTarget::stderr()
        } else {
            ProgressDrawTarget::hidden()
        };
        Progress {
            bar: styled(ProgressBar::with_draw_target(Some(len), target), template),
            start: Instant::now(),
            pending: AtomicBool::new(false),
        }
    }

    /// A bar that shows itself only after half a second, on a terminal;
    /// [`Progress::phase`] gives each phase its message and length.
    pub fn delayed(template: &str) -> Progress {
        let bar = ProgressBar::with_draw_target(Some(1), ProgressDrawTarget::hidden());
        Progress {
            bar: styled(bar, template),
            start: Instant::now(),
            pending: AtomicBool::new(std::io::stderr().is_terminal()),
        }
    }

    /// Starts a phase of `len` steps, named `msg` (the `{msg}` of the
    /// template).
    pub fn phase(&self, msg: &'static str, len: usize) {
        self.bar.set_message(msg);
        self.bar.set_length(len as u64);
        self.bar.set_position(0);
    }

    /// Sets the `{msg}` of the template.
    pub fn message(&self, msg: String) {
        self.bar.set_message(msg);
    }

    /// One step done.
    pub fn inc(&self) {
        self.bar.inc(1);
        if self.pending.load(Ordering::Relaxed)
            && self.start.elapsed() > DELAY
            && self.pending.swap(false, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
    }

    /// Runs `f` (which may print) with the bar cleared, then redraws it.
    pub fn suspend<R>(&self, f: impl FnOnce() -> R) -> R {
        self.bar.suspend(f)
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
