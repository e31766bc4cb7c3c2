//! Improved explicit Euler (Heun), thesis eqs. (23)–(24): an Euler predictor,
//! then the trapezoidal rule with the rates at both ends. Second order.

use super::*;

#[derive(Default)]
pub struct ImprovedEuler(Work<4>);

impl Integrator for ImprovedEuler {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let ([f0, f1, xp, vp], reaction) = self.0.begin(x.len());
        let inv_mass = sys.inv_mass();
        sys.force(x, v, f0);
        advanced(xp, x, v, h); // (23) for x …
        kicked(vp, v, f0, inv_mass, h); // … and for v
        sys.force(xp, vp, f1);
        // (24): x += h/2 (v + v_p), v += h/2 (a0 + a_p)
        drift(x, v, 0.5 * h);
        drift(x, vp, 0.5 * h);
        kick(v, f0, inv_mass, 0.5 * h, reaction);
        kick(v, f1, inv_mass, 0.5 * h, reaction);
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
