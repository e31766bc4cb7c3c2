//! rigid-proc: connects the body library to the coupler.

use coupler::vtu::{CellKind, Piece, Series};
use coupler::{Command, Field, Monitor, Participant, Role};
use nalgebra::Vector3;
use rigid_proc::body::STATE_LEN;
use rigid_proc::{Bodies, Load};

type Error = Box<dyn std::error::Error>;

fn main() {
    if let Err(e) = run() {
        eprintln!("rigid-proc: {e}");
        std::process::exit(1);
    }
}

fn monitors(b: &Bodies) -> Vec<Monitor> {
    let (p, l) = (b.momentum(), b.angular_momentum());
    let mut v = vec![
        Monitor::new("kinetic_energy", b.kinetic_energy()),
        Monitor::new("potential_energy", b.potential_energy()),
        Monitor::new("momentum.x", p.x),
        Monitor::new("momentum.y", p.y),
        Monitor::new("momentum.z", p.z),
        Monitor::new("angular_momentum", l.norm()),
        Monitor::new("contact_impulses", b.contact_impulses as f64),
    ];
    let xyz = ["x", "y", "z"];
    for body in b
        .bodies
        .iter()
        .filter(|body| body.inv_mass() > 0.0 || body.state.v != Vector3::zeros())
    {
        let s = &body.state;
        let omega = body.world_angular_velocity();
        for c in 0..3 {
            v.push(Monitor::new(format!("{}.{}", body.name, xyz[c]), s.x[c]));
        }
        for c in 0..3 {
            v.push(Monitor::new(format!("{}.v{}", body.name, xyz[c]), s.v[c]));
        }
        if body.shape.is_some() {
            for c in 0..3 {
                v.push(Monitor::new(
                    format!("{}.omega{}", body.name, xyz[c]),
                    omega[c],
                ));
            }
            // Angular velocity about each principal axis, wᵢ of eq. (2.12).
            for c in 0..3 {
                v.push(Monitor::new(format!("{}.w{}", body.name, c + 1), s.w[c]));
            }
            v.push(Monitor::new(
                format!("{}.kinetic_energy", body.name),
                body.kinetic_energy(),
            ));
            v.push(Monitor::new(
                format!("{}.spin_momentum", body.name),
                body.spin_momentum().norm(),
            ));
        }
    }
    v
}

fn publish(p: &mut Participant, b: &Bodies, window_end: bool) -> Result<(), Error> {
    let n = 6 * b.attachments.len();
    p.write_field(Field::AttachmentState, n, |out| b.attachment_state(out))?;
    let n = STATE_LEN * b.bodies.len();
    p.write_field(Field::CollisionBodies, n, |out| b.write_states(out))?;
    if window_end {
        p.write_field(Field::BodyStates, n, |out| b.write_states(out))?;
    }
    Ok(())
}

/// Every body's surface (mass points as vertices) for ParaView.
fn write_surfaces(series: &mut Series, b: &Bodies, index: u64, time: f64) -> Result<(), Error> {
    let mut points = Vec::new();
    let mut velocity = Vec::new();
    let mut triangles = Vec::new();
    for body in &b.bodies {
        let Some(shape) = &body.shape else { continue };
        let pose = body.own_pose();
        let (local, tris) = shape.surface();
        let first = points.len() / 3;
        for p in &local {
            let w = (pose * p).coords;
            points.extend_from_slice(w.as_slice());
            velocity.extend_from_slice(body.velocity_at(&w).as_slice());
        }
        triangles.extend(tris.iter().flat_map(|t| t.map(|i| first + i as usize)));
    }
    series.write(
        index,
        time,
        &Piece {
            points: &points,
            kind: CellKind::Triangle,
            connectivity: &triangles,
            point_data: vec![("velocity", 3, &velocity)],
        },
    )?;
    Ok(())
}

fn run() -> Result<(), Error> {
    let mut p = Participant::connect(Role::Rigid)?;
    let scenario = p.scenario().clone();
    let section = scenario
        .rigid
        .as_ref()
        .ok_or("the scenario has no [rigid] section")?;
    let attached = scenario
        .structure
        .as_ref()
        .map(|s| s.attachments())
        .unwrap_or_default();
    let mut bodies = Bodies::new(section, &attached)?;
    // Centres of mass of every body, and the surfaces of bodies with shapes.
    let mut centres = Series::new(p.run_dir(), "bodies");
    let mut surfaces = bodies
        .bodies
        .iter()
        .any(|b| b.shape.is_some())
        .then(|| Series::new(p.run_dir(), "body-surfaces"));
    let mut loads: Vec<Load> = Vec::new();
    let mut loads_window = None;
    let mut steps = 0u64;
    loop {
        match p.next_command()? {
            Command::Initialize => {
                publish(&mut p, &bodies, true)?;
                p.done(monitors(&bodies))?;
            }
            Command::Advance(step) => {
                // The fluid sends one load per window; its sub-steps keep it.
                if p.is_connected(Field::BodyLoads) && loads_window != Some(step.window) {
                    let f = p.read_field(Field::BodyLoads)?;
                    loads = f
                        .chunks_exact(6)
                        .map(|c| Load {
                            force: Vector3::new(c[0], c[1], c[2]),
                            torque: Vector3::new(c[3], c[4], c[5]),
                        })
                        .collect();
                    loads_window = Some(step.window);
                }
                let impulse = match p.is_connected(Field::AttachmentImpulse) {
                    true => Some(p.read_field(Field::AttachmentImpulse)?),
                    false => None,
                };
                if p.is_connected(Field::CollisionImpulse) {
                    bodies.apply_momenta(&p.read_field(Field::CollisionImpulse)?);
                }
                let h = step.dt / step.substeps as f64;
                for k in 0..step.substeps {
                    // The impulse covers the whole step; apply it in the first sub-step.
                    let j = match k {
                        0 => impulse.as_deref().unwrap_or(&[]),
                        _ => &[],
                    };
                    bodies.step(h, j, &loads);
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
                publish(&mut p, &bodies, step.window_end)?;
                p.done(if step.window_end {
                    monitors(&bodies)
                } else {
                    Vec::new()
                })?;
            }
            Command::Output { index, time } => {
                write_points(&mut centres, &bodies, index, time)?;
                if let Some(series) = &mut surfaces {
                    write_surfaces(series, &bodies, index, time)?;
                }
                p.done(Vec::new())?;
            }
            Command::Stop => break,
            Command::Setup(_) => return Err("unexpected second setup".into()),
        }
    }
    p.finish(steps)?;
    Ok(())
}

/// Every body's centre of mass, as vertices.
fn write_points(series: &mut Series, b: &Bodies, index: u64, time: f64) -> Result<(), Error> {
    let points: Vec<f64> = b
        .bodies
        .iter()
        .flat_map(|b| b.state.x.iter().copied().collect::<Vec<_>>())
        .collect();
    let vel: Vec<f64> = b
        .bodies
        .iter()
        .flat_map(|b| b.state.v.iter().copied().collect::<Vec<_>>())
        .collect();
    let conn: Vec<usize> = (0..b.bodies.len()).collect();
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
    Ok(())
}
