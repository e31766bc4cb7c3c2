//! How a rigid body moves: the scenario's `motion` key, which the rigid
//! solver obeys and the structure's collisions and the flow's markers must
//! know (a static or prescribed body is infinitely heavy in a contact).

use serde::{Deserialize, Serialize};

#[derive(
    Debug, Clone, Copy, Default, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema,
)]
#[serde(rename_all = "kebab-case")]
pub enum Motion {
    /// Moved by its loads: Newton's law and Euler's equations (dissertation eq. 2.12).
    #[default]
    Dynamic,
    /// Held in place; infinitely heavy in contacts.
    Static,
    /// Moves with its given `velocity` and `angular_velocity` whatever acts on
    /// it; infinitely heavy in contacts.
    Prescribed,
}
