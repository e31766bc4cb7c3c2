//! How many of the machine's cores other work holds: the runnable tasks
//! the kernel counts (`/proc/loadavg`, its fourth field: runnable / all,
//! counted when read) less those of this run that the flags show awake.
//!
//! A participant spins only on a core nobody else wants (`presence.rs`).
//! Counting only the run's own processes against the machine's cores, as
//! it once did, made a waiter spin beside a user's busy process on a
//! two-core machine: three runnable tasks on two cores, so the computing
//! participant lost a third of its core and the spinner, preempted, saw
//! its value late (issue 43: canopy-porous, pendulum and c9-drop-body ran
//! 2.7–3.8× slower beside one busy loop although they need one core).
//!
//! One reading is noisy: a process woken a moment ago still shows as
//! asleep on its flag, and short-lived tasks come and go (a shell's
//! `cat`, a kernel thread). So a reading is taken at most every
//! [`SAMPLE_EVERY`] while someone asks, and the load is the least of the
//! readings of the last [`FRESH`]: a busy process shows in every one of
//! them, a blip in one. Where the file cannot be read (not Linux), there
//! is no other work as far as this module knows.

use std::cell::Cell;
use std::fs::File;
use std::os::unix::fs::FileExt;
use std::time::{Duration, Instant};

/// Least time between two readings of `/proc/loadavg` (one costs a few
/// µs: a spinner asking every poll reads it at most this often).
pub const SAMPLE_EVERY: Duration = Duration::from_millis(1);
/// Readings older than this are forgotten.
pub const FRESH: Duration = Duration::from_millis(20);
/// Readings kept: a busy process is seen after this many.
const KEPT: usize = 4;

/// The other work on the machine, from recent readings.
pub struct Load {
    file: Option<File>,
    /// (when, tasks runnable beyond this run's) of the last readings.
    readings: Cell<[Option<(Instant, u64)>; KEPT]>,
    next: Cell<usize>,
}

impl Load {
    pub fn new() -> Load {
        Load {
            file: File::open("/proc/loadavg").ok(),
            readings: Cell::new([None; KEPT]),
            next: Cell::new(0),
        }
    }

    /// Cores other work holds, `ours` being the tasks this run has
    /// runnable now (by its flags, the caller counted as running).
    pub fn others(&self, now: Instant, ours: u64) -> u64 {
        let mut readings = self.readings.get();
        let last = readings[(self.next.get() + KEPT - 1) % KEPT];
        if last.is_none_or(|(at, _)| now.duration_since(at) >= SAMPLE_EVERY) {
            let Some(runnable) = self.runnable() else {
                return 0;
            };
            readings[self.next.get()] = Some((now, runnable.saturating_sub(ours)));
            self.next.set((self.next.get() + 1) % KEPT);
            self.readings.set(readings);
        }
        least_fresh(&readings, now)
    }

    /// The kernel's count of runnable tasks, read now.
    fn runnable(&self) -> Option<u64> {
        let mut buf = [0u8; 128];
        let n = self.file.as_ref()?.read_at(&mut buf, 0).ok()?;
        runnable_in(std::str::from_utf8(&buf[..n]).ok()?)
    }
}

impl Default for Load {
    fn default() -> Self {
        Load::new()
    }
}

/// The least of the readings younger than [`FRESH`] (the newest always
/// is: `others` has just taken it, or took it under [`SAMPLE_EVERY`] ago).
fn least_fresh(readings: &[Option<(Instant, u64)>], now: Instant) -> u64 {
    readings
        .iter()
        .flatten()
        .filter(|(at, _)| now.duration_since(*at) < FRESH)
        .map(|&(_, n)| n)
        .min()
        .unwrap_or(0)
}

/// The runnable count in a `/proc/loadavg` line: "0.10 0.05 0.01 3/80 1695".
fn runnable_in(line: &str) -> Option<u64> {
    line.split_whitespace()
        .nth(3)?
        .split('/')
        .next()?
        .parse()
        .ok()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_runnable_count_is_the_fourth_fields_numerator() {
        assert_eq!(runnable_in("0.10 0.05 0.01 3/80 1695\n"), Some(3));
        assert_eq!(runnable_in("0.10 0.05 0.01"), None);
    }

    #[test]
    fn a_blip_in_one_reading_is_not_load_but_a_lasting_process_is() {
        let t0 = Instant::now();
        let ms = |m| t0 + Duration::from_millis(m);
        let blip = [Some((ms(0), 0)), Some((ms(1), 2)), Some((ms(2), 0)), None];
        assert_eq!(least_fresh(&blip, ms(3)), 0);
        let busy = [Some((ms(0), 1)), Some((ms(1), 2)), Some((ms(2), 1)), None];
        assert_eq!(least_fresh(&busy, ms(3)), 1);
        // A quiet reading from before the busy process started is forgotten.
        let started = [Some((ms(0), 0)), Some((ms(30), 1)), None, None];
        assert_eq!(least_fresh(&started, ms(31)), 1);
    }

    /// The kernel counts a process that computes: with one thread busy
    /// here beside this one, the count read is at least this run's 1 and
    /// the busy thread's 1 (Linux only; elsewhere nothing is read).
    #[test]
    fn a_busy_thread_is_counted_as_runnable() {
        let load = Load::new();
        if load.file.is_none() {
            return;
        }
        let stop = std::sync::Arc::new(std::sync::atomic::AtomicBool::new(false));
        let s = stop.clone();
        let busy = std::thread::spawn(move || {
            while !s.load(std::sync::atomic::Ordering::Relaxed) {
                std::hint::spin_loop();
            }
        });
        std::thread::sleep(Duration::from_millis(20));
        let most = (0..50)
            .map(|_| {
                std::thread::sleep(Duration::from_millis(1));
                load.runnable().unwrap()
            })
            .max()
            .unwrap();
        stop.store(true, std::sync::atomic::Ordering::Relaxed);
        busy.join().unwrap();
        assert!(
            most >= 2,
            "at most {most} runnable with a thread spinning beside this one"
        );
    }
}
