//! A running participant: it takes its commands from the run's schedule,
//! reads and writes fields in shared memory, and reports monitors.
//!
//! ```no_run
//! use participant::{Cadence, Command, Declaration, Monitor};
//! let joining = participant::connect()?;
//! let n = 3;
//! let declaration = Declaration::new(Cadence::PerWindow { substeps: 1 })
//!     .writes("canopy.positions", 3, n)
//!     .reads_if_written("canopy.pressure")
//!     .monitors(["kinetic_energy"]);
//! let mut p = joining.declare(declaration)?;
//! loop {
//!     match p.next_command()? {
//!         Command::Initialize => {
//!             p.write_field("canopy.positions", 3 * n, |out| out.fill(0.0))?;
//!             p.done(vec![Monitor::new("kinetic_energy", 0.0)])?;
//!         }
//!         Command::Advance(step) => {
//!             // read inputs in place, step the physics, write outputs in place
//!             p.done(vec![Monitor::new("kinetic_energy", 0.0)])?;
//!         }
//!         Command::Output { .. } => p.done(vec![])?,
//!         // Only to a participant that declares `.checkpoints()`.
//!         Command::SaveCheckpoint | Command::RestoreCheckpoint => p.done(vec![])?,
//!         // Only to one that declares `.restarts()`.
//!         Command::WriteCheckpoint { .. } | Command::Resume { .. } => p.done(vec![])?,
//!         Command::Stop => break,
//!     }
//! }
//! p.finish(0)?;
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```
//!
//! Fields are zero-copy: [`Participant::write_field`] hands the solver the
//! loaned shared-memory slice to compute into, and [`Participant::read_field`]
//! returns a view of the received value, read in place.

use crate::channel::{self, BytesIn, BytesOut, ChannelError, Ipc};
use crate::clock::Clock;
use crate::error::ExchangeError;
use crate::fields::{Inputs, Outputs};
use crate::implicit::Tries;
use crate::monitors::{Batch, Monitor, Rows};
use crate::restart;
use crate::summary::Summary;
use crate::timing::{Command, Plan, Timing};
use crate::verdict::{self, Heard};
use crate::wait::{WaitError, Waiter};
use crate::wire::{FromParticipant, Setup, Stats};
use iceoryx2::node::Node;
use iceoryx2::port::notifier::Notifier;
use std::path::Path;
use std::time::{Duration, Instant};

mod field_io;
mod joint_try;
mod run_checkpoint;

pub use field_io::FieldView;

pub(crate) fn monitors_message(b: Batch) -> FromParticipant {
    FromParticipant::Monitors {
        first_row: b.first_row,
        rows: b.rows,
        width: b.width,
        values: b.values,
    }
}

/// The control channel between a participant and the coupler.
pub(crate) struct Control {
    pub commands: BytesIn,
    pub status: BytesOut,
    pub wake_coupler: Notifier<Ipc>,
}

impl Control {
    /// Send a message the coupler must hear at once.
    pub(crate) fn send(&self, msg: &FromParticipant) -> Result<(), ChannelError> {
        channel::send_message(&self.status, &self.wake_coupler, msg)
    }

    /// Leave a message the coupler reads when it next looks (monitor rows).
    pub(crate) fn post(&self, msg: &FromParticipant) -> Result<(), ChannelError> {
        channel::post_message(&self.status, msg)
    }
}

/// How often a participant asks whether the coupler still runs: at most
/// once per this interval, not at every command (a system call each; the
/// pendulum hands out some 100 000 a second).
const COUPLER_LOOK: Duration = Duration::from_millis(20);

/// One solver's connection to a running coupled run. See the module docs.
pub struct Participant {
    name: String,
    setup: Setup,
    control: Control,
    waiter: Waiter,
    outputs: Outputs,
    inputs: Inputs,
    plan: Plan,
    /// Implicit coupling: the tries at the current window.
    tries: Option<Tries>,
    rows: Rows,
    /// The command handed out and not yet reported done.
    pending: Option<Command>,
    /// When this participant last told the coupler something (rows, or
    /// a try of a long implicit window: `joint_try.rs`).
    reported: Instant,
    /// Whether a failure was reported.
    failed: bool,
    /// What it says of its run, sent when it finishes.
    summary: Option<Summary>,
    clock: Clock,
    connected: Instant,
    /// When the coupler was last found alive ([`COUPLER_LOOK`]).
    coupler_seen: Instant,
    // Declared last: ports are dropped before their node.
    _node: Node<Ipc>,
}

impl Participant {
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn new(
        name: String,
        setup: Setup,
        control: Control,
        waiter: Waiter,
        (outputs, inputs): (Outputs, Inputs),
        plan: Plan,
        rows: Rows,
        connected: Instant,
        node: Node<Ipc>,
    ) -> Participant {
        let now = Instant::now();
        let tries = setup
            .scheme
            .implicit()
            .map(|i| Tries::new(i.clone(), &outputs));
        Participant {
            name,
            setup,
            control,
            waiter,
            outputs,
            inputs,
            plan,
            tries,
            rows,
            pending: None,
            reported: now,
            failed: false,
            summary: None,
            clock: Clock {
                back: now,
                started: now,
                stats: Stats::default(),
            },
            connected,
            coupler_seen: now,
            _node: node,
        }
    }

    /// This participant's name: its key under `[participants]`.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The run directory, where the participant writes its output files.
    pub fn run_dir(&self) -> &Path {
        &self.setup.run_dir
    }

    pub fn timing(&self) -> &Timing {
        &self.setup.timing
    }

    /// Whether the run's scheme wants, at `Initialize`, every field this
    /// participant writes at window ends (the parallel scheme: each
    /// participant takes a window's first try from the others' values
    /// before it, so the first window needs values from the start).
    pub fn publishes_at_start(&self) -> bool {
        self.setup.scheme.implicit().is_some_and(|i| i.parallel)
    }

    /// Whether a participant of this name takes part in the run.
    pub fn is_present(&self, name: &str) -> bool {
        self.setup.participants.iter().any(|p| p == name)
    }

    /// Whether `field` is exchanged in this run: a declared write that some
    /// participant reads, or a declared read that some participant writes.
    pub fn is_connected(&self, field: &str) -> bool {
        match (self.outputs.find(field), self.inputs.find(field)) {
            (Some(i), _) => self.outputs.has_readers(i),
            (_, Some(i)) => self.inputs.list[i].is_connected(),
            _ => false,
        }
    }

    /// The next command of the schedule. The previous one must have been
    /// reported [`done`](Self::done).
    pub fn next_command(&mut self) -> Result<Command, ExchangeError> {
        let entered = self.clock.enter();
        if self.pending.is_some() {
            return Err(ExchangeError::Misuse(
                "next_command() was called before the last command was reported done()",
            ));
        }
        if self.coupler_seen.elapsed() >= COUPLER_LOOK {
            let coupler = self.setup.coupler_pid;
            if !crate::usage::is_alive(coupler) {
                return Err(ExchangeError::CouplerGone(coupler));
            }
            self.coupler_seen = Instant::now();
        }
        let mut waited = Duration::ZERO;
        if let Some((window, iteration)) = self.plan.verdict_due() {
            let waiting = Instant::now();
            let again = self.verdict(window, iteration)?;
            waited = waiting.elapsed();
            self.plan.decide(again);
            if !again {
                let first = self.setup.participants.first() == Some(&self.name);
                let tries = self.tries.as_ref().expect("an implicit plan has tries");
                self.rows
                    .update(&tries.monitors(iteration + 1, first))
                    .map_err(ExchangeError::UndeclaredMonitor)?;
                self.rows.push_row();
                self.send_rows(false)?;
            }
        }
        let command = self.plan.next().ok_or(ExchangeError::Misuse(
            "next_command() was called after Stop",
        ))?;
        match command {
            Command::WriteCheckpoint { window } => {
                let dir = restart::dir(&self.setup.run_dir, window);
                std::fs::create_dir_all(&dir).map_err(|e| {
                    ExchangeError::Checkpoint(format!("cannot create {}: {e}", dir.display()))
                })?;
            }
            Command::Resume { window } => self.resume(window)?,
            _ => {}
        }
        if command != Command::Stop {
            self.pending = Some(command);
        }
        self.clock.stats.commands += 1;
        self.clock.leave(entered, waited, Duration::ZERO);
        Ok(command)
    }

    /// The verdict on try `iteration` at `window`, once every participant
    /// has posted its word on it (`verdict.rs`): take the window again
    /// (true) or go on. At the most tries allowed, an unconverged window
    /// stops the run, or goes on with a warning if the scenario says so.
    fn verdict(&mut self, window: u64, iteration: u32) -> Result<bool, ExchangeError> {
        let tries = self.tries.as_ref().expect("an implicit plan has tries");
        let presence = &self.waiter.presence;
        let me = presence.me();
        let names = &self.setup.participants;
        let others = || {
            (0..names.len())
                .filter(|&p| p != me)
                .filter_map(|p| presence.word(p).map(|w| (p, w)))
        };
        let behind = others()
            .find(|(_, w)| {
                verdict::hear([(0, *w)].into_iter(), window, iteration) == Heard::Waiting
            })
            .map_or(me, |(p, _)| p);
        let deadline = Duration::from_secs_f64(self.setup.timing.timeout);
        let heard = self.waiter.wait(
            behind,
            Duration::ZERO,
            deadline,
            || {
                Ok(match verdict::hear(others(), window, iteration) {
                    Heard::Waiting => None,
                    heard => Some(heard),
                })
            },
            || {},
        );
        let mut unconverged = match heard {
            Ok(w) => match w.value {
                Heard::Decided(again) => return Ok(again),
                Heard::All { unconverged } => unconverged,
                Heard::Waiting => unreachable!("a wait ends with a word"),
            },
            Err(WaitError::Timeout(seconds)) => {
                return Err(ExchangeError::Stalled {
                    field: format!("the word on try {} at window {window}", iteration + 1),
                    writer: names[behind].clone(),
                    seconds,
                })
            }
            Err(WaitError::Channel(e)) => return Err(e.into()),
        };
        if !tries.converged {
            unconverged.push(me);
        }
        let s = &tries.settings;
        let done = iteration + 1;
        if done < s.min_iterations.max(1) || (!unconverged.is_empty() && done < s.max_iterations) {
            return Ok(true);
        }
        if unconverged.is_empty() {
            return Ok(false);
        }
        let detail = tries.unconverged_detail(&unconverged, me, names, presence);
        if s.go_on_at_max {
            if !tries.converged {
                eprintln!(
                    "warning: {}: window {window} did not converge in {done} tries ({detail}); going on",
                    self.name
                );
            }
            return Ok(false);
        }
        Err(ExchangeError::Unconverged {
            window,
            tries: done,
            detail,
        })
    }

    /// Report the last command done, with the newest values of any of the
    /// declared monitors. At the start and at every window end a row of
    /// `monitors.csv` is closed with the newest value of each.
    pub fn done(&mut self, monitors: Vec<Monitor>) -> Result<(), ExchangeError> {
        let solver = self.clock.back.elapsed();
        let entered = self.clock.enter();
        let Some(command) = self.pending.take() else {
            return Err(ExchangeError::Misuse(
                "done() was called with no command pending",
            ));
        };
        self.rows
            .update(&monitors)
            .map_err(ExchangeError::UndeclaredMonitor)?;
        let mut waited = Duration::ZERO;
        let closes_row = match (command, self.tries.as_mut()) {
            (Command::Initialize, Some(tries)) => {
                tries.send_as_is(&mut self.outputs, &self.waiter.presence)?;
                true
            }
            (Command::SaveCheckpoint, Some(tries)) => {
                tries.start_window();
                self.clock.stats.checkpoint_s += solver.as_secs_f64();
                false
            }
            (Command::RestoreCheckpoint, _) => {
                self.clock.stats.checkpoint_s += solver.as_secs_f64();
                false
            }
            // The row closes once the verdict lets the window go on.
            (Command::Advance(a), Some(_)) if a.window_end => {
                waited = self.close_try(a.window, a.iteration)?;
                false
            }
            (Command::Resume { .. }, Some(tries)) => {
                tries.send_held(&mut self.outputs, &self.waiter.presence)?;
                false
            }
            (Command::WriteCheckpoint { window }, _) => {
                self.write_checkpoint(window)?;
                false
            }
            (Command::Initialize, None) => true,
            (Command::Advance(a), None) => a.window_end,
            _ => false,
        };
        if closes_row {
            self.rows.push_row();
            self.send_rows(false)?;
        }
        self.clock.leave(entered, waited, Duration::ZERO);
        Ok(())
    }

    /// Send the monitor rows closed so far: posted for the coupler's next
    /// look, or when `last` (before a failure or the statistics) at once.
    fn send_rows(&mut self, last: bool) -> Result<(), ChannelError> {
        if let Some(msg) = self.rows.take(last).map(monitors_message) {
            match last {
                true => self.control.send(&msg)?,
                false => self.control.post(&msg)?,
            }
            self.reported = Instant::now();
        }
        Ok(())
    }

    /// Run `body`; an error it returns is reported to the coupler (as
    /// [`fail`](Self::fail) would) before it is handed back, so that the
    /// coupler says what went wrong, not only that the process ended.
    pub fn reporting<T, E: std::fmt::Display>(
        &mut self,
        body: impl FnOnce(&mut Participant) -> Result<T, E>,
    ) -> Result<T, E> {
        let result = body(self);
        if let Err(e) = &result {
            let _ = self.fail(e.to_string());
        }
        result
    }

    /// Report that this participant cannot go on; the caller then exits
    /// non-zero. The monitor rows closed so far are sent first. Only the
    /// first report counts.
    pub fn fail(&mut self, reason: impl Into<String>) -> Result<(), ExchangeError> {
        if self.failed {
            return Ok(());
        }
        self.failed = true;
        self.waiter.presence.own().leave();
        self.send_rows(true)?;
        let reason = reason.into();
        Ok(self.control.send(&FromParticipant::Failed { reason })?)
    }

    /// Keep this participant's shared memory until every reader of its
    /// fields has left the run, at most the run's timeout. A field that
    /// outgrew its first segment lives in a segment that a reader maps only
    /// when it receives the value, and the segment goes with its writer:
    /// a writer leaving first would lose its last value (iceoryx2's "lost
    /// chunk" of a reallocated data segment) and stall its reader. Every
    /// participant leaves before it lingers, so no two wait for each other.
    fn linger(&self) {
        let presence = &self.waiter.presence;
        let limit = Duration::from_secs_f64(self.setup.timing.timeout);
        let since = Instant::now();
        let mut readers: Vec<usize> = self.outputs.readers().collect();
        while since.elapsed() < limit {
            readers.retain(|&r| !presence.has_left(r));
            if readers.is_empty() {
                return;
            }
            std::thread::sleep(Duration::from_micros(200));
        }
    }

    /// What this participant says of its whole run (under the name it
    /// declared with [`crate::Declaration::summary`]): sent by
    /// [`Participant::finish`], once the last monitor rows are.
    pub fn summarize(&mut self, summary: Summary) {
        self.summary = Some(summary);
    }

    /// After `Stop`: send the last monitor rows, the summary if there is
    /// one, and this process's statistics; `substeps` is the number of
    /// internal sub-steps the solver took. The process then exits 0.
    pub fn finish(mut self, substeps: u64) -> Result<(), ExchangeError> {
        let entered = self.clock.enter();
        self.waiter.presence.own().leave();
        self.send_rows(true)?;
        if let Some(summary) = self.summary.take() {
            self.control.send(&FromParticipant::Summary(summary))?;
        }
        self.linger();
        self.clock.leave(entered, Duration::ZERO, Duration::ZERO);
        let mut stats = self.clock.stats.clone();
        stats.substeps = substeps;
        stats.cpu_s = crate::usage::cpu_seconds();
        stats.wall_s = self.connected.elapsed().as_secs_f64();
        stats.run_s = self.clock.started.elapsed().as_secs_f64();
        Ok(self.control.send(&FromParticipant::Finished(stats))?)
    }
}
