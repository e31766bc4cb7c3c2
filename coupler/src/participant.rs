//! The participant API: what a solver process calls to take part in a run.
//!
//! ```no_run
//! use coupler::{Command, Field, Participant, Role, Monitor};
//! let mut p = Participant::connect(Role::Structure)?;
//! let n = 3;
//! loop {
//!     match p.next_command()? {
//!         Command::Initialize => {
//!             p.write_field(Field::CanopyPositions, n, |out| out.fill(0.0))?;
//!             p.done(vec![])?;
//!         }
//!         Command::Advance(step) => {
//!             // read inputs in place, step the physics, write outputs in place
//!             p.done(vec![Monitor::new("kinetic_energy", 0.0)])?;
//!         }
//!         Command::Output { .. } => p.done(vec![])?,
//!         Command::Stop => break,
//!         Command::Setup(_) => unreachable!("connect() consumes the setup"),
//!     }
//! }
//! p.finish(0)?;
//! # Ok::<(), coupler::ExchangeError>(())
//! ```
//!
//! Fields are zero-copy: [`Participant::write_field`] hands the solver the
//! loaned shared-memory slice to compute into, and [`Participant::read_field`]
//! returns a view of the received sample, read in place.

use crate::channel::{self, BytesIn, BytesOut, ChannelError, FieldIn, FieldOut, FieldSample, Ipc};
use crate::names;
use crate::protocol::{Command, Field, Monitor, Role, Setup, Stats, Status};
use crate::scenario::Scenario;
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use std::collections::HashMap;
use std::path::Path;
use std::time::{Duration, Instant};

/// How long a participant waits for its setup after connecting.
const SETUP_TIMEOUT: Duration = Duration::from_secs(60);

#[derive(Debug, thiserror::Error)]
pub enum ExchangeError {
    #[error("not launched by the coupler: environment variable {0} is not set")]
    NotLaunched(&'static str),
    #[error("{0}")]
    Channel(#[from] ChannelError),
    #[error("field {0} is not exchanged in this run")]
    NotConnected(&'static str),
    #[error("field {0}: no new value arrived since the last read")]
    NoNewData(&'static str),
    #[error("expected {expected}, the coupler sent {got}")]
    Protocol { expected: &'static str, got: String },
    #[error("the resolved scenario does not parse: {0}")]
    Scenario(String),
}

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

/// One solver's connection to a run. See the module docs for the call sequence.
pub struct Participant {
    role: Role,
    setup: Setup,
    scenario: Scenario,
    commands: BytesIn,
    status: BytesOut,
    wake_coupler: Notifier<Ipc>,
    wake_me: Listener<Ipc>,
    outputs: HashMap<Field, FieldOut>,
    inputs: HashMap<Field, FieldIn>,
    stats: Stats,
    started: Instant,
    // Declared last: ports are dropped before their node.
    _node: Node<Ipc>,
}

impl Participant {
    /// Connect to the run that launched this process (run id and role come
    /// from the environment the launcher sets), receive the setup and open the
    /// field ports. Returns when the coupler may send `Initialize`.
    pub fn connect(role: Role) -> Result<Participant, ExchangeError> {
        let run = std::env::var(names::ENV_RUN_ID)
            .map_err(|_| ExchangeError::NotLaunched(names::ENV_RUN_ID))?;
        let started = Instant::now();
        let node = channel::node(role.name())?;
        let commands = channel::bytes_in(&node, &names::command(&run, role))?;
        let status = channel::bytes_out(&node, &names::status(&run, role))?;
        let wake_me = channel::listener(&node, &names::participant_wake(&run, role))?;
        let wake_coupler = channel::notifier(&node, &names::coupler_wake(&run))?;
        channel::send_message(&status, &wake_coupler, &Status::Connected)?;

        let never = || false;
        let cmd: Command = channel::wait_until(&wake_me, Some(SETUP_TIMEOUT), &never, || {
            channel::try_receive_message(&commands)
        })?;
        let setup = match cmd {
            Command::Setup(s) => s,
            other => {
                return Err(ExchangeError::Protocol {
                    expected: "Setup",
                    got: format!("{other:?}"),
                })
            }
        };
        let scenario = Scenario::from_resolved(&setup.scenario_toml)
            .map_err(|e| ExchangeError::Scenario(e.to_string()))?;

        let mut outputs = HashMap::new();
        let mut inputs = HashMap::new();
        for field in Field::ALL {
            if !field.is_connected(&setup.present, &scenario) {
                continue;
            }
            let (producer, consumer) = field.route();
            let name = names::field(&run, field);
            if producer == role {
                outputs.insert(field, channel::field_out(&node, &name, 1024)?);
            } else if consumer == role {
                inputs.insert(field, channel::field_in(&node, &name)?);
            }
        }
        let mut p = Participant {
            role,
            setup,
            scenario,
            commands,
            status,
            wake_coupler,
            wake_me,
            outputs,
            inputs,
            stats: Stats::default(),
            started,
            _node: node,
        };
        p.reply(&Status::Ready)?;
        Ok(p)
    }

    pub fn role(&self) -> Role {
        self.role
    }

    /// The resolved scenario of this run.
    pub fn scenario(&self) -> &Scenario {
        &self.scenario
    }

    /// The run directory, where the participant writes its own `.vtu`/`.pvd` files.
    pub fn run_dir(&self) -> &Path {
        &self.setup.run_dir
    }

    /// Whether a role takes part in this run.
    pub fn is_present(&self, role: Role) -> bool {
        self.setup.present.contains(&role)
    }

    /// Whether `field` is exchanged in this run (its producer and consumer both take part).
    pub fn is_connected(&self, field: Field) -> bool {
        field.is_connected(&self.setup.present, &self.scenario)
    }

    /// Publish `len` values of `field`. `fill` receives the loaned shared-memory
    /// slice and must overwrite every value (its previous contents are stale
    /// values of an earlier exchange). A field nobody reads in this run is
    /// skipped without calling `fill`.
    pub fn write_field(
        &mut self,
        field: Field,
        len: usize,
        fill: impl FnOnce(&mut [f64]),
    ) -> Result<(), ExchangeError> {
        let Some(publisher) = self.outputs.get(&field) else {
            return Ok(());
        };
        let t0 = Instant::now();
        let sample = publisher
            .loan_slice_uninit(len)
            .map_err(channel::ipc_err("loan field"))?;
        // SAFETY: the payload lies in a shared-memory segment the OS zero-filled
        // when it was mapped and which since holds only f64 values, so every
        // element is an initialised f64; `fill` overwrites all of them.
        let mut sample = unsafe { sample.assume_init() };
        let compute = Instant::now();
        fill(sample.payload_mut());
        let computed = compute.elapsed();
        sample.send().map_err(channel::ipc_err("send field"))?;
        self.stats.exchange_s += (t0.elapsed() - computed).as_secs_f64();
        Ok(())
    }

    /// The newest value of `field` that arrived since the last read, in place.
    /// Fails with [`ExchangeError::NoNewData`] when nothing new arrived: the
    /// schedule guarantees inputs are sent before the command that needs them.
    pub fn read_field(&mut self, field: Field) -> Result<FieldView, ExchangeError> {
        let t0 = Instant::now();
        let subscriber = self
            .inputs
            .get(&field)
            .ok_or(ExchangeError::NotConnected(field.name()))?;
        let mut newest = None;
        while let Some(s) = subscriber
            .receive()
            .map_err(channel::ipc_err("receive field"))?
        {
            newest = Some(s);
        }
        self.stats.exchange_s += t0.elapsed().as_secs_f64();
        newest
            .map(|sample| FieldView { sample })
            .ok_or(ExchangeError::NoNewData(field.name()))
    }

    /// Block until the coupler sends the next command.
    pub fn next_command(&mut self) -> Result<Command, ExchangeError> {
        let t0 = Instant::now();
        let never = || false;
        let commands = &self.commands;
        let cmd = channel::wait_until(&self.wake_me, None, &never, || {
            channel::try_receive_message(commands)
        })?;
        self.stats.wait_s += t0.elapsed().as_secs_f64();
        self.stats.commands += 1;
        Ok(cmd)
    }

    /// Report the last command done, with monitors (at window ends).
    pub fn done(&mut self, monitors: Vec<Monitor>) -> Result<(), ExchangeError> {
        self.reply(&Status::Done { monitors })
    }

    /// Report that this participant cannot go on; the caller then exits non-zero.
    pub fn fail(&mut self, reason: impl Into<String>) -> Result<(), ExchangeError> {
        self.reply(&Status::Failed {
            reason: reason.into(),
        })
    }

    /// Reply to `Stop` with this process's statistics; `substeps` is the number
    /// of internal sub-steps the solver took.
    pub fn finish(mut self, substeps: u64) -> Result<(), ExchangeError> {
        self.stats.substeps = substeps;
        self.stats.cpu_s = crate::usage::cpu_seconds();
        self.stats.wall_s = self.started.elapsed().as_secs_f64();
        let stats = self.stats.clone();
        self.reply(&Status::Finished(stats))
    }

    fn reply(&mut self, status: &Status) -> Result<(), ExchangeError> {
        let t0 = Instant::now();
        channel::send_message(&self.status, &self.wake_coupler, status)?;
        self.stats.exchange_s += t0.elapsed().as_secs_f64();
        Ok(())
    }
}
