//! Euler–Cromer (symplectic Euler), thesis eqs. (15)–(16): velocity first,
//! then position with the new velocity. First order, but it keeps the energy of
//! an undamped oscillator bounded.

use super::*;

#[derive(Default)]
pub struct EulerCromer(Work<1>);

impl Integrator for EulerCromer {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let ([f], reaction) = self.0.begin(x.len());
        sys.force(x, v, f);
        kick_drift(x, v, f, sys.inv_mass(), (h, h), reaction); // (15), then (16)
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
