//! The step on a GPU (`[fluid] device = "gpu"`): the fluid-gpu crate runs
//! the same projection method on the device, the state kept there from
//! step to step. The host's `u` and `q` are brought back when the run
//! loop asks at a window's end ([`Incompressible::fetch`]), for the
//! monitors, the output and the exchanged fields, and after each
//! [`Incompressible::step`] called alone; a restore, or anything else that
//! sets the state on the host, sends it up again before the next step.
//!
//! The device covers a uniform box on one rank, every kind of side, the box
//! following the parachute, and the bodies and the canopy in it (their
//! markers sent when they move, what the forcing gave the fluid brought
//! back with u and q). Under implicit coupling a window's start is copied
//! on the device, and its checkpoint leaves the step history there
//! ([`Incompressible::snapshot_window`]). What it does not cover,
//! fluid-section's check refuses with `device = "gpu"`, and [`device_box`]
//! says why here.

use crate::incompressible::checkpoint::History;
use crate::incompressible::immersed::ImmersedBody;
use crate::incompressible::setup::flow_from;
use crate::incompressible::side::Side;
use crate::incompressible::{FlowError, Incompressible, StepReport};
use fluid_gpu::{Flow, FlowBox, Gpu, Law, Marker, Moving};
use fluid_section::flow::MAX_COURANT;
use fluid_section::FluidSection;

/// The flow on the device, and whether it holds the current state.
pub(crate) struct OnDevice {
    pub(crate) flow: Flow,
    /// The markers the device forces the air at, as last sent.
    markers: Vec<Marker>,
    /// The device holds the current state (else the host does).
    pub(crate) current: bool,
    /// The host's `u`, and its `q`, are older than the device's: a
    /// window's end brings q back for the exchanged fields, u only where
    /// something on the host reads it (`device_fetch.rs`).
    pub(crate) u_stale: bool,
    pub(crate) q_stale: bool,
    /// A window's start was just copied on the device
    /// ([`Incompressible::snapshot_window`]); the next save takes it.
    snapshot_taken: std::cell::Cell<bool>,
}

/// The box the device steps for this flow, or why it cannot.
pub fn device_box(flow: &Incompressible) -> Result<FlowBox, String> {
    let g = &flow.setup.grid;
    if flow.part.split() {
        return Err("the device runs the flow on one rank (leave out [run] ranks)".into());
    }
    if g.is_graded() {
        return Err("the device runs a uniform box ([fluid.box] cells, no core)".into());
    }
    let side = |s: Side| match s {
        Side::Velocity(v) => Ok(fluid_gpu::Side::Velocity(v)),
        Side::Outflow => Ok(fluid_gpu::Side::Outflow),
        Side::Periodic => Ok(fluid_gpu::Side::Periodic),
        Side::Parabolic(v) => Ok(fluid_gpu::Side::Parabolic(v)),
        Side::Rank => Err("the device runs the flow on one rank".to_string()),
    };
    let mut sides = [[fluid_gpu::Side::Periodic; 2]; 3];
    for (to, from) in sides
        .iter_mut()
        .flatten()
        .zip(flow.setup.sides.iter().flatten())
    {
        *to = side(*from)?;
    }
    Ok(FlowBox {
        n: g.n,
        h: [0, 1, 2].map(|d| g.axes[d].width(0)),
        sides,
        nu: flow.setup.nu,
        density: flow.setup.density,
    })
}

/// Whether the first adapter takes the section's flow: the `--check`
/// answer of `device = "gpu"` (the kernels built, nothing run). The
/// adapter's name and precision where it does.
pub fn probe(section: &FluidSection) -> Result<String, String> {
    let mut flow = flow_from(section).ok_or("[fluid] has no box")?;
    let gpu = Gpu::new().map_err(|e| e.to_string())?;
    flow.to_device(&gpu)?;
    Ok(format!("{} in {:?}", gpu.name(), gpu.precision()))
}

impl Incompressible {
    /// From now on, step on `gpu`.
    pub fn to_device(&mut self, gpu: &Gpu) -> Result<(), String> {
        self.to_device_binding_at_most(gpu, u64::MAX)
    }

    /// [`Incompressible::to_device`], the arrays split as if the adapter
    /// bound at most `bytes` a binding (`Flow::binding_at_most`).
    pub fn to_device_binding_at_most(&mut self, gpu: &Gpu, bytes: u64) -> Result<(), String> {
        let spec = device_box(self)?;
        let flow = Flow::binding_at_most(gpu, &spec, bytes).map_err(|e| e.to_string())?;
        self.device = Some(OnDevice {
            flow,
            markers: Vec::new(),
            current: false,
            u_stale: false,
            q_stale: false,
            snapshot_taken: std::cell::Cell::new(false),
        });
        Ok(())
    }

    /// Whether the steps run on a device.
    pub fn on_device(&self) -> bool {
        self.device.is_some()
    }

    /// The state on the host was set: send it up before the next step.
    pub(crate) fn host_changed(&mut self) {
        if let Some(d) = &mut self.device {
            (d.current, d.u_stale, d.q_stale) = (false, false, false);
        }
    }

    /// A window that implicit coupling may take again begins: where the
    /// device holds the state, it copies it there, and the window's save
    /// ([`Incompressible::save`]) then leaves the step history on the
    /// device, a restore taking it back there.
    pub fn snapshot_window(&mut self) -> Result<(), FlowError> {
        self.send_state()?;
        let Some(d) = self.device.as_mut() else {
            return Ok(());
        };
        d.flow.snapshot().map_err(gpu)?;
        d.snapshot_taken.set(true);
        Ok(())
    }

    /// Sends the host's state up where the device does not hold it.
    pub(crate) fn send_state(&mut self) -> Result<(), FlowError> {
        if self.device.as_ref().is_none_or(|d| d.current) {
            return Ok(());
        }
        let mut history = History::default();
        self.save_history(&mut history);
        let h = fluid_gpu::History {
            phi: history.phi,
            last_dt: history.last_dt,
            advection: history.advection,
            delta: history.delta,
        };
        let d = self.device.as_mut().expect("a device");
        d.flow.upload(&self.u.u, &self.q, Some(&h)).map_err(gpu)?;
        d.current = true;
        Ok(())
    }

    /// Whether this save takes the device's copy of the window's start
    /// (once: a later save, a run checkpoint's, reads the history back).
    pub(crate) fn take_snapshot(&self) -> bool {
        self.device
            .as_ref()
            .is_some_and(|d| d.snapshot_taken.replace(false))
    }

    /// Whether the device holds the state and its copy of a window's start.
    pub fn holds_snapshot(&self) -> bool {
        self.device
            .as_ref()
            .is_some_and(|d| d.current && d.flow.has_snapshot())
    }

    /// Back to the device's copy of the window's start; false where it has
    /// none (the caller then sends the checkpoint's state up).
    pub(crate) fn restore_snapshot(&mut self) -> bool {
        let Some(d) = self.device.as_mut().filter(|d| d.current) else {
            return false;
        };
        match d.flow.restore_snapshot() {
            Ok(true) => {
                // The host's q is the checkpoint's; its u may be older
                // than the window's start, so it is read anew when needed.
                d.q_stale = false;
                d.u_stale = true;
                true
            }
            _ => false,
        }
    }

    /// The step history, from the device where it holds the state.
    pub(crate) fn device_history(&self, into: &mut History) -> bool {
        let Some(d) = self.device.as_ref().filter(|d| d.current) else {
            return false;
        };
        // A device lost while saving: the checkpoint keeps the host's
        // older history, and the next step stops the run with the
        // device's error.
        let Ok(h) = d.flow.history() else {
            return false;
        };
        into.phi = h.phi;
        into.last_dt = h.last_dt;
        into.advection = h.advection;
        into.delta = h.delta;
        true
    }

    /// [`Incompressible::step_in_window`] on the device.
    pub(crate) fn step_on_device(&mut self, dt: f64, first: bool) -> Result<StepReport, FlowError> {
        self.send_state()?;
        let markers = self.device_markers();
        let d = self.device.as_mut().expect("a device");
        if markers != d.markers {
            d.flow.set_markers(&markers).map_err(gpu)?;
            d.markers = markers;
        }
        let courant = d.flow.courant(dt);
        if !courant.is_finite() {
            return Err(FlowError::NonFinite);
        }
        if courant > MAX_COURANT {
            return Err(FlowError::Courant(courant));
        }
        let clock = std::time::Instant::now();
        // A box that follows the parachute moves over the step: the sides
        // as seen from it at the step's start and end (`frame.rs`).
        let sides = given(&self.sides);
        let dv = self.move_frame(dt);
        let moving = Moving {
            sides,
            sides_end: given(&self.sides),
            frame: self.frame_velocity(),
            dv,
        };
        // Under implicit coupling a window's later tries take its first
        // prediction, kept on the device (fluid-gpu's window.rs).
        let first = first && self.prediction.is_some();
        let d = self.device.as_mut().expect("a device");
        let report = d
            .flow
            .step_in_window(dt, &moving, first)
            .map_err(|e| match e {
                fluid_gpu::FlowError::NonFinite => FlowError::NonFinite,
                e => FlowError::Device(e.to_string()),
            })?;
        (d.u_stale, d.q_stale) = (true, true);
        for body in self.forced() {
            body.forced_for(dt);
        }
        self.last_dt = Some(dt);
        self.time += dt;
        Ok(StepReport {
            courant,
            pressure_iterations: report.pressure_iterations,
            pressure_seconds: clock.elapsed().as_secs_f64(),
            viscous_iterations: report.viscous_iterations,
            kept_prediction: report.kept_prediction,
        })
    }
}

impl Incompressible {
    /// The bodies with markers, then the canopy: the ones the forcing
    /// holds the air at, in `immersed::force`'s order.
    pub(crate) fn forced(&mut self) -> impl Iterator<Item = &mut ImmersedBody> {
        self.bodies
            .iter_mut()
            .chain(self.canopy.as_mut())
            .filter(|b| !b.markers.is_empty())
    }

    /// The forced bodies' markers as the device takes them.
    fn device_markers(&mut self) -> Vec<Marker> {
        let mut out = Vec::new();
        for b in self.forced() {
            let law = match (b.porous, b.is_sheet()) {
                (Some(ab), _) => Law::Porous(ab),
                (None, true) => Law::Sheet,
                (None, false) => Law::Body,
            };
            for (m, &target) in b.markers.iter().zip(&b.targets) {
                out.push(Marker {
                    x: m.x,
                    normal: m.normal,
                    area: m.area,
                    target,
                    law,
                });
            }
        }
        out
    }
}

/// The given velocities of `sides` as the device takes them.
fn given(sides: &crate::incompressible::side::Sides) -> [[[f64; 3]; 2]; 3] {
    sides.map(|pair| {
        pair.map(|s| match s {
            Side::Velocity(v) | Side::Parabolic(v) => v,
            _ => [0.0; 3],
        })
    })
}

pub(crate) fn gpu(e: fluid_gpu::GpuError) -> FlowError {
    FlowError::Device(e.to_string())
}
