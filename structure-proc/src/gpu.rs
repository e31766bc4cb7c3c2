//! The structure on a GPU (the `structure-gpu` crate, dissertation
//! chapter 5): a network as the device reads it, and what the device path
//! does not take yet.

use crate::driver::{Error, Stepper};
use crate::forces::damping::Law;
use crate::forces::Loads;
use crate::integrators::StepError;
use crate::network::{Network, NodeKind};
use crate::Model;
use structure_gpu::{Gpu, GpuError, Scheme, Solver};
use structure_section::{Integrator, StructureSection};

/// What of a network the device path does not take yet.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("the GPU path does not take {0} yet")]
pub struct Unsupported(pub &'static str);

/// `net` as the device reads it, or the first part it does not take. With
/// `fluid`, the canopy triangles take the jump a fluid sends
/// ([`structure_gpu::Solver::set_pressure`]), as [`crate::forces::Loads`]
/// gives it on the CPU.
pub fn network(net: &Network, fluid: bool) -> Result<structure_gpu::Network, Unsupported> {
    if net.kind.iter().any(|k| matches!(k, NodeKind::Attached(_))) {
        return Err(Unsupported("nodes attached to rigid bodies"));
    }
    let springs = net.springs.iter().map(|s| structure_gpu::Spring {
        i: s.i,
        j: s.j,
        k: s.k,
        rest: s.rest,
        tension_only: s.tension_only,
        eps: s.eps,
    });
    let membrane = net.membrane.iter().map(|t| structure_gpu::Membrane {
        nodes: t.nodes,
        rest: t.rest,
        q: [0, 1, 2].map(|r| [0, 1, 2].map(|c| t.q[(r, c)])),
    });
    let dampers = net.dampers.iter().map(|d| structure_gpu::Damper {
        i: d.i,
        j: d.j,
        c: d.c,
        slack_below: d.slack_below,
    });
    Ok(structure_gpu::Network {
        mass: net.mass.clone(),
        inv_mass: net.inv_mass.clone(),
        gravity: net.gravity,
        springs: springs.collect(),
        membrane: membrane.collect(),
        dampers: dampers.collect(),
        damping: net.damping.map(|law| match law {
            Law::RelativeVelocity => structure_gpu::DampingLaw::RelativeVelocity,
            Law::Axial => structure_gpu::DampingLaw::Axial,
        }),
        // The CPU adds the pressure load only when a fluid sends it or the
        // porous law acts (forces/mod.rs, `add_pressure`).
        triangles: if fluid || net.porous.is_some() {
            net.triangles.clone()
        } else {
            Vec::new()
        },
        porous: net.porous.as_ref().map(|p| structure_gpu::Porous {
            free_stream: p.free_stream,
            a: p.a,
            b: p.b,
            porosity: p.porosity,
            thickness: p.thickness,
        }),
    })
}

/// The scenario's explicit scheme run on a GPU (`[structure] device =
/// "gpu"`): the state goes to the device at the start of each call and
/// comes back at its end, so a window's sub-steps with nothing between
/// them ([`Stepper::steps`]) stay on the device.
pub struct OnDevice {
    name: &'static str,
    solver: Solver,
}

impl OnDevice {
    /// The section's integrator on the first adapter wgpu finds, for `m`.
    pub fn new(section: &StructureSection, m: &Model) -> Result<OnDevice, Error> {
        let scheme = match section.integrator {
            Integrator::EulerCromer => Scheme::EulerCromer,
            Integrator::VelocityVerlet => Scheme::VelocityVerlet,
            Integrator::Rk4 => Scheme::Rk4,
            other => {
                return Err(
                    format!("the GPU does not run integrator = \"{}\"", other.name()).into(),
                )
            }
        };
        if !m.attachments.is_empty() {
            return Err(Unsupported("nodes attached to rigid bodies").into());
        }
        // The canopy's triangles take a fluid's jump whenever one comes
        // (a zero jump adds nothing).
        let net = network(&m.net, true)?;
        let gpu = Gpu::new()?;
        let solver = Solver::new(&gpu, &net, scheme)?;
        Ok(OnDevice {
            name: section.integrator.name(),
            solver,
        })
    }
}

impl Stepper for OnDevice {
    fn name(&self) -> &str {
        self.name
    }

    fn step(&mut self, m: &mut Model, loads: &Loads, dt: f64) -> Result<(), StepError> {
        self.steps(m, loads, dt, 1).map_err(|(_, e)| e)
    }

    fn steps(
        &mut self,
        m: &mut Model,
        loads: &Loads,
        dt: f64,
        n: u32,
    ) -> Result<(), (u32, StepError)> {
        let lost = |e: GpuError| (0, StepError::Device(e.to_string()));
        self.solver.upload(&m.x, &m.v);
        if !loads.pressure.is_empty() {
            self.solver.set_pressure(loads.pressure);
        }
        self.solver.advance(dt, n as u64).map_err(lost)?;
        self.solver.download(&mut m.x, &mut m.v).map_err(lost)
    }

    /// One-step schemes: nothing beyond the state.
    fn save_history(&self, _: &mut Vec<f64>) {}

    fn restore_history(&mut self, _: &[f64]) {}

    fn is_scenario_integrator(&self) -> bool {
        true
    }
}
