//! A participant's fields: a value written into the loaned shared-memory
//! slice (held back until the try is done where implicit coupling relaxes
//! it), and a value read in place once it has come, waited for at most
//! `[coupling] timeout`, the coupler told which writer stalled it.

use super::{monitors_message, Participant};
use crate::channel::FieldSample;
use crate::error::ExchangeError;
use crate::timing::Command;
use crate::wait::WaitError;
use crate::wire::FromParticipant;
use std::time::{Duration, Instant};

/// A received field, read in place in shared memory. Derefs to `[f64]`.
pub struct FieldView {
    sample: FieldSample,
}

impl std::ops::Deref for FieldView {
    type Target = [f64];
    fn deref(&self) -> &[f64] {
        self.sample.payload()
    }
}

impl Participant {
    /// Publish `len` values of `field`. `fill` receives the loaned
    /// shared-memory slice and must overwrite every value (its previous
    /// contents are stale values of an earlier exchange). A field nobody
    /// reads in this run is skipped without calling `fill`.
    pub fn write_field(
        &mut self,
        field: &str,
        len: usize,
        fill: impl FnOnce(&mut [f64]),
    ) -> Result<(), ExchangeError> {
        let entered = self.clock.enter();
        let i = self
            .outputs
            .find(field)
            .ok_or_else(|| ExchangeError::Undeclared(field.to_string()))?;
        if let Some(tries) = self.tries.as_mut().filter(|t| t.is_accelerated(i)) {
            let at_end = match self.pending {
                Some(Command::Advance(a)) => a.window_end,
                Some(Command::Initialize | Command::Resume { .. }) => true,
                _ => false,
            };
            if !at_end {
                return Err(ExchangeError::AcceleratedMidWindow(field.to_string()));
            }
            // Sent when the try is done (`done`), relaxed.
            if let Some((sample, computed)) = self.outputs.fill(i, len, fill)? {
                tries.hold(i, sample);
                self.clock
                    .leave_sent(entered, Duration::ZERO, computed, Duration::ZERO);
            }
            return Ok(());
        }
        let written = match self.outputs.write(i, len, fill, &self.waiter.presence) {
            Ok(w) => w,
            Err(e) => {
                // The coupler hears why, not only that this process ended.
                let reason = e.to_string();
                let _ = self.control.send(&FromParticipant::Failed { reason });
                return Err(e);
            }
        };
        self.clock
            .leave_sent(entered, Duration::ZERO, written.computed, written.in_flight);
        Ok(())
    }

    /// The next value of `field`, read in place; waits until it arrives.
    /// Every value written is read once, in order.
    pub fn read_field(&mut self, field: &str) -> Result<FieldView, ExchangeError> {
        let entered = self.clock.enter();
        let (view, waited) = self.receive(field)?;
        self.clock.leave(entered, waited, Duration::ZERO);
        Ok(view)
    }

    /// The next value of `field` and how long it was waited for, counted in
    /// the statistics but for the wait itself.
    pub(super) fn receive(&mut self, field: &str) -> Result<(FieldView, Duration), ExchangeError> {
        let i = self
            .inputs
            .find(field)
            .ok_or_else(|| ExchangeError::Undeclared(field.to_string()))?;
        let input = &self.inputs.list[i];
        let Some(source) = &input.source else {
            return Err(ExchangeError::NotConnected(field.to_string()));
        };
        let deadline = Duration::from_secs_f64(self.setup.timing.timeout);
        let waited_from = Instant::now();
        let (rows, control) = (&mut self.rows, &self.control);
        // A long wait may be a stopping run's: the rows so far go out now.
        let send_rows = || {
            if let Some(msg) = rows.take(true).map(monitors_message) {
                let _ = control.post(&msg);
            }
        };
        let result = self.waiter.wait(
            input.writer,
            input.last_wait,
            deadline,
            || input.poll(),
            send_rows,
        );
        let waited = waited_from.elapsed();
        let got = match result {
            Ok(w) => w,
            Err(WaitError::Timeout(seconds)) => {
                let (field, writer) = (field.to_string(), source.writer.clone());
                let names = &self.setup.participants;
                let chain = self.waiter.presence.waits_after(input.writer, deadline);
                let then = chain.into_iter().map(|p| names[p].clone()).collect();
                let _ = self.control.send(&FromParticipant::Stalled {
                    field: field.clone(),
                    writer: writer.clone(),
                    seconds,
                    then,
                });
                return Err(ExchangeError::Stalled {
                    field,
                    writer,
                    seconds,
                });
            }
            Err(WaitError::Channel(e)) => return Err(e.into()),
        };
        let input = &mut self.inputs.list[i];
        let sent = input.accept(&got.value)?;
        self.clock.stats.reads += 1;
        input.last_wait = waited;
        self.clock.stats.sleeps += got.slept as u64;
        self.clock.stats.ready += got.ready as u64;
        if !got.ready {
            // It came while this participant waited: how late it learned of it.
            let late = crate::channel::monotonic_ns().saturating_sub(sent);
            self.clock.stats.latency_s += late as f64 * 1e-9;
        }
        Ok((FieldView { sample: got.value }, waited))
    }
}
