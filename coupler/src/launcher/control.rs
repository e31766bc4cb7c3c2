//! The coupler's end of the control channels: one command port and one status
//! port per participant, and one event that wakes the coupler.

use crate::channel::{self, BytesIn, BytesOut, ChannelError, Ipc};
use crate::names;
use crate::protocol::{Command, Role, Stats, Status};
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use std::collections::BTreeMap;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

struct Port {
    commands: BytesOut,
    status: BytesIn,
    wake: Notifier<Ipc>,
}

/// Why a participant did not give the expected answer.
#[derive(Debug, thiserror::Error)]
pub enum ControlError {
    #[error("participant `{role}` reported failure: {reason}")]
    Failed { role: &'static str, reason: String },
    #[error("participant `{role}` did not answer within {seconds:.1} s")]
    Timeout { role: &'static str, seconds: f64 },
    #[error("participant `{role}` sent {got} where {expected} was expected")]
    Protocol {
        role: &'static str,
        expected: &'static str,
        got: String,
    },
    #[error("stopped")]
    Aborted,
    #[error("{0}")]
    Output(String),
    #[error("coupling channel: {0}")]
    Channel(ChannelError),
}

pub struct Control {
    ports: BTreeMap<Role, Port>,
    listener: Listener<Ipc>,
    abort: Arc<AtomicBool>,
    /// Seconds spent sending commands (the coupler's share of exchange time).
    pub send_s: f64,
    _node: Node<Ipc>,
}

impl Control {
    pub fn open(
        run: &str,
        roles: &[Role],
        abort: Arc<AtomicBool>,
    ) -> Result<Control, ChannelError> {
        let node = channel::node("coupler")?;
        let listener = channel::listener(&node, &names::coupler_wake(run))?;
        let mut ports = BTreeMap::new();
        for &role in roles {
            ports.insert(
                role,
                Port {
                    commands: channel::bytes_out(&node, &names::command(run, role))?,
                    status: channel::bytes_in(&node, &names::status(run, role))?,
                    wake: channel::notifier(&node, &names::participant_wake(run, role))?,
                },
            );
        }
        Ok(Control {
            ports,
            listener,
            abort,
            send_s: 0.0,
            _node: node,
        })
    }

    pub fn send(&mut self, role: Role, cmd: &Command) -> Result<(), ControlError> {
        let t0 = Instant::now();
        let port = &self.ports[&role];
        channel::send_message(&port.commands, &port.wake, cmd).map_err(ControlError::Channel)?;
        self.send_s += t0.elapsed().as_secs_f64();
        Ok(())
    }

    /// The next status from `role`, or why there is none.
    pub fn wait(&self, role: Role, timeout: Duration) -> Result<Status, ControlError> {
        let port = &self.ports[&role];
        let abort = || self.abort.load(Ordering::Relaxed);
        let status = channel::wait_until(&self.listener, Some(timeout), &abort, || {
            channel::try_receive_message::<Status>(&port.status)
        })
        .map_err(|e| match e {
            ChannelError::Timeout(s) => ControlError::Timeout {
                role: role.name(),
                seconds: s,
            },
            ChannelError::Aborted => ControlError::Aborted,
            other => ControlError::Channel(other),
        })?;
        if let Status::Failed { reason } = status {
            return Err(ControlError::Failed {
                role: role.name(),
                reason,
            });
        }
        Ok(status)
    }

    fn expect(
        &self,
        role: Role,
        timeout: Duration,
        expected: &'static str,
        ok: impl Fn(&Status) -> bool,
    ) -> Result<Status, ControlError> {
        let s = self.wait(role, timeout)?;
        if ok(&s) {
            Ok(s)
        } else {
            Err(ControlError::Protocol {
                role: role.name(),
                expected,
                got: format!("{s:?}"),
            })
        }
    }

    pub fn expect_connected(&self, role: Role, timeout: Duration) -> Result<(), ControlError> {
        self.expect(role, timeout, "Connected", |s| {
            matches!(s, Status::Connected)
        })
        .map(|_| ())
    }

    pub fn expect_ready(&self, role: Role, timeout: Duration) -> Result<(), ControlError> {
        self.expect(role, timeout, "Ready", |s| matches!(s, Status::Ready))
            .map(|_| ())
    }

    /// Send `cmd` and wait for `Done`; returns its monitors.
    pub fn call(
        &mut self,
        role: Role,
        cmd: &Command,
        timeout: Duration,
    ) -> Result<Vec<crate::Monitor>, ControlError> {
        self.send(role, cmd)?;
        match self.expect(role, timeout, "Done", |s| matches!(s, Status::Done { .. }))? {
            Status::Done { monitors } => Ok(monitors),
            _ => unreachable!("expect() checked the variant"),
        }
    }

    pub fn expect_finished(&self, role: Role, timeout: Duration) -> Result<Stats, ControlError> {
        match self.expect(role, timeout, "Finished", |s| {
            matches!(s, Status::Finished(_))
        })? {
            Status::Finished(stats) => Ok(stats),
            _ => unreachable!("expect() checked the variant"),
        }
    }
}
