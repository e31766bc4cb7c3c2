//! xpbd-proc: a second structure solver for canopy. It reads the same
//! `[structure]` section and builds the same spring-mass model as
//! structure-proc (the generators are shared), speaks the same protocol
//! through the same driver, but advances the model with a different method:
//! extended position-based dynamics, every spring a compliant distance
//! constraint ([`xpbd`]).

pub mod xpbd;

pub use xpbd::{Unsupported, Xpbd};
