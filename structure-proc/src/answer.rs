//! What a structure program answers to `PROGRAM --check SCENARIO`
//! (docs/PROTOCOL.md, "Checking a scenario"): its section checked, and the
//! stability estimate of the model it builds: ω_max of dissertation eq.
//! (3.7), the integrator's stability interval, the sub-steps a window
//! needs, and a warning when the scenario's are too few.

use crate::damped::DampingRate;
use crate::driver::{Error, Stepper};
use crate::stability::{
    attached_omega, damping_rate, estimate, omega_max, warning, Estimate, Interval,
    ATTACHED_INTERVAL,
};
use crate::{build_model, Model};
use scenario::{section, Answer, ScenarioError};
use std::path::Path;
use structure_section::{Device, Scene, StructureSection};

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
    let dt = scene.structure.dt(scene.scenario.coupling.window);
    let built = build_model(section, scene.rigid.as_ref(), dt).map(|m| {
        let stepper = make(section, &m);
        (m, stepper)
    });
    // A GPU that cannot run the scene is a problem of the key that asks
    // for it: no adapter, or a part of the network the device does not take.
    if let (Device::Gpu, Ok((_, Err(e)))) = (section.device, &built) {
        let why = format!("device = \"gpu\": {e}");
        section::checked(path, text, |c| {
            c.within("structure", None, |c| c.problem(&["device"], why))
        })?;
    }
    // Every structure stepper saves and restores window checkpoints, and
    // the driver writes them to disk as run checkpoints.
    let mut answer = Answer::with_restarts();
    answer
        .manifest
        .insert("integrator".into(), section.integrator.name().into());
    // The structure's own clock within the coupler's windows.
    let n_s = section.substeps;
    answer
        .notes
        .push(format!("sub-steps n_s = {n_s} a window (Δt_s = {dt:e} s)"));
    answer
        .manifest
        .insert("substeps".into(), i64::from(n_s).into());
    answer.manifest.insert("dt_s".into(), dt.into());
    let estimated = built
        .map_err(Error::from)
        .and_then(|(m, stepper)| scheme_omega_max(&scene, path, text, &m, stepper?));
    let ((omega, damping), attached, layer) = match estimated {
        Ok(w) => w,
        Err(e) => {
            answer.notes.push(format!("stability not estimated: {e}"));
            return Ok(answer);
        }
    };
    answer.warnings.extend(layer);
    if attached > 0.0 {
        attached_answer(&mut answer, attached, &scene.scenario.coupling);
    }
    if omega == 0.0 {
        answer
            .notes
            .push("stability: no spring holds a free node of the structure, so eq. 3.7 sets no limit on its step".into());
        return Ok(answer);
    }
    let c = &scene.scenario.coupling;
    let name = section.integrator.name();
    let est = estimate(omega, c.window, section.scheme(), damping);
    answer.notes.push(note(&est, section, name));
    answer
        .warnings
        .extend(warning(&est, c.window, section.substeps, name));
    answer
        .manifest
        .insert("stability".into(), manifest(&est).into());
    Ok(answer)
}

/// The ω_max bound and damping rate of the model the scene builds, if the
/// program's stepper is the scenario's integrator (whose interval the
/// estimate assumes).
fn scheme_omega_max<S: Stepper>(
    scene: &Scene,
    path: &Path,
    text: &str,
    m: &Model,
    stepper: S,
) -> Result<((f64, DampingRate), f64, Option<String>), Error> {
    let section = &scene.structure;
    let dt = scene.structure.dt(scene.scenario.coupling.window);
    let layer = layer_warning(section, m);
    let weights = attachment_weights(scene, path, text)?;
    let nodes: Vec<usize> = m.attachments.iter().map(|a| a.node).collect();
    let attached = attached_omega(&nodes, &weights, &m.couplings);
    if !stepper.is_scenario_integrator() {
        return Err(format!(
            "{} does not use `integrator = \"{}\"`, so eq. (3.7) and its interval do not apply",
            stepper.name(),
            section.integrator.name()
        )
        .into());
    }
    let damping = damping_rate(&m.net, dt);
    Ok((
        (omega_max(&m.inv_mass, &m.couplings), damping),
        attached,
        layer,
    ))
}

/// Why the collision layer is too thick for the fabric's mesh, if it is:
/// a triangle whose smallest altitude is below `thickness` has a vertex
/// closer than the layer to its opposite edge, so wherever the pass tests
/// that region its own neighbouring features repel each other.
fn layer_warning(section: &StructureSection, m: &Model) -> Option<String> {
    let spec = section.collision.as_ref().filter(|c| c.self_contact)?;
    let (k, h) = crate::collision::geometry::smallest_altitude(&m.x, &m.net.triangles)?;
    (h <= spec.thickness).then(|| {
        format!(
            "[structure.collision] thickness = {:e} m is not below the smallest altitude of the \
             fabric's triangles, {h:.3e} m (triangle {k}, nodes {:?}): where the contact pass \
             tests that region, neighbouring features of the mesh repel each other; a thinner \
             layer or a mesh without such slivers avoids it",
            spec.thickness, m.net.triangles[k]
        )
    })
}

/// Each attachment's effective inverse mass [1/kg], in the order the
/// structure numbers them: its body's 1/m plus |r|²/I_min for the point r
/// off the centre of mass (0 for a static or prescribed body).
fn attachment_weights(scene: &Scene, path: &Path, text: &str) -> Result<Vec<f64>, Error> {
    let specs = rigid_section::attachments(path, text)?;
    let bodies = scene.rigid.as_ref().map_or(&[][..], |r| &r.bodies[..]);
    let weight = |a: &rigid_section::AttachmentSpec| -> Result<f64, Error> {
        let Some(spec) = bodies.iter().find(|b| b.name == a.body) else {
            return Ok(0.0);
        };
        let body = spec.body()?;
        let w = body.inv_mass();
        if w == 0.0 {
            return Ok(0.0);
        }
        let lever = (nalgebra::Vector3::from(spec.world_point(a.point)) - body.state.x).norm();
        let least = body
            .mass
            .principal
            .iter()
            .copied()
            .fold(f64::INFINITY, f64::min);
        Ok(w + if least > 0.0 {
            lever * lever / least
        } else {
            0.0
        })
    };
    specs.iter().map(weight).collect()
}

/// The note and warning on the bodies' strings: ω of [`attached_omega`]
/// over an impulse sub-step.
fn attached_answer(answer: &mut Answer, omega: f64, c: &scenario::CouplingSection) {
    let dt = c.window / c.impulse_substeps as f64;
    let limit = ATTACHED_INTERVAL / omega;
    let needed = ((omega * c.window / ATTACHED_INTERVAL).ceil() as u64).max(1);
    answer.notes.push(format!(
        "stability of the bodies on their strings: ω = {omega:.4e} rad/s (eq. 3.7 with each \
         body's mass at its attachment), stable for ω·Δt_i ≤ {ATTACHED_INTERVAL} over an impulse \
         sub-step, Δt_i ≤ {limit:.3e} s, impulse_substeps ≥ {needed}"
    ));
    if dt > limit {
        answer.warnings.push(format!(
            "the impulse sub-step Δt_i = {dt:e} s is above {limit:.3e} s, where a body's exchange \
             with its strings is sure to be stable (ω·Δt_i = {:.3} with ω = {omega:.4e} rad/s); \
             impulse_substeps = {needed} or more (with [structure] substeps a multiple) guarantees it",
            omega * dt
        ));
    }
}

/// The line `coupler check` prints.
fn note(est: &Estimate, section: &StructureSection, name: &str) -> String {
    let damped = match est.interval {
        Interval::Bounded(y) if y < undamped_bound(section) => " with its damping",
        _ => "",
    };
    let limit = match (est.interval, est.stable_dt) {
        (Interval::Bounded(y), Some(dt)) => format!(
            "stable{damped} for ω_max·Δt_s ≤ {y:.3}, Δt_s ≤ {dt:.3e} s, n_s ≥ {}",
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

/// The scheme's interval on undamped oscillation (infinite when it has no
/// bound).
fn undamped_bound(section: &StructureSection) -> f64 {
    match crate::stability::interval(section.scheme()) {
        Interval::Bounded(y) => y,
        _ => f64::INFINITY,
    }
}

/// The estimate as the run's manifest records it.
fn manifest(est: &Estimate) -> toml::Table {
    let mut t = toml::Table::new();
    let i = est.interval;
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
