//! Drives a structure solver through the run's schedule: the loop every
//! structure executable shares (structure-proc with its integrators, xpbd-proc
//! with its constraint solver). It reads the fluid's pressure and the rigid
//! bodies' attachment points, asks the [`Stepper`] for the sub-steps, breaks
//! lines, sends back impulses, canopy state and monitors, and writes output.
//! The physics stays in the stepper; the IPC stays here and in the
//! participant library.

use crate::checkpoint::Checkpoint;
use crate::collision::{Contacts, Layers, Obstacles, Stats};
use crate::divergence::Watch;
use crate::forces::Loads;
use crate::opening;
use crate::opening::Record;
use crate::output::Output;
use crate::stability::{omega_max, OMEGA_MAX_MONITOR};
use crate::window_start::WindowStart;
use crate::{build_model, Model, NodeKind};
use exchange::fields::{
    ATTACHMENT_IMPULSE, ATTACHMENT_STATE, CANOPY_POSITIONS, CANOPY_PRESSURE, CANOPY_TRIANGLES,
    CANOPY_VELOCITIES, COLLISION_BODIES, COLLISION_IMPULSE, MOMENTUM_LEN, TRIANGLE_LEN, VECTOR_LEN,
};
use nalgebra::Vector3;
use participant::{Advance, Cadence, Command, Declaration, FieldView, Monitor, Participant};
use std::time::Instant;
use structure_section::{Scene, StructureSection};

pub type Error = Box<dyn std::error::Error>;

pub use crate::stepper::{Scheme, Stepper};

/// The program's `main`: answers `PROGRAM --check SCENARIO` (see
/// [`crate::answer`]), or runs and exits with status 1 and the message on
/// stderr if the run failed.
pub fn main<S: Stepper>(
    program: &str,
    make: impl Fn(&StructureSection, &Model) -> Result<S, Error>,
) {
    scenario::answer_check(|path, text| crate::answer::answer(program, path, text, &make));
    if let Err(e) = run(program, make) {
        eprintln!("{program}: {e}");
        std::process::exit(1);
    }
}

/// What the structure reports at every window end: energies, momentum, the
/// node–body impulses given so far and their sum (with collisions), its ω_max
/// bound (constant, for the coupler's stability estimate; only when it runs
/// the scenario's integrator), the canopy's deflection and the named points.
fn monitors(
    m: &Model,
    omega_max: Option<f64>,
    obstacles: Option<&Obstacles>,
    contacts: Option<&Stats>,
    pressure: Option<&[f64]>,
) -> Vec<Monitor> {
    let p = m.momentum();
    let mut v = vec![
        Monitor::new("kinetic_energy", m.kinetic_energy()),
        Monitor::new("potential_energy", m.potential_energy()),
        Monitor::new("momentum.x", p[0]),
        Monitor::new("momentum.y", p[1]),
        Monitor::new("momentum.z", p[2]),
    ];
    if let Some(o) = obstacles {
        v.push(Monitor::new("collision_impulses", o.impulses as f64));
        // The bodies push through both passes: the node–body impulses and
        // the static bodies' surfaces in the contact pass.
        let surfaces = contacts.map_or([0.0; 3], |s| s.received);
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            v.push(Monitor::new(
                format!("collision_impulse.{axis}"),
                o.received[c] + surfaces[c],
            ));
        }
    }
    if let Some(s) = contacts {
        let counts = [
            ("proximity_impulses", s.proximity),
            ("collision_impulses", s.collisions),
            ("impact_zone_steps", s.zone_steps),
            ("fabric_fabric", s.fabric_fabric),
            ("fabric_string", s.fabric_string),
            ("string_string", s.string_string),
            ("structure_body", s.structure_body),
        ];
        for (name, n) in counts {
            v.push(Monitor::new(format!("contact.{name}"), n as f64));
        }
    }
    if let Some(w) = omega_max {
        v.push(Monitor::new(OMEGA_MAX_MONITOR, w));
    }
    if m.canopy_nodes > 0 {
        v.push(Monitor::new("centre_deflection", m.centre_deflection()));
    }
    for (name, n) in &m.points {
        // A held payload is a point of the monitors from the start.
        let held = m.hold.is_some_and(|h| h.node == *n);
        if m.kind[*n] == NodeKind::Free || held {
            for (c, axis) in ["x", "y", "z", "vx", "vy", "vz"].iter().enumerate() {
                let value = if c < 3 {
                    m.x[3 * n + c]
                } else {
                    m.v[3 * n + c - 3]
                };
                v.push(Monitor::new(format!("{name}.{axis}"), value));
            }
        }
    }
    v.extend(m.parachute_monitors(pressure).into_iter().flatten());
    v
}

/// Canopy positions and velocities for the fluid (and, once, its triangles).
fn publish_canopy(p: &mut Participant, m: &Model, with_triangles: bool) -> Result<(), Error> {
    let n = VECTOR_LEN * m.canopy_nodes;
    if with_triangles {
        p.write_field(CANOPY_TRIANGLES, TRIANGLE_LEN * m.triangles.len(), |out| {
            for (o, &i) in out.iter_mut().zip(m.triangles.iter().flatten()) {
                *o = i as f64;
            }
        })?;
    }
    p.write_field(CANOPY_POSITIONS, n, |out| out.copy_from_slice(&m.x[..n]))?;
    p.write_field(CANOPY_VELOCITIES, n, |out| out.copy_from_slice(&m.v[..n]))?;
    Ok(())
}

/// What the structure exchanges: the canopy for the fluid, the attachment
/// and collision impulses for the rigid bodies, and its monitors. It steps
/// per impulse sub-step, trading impulses with the rigid bodies.
fn declaration(
    m: &Model,
    obstacles: Option<&Obstacles>,
    monitors: &[Monitor],
    n_s: u32,
) -> Declaration {
    let mut d = Declaration::new(Cadence::PerImpulse {
        substeps_per_window: n_s,
    })
    .writes(CANOPY_TRIANGLES, TRIANGLE_LEN as u32, m.triangles.len())
    .writes(CANOPY_POSITIONS, VECTOR_LEN as u32, m.canopy_nodes)
    .writes(CANOPY_VELOCITIES, VECTOR_LEN as u32, m.canopy_nodes)
    .writes(ATTACHMENT_IMPULSE, VECTOR_LEN as u32, m.attachments.len())
    .reads_if_written(CANOPY_PRESSURE)
    .reads_if_written(ATTACHMENT_STATE)
    .monitors(monitors.iter().map(|m| m.name.clone()))
    .units(crate::units::unit_of)
    .checkpoints()
    .restarts();
    if m.parachute.is_some() {
        d = d.summary(opening::SUMMARY);
    }
    if let Some(o) = obstacles {
        d = d
            .writes(
                COLLISION_IMPULSE,
                MOMENTUM_LEN as u32,
                o.momenta.len() / MOMENTUM_LEN,
            )
            .reads(COLLISION_BODIES);
    }
    d
}

/// Join the run as a structure participant, build the model of the
/// scenario's `[structure]` section, and advance it with the stepper that
/// `make` returns, to the end of the schedule.
pub fn run<S: Stepper>(
    program: &str,
    make: impl FnOnce(&StructureSection, &Model) -> Result<S, Error>,
) -> Result<(), Error> {
    let joining = participant::connect()?;
    let scene = Scene::load(joining.scenario_path(), joining.scenario(), program)?;
    let section = &scene.structure;
    let mut m = build_model(
        section,
        scene.rigid.as_ref(),
        scene.structure.dt(scene.scenario.coupling.window),
    )?;
    // The air the drag refers to: a fluid process sends the canopy's
    // pressure (a structure's own porous load is not a monitor's).
    if let Some(p) = &mut m.parachute {
        p.air_density = scene.fluid.as_ref().map(|f| f.density());
    }
    let obstacles = match (&section.collision, &scene.rigid) {
        (Some(spec), Some(rigid)) => Some(Obstacles::new(rigid, spec)?),
        _ => None,
    };
    let contacts = match &section.collision {
        Some(spec) => Contacts::with_bodies(&m.net, spec, scene.rigid.as_ref())?,
        None => None,
    };
    let watch = Watch::new(&m, &scene);
    let stepper = make(section, &m)?;
    let omega_max = stepper
        .is_scenario_integrator()
        .then(|| omega_max(&m.inv_mass, &m.couplings));
    let stats = contacts.as_ref().map(|c| &c.stats);
    let first = monitors(&m, omega_max, obstacles.as_ref(), stats, None);
    let n_s = section.substeps;
    let mut p = joining.declare(declaration(&m, obstacles.as_ref(), &first, n_s))?;
    let record = m.parachute.map(|p| Record::new(&p)).unwrap_or_default();
    let mut d = Driven {
        output: Output::new(p.run_dir(), &m),
        m,
        obstacles,
        contacts,
        watch,
        stepper,
        omega_max,
        substeps: 0,
        pressure: None,
        pressure_window: None,
        saved: None,
        window_start: WindowStart::new(scene.scenario.coupling.bodies_iterate()),
        record,
        events: Vec::new(),
        retried: scene.scenario.coupling.scheme.is_implicit(),
        timing: [0.0; 2],
    };
    let driven = p.reporting(|p| d.drive(p));
    // A run that stops says what its last try did too.
    d.tell_events();
    d.tell_contact_cost();
    driven?;
    drop(d.pressure.take());
    if let Some(summary) = d.record.summary() {
        p.summarize(summary);
    }
    p.finish(d.substeps)?;
    Ok(())
}

/// A structure model taking part in a run: its stepper, collision
/// obstacles, divergence watch and output, and the pressure the fluid sent
/// for the current window.
struct Driven<S> {
    m: Model,
    obstacles: Option<Obstacles>,
    /// The fabric's and strings' self-contact pass.
    contacts: Option<Contacts>,
    watch: Watch,
    stepper: S,
    omega_max: Option<f64>,
    output: Output,
    substeps: u64,
    pressure: Option<FieldView>,
    pressure_window: Option<u64>,
    /// The window's start, for implicit coupling to take it again.
    saved: Option<Saved>,
    /// The attachment points at the window's start, for its next try.
    window_start: WindowStart,
    /// The parachute's rows for the run's summary (`opening.rs`).
    record: Record,
    /// What the window's sub-steps did (lines broken, the payload
    /// released), told once the window stands: a try taken again forgets
    /// its own, so the log has each event once, from the try that stood.
    events: Vec<String>,
    /// Whether windows are taken again (implicit coupling): else each
    /// stands as it is taken.
    retried: bool,
    /// Seconds the sub-steps took in the integrator and in the contact
    /// pass, every try counted: what the contact pass costs, told when
    /// the run ends.
    timing: [f64; 2],
}

/// What structure-proc keeps in a run checkpoint (`[run]
/// checkpoint_interval`): what a window's start holds, the outputs written
/// so far, and the sub-steps taken.
#[derive(serde::Serialize, serde::Deserialize)]
struct RunState {
    checkpoint: Checkpoint,
    watch: Watch,
    collisions: Option<(u64, [f64; 3])>,
    #[serde(default)]
    contacts: Option<Stats>,
    outputs: [Option<Vec<(f64, String)>>; 2],
    substeps: u64,
    record: Record,
}

/// What a window's start holds beyond the model and stepper
/// (`checkpoint.rs`): the divergence watch's scale and the collision
/// counters the monitors report.
struct Saved {
    checkpoint: Checkpoint,
    watch: Watch,
    collisions: Option<(u64, Vector3<f64>)>,
    contacts: Option<Stats>,
    /// The layered contact model's groups.
    groups: Option<Layers>,
    /// Rows of the summary's record.
    rows: usize,
}

impl<S: Stepper> Driven<S> {
    fn monitors(&self) -> Vec<Monitor> {
        let pressure = self.pressure.as_deref();
        let stats = self.contacts.as_ref().map(|c| &c.stats);
        monitors(
            &self.m,
            self.omega_max,
            self.obstacles.as_ref(),
            stats,
            pressure,
        )
    }

    /// The schedule, to its end.
    fn drive(&mut self, p: &mut Participant) -> Result<(), Error> {
        loop {
            match p.next_command()? {
                Command::Initialize => {
                    publish_canopy(p, &self.m, true)?;
                    let monitors = self.monitors();
                    self.record.add(p.timing().start_time, &monitors);
                    p.done(monitors)?;
                }
                Command::SaveCheckpoint => {
                    // A new window: the last one stood.
                    self.tell_events();
                    self.save();
                    p.done(Vec::new())?;
                }
                Command::RestoreCheckpoint => {
                    self.events.clear();
                    self.restore();
                    p.done(Vec::new())?;
                }
                Command::WriteCheckpoint { window } => {
                    self.tell_events();
                    let state = self.run_state();
                    participant::restart::write(&p.state_file(window), &state)?;
                    p.done(Vec::new())?;
                }
                Command::Resume { window } => {
                    self.resume(participant::restart::read(&p.state_file(window))?)?;
                    publish_canopy(p, &self.m, true)?;
                    p.done(Vec::new())?;
                }
                Command::Advance(step) => self.advance(p, &step)?,
                Command::Output { index, time } => {
                    self.output.write(&self.m, index, time)?;
                    p.done(Vec::new())?;
                }
                Command::Stop => {
                    self.tell_events();
                    return Ok(());
                }
            }
        }
    }

    /// Writes to the log what the contact pass cost against the
    /// sub-steps' own work, if there is one (issue 46 asks at most 5×
    /// over a packed opening).
    fn tell_contact_cost(&self) {
        let [steps, contact] = self.timing;
        if let (Some(c), true) = (&self.contacts, steps > 0.0) {
            eprintln!(
                "the contact pass took {contact:.2} s, {:.2} times the sub-steps' own {steps:.2} s ({} sub-steps, {} of them in quiet spells)",
                contact / steps,
                self.substeps,
                c.quiet_steps()
            );
        }
    }

    /// Writes the events of the window that stood to the log.
    fn tell_events(&mut self) {
        for event in self.events.drain(..) {
            eprintln!("{event}");
        }
    }

    fn save(&mut self) {
        let saved = self.saved.get_or_insert_with(|| Saved {
            checkpoint: Checkpoint::default(),
            watch: self.watch.clone(),
            collisions: None,
            contacts: None,
            groups: None,
            rows: 0,
        });
        self.m.save(&mut saved.checkpoint);
        self.stepper.save_history(&mut saved.checkpoint.history);
        saved.watch.clone_from(&self.watch);
        saved.collisions = self.obstacles.as_ref().map(|o| (o.impulses, o.received));
        saved.contacts = self.contacts.as_ref().map(|c| c.stats);
        saved.groups = self.contacts.as_ref().and_then(Contacts::groups);
        saved.rows = self.record.rows.len();
        self.window_start.first = true;
    }

    fn restore(&mut self) {
        let Some(saved) = &self.saved else { return };
        self.m.restore(&saved.checkpoint);
        self.stepper.restore_history(&saved.checkpoint.history);
        self.watch.clone_from(&saved.watch);
        if let (Some(o), Some((impulses, received))) = (&mut self.obstacles, saved.collisions) {
            o.impulses = impulses;
            o.received = received;
        }
        if let (Some(c), Some(stats)) = (&mut self.contacts, saved.contacts) {
            c.stats = stats;
            if let Some(groups) = &saved.groups {
                c.restore_groups(groups);
            }
            // A line broken since the checkpoint is whole again.
            c.sync(&self.m.net);
        }
        self.record.truncate(saved.rows);
        // The window's pressure comes again with its next try.
        self.pressure_window = None;
        self.window_start.first = true;
    }

    /// What a run checkpoint keeps: a window checkpoint as of now (the
    /// next window's start), the outputs written so far, and the
    /// sub-steps taken (for the statistics).
    fn run_state(&mut self) -> RunState {
        self.save();
        let saved = self.saved.as_ref().expect("just saved");
        RunState {
            checkpoint: saved.checkpoint.clone(),
            watch: saved.watch.clone(),
            collisions: saved.collisions.map(|(n, p)| (n, p.into())),
            contacts: saved.contacts,
            outputs: self.output.entries(),
            substeps: self.substeps,
            record: self.record.clone(),
        }
    }

    /// A restarted run: the model, stepper and outputs as a run checkpoint
    /// kept them.
    fn resume(&mut self, state: RunState) -> Result<(), Error> {
        self.saved = Some(Saved {
            checkpoint: state.checkpoint,
            watch: state.watch,
            collisions: state.collisions.map(|(n, p)| (n, p.into())),
            contacts: state.contacts,
            groups: None,
            rows: state.record.rows.len(),
        });
        self.record = state.record;
        self.restore();
        self.window_start.first = false;
        self.output.resume(state.outputs)?;
        self.substeps = state.substeps;
        Ok(())
    }

    fn advance(&mut self, p: &mut Participant, step: &Advance) -> Result<(), Error> {
        self.read_inputs(p, step)?;
        let failed = self.substeps(step);
        if !self.retried {
            self.tell_events();
        }
        if let Some(why) = failed {
            return Err(why.into());
        }
        let m = &self.m;
        p.write_field(
            ATTACHMENT_IMPULSE,
            VECTOR_LEN * m.attachments.len(),
            |out| {
                for (o, a) in out.chunks_exact_mut(3).zip(&m.attachments) {
                    o.copy_from_slice(&a.impulse);
                }
            },
        )?;
        if let Some(o) = &self.obstacles {
            p.write_field(COLLISION_IMPULSE, o.momenta.len(), |out| {
                out.copy_from_slice(&o.momenta)
            })?;
        }
        if !step.window_end {
            return Ok(p.done(Vec::new())?);
        }
        publish_canopy(p, &self.m, false)?;
        let monitors = self.monitors();
        let (start, length) = p.timing().window_span(step.window);
        self.record.add(start + length, &monitors);
        Ok(p.done(monitors)?)
    }

    /// What the step reads: the window's pressure (the fluid sends one per
    /// window; impulse sub-steps after the first keep it), the rigid
    /// bodies' attachment points and the collision obstacles.
    fn read_inputs(&mut self, p: &mut Participant, step: &Advance) -> Result<(), Error> {
        if p.is_connected(CANOPY_PRESSURE) && self.pressure_window != Some(step.window) {
            self.pressure = Some(p.read_field(CANOPY_PRESSURE)?);
            self.pressure_window = Some(step.window);
        }
        if p.is_connected(ATTACHMENT_STATE) {
            let state = p.read_field(ATTACHMENT_STATE)?;
            self.window_start.place(&mut self.m, &state, step);
            for a in &self.m.attachments {
                let speed = a.v0.iter().map(|c| c * c).sum::<f64>().sqrt();
                self.watch.raise(speed, "the fastest rigid body");
            }
        }
        if let Some(o) = &mut self.obstacles {
            o.set_states(&p.read_field(COLLISION_BODIES)?, step.time);
            if let Some(c) = &mut self.contacts {
                c.place_bodies(&o.bodies);
            }
        }
        Ok(())
    }

    /// The step's sub-steps, collisions and line breaks; why the step
    /// failed or diverged, if it did.
    fn substeps(&mut self, step: &Advance) -> Option<String> {
        let m = &mut self.m;
        let loads = Loads {
            pressure: self.pressure.as_deref().unwrap_or(&[]),
        };
        // The step's inputs: its sub-step h, and the time at each sub-step's
        // end (summed as the sub-steps go, for line breaks).
        let h = step.dt / step.substeps as f64;
        let mut time = step.time;
        self.substeps += step.substeps as u64;
        let between = self.obstacles.is_some()
            || self.contacts.is_some()
            || m.lines.iter().any(|l| l.may_break())
            || m.held();
        if !between {
            return match self.stepper.steps(m, &loads, h, step.substeps) {
                Ok(()) => self
                    .watch
                    .check(m)
                    .map(|why| format!("diverged at t = {:.6e} s: {why}", step.time + step.dt)),
                Err((k, e)) => Some(format!(
                    "{} failed at t = {:.6e} s: {e}",
                    self.stepper.name(),
                    step.time + k as f64 * h
                )),
            };
        }
        for k in 0..step.substeps {
            if let Some(o) = &mut self.obstacles {
                o.begin_step(&m.x);
            }
            let started = Instant::now();
            if let Some(c) = &mut self.contacts {
                c.begin_step(&m.x);
            }
            let stepping = Instant::now();
            let stepped = self.stepper.step(m, &loads, h);
            let stepped_at = Instant::now();
            self.timing[0] += (stepped_at - stepping).as_secs_f64();
            self.timing[1] += (stepping - started).as_secs_f64();
            if let Err(e) = stepped {
                let t = step.time + k as f64 * h;
                return Some(format!(
                    "{} failed at t = {t:.6e} s: {e}",
                    self.stepper.name()
                ));
            }
            let t = step.time + (k + 1) as f64 * h;
            if let Some(c) = &mut self.contacts {
                if let Some(o) = &self.obstacles {
                    c.move_bodies(&o.bodies, h);
                }
                let resolved = c.resolve(&mut m.x, &mut m.v, &m.net.mass, &m.net.inv_mass, h);
                self.timing[1] += stepped_at.elapsed().as_secs_f64();
                if let Err(e) = resolved {
                    return Some(format!("the collision pass failed at t = {t:.6e} s: {e}"));
                }
                if let Some(o) = &mut self.obstacles {
                    for (b, lin, ang) in c.body_momenta() {
                        o.push(b, &lin, &ang);
                    }
                }
            }
            if let Some(o) = &mut self.obstacles {
                o.resolve(&mut m.x, &mut m.v, &m.net.inv_mass, h);
            }
            time += h;
            let breaks = m.break_lines(time);
            if let (Some(c), false) = (&mut self.contacts, breaks.is_empty()) {
                c.sync(&m.net);
            }
            self.events.extend(breaks);
            self.events.extend(m.release(time));
        }
        let why = self.watch.check(m)?;
        Some(format!(
            "diverged at t = {:.6e} s: {why}",
            step.time + step.dt
        ))
    }
}
