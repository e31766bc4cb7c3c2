//! The accuracy sweep on a scenario: each integrator at each structure step
//! runs through `coupler run`, like any user run, and its monitored positions
//! are compared with those of a reference run of RK4 (the most accurate
//! fixed-step scheme) at a much smaller step. The structure step is varied
//! through `structure_substeps` at a fixed coupling window, so every run
//! reports its monitors at the same times. CPU time is the structure
//! process's, from the run's manifest.

use crate::accuracy::{adaptive_tolerance, Run, Status};
use coupler::scenario::structure::Integrator;
use coupler::Scenario;
use std::path::{Path, PathBuf};
use std::process::Command;

/// The reference runs this many halvings below the smallest step of the ladder.
pub const REFERENCE_HALVINGS: u32 = 3;
/// The scheme of the reference run.
pub const REFERENCE: Integrator = Integrator::Rk4;

/// A scenario under study.
pub struct ScenarioStudy {
    pub path: PathBuf,
    pub scenario: Scenario,
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
        let mut scenario = Scenario::load(path).map_err(|e| e.to_string())?;
        if scenario.structure.is_none() {
            return Err(format!("{}: has no [structure] to study", path.display()));
        }
        if let Some(t) = end_time {
            if !(t > scenario.run.start_time) {
                return Err(format!(
                    "--end-time {t}: must be after the start time {} s",
                    scenario.run.start_time
                ));
            }
            scenario.run.end_time = t;
        }
        scenario.run.output_interval = 0.0;
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
            scenario,
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
        let mut s = self.scenario.clone();
        let st = s.structure.as_mut().expect("checked in new");
        st.integrator = integrator;
        let mut name = format!("{}-n{substeps}", integrator.name());
        if let Some(t) = tolerance {
            st.adaptive.tolerance = t;
            name = format!("{}-tol{t:.0e}", integrator.name());
        }
        s.coupling.structure_substeps = substeps;
        let toml = self.dir.join("runs").join(format!("{name}.toml"));
        let out = self.dir.join("runs").join(&name);
        let _ = std::fs::remove_dir_all(&out);
        std::fs::create_dir_all(self.dir.join("runs")).map_err(|e| e.to_string())?;
        std::fs::write(&toml, s.to_toml()).map_err(|e| e.to_string())?;
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
        match r.status {
            Status::Ok => Ok(r.rows),
            s => Err(format!("the reference run did not finish: {}", s.label())),
        }
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
                    let base = self.scenario.coupling.structure_substeps;
                    (base, Some(adaptive_tolerance(l, substeps.len())))
                } else {
                    (n, None)
                };
                let o = self.run(i, n, tolerance)?;
                let run = Run {
                    integrator: i,
                    dt: self.step(n),
                    tolerance,
                    error: if o.status == Status::Ok {
                        error(&o.rows, reference)
                    } else {
                        f64::NAN
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
pub const ERROR_MEASURE: &str = "largest difference from the reference run over every window end and every monitored structure position (named points' x, y, z and the canopy's centre deflection), divided by the largest displacement of those positions in the reference run";

/// The structure's monitored positions from `monitors.csv`, by row:
/// columns `structure.<point>.x|y|z` and `structure.centre_deflection`.
fn compared_columns(path: &Path) -> Result<Vec<Vec<f64>>, String> {
    let text = std::fs::read_to_string(path)
        .map_err(|e| format!("cannot read {}: {e}", path.display()))?;
    let mut lines = text.lines();
    let header: Vec<&str> = lines.next().unwrap_or_default().split(',').collect();
    let keep: Vec<usize> = header
        .iter()
        .enumerate()
        .filter(|(_, h)| {
            h.starts_with("structure.")
                && (h.ends_with(".x")
                    || h.ends_with(".y")
                    || h.ends_with(".z")
                    || h.ends_with("centre_deflection"))
        })
        .map(|(i, _)| i)
        .collect();
    if keep.is_empty() {
        return Err(format!(
            "{}: the structure monitors no position (name a point or give a canopy)",
            path.display()
        ));
    }
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

/// Largest |q − q_ref| over rows and columns, over the largest displacement
/// |q_ref(t) − q_ref(0)|; infinite when the run wrote fewer rows.
pub fn error(rows: &[Vec<f64>], reference: &[Vec<f64>]) -> f64 {
    if rows.len() < reference.len() || reference.is_empty() {
        return f64::INFINITY;
    }
    let start = &reference[0];
    let mut scale: f64 = 0.0;
    let mut worst: f64 = 0.0;
    for (r, q) in reference.iter().zip(rows) {
        for c in 0..r.len() {
            scale = scale.max((r[c] - start[c]).abs());
            let d = (q[c] - r[c]).abs();
            worst = if d.is_nan() {
                f64::INFINITY
            } else {
                worst.max(d)
            };
        }
    }
    worst / scale.max(f64::MIN_POSITIVE)
}
