//! structure-proc: the spring-mass canopy and strings (seed 003 §2.1, §3.2).
//!
//! The physics lives here and never touches IPC; `main.rs` connects it to the
//! coupler. Data are flat arrays (`x`, `v`: xyz interleaved per node), and the
//! step functions take their inputs explicitly.

pub mod annulus;
pub mod build;
pub mod forces;
pub mod integrator;
pub mod model;
pub mod output;

pub use build::build_model;
pub use integrator::Integrator;
pub use model::{Model, NodeKind, Spring};
