//! rigid-proc: connects the body library to the coupler.

use coupler::vtu::{CellKind, Piece, Series};
use coupler::{Command, Field, Monitor, Participant, Role};
use rigid_proc::Bodies;

type Error = Box<dyn std::error::Error>;

fn main() {
    if let Err(e) = run() {
        eprintln!("rigid-proc: {e}");
        std::process::exit(1);
    }
}

fn monitors(b: &Bodies) -> Vec<Monitor> {
    let mut v = vec![
        Monitor::new("kinetic_energy", b.kinetic_energy()),
        Monitor::new("potential_energy", b.potential_energy()),
    ];
    for body in &b.bodies {
        for (c, axis) in ["x", "y", "z"].iter().enumerate() {
            v.push(Monitor::new(format!("{}.{axis}", body.name), body.x[c]));
        }
        for (c, axis) in ["vx", "vy", "vz"].iter().enumerate() {
            v.push(Monitor::new(format!("{}.{axis}", body.name), body.v[c]));
        }
    }
    v
}

fn publish(p: &mut Participant, b: &Bodies) -> Result<(), Error> {
    let n = 6 * b.attachment_body.len();
    p.write_field(Field::AttachmentState, n, |out| b.attachment_state(out))?;
    Ok(())
}

fn run() -> Result<(), Error> {
    let mut p = Participant::connect(Role::Rigid)?;
    let scenario = p.scenario().clone();
    let section = scenario
        .rigid
        .as_ref()
        .ok_or("the scenario has no [rigid] section")?;
    let attached: Vec<&str> = scenario
        .structure
        .iter()
        .flat_map(|s| s.attachment_bodies())
        .collect();
    let mut bodies = Bodies::new(section, &attached);
    let mut series = Series::new(p.run_dir(), "bodies");
    let mut steps = 0u64;
    loop {
        match p.next_command()? {
            Command::Initialize => {
                publish(&mut p, &bodies)?;
                p.done(monitors(&bodies))?;
            }
            Command::Advance(step) => {
                let impulse = match p.is_connected(Field::AttachmentImpulse) {
                    true => Some(p.read_field(Field::AttachmentImpulse)?),
                    false => None,
                };
                let h = step.dt / step.substeps as f64;
                for k in 0..step.substeps {
                    // The impulse covers the whole step; apply it in the first sub-step.
                    let j = if k == 0 {
                        impulse.as_deref().unwrap_or(&[])
                    } else {
                        &[]
                    };
                    bodies.step(h, j);
                }
                steps += step.substeps as u64;
                if let Some(name) = bodies.first_non_finite() {
                    let msg = format!(
                        "diverged at t = {:.6e} s: body `{name}` has a non-finite state",
                        step.time + step.dt
                    );
                    p.fail(msg.clone())?;
                    return Err(msg.into());
                }
                publish(&mut p, &bodies)?;
                p.done(if step.window_end {
                    monitors(&bodies)
                } else {
                    Vec::new()
                })?;
            }
            Command::Output { index, time } => {
                let points: Vec<f64> = bodies.bodies.iter().flat_map(|b| b.x).collect();
                let vel: Vec<f64> = bodies.bodies.iter().flat_map(|b| b.v).collect();
                let conn: Vec<usize> = (0..bodies.bodies.len()).collect();
                series.write(
                    index,
                    time,
                    &Piece {
                        points: &points,
                        kind: CellKind::Vertex,
                        connectivity: &conn,
                        point_data: vec![("velocity", 3, &vel)],
                    },
                )?;
                p.done(Vec::new())?;
            }
            Command::Stop => break,
            Command::Setup(_) => return Err("unexpected second setup".into()),
        }
    }
    p.finish(steps)?;
    Ok(())
}
