//! fluid-proc's driver: joins the run as the fluid participant and runs the
//! scenario's flow model through the schedule, on one rank or several
//! (`ranks.rs`). The porous free-stream model is here; the incompressible
//! flow's loop is `flow_run.rs`, the gas's `gas_run.rs`. The physics never
//! touches IPC; `main.rs` only calls [`run`].

use crate::comm::Single;
use crate::flow_run::{self, fail};
use crate::{check_triangles, gas_run, ranks, triangles_from_field, Porous};
use exchange::fields::{
    BODY_LOADS, BODY_STATES, CANOPY_POSITIONS, CANOPY_PRESSURE, CANOPY_TRIANGLES,
    CANOPY_VELOCITIES, LOAD_LEN,
};
use fluid_section::FluidModel;
use fluid_section::{FluidSection, Scene};
use participant::{Cadence, Command, Declaration, Joining, Monitor, Participant};
use std::sync::Arc;

pub type Error = Box<dyn std::error::Error>;

/// Join the run and run its flow to the end of the schedule; on MPI ranks
/// when the launcher started this program under `mpirun`.
pub fn run() -> Result<(), Error> {
    if participant::ranks() > 1 {
        return ranks::ranks();
    }
    let (joining, scenario, section) = connect()?;
    match section.model {
        FluidModel::PorousFreeStream => run_porous(joining, &scenario, &section),
        FluidModel::Incompressible => {
            flow_run::lead(joining, &scenario, &section, Arc::new(Single)).map_err(|s| s.error)
        }
        FluidModel::Euler => {
            gas_run::lead(joining, &scenario, Arc::new(Single)).map_err(|s| s.error)
        }
    }
}

/// Connects to the coupler; the scenario and its `[fluid]` section.
pub(crate) fn connect() -> Result<(Joining, Scene, FluidSection), Error> {
    let joining = participant::connect()?;
    let scene = Scene::load(joining.scenario_path(), joining.scenario())?;
    let section = scene.fluid.clone();
    Ok((joining, scene, section))
}

/// What a flow exchanges, once a window: the canopy in and its pressure
/// out, the loads on `bodies` bodies out, and their states in when the
/// flow has them in it (`with_bodies`; a read must take every value).
pub(crate) fn declaration(bodies: usize, with_bodies: bool, monitors: Vec<String>) -> Declaration {
    let d = Declaration::new(Cadence::PerWindow { substeps: 1 })
        .writes_items_of(CANOPY_PRESSURE, 1)
        .writes(BODY_LOADS, LOAD_LEN as u32, bodies)
        .reads_if_written(CANOPY_TRIANGLES)
        .reads_if_written(CANOPY_POSITIONS)
        .reads_if_written(CANOPY_VELOCITIES)
        .monitors(monitors)
        .units(crate::units::unit_of)
        .checkpoints();
    match with_bodies {
        true => d.reads_if_written(BODY_STATES),
        false => d,
    }
}

/// The porous free-stream model: a pressure jump per canopy triangle.
fn run_porous(joining: Joining, scenario: &Scene, section: &FluidSection) -> Result<(), Error> {
    let load = section
        .porous_load()
        .ok_or("[fluid] lacks a key of the porous free-stream model")?;
    let model = Porous::new(&load.params());
    let bodies = scenario.rigid.as_ref().map_or(0, |r| r.bodies.len());
    // No flow goes round the bodies here: their states are not read.
    let declared = declaration(bodies, false, vec!["mean_pressure_jump".into()]).restarts();
    let mut p = joining.declare(declared)?;
    let windows = p.reporting(|p| porous_windows(p, &model, bodies))?;
    p.finish(windows)?;
    Ok(())
}

/// The schedule, to its end; the windows taken.
fn porous_windows(p: &mut Participant, model: &Porous, bodies: usize) -> Result<u64, Error> {
    let mut triangles: Option<Vec<[usize; 3]>> = None;
    let mut windows = 0u64;
    loop {
        match p.next_command()? {
            // No pressure exists before the first window; NaN marks it in monitors.csv.
            Command::Initialize => p.done(vec![Monitor::new("mean_pressure_jump", f64::NAN)])?,
            // The jumps depend on the window's inputs alone: nothing to
            // save, to write or to read back (the canopy's triangles come
            // again when a restarted run resumes).
            Command::Output { .. }
            | Command::SaveCheckpoint
            | Command::RestoreCheckpoint
            | Command::WriteCheckpoint { .. }
            | Command::Resume { .. } => p.done(Vec::new())?,
            Command::Advance(_) => {
                let m = porous_window(p, model, bodies, &mut triangles)?;
                windows += 1;
                p.done(m)?;
            }
            Command::Stop => return Ok(windows),
        }
    }
}

/// One window of the porous free-stream model: the jumps on the canopy the
/// structure left at the window's start, and no load on the bodies.
fn porous_window(
    p: &mut Participant,
    model: &Porous,
    bodies: usize,
    triangles: &mut Option<Vec<[usize; 3]>>,
) -> Result<Vec<Monitor>, Error> {
    if p.is_connected(BODY_LOADS) {
        // The porous free-stream model has no flow around bodies, so it
        // exerts no force on them: a body here is what the dissertation
        // (§2.4) calls a mass-point parachutist, outside the flow. The
        // pressure integral of eq. (2.40) comes with a flow field.
        p.write_field(BODY_LOADS, LOAD_LEN * bodies, |out| out.fill(0.0))?;
    }
    if !p.is_connected(CANOPY_POSITIONS) {
        return Ok(Vec::new());
    }
    if triangles.is_none() {
        // Connectivity arrives once, at initialisation.
        *triangles = Some(triangles_from_field(&p.read_field(CANOPY_TRIANGLES)?));
    }
    let tris = triangles.as_deref().unwrap_or(&[]);
    let x = p.read_field(CANOPY_POSITIONS)?;
    if let Err(msg) = check_triangles(tris, x.len() / 3) {
        return Err(fail(p, msg));
    }
    let v = p.read_field(CANOPY_VELOCITIES)?;
    let mut total = 0.0;
    p.write_field(CANOPY_PRESSURE, tris.len(), |out| {
        model.pressure(tris, &x, &v, out);
        total = out.iter().sum::<f64>();
    })?;
    let mean = total / tris.len().max(1) as f64;
    Ok(vec![Monitor::new("mean_pressure_jump", mean)])
}
