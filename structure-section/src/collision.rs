//! `[structure.collision]`: the structure's collision pass (dissertation
//! §2.5, §3.4): the fabric and strings against themselves and each other
//! (proximity, continuous detection, impact zones), and free nodes against
//! the rigid bodies' shapes, each body one impact zone.

use rigid_section::{check_restitution, RigidSection};
use scenario::Checker;
use serde::{Deserialize, Serialize};

/// Default proximity layer [m]: a fabric's order of thickness, well above
/// round-off at scene sizes of metres.
pub const DEFAULT_THICKNESS: f64 = 1e-3;

#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
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
    /// Whether the fabric and strings collide with themselves and each
    /// other (self-contact, fabric–string, string–string).
    #[serde(default = "yes")]
    pub self_contact: bool,
    /// Coulomb's μ between structure features in contact (dissertation
    /// §2.5: "apply impulse and friction"); 0, the default, is frictionless.
    #[serde(default)]
    pub friction: f64,
    /// k of the repulsion impulse, eq. 3.30 [N/m]; by default the mean
    /// stiffness of the structure's springs and membrane edges.
    #[serde(default)]
    pub repulsion_stiffness: Option<f64>,
    /// Whether moving shaped bodies' surfaces (faceted, 24 segments round)
    /// join the contact pass as static bodies' do: their edges and faces
    /// against the structure's, pushing along the body's true normal, each
    /// body taking the reaction. False leaves moving bodies to the node
    /// test alone.
    #[serde(default = "yes")]
    pub moving_body_surfaces: bool,
    /// How the fabric and strings meet themselves: `"pairwise"`, the
    /// default, Bridson et al.'s (2002) pass as the dissertation §2.5
    /// gives it, every candidate pair bounded at every step and every pair
    /// within the layer measured and pushed; `"layered"`, for fabric
    /// pressed in layers (a packed canopy), the candidate pairs kept in
    /// groups of neighbouring patches that a group's bound skips whole,
    /// one point–triangle repulsion per contact, and edge–edge approaches
    /// of fabric stopped by the continuous test alone. Both end every step
    /// with the same continuous test and impact zones, so neither lets a
    /// fold cross another.
    #[serde(default)]
    pub model: ContactModel,
}

/// How the contacts of `[structure.collision]` are found and pushed.
#[derive(
    Debug, Clone, Copy, PartialEq, Eq, Default, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "lowercase")]
pub enum ContactModel {
    /// Every candidate pair bounded at every step, every pair within the
    /// layer pushed, pair by pair.
    #[default]
    Pairwise,
    /// The candidates in patch groups skipped whole while their bound
    /// allows, one point–triangle repulsion per contact.
    Layered,
}

impl Default for Collision {
    fn default() -> Collision {
        Collision {
            thickness: DEFAULT_THICKNESS,
            restitution: 0.0,
            self_contact: true,
            friction: 0.0,
            repulsion_stiffness: None,
            moving_body_surfaces: true,
            model: ContactModel::Pairwise,
        }
    }
}

fn yes() -> bool {
    true
}

fn default_thickness() -> f64 {
    DEFAULT_THICKNESS
}

impl Collision {
    pub fn check(&self, c: &mut Checker, rigid: Option<&RigidSection>) {
        c.within("collision", None, |c| {
            c.positive(&["thickness"], self.thickness, "m");
            check_restitution(c, self.restitution);
            c.finite_nonneg(&["friction"], self.friction);
            if let Some(k) = self.repulsion_stiffness {
                c.finite_nonneg(&["repulsion_stiffness"], k);
            }
            let shaped = rigid.is_some_and(|r| r.bodies.iter().any(|b| b.shape.is_some()));
            if !shaped && !self.self_contact {
                c.problem(
                    &["self_contact"],
                    "is false and no [[rigid.bodies]] entry has a shape: nothing would collide"
                        .into(),
                );
            }
        });
    }
}
