//! Euler–Richardson, thesis eqs. (17)–(22): a half step to the midpoint, then
//! the full step with the midpoint rates. Second order, two forces per step.

use super::*;

#[derive(Default)]
pub struct EulerRichardson(Work<3>);

impl Integrator for EulerRichardson {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let ([f, xm, vm], reaction) = self.0.begin(x.len());
        let inv_mass = sys.inv_mass();
        sys.force(x, v, f); // (17)
        kicked(vm, v, f, inv_mass, 0.5 * h); // (18)
        advanced(xm, x, v, 0.5 * h); // (19)
        sys.force(xm, vm, f); // (20)
        kick(v, f, inv_mass, h, reaction); // (21)
        drift(x, vm, h); // (22)
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
