//! What a participant says it exchanges, when it joins a run: the fields it
//! writes (name, values per item, item count) and reads, the monitors it
//! reports, and how often it steps. Fields and participants are names:
//! the coupler matches each read to the one participant that writes a
//! field of that name, and refuses a required read that nobody writes.
//!
//! ```
//! use participant::{Cadence, Declaration};
//! let nodes = 4;
//! let d = Declaration::new(Cadence::PerWindow { substeps: 1 })
//!     .writes("canopy.positions", 3, nodes)
//!     .reads("canopy.pressure")
//!     .reads_if_written("body.states")
//!     .monitors(["kinetic_energy", "centre_deflection"]);
//! assert_eq!(d.monitor_names().len(), 2);
//! ```

use crate::timing::Cadence;
use serde::{Deserialize, Serialize};

/// What a participant that saves and restores window checkpoints declares
/// it supports.
pub const CHECKPOINTS: &str = "checkpoints";
/// What a participant that writes run checkpoints and resumes from them
/// declares it supports.
pub const RESTARTS: &str = "restarts";

/// A field a participant publishes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Write {
    pub name: String,
    /// Values per item (3 for a position, 13 for a rigid body's state).
    pub per_item: u32,
    /// Items per value written; None when it is known only later (a
    /// pressure per triangle of a mesh that another participant sends).
    pub items: Option<u64>,
}

/// A field a participant takes.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Read {
    pub name: String,
    /// A required read with no writer stops the run before it starts; an
    /// optional one is simply not exchanged.
    pub required: bool,
}

/// Everything a participant exchanges. Built with the methods below, read
/// as a sentence; handed to [`crate::Joining::declare`].
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Declaration {
    pub cadence: Cadence,
    pub writes: Vec<Write>,
    pub reads: Vec<Read>,
    pub monitors: Vec<String>,
    /// The SI unit of each monitor that has one, by name (`m/s`, `N`, `1`
    /// for a ratio): the report's axes say it ([`Declaration::units`]).
    #[serde(default)]
    pub units: std::collections::BTreeMap<String, String>,
    /// Optional commands the participant supports: [`CHECKPOINTS`] for
    /// `SaveCheckpoint` and `RestoreCheckpoint`, which implicit coupling
    /// needs; [`RESTARTS`] for `WriteCheckpoint` and `Resume`, which run
    /// checkpoints and `coupler run --restart` need.
    pub supports: Vec<String>,
    /// The manifest key of the summary it writes at its end
    /// ([`Declaration::summary`]).
    #[serde(default)]
    pub summary: Option<String>,
}

impl Declaration {
    /// A participant that steps with `cadence` and exchanges nothing yet.
    pub fn new(cadence: Cadence) -> Declaration {
        Declaration {
            cadence,
            writes: Vec::new(),
            reads: Vec::new(),
            monitors: Vec::new(),
            units: Default::default(),
            supports: Vec::new(),
            summary: None,
        }
    }

    /// Writes `name`: `items` items of `per_item` values each time.
    pub fn writes(mut self, name: &str, per_item: u32, items: usize) -> Self {
        self.writes.push(Write {
            name: name.to_string(),
            per_item,
            items: Some(items as u64),
        });
        self
    }

    /// Writes `name`, items of `per_item` values, as many as each write needs.
    pub fn writes_items_of(mut self, name: &str, per_item: u32) -> Self {
        self.writes.push(Write {
            name: name.to_string(),
            per_item,
            items: None,
        });
        self
    }

    /// Reads `name`, which some participant of the run must write.
    pub fn reads(mut self, name: &str) -> Self {
        self.reads.push(Read {
            name: name.to_string(),
            required: true,
        });
        self
    }

    /// Reads `name` when some participant writes it.
    pub fn reads_if_written(mut self, name: &str) -> Self {
        self.reads.push(Read {
            name: name.to_string(),
            required: false,
        });
        self
    }

    /// Reports these monitors (at the start and at every window end); they
    /// become the columns `<participant>.<name>` of `monitors.csv`.
    pub fn monitors<S: Into<String>>(mut self, names: impl IntoIterator<Item = S>) -> Self {
        self.monitors.extend(names.into_iter().map(Into::into));
        self
    }

    /// The unit of each monitor declared so far that has none yet, as
    /// `unit_of` gives it from the monitor's name (an empty unit: none).
    /// The coupler writes them to `units.csv` beside `monitors.csv` and
    /// labels the report's axes with them.
    pub fn units<S: AsRef<str>>(mut self, unit_of: impl Fn(&str) -> S) -> Self {
        for m in &self.monitors {
            let unit = unit_of(m);
            let unit = unit.as_ref();
            if !unit.is_empty() && !self.units.contains_key(m) {
                self.units.insert(m.clone(), unit.to_string());
            }
        }
        self
    }

    /// Monitor `name`'s unit; empty when it was given none.
    pub fn unit_of(&self, name: &str) -> &str {
        self.units.get(name).map_or("", String::as_str)
    }

    /// Writes, when the run ends, a summary of it
    /// ([`crate::Participant::summarize`]): its values go into the run's
    /// `manifest.json` under `name`, its line to the coupler's stderr.
    pub fn summary(mut self, name: impl Into<String>) -> Self {
        self.summary = Some(name.into());
        self
    }

    /// Saves its state at a window's start and restores it on
    /// `SaveCheckpoint` and `RestoreCheckpoint`, so that implicit coupling
    /// can take a window again; a window taken again from its checkpoint
    /// with the same inputs must give the same outputs.
    pub fn checkpoints(mut self) -> Self {
        self.supports.push(CHECKPOINTS.to_string());
        self
    }

    pub fn supports_checkpoints(&self) -> bool {
        self.supports.iter().any(|s| s == CHECKPOINTS)
    }

    /// Writes what the run needs to go on into files on `WriteCheckpoint`
    /// and reads them back on `Resume`, in place of `Initialize`, so that
    /// a stopped run can be restarted: the restarted run must give the
    /// same outputs as the whole run, bit for bit.
    pub fn restarts(mut self) -> Self {
        self.supports.push(RESTARTS.to_string());
        self
    }

    pub fn supports_restarts(&self) -> bool {
        self.supports.iter().any(|s| s == RESTARTS)
    }

    pub fn monitor_names(&self) -> &[String] {
        &self.monitors
    }

    /// The first name declared twice (a field written twice, read twice,
    /// or a monitor named twice), or one that cannot name a service.
    pub fn problem(&self) -> Option<String> {
        let mut seen = std::collections::HashSet::new();
        for w in &self.writes {
            if !crate::names::is_plain(&w.name) {
                return Some(format!(
                    "field name `{}` is not plain: letters, digits, `_ - .`",
                    w.name
                ));
            }
            if w.per_item == 0 {
                return Some(format!(
                    "field `{}` is declared with 0 values per item",
                    w.name
                ));
            }
            if !seen.insert(("w", w.name.as_str())) {
                return Some(format!("field `{}` is declared as written twice", w.name));
            }
        }
        for r in &self.reads {
            if !crate::names::is_plain(&r.name) {
                return Some(format!(
                    "field name `{}` is not plain: letters, digits, `_ - .`",
                    r.name
                ));
            }
            if !seen.insert(("r", r.name.as_str())) {
                return Some(format!("field `{}` is declared as read twice", r.name));
            }
            if seen.contains(&("w", r.name.as_str())) {
                return Some(format!(
                    "field `{}` is declared as both written and read",
                    r.name
                ));
            }
        }
        for m in &self.monitors {
            if m.is_empty() || m.contains(',') || !seen.insert(("m", m.as_str())) {
                return Some(format!(
                    "monitor `{m}` is empty, holds a comma or is declared twice"
                ));
            }
        }
        if let Some(name) = &self.summary {
            if !crate::names::is_plain(name) {
                return Some(format!(
                    "summary name `{name}` is not plain: letters, digits, `_ - .`"
                ));
            }
        }
        None
    }
}
