//! Explicit (forward) Euler, thesis §2.4.1, eq. (12): x and v both advance with
//! the rates at the start of the step. First order; gains energy on oscillators.

use super::*;

#[derive(Default)]
pub struct ExplicitEuler(Work<1>);

impl Integrator for ExplicitEuler {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let ([f], reaction) = self.0.begin(x.len());
        sys.force(x, v, f);
        drift(x, v, h);
        kick(v, f, sys.inv_mass(), h, reaction);
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
