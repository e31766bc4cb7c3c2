//! The incompressible model in the run loop (`run.rs`): one flow step per
//! window (sub-steps when the coupler asks for them), the flow field
//! written as `fluid.pvd`. Each rank steps its slab of the box
//! (`part.rs`); rank 0 gathers the cells for the output.
//!
//! The bodies and the canopy in the flow are read and answered by rank 0
//! ([`Interface`]): it places them and shares their markers with the other
//! ranks each window (`Incompressible::share_bodies`; every rank forces
//! its own faces). The bodies' loads are the forcing rank 0 records; the
//! canopy's pressure jump and the bodies' pressure force it reads from
//! the pressure it gathers.

use crate::comm::Comm;
use crate::driver::{declaration, Error};
use crate::incompressible::checkpoint::Checkpoint;
use crate::incompressible::device_fetch::WindowMonitors;
use crate::incompressible::faces::Faces;
use crate::incompressible::flow_bodies::FlowBodies;
use crate::incompressible::flow_canopy::FlowCanopy;
use crate::incompressible::probe;
use crate::incompressible::setup::flow_on;
use crate::incompressible::{Incompressible, StepReport};
use crate::model::{Cells, Lead, Model, Window};
use exchange::fields::*;
use fluid_gpu::Gpu;
use fluid_section::flow::Probe;
use fluid_section::frame::FrameSpec;
use fluid_section::{Device, FluidSection, Scene};
use participant::{Advance, Declaration, Monitor, Participant};
use std::sync::Arc;

/// One rank's flow, and its faces at the start of the window.
pub struct Flow {
    flow: Incompressible,
    before: Faces,
    /// Whether probes read the cells at the start and at window ends.
    probing: bool,
    /// The box's low corner in the world at the start [m].
    origin: [f64; 3],
}

impl Flow {
    /// The box's cell pressures [Pa] and velocities [m/s] on rank 0, when
    /// probes read them (every rank calls it together).
    fn probed(&mut self) -> Probed {
        if !self.probing {
            return None;
        }
        if let Err(e) = self.flow.fetch_velocities() {
            eprintln!("fluid-proc: {e}");
        }
        let pressure = self.flow.part.gather(&self.flow.pressure());
        let velocity = self.flow.part.gather(&self.flow.cell_velocity());
        pressure.zip(velocity)
    }
}

/// What probes read: the box's cell pressures and velocities, on rank 0.
type Probed = Option<(Vec<f64>, Vec<f64>)>;

/// What an advance hands rank 0: the flow's monitors at a window's end,
/// the box's pressure [Pa] where the canopy or the bodies' monitors read
/// it, and what the probes read.
pub struct Advanced {
    monitors: Vec<Monitor>,
    pressure: Option<Vec<f64>>,
    probed: Probed,
}

impl Model for Flow {
    type Advanced = Advanced;
    type Started = (Vec<Monitor>, Probed);
    type Saved = Checkpoint;
    const FIELD: bool = true;

    /// This rank's flow at the start: with `[fluid.frame]`, in the box
    /// that follows the parachute (`frame.rs`).
    fn on(scene: &Scene, comm: Arc<dyn Comm>) -> Result<Flow, String> {
        let section = &scene.fluid;
        let mut flow = flow_on(section, comm).ok_or("[fluid] has no box")?;
        if section.device == Device::Gpu {
            let gpu = Gpu::new().map_err(|e| format!("device = \"gpu\": {e}"))?;
            flow.to_device(&gpu)
                .map_err(|e| format!("device = \"gpu\": {e}"))?;
        }
        if let Some(v) = scene.frame_start() {
            flow.start_following(v);
        }
        Ok(Flow {
            before: flow.u.clone(),
            flow,
            probing: section.probes.as_ref().is_some_and(|p| !p.is_empty()),
            origin: section.flow_box.map_or([0.0; 3], |b| b.lower),
        })
    }

    fn start(&mut self) -> Self::Started {
        let before = self.flow.u.clone();
        let m = match self.flow.window_monitors(&before) {
            Ok(m) => monitors(m, StepReport::default(), f64::NAN),
            Err(_) => Vec::new(),
        };
        (m, self.probed())
    }

    fn advance(&mut self, w: Window) -> Result<(Advanced, u64), String> {
        let flow = &mut self.flow;
        flow.remember_window_start(&mut self.before)
            .map_err(|e| format!("flow at t = {} s: {e}", flow.time))?;
        flow.share_bodies();
        flow.share_frame();
        let n = w.substeps.max(1);
        let mut report = StepReport::default();
        for k in 0..n {
            report = flow
                .step_in_window(w.dt / n as f64, k == 0)
                .map_err(|e| format!("flow step at t = {} s: {e}", flow.time))?;
        }
        // The window's end pressure to the host, where it ran on a device
        // (the velocities stay there unless the host reads them).
        flow.fetch_window_end()
            .map_err(|e| format!("flow at t = {} s: {e}", flow.time))?;
        let monitors = if w.window_end {
            let m = flow
                .window_monitors(&self.before)
                .map_err(|e| format!("flow at t = {} s: {e}", flow.time))?;
            monitors(m, report, w.dt)
        } else {
            Vec::new()
        };
        let shaped = flow.bodies.iter().any(|b| !b.markers.is_empty());
        let pressure = if flow.canopy.is_some() || (w.window_end && shaped) {
            flow.part.gather(&flow.pressure())
        } else {
            None
        };
        let probed = if w.window_end { self.probed() } else { None };
        let advanced = Advanced {
            monitors,
            pressure,
            probed,
        };
        Ok((advanced, n as u64))
    }

    fn new_window(&mut self) {
        // A window may be taken again: its later tries take the first
        // one's prediction (`prediction.rs`); on a device, its start is
        // copied there (`device.rs`).
        self.flow.keep_predictions();
        if let Err(e) = self.flow.snapshot_window() {
            // The save then reads the state back instead.
            eprintln!("fluid-proc: {e}");
        }
    }

    fn save(&self, into: &mut Checkpoint) {
        self.flow.save(into);
    }

    fn restore(&mut self, from: &Checkpoint) -> Result<(), String> {
        if !self.flow.fits(from) {
            return Err("another part of the flow than this rank's".into());
        }
        if from.on_device() && !self.flow.holds_snapshot() {
            return Err("the device no longer holds the window's start it saved".into());
        }
        self.flow.restore(from);
        Ok(())
    }

    fn cells(&mut self) -> Option<Cells> {
        if let Err(e) = self.flow.fetch_velocities() {
            eprintln!("fluid-proc: the flow's output: {e}");
            return None;
        }
        let flow = &self.flow;
        let velocity = flow.part.gather(&flow.cell_velocity());
        let pressure = flow.part.gather(&flow.pressure());
        let (velocity, pressure) = velocity.zip(pressure)?;
        let g = flow.grid();
        let origin = flow.box_origin(self.origin);
        let faces = g.is_graded().then(|| {
            [0, 1, 2].map(|d| {
                (0..=g.n[d])
                    .map(|i| origin[d] + g.axes[d].face(i))
                    .collect()
            })
        });
        Some(Cells {
            origin,
            spacing: g.h,
            cells: g.n,
            faces,
            fields: vec![("velocity", 3, velocity), ("pressure", 1, pressure)],
        })
    }
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

/// The flow's monitors of `m` and the step's report `r`; the steady
/// residual max|∂u/∂t| over a window of `dt` [m/s²] (NaN at the start).
fn monitors(m: WindowMonitors, r: StepReport, dt: f64) -> Vec<Monitor> {
    let values = [
        m.kinetic_energy,
        m.momentum[0],
        m.momentum[1],
        m.momentum[2],
        m.max_divergence,
        m.max_change / dt,
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

/// The monitors of a box that follows the parachute: where it is and how
/// fast it falls over the ground.
const FRAME_MONITORS: [&str; 2] = ["frame_altitude", "frame_descent_speed"];

/// What rank 0 reads from and answers to the other participants: the
/// bodies and the canopy in the flow, and the bodies' loads.
pub struct Interface {
    bodies: FlowBodies,
    canopy: FlowCanopy,
    loads: Vec<f64>,
    /// Whether the canopy's mean jump is a monitor: when a structure
    /// takes part, which writes the canopy.
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

impl Lead for Interface {
    type Model = Flow;

    fn new(scene: &Scene, f: &mut Flow) -> Result<Interface, String> {
        let section: &FluidSection = &scene.fluid;
        let origin = f.origin;
        // The bodies go into the flow first: a load is kept for each.
        let bodies = FlowBodies::new(scene, &mut f.flow, origin)?;
        Ok(Interface {
            loads: vec![0.0; LOAD_LEN * f.flow.bodies.len()],
            bodies,
            canopy: FlowCanopy::new(section, origin),
            jump_monitor: scene.scenario.participants.lists("structure"),
            probes: section.probes.clone().unwrap_or_default(),
            origin,
            following: section.frame.clone().map(Following::new),
        })
    }

    fn declaration(&self, f: &Flow) -> Declaration {
        let mut names: Vec<String> = FLOW_MONITORS.iter().map(|n| n.to_string()).collect();
        names.extend(
            self.bodies
                .monitors(&f.flow, None)
                .into_iter()
                .map(|m| m.name),
        );
        if self.jump_monitor {
            names.push("mean_pressure_jump".into());
        }
        names.extend(probe::names(&self.probes));
        if self.following.is_some() {
            names.extend(FRAME_MONITORS.map(String::from));
        }
        declaration(f.flow.bodies.len(), true, names)
    }

    fn new_window(&mut self) {
        self.canopy.new_window();
        self.following.iter_mut().for_each(Following::new_window);
    }

    fn start(
        &mut self,
        p: &mut Participant,
        f: &mut Flow,
        (mut m, probed): (Vec<Monitor>, Probed),
    ) -> Result<Vec<Monitor>, Error> {
        if p.publishes_at_start() {
            self.answer_at_start(p)?;
        }
        m.extend(self.monitors(&f.flow, None));
        m.extend(self.probe_monitors(&f.flow, probed));
        Ok(m)
    }

    fn place(&mut self, p: &mut Participant, f: &mut Flow, a: &Advance) -> Result<(), Error> {
        let flow = &mut f.flow;
        self.place_in(p, flow, a.dt)
            .map_err(|e| format!("at t = {} s: {e}", flow.time).into())
    }

    fn answer(
        &mut self,
        p: &mut Participant,
        f: &mut Flow,
        advanced: Advanced,
        a: &Advance,
    ) -> Result<Vec<Monitor>, Error> {
        let Advanced {
            mut monitors,
            pressure,
            probed,
        } = advanced;
        let flow = &mut f.flow;
        self.answer_with(p, flow, pressure.as_deref())?;
        if a.window_end {
            let read = pressure.as_deref().map(|p| (&self.loads[..], p));
            monitors.extend(self.monitors(flow, read));
            monitors.extend(self.probe_monitors(flow, probed));
        }
        Ok(monitors)
    }
}

impl Interface {
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
    fn place_in(
        &mut self,
        p: &mut Participant,
        flow: &mut Incompressible,
        dt: f64,
    ) -> Result<(), Error> {
        if p.is_connected(BODY_STATES) {
            self.bodies.read(&p.read_field(BODY_STATES)?, flow)?;
        }
        let mut canopy_velocity = None;
        if p.is_connected(CANOPY_POSITIONS) {
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
    fn answer_with(
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
