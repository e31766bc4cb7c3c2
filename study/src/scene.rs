//! The accuracy sweep on a scenario: each integrator at each structure step
//! runs through `coupler run`, like any user run, and its monitored positions
//! are compared with those of a reference run of RK4 (the most accurate
//! fixed-step scheme) at a much smaller step. The structure step is varied
//! through `[structure] substeps` at a fixed coupling window, so every run
//! reports its monitors at the same times. CPU time is the structure
//! process's, from the run's manifest.

use crate::accuracy::{adaptive_tolerance, Run, Status};
use scenario::Scenario;
use std::path::{Path, PathBuf};
use std::process::Command;
use structure_section::{Integrator, Scene, StructureSection};
use toml_edit::{value, DocumentMut};

/// The reference runs this many halvings below the smallest step of the ladder.
pub const REFERENCE_HALVINGS: u32 = 3;
/// The scheme of the reference run.
pub const REFERENCE: Integrator = Integrator::Rk4;

/// A scenario under study.
pub struct ScenarioStudy {
    pub path: PathBuf,
    /// The file's text, each variant an edit of it (every table the study
    /// does not vary stays as written).
    pub text: String,
    pub scenario: Scenario,
    pub structure: StructureSection,
    /// The `coupler` executable that runs it.
    pub coupler: PathBuf,
    /// Where the variants and their runs go.
    pub dir: PathBuf,
}

/// What a run left that the study reads.
struct Outcome {
    /// Monitor columns compared, by row.
    rows: Vec<Vec<f64>>,
    cpu_seconds: f64,
    substeps: u64,
    status: Status,
}

impl ScenarioStudy {
    /// Load `path`; fails with a message when it cannot be studied.
    pub fn new(path: &Path, dir: &Path, end_time: Option<f64>) -> Result<ScenarioStudy, String> {
        let text = scenario::read_text(path).map_err(|e| e.to_string())?;
        let mut scenario = Scenario::parse(path, &text).map_err(|e| e.to_string())?;
        if !scenario.participants.lists("structure") {
            return Err(format!("{}: has no [structure] to study", path.display()));
        }
        let program = scenario
            .participants
            .get("structure")
            .map(|p| p.program.clone());
        let scene = Scene::load(path, &text, program.as_deref().unwrap_or("structure"))
            .map_err(|e| e.to_string())?;
        let mut doc: DocumentMut = text
            .parse()
            .map_err(|e| format!("{}: {e}", path.display()))?;
        if let Some(t) = end_time {
            if !(t > scenario.run.start_time) {
                return Err(format!(
                    "--end-time {t}: must be after the start time {} s",
                    scenario.run.start_time
                ));
            }
            scenario.run.end_time = t;
            doc["run"]["end_time"] = value(t);
        }
        scenario.run.output_interval = 0.0;
        doc["run"]["output_interval"] = value(0.0);
        let exe = std::env::current_exe().map_err(|e| e.to_string())?;
        let coupler = exe.with_file_name("coupler");
        if !coupler.is_file() {
            return Err(format!(
                "no `coupler` executable beside {} (build it: cargo build --release -p coupler)",
                exe.display()
            ));
        }
        Ok(ScenarioStudy {
            path: path.to_path_buf(),
            text: doc.to_string(),
            scenario,
            structure: scene.structure,
            coupler,
            dir: dir.to_path_buf(),
        })
    }

    /// The structure step at `substeps` sub-steps of the window [s].
    pub fn step(&self, substeps: u32) -> f64 {
        self.scenario.coupling.window / substeps as f64
    }

    /// The scene's name.
    pub fn name(&self) -> &str {
        &self.scenario.run.name
    }

    /// Run `integrator` with `substeps` structure sub-steps per window (and,
    /// for an adaptive one, `tolerance`).
    fn run(
        &self,
        integrator: Integrator,
        substeps: u32,
        tolerance: Option<f64>,
    ) -> Result<Outcome, String> {
        let mut s: DocumentMut = self.text.parse().map_err(|e| format!("{e}"))?;
        s["structure"]["integrator"] = value(integrator.name());
        let mut name = format!("{}-n{substeps}", integrator.name());
        if let Some(t) = tolerance {
            s["structure"]["adaptive"]["tolerance"] = value(t);
            name = format!("{}-tol{t:.0e}", integrator.name());
        }
        s["structure"]["substeps"] = value(i64::from(substeps));
        let toml = self.dir.join("runs").join(format!("{name}.toml"));
        let out = self.dir.join("runs").join(&name);
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(self.dir.join("runs")).map_err(|e| e.to_string())?;
        std::fs::write(&toml, s.to_string()).map_err(|e| e.to_string())?;
        let o = Command::new(&self.coupler)
            .arg("run")
            .arg(&toml)
            .arg("--out")
            .arg(&out)
            .output()
            .map_err(|e| format!("cannot run {}: {e}", self.coupler.display()))?;
        let manifest: serde_json::Value = std::fs::read_to_string(out.join("manifest.json"))
            .ok()
            .and_then(|t| serde_json::from_str(&t).ok())
            .ok_or_else(|| {
                format!(
                    "{name}: no manifest; coupler said: {}",
                    String::from_utf8_lossy(&o.stderr)
                )
            })?;
        let structure = manifest["processes"]
            .as_array()
            .and_then(|ps| ps.iter().find(|p| p["role"] == "structure"));
        let status = if o.status.success() {
            Status::Ok
        } else {
            let error = manifest["error"].as_str().unwrap_or("failed").to_string();
            match diverged_at(&error) {
                Some(t) => Status::Diverged(t),
                None => Status::Failed(error),
            }
        };
        Ok(Outcome {
            rows: compared_columns(&out.join("monitors.csv"))?,
            cpu_seconds: structure
                .and_then(|p| p["cpu_s"].as_f64())
                .unwrap_or(f64::NAN),
            substeps: structure.and_then(|p| p["substeps"].as_u64()).unwrap_or(0),
            status,
        })
    }

    /// The reference: [`REFERENCE`] at `substeps`; its rows.
    pub fn reference(&self, substeps: u32) -> Result<Vec<Vec<f64>>, String> {
        let r = self.run(REFERENCE, substeps, None)?;
        if r.status != Status::Ok {
            return Err(format!(
                "the reference run did not finish: {}",
                r.status.label()
            ));
        }
        if error(&r.rows, &r.rows).is_none() {
            return Err(format!(
                "{}: no monitored structure quantity moves in the reference run, so there is nothing to compare",
                self.path.display()
            ));
        }
        Ok(r.rows)
    }

    /// Every integrator at every sub-step count, against `reference`; an
    /// adaptive one at the scenario's own sub-steps and, level by level, the
    /// tolerances of [`adaptive_tolerance`].
    pub fn sweep(
        &self,
        integrators: &[Integrator],
        substeps: &[u32],
        reference: &[Vec<f64>],
        mut progress: impl FnMut(&Run),
    ) -> Result<Vec<Run>, String> {
        let mut runs = Vec::new();
        for &i in integrators {
            for (l, &n) in substeps.iter().enumerate() {
                let (n, tolerance) = if i.is_adaptive() {
                    let base = self.structure.substeps;
                    (base, Some(adaptive_tolerance(l, substeps.len())))
                } else {
                    (n, None)
                };
                let o = self.run(i, n, tolerance)?;
                let run = Run {
                    integrator: i,
                    dt: self.step(n),
                    tolerance,
                    error: match o.status {
                        Status::Ok => error(&o.rows, reference).unwrap_or(f64::NAN),
                        _ => f64::NAN,
                    },
                    cpu_seconds: o.cpu_seconds,
                    steps: o.substeps,
                    status: o.status,
                };
                progress(&run);
                runs.push(run);
            }
        }
        Ok(runs)
    }
}

/// The time in "… diverged at t = 2.42e0 s: …".
fn diverged_at(error: &str) -> Option<f64> {
    let rest = error.split("diverged at t = ").nth(1)?;
    rest.split_whitespace().next()?.parse().ok()
}

/// What the error measures, for the report.
pub const ERROR_MEASURE: &str = "largest difference from the reference run over every window end, for each monitored structure quantity that moves in the reference (named points' x, y, z, the canopy's centre deflection, kinetic and potential energy) divided by its range in the reference, the largest over the quantities";

/// The structure's monitored positions and energies from `monitors.csv`, by
/// row: columns `structure.<point>.x|y|z`, `structure.centre_deflection`,
/// `structure.kinetic_energy` and `structure.potential_energy`.
fn compared_columns(path: &Path) -> Result<Vec<Vec<f64>>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let compared = |h: &str| {
        h.starts_with("structure.")
            && [
                ".x",
                ".y",
                ".z",
                "centre_deflection",
                "kinetic_energy",
                "potential_energy",
            ]
            .iter()
            .any(|end| h.ends_with(end))
    };
    let keep: Vec<usize> = (0..header.len()).filter(|&i| compared(header[i])).collect();
    Ok(lines
        .map(|l| {
            let v: Vec<f64> = l
                .split(',')
                .map(|x| x.parse().unwrap_or(f64::NAN))
                .collect();
            keep.iter()
                .map(|&i| v.get(i).copied().unwrap_or(f64::NAN))
                .collect()
        })
        .collect())
}

/// The range max_t q_ref − min_t q_ref of each column of `reference`.
fn ranges(reference: &[Vec<f64>]) -> Vec<f64> {
    let columns = reference.first().map_or(0, Vec::len);
    (0..columns)
        .map(|c| {
            let (lo, hi) = reference.iter().fold((f64::MAX, f64::MIN), |(lo, hi), r| {
                (lo.min(r[c]), hi.max(r[c]))
            });
            hi - lo
        })
        .collect()
}

/// The largest over the columns that move in `reference` of
/// max_t |q − q_ref| / range(q_ref); infinite when the run wrote fewer rows
/// or a non-finite value. None when nothing moves in the reference.
pub fn error(rows: &[Vec<f64>], reference: &[Vec<f64>]) -> Option<f64> {
    let range = ranges(reference);
    let moving: Vec<usize> = (0..range.len()).filter(|&c| range[c] > 0.0).collect();
    if moving.is_empty() {
        return None;
    }
    if rows.len() < reference.len() {
        return Some(f64::INFINITY);
    }
    let mut worst: f64 = 0.0;
    for (r, q) in reference.iter().zip(rows) {
        for &c in &moving {
            let d = (q[c] - r[c]).abs() / range[c];
            worst = if d.is_nan() {
                f64::INFINITY
            } else {
                worst.max(d)
            };
        }
    }
    Some(worst)
}
