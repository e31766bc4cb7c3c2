//! fluid-proc's driver: joins the run as the fluid participant and runs
//! the scenario's flow model through the schedule (`run.rs`), on one rank
//! or several (`ranks.rs`). The physics never touches IPC; `main.rs` only
//! calls [`run`].

use crate::comm::{Comm, Single};
use crate::euler::run::Walls;
use crate::incompressible::run::Interface;
use crate::porous::Jumps;
use crate::ranks::{self, Stopped};
use exchange::fields::{
    BODY_LOADS, BODY_STATES, CANOPY_POSITIONS, CANOPY_PRESSURE, CANOPY_TRIANGLES,
    CANOPY_VELOCITIES, LOAD_LEN,
};
use fluid_section::FluidModel;
use fluid_section::{FluidSection, Scene};
use participant::{Cadence, Declaration, Joining};
use std::sync::Arc;

pub type Error = Box<dyn std::error::Error>;

/// Join the run and run its flow to the end of the schedule; on MPI ranks
/// when the launcher started this program under `mpirun`.
pub fn run() -> Result<(), Error> {
    if participant::ranks() > 1 {
        return ranks::ranks();
    }
    let (joining, scene, _) = connect()?;
    lead(joining, &scene, Arc::new(Single)).map_err(|s| s.error)
}

/// Rank 0 (or the only rank): the scene's model through the schedule.
pub(crate) fn lead(joining: Joining, scene: &Scene, comm: Arc<dyn Comm>) -> Result<(), Stopped> {
    match scene.fluid.model {
        FluidModel::PorousFreeStream => crate::run::lead::<Jumps>(joining, scene, comm),
        FluidModel::Incompressible => crate::run::lead::<Interface>(joining, scene, comm),
        FluidModel::Euler => crate::run::lead::<Walls>(joining, scene, comm),
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
