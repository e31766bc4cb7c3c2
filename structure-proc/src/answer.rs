//! What a structure program answers to `PROGRAM --check SCENARIO`
//! (docs/PROTOCOL.md, "Checking a scenario"): its section checked, and the
//! stability estimate of the model it builds: ω_max of dissertation eq.
//! (3.7), the integrator's stability interval, the sub-steps a window
//! needs, and a warning when the scenario's are too few.

use crate::driver::{Error, Stepper};
use crate::stability::{estimate, interval, omega_max, warning, Estimate, Interval};
use crate::{build_model, Model};
use scenario::{Answer, ScenarioError};
use std::path::Path;
use structure_section::{Scene, StructureSection};

/// The answer for the scenario text from `path`; a problem in it is the
/// error. `make` gives the program's stepper for the model.
pub fn answer<S: Stepper>(
    program: &str,
    path: &Path,
    text: &str,
    make: impl FnOnce(&StructureSection, &Model) -> Result<S, Error>,
) -> Result<Answer, ScenarioError> {
    let scene = Scene::load(path, text, program)?;
    let section = &scene.structure;
    // Every structure stepper saves and restores window checkpoints, and
    // the driver writes them to disk as run checkpoints.
    let mut answer = Answer::with_restarts();
    answer
        .manifest
        .insert("integrator".into(), section.integrator.name().into());
    let omega = match scheme_omega_max(&scene, make) {
        Ok(w) => w,
        Err(e) => {
            answer.notes.push(format!("stability not estimated: {e}"));
            return Ok(answer);
        }
    };
    if omega == 0.0 {
        answer
            .notes
            .push("stability: no spring holds a free node, so eq. 3.7 sets no step limit".into());
        return Ok(answer);
    }
    let c = &scene.scenario.coupling;
    let name = section.integrator.name();
    let est = estimate(omega, c.window, section.scheme());
    answer.notes.push(note(&est, section, name));
    answer
        .warnings
        .extend(warning(&est, c.window, c.structure_substeps, name));
    answer
        .manifest
        .insert("stability".into(), manifest(&est, section).into());
    Ok(answer)
}

/// The ω_max bound of the model the scene builds, if the program's stepper
/// is the scenario's integrator (whose interval the estimate assumes).
fn scheme_omega_max<S: Stepper>(
    scene: &Scene,
    make: impl FnOnce(&StructureSection, &Model) -> Result<S, Error>,
) -> Result<f64, Error> {
    let section = &scene.structure;
    let dt = scene.scenario.coupling.structure_dt();
    let m = build_model(section, scene.rigid.as_ref(), dt)?;
    let stepper = make(section, &m)?;
    if !stepper.is_scenario_integrator() {
        return Err(format!(
            "{} does not use `integrator = \"{}\"`, so eq. (3.7) and its interval do not apply",
            stepper.name(),
            section.integrator.name()
        )
        .into());
    }
    Ok(omega_max(&m.inv_mass, &m.couplings))
}

/// The line `coupler check` prints.
fn note(est: &Estimate, section: &StructureSection, name: &str) -> String {
    let limit = match (interval(section.scheme()), est.stable_dt) {
        (Interval::Bounded(y), Some(dt)) => format!(
            "stable for ω_max·Δt_s ≤ {y:.3}, Δt_s ≤ {dt:.3e} s, n_s ≥ {}",
            est.n_s
        ),
        (Interval::Empty, _) => "gains energy at every step".to_string(),
        _ => "unconditionally stable".to_string(),
    };
    format!(
        "stability ω_max = {:.4e} rad/s (dissertation eq. 3.7): {name} {limit}; the \
         dissertation's ω_max·Δt_s < 0.1 needs n_s ≥ {}",
        est.omega_max, est.n_s_seed
    )
}

/// The estimate as the run's manifest records it.
fn manifest(est: &Estimate, section: &StructureSection) -> toml::Table {
    let mut t = toml::Table::new();
    let i = interval(section.scheme());
    t.insert("omega_max".into(), est.omega_max.into());
    t.insert("interval".into(), i.label().into());
    if let Interval::Bounded(y) = i {
        t.insert("interval_omega_h".into(), y.into());
    }
    if let Some(dt) = est.stable_dt {
        t.insert("stable_dt_s".into(), dt.into());
    }
    t.insert("n_s".into(), (est.n_s as i64).into());
    t.insert("n_s_seed".into(), (est.n_s_seed as i64).into());
    t
}
