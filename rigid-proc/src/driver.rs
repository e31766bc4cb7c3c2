//! Drives the rigid bodies through the run's schedule: reads the
//! structure's impulses and the fluid's loads, steps the bodies, sends back
//! their states and attachment points, reports monitors, writes output.
//! The physics stays in [`Bodies`]; the IPC stays here and in the
//! participant library.

use crate::checkpoint::Checkpoint;
use crate::output::{write_points, write_surfaces};
use crate::{Bodies, Load};
use exchange::fields::{
    ATTACHMENT_IMPULSE, ATTACHMENT_STATE, ATTACHMENT_STATE_LEN, BODY_LOADS, BODY_STATES,
    COLLISION_BODIES, COLLISION_IMPULSE, LOAD_LEN, STATE_LEN,
};
use nalgebra::Vector3;
use participant::vtu::Series;
use participant::{Advance, Cadence, Command, Declaration, Monitor, Participant};
use rigid_section::Scene;

type Error = Box<dyn std::error::Error>;

fn monitors(b: &Bodies) -> Vec<Monitor> {
    let (p, l) = (b.momentum(), b.angular_momentum());
    let mut v = vec![
        Monitor::new("kinetic_energy", b.kinetic_energy()),
        Monitor::new("potential_energy", b.potential_energy()),
        Monitor::new("momentum.x", p.x),
        Monitor::new("momentum.y", p.y),
        Monitor::new("momentum.z", p.z),
        Monitor::new("angular_momentum", l.norm()),
        Monitor::new("contact_impulses", b.contact_impulses as f64),
    ];
    let xyz = ["x", "y", "z"];
    for body in b
        .bodies
        .iter()
        .filter(|body| body.inv_mass() > 0.0 || body.state.v != Vector3::zeros())
    {
        let s = &body.state;
        let omega = body.world_angular_velocity();
        for c in 0..3 {
            v.push(Monitor::new(format!("{}.{}", body.name, xyz[c]), s.x[c]));
        }
        for c in 0..3 {
            v.push(Monitor::new(format!("{}.v{}", body.name, xyz[c]), s.v[c]));
        }
        if body.shape.is_some() {
            for c in 0..3 {
                v.push(Monitor::new(
                    format!("{}.omega{}", body.name, xyz[c]),
                    omega[c],
                ));
            }
            // Angular velocity about each principal axis, wᵢ of eq. (2.12).
            for c in 0..3 {
                v.push(Monitor::new(format!("{}.w{}", body.name, c + 1), s.w[c]));
            }
            v.push(Monitor::new(
                format!("{}.kinetic_energy", body.name),
                body.kinetic_energy(),
            ));
            v.push(Monitor::new(
                format!("{}.spin_momentum", body.name),
                body.spin_momentum().norm(),
            ));
        }
    }
    v
}

/// Monitor `name`'s SI unit (for the report's axes; empty: none known).
fn unit_of(name: &str) -> &'static str {
    let ends = |suffixes: &[&str]| suffixes.iter().any(|s| name.ends_with(s));
    match name {
        "kinetic_energy" | "potential_energy" => "J",
        "angular_momentum" => "kg·m²/s",
        "contact_impulses" => "impulses",
        n if n.starts_with("momentum.") => "kg·m/s",
        // A body's: its energy and spin, its centre, velocity and spin rates.
        _ if ends(&[".kinetic_energy"]) => "J",
        _ if ends(&[".spin_momentum"]) => "kg·m²/s",
        _ if ends(&[".omegax", ".omegay", ".omegaz", ".w1", ".w2", ".w3"]) => "rad/s",
        _ if ends(&[".vx", ".vy", ".vz"]) => "m/s",
        _ if ends(&[".x", ".y", ".z"]) => "m",
        _ => "",
    }
}

fn publish(p: &mut Participant, b: &Bodies, window_end: bool) -> Result<(), Error> {
    let n = ATTACHMENT_STATE_LEN * b.attachments.len();
    p.write_field(ATTACHMENT_STATE, n, |out| b.attachment_state(out))?;
    let n = STATE_LEN * b.bodies.len();
    p.write_field(COLLISION_BODIES, n, |out| b.write_states(out))?;
    if window_end {
        p.write_field(BODY_STATES, n, |out| b.write_states(out))?;
    }
    Ok(())
}

/// What the bodies exchange: their states and attachment points out, the
/// structure's impulses and the fluid's loads in. They step per impulse
/// sub-step, trading impulses with the structure.
fn declaration(b: &Bodies, n_i: u32) -> Declaration {
    let n = b.bodies.len();
    Declaration::new(Cadence::PerImpulse {
        substeps_per_window: n_i,
    })
    .writes(
        ATTACHMENT_STATE,
        ATTACHMENT_STATE_LEN as u32,
        b.attachments.len(),
    )
    .writes(COLLISION_BODIES, STATE_LEN as u32, n)
    .writes(BODY_STATES, STATE_LEN as u32, n)
    .reads_if_written(BODY_LOADS)
    .reads_if_written(ATTACHMENT_IMPULSE)
    .reads_if_written(COLLISION_IMPULSE)
    .monitors(monitors(b).into_iter().map(|m| m.name))
    .units(unit_of)
    .checkpoints()
    .restarts()
}

/// Join the run as the rigid-body participant, build the bodies of the
/// scenario's `[rigid]` section and step them to the end of the schedule.
pub fn run() -> Result<(), Error> {
    let joining = participant::connect()?;
    let scene = Scene::load(joining.scenario_path(), joining.scenario())?;
    let bodies = Bodies::new(&scene.rigid, &scene.attachments)?;
    let n_i = scene.scenario.coupling.impulse_substeps;
    let mut p = joining.declare(declaration(&bodies, n_i))?;
    let mut d = Driven {
        // Centres of mass of every body, and the surfaces of bodies with shapes.
        centres: Series::new(p.run_dir(), "bodies"),
        surfaces: bodies
            .bodies
            .iter()
            .any(|b| b.shape.is_some())
            .then(|| Series::new(p.run_dir(), "body-surfaces")),
        bodies,
        loads: Vec::new(),
        loads_window: None,
        steps: 0,
        checkpoint: Checkpoint::default(),
        impulses_as_forces: scene.scenario.coupling.bodies_iterate(),
    };
    p.reporting(|p| d.drive(p))?;
    p.finish(d.steps)?;
    Ok(())
}

/// What rigid-proc keeps in a run checkpoint: the bodies, the outputs
/// written so far, and the steps taken (for the statistics).
#[derive(serde::Serialize, serde::Deserialize)]
struct RunState {
    bodies: Checkpoint,
    centres: Vec<(f64, String)>,
    surfaces: Option<Vec<(f64, String)>>,
    steps: u64,
}

impl RunState {
    fn write(&self, path: &std::path::Path) -> std::io::Result<()> {
        participant::restart::write(path, self)
    }

    fn read(path: &std::path::Path) -> std::io::Result<RunState> {
        participant::restart::read(path)
    }
}

/// The bodies taking part in a run, their output, and the fluid's loads
/// for the current window.
struct Driven {
    bodies: Bodies,
    centres: Series,
    surfaces: Option<Series>,
    loads: Vec<Load>,
    loads_window: Option<u64>,
    steps: u64,
    /// The window's start, for implicit coupling to take it again.
    checkpoint: Checkpoint,
    /// Whether the structure's impulses act as constant forces over the
    /// step rather than as kicks at its start (`bodies_iterate`).
    impulses_as_forces: bool,
}

impl Driven {
    /// The schedule, to its end.
    fn drive(&mut self, p: &mut Participant) -> Result<(), Error> {
        loop {
            match p.next_command()? {
                Command::Initialize => {
                    publish(p, &self.bodies, true)?;
                    p.done(monitors(&self.bodies))?;
                }
                Command::SaveCheckpoint => {
                    self.bodies.save(&mut self.checkpoint);
                    p.done(Vec::new())?;
                }
                Command::RestoreCheckpoint => {
                    self.bodies.restore(&self.checkpoint);
                    // The window's load comes again with its next try.
                    self.loads_window = None;
                    p.done(Vec::new())?;
                }
                Command::WriteCheckpoint { window } => {
                    self.run_state().write(&p.state_file(window))?;
                    p.done(Vec::new())?;
                }
                Command::Resume { window } => {
                    self.resume(p, window)?;
                    publish(p, &self.bodies, true)?;
                    p.done(Vec::new())?;
                }
                Command::Advance(step) => self.advance(p, &step)?,
                Command::Output { index, time } => {
                    write_points(&mut self.centres, &self.bodies, index, time)?;
                    if let Some(series) = &mut self.surfaces {
                        write_surfaces(series, &self.bodies, index, time)?;
                    }
                    p.done(Vec::new())?;
                }
                Command::Stop => return Ok(()),
            }
        }
    }

    /// What a run checkpoint keeps.
    fn run_state(&self) -> RunState {
        let mut bodies = Checkpoint::default();
        self.bodies.save(&mut bodies);
        RunState {
            bodies,
            centres: self.centres.entries().to_vec(),
            surfaces: self.surfaces.as_ref().map(|s| s.entries().to_vec()),
            steps: self.steps,
        }
    }

    /// A restarted run: the bodies and outputs as the run checkpoint of
    /// `window` kept them.
    fn resume(&mut self, p: &Participant, window: u64) -> Result<(), Error> {
        let saved = RunState::read(&p.state_file(window))?;
        self.bodies.restore(&saved.bodies);
        self.centres.resume(saved.centres)?;
        if let (Some(series), Some(entries)) = (&mut self.surfaces, saved.surfaces) {
            series.resume(entries)?;
        }
        self.steps = saved.steps;
        Ok(())
    }

    fn advance(&mut self, p: &mut Participant, step: &Advance) -> Result<(), Error> {
        // The fluid sends one load per window; its sub-steps keep it.
        if p.is_connected(BODY_LOADS) && self.loads_window != Some(step.window) {
            let f = p.read_field(BODY_LOADS)?;
            self.loads = f
                .chunks_exact(LOAD_LEN)
                .map(|c| Load {
                    force: Vector3::new(c[0], c[1], c[2]),
                    torque: Vector3::new(c[3], c[4], c[5]),
                })
                .collect();
            self.loads_window = Some(step.window);
        }
        let impulse = match p.is_connected(ATTACHMENT_IMPULSE) {
            true => Some(p.read_field(ATTACHMENT_IMPULSE)?),
            false => None,
        };
        if p.is_connected(COLLISION_IMPULSE) {
            self.bodies.apply_momenta(&p.read_field(COLLISION_IMPULSE)?);
        }
        let h = step.dt / step.substeps as f64;
        let impulse = impulse.as_deref().unwrap_or(&[]);
        if self.impulses_as_forces {
            // The impulse is the structure's force integrated along this
            // try's path: spread over the step (`bodies_iterate`).
            let loads = self
                .bodies
                .with_impulses_as_forces(impulse, step.dt, &self.loads);
            for _ in 0..step.substeps {
                self.bodies.step(h, &[], &loads);
            }
        } else {
            for k in 0..step.substeps {
                // The impulse covers the whole step; apply it in the first
                // sub-step: with Euler–Cromer's impulse the coupled step is
                // then symplectic Euler.
                let j = if k == 0 { impulse } else { &[] };
                self.bodies.step(h, j, &self.loads);
            }
        }
        self.steps += step.substeps as u64;
        if let Some(name) = self.bodies.first_non_finite() {
            let t = step.time + step.dt;
            return Err(
                format!("diverged at t = {t:.6e} s: body `{name}` has a non-finite state").into(),
            );
        }
        publish(p, &self.bodies, step.window_end)?;
        p.done(match step.window_end {
            true => monitors(&self.bodies),
            false => Vec::new(),
        })?;
        Ok(())
    }
}
