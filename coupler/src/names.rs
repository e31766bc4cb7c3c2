//! iceoryx2 service names. Every name carries the run id, so two runs on one
//! machine never see each other's services.

use crate::protocol::{Field, Role};

/// Prefix shared by every canopy service; `canopy/<run id>/…`.
pub const PREFIX: &str = "canopy";

/// Environment variable through which the launcher hands a participant its run id.
pub const ENV_RUN_ID: &str = "CANOPY_RUN_ID";
/// Environment variable naming the role a launched participant plays.
pub const ENV_ROLE: &str = "CANOPY_ROLE";
/// Environment variable giving the number of MPI ranks a participant was
/// started on under `mpirun` (absent: one, no MPI).
pub const ENV_RANKS: &str = "CANOPY_RANKS";

/// Commands from the coupler to one participant (bincode bytes).
pub fn command(run: &str, role: Role) -> String {
    format!("{PREFIX}/{run}/{}/command", role.name())
}

/// Status replies from one participant to the coupler (bincode bytes).
pub fn status(run: &str, role: Role) -> String {
    format!("{PREFIX}/{run}/{}/status", role.name())
}

/// Event that wakes a participant when a command is waiting for it.
pub fn participant_wake(run: &str, role: Role) -> String {
    format!("{PREFIX}/{run}/{}/wake", role.name())
}

/// Event that wakes the coupler when a status reply is waiting.
pub fn coupler_wake(run: &str) -> String {
    format!("{PREFIX}/{run}/coupler/wake")
}

/// A bulk `[f64]` field, published by its producer and read in place by its consumer.
pub fn field(run: &str, field: Field) -> String {
    format!("{PREFIX}/{run}/field/{}", field.name())
}

/// A fresh run id: process id and clock, short enough for service names.
pub fn new_run_id() -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    format!("{:x}{:x}", std::process::id(), nanos & 0xffff_ffff_ffff)
}
