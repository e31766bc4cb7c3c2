//! fluid-proc's incompressible model, on one rank or several (part of the
//! binary; `ranks.rs` says how they work together): one flow step per
//! window (sub-steps when the coupler asks for them), the flow field
//! written as `fluid.pvd`. Each rank steps its slab of the box
//! (`part.rs`); rank 0 gathers the cells for the output.
//!
//! The bodies and the canopy in the flow are read and answered by rank 0:
//! it places them and shares their markers with the other ranks each
//! window (`Incompressible::share_bodies`; every rank forces its own
//! faces). The bodies' loads are the forcing rank 0 records; the canopy's
//! pressure jump and the bodies' pressure force it reads from the pressure
//! it gathers.

use crate::checkpoint::Checkpoint;
use crate::comm::Comm;
use crate::driver::{declaration, Error};
use crate::faces::Faces;
use crate::flow_bodies::FlowBodies;
use crate::flow_canopy::FlowCanopy;
use crate::incompressible::{Incompressible, StepReport};
use crate::probe;
use crate::rank_checkpoint::{self, Place};
use crate::ranks::{Order, Stopped};
use crate::setup::flow_on;
use exchange::fields::*;
use fluid_section::flow::Probe;
use fluid_section::frame::FrameSpec;
use fluid_section::{FluidSection, Scene};
use participant::vtu::{Image, Series};
use participant::{Command, Joining, Monitor, Participant};
use std::sync::Arc;

/// One rank's flow, its faces at the start of the window, the window's
/// checkpoint (implicit coupling), and where run checkpoints go.
struct Flow {
    flow: Incompressible,
    before: Faces,
    checkpoint: Checkpoint,
    comm: Arc<dyn Comm>,
    /// Where run checkpoints go (rank 0 tells the others).
    place: Place,
    /// Whether probes read the cells at the start and at window ends.
    probing: bool,
}

impl Flow {
    fn new(flow: Incompressible, comm: Arc<dyn Comm>, section: &FluidSection) -> Flow {
        Flow {
            before: flow.u.clone(),
            flow,
            checkpoint: Checkpoint::default(),
            comm,
            place: Place::default(),
            probing: section.probes.as_ref().is_some_and(|p| !p.is_empty()),
        }
    }

    /// The box's cell pressures [Pa] and velocities [m/s] on rank 0, when
    /// probes read them (every rank calls it together).
    fn probed(&self) -> Probed {
        if !self.probing {
            return None;
        }
        let pressure = self.flow.part.gather(&self.flow.pressure());
        let velocity = self.flow.part.gather(&self.flow.cell_velocity());
        pressure.zip(velocity)
    }
}

/// What probes read: the box's cell pressures and velocities, on rank 0.
type Probed = Option<(Vec<f64>, Vec<f64>)>;

/// What obeying an order gave; only rank 0's is used.
enum Done {
    Monitors(Vec<Monitor>, Probed),
    /// The box's cell velocities and pressures, on rank 0.
    Output(Option<(Vec<f64>, Vec<f64>)>),
    /// Monitors, steps taken, and on rank 0 the box's pressure [Pa] where
    /// the canopy or the bodies' monitors read it.
    Advanced(Vec<Monitor>, u64, Option<Vec<f64>>, Probed),
    Checkpoint,
    Stop,
}

/// Obeys `order` on this rank (every rank calls it with the same order);
/// a failed step fails on every rank together, with this message.
fn obey(f: &mut Flow, order: Order) -> Result<Done, String> {
    let flow = &mut f.flow;
    Ok(match order {
        Order::Monitors => {
            Done::Monitors(monitors(flow, StepReport::default(), f64::NAN), f.probed())
        }
        Order::Output { .. } => {
            let velocity = flow.part.gather(&flow.cell_velocity());
            let pressure = flow.part.gather(&flow.pressure());
            Done::Output(velocity.zip(pressure))
        }
        Order::Advance {
            dt,
            substeps,
            window_end,
        } => {
            f.before.clone_from(&flow.u);
            flow.share_bodies();
            flow.share_frame();
            let n = substeps.max(1);
            let mut report = StepReport::default();
            for k in 0..n {
                report = flow
                    .step_in_window(dt / n as f64, k == 0)
                    .map_err(|e| format!("flow step at t = {} s: {e}", flow.time))?;
            }
            let m = if window_end {
                // How far from steady: max|∂u/∂t| over the window [m/s²].
                let change = flow.max_change(&f.before) / dt;
                monitors(flow, report, change)
            } else {
                Vec::new()
            };
            let shaped = flow.bodies.iter().any(|b| !b.markers.is_empty());
            let pressure = if flow.canopy.is_some() || (window_end && shaped) {
                flow.part.gather(&flow.pressure())
            } else {
                None
            };
            let probed = if window_end { f.probed() } else { None };
            Done::Advanced(m, n as u64, pressure, probed)
        }
        Order::Checkpoint { restore: false } => {
            // A window may be taken again: its later tries take the
            // first one's prediction (`prediction.rs`).
            flow.keep_predictions();
            flow.save(&mut f.checkpoint);
            Done::Checkpoint
        }
        Order::Checkpoint { restore: true } => {
            flow.restore(&f.checkpoint);
            Done::Checkpoint
        }
        Order::RunCheckpoint { window, resume } => {
            let (comm, place) = (f.comm.as_ref(), &f.place);
            match resume {
                false => {
                    flow.save(&mut f.checkpoint);
                    rank_checkpoint::write_part(comm, place, window, &f.checkpoint)?;
                }
                true => rank_checkpoint::read_part(comm, place, window, |c: Checkpoint| {
                    if !flow.fits(&c) {
                        return Err("another part of the flow than this rank's".into());
                    }
                    flow.restore(&c);
                    Ok(())
                })?,
            }
            Done::Checkpoint
        }
        Order::Stop => Done::Stop,
    })
}

/// The flow's own monitors, in the order [`monitors`] reports them.
const FLOW_MONITORS: [&str; 9] = [
    "kinetic_energy",
    "momentum_x",
    "momentum_y",
    "momentum_z",
    "max_divergence",
    "steady_residual",
    "courant",
    "pressure_iterations",
    "viscous_iterations",
];

/// Sums and maxima over every rank: every rank calls it together.
fn monitors(flow: &mut Incompressible, r: StepReport, steady_residual: f64) -> Vec<Monitor> {
    let momentum = flow.momentum();
    let values = [
        flow.kinetic_energy(),
        momentum[0],
        momentum[1],
        momentum[2],
        flow.max_divergence(),
        steady_residual,
        r.courant,
        r.pressure_iterations as f64,
        r.viscous_iterations as f64,
    ];
    FLOW_MONITORS
        .iter()
        .zip(values)
        .map(|(name, v)| Monitor::new(*name, v))
        .collect()
}

/// This rank's flow at the start: with `[fluid.frame]`, in the box that
/// follows the parachute (`frame.rs`).
fn flow_of(scenario: &Scene, comm: Arc<dyn Comm>) -> Option<Incompressible> {
    let mut flow = flow_on(&scenario.fluid, comm)?;
    if let Some(v) = scenario.frame_start() {
        flow.start_following(v);
    }
    Some(flow)
}

/// The monitors of a box that follows the parachute: where it is and how
/// fast it falls over the ground.
const FRAME_MONITORS: [&str; 2] = ["frame_altitude", "frame_descent_speed"];

/// Rank 0 (or the only rank): declares what the flow exchanges, runs the
/// schedule and finishes.
pub fn lead(
    joining: Joining,
    scenario: &Scene,
    section: &FluidSection,
    comm: Arc<dyn Comm>,
) -> Result<(), Stopped> {
    let c = comm.as_ref();
    let flow = flow_of(scenario, comm.clone())
        .ok_or_else(|| Stopped::before_order(c, "[fluid] has no box"))?;
    let mut f = Flow::new(flow, comm.clone(), section);
    let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
    let bodies =
        FlowBodies::new(scenario, &mut f.flow, origin).map_err(|e| Stopped::before_order(c, e))?;
    let mut names: Vec<String> = FLOW_MONITORS.iter().map(|n| n.to_string()).collect();
    names.extend(bodies.monitors(&f.flow, None).into_iter().map(|m| m.name));
    // The canopy's jump is monitored when a structure takes part, which
    // writes the canopy.
    let jump_monitor = scenario.scenario.participants.lists("structure");
    if jump_monitor {
        names.push("mean_pressure_jump".into());
    }
    names.extend(probe::names(section.probes.as_deref().unwrap_or(&[])));
    if section.frame.is_some() {
        names.extend(FRAME_MONITORS.map(String::from));
    }
    let mut p = joining
        .declare(declaration(f.flow.bodies.len(), true, names).restarts())
        .map_err(|e| Stopped::before_order(c, e))?;
    f.place = Place::of(&p);
    let steps = p.reporting(|p| run(p, &mut f, section, bodies, jump_monitor, comm))?;
    p.finish(steps)?;
    Ok(())
}

/// The schedule's commands, turned into orders every rank obeys.
fn run(
    p: &mut Participant,
    f: &mut Flow,
    section: &FluidSection,
    bodies: FlowBodies,
    jump_monitor: bool,
    comm: Arc<dyn Comm>,
) -> Result<u64, Stopped> {
    let c = comm.as_ref();
    let mut io = Interface::new(p, f, section, bodies, jump_monitor);
    let origin = io.origin;
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    loop {
        let command = p.next_command().map_err(|e| Stopped::before_order(c, e))?;
        if command == Command::SaveCheckpoint {
            io.canopy.new_window();
            io.following.iter_mut().for_each(Following::new_window);
        }
        if let Command::Advance(a) = command {
            let flow = &mut f.flow;
            if let Err(e) = io.place(p, flow, a.dt) {
                let msg = format!("at t = {} s: {e}", flow.time);
                return Err(Stopped::before_order(c, fail(p, msg)));
            }
        }
        let order = Order::of(&command);
        let done = obey(f, order.share(c)).map_err(|msg| Stopped {
            error: fail(p, msg),
            together: true,
        })?;
        let flow = &mut f.flow;
        match (command, done) {
            (_, Done::Stop) => break,
            (Command::WriteCheckpoint { window }, Done::Checkpoint) => {
                rank_checkpoint::write_lead(p, window, &series, steps)?;
                p.done(Vec::new())?
            }
            (Command::Resume { window }, Done::Checkpoint) => {
                steps = rank_checkpoint::read_lead(p, window, &mut series)?;
                p.done(Vec::new())?
            }
            (_, Done::Checkpoint) => p.done(Vec::new())?,
            (_, Done::Monitors(mut m, probed)) => {
                if p.publishes_at_start() {
                    io.answer_at_start(p)?;
                }
                m.extend(io.monitors(flow, None));
                m.extend(io.probe_monitors(flow, probed));
                p.done(m)?
            }
            (Command::Output { index, time }, Done::Output(Some((velocity, pressure)))) => {
                let g = flow.grid();
                let image = Image {
                    origin: flow.box_origin(origin),
                    spacing: g.h,
                    cells: g.n,
                    cell_data: vec![("velocity", 3, &velocity), ("pressure", 1, &pressure)],
                };
                series.write_image(index, time, &image)?;
                p.done(Vec::new())?
            }
            (Command::Advance(a), Done::Advanced(mut m, n, pressure, probed)) => {
                steps += n;
                io.answer(p, flow, pressure.as_deref())?;
                if a.window_end {
                    let read = pressure.as_deref().map(|p| (&io.loads[..], p));
                    m.extend(io.monitors(flow, read));
                    m.extend(io.probe_monitors(flow, probed));
                }
                p.done(m)?;
            }
            _ => unreachable!("each order comes from its command"),
        }
    }
    Ok(steps)
}

/// What rank 0 reads from and answers to the other participants: the
/// bodies and the canopy in the flow, and the bodies' loads.
struct Interface {
    bodies: FlowBodies,
    canopy: FlowCanopy,
    loads: Vec<f64>,
    /// Whether a structure writes the canopy.
    with_canopy: bool,
    /// Whether the canopy's mean jump is a monitor.
    jump_monitor: bool,
    /// `[[fluid.probes]]`, and the box's low corner in the world at the
    /// start [m].
    probes: Vec<Probe>,
    origin: [f64; 3],
    /// What the box follows, when it moves (`[fluid.frame]`).
    following: Option<Following>,
}

/// What a box that follows the parachute follows, and its velocity at the
/// end of the present window: under implicit coupling the first try's, so
/// that every try of a window moves the box alike.
struct Following {
    spec: FrameSpec,
    target: [f64; 3],
    /// Whether the present window's target is chosen (implicit coupling).
    chosen: bool,
    implicit: bool,
}

impl Following {
    fn new(spec: FrameSpec) -> Following {
        Following {
            spec,
            target: [0.0; 3],
            chosen: false,
            implicit: false,
        }
    }

    fn new_window(&mut self) {
        self.implicit = true;
        self.chosen = false;
    }

    /// The frame's monitors, from the box's `offset` [m] and `velocity`
    /// [m/s] over the ground.
    fn monitors(&self, flow: &Incompressible) -> [Monitor; 2] {
        let (offset, velocity) = (flow.frame_offset(), flow.frame_velocity());
        let values = [self.spec.altitude() + offset[2], -velocity[2]];
        [0, 1].map(|i| Monitor::new(FRAME_MONITORS[i], values[i]))
    }
}

impl Interface {
    /// What rank 0 answers for `f`, the scenario's `section`, its
    /// `bodies`, and whether the canopy's mean jump is a monitor.
    fn new(
        p: &Participant,
        f: &Flow,
        section: &FluidSection,
        bodies: FlowBodies,
        jump_monitor: bool,
    ) -> Interface {
        let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
        Interface {
            loads: vec![0.0; LOAD_LEN * f.flow.bodies.len()],
            bodies,
            canopy: FlowCanopy::new(section, origin),
            with_canopy: p.is_connected(CANOPY_POSITIONS),
            jump_monitor,
            probes: section.probes.clone().unwrap_or_default(),
            origin,
            following: section.frame.clone().map(Following::new),
        }
    }

    /// The probes' monitors from the cells they read (none without probes).
    fn probe_monitors(&self, flow: &Incompressible, probed: Probed) -> Vec<Monitor> {
        if self.probes.is_empty() {
            return Vec::new();
        }
        let fields = probed.as_ref().map(|(p, v)| (&p[..], &v[..]));
        probe::monitors(&self.probes, flow.grid(), self.origin, fields)
    }

    /// Puts the bodies and the canopy where rigid-proc and the structure
    /// left them at the window's start, and aims a box that follows the
    /// parachute at what it follows over the window's `dt` [s].
    fn place(
        &mut self,
        p: &mut Participant,
        flow: &mut Incompressible,
        dt: f64,
    ) -> Result<(), Error> {
        if p.is_connected(BODY_STATES) {
            self.bodies.read(&p.read_field(BODY_STATES)?, flow)?;
        }
        let mut canopy_velocity = None;
        if self.with_canopy {
            let canopy = &mut self.canopy;
            if canopy.needs_triangles() {
                canopy.set_triangles(&p.read_field(CANOPY_TRIANGLES)?);
            }
            let x = p.read_field(CANOPY_POSITIONS)?;
            let v = p.read_field(CANOPY_VELOCITIES)?;
            canopy.place(&x, &v, flow)?;
            canopy_velocity = Some(FlowCanopy::mean_velocity(&v));
        }
        if let Some(f) = &mut self.following {
            if !f.chosen {
                let followed = match f.spec.follows_canopy() {
                    true => canopy_velocity,
                    false => self.bodies.velocity_of(&f.spec.follow),
                };
                f.target = followed.ok_or_else(|| {
                    format!(
                        "the frame follows `{}`, which is not in the flow",
                        f.spec.follow
                    )
                })?;
                f.chosen = f.implicit;
            }
            flow.aim_frame(f.target, dt);
        }
        Ok(())
    }

    /// The bodies' loads and the canopy's jumps, read from the box's
    /// `pressure` [Pa] (gathered on rank 0), to their readers.
    fn answer(
        &mut self,
        p: &mut Participant,
        flow: &mut Incompressible,
        pressure: Option<&[f64]>,
    ) -> Result<(), Error> {
        if p.is_connected(BODY_LOADS) {
            // rigid-proc reads a load every window, bodies or none.
            let loads = &mut self.loads;
            self.bodies.take_loads(flow, loads);
            p.write_field(BODY_LOADS, loads.len(), |out| out.copy_from_slice(loads))?;
        }
        if p.is_connected(CANOPY_PRESSURE) {
            let pressure = pressure.ok_or("the canopy is not in the flow")?;
            let jumps = self.canopy.jumps(flow.grid(), pressure);
            p.write_field(CANOPY_PRESSURE, jumps.len(), |out| {
                out.copy_from_slice(jumps)
            })?;
        }
        Ok(())
    }

    /// Answers before the first window, which the parallel scheme's
    /// readers take their first try from: no load on the bodies and no
    /// jump across the canopy, as the air has not yet pushed (preCICE's
    /// zero initial data).
    fn answer_at_start(&mut self, p: &mut Participant) -> Result<(), Error> {
        if p.is_connected(BODY_LOADS) {
            p.write_field(BODY_LOADS, self.loads.len(), |out| out.fill(0.0))?;
        }
        if p.is_connected(CANOPY_PRESSURE) {
            if self.canopy.needs_triangles() {
                self.canopy.set_triangles(&p.read_field(CANOPY_TRIANGLES)?);
            }
            let n = self.canopy.triangle_count();
            p.write_field(CANOPY_PRESSURE, n, |out| out.fill(0.0))?;
        }
        Ok(())
    }

    /// The bodies' monitors (from their `read` loads and pressure, if any)
    /// and the canopy's mean jump.
    fn monitors(&self, flow: &Incompressible, read: Option<(&[f64], &[f64])>) -> Vec<Monitor> {
        let mut m = self.bodies.monitors(flow, read);
        if self.jump_monitor {
            m.push(Monitor::new("mean_pressure_jump", self.canopy.mean_jump()));
        }
        if let Some(f) = &self.following {
            m.extend(f.monitors(flow));
        }
        m
    }
}

/// Tells the coupler the run failed with `msg` and gives it back as the
/// error to stop on (the coupler's own error if even telling it failed).
pub fn fail(p: &mut Participant, msg: String) -> Error {
    match p.fail(msg.clone()) {
        Ok(()) => msg.into(),
        Err(e) => e.into(),
    }
}

/// A rank other than 0: obeys rank 0's orders until it stops, or until a
/// step fails (rank 0 meets the same failure and reports it).
#[cfg_attr(not(feature = "mpi"), allow(dead_code))]
pub fn follow(scenario: &Scene, comm: Arc<dyn Comm>) -> Result<(), Error> {
    let flow = flow_of(scenario, comm.clone()).ok_or("[fluid] has no box")?;
    let mut f = Flow::new(flow, comm.clone(), &scenario.fluid);
    loop {
        let order = Order::Stop.share(comm.as_ref());
        match obey(&mut f, order) {
            Ok(Done::Stop) | Err(_) => return Ok(()),
            Ok(_) => {}
        }
    }
}
