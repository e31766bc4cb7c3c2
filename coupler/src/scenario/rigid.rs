//! `[rigid]`: bodies moved by rigid-proc. This issue moves them as point
//! masses; rotation (seed 000 §2.1) comes with the rigid-body solver.

use super::check::Checker;
use super::structure::default_gravity;
use serde::{Deserialize, Serialize};

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct RigidSection {
    /// Gravitational acceleration [m/s²].
    #[serde(default = "default_gravity")]
    pub gravity: [f64; 3],
    pub bodies: Vec<BodySpec>,
}

#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct BodySpec {
    pub name: String,
    /// Mass [kg].
    pub mass: f64,
    /// Initial position of the centre of mass [m].
    pub position: [f64; 3],
    /// Initial velocity [m/s].
    #[serde(default)]
    pub velocity: [f64; 3],
    /// Linear viscous drag b [N·s/m]: force −b·v. For a pendulum of length L,
    /// b = c/L² gives the damping torque −c·θ̇ of seed 003 eq. (61).
    #[serde(default)]
    pub linear_damping: f64,
}

impl RigidSection {
    pub fn check(&self, c: &mut Checker) {
        c.within("rigid", None, |c| {
            c.finite3(&["gravity"], self.gravity);
            if self.bodies.is_empty() {
                c.problem(&["bodies"], "lists no body".into());
            }
            for (i, b) in self.bodies.iter().enumerate() {
                c.within("bodies", Some(i), |c| {
                    c.plain_name(&["name"], &b.name, false);
                    if self.bodies[..i].iter().any(|o| o.name == b.name) {
                        c.problem(&["name"], format!("body name `{}` is used twice", b.name));
                    }
                    c.positive(&["mass"], b.mass, "kg");
                    c.finite3(&["position"], b.position);
                    c.finite3(&["velocity"], b.velocity);
                    c.finite_nonneg(&["linear_damping"], b.linear_damping);
                });
            }
        });
    }
}
