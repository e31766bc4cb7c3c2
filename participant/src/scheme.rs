//! How the participants of a run are coupled in time, as the coupler tells
//! them in the setup (`[coupling] scheme` of the scenario).
//!
//! Explicit: every window is taken once, in the staggered order of the
//! schedule. Implicit: every window is taken again from its checkpoint
//! until the interface converges (preCICE's implicit coupling; Degroote,
//! Bathe & Vierendeels 2009). The fields that close the loop, those the
//! first participant of a window reads at its start, are *accelerated*:
//! their writer relaxes each new value against the one it sent before
//! (`acceleration.rs`) and measures their residual, and every participant
//! learns from all the others whether the window converged
//! (`verdict.rs`). PROTOCOL.md, "Implicit coupling", says why it is done
//! this way.

use serde::{Deserialize, Serialize};

/// The monitors the library adds to an implicit run's declarations, which
/// the coupler gathers into `iterations.csv`: the tries each window took
/// (on the run's first participant: every participant takes as many); per
/// accelerated field, on its writer, the last try's relative residual
/// ‖r‖₂/‖x‖₂ (`RESIDUAL` + the field's name); and the IQN-ILS columns the
/// writer's last relaxation used.
pub const TRIES: &str = "implicit.tries";
pub const RESIDUAL: &str = "implicit.residual.";
pub const COLUMNS: &str = "implicit.columns";

#[derive(Debug, Clone, PartialEq, Serialize, Deserialize, Default)]
pub enum Scheme {
    #[default]
    Explicit,
    Implicit(Implicit),
}

impl Scheme {
    pub fn implicit(&self) -> Option<&Implicit> {
        match self {
            Scheme::Explicit => None,
            Scheme::Implicit(i) => Some(i),
        }
    }
}

/// An implicit scheme's settings.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Implicit {
    /// The accelerated fields, with their convergence limits.
    pub fields: Vec<Measured>,
    pub acceleration: Acceleration,
    /// Tries per window at least and at most.
    pub min_iterations: u32,
    pub max_iterations: u32,
    /// On reaching `max_iterations` unconverged: go on with a warning
    /// rather than stop the run.
    pub go_on_at_max: bool,
    /// Parallel implicit: every participant computes each try at once from
    /// the others' last values (so each publishes its window-end fields
    /// at `Initialize` too), and the writers relax their fields together,
    /// as one vector (`joint.rs`).
    #[serde(default)]
    pub parallel: bool,
    /// IQN-ILS: ω on the part of a residual its columns do not explain
    /// ([`crate::iqn_ils::Columns::step_from`]); 1 takes it whole.
    #[serde(default = "whole")]
    pub complement: f64,
}

fn whole() -> f64 {
    1.0
}

impl Implicit {
    pub fn measured(&self, field: &str) -> Option<&Measured> {
        self.fields.iter().find(|f| f.field == field)
    }
}

/// A field whose residual decides whether a window has converged: it has
/// when ‖r‖₂ ≤ relative·‖x‖₂ or ‖r‖₂ ≤ absolute (either limit may be
/// absent), r = x − x̃ the change from the value sent before.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Measured {
    pub field: String,
    pub relative: Option<f64>,
    pub absolute: Option<f64>,
}

impl Measured {
    /// Whether a residual of norm `r` on a value of norm `x` converged.
    pub fn converged(&self, r: f64, x: f64) -> bool {
        self.relative.is_some_and(|l| r <= l * x) || self.absolute.is_some_and(|l| r <= l)
    }
}

/// How a writer relaxes its accelerated fields, x̃_{k+1} = x̃_k + ω_k r_k.
#[derive(Debug, Clone, Copy, PartialEq, Serialize, Deserialize)]
pub enum Acceleration {
    /// A fixed ω.
    Constant { omega: f64 },
    /// Aitken's dynamic ω (Küttler & Wall 2008, eq. 44), starting each
    /// window at `initial`.
    Aitken { initial: f64 },
    /// IQN-ILS (Degroote et al. 2009): `initial` ω while it has no column,
    /// the columns of the last `reused_windows` windows, at most
    /// `max_columns`, filtered by QR2 with limit `filter`.
    IqnIls {
        initial: f64,
        reused_windows: u32,
        max_columns: u32,
        filter: f64,
    },
}
