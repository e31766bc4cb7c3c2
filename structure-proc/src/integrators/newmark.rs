//! Newmark's method, thesis eqs. (25)–(26), and its HHT-α extension (§2.4.7):
//!   x₊ = x + Δt v + (½ − β) Δt² a + β Δt² a₊,
//!   v₊ = v + (1 − γ) Δt a + γ Δt a₊,
//!   M a₊ = (1 + α) F(x₊, v₊) − α F(x, v)      (α = 0: Newmark).
//! The implicit a₊ is found by Newton iterations with conjugate gradients
//! (`newton.rs`) instead of the linear increments of eqs. (28)–(36), so that the
//! nonlinear springs are solved, not linearised. β = 1/4, γ = 1/2 (average
//! acceleration) is unconditionally stable; HHT with α ∈ [−1/3, 0],
//! β = (1 − α)²/4, γ = ½ − α damps the highest frequencies and stays second order.

use super::newton::{Newton, Target};
use super::*;

pub struct Newmark {
    beta: f64,
    gamma: f64,
    alpha: f64,
    newton: Newton,
    /// a_n, carried from step to step as the scheme requires (empty before the first step).
    a: Vec<f64>,
    /// F_n, x̂, v̂ and HHT's −α·F_n.
    work: Work<4>,
}

impl Newmark {
    pub fn new(beta: f64, gamma: f64, alpha: f64, newton: NewtonParams) -> Newmark {
        Newmark {
            beta,
            gamma,
            alpha,
            newton: Newton::new(newton),
            a: Vec::new(),
            work: Work::default(),
        }
    }
}

impl Integrator for Newmark {
    /// a_n, carried into the next step's predictor (empty before the first).
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
        let ([f, xhat, vhat, extra], reaction) = self.work.begin(n);
        let inv_mass = sys.inv_mass();
        sys.force(x, v, f);
        if self.a.len() != n {
            self.a = (0..n).map(|d| f[d] * inv_mass[d / 3]).collect();
        }
        let (beta, gamma, alpha) = (self.beta, self.gamma, self.alpha);
        for d in 0..n {
            xhat[d] = x[d] + h * v[d] + (0.5 - beta) * h * h * self.a[d];
            vhat[d] = v[d] + (1.0 - gamma) * h * self.a[d];
            extra[d] = -alpha * f[d];
        }
        let target = Target {
            xhat,
            vhat,
            b: beta * h * h,
            g: gamma * h,
            w: 1.0 + alpha,
            extra: (alpha != 0.0).then_some(&extra[..]),
        };
        // Newton starts from x_{n+1} = x_n. Extrapolating (from a_n, or x + h·v)
        // is closer on the slow modes but lands ω·h (or ω²h²/2) amplitudes away
        // on a stiff mode with ω·h ≫ 1, where springs can invert and Newton
        // converges to a spurious root; from x_n every mode starts within the
        // distance it actually moves in a step.
        if beta > 0.0 {
            for d in 0..n {
                self.a[d] = (x[d] - xhat[d]) / (beta * h * h);
            }
        }
        self.newton.solve(sys, h, &target, &mut self.a)?;
        x.copy_from_slice(&self.newton.x);
        v.copy_from_slice(&self.newton.v);
        // Held nodes: the same weights applied to the force they feel.
        for d in 0..n {
            if inv_mass[d / 3] == 0.0 {
                let f_end = (1.0 + alpha) * self.newton.f[d] - alpha * f[d];
                reaction[d] = h * ((1.0 - gamma) * f[d] + gamma * f_end);
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
