//! What crosses between canopy's processes (docs/PROTOCOL.md, "Fields"):
//!
//! - [`fields`]: every exchanged field's name and layout, the one place
//!   they are written;
//! - [`Motion`]: how a rigid body moves, as the scenario says and as the
//!   structure's collisions and the flow's markers must know it;
//! - with the `body` feature (on by default), a rigid body as every solver
//!   sees it: its [`shape`], [`mass`] properties, [`body`] state in the
//!   layout [`fields::STATE_LEN`] sends, and its answer to an impulse.
//!
//! rigid-proc moves the bodies; the fluid and the structure read their
//! states through this crate without linking rigid-proc.

pub mod fields;
mod motion;

#[cfg(feature = "body")]
pub mod body;
#[cfg(feature = "body")]
pub mod euler_parameters;
#[cfg(feature = "body")]
pub mod mass;
#[cfg(feature = "body")]
pub mod shape;

pub use motion::Motion;

#[cfg(feature = "body")]
pub use body::{Body, State};
#[cfg(feature = "body")]
pub use shape::Shape;
