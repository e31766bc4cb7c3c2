//! A participant's part of the run checkpoints (`[run] checkpoint_interval`):
//! where its solver writes its state, the library's own part written last
//! once the coupler keeps the checkpoint's monitor rows on disk, and what
//! a restarted run reads back.

use super::Participant;
use crate::channel;
use crate::error::ExchangeError;
use crate::restart;
use crate::wait::WaitError;
use crate::wire::{FromParticipant, ToParticipant};
use std::time::Duration;

impl Participant {
    /// The file this participant keeps its state in at the run checkpoint
    /// of `window` (written on `WriteCheckpoint`, read back on `Resume`; a
    /// participant on several processes names one per process with
    /// [`restart::state_file`]).
    pub fn state_file(&self, window: u64) -> std::path::PathBuf {
        restart::state_file(&self.setup.run_dir, window, &self.name, None)
    }

    /// A restarted run: the library's part of the checkpoint of `window`,
    /// the monitor rows closed up to its end (one at the start, one per
    /// window) and the acceleration state.
    pub(super) fn resume(&mut self, window: u64) -> Result<(), ExchangeError> {
        let saved = restart::LibraryState::read(&self.setup.run_dir, window, &self.name)
            .map_err(|e| ExchangeError::Checkpoint(e.to_string()))?;
        if !self.rows.resume(&saved.monitors, window + 2) {
            return Err(ExchangeError::Checkpoint(format!(
                "the checkpoint of window {window} holds {} monitors of `{}`, and it now \
                 declares {}",
                saved.monitors.len(),
                self.name,
                self.rows.latest().len()
            )));
        }
        if let (Some(tries), Some(a)) = (self.tries.as_mut(), saved.accelerator) {
            tries.resume(a);
        }
        Ok(())
    }

    /// The library's part of the run checkpoint of `window`, after the
    /// solver's: its presence marks this participant's part complete. It
    /// is written only once `monitors.csv` holds the rows that go with the
    /// checkpoint, so that a restart can go on from every complete one
    /// (the coupler writes rows up to a quarter of a second late).
    pub(super) fn write_checkpoint(&mut self, window: u64) -> Result<(), ExchangeError> {
        self.await_rows_kept(window + 2)?;
        let state = restart::LibraryState {
            monitors: self.rows.latest().to_vec(),
            accelerator: self.tries.as_ref().map(|t| t.accelerator().clone()),
        };
        let run_dir = &self.setup.run_dir;
        (state.write(run_dir, window, &self.name))
            .and_then(|_| restart::prune(run_dir, &self.name))
            .map_err(|e| ExchangeError::Checkpoint(e.to_string()))
    }

    /// Send the monitor rows closed so far and wait until the coupler
    /// says `monitors.csv` holds its first `rows` rows on disk.
    fn await_rows_kept(&mut self, rows: u64) -> Result<(), ExchangeError> {
        self.send_rows(true)?;
        self.control.send(&FromParticipant::Checkpoint { rows })?;
        let deadline = Duration::from_secs_f64(self.setup.timing.timeout);
        let commands = &self.control.commands;
        let answer = self.waiter.wait_for_coupler(deadline, || {
            channel::try_receive_message::<ToParticipant>(commands)
        });
        match answer {
            Ok(ToParticipant::RowsKept { rows: kept }) if kept >= rows => Ok(()),
            Ok(other) => Err(ExchangeError::Checkpoint(format!(
                "the coupler answered {other:?} where it was to keep {rows} monitor rows"
            ))),
            Err(WaitError::Timeout(seconds)) => Err(ExchangeError::Checkpoint(format!(
                "the coupler did not say within {seconds:.1} s that monitors.csv holds \
                 the {rows} rows of this checkpoint"
            ))),
            Err(WaitError::Channel(e)) => Err(e.into()),
        }
    }
}
