//! CPU time of this process, every thread included: what a run costs, not
//! how long the machine took to get round to it.

/// CPU seconds this process has used so far.
pub fn process_seconds() -> f64 {
    let mut ts = libc::timespec {
        tv_sec: 0,
        tv_nsec: 0,
    };
    // SAFETY: `ts` is a valid, writable timespec; the clock id is a constant.
    let rc = unsafe { libc::clock_gettime(libc::CLOCK_PROCESS_CPUTIME_ID, &mut ts) };
    assert_eq!(
        rc, 0,
        "CLOCK_PROCESS_CPUTIME_ID is always available on Linux"
    );
    ts.tv_sec as f64 + ts.tv_nsec as f64 * 1e-9
}

/// Runs `f` until it has taken at least `min_seconds` of CPU time (at most
/// `max_repeats` times) and returns its last result and the CPU seconds of one call.
pub fn timed<T>(min_seconds: f64, max_repeats: u32, mut f: impl FnMut() -> T) -> (T, f64) {
    let start = process_seconds();
    let mut repeats = 0;
    loop {
        let out = f();
        repeats += 1;
        let spent = process_seconds() - start;
        if spent >= min_seconds || repeats >= max_repeats {
            return (out, spent / repeats as f64);
        }
    }
}
