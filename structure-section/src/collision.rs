//! `[structure.collision]`: structure nodes against the rigid bodies' shapes
//! (dissertation §2.5, §3.4: the point-against-body tests of the collision
//! module, with the body as one impact zone).

use rigid_section::{check_restitution, RigidSection};
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Default proximity layer [m]: a fabric's order of thickness, well above
/// round-off at scene sizes of metres.
pub const DEFAULT_THICKNESS: f64 = 1e-3;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Collision {
    /// Gap [m] kept between every free node and every body surface: a node
    /// found closer (or inside, or having crossed the surface during the
    /// step) is put back this far out along the surface normal.
    #[serde(default = "default_thickness")]
    pub thickness: f64,
    /// C_R of a node–body impact (dissertation eq. 3.31) for bodies that do not
    /// give their own `restitution`; 0, the default, lets a fabric land
    /// without bouncing.
    #[serde(default)]
    pub restitution: f64,
}

fn default_thickness() -> f64 {
    DEFAULT_THICKNESS
}

impl Collision {
    pub fn check(&self, c: &mut Checker, rigid: Option<&RigidSection>) {
        c.within("collision", None, |c| {
            c.positive(&["thickness"], self.thickness, "m");
            check_restitution(c, self.restitution);
            let shaped = rigid.is_some_and(|r| r.bodies.iter().any(|b| b.shape.is_some()));
            if !shaped {
                c.problem(
                    &[],
                    "collides structure nodes with rigid bodies, but no [[rigid.bodies]] entry has a shape"
                        .into(),
                );
            }
        });
    }
}
