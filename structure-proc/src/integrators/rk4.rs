//! Classical fourth-order Runge–Kutta on the state (x, v), thesis eqs. (42)–(51).

use super::*;

#[derive(Default)]
pub struct Rk4(Work<8>);

impl Integrator for Rk4 {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        // Forces f1…f4 of the stages, stage velocities v2…v4 (the k_x rates of
        // eqs. 45, 47, 49) and the stage position.
        let ([f1, f2, f3, f4, v2, v3, v4, xs], reaction) = self.0.begin(x.len());
        let inv_mass = sys.inv_mass();
        sys.force(x, v, f1); // (42)–(43)
        advanced(xs, x, v, 0.5 * h);
        kicked(v2, v, f1, inv_mass, 0.5 * h);
        sys.force(xs, v2, f2); // (44)–(45)
        advanced(xs, x, v2, 0.5 * h);
        kicked(v3, v, f2, inv_mass, 0.5 * h);
        sys.force(xs, v3, f3); // (46)–(47)
        advanced(xs, x, v3, h);
        kicked(v4, v, f3, inv_mass, h);
        sys.force(xs, v4, f4); // (48)–(49)
                               // (51) then (50)
        for (vk, w) in [(&*v, 1.0), (&*v2, 2.0), (&*v3, 2.0), (&*v4, 1.0)] {
            drift(x, vk, w * h / 6.0);
        }
        for (f, w) in [(&*f1, 1.0), (&*f2, 2.0), (&*f3, 2.0), (&*f4, 1.0)] {
            kick(v, f, inv_mass, w * h / 6.0, reaction);
        }
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
