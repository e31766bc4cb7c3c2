//! fluid-proc: the flow models that load the canopy. For now the porous
//! free-stream model of seed 003 §2.1; the physics never touches IPC.

pub mod porous;

pub use porous::Porous;
