//! Point-mass bodies advanced by impulses (seed 000 §3.1.1 uses impulses for
//! the string and collision loads; here they act at the centre of mass).

use coupler::scenario::RigidSection;

#[derive(Debug, Clone, PartialEq)]
pub struct Body {
    pub name: String,
    pub mass: f64,
    pub x: [f64; 3],
    pub v: [f64; 3],
    /// Linear viscous drag b [N·s/m].
    pub damping: f64,
}

#[derive(Debug, Clone)]
pub struct Bodies {
    pub bodies: Vec<Body>,
    pub gravity: [f64; 3],
    /// For each attachment point (in `StructureSection::attachment_bodies` order), the body it belongs to.
    pub attachment_body: Vec<usize>,
}

impl Bodies {
    /// Bodies of `[rigid]`; `attached` names the body of each attachment point.
    pub fn new(s: &RigidSection, attached: &[&str]) -> Bodies {
        let bodies: Vec<Body> = s
            .bodies
            .iter()
            .map(|b| Body {
                name: b.name.clone(),
                mass: b.mass,
                x: b.position,
                v: b.velocity,
                damping: b.linear_damping,
            })
            .collect();
        let attachment_body = attached
            .iter()
            .map(|name| bodies.iter().position(|b| b.name == *name).unwrap_or(0))
            .collect();
        Bodies {
            bodies,
            gravity: s.gravity,
            attachment_body,
        }
    }

    /// Advance by `dt` with the impulses `impulse` (3 per attachment point) the
    /// structure exerted over this step, plus gravity and drag:
    /// v⁺ = v + (J + (m g − b v) dt)/m, then x⁺ = x + v⁺ dt (symplectic Euler).
    pub fn step(&mut self, dt: f64, impulse: &[f64]) {
        let mut j = vec![[0.0; 3]; self.bodies.len()];
        for (a, imp) in impulse.chunks_exact(3).enumerate() {
            if let Some(&b) = self.attachment_body.get(a) {
                for c in 0..3 {
                    j[b][c] += imp[c];
                }
            }
        }
        for (b, jb) in self.bodies.iter_mut().zip(&j) {
            for c in 0..3 {
                let force = b.mass * self.gravity[c] - b.damping * b.v[c];
                b.v[c] += (jb[c] + force * dt) / b.mass;
                b.x[c] += b.v[c] * dt;
            }
        }
    }

    /// Position then velocity of every attachment point, 6 per point.
    pub fn attachment_state(&self, out: &mut [f64]) {
        for (o, &b) in out.chunks_exact_mut(6).zip(&self.attachment_body) {
            let body = &self.bodies[b];
            o[..3].copy_from_slice(&body.x);
            o[3..].copy_from_slice(&body.v);
        }
    }

    pub fn kinetic_energy(&self) -> f64 {
        self.bodies
            .iter()
            .map(|b| 0.5 * b.mass * b.v.iter().map(|v| v * v).sum::<f64>())
            .sum()
    }

    /// Gravitational potential energy −m g·x [J].
    pub fn potential_energy(&self) -> f64 {
        self.bodies
            .iter()
            .map(|b| -b.mass * (0..3).map(|c| self.gravity[c] * b.x[c]).sum::<f64>())
            .sum()
    }

    pub fn first_non_finite(&self) -> Option<&str> {
        self.bodies
            .iter()
            .find(|b| b.x.iter().chain(&b.v).any(|v| !v.is_finite()))
            .map(|b| b.name.as_str())
    }
}
