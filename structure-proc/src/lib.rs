//! structure-proc: the spring-mass canopy, cloth and strings (dissertation §2.3,
//! thesis §2.1–§2.4, §3.2).
//!
//! The physics lives here and never touches IPC; `driver.rs` connects a
//! model and its stepper to the participant library, and `main.rs` only picks the stepper. Data are flat arrays (`x`, `v`: xyz interleaved per node), and the
//! step functions take their inputs explicitly. Force terms are in `forces/`,
//! time integrators in `integrators/`, and the two meet only through the
//! [`System`] trait.

pub mod annulus;
pub mod answer;
pub mod build;
pub mod checkpoint;
pub mod collision;
pub mod cross;
pub mod damped;
pub mod designer;
pub mod divergence;
pub mod dome;
pub mod driver;
pub mod forces;
#[cfg(feature = "gpu")]
pub mod gpu;
pub mod integrators;
pub mod lines;
pub mod model;
pub mod network;
pub mod opening;
pub mod output;
pub mod pack;
pub mod parachute;
pub mod rectangle;
pub mod reefing;
pub mod release;
pub mod rings;
pub mod sheets;
pub mod stability;
pub mod stepper;
pub mod system;
pub mod units;
pub mod window_start;

pub use build::build_model;
pub use integrators::{integrator, Integrator, StepError};
pub use model::{Model, NodeKind, Spring};
pub use system::System;
