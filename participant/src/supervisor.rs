//! The coupler's end of the protocol: open a control channel per
//! participant, take each through the handshake (hello, setup,
//! declaration, connections, ready, start), then collect what they report
//! while they run the schedule by themselves.
//!
//! Solvers do not use this module; the `coupler` executable does.

use crate::channel::{self, BytesIn, BytesOut, ChannelError, Ipc};
use crate::declaration::Declaration;
use crate::matching::connect_fields;
use crate::names;
use crate::timing::Cadence;
use crate::wire::{FromParticipant, ToParticipant};
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

pub use crate::channel::{
    cleanup_dead_nodes, services_of_run, stale_node_entries, HALF_CREATED_AGE,
};
pub use crate::names::{new_run_id, ENV_PARTICIPANT, ENV_RANKS, ENV_RUN_ID};
pub use crate::summary::Summary;
pub use crate::wire::{Setup, Stats};

/// What a running participant reports.
#[derive(Debug, Clone, PartialEq)]
pub enum Report {
    /// `rows` monitor rows from `first_row` on, `width` values each (the
    /// declared monitors, in order), flat.
    Monitors {
        first_row: u64,
        rows: u64,
        width: u32,
        values: Vec<f64>,
    },
    Finished(Stats),
    /// What the participant says of its whole run, under the name it
    /// declared.
    Summary(Summary),
    /// The participant writes the run checkpoint that goes with the first
    /// `rows` rows, and waits for [`Supervisor::rows_kept`].
    Checkpoint {
        rows: u64,
    },
    /// `tries` tries of window `window` are done (a long implicit window).
    Tried {
        window: u64,
        tries: u32,
    },
}

/// Why the coupler stops a run.
#[derive(Debug, thiserror::Error)]
pub enum SuperviseError {
    #[error("participant `{participant}` reported failure: {reason}")]
    Failed { participant: String, reason: String },
    #[error("participant `{participant}` did not answer within {seconds:.1} s{detail}")]
    Timeout {
        participant: String,
        seconds: f64,
        /// Who noticed, and waiting for what.
        detail: String,
    },
    #[error("participant `{participant}` sent {got} where {expected} was expected")]
    Protocol {
        participant: String,
        expected: &'static str,
        got: String,
    },
    /// The declarations do not fit together (a read nobody writes).
    #[error("{0}")]
    Mismatch(String),
    #[error("stopped")]
    Aborted,
    #[error("coupling channel: {0}")]
    Channel(ChannelError),
}

impl SuperviseError {
    /// The participant to blame, if one is.
    pub fn culprit(&self) -> Option<&str> {
        match self {
            SuperviseError::Failed { participant, .. }
            | SuperviseError::Timeout { participant, .. }
            | SuperviseError::Protocol { participant, .. } => Some(participant),
            _ => None,
        }
    }
}

/// `waiter` waited `seconds` in vain for `field` from `writer`, which
/// itself waited for the first of `then`, and so on: the last of the
/// chain is the one that did not answer, and the message names them all.
fn stalled(
    waiter: &str,
    field: &str,
    writer: String,
    then: Vec<String>,
    seconds: f64,
) -> SuperviseError {
    let mut detail = format!(" (`{waiter}` waited for field `{field}`");
    if !then.is_empty() {
        detail.push_str(&format!(" from `{writer}`"));
        for (k, next) in then.iter().enumerate() {
            let who = if k == 0 { "which" } else { "which in turn" };
            detail.push_str(&format!(", {who} waited for `{next}`"));
        }
    }
    detail.push(')');
    SuperviseError::Timeout {
        participant: then.last().cloned().unwrap_or(writer),
        seconds,
        detail,
    }
}

struct Port {
    commands: BytesOut,
    status: BytesIn,
    wake: Notifier<Ipc>,
}

pub struct Supervisor {
    names: Vec<String>,
    ports: Vec<Port>,
    listener: Listener<Ipc>,
    abort: Arc<AtomicBool>,
    declarations: Vec<Declaration>,
    /// Seconds spent sending to the participants.
    pub send_s: f64,
    _node: Node<Ipc>,
}

impl Supervisor {
    /// Open the control channels of the participants `names` of run `run`.
    pub fn open(
        run: &str,
        names: &[String],
        abort: Arc<AtomicBool>,
    ) -> Result<Supervisor, ChannelError> {
        let node = channel::node("coupler")?;
        let listener = channel::listener(&node, &names::coupler_wake(run))?;
        let mut ports = Vec::new();
        for name in names {
            ports.push(Port {
                commands: channel::bytes_out(&node, &names::command(run, name))?,
                status: channel::bytes_in(&node, &names::status(run, name))?,
                wake: channel::notifier(&node, &names::wake(run, name))?,
            });
        }
        Ok(Supervisor {
            names: names.to_vec(),
            ports,
            listener,
            abort,
            declarations: Vec::new(),
            send_s: 0.0,
            _node: node,
        })
    }

    pub fn names(&self) -> &[String] {
        &self.names
    }

    /// The declarations, once [`join`](Self::join) has collected them.
    pub fn declarations(&self) -> &[Declaration] {
        &self.declarations
    }

    fn send(&mut self, i: usize, msg: &ToParticipant) -> Result<(), SuperviseError> {
        let t0 = Instant::now();
        let port = &self.ports[i];
        channel::send_message(&port.commands, &port.wake, msg).map_err(SuperviseError::Channel)?;
        self.send_s += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// The next message of participant `i`, or why there is none.
    fn wait(&self, i: usize, timeout: Duration) -> Result<FromParticipant, SuperviseError> {
        let abort = || self.abort.load(Ordering::Relaxed);
        let msg = channel::wait_until(&self.listener, Some(timeout), &abort, || {
            channel::try_receive_message::<FromParticipant>(&self.ports[i].status)
        })
        .map_err(|e| self.channel_error(i, e))?;
        self.refuse_failure(i, msg)
    }

    fn channel_error(&self, i: usize, e: ChannelError) -> SuperviseError {
        match e {
            ChannelError::Timeout(seconds) => SuperviseError::Timeout {
                participant: self.names[i].clone(),
                seconds,
                detail: String::new(),
            },
            ChannelError::Aborted => SuperviseError::Aborted,
            other => SuperviseError::Channel(other),
        }
    }

    /// A failure or a stall is an error; anything else is passed on.
    fn refuse_failure(
        &self,
        i: usize,
        msg: FromParticipant,
    ) -> Result<FromParticipant, SuperviseError> {
        match msg {
            FromParticipant::Failed { reason } => Err(SuperviseError::Failed {
                participant: self.names[i].clone(),
                reason,
            }),
            FromParticipant::Stalled {
                field,
                writer,
                seconds,
                then,
            } => Err(stalled(&self.names[i], &field, writer, then, seconds)),
            other => Ok(other),
        }
    }

    fn protocol(&self, i: usize, expected: &'static str, got: FromParticipant) -> SuperviseError {
        SuperviseError::Protocol {
            participant: self.names[i].clone(),
            expected,
            got: format!("{got:?}"),
        }
    }

    /// Wait for every participant's hello (`connect` long at most), send
    /// each its setup, and collect their declarations (`timeout` each).
    pub fn join(
        &mut self,
        setup: impl Fn(&str) -> Setup,
        connect: Duration,
        timeout: Duration,
    ) -> Result<(), SuperviseError> {
        for i in 0..self.names.len() {
            match self.wait(i, connect) {
                Ok(FromParticipant::Hello { .. }) => {}
                Ok(other) => return Err(self.protocol(i, "Hello", other)),
                Err(SuperviseError::Timeout {
                    participant,
                    seconds,
                    ..
                }) => {
                    return Err(SuperviseError::Timeout {
                        participant,
                        seconds,
                        detail:
                            ": it never connected (does its program speak the canopy protocol?)"
                                .into(),
                    })
                }
                Err(e) => return Err(e),
            }
            let s = setup(&self.names[i]);
            self.send(i, &ToParticipant::Setup(s))?;
        }
        let mut declarations = Vec::new();
        for i in 0..self.names.len() {
            match self.wait(i, timeout)? {
                FromParticipant::Declare(d) => declarations.push(d),
                other => return Err(self.protocol(i, "Declare", other)),
            }
        }
        if let Some(first) = self.names.first() {
            self.refuse_unsupported(&setup(first), &declarations)?;
        }
        self.declarations = declarations;
        Ok(())
    }

    /// What the run's `setup` asks of every participant that one's
    /// declaration does not offer: implicit coupling needs
    /// `checkpoints()`, run checkpoints and a restart need `restarts()`.
    fn refuse_unsupported(
        &self,
        setup: &Setup,
        declarations: &[Declaration],
    ) -> Result<(), SuperviseError> {
        type Offers = fn(&Declaration) -> bool;
        let restarts = setup.timing.checkpoint_interval > 0.0 || setup.resume.is_some();
        let needs: [(bool, Offers, &str); 2] = [
            (
                setup.scheme.implicit().is_some(),
                Declaration::supports_checkpoints,
                "[coupling] scheme = \"implicit\" takes windows again from their \
                 checkpoints, and `{who}` does not save and restore them \
                 (its declaration lacks `checkpoints()`): use scheme = \"explicit\"",
            ),
            (
                restarts,
                Declaration::supports_restarts,
                "[run] checkpoint_interval asks every participant to write run \
                 checkpoints, and `{who}` does not (its declaration lacks \
                 `restarts()`): remove checkpoint_interval",
            ),
        ];
        self.refuse_uneven_impulses(setup, declarations)?;
        for (wanted, offers, message) in needs {
            let unable: Vec<&str> = (self.names.iter().zip(declarations))
                .filter(|(_, d)| !offers(d))
                .map(|(n, _)| n.as_str())
                .collect();
            if wanted && !unable.is_empty() {
                let who = unable.join("`, `");
                return Err(SuperviseError::Mismatch(message.replace("{who}", &who)));
            }
        }
        Ok(())
    }

    /// A participant stepping per impulse sub-step beside another takes its
    /// sub-steps n_i at a time: refused where n_i does not divide them.
    fn refuse_uneven_impulses(
        &self,
        setup: &Setup,
        declarations: &[Declaration],
    ) -> Result<(), SuperviseError> {
        let per_impulse = |d: &Declaration| match d.cadence {
            Cadence::PerImpulse {
                substeps_per_window,
            } => Some(substeps_per_window),
            Cadence::PerWindow { .. } => None,
        };
        let n_i = setup.timing.impulse_substeps.max(1);
        if declarations.iter().filter_map(per_impulse).count() < 2 {
            return Ok(());
        }
        let uneven = (self.names.iter().zip(declarations))
            .find_map(|(name, d)| per_impulse(d).filter(|n| n % n_i != 0).map(|n| (name, n)));
        match uneven {
            Some((name, n)) => Err(SuperviseError::Mismatch(format!(
                "`{name}` declares {n} sub-steps a window, which [coupling] impulse_substeps = \
                 {n_i} does not divide: between two impulse exchanges it takes a whole \
                 number of its sub-steps (declare a multiple of {n_i})"
            ))),
            None => Ok(()),
        }
    }

    /// Connect the declared fields, wait until every participant has opened
    /// its ports, and start them all.
    pub fn start(&mut self, timeout: Duration) -> Result<(), SuperviseError> {
        let connections =
            connect_fields(&self.names, &self.declarations).map_err(SuperviseError::Mismatch)?;
        for (i, c) in connections.into_iter().enumerate() {
            self.send(i, &ToParticipant::Connections(c))?;
        }
        for i in 0..self.names.len() {
            match self.wait(i, timeout)? {
                FromParticipant::Ready => {}
                other => return Err(self.protocol(i, "Ready", other)),
            }
        }
        for i in 0..self.names.len() {
            self.send(i, &ToParticipant::Start)?;
        }
        Ok(())
    }

    /// Tell participant `i` that `monitors.csv` holds its first `rows`
    /// rows on disk (the answer to [`Report::Checkpoint`]).
    pub fn rows_kept(&mut self, i: usize, rows: u64) -> Result<(), SuperviseError> {
        self.send(i, &ToParticipant::RowsKept { rows })
    }

    /// Whether participant `i` declared the summary `name`.
    fn declared_summary(&self, i: usize, name: &str) -> bool {
        self.declarations.get(i).and_then(|d| d.summary.as_deref()) == Some(name)
    }

    /// The next report of any participant, waiting at most `slice` for one.
    pub fn next_report(&self, slice: Duration) -> Result<Option<(usize, Report)>, SuperviseError> {
        let deadline = Instant::now() + slice;
        loop {
            for i in 0..self.ports.len() {
                let msg = channel::try_receive_message::<FromParticipant>(&self.ports[i].status)
                    .map_err(SuperviseError::Channel)?;
                let Some(msg) = msg else { continue };
                let report = match self.refuse_failure(i, msg)? {
                    FromParticipant::Monitors {
                        first_row,
                        rows,
                        width,
                        values,
                    } => Report::Monitors {
                        first_row,
                        rows,
                        width,
                        values,
                    },
                    FromParticipant::Finished(stats) => Report::Finished(stats),
                    FromParticipant::Summary(s) if self.declared_summary(i, &s.name) => {
                        Report::Summary(s)
                    }
                    FromParticipant::Checkpoint { rows } => Report::Checkpoint { rows },
                    FromParticipant::Tried { window, tries } => Report::Tried { window, tries },
                    other => return Err(self.protocol(i, "a report", other)),
                };
                return Ok(Some((i, report)));
            }
            if self.abort.load(Ordering::Relaxed) {
                return Err(SuperviseError::Aborted);
            }
            let now = Instant::now();
            if now >= deadline {
                return Ok(None);
            }
            channel::block(&self.listener, deadline - now).map_err(SuperviseError::Channel)?;
        }
    }
}
