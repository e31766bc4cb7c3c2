//! Joining a run: connect to the coupler that launched this process, read
//! the setup, declare what this participant exchanges, open the field
//! ports the coupler's answer names, and wait for the start.

use crate::channel::{self, BytesIn, Ipc};
use crate::declaration::Declaration;
use crate::error::JoinError;
use crate::fields::{Inputs, Outputs};
use crate::monitors::Rows;
use crate::names;
use crate::participant::{Control, Participant};
use crate::presence::{Own, Presence};
use crate::timing::{Plan, Timing};
use crate::wait::Waiter;
use crate::wire::{Connections, FromParticipant, Setup, ToParticipant};
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use std::path::Path;
use std::time::{Duration, Instant};

/// How long a participant waits for its setup after connecting.
const SETUP_TIMEOUT: Duration = Duration::from_secs(60);

/// Connect to the run that launched this process. Its run id and its
/// participant name come from the environment the launcher sets; returns
/// once the setup has arrived, before anything is declared.
pub fn connect() -> Result<Joining, JoinError> {
    let run =
        std::env::var(names::ENV_RUN_ID).map_err(|_| JoinError::NotLaunched(names::ENV_RUN_ID))?;
    let name = std::env::var(names::ENV_PARTICIPANT)
        .map_err(|_| JoinError::NotLaunched(names::ENV_PARTICIPANT))?;
    connect_as(&run, &name)
}

/// Connect as participant `name` of run `run`, given rather than read
/// from the environment: for participants that run as threads of one
/// process (tests), or a program started by other means than the coupler.
pub fn connect_as(run: &str, name: &str) -> Result<Joining, JoinError> {
    let started = Instant::now();
    let node = channel::node(name)?;
    let commands = channel::bytes_in(&node, &names::command(run, name))?;
    let status = channel::bytes_out(&node, &names::status(run, name))?;
    let listener = channel::listener(&node, &names::wake(run, name))?;
    let own = Own::create(&node, run, name, crate::ranks())?;
    let wake_coupler = channel::notifier(&node, &names::coupler_wake(run))?;
    let hello = FromParticipant::Hello {
        pid: std::process::id(),
    };
    channel::send_message(&status, &wake_coupler, &hello)?;
    let setup = match expect(&listener, &commands, SETUP_TIMEOUT)? {
        ToParticipant::Setup(s) => s,
        other => return Err(protocol("Setup", &other)),
    };
    Ok(Joining {
        name: name.to_string(),
        setup,
        control: Control {
            commands,
            status,
            wake_coupler,
        },
        listener,
        own,
        started,
        node,
    })
}

fn protocol(expected: &'static str, got: &ToParticipant) -> JoinError {
    JoinError::Protocol {
        expected,
        got: format!("{got:?}"),
    }
}

fn expect(
    listener: &Listener<Ipc>,
    commands: &BytesIn,
    timeout: Duration,
) -> Result<ToParticipant, JoinError> {
    let never = || false;
    Ok(channel::wait_until(
        listener,
        Some(timeout),
        &never,
        || channel::try_receive_message(commands),
    )?)
}

/// A participant that has connected and read its setup, and has yet to
/// declare what it exchanges.
pub struct Joining {
    name: String,
    setup: Setup,
    control: Control,
    listener: Listener<Ipc>,
    own: Own,
    started: Instant,
    // Declared last: ports are dropped before their node.
    node: Node<Ipc>,
}

impl Joining {
    /// This participant's name: its key under `[participants]` and its section's name.
    pub fn name(&self) -> &str {
        &self.name
    }

    /// The resolved scenario (every default filled in), as TOML text.
    pub fn scenario(&self) -> &str {
        &self.setup.scenario
    }

    /// The scenario file the run started from, for messages that name it.
    pub fn scenario_path(&self) -> &Path {
        &self.setup.scenario_path
    }

    /// The run directory, where the participant writes its output files.
    pub fn run_dir(&self) -> &Path {
        &self.setup.run_dir
    }

    pub fn timing(&self) -> &Timing {
        &self.setup.timing
    }

    /// The run's participants, by name.
    pub fn participants(&self) -> &[String] {
        &self.setup.participants
    }

    /// Tell the coupler this participant cannot take part (a bad section,
    /// a model that cannot be built); the caller then exits non-zero.
    pub fn fail(self, reason: impl Into<String>) -> Result<(), JoinError> {
        let msg = FromParticipant::Failed {
            reason: reason.into(),
        };
        Ok(self.control.send(&msg)?)
    }

    /// Declare what this participant exchanges, open its ports as the
    /// coupler connects them, and wait until every participant is ready.
    /// Returns the running participant, whose first command is `Initialize`
    /// (`Resume` in a restarted run).
    pub fn declare(self, declaration: Declaration) -> Result<Participant, JoinError> {
        let declaration = match self.setup.scheme.implicit() {
            Some(i) => {
                crate::implicit::with_implicit(declaration, i, &self.name, &self.setup.participants)
            }
            None => declaration,
        };
        if let Some(problem) = declaration.problem() {
            let _ = self.control.send(&FromParticipant::Failed {
                reason: format!("declaration: {problem}"),
            });
            return Err(JoinError::Declaration(problem));
        }
        self.control
            .send(&FromParticipant::Declare(declaration.clone()))?;
        // The coupler answers once every participant has declared, so the
        // slowest one's model building sets the pace.
        let patience = Duration::from_secs_f64(2.0 * self.setup.timing.timeout) + SETUP_TIMEOUT;
        let connections = match expect(&self.listener, &self.control.commands, patience)? {
            ToParticipant::Connections(c) => c,
            other => return Err(protocol("Connections", &other)),
        };
        let ports = self.open_ports(&declaration, &connections)?;
        self.control.send(&FromParticipant::Ready)?;
        match expect(&self.listener, &self.control.commands, patience)? {
            ToParticipant::Start => {}
            other => return Err(protocol("Start", &other)),
        }
        let mut plan = Plan::new(
            &self.setup.timing,
            declaration.cadence,
            connections.partnered,
        );
        if self.setup.scheme.implicit().is_some() {
            plan = plan.implicit();
        }
        if let Some(window) = self.setup.resume {
            plan = plan.resumed_after(window);
        }
        let names = &self.setup.participants;
        let me = names
            .iter()
            .position(|n| *n == self.name)
            .ok_or(JoinError::Protocol {
                expected: "a setup that lists this participant",
                got: format!("{names:?}"),
            })?;
        let presence = Presence::open(&self.node, &self.setup.run_id, names, me, self.own)?;
        Ok(Participant::new(
            self.name,
            self.setup,
            self.control,
            Waiter::new(self.listener, presence),
            ports,
            plan,
            Rows::new(&declaration.monitors),
            self.started,
            self.node,
        ))
    }

    fn open_ports(
        &self,
        declaration: &Declaration,
        connections: &Connections,
    ) -> Result<(Outputs, Inputs), JoinError> {
        let run = &self.setup.run_id;
        if connections.reads.len() != declaration.reads.len()
            || connections.writes.len() != declaration.writes.len()
        {
            return Err(JoinError::Protocol {
                expected: "a connection for every declared field",
                got: format!("{connections:?}"),
            });
        }
        let patience = Duration::from_secs_f64(self.setup.timing.timeout);
        let names = &self.setup.participants;
        let outputs = Outputs::open(
            &self.node,
            run,
            names,
            &declaration.writes,
            &connections.writes,
            patience,
        )?;
        let inputs = Inputs::open(
            &self.node,
            run,
            names,
            &declaration.reads,
            &connections.reads,
        )?;
        Ok((outputs, inputs))
    }
}
