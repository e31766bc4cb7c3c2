//! Linux's futex on a 32-bit word that several processes map: sleep while
//! it holds a value, wake whoever sleeps on it. The wake-up event of every
//! canopy run (`futex_event.rs`) and the bench's floor under a sleeping
//! hand-off (`coupler bench exchange`) both stand on these two calls.

use std::sync::atomic::AtomicU32;
use std::time::Duration;

/// Why a [`wait`] ended early.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Cut {
    /// A signal arrived.
    Signal,
    /// The kernel refused the wait (an error number other than these).
    Refused(i32),
}

/// Sleep while `word` holds `expected`, at most `timeout` (None: until
/// woken). A changed word, a wake-up or the timeout return `Ok`.
pub fn wait(word: &AtomicU32, expected: u32, timeout: Option<Duration>) -> Result<(), Cut> {
    let ts = timeout.map(|t| libc::timespec {
        tv_sec: t.as_secs().min(i32::MAX as u64) as libc::time_t,
        tv_nsec: t.subsec_nanos() as libc::c_long,
    });
    let ts_ptr = ts.as_ref().map_or(std::ptr::null(), |t| t as *const _);
    // SAFETY: `word` is a live, aligned 32-bit atomic; the kernel only
    // reads it and the timespec. Not FUTEX_PRIVATE: the word may be shared
    // between processes.
    let r = unsafe {
        libc::syscall(
            libc::SYS_futex,
            word.as_ptr(),
            libc::FUTEX_WAIT,
            expected,
            ts_ptr,
        )
    };
    if r == 0 {
        return Ok(());
    }
    match std::io::Error::last_os_error().raw_os_error() {
        Some(libc::EAGAIN) | Some(libc::ETIMEDOUT) => Ok(()),
        Some(libc::EINTR) => Err(Cut::Signal),
        e => Err(Cut::Refused(e.unwrap_or(0))),
    }
}

/// Wake one process (or thread) sleeping on `word`; waking nobody is
/// harmless.
pub fn wake(word: &AtomicU32) {
    // SAFETY: as in `wait`.
    unsafe {
        libc::syscall(libc::SYS_futex, word.as_ptr(), libc::FUTEX_WAKE, 1);
    }
}
