//! Velocity Verlet, thesis eqs. (37)–(40): half kick, drift, half kick.
//! Second order and symplectic for forces that depend on position only.
//!
//! Eq. (39) needs v_{n+1} inside a velocity-dependent (damping) force before it
//! is known. We use the Euler prediction v_n + Δt·a_n there: it costs nothing and
//! keeps second order with damping (the half-step velocity would drop it to first).

use super::*;

#[derive(Default)]
pub struct VelocityVerlet(Work<3>);

impl Integrator for VelocityVerlet {
    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let ([f0, f1, vp], reaction) = self.0.begin(x.len());
        let inv_mass = sys.inv_mass();
        // The end of the last step's force was at these positions: the
        // system may reuse its position-only terms (forces/kept.rs).
        sys.force_keeping(x, v, f0);
        kicked(vp, v, f0, inv_mass, h); // predictor for (39)
        kick_drift(x, v, f0, inv_mass, (0.5 * h, h), reaction); // (37), then (38)
        sys.force_keeping(x, vp, f1); // (39)
        kick(v, f1, inv_mass, 0.5 * h, reaction); // (40)
        Ok(())
    }

    fn reaction(&self) -> &[f64] {
        &self.0.reaction
    }
}
