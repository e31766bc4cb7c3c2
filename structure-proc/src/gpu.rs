//! The structure on a GPU (the `structure-gpu` crate, dissertation
//! chapter 5): a network as the device reads it, and the scenario's scheme
//! stepping it there.

use crate::driver::{Error, Stepper};
use crate::forces::damping::Law;
use crate::forces::Loads;
use crate::integrators::StepError;
use crate::network::Network;
use crate::Model;
use structure_gpu::{Gpu, GpuError, Scheme, Solver};
use structure_section::{Integrator, StructureSection};

/// `net` as the device reads it. With `fluid`, the canopy triangles take
/// the jump a fluid sends ([`structure_gpu::Solver::set_pressure`]), as
/// [`crate::forces::Loads`] gives it on the CPU.
pub fn network(net: &Network, fluid: bool) -> structure_gpu::Network {
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
    structure_gpu::Network {
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
        porous: net.porous,
    }
}

/// The scenario's explicit scheme run on a GPU (`[structure] device =
/// "gpu"`): the state goes to the device at the start of each call and
/// comes back at its end, so a window's sub-steps with nothing between
/// them ([`Stepper::steps`]) stay on the device. Attached nodes move with
/// their body there and come back at their exact place (x0 + v0·τ); the
/// impulse they took goes to their attachment, as [`Model::finish_step`]
/// does on the CPU. A line break or a payload's release changes the
/// network (a spring's stiffness, a node's mass): the device's copy is
/// made anew when either differs from what it was made of, a window
/// restored from its checkpoint included.
pub struct OnDevice {
    name: &'static str,
    gpu: Gpu,
    scheme: Scheme,
    solver: Solver,
    /// What the device's network was made of: the payload held, the lines broken.
    made_of: (bool, usize),
    /// The reaction read back, 3 per node.
    reaction: Vec<f64>,
}

/// The payload held, the lines broken: what changes the network in a run.
fn changes(m: &Model) -> (bool, usize) {
    (m.held(), m.lines.iter().filter(|l| l.broken).count())
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
        let gpu = Gpu::new()?;
        let solver = made(&gpu, m, scheme)?;
        Ok(OnDevice {
            name: section.integrator.name(),
            gpu,
            scheme,
            solver,
            made_of: changes(m),
            reaction: vec![0.0; m.x.len()],
        })
    }
}

/// `m`'s network on the device. The canopy's triangles take a fluid's
/// jump whenever one comes (a zero jump adds nothing).
fn made(gpu: &Gpu, m: &Model, scheme: Scheme) -> Result<Solver, GpuError> {
    Solver::new(gpu, &network(&m.net, true), scheme)
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
        // A failure is reported at the window's first step: the device does
        // not say which of its steps failed.
        let lost = |e: GpuError| (0, StepError::Device(e.to_string()));
        if changes(m) != self.made_of {
            self.solver = made(&self.gpu, m, self.scheme).map_err(lost)?;
            self.made_of = changes(m);
        }
        self.solver.upload(&m.x, &m.v);
        if !loads.pressure.is_empty() {
            if loads.pressure.len() != m.triangles.len() {
                let why = format!(
                    "{} pressure values for {} triangles",
                    loads.pressure.len(),
                    m.triangles.len()
                );
                return Err((0, StepError::Device(why)));
            }
            self.solver.set_pressure(loads.pressure);
        }
        self.solver.advance(dt, n as u64).map_err(lost)?;
        self.solver.download(&mut m.x, &mut m.v).map_err(lost)?;
        if !m.attachments.is_empty() {
            self.solver.reaction(&mut self.reaction).map_err(lost)?;
            // τ summed step by step as the CPU sums it; the last step's
            // dt and the impulse come with finish_step.
            for a in &mut m.attachments {
                for _ in 1..n {
                    a.tau += dt;
                }
            }
            m.finish_step(&self.reaction, dt);
        }
        Ok(())
    }

    /// One-step schemes: nothing beyond the state.
    fn save_history(&self, _: &mut Vec<f64>) {}

    fn restore_history(&mut self, _: &[f64]) {}

    fn is_scenario_integrator(&self) -> bool {
        true
    }
}
