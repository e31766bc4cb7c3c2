//! Extended position-based dynamics (XPBD): Macklin, Müller & Chentanez,
//! "XPBD: position-based simulation of compliant constrained dynamics",
//! Motion in Games 2016 (equation numbers below are theirs).
//!
//! Every spring of the model is a distance constraint C = l − l⁰ with
//! compliance α = 1/k, so that its energy ½ α⁻¹ C² is the spring's ½ k δ²;
//! strings are one-sided (C = max(l − l⁰ − ε, 0), the tension-only law of
//! thesis eq. 3). A step predicts the positions under the external loads
//! (gravity and the fluid's pressure jump), then projects the constraints by
//! Gauss–Seidel sweeps on the multipliers λ (eq. 18), and takes the velocity
//! from the position change. The sweeps repeat until the largest correction
//! is below a tolerance, so the step solves the backward-Euler equations of
//! the same springs and a settled state is the same equilibrium structure-proc
//! reaches with a force integrator.
//!
//! Damping is XPBD's constraint damping (eq. 26): a dashpot along each
//! constraint with the coefficient β of the spring's damper, whichever law the
//! scenario names; it changes how the structure settles, not where.

use structure_proc::driver::Stepper;
use structure_proc::forces::external_force;
use structure_proc::forces::spring::point;
use structure_proc::forces::Loads;
use structure_proc::integrators::extent;
use structure_proc::{Model, StepError};

/// What XPBD cannot take from a model.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("a Delingette membrane fabric is not supported: XPBD models fabric as springs; give the fabric `stiffness` or `fibre` instead of `membrane`")]
pub struct Unsupported;

pub struct Xpbd {
    /// Sweeps stop when no node moved more than this times the structure's extent [-].
    pub tolerance: f64,
    /// Sweeps per step before the step fails.
    pub max_sweeps: u32,
    /// Positions at the start of the step.
    prev: Vec<f64>,
    /// External force at the start of the step [N], 3 per node.
    f: Vec<f64>,
    /// Multiplier λ_j of every spring, accumulated over the sweeps.
    lambda: Vec<f64>,
    /// Impulse of the last step on the held nodes [N·s], 3 per node.
    reaction: Vec<f64>,
}

impl Xpbd {
    pub fn new(m: &Model) -> Result<Xpbd, Unsupported> {
        if !m.membrane.is_empty() {
            return Err(Unsupported);
        }
        Ok(Xpbd {
            tolerance: 1e-10,
            max_sweeps: 500,
            prev: Vec::new(),
            f: Vec::new(),
            lambda: Vec::new(),
            reaction: Vec::new(),
        })
    }

    /// Impulse ∫F dt of the last step on the nodes with 1/m = 0 [N·s].
    pub fn reaction(&self) -> &[f64] {
        &self.reaction
    }

    /// Gauss–Seidel sweeps over the springs until the largest position
    /// correction is at most `tol` [m]; the last correction if they never get there.
    fn project(&mut self, m: &mut Model, h: f64, tol: f64) -> Result<(), f64> {
        // The network is read, the positions moved: two borrows of the model.
        let (net, x) = (&m.net, &mut m.x);
        let mut largest = f64::INFINITY;
        for _ in 0..self.max_sweeps {
            largest = 0.0;
            for (j, s) in net.springs.iter().enumerate() {
                if s.k == 0.0 {
                    continue; // broken line
                }
                let d = point(&*x, s.j) - point(&*x, s.i);
                let l = d.norm();
                if l == 0.0 {
                    continue;
                }
                let e = d / l;
                let c = s.stretch(l);
                let slack = s.tension_only && c == 0.0;
                let (wi, wj) = (net.inv_mass[s.i], net.inv_mass[s.j]);
                // α̃ = α/h² (eq. 4); γ = α̃ β̃/h with β̃ = h² β (eq. 26).
                let alpha = 1.0 / (s.k * h * h);
                let beta = match (net.damping, net.dampers.get(j)) {
                    (Some(_), Some(dmp)) if !slack => dmp.c,
                    _ => 0.0,
                };
                let gamma = alpha * beta * h;
                let moved = point(&*x, s.j) - point(&self.prev, s.j) - point(&*x, s.i)
                    + point(&self.prev, s.i);
                // Eq. (26), Δλ for one constraint.
                let mut dl = (-c - alpha * self.lambda[j] - gamma * e.dot(&moved))
                    / ((1.0 + gamma) * (wi + wj) + alpha);
                if s.tension_only {
                    // A string pulls (λ ≤ 0) or does nothing.
                    dl = dl.min(-self.lambda[j]);
                }
                self.lambda[j] += dl;
                for (n, w, sign) in [(s.i, wi, -1.0), (s.j, wj, 1.0)] {
                    for k in 0..3 {
                        x[3 * n + k] += sign * w * e[k] * dl;
                    }
                }
                largest = largest.max(dl.abs() * wi.max(wj));
            }
            if largest <= tol {
                return Ok(());
            }
        }
        Err(largest)
    }
}

impl Stepper for Xpbd {
    fn name(&self) -> &str {
        "xpbd"
    }

    /// None: every step starts its multipliers λ from zero (Macklin et al.
    /// 2016, Algorithm 1), and its buffers are scratch.
    fn save_history(&self, _into: &mut Vec<f64>) {}

    fn restore_history(&mut self, _from: &[f64]) {}

    fn step(&mut self, m: &mut Model, loads: &Loads, h: f64) -> Result<(), StepError> {
        let n = m.x.len();
        self.f.resize(n, 0.0);
        external_force(m, loads, &m.x, &m.v, &mut self.f);
        self.reaction.clear();
        self.reaction.resize(n, 0.0);
        // Prediction (Algorithm 1, lines 2–3): held nodes keep their velocity
        // and send the external load on them to whatever holds them.
        for d in 0..n {
            let w = m.inv_mass[d / 3];
            if w == 0.0 {
                self.reaction[d] += h * self.f[d];
            } else {
                m.v[d] += h * w * self.f[d];
            }
        }
        self.prev.clone_from(&m.x);
        for d in 0..n {
            m.x[d] += h * m.v[d];
        }
        self.lambda.clear();
        self.lambda.resize(m.springs.len(), 0.0);
        let tol = self.tolerance * extent(&m.x).max(f64::MIN_POSITIVE);
        if let Err(correction) = self.project(m, h, tol) {
            return Err(StepError::NoConvergence {
                iterations: self.max_sweeps,
                correction,
            });
        }
        // Velocity update (line 16); held nodes did not move off their path.
        for d in 0..n {
            if m.inv_mass[d / 3] != 0.0 {
                m.v[d] = (m.x[d] - self.prev[d]) / h;
            }
        }
        // Each constraint pushes with ∇C·λ/h² (eq. 12): over the step, the
        // impulse ∇C·λ/h on the held nodes.
        for (s, &lambda) in m.springs.iter().zip(&self.lambda) {
            if lambda == 0.0 {
                continue;
            }
            let d = point(&m.x, s.j) - point(&m.x, s.i);
            let e = d / d.norm();
            for (node, sign) in [(s.i, -1.0), (s.j, 1.0)] {
                if m.inv_mass[node] == 0.0 {
                    for k in 0..3 {
                        self.reaction[3 * node + k] += sign * e[k] * lambda / h;
                    }
                }
            }
        }
        m.finish_step(&self.reaction, h);
        Ok(())
    }
}
