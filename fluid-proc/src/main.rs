//! fluid-proc: connects the flow models to the coupler.

use coupler::{Command, Field, Monitor, Participant, Role};
use fluid_proc::{triangles_from_field, Porous};

type Error = Box<dyn std::error::Error>;

fn main() {
    if let Err(e) = run() {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}

fn run() -> Result<(), Error> {
    let mut p = Participant::connect(Role::Fluid)?;
    let section = p
        .scenario()
        .fluid
        .clone()
        .ok_or("the scenario has no [fluid] section")?;
    let model = Porous::new(&section.porous_load());
    let bodies = p.scenario().rigid.as_ref().map_or(0, |r| r.bodies.len());
    let mut triangles: Option<Vec<[usize; 3]>> = None;
    let mut windows = 0u64;
    loop {
        match p.next_command()? {
            // No pressure exists before the first window; NaN marks it in monitors.csv.
            Command::Initialize => p.done(vec![Monitor::new("mean_pressure_jump", f64::NAN)])?,
            Command::Output { .. } => p.done(Vec::new())?,
            Command::Advance(_) => {
                if p.is_connected(Field::BodyLoads) {
                    // The porous free-stream model has no flow around bodies, so
                    // it exerts no force on them: a body here is what seed 000
                    // §2.4 calls a mass-point parachutist, outside the flow. The
                    // pressure integral of eq. (2.40) comes with a flow field.
                    p.write_field(Field::BodyLoads, 6 * bodies, |out| out.fill(0.0))?;
                }
                if !p.is_connected(Field::CanopyPositions) {
                    windows += 1;
                    p.done(Vec::new())?;
                    continue;
                }
                if triangles.is_none() {
                    // Connectivity arrives once, at initialisation.
                    triangles = Some(triangles_from_field(&p.read_field(Field::CanopyTriangles)?));
                }
                let tris = triangles.as_deref().unwrap_or(&[]);
                let x = p.read_field(Field::CanopyPositions)?;
                let nodes = x.len() / 3;
                if let Some(t) = tris.iter().find(|t| t.iter().any(|&i| i >= nodes)) {
                    let msg =
                        format!("canopy triangle {t:?} names a vertex beyond the {nodes} sent");
                    p.fail(msg.clone())?;
                    return Err(msg.into());
                }
                let v = p.read_field(Field::CanopyVelocities)?;
                let mut total = 0.0;
                p.write_field(Field::CanopyPressure, tris.len(), |out| {
                    model.pressure(tris, &x, &v, out);
                    total = out.iter().sum::<f64>();
                })?;
                windows += 1;
                p.done(vec![Monitor::new(
                    "mean_pressure_jump",
                    total / tris.len().max(1) as f64,
                )])?;
            }
            Command::Stop => break,
            Command::Setup(_) => return Err("unexpected second setup".into()),
        }
    }
    p.finish(windows)?;
    Ok(())
}
