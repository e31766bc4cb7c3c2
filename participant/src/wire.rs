//! What crosses between the coupler and a participant on the control
//! channels: serde types encoded with bincode 2. Bulk data never travels
//! here; it goes through the fields (flat `[f64]` in shared memory).
//!
//! The handshake: the participant says [`FromParticipant::Hello`], the
//! coupler sends [`Setup`], the participant declares what it exchanges
//! ([`Declaration`]), the coupler answers with its [`Connections`], the
//! participant opens its ports and says `Ready`, and the coupler says
//! `Start` once everyone is ready. From then on each participant follows
//! the schedule by itself and only reports: monitor rows, a failure, or
//! its summary and statistics at the end; at a run checkpoint it asks the coupler to
//! keep the rows so far on disk, and waits for the answer.

use crate::declaration::Declaration;
use crate::summary::Summary;
use crate::timing::Timing;
use serde::{Deserialize, Serialize};
use std::path::PathBuf;

/// Everything a participant is told about the run once it connects.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Setup {
    pub run_id: String,
    /// Where the participant writes its output files.
    pub run_dir: PathBuf,
    /// The scenario file the run was started from (for messages that name
    /// a file and line).
    pub scenario_path: PathBuf,
    /// The resolved scenario (every default filled in), as TOML.
    pub scenario: String,
    /// The participants of this run, by name, in the scenario's order.
    pub participants: Vec<String>,
    pub timing: Timing,
    /// Explicit, or implicit with its settings (`[coupling] scheme`).
    pub scheme: crate::scheme::Scheme,
    /// A restarted run: the window after whose end it goes on, from the
    /// run checkpoint written there (`Command::Resume`).
    #[serde(default)]
    pub resume: Option<u64>,
    /// The coupler's process id (0: not told). A participant whose coupler
    /// is gone stops at its next command rather than run on alone and
    /// write into a run directory that a restarted run may be using.
    #[serde(default)]
    pub coupler_pid: u32,
}

/// Who writes a field a participant reads, and its layout.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Source {
    pub writer: String,
    pub per_item: u32,
    /// Item count when the writer declared one.
    pub items: Option<u64>,
    /// How many participants read the field (both ends open its service alike).
    pub readers: u32,
}

/// The coupler's answer to a declaration: how its fields are connected.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Connections {
    /// For each declared read, in order: who writes it (None: nobody
    /// does, which only an optional read allows).
    pub reads: Vec<Option<Source>>,
    /// For each declared write, in order: who reads it.
    pub writes: Vec<Vec<String>>,
    /// Whether another participant steps per impulse sub-step.
    pub partnered: bool,
}

/// Counters a participant reports when it finishes.
#[derive(Debug, Clone, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    pub cpu_s: f64,
    /// From connecting to finishing.
    pub wall_s: f64,
    /// From `Start` to finishing: the coupled run itself.
    pub run_s: f64,
    /// Seconds of that spent outside the library: the solver's own work.
    pub compute_s: f64,
    /// Seconds inside field reads and writes and reports, waiting excluded.
    pub exchange_s: f64,
    /// Seconds spent waiting for fields to arrive.
    pub wait_s: f64,
    /// Of that, seconds between a value's sending and this participant
    /// seeing it, for values it waited for: what the handing over cost.
    pub latency_s: f64,
    /// Waits that ended asleep on the wake event rather than spinning.
    pub sleeps: u64,
    /// Reads whose value was there at the first look: no wait at all.
    pub ready: u64,
    pub commands: u64,
    /// Field values read: hand-offs from another participant.
    pub reads: u64,
    /// Internal sub-steps taken, as counted by the solver.
    pub substeps: u64,
    /// Implicit coupling: seconds the solver took to save and restore its
    /// window checkpoints (part of `compute_s`), and seconds the library
    /// took to measure and relax the accelerated fields (part of
    /// `exchange_s`).
    pub checkpoint_s: f64,
    pub accelerate_s: f64,
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum ToParticipant {
    Setup(Setup),
    Connections(Connections),
    Start,
    /// `monitors.csv` holds its first `rows` rows, synced to disk: the
    /// answer to [`FromParticipant::Checkpoint`].
    RowsKept {
        rows: u64,
    },
}

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub enum FromParticipant {
    /// Ports are open; send the setup.
    Hello {
        pid: u32,
    },
    Declare(Declaration),
    /// Field ports are open; the participant waits for `Start`.
    Ready,
    /// `rows` rows `first_row, first_row + 1, …` of the declared monitors,
    /// `width` values each, flat. Row 0 is the state at the start, row
    /// w + 1 the state at the end of window w.
    Monitors {
        first_row: u64,
        rows: u64,
        width: u32,
        values: Vec<f64>,
    },
    /// No value of `field` came from `writer` within `seconds`; `writer`
    /// itself waited for the next of `then`, which waited for the one
    /// after, and so on (the chain of waits the flags showed then): the
    /// last of the chain is the one that did not answer.
    Stalled {
        field: String,
        writer: String,
        seconds: f64,
        then: Vec<String>,
    },
    /// The participant writes the run checkpoint that goes with the first
    /// `rows` monitor rows (sent before this), and completes it only once
    /// the coupler answers [`ToParticipant::RowsKept`]: a complete
    /// checkpoint always finds its rows in `monitors.csv`.
    Checkpoint {
        rows: u64,
    },
    /// `tries` tries of window `window` are done and the window is taken
    /// again or goes on: sent at most every second, so that the coupler
    /// hears a participant that works through a long implicit window.
    Tried {
        window: u64,
        tries: u32,
    },
    /// What the participant says of its whole run, sent just before
    /// `Finished`.
    Summary(Summary),
    /// The participant cannot go on (diverged, bad input); it exits non-zero after this.
    Failed {
        reason: String,
    },
    Finished(Stats),
}

/// bincode configuration used for every control message.
pub fn encode<T: Serialize>(msg: &T) -> Vec<u8> {
    bincode::serde::encode_to_vec(msg, bincode::config::standard())
        .expect("control messages always encode")
}

pub fn decode<T: for<'de> Deserialize<'de>>(
    bytes: &[u8],
) -> Result<T, bincode::error::DecodeError> {
    bincode::serde::decode_from_slice(bytes, bincode::config::standard()).map(|(v, _)| v)
}
