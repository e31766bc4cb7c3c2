//! Progress of a run: a bar on a terminal, plain log lines otherwise.

use indicatif::{ProgressBar, ProgressStyle};
use std::io::IsTerminal;
use std::time::{Duration, Instant};

const LOG_EVERY: Duration = Duration::from_secs(5);
const BAR_EVERY: Duration = Duration::from_millis(100);

pub struct Progress {
    name: String,
    t0: f64,
    t_end: f64,
    started: Instant,
    last: Instant,
    bar: Option<ProgressBar>,
    /// Implicit coupling: the last window's tries and their mean so far.
    tries: Option<(f64, f64)>,
}

impl Progress {
    pub fn new(name: &str, t0: f64, t_end: f64) -> Progress {
        let bar = std::io::stderr().is_terminal().then(|| {
            let bar = ProgressBar::new(1000);
            bar.set_style(
                ProgressStyle::with_template("{prefix} [{bar:30}] {msg}")
                    .unwrap_or_else(|_| ProgressStyle::default_bar())
                    .progress_chars("=> "),
            );
            bar.set_prefix(name.to_string());
            bar
        });
        let now = Instant::now();
        Progress {
            name: name.to_string(),
            t0,
            t_end,
            started: now,
            last: now,
            bar,
            tries: None,
        }
    }

    /// The last window's tries and the mean over the windows so far.
    pub fn set_tries(&mut self, last: f64, mean: f64) {
        self.tries = Some((last, mean));
    }

    fn line(&self, t: f64, steps: u64) -> String {
        let elapsed = self.started.elapsed().as_secs_f64();
        let rate = steps as f64 / elapsed.max(1e-9);
        let done = ((t - self.t0) / (self.t_end - self.t0)).clamp(0.0, 1.0);
        let eta = if done > 0.0 {
            elapsed * (1.0 - done) / done
        } else {
            f64::NAN
        };
        let tries = match self.tries {
            Some((last, mean)) => format!(", {last:.0} tries/window (mean {mean:.2})"),
            None => String::new(),
        };
        format!(
            "t = {t:.4}/{:.4} s, {rate:.0} windows/s{tries}, ETA {eta:.0} s",
            self.t_end
        )
    }

    /// Report that simulated time `t` is reached after `steps` windows.
    pub fn update(&mut self, t: f64, steps: u64) {
        let every = if self.bar.is_some() {
            BAR_EVERY
        } else {
            LOG_EVERY
        };
        if self.last.elapsed() < every {
            return;
        }
        self.last = Instant::now();
        let msg = self.line(t, steps);
        match &self.bar {
            Some(bar) => {
                bar.set_position((1000.0 * (t - self.t0) / (self.t_end - self.t0)) as u64);
                bar.set_message(msg);
            }
            None => eprintln!("[{}] {msg}", self.name),
        }
    }

    pub fn finish(&mut self, t: f64, steps: u64) {
        let msg = self.line(t, steps);
        if let Some(bar) = self.bar.take() {
            bar.finish_and_clear()
        }
        eprintln!("[{}] {msg}", self.name);
    }

    pub fn abandon(&mut self) {
        if let Some(bar) = self.bar.take() {
            bar.abandon();
        }
    }
}
