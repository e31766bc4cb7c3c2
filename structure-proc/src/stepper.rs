//! What advances a structure model by one structure step: the [`Stepper`]
//! the driver (`driver.rs`) asks for each sub-step, chosen by the program
//! at run time (structure-proc's integrators on the CPU or the GPU,
//! xpbd-proc's constraint solver), and the integrators of thesis §2.4 as one.

use crate::forces::Loads;
use crate::integrators::{Integrator, StepError};
use crate::Model;
use structure_section::StructureSection;

/// A method that advances the model by one structure step `m.dt`.
pub trait Stepper {
    /// The method's name, for messages.
    fn name(&self) -> &str;

    /// Advance `m` by `dt` under `loads`: positions, velocities, the
    /// attachment impulses and `m.time` (see [`Model::finish_step`]).
    fn step(&mut self, m: &mut Model, loads: &Loads, dt: f64) -> Result<(), StepError>;

    /// `n` steps of `dt` with nothing between them (no collision pass, no
    /// line that can break, no payload to release): a method that keeps
    /// its state elsewhere (the GPU) takes them in one go. On failure, the
    /// step that failed (0 for the first) and why.
    fn steps(
        &mut self,
        m: &mut Model,
        loads: &Loads,
        dt: f64,
        n: u32,
    ) -> Result<(), (u32, StepError)> {
        for k in 0..n {
            self.step(m, loads, dt).map_err(|e| (k, e))?;
        }
        Ok(())
    }

    /// Append to `into` what the method's next step reads beyond the model
    /// (an integrator's carried acceleration, an adaptive step size), so
    /// that a window can be repeated from its checkpoint bit for bit
    /// (`checkpoint.rs`). A method with no such history appends nothing.
    fn save_history(&self, into: &mut Vec<f64>);

    /// Take back what [`save_history`](Self::save_history) wrote.
    fn restore_history(&mut self, from: &[f64]);

    /// Whether the method is the scenario's `[structure] integrator`, whose
    /// stability interval the coupler's estimate assumes. Other methods
    /// (xpbd-proc's constraint solver) report no ω_max.
    fn is_scenario_integrator(&self) -> bool {
        false
    }
}

/// A stepper chosen at run time (the CPU's or the GPU's).
impl<T: Stepper + ?Sized> Stepper for Box<T> {
    fn name(&self) -> &str {
        (**self).name()
    }

    fn step(&mut self, m: &mut Model, loads: &Loads, dt: f64) -> Result<(), StepError> {
        (**self).step(m, loads, dt)
    }

    fn steps(
        &mut self,
        m: &mut Model,
        loads: &Loads,
        dt: f64,
        n: u32,
    ) -> Result<(), (u32, StepError)> {
        (**self).steps(m, loads, dt, n)
    }

    fn save_history(&self, into: &mut Vec<f64>) {
        (**self).save_history(into)
    }

    fn restore_history(&mut self, from: &[f64]) {
        (**self).restore_history(from)
    }

    fn is_scenario_integrator(&self) -> bool {
        (**self).is_scenario_integrator()
    }
}

/// One of the integrators of thesis §2.4 (or backward Euler) as a stepper.
pub struct Scheme {
    pub name: &'static str,
    pub integrator: Box<dyn Integrator>,
}

impl Scheme {
    /// The integrator the section names.
    pub fn of(section: &StructureSection) -> Scheme {
        Scheme {
            name: section.integrator.name(),
            integrator: crate::integrator(section.scheme()),
        }
    }
}

impl Stepper for Scheme {
    fn name(&self) -> &str {
        self.name
    }

    fn step(&mut self, m: &mut Model, loads: &Loads, dt: f64) -> Result<(), StepError> {
        m.step(self.integrator.as_mut(), loads, dt)
    }

    fn save_history(&self, into: &mut Vec<f64>) {
        self.integrator.save_history(into);
    }

    fn restore_history(&mut self, from: &[f64]) {
        self.integrator.restore_history(from);
    }

    fn is_scenario_integrator(&self) -> bool {
        true
    }
}
