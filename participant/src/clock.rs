//! Where a participant's time goes: its solver's own work between the
//! library's calls, the exchange inside them, and waiting for fields
//! (the statistics of `manifest.json`).

use crate::wire::Stats;
use std::time::{Duration, Instant};

/// Where the participant's time goes: its own work (between calls), the
/// exchange inside calls, and waiting for fields.
pub(crate) struct Clock {
    /// When the library last handed control back to the solver.
    pub back: Instant,
    pub started: Instant,
    pub stats: Stats,
}

impl Clock {
    /// Entering a call: the time since the last one was the solver's.
    pub fn enter(&mut self) -> Instant {
        let now = Instant::now();
        self.stats.compute_s += (now - self.back).as_secs_f64();
        now
    }

    /// Leaving a call entered at `entered`, of which `waited` was spent
    /// waiting and `computed` in the solver's own closure.
    pub fn leave(&mut self, entered: Instant, waited: Duration, computed: Duration) {
        self.leave_sent(entered, waited, computed, Duration::ZERO);
    }

    /// The same for a write, of which `in_flight` was spent sending a value
    /// after stamping it: its reader, if it waits for it, counts that as
    /// the value's latency, so it is not counted twice.
    pub fn leave_sent(
        &mut self,
        entered: Instant,
        waited: Duration,
        computed: Duration,
        in_flight: Duration,
    ) {
        let now = Instant::now();
        let inside = now - entered;
        let exchange = inside.saturating_sub(waited + computed + in_flight);
        self.stats.exchange_s += exchange.as_secs_f64();
        self.stats.wait_s += waited.as_secs_f64();
        self.stats.compute_s += computed.as_secs_f64();
        self.back = now;
    }
}
