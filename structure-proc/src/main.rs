//! structure-proc: connects the spring-mass library to the coupler.

use coupler::{Command, Field, Monitor, Participant, Role};
use structure_proc::forces::Loads;
use structure_proc::output::Output;
use structure_proc::{build_model, integrator, Model};

type Error = Box<dyn std::error::Error>;

fn main() {
    if let Err(e) = run() {
        eprintln!("structure-proc: {e}");
        std::process::exit(1);
    }
}

fn monitors(m: &Model) -> Vec<Monitor> {
    let mut v = vec![
        Monitor::new("kinetic_energy", m.kinetic_energy()),
        Monitor::new("potential_energy", m.potential_energy()),
    ];
    if m.canopy_nodes > 0 {
        v.push(Monitor::new("centre_deflection", m.centre_deflection()));
    }
    for (name, n) in &m.points {
        if m.kind[*n] == structure_proc::NodeKind::Free {
            for (c, axis) in ["x", "y", "z", "vx", "vy", "vz"].iter().enumerate() {
                let value = if c < 3 {
                    m.x[3 * n + c]
                } else {
                    m.v[3 * n + c - 3]
                };
                v.push(Monitor::new(format!("{name}.{axis}"), value));
            }
        }
    }
    v
}

/// Canopy positions and velocities for the fluid (and, once, its triangles).
fn publish_canopy(p: &mut Participant, m: &Model, with_triangles: bool) -> Result<(), Error> {
    let n = 3 * m.canopy_nodes;
    if with_triangles {
        p.write_field(Field::CanopyTriangles, 3 * m.triangles.len(), |out| {
            for (o, &i) in out.iter_mut().zip(m.triangles.iter().flatten()) {
                *o = i as f64;
            }
        })?;
    }
    p.write_field(Field::CanopyPositions, n, |out| {
        out.copy_from_slice(&m.x[..n])
    })?;
    p.write_field(Field::CanopyVelocities, n, |out| {
        out.copy_from_slice(&m.v[..n])
    })?;
    Ok(())
}

fn run() -> Result<(), Error> {
    let mut p = Participant::connect(Role::Structure)?;
    let scenario = p.scenario().clone();
    let section = scenario
        .structure
        .as_ref()
        .ok_or("the scenario has no [structure] section")?;
    let dt = scenario.coupling.window / scenario.coupling.structure_substeps as f64;
    let mut m = build_model(section, scenario.rigid.as_ref(), dt)?;
    let mut integrator = integrator(section.scheme());
    let mut output = Output::new(p.run_dir(), &m);
    let mut substeps = 0u64;
    let mut pressure = None;
    let mut pressure_window = None;
    loop {
        match p.next_command()? {
            Command::Initialize => {
                publish_canopy(&mut p, &m, true)?;
                p.done(monitors(&m))?;
            }
            Command::Advance(step) => {
                // The fluid publishes one pressure per window; impulse sub-steps
                // after the first keep using it.
                if p.is_connected(Field::CanopyPressure) && pressure_window != Some(step.window) {
                    pressure = Some(p.read_field(Field::CanopyPressure)?);
                    pressure_window = Some(step.window);
                }
                if p.is_connected(Field::AttachmentState) {
                    let state = p.read_field(Field::AttachmentState)?;
                    m.set_attachments(&state);
                }
                let loads = Loads {
                    pressure: pressure.as_deref().unwrap_or(&[]),
                };
                m.dt = step.dt / step.substeps as f64;
                m.time = step.time;
                let mut failure = None;
                for k in 0..step.substeps {
                    if let Err(e) = m.step(integrator.as_mut(), &loads) {
                        let t = step.time + k as f64 * m.dt;
                        failure = Some(format!(
                            "{} failed at t = {t:.6e} s: {e}",
                            section.integrator.name()
                        ));
                        break;
                    }
                }
                substeps += step.substeps as u64;
                if failure.is_none() {
                    if let Some((node, what)) = m.first_non_finite() {
                        failure = Some(format!(
                            "diverged at t = {:.6e} s: node {node} has a non-finite {what}",
                            step.time + step.dt
                        ));
                    }
                }
                if let Some(msg) = failure {
                    p.fail(msg.clone())?;
                    return Err(msg.into());
                }
                let n_att = m.attachments.len();
                p.write_field(Field::AttachmentImpulse, 3 * n_att, |out| {
                    for (o, a) in out.chunks_exact_mut(3).zip(&m.attachments) {
                        o.copy_from_slice(&a.impulse);
                    }
                })?;
                if step.window_end {
                    publish_canopy(&mut p, &m, false)?;
                    p.done(monitors(&m))?;
                } else {
                    p.done(Vec::new())?;
                }
            }
            Command::Output { index, time } => {
                output.write(&m, index, time)?;
                p.done(Vec::new())?;
            }
            Command::Stop => break,
            Command::Setup(_) => return Err("unexpected second setup".into()),
        }
    }
    p.finish(substeps)?;
    Ok(())
}
