//! fluid-proc: connects the flow models to the coupler.

use coupler::scenario::fluid::FluidModel;
use coupler::scenario::FluidSection;
use coupler::{Command, Field, Monitor, Participant, Role};
use fluid_proc::comm::Single;
use fluid_proc::{check_triangles, triangles_from_field, Porous};
use std::sync::Arc;

mod clearance;
mod flow_bodies;
mod flow_canopy;
mod flow_run;
mod gas_run;
mod ranks;

use flow_run::fail;

type Error = Box<dyn std::error::Error>;

fn main() {
    let ranks = std::env::var(coupler::names::ENV_RANKS)
        .ok()
        .and_then(|r| r.parse::<usize>().ok())
        .unwrap_or(1);
    let result = if ranks > 1 { ranks::ranks() } else { run() };
    if let Err(e) = result {
        eprintln!("fluid-proc: {e}");
        std::process::exit(1);
    }
}

/// Connects to the coupler; the scenario's `[fluid]` section.
fn connect() -> Result<(Participant, FluidSection), Error> {
    let p = Participant::connect(Role::Fluid)?;
    let section = p
        .scenario()
        .fluid
        .clone()
        .ok_or("the scenario has no [fluid] section")?;
    Ok((p, section))
}

fn run() -> Result<(), Error> {
    let (mut p, section) = connect()?;
    let steps = match section.model {
        FluidModel::PorousFreeStream => run_porous(&mut p, &section)?,
        FluidModel::Incompressible => {
            flow_run::lead(&mut p, &section, Arc::new(Single)).map_err(|s| s.error)?
        }
        FluidModel::Euler => {
            gas_run::lead(&mut p, &section, Arc::new(Single)).map_err(|s| s.error)?
        }
    };
    p.finish(steps)?;
    Ok(())
}

/// The porous free-stream model: a pressure jump per canopy triangle.
fn run_porous(p: &mut Participant, section: &FluidSection) -> Result<u64, Error> {
    let load = section
        .porous_load()
        .ok_or("[fluid] lacks a key of the porous free-stream model")?;
    let model = Porous::new(&load);
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
                if let Err(msg) = check_triangles(tris, x.len() / 3) {
                    return Err(fail(p, msg));
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
    Ok(windows)
}
