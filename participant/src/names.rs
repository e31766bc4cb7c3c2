//! iceoryx2 service names and the environment a launched participant reads.
//! Every service name carries the run id, so two runs on one machine never
//! see each other's services.

/// Prefix shared by every canopy service; `canopy/<run id>/…`.
pub const PREFIX: &str = "canopy";

/// Environment variable through which the launcher hands a participant its run id.
pub const ENV_RUN_ID: &str = "CANOPY_RUN_ID";
/// Environment variable naming the participant a launched program plays:
/// its key under `[participants]`, which is also the name of its section.
pub const ENV_PARTICIPANT: &str = "CANOPY_PARTICIPANT";
/// Environment variable giving the number of MPI ranks a participant was
/// started on under `mpirun` (absent: one, no MPI).
pub const ENV_RANKS: &str = "CANOPY_RANKS";

/// Control messages from the coupler to one participant (bincode bytes).
pub fn command(run: &str, participant: &str) -> String {
    format!("{PREFIX}/{run}/p/{participant}/command")
}

/// Status messages from one participant to the coupler (bincode bytes).
pub fn status(run: &str, participant: &str) -> String {
    format!("{PREFIX}/{run}/p/{participant}/status")
}

/// Event that wakes a participant: a command, or a field it reads, arrived.
pub fn wake(run: &str, participant: &str) -> String {
    format!("{PREFIX}/{run}/p/{participant}/wake")
}

/// Blackboard on which a participant says whether it sleeps on its wake
/// event, so that writers notify it only then.
pub fn asleep(run: &str, participant: &str) -> String {
    format!("{PREFIX}/{run}/p/{participant}/asleep")
}

/// Event that wakes the coupler when a status message is waiting.
pub fn coupler_wake(run: &str) -> String {
    format!("{PREFIX}/{run}/coupler/wake")
}

/// A bulk `[f64]` field, published by its writer and read in place by its readers.
pub fn field(run: &str, field: &str) -> String {
    format!("{PREFIX}/{run}/field/{field}")
}

/// A fresh run id: process id and clock, short enough for service names.
#[cfg_attr(not(feature = "coupler"), allow(dead_code))]
pub fn new_run_id() -> String {
    let nanos = std::time::SystemTime::now()
        .duration_since(std::time::UNIX_EPOCH)
        .map(|d| d.as_nanos())
        .unwrap_or(0);
    format!("{:x}{:x}", std::process::id(), nanos & 0xffff_ffff_ffff)
}

/// Whether `name` may name a participant or a field: it becomes part of a
/// service name, so letters, digits and `_ - .` only, and not empty.
pub fn is_plain(name: &str) -> bool {
    !name.is_empty()
        && name.len() <= 64
        && name
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || matches!(c, '_' | '-' | '.'))
}
