//! canopy's participant library: what a solver process calls to take part
//! in a coupled run.
//!
//! 1. [`connect`] to the coupler that launched the process; the
//!    [`Joining`] it returns holds the setup: the scenario text, the run
//!    directory, the run's [`Timing`], the other participants.
//! 2. Build the model, then [`Joining::declare`] what it exchanges: the
//!    fields it writes and reads, its monitors, its [`Cadence`].
//! 3. Loop over [`Participant::next_command`]: `Initialize`, `Advance`,
//!    `Output`, then `Stop`; read and write fields in place in shared
//!    memory, report each command [`done`](Participant::done) with its
//!    monitors, and [`finish`](Participant::finish).
//!
//! Every participant follows the run's schedule by itself: a read waits
//! until its writer has published the value, so no one starts a step
//! before its inputs arrived, and the coupler only supervises. The
//! protocol is described for solver authors in `docs/PROTOCOL.md`.

mod acceleration;
mod channel;
mod clock;
mod declaration;
mod error;
mod fields;
pub mod futex;
mod futex_event;
mod implicit;
mod iqn_ils;
mod joining;
mod joint;
mod load;
mod matching;
mod monitors;
mod names;
mod participant;
mod presence;
pub mod restart;
mod service;
mod summary;
mod timing;
mod usage;
mod verdict;
pub mod vtu;
mod wait;
mod wire;

pub use declaration::Declaration;
pub use error::{ChannelError, ExchangeError, JoinError};
pub use joining::{connect, connect_as, Joining};
pub use monitors::Monitor;
pub use participant::{FieldView, Participant};
pub use summary::Summary;
pub use timing::{Advance, Cadence, Command, Timing};

// What the coupler uses and a solver does not: public with the `coupler`
// feature (the coupler, canopy's tests and benches), else kept inside.
#[cfg(feature = "coupler")]
pub mod atomic;
#[cfg(not(feature = "coupler"))]
#[allow(dead_code)]
mod atomic;
#[cfg(feature = "coupler")]
pub mod mpirun;
#[cfg(feature = "coupler")]
pub mod scheme;
#[cfg(not(feature = "coupler"))]
#[allow(dead_code)]
mod scheme;
#[cfg(feature = "coupler")]
pub mod supervisor;
#[cfg(feature = "coupler")]
pub use usage::cpu_seconds;

/// The number of MPI ranks this participant was started on (`ranks = N`
/// under `[participants.<name>]` starts it under `mpirun`); 1 otherwise.
/// Only rank 0 connects; the others follow it.
pub fn ranks() -> usize {
    std::env::var(names::ENV_RANKS)
        .ok()
        .and_then(|r| r.parse().ok())
        .unwrap_or(1)
}
