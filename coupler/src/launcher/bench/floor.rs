//! The hardware's floor under any exchange: one cache line handed from one
//! core to the other and back, by two threads spinning on atomics, with no
//! library, no data and no system call. A coupled scene that hands values
//! over more often than its physics can pay for this floor cannot reach a
//! small exchange share on this machine, however the exchange is built.

use std::sync::atomic::{AtomicU64, Ordering};
use std::sync::Arc;
use std::time::Instant;

/// Round trips timed (after a tenth as many to warm up).
const ROUNDS: u64 = 200_000;

/// The pair of lines the two threads hand back and forth, a line apart so
/// that each store moves exactly one line.
#[repr(align(128))]
struct Line(AtomicU64);

/// Mean round trip of one cache line between two cores [µs],
/// or None where the machine has one core (spinning would deadlock).
pub fn round_trip_us() -> Option<f64> {
    let cores = std::thread::available_parallelism().map_or(1, |n| n.get());
    if cores < 2 {
        return None;
    }
    let lines = Arc::new([Line(AtomicU64::new(0)), Line(AtomicU64::new(0))]);
    let other = lines.clone();
    let warm = ROUNDS / 10;
    let total = warm + ROUNDS;
    let answer = std::thread::spawn(move || {
        for i in 1..=total {
            while other[0].0.load(Ordering::Acquire) != i {
                std::hint::spin_loop();
            }
            other[1].0.store(i, Ordering::Release);
        }
    });
    let mut started = Instant::now();
    for i in 1..=total {
        if i == warm + 1 {
            started = Instant::now();
        }
        lines[0].0.store(i, Ordering::Release);
        while lines[1].0.load(Ordering::Acquire) != i {
            std::hint::spin_loop();
        }
    }
    let elapsed = started.elapsed();
    answer.join().ok()?;
    Some(elapsed.as_secs_f64() * 1e6 / ROUNDS as f64)
}
