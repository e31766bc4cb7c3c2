//! How a participant waits for a field: spin while that costs nobody a
//! core and the value is expected soon, otherwise sleep on the wake event
//! until the value comes or spinning is worth it again (`presence.rs`
//! says when). A lost wake-up costs at most [`BLOCK_SLICE`].

use crate::channel::{self, ChannelError, Ipc, BLOCK_SLICE};
use crate::presence::{expected, Presence, State};
use iceoryx2::port::listener::Listener;
use std::time::{Duration, Instant};

/// Longest wait expected to be short: a participant spins only while its
/// last wait for the same field, and this one so far, were no longer.
pub const SPIN_LONG: Duration = Duration::from_millis(5);
/// Every wait polls this long before it asks whether to go on spinning,
/// unless other work holds some of the machine's cores.
pub const SPIN_SHORT: Duration = Duration::from_micros(20);
/// Spin without yielding the core this long; yield between polls after.
const SPIN_HOT: Duration = Duration::from_micros(50);
/// A wait this long is not a step's wait: `waiting_long` runs (to send the
/// monitor rows, should the run be stopping).
pub const LONG_WAIT: Duration = Duration::from_millis(50);

/// Why a wait ended without a value.
#[derive(Debug)]
pub enum WaitError {
    /// Nothing came within the deadline [s].
    Timeout(f64),
    Channel(ChannelError),
}

impl From<ChannelError> for WaitError {
    fn from(e: ChannelError) -> Self {
        WaitError::Channel(e)
    }
}

/// A participant's wake event, and what every participant is doing.
pub struct Waiter {
    listener: Listener<Ipc>,
    pub presence: Presence,
}

/// What one wait took.
pub struct Waited<T> {
    pub value: T,
    pub slept: bool,
    /// Whether the value was there at the first look (no wait at all).
    pub ready: bool,
}

impl Waiter {
    pub fn new(listener: Listener<Ipc>, presence: Presence) -> Waiter {
        Waiter { listener, presence }
    }

    /// Poll until `poll` yields a value written by participant `writer`,
    /// giving up after `deadline`. `last` is how long the previous wait for
    /// the same value took; `waiting_long` runs once if this one passes
    /// [`LONG_WAIT`].
    pub fn wait<T>(
        &self,
        writer: usize,
        last: Duration,
        deadline: Duration,
        mut poll: impl FnMut() -> Result<Option<T>, ChannelError>,
        mut waiting_long: impl FnMut(),
    ) -> Result<Waited<T>, WaitError> {
        let start = Instant::now();
        let p = &self.presence;
        let expected = expected(last);
        let short = |waited: Duration| last <= SPIN_LONG && waited <= SPIN_LONG;
        if let Some(value) = poll()? {
            return Ok(Waited {
                value,
                slept: false,
                ready: true,
            });
        }
        let mut slept = false;
        let result = loop {
            p.waiting(State::Spinning, short(start.elapsed()), expected, writer);
            let spun = self.spin(start, deadline, &mut poll, |waited| {
                (waited < SPIN_SHORT && p.can_spin() && !p.crowded())
                    || p.may_spin(short(waited), expected, writer)
            });
            match spun {
                Ok(None) => {}
                other => break other,
            }
            slept = true;
            let still_short = short(start.elapsed());
            p.waiting(State::Asleep, still_short, expected, writer);
            p.freed_core(still_short, expected, writer)?;
            match self.sleep(start, deadline, &mut poll, &mut waiting_long, || {
                p.may_spin(short(start.elapsed()), expected, writer)
            }) {
                Ok(None) => {}
                other => break other,
            }
        };
        // One that gave up keeps its flag (waiting for `writer`) to the
        // end: another participant's chain of waits then passes through it
        // to the one that held both up (`Presence::waits_after`).
        if !matches!(result, Err(WaitError::Timeout(_))) {
            self.presence.computing()?;
        }
        result.map(|v| Waited {
            value: v.expect("a wait ends with a value or an error"),
            slept,
            ready: false,
        })
    }

    /// Sleep on the wake event until `poll` yields a message from the
    /// coupler, giving up after `deadline`. Such a wait is rare (a run
    /// checkpoint's), so it never spins.
    pub fn wait_for_coupler<T>(
        &self,
        deadline: Duration,
        mut poll: impl FnMut() -> Result<Option<T>, ChannelError>,
    ) -> Result<T, WaitError> {
        let start = Instant::now();
        loop {
            let waited = match look(start, deadline, &mut poll)? {
                Ok(value) => return Ok(value),
                Err(waited) => waited,
            };
            channel::block(&self.listener, (deadline - waited).min(BLOCK_SLICE))?;
        }
    }

    /// Poll while `go_on(waited)`; a value, or None to sleep.
    fn spin<T>(
        &self,
        start: Instant,
        deadline: Duration,
        poll: &mut impl FnMut() -> Result<Option<T>, ChannelError>,
        go_on: impl Fn(Duration) -> bool,
    ) -> Result<Option<T>, WaitError> {
        loop {
            let waited = match look(start, deadline, poll)? {
                Ok(value) => return Ok(Some(value)),
                Err(waited) => waited,
            };
            self.presence.own().beat();
            if !go_on(waited) {
                return Ok(None);
            }
            if waited < SPIN_HOT {
                std::hint::spin_loop();
            } else {
                std::thread::yield_now();
            }
        }
    }

    /// Sleep until a value comes, or until woken when `spin_again()`: then
    /// None.
    fn sleep<T>(
        &self,
        start: Instant,
        deadline: Duration,
        poll: &mut impl FnMut() -> Result<Option<T>, ChannelError>,
        waiting_long: &mut impl FnMut(),
        spin_again: impl Fn() -> bool,
    ) -> Result<Option<T>, WaitError> {
        let mut long = false;
        loop {
            let waited = match look(start, deadline, poll)? {
                Ok(value) => return Ok(Some(value)),
                Err(waited) => waited,
            };
            self.presence.own().beat();
            if waited >= LONG_WAIT && !long {
                long = true;
                waiting_long();
            }
            channel::block(&self.listener, (deadline - waited).min(BLOCK_SLICE))?;
            if spin_again() {
                return Ok(None);
            }
        }
    }
}

/// One look for the value: it, or how long the wait has lasted; an error
/// once that is past the deadline.
fn look<T>(
    start: Instant,
    deadline: Duration,
    poll: &mut impl FnMut() -> Result<Option<T>, ChannelError>,
) -> Result<Result<T, Duration>, WaitError> {
    if let Some(value) = poll()? {
        return Ok(Ok(value));
    }
    let waited = start.elapsed();
    match waited >= deadline {
        true => Err(WaitError::Timeout(deadline.as_secs_f64())),
        false => Ok(Err(waited)),
    }
}
