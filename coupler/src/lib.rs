//! canopy's coupling library.
//!
//! Every solver process links this crate (with `default-features = false`) for
//! the [`participant`] API: connect, read a field, write a field, wait for the
//! next command, report, finish. The `coupler` executable adds the launcher,
//! the coupling schedule and the run directory behind the `launcher` feature,
//! so a solver never pulls in tokio, CLI parsing or progress bars.
//!
//! The protocol is described for solver authors in `docs/PROTOCOL.md`.

pub mod channel;
pub mod mpirun;
pub mod names;
pub mod participant;
pub mod protocol;
pub mod scenario;
pub mod usage;
pub mod vtu;

#[cfg(feature = "launcher")]
pub mod launcher;

pub use participant::{ExchangeError, FieldView, Participant};
pub use protocol::{Advance, Command, Field, Monitor, Role, Stats, Status};
pub use scenario::Scenario;
