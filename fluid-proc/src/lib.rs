//! fluid-proc: the flow models that load the canopy and the bodies.
//!
//! - The porous free-stream model of thesis §2.1, whose law lives in the
//!   `porous` crate (structure solvers apply the same law with
//!   `[structure.porous]`); it is what the scenes run today.
//! - The incompressible Navier–Stokes solver of dissertation §3.2.2
//!   (`incompressible.rs`, the step of eqs. 3.18–3.20), built from:
//!   - the box of cells and its pressure sides (`grid.rs`) and velocity
//!     sides (`side.rs`), and the scenario's flow (`setup.rs`);
//!   - face velocities with ghost layers that carry the sides (`padded.rs`);
//!   - the WENO5 advection term (`weno5.rs`, `advection.rs`) and the
//!     Crank–Nicolson viscous solve (`viscosity.rs`);
//!   - the pressure operator (`laplacian.rs`), its multigrid-preconditioned
//!     conjugate-gradient solve (`multigrid.rs`, `poisson.rs`) and the
//!     projection (`projection.rs`) of the face velocities on the staggered
//!     grid (`faces.rs`);
//!   - every loop of the step on the pool's threads, the same to the bit
//!     on any number of them (`rows.rs`).
//! - Rigid bodies in that flow: markers on their surfaces (`surface.rs`)
//!   held to the bodies' motion by direct forcing (`immersed.rs`) with
//!   Peskin's 4-point δ (`delta.rs`); the pressure force of eq. 2.40 read
//!   on the fluid's side of their surfaces (`pressure_force.rs`).
//! - The canopy in that flow (`canopy.rs`): an open surface the air slips
//!   along, held to the fabric's normal velocity (or, porous, letting
//!   through what the Darcy–Forchheimer law allows), its pressure jump read
//!   side by side through the local index coating (`coating.rs`).
//! - The compressible Euler solver of dissertation §3.2.1 (`compressible.rs`,
//!   third-order TVD Runge–Kutta): the ideal gas and its characteristic
//!   fields (`gas.rs`), the characteristic WENO5 flux along a line
//!   (`characteristic.rs`), and the exact Riemann solution it is checked
//!   against (`riemann.rs`). Rigid bodies in the gas are moving walls:
//!   ghost cells filled from image points (`gas_bodies.rs`) across the
//!   signed distance to their surfaces (`level_set.rs`), moving as
//!   `body_motion.rs` carries them through a window.
//! - The ranks a solver's box is split among (`comm.rs`; on MPI with the
//!   `mpi` feature, `mpi_comm.rs`), and the incompressible flow's slab of
//!   it on each (`part.rs`).
//!
//! The physics never touches IPC. The driver (`driver.rs`) joins the run
//! through the participant library and runs a model's loop: the porous
//! one there, the incompressible flow's in `flow_run.rs` (the bodies and
//! the canopy it places each window: `flow_bodies.rs`, `flow_canopy.rs`,
//! `clearance.rs`), the gas's (and its bodies') in `gas_run.rs`, and the orders rank 0
//! shares with the other ranks in `ranks.rs`.

pub mod advection;
pub mod body_motion;
pub mod canopy;
pub mod characteristic;
pub mod checkpoint;
pub mod clearance;
pub mod coating;
pub mod comm;
mod component;
pub mod compressible;
pub mod delta;
pub mod driver;
pub mod faces;
pub mod flow_bodies;
pub mod flow_canopy;
pub mod flow_run;
pub mod frame;
pub mod gas;
pub mod gas_bodies;
pub mod gas_run;
pub mod grid;
pub mod immersed;
pub mod incompressible;
pub mod laplacian;
pub mod level_set;
#[cfg(feature = "mpi")]
pub mod mpi_comm;
pub mod multigrid;
pub mod padded;
pub mod part;
pub mod poisson;
pub mod prediction;
pub mod pressure_force;
pub mod probe;
pub mod profile;
pub mod projection;
pub mod rank_checkpoint;
pub mod ranks;
pub mod riemann;
pub mod rows;
pub mod setup;
pub mod side;
pub mod surface;
pub mod units;
pub mod viscosity;
pub mod weno5;

pub use porous::Porous;

/// Triangles from the flat index field the structure sends once.
pub fn triangles_from_field(field: &[f64]) -> Vec<[usize; 3]> {
    field
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .collect()
}

/// An error naming the first triangle with a vertex beyond the `nodes`
/// whose positions were sent.
pub fn check_triangles(triangles: &[[usize; 3]], nodes: usize) -> Result<(), String> {
    match triangles.iter().find(|t| t.iter().any(|&i| i >= nodes)) {
        Some(t) => Err(format!(
            "canopy triangle {t:?} names a vertex beyond the {nodes} sent"
        )),
        None => Ok(()),
    }
}
