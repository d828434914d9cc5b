//! A progress bar for long renders.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use pointshade::scene;

/// A progress bar on stderr that appears only for renders longer than about a second, only on a
/// terminal, and never with --quiet.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    enabled: bool,
    shown: AtomicBool,
    /// The bar counts milliseconds of a time budget, not tiles.
    budget: bool,
}

impl Progress {
    /// A bar over the tiles of `scene`, or over its time budget in milliseconds, hidden until
    /// the render has taken a second.
    pub fn new(scene: &scene::Scene, quiet: bool) -> Self {
        let (length, template) = match scene.film.time_budget {
            Some(budget) => (
                (budget as f64 * 1e3) as u64,
                "{bar:40} {percent:>3}% of the time budget",
            ),
            None => (
                (scene.film.width.div_ceil(16) * scene.film.height.div_ceil(16)) as u64,
                "{bar:40} {percent:>3}% tiles {pos}/{len} eta {eta}",
            ),
        };
        let bar = ProgressBar::with_draw_target(Some(length), ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template(template) {
            bar.set_style(style);
        }
        Self {
            budget: scene.film.time_budget.is_some(),
            bar,
            start: Instant::now(),
            enabled: !quiet && std::io::stderr().is_terminal(),
            shown: AtomicBool::new(false),
        }
    }

    /// Records that `done` tiles are finished.
    pub fn tick(&self, done: u64) {
        if self.enabled
            && !self.shown.load(Ordering::Relaxed)
            && self.start.elapsed() > Duration::from_secs(1)
            && !self.shown.swap(true, Ordering::Relaxed)
        {
            self.bar.set_draw_target(ProgressDrawTarget::stderr());
        }
        let position = match self.budget {
            true => self.start.elapsed().as_millis() as u64,
            false => done,
        };
        self.bar.set_position(position);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
