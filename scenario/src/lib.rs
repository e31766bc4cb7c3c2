//! Scenario files, the part every participant shares: `[run]`, `[coupling]`
//! and `[participants]`, parsed with serde, unknown keys rejected, every
//! value checked. Every other table belongs to the participant of the same
//! name, whose program reads and checks it ([`section`], [`answer`]); every
//! problem is reported as one message naming the file, line and key.

pub mod answer;
mod check;
mod error;
pub mod implicit;
pub mod reference;
pub mod section;
mod spans;

pub use answer::{answer_check, answer_check_as, Answer, CHECK_FLAG};
pub use check::{
    add_rule, path_string, recording_rules, Checker, Problem, Rules, Seg, MAX_MAGNITUDE,
    MIN_POSITIVE,
};
pub use error::ScenarioError;
pub use implicit::{ImplicitSection, SchemeName};

use serde::{Deserialize, Serialize};
use std::collections::BTreeMap;
use std::path::Path;

/// Most coupling windows one run may take.
pub const MAX_WINDOWS: f64 = 1e9;
/// Most sub-steps per window.
pub const MAX_SUBSTEPS: f64 = 1e6;
/// Fewest steps of the f64 clock a window spans (2^20, about 10^6): the
/// time of every window's end is then exact to a millionth of a window,
/// and outputs and checkpoints fall on the windows they are due at.
pub const MIN_CLOCK_STEPS_PER_WINDOW: f64 = 1048576.0;
/// Longest answer timeout [s] (a day).
pub const MAX_TIMEOUT: f64 = 86_400.0;
/// Most MPI ranks a participant may ask for (guards against typos).
pub const MAX_RANKS: f64 = 4096.0;

/// The coupling part of a scenario file, with the names of the
/// participants' own tables.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
pub struct Scenario {
    pub run: RunSection,
    pub coupling: CouplingSection,
    pub participants: Participants,
    /// The file's other top-level tables, in file order: each is the
    /// section of the listed participant of the same name.
    #[serde(skip)]
    pub sections: Vec<String>,
}

/// `[run]`: what is simulated and for how long.
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct RunSection {
    /// Scene name, used in logs and the manifest.
    pub name: String,
    /// Simulated start time [s].
    #[serde(default)]
    pub start_time: f64,
    /// Simulated end time [s].
    pub end_time: f64,
    /// Simulated time between `.vtu` outputs [s]; 0 writes only the first and last state.
    #[serde(default)]
    pub output_interval: f64,
    /// Simulated time between run checkpoints [s], from which `coupler run
    /// --restart` goes on; absent writes none.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub checkpoint_interval: Option<f64>,
}

/// `[coupling]`: the FSI window and its sub-steps (docs/PROTOCOL.md, "The schedule").
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct CouplingSection {
    /// FSI window = one fluid step Δt_f [s].
    pub window: f64,
    /// Impulse exchanges between structure and rigid bodies per window; it
    /// must divide the sub-steps each of them takes a window (the
    /// structure's `[structure] substeps`).
    #[serde(default = "one")]
    pub impulse_substeps: u32,
    /// Seconds a participant may take to answer one command before the run is failed.
    #[serde(default = "default_timeout")]
    pub timeout: f64,
    /// `explicit` (each window once), `implicit` (each window again from
    /// its checkpoint until the interface converges, the participants in
    /// turn) or `parallel-implicit` (the same, the participants at once).
    #[serde(default)]
    pub scheme: SchemeName,
    /// The implicit scheme's settings; defaults when absent.
    #[serde(default)]
    pub implicit: Option<ImplicitSection>,
}

impl CouplingSection {
    /// The implicit scheme's settings, when the scheme is implicit.
    pub fn implicit_settings(&self) -> Option<ImplicitSection> {
        (self.scheme.is_implicit()).then(|| self.implicit.clone().unwrap_or_default())
    }

    /// Whether the participants compute each try of a window at once.
    pub fn parallel(&self) -> bool {
        self.scheme == SchemeName::ParallelImplicit
    }

    /// Whether the structure and the rigid bodies iterate each window
    /// together: an implicit scheme with one impulse exchange per window.
    /// Each try the structure then moves an attachment point along the
    /// chord from its window-start position to where the last try's body
    /// ended, and the body takes the structure's impulse as a constant force
    /// over the window; converged, that is the average-vector-field method
    /// (McLachlan, Quispel & Robidoux 1999), which keeps the energy of a
    /// string held by a body exactly, up to the structure's quadrature of
    /// its force along the chord. With more exchanges per window the
    /// window's first value of the body is its start, as in an explicit
    /// window, and the body takes each impulse as a kick.
    pub fn bodies_iterate(&self) -> bool {
        self.scheme.is_implicit() && self.impulse_substeps == 1
    }
}

fn one() -> u32 {
    1
}
fn default_timeout() -> f64 {
    60.0
}

/// Keys of the coupling sections that a solver's own table took over, and
/// where each went: a scenario written before gets told where to write it.
const MOVED: [(&str, &str, &str); 1] = [(
    "coupling",
    "structure_substeps",
    "the structure's sub-steps are the structure's own setting now: write \
     `substeps = N` in its table ([structure] for structure-proc and xpbd-proc)",
)];

/// Refuses a key of [`MOVED`], naming where it went.
fn refuse_moved(path: &Path, text: &str) -> Result<(), ScenarioError> {
    for (table, key, went) in MOVED {
        let Some(t) = section::read::<toml::Table>(path, text, table)? else {
            continue;
        };
        if t.contains_key(key) {
            let message = format!("`{key}` is no longer a key of [{table}]: {went}");
            return Err(ScenarioError::at_key(path, text, &[table, key], message));
        }
    }
    Ok(())
}

/// canopy's own participants, in the order they start and their monitors'
/// columns appear; any other name a scenario lists comes after them, in
/// alphabetical order.
pub const PARTICIPANTS: [&str; 3] = ["fluid", "structure", "rigid"];

/// The coupling sections, which the coupler reads; no participant may take
/// their names.
pub const COUPLING_SECTIONS: [&str; 3] = ["run", "coupling", "participants"];

/// `[participants]`: the processes this scene starts, by name. A name not
/// listed is not started and exchanges nothing.
#[derive(Debug, Clone, Default, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(transparent)]
pub struct Participants(BTreeMap<String, ParticipantSpec>);

/// Which executable plays a participant: any program that speaks the
/// protocol (docs/PROTOCOL.md).
#[derive(Debug, Clone, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ParticipantSpec {
    /// A bare name is looked up beside the `coupler` executable, then on PATH;
    /// a path is taken relative to the scenario file.
    pub program: String,
    #[serde(default)]
    pub args: Vec<String>,
    /// MPI ranks to run on: more than one starts the program under
    /// `mpirun -n ranks` (a program that runs as one process refuses it in
    /// its `--check`).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranks: Option<u32>,
}

impl ParticipantSpec {
    /// The program alone, with no arguments, on one rank.
    pub fn program(program: &str) -> ParticipantSpec {
        ParticipantSpec {
            program: program.to_string(),
            args: Vec::new(),
            ranks: None,
        }
    }

    /// The ranks it runs on (1 unless `ranks` is given).
    pub fn ranks(&self) -> u32 {
        self.ranks.unwrap_or(1)
    }
}

impl Participants {
    /// The participant called `name`, if the scenario lists it.
    pub fn get(&self, name: &str) -> Option<&ParticipantSpec> {
        self.0.get(name)
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut ParticipantSpec> {
        self.0.get_mut(name)
    }

    /// Whether the scenario lists a participant called `name`.
    pub fn lists(&self, name: &str) -> bool {
        self.0.contains_key(name)
    }

    /// Lists (or replaces) the participant `name`.
    pub fn insert(&mut self, name: &str, spec: ParticipantSpec) {
        self.0.insert(name.to_string(), spec);
    }

    /// Removes the participant `name` from the list.
    pub fn remove(&mut self, name: &str) -> Option<ParticipantSpec> {
        self.0.remove(name)
    }

    /// The listed participants' names: canopy's own in the order of
    /// [`PARTICIPANTS`], then the others alphabetically.
    pub fn names(&self) -> Vec<&str> {
        let own = PARTICIPANTS.into_iter().filter(|n| self.lists(n));
        let others = self
            .0
            .keys()
            .map(String::as_str)
            .filter(|n| !PARTICIPANTS.contains(n));
        own.chain(others).collect()
    }
}

impl Scenario {
    /// Read, parse and check the coupling part of a scenario file.
    pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
        Scenario::parse(path, &read_text(path)?)
    }

    /// Parse and check the coupling part of scenario text; `path` names the
    /// file in messages.
    pub fn parse(path: &Path, text: &str) -> Result<Scenario, ScenarioError> {
        let missing = |name: &str| ScenarioError {
            file: path.to_path_buf(),
            line: None,
            column: None,
            key: Some(name.to_string()),
            message: format!("the scenario has no [{name}] table"),
        };
        refuse_moved(path, text)?;
        let scenario = Scenario {
            run: section::read(path, text, "run")?.ok_or_else(|| missing("run"))?,
            coupling: section::read(path, text, "coupling")?.ok_or_else(|| missing("coupling"))?,
            participants: section::read(path, text, "participants")?
                .ok_or_else(|| missing("participants"))?,
            sections: section::table_names(path, text)?
                .into_iter()
                .filter(|n| !COUPLING_SECTIONS.contains(&n.as_str()))
                .collect(),
        };
        section::checked(path, text, |c| scenario.check(c))?;
        Ok(scenario)
    }

    /// Refuses `ranks` for participant `name`, played by `program`, which
    /// runs as one process (only a program built for MPI takes ranks).
    pub fn check_one_process(&self, c: &mut Checker, name: &str, program: &str) {
        let ranks = self.participants.get(name).and_then(|p| p.ranks);
        if let Some(ranks) = ranks.filter(|&r| r != 1) {
            c.problem(
                &["participants", name, "ranks"],
                format!(
                    "ranks = {ranks}: {program} runs as one process; ranks is for a program \
                     built for MPI, such as fluid-proc"
                ),
            );
        }
    }

    /// Number of FSI windows from start to end (the last one may be shortened).
    pub fn windows(&self) -> u64 {
        let span = self.run.end_time - self.run.start_time;
        (span / self.coupling.window - 1e-9).ceil().max(1.0) as u64
    }

    /// Start time and length of window `w`; the last window ends exactly at `end_time`.
    pub fn window_span(&self, w: u64) -> (f64, f64) {
        let t = self.run.start_time + w as f64 * self.coupling.window;
        (t, self.coupling.window.min(self.run.end_time - t))
    }

    fn check(&self, c: &mut Checker) {
        self.check_run(c);
        self.check_coupling(c);
        self.check_participants(c);
    }

    /// `[run]`: a name, a clock that runs forward, outputs a run can write.
    fn check_run(&self, c: &mut Checker) {
        let r = &self.run;
        c.plain_name(&["run", "name"], &r.name, true);
        c.finite_nonneg(&["run", "start_time"], r.start_time);
        c.finite(&["run", "end_time"], r.end_time);
        if r.end_time <= r.start_time {
            c.problem(
                &["run", "end_time"],
                format!(
                    "end_time = {} must be after start_time = {}",
                    r.end_time, r.start_time
                ),
            );
        }
        c.finite_nonneg(&["run", "output_interval"], r.output_interval);
        let span = r.end_time - r.start_time;
        if r.output_interval > 0.0 && span / r.output_interval > MAX_WINDOWS {
            c.problem(
                &["run", "output_interval"],
                format!(
                    "output_interval = {:e} s asks for more than {MAX_WINDOWS:e} outputs from \
                     start_time to end_time (0 writes the first and last state only)",
                    r.output_interval
                )
                .replace("  ", " "),
            );
        }
        if let Some(every) = r.checkpoint_interval {
            let key = ["run", "checkpoint_interval"];
            c.positive(&key, every, "s");
            if every > 0.0 && span / every > MAX_WINDOWS {
                c.problem(
                    &key,
                    format!(
                        "checkpoint_interval = {every:e} s asks for more than {MAX_WINDOWS:e} \
                         checkpoints from start_time to end_time"
                    ),
                );
            }
        }
    }

    /// `[coupling]`: a window that fits the run, sub-steps that divide.
    fn check_coupling(&self, c: &mut Checker) {
        let (r, k) = (&self.run, &self.coupling);
        c.positive(&["coupling", "window"], k.window, "s");
        if k.window > 0.0 && (r.end_time - r.start_time) / k.window > MAX_WINDOWS {
            c.problem(&["coupling", "window"], format!(
                "window = {} gives more than {MAX_WINDOWS:e} windows from start_time to end_time", k.window));
        }
        self.check_clock(c);
        c.at_most(
            &["coupling", "impulse_substeps"],
            k.impulse_substeps as f64,
            MAX_SUBSTEPS,
        );
        c.at_most(&["coupling", "timeout"], k.timeout, MAX_TIMEOUT);
        c.nonzero(&["coupling", "impulse_substeps"], k.impulse_substeps as f64);
        c.positive(&["coupling", "timeout"], k.timeout, "s");
        match (&k.implicit, k.scheme) {
            (Some(_), SchemeName::Explicit) => c.problem(
                &["coupling", "implicit"],
                "[coupling.implicit] is given but scheme is \"explicit\": set \
                 scheme = \"implicit\" (or \"parallel-implicit\") or remove the table"
                    .into(),
            ),
            (Some(i), _) => i.check(c, k.bodies_iterate(), k.parallel()),
            (None, _) => {}
        }
    }

    /// A clock that tells the windows apart: far from 0 the f64 times
    /// are coarse (1e15 s steps by 0.125 s), and windows shorter than
    /// [`MIN_CLOCK_STEPS_PER_WINDOW`] of those steps would end at repeated
    /// or rounded times.
    fn check_clock(&self, c: &mut Checker) {
        let (r, window) = (&self.run, self.coupling.window);
        let far = r.start_time.abs().max(r.end_time.abs());
        if !(far.is_finite() && window > 0.0) {
            return;
        }
        let step = far.next_up() - far;
        if window >= MIN_CLOCK_STEPS_PER_WINDOW * step {
            return;
        }
        // The start, if it alone is that far out; else the end.
        let start_step = r.start_time.abs().next_up() - r.start_time.abs();
        let (key, value) = match window < MIN_CLOCK_STEPS_PER_WINDOW * start_step {
            true => ("start_time", r.start_time),
            false => ("end_time", r.end_time),
        };
        c.problem(
            &["run", key],
            format!(
                "{key} = {value} s: near it the clock (f64) steps by {step:e} s, too coarse \
                 for windows of {window:e} s (each must span {MIN_CLOCK_STEPS_PER_WINDOW:e} \
                 steps, so that its end time is exact): start nearer 0 s, or make \
                 [coupling] window at least {:e} s",
                MIN_CLOCK_STEPS_PER_WINDOW * step
            ),
        );
    }

    /// `[participants]` and the tables beside it: each table a listed
    /// participant's, each participant with a program and its table.
    fn check_participants(&self, c: &mut Checker) {
        if self.participants.names().is_empty() {
            c.problem(
                &["participants"],
                "lists no participant: name at least one, for example fluid, structure or rigid"
                    .into(),
            );
        }
        for name in self.participants.names() {
            self.check_participant(c, name);
        }
        for name in &self.sections {
            if !self.participants.lists(name) {
                c.problem(
                    &[name],
                    format!(
                        "[{name}] section given but no participant `{name}` is listed in \
                         [participants] (nor is it a coupling section: [run], [coupling], \
                         [participants])"
                    ),
                );
            }
        }
    }

    fn check_participant(&self, c: &mut Checker, name: &str) {
        let spec = self.participants.get(name).expect("a listed name");
        c.plain_name(&["participants", name], name, false);
        if spec.program.trim().is_empty() {
            c.problem(
                &["participants", name, "program"],
                "program is empty".into(),
            );
        }
        if let Some(ranks) = spec.ranks {
            let key = ["participants", name, "ranks"];
            c.nonzero(&key, ranks as f64);
            c.at_most(&key, ranks as f64, MAX_RANKS);
        }
        if !self.sections.iter().any(|s| s == name) {
            c.problem(
                &["participants", name],
                format!("participant `{name}` is listed but the scenario has no [{name}] section"),
            );
        }
    }
}

/// Longest scenario file read [bytes]: a scenario is a page of TOML.
pub const MAX_SCENARIO_BYTES: u64 = 1 << 24;

/// The text of the scenario file at `path`, which must be a regular file
/// (a FIFO or a device would block the reader or never end) of at most
/// [`MAX_SCENARIO_BYTES`].
pub fn read_text(path: &Path) -> Result<String, ScenarioError> {
    let meta = std::fs::metadata(path).map_err(|e| ScenarioError::io(path, &e))?;
    let refuse = |why: &str| ScenarioError::io(path, &std::io::Error::other(why.to_string()));
    if !meta.is_file() {
        return Err(refuse("it is not a regular file"));
    }
    if meta.len() > MAX_SCENARIO_BYTES {
        return Err(refuse(&format!(
            "it holds {} bytes, more than a scenario's {MAX_SCENARIO_BYTES}",
            meta.len()
        )));
    }
    std::fs::read_to_string(path).map_err(|e| ScenarioError::io(path, &e))
}
