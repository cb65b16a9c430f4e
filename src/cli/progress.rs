//! Progress bars that appear only for work that takes over a second.

use std::time::{Duration, Instant};

use indicatif::{ProgressBar, ProgressStyle};

/// A progress bar that stays hidden unless the work is still running after one second.
pub struct LazyProgress {
    started: Instant,
    total: u64,
    message: &'static str,
    bar: Option<ProgressBar>,
}

impl LazyProgress {
    /// A bar for `total` steps described by `message`.
    pub fn new(total: u64, message: &'static str) -> Self {
        LazyProgress {
            started: Instant::now(),
            total,
            message,
            bar: None,
        }
    }

    /// Reports that `done` steps are complete.
    pub fn set(&mut self, done: u64) {
        if let Some(bar) = &self.bar {
            bar.set_position(done);
        } else if done.is_multiple_of(256) && self.started.elapsed() > Duration::from_secs(1) {
            let bar = ProgressBar::new(self.total).with_message(self.message);
            bar.set_style(
                ProgressStyle::with_template("{msg} [{bar:40}] {pos}/{len} ({elapsed}, ETA {eta})")
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            bar.set_position(done);
            self.bar = Some(bar);
        }
    }

    /// Removes the bar, if shown.
    pub fn finish(&self) {
        if let Some(bar) = &self.bar {
            bar.finish_and_clear();
        }
    }
}
