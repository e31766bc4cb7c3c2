//! fluid-proc: connects the flow models to the coupler.

use coupler::scenario::fluid::FluidModel;
use coupler::scenario::FluidSection;
use coupler::vtu::{Image, Series};
use coupler::{Command, Field, Monitor, Participant, Role};
use fluid_proc::comm::Single;
use fluid_proc::incompressible::{Incompressible, StepReport};
use fluid_proc::setup::flow_from;
use fluid_proc::{check_triangles, triangles_from_field, Porous};

mod clearance;
mod flow_bodies;
mod flow_canopy;
mod gas_run;

use flow_bodies::FlowBodies;
use flow_canopy::FlowCanopy;

type Error = Box<dyn std::error::Error>;

fn main() {
    let ranks = std::env::var(coupler::names::ENV_RANKS)
        .ok()
        .and_then(|r| r.parse::<usize>().ok())
        .unwrap_or(1);
    let result = if ranks > 1 { gas_run::ranks() } else { run() };
    if let Err(e) = result {
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
    let steps = match section.model {
        FluidModel::PorousFreeStream => run_porous(&mut p, &section)?,
        FluidModel::Incompressible => run_incompressible(&mut p, &section)?,
        FluidModel::Euler => {
            gas_run::lead(&mut p, &section, std::sync::Arc::new(Single)).map_err(|s| s.error)?
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

/// The incompressible Navier–Stokes model on its box of cells: one flow
/// step per window (sub-steps when the coupler asks for them), the flow
/// field written as `fluid.pvd`.
fn run_incompressible(p: &mut Participant, section: &FluidSection) -> Result<u64, Error> {
    let mut flow = flow_from(section).ok_or("[fluid] has no box")?;
    let origin = section.flow_box.map_or([0.0; 3], |b| b.lower);
    let mut bodies = FlowBodies::new(p.scenario(), &mut flow, origin)?;
    let mut canopy = FlowCanopy::new(section, origin);
    let with_canopy = p.is_connected(Field::CanopyPositions);
    let mut loads = vec![0.0; 6 * flow.bodies.len()];
    let mut series = Series::new(p.run_dir(), "fluid");
    let mut steps = 0u64;
    let mut before = flow.u.clone();
    loop {
        match p.next_command()? {
            Command::Initialize => {
                let mut m = flow_monitors(&mut flow, StepReport::default(), f64::NAN);
                m.extend(bodies.monitors(&flow, None));
                if with_canopy {
                    m.push(Monitor::new("mean_pressure_jump", canopy.mean_jump()));
                }
                p.done(m)?
            }
            Command::Output { index, time } => {
                let velocity = flow.cell_velocity();
                let pressure = flow.pressure();
                let g = flow.grid();
                series.write_image(
                    index,
                    time,
                    &Image {
                        origin,
                        spacing: g.h,
                        cells: g.n,
                        cell_data: vec![("velocity", 3, &velocity), ("pressure", 1, &pressure)],
                    },
                )?;
                p.done(Vec::new())?
            }
            Command::Advance(a) => {
                if p.is_connected(Field::BodyStates) {
                    // The bodies where rigid-proc left them at the window's start.
                    let states = p.read_field(Field::BodyStates)?;
                    if let Err(e) = bodies.read(&states, &mut flow) {
                        return Err(fail(p, format!("at t = {} s: {e}", flow.time)));
                    }
                }
                if with_canopy {
                    // The canopy where the structure left it at the window's start.
                    if canopy.needs_triangles() {
                        canopy.set_triangles(&p.read_field(Field::CanopyTriangles)?);
                    }
                    let x = p.read_field(Field::CanopyPositions)?;
                    let v = p.read_field(Field::CanopyVelocities)?;
                    if let Err(e) = canopy.place(&x, &v, &mut flow) {
                        return Err(fail(p, format!("at t = {} s: {e}", flow.time)));
                    }
                }
                before.clone_from(&flow.u);
                let n = a.substeps.max(1);
                let dt = a.dt / n as f64;
                let mut report = StepReport::default();
                for _ in 0..n {
                    match flow.step(dt) {
                        Ok(r) => report = r,
                        Err(e) => {
                            return Err(fail(p, format!("flow step at t = {} s: {e}", flow.time)));
                        }
                    }
                    steps += 1;
                }
                if p.is_connected(Field::BodyLoads) {
                    // rigid-proc reads a load every window, bodies or none.
                    bodies.take_loads(&mut flow, &mut loads);
                    p.write_field(Field::BodyLoads, loads.len(), |out| {
                        out.copy_from_slice(&loads)
                    })?;
                }
                if p.is_connected(Field::CanopyPressure) {
                    let jumps = canopy.jumps(&flow);
                    p.write_field(Field::CanopyPressure, jumps.len(), |out| {
                        out.copy_from_slice(jumps)
                    })?;
                }
                let m = if a.window_end {
                    // How far from steady: max|∂u/∂t| over the window [m/s²].
                    let change = flow.u.max_difference(&before) / a.dt;
                    let mut m = flow_monitors(&mut flow, report, change);
                    m.extend(bodies.monitors(&flow, Some(&loads)));
                    if with_canopy {
                        m.push(Monitor::new("mean_pressure_jump", canopy.mean_jump()));
                    }
                    m
                } else {
                    Vec::new()
                };
                p.done(m)?;
            }
            Command::Stop => break,
            Command::Setup(_) => return Err("unexpected second setup".into()),
        }
    }
    Ok(steps)
}

/// Tells the coupler the run failed with `msg` and gives it back as the
/// error to stop on (the coupler's own error if even telling it failed).
fn fail(p: &mut Participant, msg: String) -> Error {
    match p.fail(msg.clone()) {
        Ok(()) => msg.into(),
        Err(e) => e.into(),
    }
}

fn flow_monitors(flow: &mut Incompressible, r: StepReport, steady_residual: f64) -> Vec<Monitor> {
    let momentum = flow.momentum();
    vec![
        Monitor::new("kinetic_energy", flow.kinetic_energy()),
        Monitor::new("momentum_x", momentum[0]),
        Monitor::new("momentum_y", momentum[1]),
        Monitor::new("momentum_z", momentum[2]),
        Monitor::new("max_divergence", flow.max_divergence()),
        Monitor::new("steady_residual", steady_residual),
        Monitor::new("courant", r.courant),
        Monitor::new("pressure_iterations", r.pressure_iterations as f64),
        Monitor::new("viscous_iterations", r.viscous_iterations as f64),
    ]
}
