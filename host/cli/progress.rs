//! Progress display for long commands.

use std::time::{Duration, Instant};

/// A progress bar that appears only once the work has taken over a second.
pub struct DelayedProgress {
    bar: indicatif::ProgressBar,
    start: Instant,
    shown: bool,
}

impl DelayedProgress {
    pub fn new(what: &str) -> Self {
        let bar = indicatif::ProgressBar::hidden();
        if let Ok(style) = indicatif::ProgressStyle::with_template("{msg} [{bar:40}] {percent}% {elapsed} (eta {eta})") {
            bar.set_style(style.progress_chars("=> "));
        }
        bar.set_message(what.to_string());
        Self { bar, start: Instant::now(), shown: false }
    }
    pub fn update(&mut self, done: u64, total: u64) {
        if !self.shown && self.start.elapsed() > Duration::from_secs(1) {
            self.bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
            self.shown = true;
        }
        self.bar.set_length(total);
        self.bar.set_position(done);
    }
    pub fn finish(&self) {
        self.bar.finish_and_clear();
    }
}
