//! The hardware's floor under any exchange: one cache line handed from one
//! core to the other and back, by two threads spinning on atomics, with no
//! library, no data and no system call. A coupled scene that hands values
//! over more often than its physics can pay for this floor cannot reach a
//! small exchange share on this machine, however the exchange is built.
//!
//! Beside other work nobody may spin, and the floor is the kernel's: a
//! hand-off between two processes that sleep on a futex and wake each
//! other, with no library either ([`sleeping_round_trip_us`]).

use participant::futex;
use std::sync::atomic::{AtomicU32, AtomicU64, Ordering};
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

/// Mean round trip of a hand-off between two processes that each sleep on
/// a futex until the other has written and woken it [µs]: the least a
/// sleeping hand-off between two participants costs on this machine as it
/// is (a system call on each side and a switch of processes), or None
/// where the shared page or the second process cannot be had.
pub fn sleeping_round_trip_us() -> Option<f64> {
    let rounds = (ROUNDS / 10) as u32;
    let warm = rounds / 10;
    let total = warm + rounds;
    // SAFETY: a fresh anonymous shared page, unmapped below; both
    // processes see its first word as the same 32-bit atomic.
    let page = unsafe {
        libc::mmap(
            std::ptr::null_mut(),
            4096,
            libc::PROT_READ | libc::PROT_WRITE,
            libc::MAP_SHARED | libc::MAP_ANONYMOUS,
            -1,
            0,
        )
    };
    if page == libc::MAP_FAILED {
        return None;
    }
    // SAFETY: the page is mapped, aligned and zeroed, and outlives both uses.
    let word = unsafe { &*(page as *const AtomicU32) };
    // Turn 2i−1 is the answerer's, 2i the caller's. The child only touches
    // the word and makes system calls (no allocation, no lock), so forking
    // from this threaded process is safe; it leaves with `_exit`.
    // SAFETY: see above.
    let child = unsafe { libc::fork() };
    if child == 0 {
        for i in 1..=total {
            sleep_until(word, 2 * i - 1);
            word.store(2 * i, Ordering::SeqCst);
            futex::wake(word);
        }
        // SAFETY: ends the child without running the parent's destructors.
        unsafe { libc::_exit(0) };
    }
    let result = (child > 0).then(|| {
        let mut started = Instant::now();
        for i in 1..=total {
            if i == warm + 1 {
                started = Instant::now();
            }
            word.store(2 * i - 1, Ordering::SeqCst);
            futex::wake(word);
            sleep_until(word, 2 * i);
        }
        let elapsed = started.elapsed();
        // SAFETY: reaps the child started above.
        unsafe { libc::waitpid(child, std::ptr::null_mut(), 0) };
        elapsed.as_secs_f64() * 1e6 / rounds as f64
    });
    // SAFETY: the page mapped above, no longer used by this process.
    unsafe { libc::munmap(page, 4096) };
    result
}

/// Sleep on `word` until it holds `turn`.
fn sleep_until(word: &AtomicU32, turn: u32) {
    loop {
        let now = word.load(Ordering::SeqCst);
        if now == turn {
            return;
        }
        let _ = futex::wait(word, now, None);
    }
}
