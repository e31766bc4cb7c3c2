//! Scenario files: TOML parsed with serde, unknown keys rejected, every value
//! checked, every problem reported as one message naming the file, line and key.

mod canopy_flow;
mod check;
pub mod collision;
mod error;
pub mod flow;
pub mod fluid;
pub mod gas;
pub mod integrator;
pub mod mesh;
pub mod parachute;
pub mod rigid;
mod spans;
pub mod stability;
pub mod structure;

pub use check::Checker;
pub use error::ScenarioError;
pub use fluid::{FluidSection, PorousLoad};
pub use rigid::RigidSection;
pub use structure::StructureSection;

use serde::{Deserialize, Serialize};
use std::path::Path;

/// Most coupling windows one run may take.
pub const MAX_WINDOWS: f64 = 1e9;
/// Most sub-steps per window.
pub const MAX_SUBSTEPS: f64 = 1e6;
/// Longest answer timeout [s] (a day).
pub const MAX_TIMEOUT: f64 = 86_400.0;
/// Most MPI ranks a participant may ask for (guards against typos).
pub const MAX_RANKS: f64 = 4096.0;

/// A whole scenario file.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Scenario {
    pub run: RunSection,
    pub coupling: CouplingSection,
    pub participants: Participants,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fluid: Option<FluidSection>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structure: Option<StructureSection>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rigid: Option<RigidSection>,
}

/// `[run]`: what is simulated and for how long.
#[derive(Debug, Clone, Serialize, Deserialize)]
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
}

/// `[coupling]`: the FSI window and its sub-steps (DESIGN.md, "Time stepping").
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct CouplingSection {
    /// FSI window = one fluid step Δt_f [s].
    pub window: f64,
    /// Structure sub-steps n_s per window (Δt_s = Δt_f / n_s).
    #[serde(default = "one")]
    pub structure_substeps: u32,
    /// Impulse exchanges between structure and rigid bodies per window; must divide n_s.
    #[serde(default = "one")]
    pub impulse_substeps: u32,
    /// Seconds a participant may take to answer one command before the run is failed.
    #[serde(default = "default_timeout")]
    pub timeout: f64,
}

impl CouplingSection {
    /// The structure step Δt_s = Δt_f / n_s [s].
    pub fn structure_dt(&self) -> f64 {
        self.window / self.structure_substeps as f64
    }
}

fn one() -> u32 {
    1
}
fn default_timeout() -> f64 {
    60.0
}

/// The participants a scenario may list, each with a section of the same
/// name that its program reads.
pub const PARTICIPANTS: [&str; 3] = ["fluid", "structure", "rigid"];

/// `[participants]`: the processes this scene starts. A role not listed is not
/// started and exchanges nothing.
#[derive(Debug, Clone, Default, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Participants {
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub fluid: Option<ParticipantSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub structure: Option<ParticipantSpec>,
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub rigid: Option<ParticipantSpec>,
}

/// Which executable plays a role: any program that speaks the protocol.
#[derive(Debug, Clone, Serialize, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct ParticipantSpec {
    /// A bare name is looked up beside the `coupler` executable, then on PATH;
    /// a path is taken relative to the scenario file.
    pub program: String,
    #[serde(default)]
    pub args: Vec<String>,
    /// MPI ranks to run on (fluid only): more than one starts the program
    /// under `mpirun -n ranks`.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub ranks: Option<u32>,
}

impl ParticipantSpec {
    /// The ranks it runs on (1 unless `ranks` is given).
    pub fn ranks(&self) -> u32 {
        self.ranks.unwrap_or(1)
    }
}

impl Participants {
    /// The participant called `name`, if the scenario lists it.
    pub fn get(&self, name: &str) -> Option<&ParticipantSpec> {
        match name {
            "fluid" => self.fluid.as_ref(),
            "structure" => self.structure.as_ref(),
            "rigid" => self.rigid.as_ref(),
            _ => None,
        }
    }

    pub fn get_mut(&mut self, name: &str) -> Option<&mut ParticipantSpec> {
        match name {
            "fluid" => self.fluid.as_mut(),
            "structure" => self.structure.as_mut(),
            "rigid" => self.rigid.as_mut(),
            _ => None,
        }
    }

    /// The listed participants' names, in the order of [`PARTICIPANTS`].
    pub fn names(&self) -> Vec<&'static str> {
        PARTICIPANTS
            .into_iter()
            .filter(|n| self.get(n).is_some())
            .collect()
    }
}

impl Scenario {
    /// Read, parse and check a scenario file.
    pub fn load(path: &Path) -> Result<Scenario, ScenarioError> {
        let text = read_text(path)?;
        let mut scenario = Scenario::parse(path, &text)?;
        // Files a scenario names are relative to it; read them now, so a bad
        // mesh stops the run before any process starts.
        let dir = path.parent().unwrap_or(Path::new("."));
        if let Some(rigid) = &mut scenario.rigid {
            rigid.resolve_meshes(dir).map_err(|(i, e)| {
                let at = |k: &str| check::Seg::Key(k.into());
                let problem = check::Problem {
                    path: vec![
                        at("rigid"),
                        at("bodies"),
                        check::Seg::Index(i),
                        at("shape"),
                        at("file"),
                    ],
                    message: e.to_string(),
                };
                ScenarioError::from_problem(path, &text, problem)
            })?;
        }
        Ok(scenario)
    }

    /// Parse and check scenario text; `path` is only used in messages.
    pub fn parse(path: &Path, text: &str) -> Result<Scenario, ScenarioError> {
        let scenario: Scenario =
            toml::from_str(text).map_err(|e| ScenarioError::from_toml(path, text, &e))?;
        let mut checker = Checker::default();
        scenario.check(&mut checker);
        match checker.into_problem() {
            None => Ok(scenario),
            Some(p) => Err(ScenarioError::from_problem(path, text, p)),
        }
    }

    /// Parse the resolved scenario a participant receives in its setup.
    pub fn from_resolved(text: &str) -> Result<Scenario, ScenarioError> {
        Scenario::parse(Path::new("<resolved scenario>"), text)
    }

    /// The scenario with every default filled in, as written to the run directory.
    pub fn to_toml(&self) -> String {
        toml::to_string_pretty(self).expect("a scenario always serialises")
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
        let k = &self.coupling;
        c.positive(&["coupling", "window"], k.window, "s");
        if k.window > 0.0 && (r.end_time - r.start_time) / k.window > MAX_WINDOWS {
            c.problem(&["coupling", "window"], format!(
                "window = {} gives more than {MAX_WINDOWS:e} windows from start_time to end_time", k.window));
        }
        c.at_most(
            &["coupling", "structure_substeps"],
            k.structure_substeps as f64,
            MAX_SUBSTEPS,
        );
        c.at_most(
            &["coupling", "impulse_substeps"],
            k.impulse_substeps as f64,
            MAX_SUBSTEPS,
        );
        c.at_most(&["coupling", "timeout"], k.timeout, MAX_TIMEOUT);
        c.nonzero(
            &["coupling", "structure_substeps"],
            k.structure_substeps as f64,
        );
        c.nonzero(&["coupling", "impulse_substeps"], k.impulse_substeps as f64);
        if k.impulse_substeps > 0 && !k.structure_substeps.is_multiple_of(k.impulse_substeps) {
            c.problem(
                &["coupling", "impulse_substeps"],
                format!(
                    "impulse_substeps = {} must divide structure_substeps = {}",
                    k.impulse_substeps, k.structure_substeps
                ),
            );
        }
        c.positive(&["coupling", "timeout"], k.timeout, "s");
        if self.participants.names().is_empty() {
            c.problem(
                &["participants"],
                "lists no participant: name at least one of fluid, structure, rigid".into(),
            );
        }
        for role in PARTICIPANTS {
            if let Some(spec) = self.participants.get(role) {
                if spec.program.trim().is_empty() {
                    c.problem(
                        &["participants", role, "program"],
                        "program is empty".into(),
                    );
                }
                if let Some(ranks) = spec.ranks {
                    let key = ["participants", role, "ranks"];
                    if role != "fluid" {
                        c.problem(
                            &key,
                            format!(
                                "ranks is for the fluid participant only; `{}` runs as one process",
                                role
                            ),
                        );
                    }
                    c.nonzero(&key, ranks as f64);
                    c.at_most(&key, ranks as f64, MAX_RANKS);
                }
            }
            let has_section = match role {
                "fluid" => self.fluid.is_some(),
                "structure" => self.structure.is_some(),
                _ => self.rigid.is_some(),
            };
            let listed = self.participants.get(role).is_some();
            if listed && !has_section {
                c.problem(
                    &["participants", role],
                    format!(
                        "participant `{0}` is listed but the scenario has no [{0}] section",
                        role
                    ),
                );
            }
            if has_section && !listed {
                c.problem(
                    &[role],
                    format!(
                        "[{0}] section given but no participant `{0}` is listed in [participants]",
                        role
                    ),
                );
            }
        }
        if let Some(s) = &self.fluid {
            s.check(c);
            // The incompressible flow takes the canopy and rigid bodies
            // (immersed boundaries); the gas takes neither yet.
            let coupled =
                self.participants.structure.is_some() || self.participants.rigid.is_some();
            if s.model == fluid::FluidModel::Euler && coupled {
                c.problem(
                    &["fluid", "model"],
                    "model = \"euler\" is not coupled to a structure or rigid bodies yet: use \
                     model = \"incompressible\" or \"porous-free-stream\" for such a scene"
                        .into(),
                );
            }
            canopy_flow::check(
                c,
                s,
                self.participants.structure.is_some(),
                self.structure.as_ref(),
            );
            let ranks = self.participants.fluid.as_ref().map_or(1, |f| f.ranks());
            if ranks > 1 {
                check_ranks(c, s, ranks);
            }
            let courant = s.start_courant(k.window).unwrap_or(0.0);
            if courant > flow::MAX_COURANT {
                c.problem(
                    &["coupling", "window"],
                    format!(
                        "window = {} s is one flow step, and at the sides' speed it crosses {courant:.3} cells \
                         (the Courant number): more than {} is unstable, so shorten it",
                        k.window,
                        flow::MAX_COURANT
                    ),
                );
            }
        }
        let porous_in_structure = self.structure.as_ref().is_some_and(|s| s.porous.is_some());
        if porous_in_structure && self.participants.fluid.is_some() {
            c.problem(
                &["structure", "porous"],
                "[structure.porous] makes the structure apply the porous load itself, but \
                 participant `fluid` loads the canopy too: keep one of them"
                    .into(),
            );
        }
        if let Some(s) = &self.structure {
            s.check(c, self.rigid.as_ref());
        }
        if let Some(s) = &self.rigid {
            s.check(c);
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

/// Whether the fluid can run on `ranks` ranks: a model split among ranks
/// (euler and incompressible), and slabs at least as thick as the
/// stencil's reach, so that each rank's halo comes from its two neighbours.
fn check_ranks(c: &mut Checker, s: &FluidSection, ranks: u32) {
    let key = ["participants", "fluid", "ranks"];
    if s.model == fluid::FluidModel::PorousFreeStream {
        c.problem(
            &key,
            format!(
                "ranks = {ranks}: model = \"{}\" has no cells to split and runs on one rank",
                s.model.name()
            ),
        );
        return;
    }
    let Some(b) = s.flow_box else { return };
    let axis = if s.model == fluid::FluidModel::Euler {
        // The one with the most cells, the last of equals.
        (0..3).rev().max_by_key(|&d| (b.cells[d], d)).unwrap_or(0)
    } else {
        // The slowest in memory more than one cell thick (fluid-proc's part.rs).
        match (1..3).rev().find(|&d| b.cells[d] > 1) {
            Some(d) => d,
            None => {
                c.problem(
                    &key,
                    format!("ranks = {ranks}: the incompressible flow is split along y or z, and this box is one cell thick along both"),
                );
                return;
            }
        }
    };
    if u64::from(b.cells[axis]) < u64::from(flow::HALO_CELLS) * u64::from(ranks) {
        c.problem(
            &key,
            format!(
                "ranks = {ranks} leaves fewer than {} cells per rank along {} ({} cells): use fewer ranks",
                flow::HALO_CELLS,
                ["x", "y", "z"][axis],
                b.cells[axis]
            ),
        );
    }
}
