//! Time integrators of seed 003 §2.4, each implemented once and used by every scene.
//! Only free nodes are integrated; fixed nodes stay put and attached nodes follow
//! their rigid body. The force on an attached node is what the structure exerts on
//! the body, so integrating it over the step gives the impulse sent to rigid-proc.

use crate::forces::{total_force, Loads};
use crate::model::{Model, NodeKind};
pub use coupler::scenario::structure::Integrator as Scheme;

/// An integrator with its work arrays.
pub struct Integrator {
    scheme: Scheme,
    f0: Vec<f64>,
    f1: Vec<f64>,
    /// 1/m for free nodes, 0 for fixed and attached ones (they are not integrated).
    inv_mass: Vec<f64>,
}

impl Integrator {
    pub fn new(scheme: Scheme, m: &Model) -> Integrator {
        let inv_mass = (0..m.nodes())
            .map(|n| {
                if m.kind[n] == NodeKind::Free && m.mass[n] > 0.0 {
                    1.0 / m.mass[n]
                } else {
                    0.0
                }
            })
            .collect();
        let len = 3 * m.nodes();
        Integrator {
            scheme,
            f0: vec![0.0; len],
            f1: vec![0.0; len],
            inv_mass,
        }
    }

    /// Advance `m` by one step of `m.dt`.
    pub fn step(&mut self, m: &mut Model, loads: &Loads) {
        match self.scheme {
            Scheme::VelocityVerlet => self.velocity_verlet(m, loads),
            Scheme::EulerCromer => self.euler_cromer(m, loads),
        }
    }

    /// Seed 003 eqs. (37)–(40). Eq. (39) needs v_{n+1} inside the damping force;
    /// the half-step velocity v_{n+½} stands in for it, which keeps the scheme explicit.
    fn velocity_verlet(&mut self, m: &mut Model, loads: &Loads) {
        let dt = m.dt;
        total_force(m, loads, &m.x, &m.v, &mut self.f0);
        for n in 0..m.nodes() {
            let inv_m = self.inv_mass[n];
            for c in 0..3 {
                let i = 3 * n + c;
                m.v[i] += 0.5 * dt * self.f0[i] * inv_m; // (37)
                m.x[i] += dt * m.v[i]; // (38)
            }
        }
        advance_attachments(m, dt);
        total_force(m, loads, &m.x, &m.v, &mut self.f1); // (39)
        for n in 0..m.nodes() {
            let inv_m = self.inv_mass[n];
            for c in 0..3 {
                let i = 3 * n + c;
                m.v[i] += 0.5 * dt * self.f1[i] * inv_m; // (40)
            }
        }
        // Trapezoidal impulse, consistent with the two half kicks.
        for a in &mut m.attachments {
            for c in 0..3 {
                a.impulse[c] += 0.5 * dt * (self.f0[3 * a.node + c] + self.f1[3 * a.node + c]);
            }
        }
    }

    /// Seed 003 eqs. (15)–(16): velocity first, then position with the new velocity.
    fn euler_cromer(&mut self, m: &mut Model, loads: &Loads) {
        let dt = m.dt;
        total_force(m, loads, &m.x, &m.v, &mut self.f0);
        for n in 0..m.nodes() {
            let inv_m = self.inv_mass[n];
            for c in 0..3 {
                let i = 3 * n + c;
                m.v[i] += dt * self.f0[i] * inv_m;
                m.x[i] += dt * m.v[i];
            }
        }
        for a in &mut m.attachments {
            for c in 0..3 {
                a.impulse[c] += dt * self.f0[3 * a.node + c];
            }
        }
        advance_attachments(m, dt);
    }
}

fn advance_attachments(m: &mut Model, dt: f64) {
    for a in &mut m.attachments {
        a.tau += dt;
    }
    m.place_attached();
}
