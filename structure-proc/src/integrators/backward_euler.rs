//! Backward (implicit) Euler: v₊ = v + Δt M⁻¹ F(x₊, v₊), x₊ = x + Δt v₊, solved
//! with Newton iterations and conjugate gradients as Baraff & Witkin (SIGGRAPH
//! 1998) do for cloth; their method is the first Newton iteration of this one.
//! First order and L-stable: stiff canopies settle at steps far beyond the
//! explicit limit of dissertation eq. (3.7).

use super::newton::{Newton, Target};
use super::*;

pub struct BackwardEuler {
    newton: Newton,
    /// Last step's acceleration, the initial guess of the next.
    a: Vec<f64>,
    /// x̂ = x + Δt v.
    work: Work<1>,
}

impl BackwardEuler {
    pub fn new(newton: NewtonParams) -> BackwardEuler {
        BackwardEuler {
            newton: Newton::new(newton),
            a: Vec::new(),
            work: Work::default(),
        }
    }
}

impl Integrator for BackwardEuler {
    /// The last step's acceleration: the next Newton solve's initial guess,
    /// which its converged result depends on to round-off.
    fn save_history(&self, into: &mut Vec<f64>) {
        into.extend_from_slice(&self.a);
    }

    fn restore_history(&mut self, from: &[f64]) {
        self.a.clear();
        self.a.extend_from_slice(from);
    }

    fn step(
        &mut self,
        sys: &dyn System,
        h: f64,
        x: &mut [f64],
        v: &mut [f64],
    ) -> Result<(), StepError> {
        let n = x.len();
        self.a.resize(n, 0.0);
        let ([xhat], reaction) = self.work.begin(n);
        advanced(xhat, x, v, h);
        // x₊ = x + h v + h² a, v₊ = v + h a.
        let target = Target {
            xhat,
            vhat: v,
            b: h * h,
            g: h,
            w: 1.0,
            extra: None,
        };
        self.newton.solve(sys, h, &target, &mut self.a)?;
        x.copy_from_slice(&self.newton.x);
        v.copy_from_slice(&self.newton.v);
        let inv_mass = sys.inv_mass();
        for d in 0..n {
            if inv_mass[d / 3] == 0.0 {
                reaction[d] = h * self.newton.f[d];
            }
        }
        Ok(())
    }

    fn linear_solves(&self) -> Option<(u64, f64)> {
        Some(self.newton.solves)
    }

    fn reaction(&self) -> &[f64] {
        &self.work.reaction
    }
}
