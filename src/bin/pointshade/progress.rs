//! The progress bar of long renders: the library's [`Progress`] drawn with indicatif.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use pointshade::render::progress::{Advance, Progress, ProgressUnit};

/// A bar on stderr that appears only for renders longer than about a second, only on a
/// terminal, and never with --quiet.
pub struct Bar {
    bar: ProgressBar,
    start: Instant,
    enabled: bool,
    shown: AtomicBool,
}

impl Bar {
    /// A bar, hidden until the render has taken a second.
    pub fn new(quiet: bool) -> Self {
        Self {
            bar: ProgressBar::with_draw_target(None, ProgressDrawTarget::hidden()),
            start: Instant::now(),
            enabled: !quiet && std::io::stderr().is_terminal(),
            shown: AtomicBool::new(false),
        }
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}

impl Progress for Bar {
    fn advance(&self, advance: Advance) {
        if !self.enabled || self.start.elapsed() < Duration::from_secs(1) {
            return;
        }
        if !self.shown.swap(true, Ordering::Relaxed) {
            let template = match advance.unit {
                ProgressUnit::BudgetMilliseconds => "{bar:40} {percent:>3}% of the time budget",
                ProgressUnit::Tiles => "{bar:40} {percent:>3}% tiles {pos}/{len} eta {eta}",
            };
            if let Ok(style) = ProgressStyle::with_template(template) {
                self.bar.set_style(style);
            }
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        self.bar.set_length(advance.total);
        self.bar.set_position(advance.done);
    }
}
