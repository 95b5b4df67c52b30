//! What a long command shows while it works: on a terminal a progress bar that fits 80
//! columns (drawn once the work has taken over a second), elsewhere (CI logs, nohup) one plain
//! line every few seconds, and nothing with `--quiet`.

use std::io::IsTerminal as _;
use std::time::{Duration, Instant};

/// Seconds between plain progress lines when stderr is not a terminal.
const LINE_INTERVAL_S: u64 = 5;
/// The bar appears only for work that takes longer than this.
const BAR_DELAY_S: u64 = 1;
/// Width of the bar in characters: with the longest status it leaves the line within 80.
const BAR_WIDTH: usize = 16;

/// Where a piece of work stands.
#[derive(Debug, Clone, Copy, PartialEq, Default)]
pub struct Status {
    /// 0 to 1.
    pub fraction: f64,
    /// Where the work stood when this process took it up (a resumed run's share already done):
    /// the ETA is the time so far over the progress made since.
    pub start_fraction: f64,
    /// Done and total of a countable unit, with its name ("spp", "tiles").
    pub count: Option<(u64, Option<u64>, &'static str)>,
    pub rays_per_second: Option<f64>,
    /// The running error estimate.
    pub relmse: Option<f64>,
}

enum Mode {
    Quiet,
    Bar { bar: indicatif::ProgressBar, shown: bool },
    Lines { last: Instant },
}

/// The progress display of one piece of work.
pub struct Progress {
    mode: Mode,
    what: &'static str,
    start: Instant,
}

/// `1234567` as `1.23M`: three significant digits.
fn si(x: f64) -> String {
    let (v, unit) = if x >= 1e9 {
        (x / 1e9, "G")
    } else if x >= 1e6 {
        (x / 1e6, "M")
    } else if x >= 1e3 {
        (x / 1e3, "k")
    } else {
        (x, "")
    };
    let digits = if v >= 100.0 {
        0
    } else if v >= 10.0 {
        1
    } else {
        2
    };
    format!("{v:.digits$}{unit}")
}

/// Seconds as `12s`, `3m05s` or `2h14m`.
fn duration(s: f64) -> String {
    let s = s.max(0.0).round() as u64;
    if s < 60 {
        format!("{s}s")
    } else if s < 3600 {
        format!("{}m{:02}s", s / 60, s % 60)
    } else {
        format!("{}h{:02}m", s / 3600, s % 3600 / 60)
    }
}

impl Status {
    /// The status after `seconds`: percentage, count, ETA, rays/s and error estimate, the short
    /// way (for the bar's line) or the long way (for a log).
    pub fn describe(&self, seconds: f64, long: bool) -> String {
        let f = self.fraction.clamp(0.0, 1.0);
        let mut parts = vec![format!("{:>3.0}%", 100.0 * f)];
        if let Some((done, total, unit)) = self.count {
            parts.push(match total {
                Some(t) => format!("{done}/{t} {unit}"),
                None => format!("{done} {unit}"),
            });
        }
        if long {
            parts.push(duration(seconds));
        }
        let made = f - self.start_fraction.clamp(0.0, 1.0);
        if made > 0.0 && f < 1.0 {
            parts.push(format!("ETA {}", duration(seconds * (1.0 - f) / made)));
        }
        if let Some(r) = self.rays_per_second {
            parts.push(format!("{} rays/s", si(r)));
        }
        if let Some(e) = self.relmse {
            parts.push(format!("{} {e:.1e}", if long { "est. relMSE" } else { "err" }));
        }
        parts.join(if long { ", " } else { " " })
    }
}

impl Progress {
    /// Progress of `what` ("rendering"), shown on stderr unless `quiet`.
    pub fn new(what: &'static str, quiet: bool) -> Self {
        let mode = if quiet {
            Mode::Quiet
        } else if std::io::stderr().is_terminal() {
            let bar = indicatif::ProgressBar::hidden();
            let template = format!("[{{bar:{BAR_WIDTH}}}] {{msg}}");
            if let Ok(style) = indicatif::ProgressStyle::with_template(&template) {
                bar.set_style(style.progress_chars("=> "));
            }
            bar.set_length(1000);
            Mode::Bar { bar, shown: false }
        } else {
            Mode::Lines { last: Instant::now() }
        };
        Self { mode, what, start: Instant::now() }
    }

    pub fn update(&mut self, status: &Status) {
        let seconds = self.start.elapsed().as_secs_f64();
        match &mut self.mode {
            Mode::Quiet => {}
            Mode::Bar { bar, shown } => {
                if !*shown && self.start.elapsed() > Duration::from_secs(BAR_DELAY_S) {
                    bar.set_draw_target(indicatif::ProgressDrawTarget::stderr());
                    *shown = true;
                }
                bar.set_position((status.fraction.clamp(0.0, 1.0) * 1000.0) as u64);
                bar.set_message(status.describe(seconds, false));
            }
            Mode::Lines { last } => {
                if last.elapsed() >= Duration::from_secs(LINE_INTERVAL_S) {
                    eprintln!("{}: {}", self.what, status.describe(seconds, true));
                    *last = Instant::now();
                }
            }
        }
    }

    pub fn finish(&self) {
        if let Mode::Bar { bar, .. } = &self.mode {
            bar.finish_and_clear();
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The bar's line, with its longest plausible status, fits an 80-column terminal.
    #[test]
    fn the_bar_line_fits_80_columns() {
        let s = Status {
            fraction: 0.4567,
            start_fraction: 0.0,
            count: Some((123_456, Some(999_999), "spp")),
            rays_per_second: Some(987.65e9),
            relmse: Some(1.234e-10),
        };
        let line = format!("[{}] {}", "=".repeat(BAR_WIDTH), s.describe(86_399.0, false));
        assert!(line.chars().count() <= 80, "{} columns: {line}", line.chars().count());
        let long = s.describe(12.3, true);
        assert!(long.contains("46%") && long.contains("ETA") && long.contains("rays/s") && long.contains("relMSE"), "{long}");
    }

    /// A resumed run's ETA counts only the progress this run made: 500 of 1024 spp resumed,
    /// 530 reached in 5 s is 30 spp in 5 s, so 494 to go take about 82 s (it said 5 s, the
    /// rate of all 530 samples).
    #[test]
    fn a_resumed_run_s_eta_counts_its_own_progress() {
        let s = Status { fraction: 530.0 / 1024.0, start_fraction: 500.0 / 1024.0, count: Some((530, Some(1024), "spp")), ..Status::default() };
        assert!(s.describe(5.0, true).contains("ETA 1m22s"), "{}", s.describe(5.0, true));
        let fresh = Status { start_fraction: 0.0, ..s };
        assert!(fresh.describe(5.0, true).contains("ETA 5s"), "{}", fresh.describe(5.0, true));
        let nothing_yet = Status { fraction: s.start_fraction, ..s };
        assert!(!nothing_yet.describe(5.0, true).contains("ETA"), "{}", nothing_yet.describe(5.0, true));
    }
}
