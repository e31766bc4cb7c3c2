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
        let h = 0.5 * m.dt;
        total_force(m, loads, &m.x, &m.v, &mut self.f0);
        kick(&mut m.v, &self.f0, &self.inv_mass, h); // (37)
        drift(&mut m.x, &m.v, m.dt); // (38)
        advance_attachments(m, m.dt);
        total_force(m, loads, &m.x, &m.v, &mut self.f1); // (39)
        kick(&mut m.v, &self.f1, &self.inv_mass, h); // (40)
                                                     // Trapezoidal impulse, consistent with the two half kicks.
        for a in &mut m.attachments {
            for c in 0..3 {
                a.impulse[c] += h * (self.f0[3 * a.node + c] + self.f1[3 * a.node + c]);
            }
        }
    }

    /// Seed 003 eqs. (15)–(16): velocity first, then position with the new velocity.
    fn euler_cromer(&mut self, m: &mut Model, loads: &Loads) {
        total_force(m, loads, &m.x, &m.v, &mut self.f0);
        kick(&mut m.v, &self.f0, &self.inv_mass, m.dt);
        drift(&mut m.x, &m.v, m.dt);
        for a in &mut m.attachments {
            for c in 0..3 {
                a.impulse[c] += m.dt * self.f0[3 * a.node + c];
            }
        }
        advance_attachments(m, m.dt);
    }
}

/// v ← v + h·f/m (nodes with 1/m = 0 keep their velocity).
fn kick(v: &mut [f64], f: &[f64], inv_mass: &[f64], h: f64) {
    for (i, vi) in v.iter_mut().enumerate() {
        *vi += h * f[i] * inv_mass[i / 3];
    }
}

/// x ← x + h·v (attached nodes are placed afterwards; fixed nodes have v = 0).
fn drift(x: &mut [f64], v: &[f64], h: f64) {
    for (xi, vi) in x.iter_mut().zip(v) {
        *xi += h * vi;
    }
}

fn advance_attachments(m: &mut Model, dt: f64) {
    for a in &mut m.attachments {
        a.tau += dt;
    }
    m.place_attached();
}
