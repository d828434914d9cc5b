//! A progress bar for long renders.

use std::io::IsTerminal;
use std::sync::atomic::{AtomicBool, Ordering};
use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressDrawTarget, ProgressStyle};

use crate::scene;

/// A progress bar on stderr that appears only for renders longer than about a second, only on a
/// terminal, and never with --quiet.
pub struct Progress {
    bar: ProgressBar,
    start: Instant,
    enabled: bool,
    shown: AtomicBool,
}

impl Progress {
    /// A bar over the tiles of `scene`, hidden until the render has taken a second.
    pub fn new(scene: &scene::Scene, quiet: bool) -> Self {
        let tiles = (scene.film.width.div_ceil(16) * scene.film.height.div_ceil(16)) as u64;
        let bar = ProgressBar::with_draw_target(Some(tiles), ProgressDrawTarget::hidden());
        if let Ok(style) = ProgressStyle::with_template("{bar:40} {percent:>3}% tiles {pos}/{len} eta {eta}") {
            bar.set_style(style);
        }
        Self {
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
        self.bar.set_position(done);
    }

    /// Removes the bar.
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
