//! fluid-proc: the flow models that load the canopy and the bodies, each
//! in a file or folder named after its `[fluid] model`:
//!
//! - `porous.rs`, model = "porous-free-stream": the porous free-stream
//!   model of thesis §2.1, whose law lives in the `porous` crate
//!   (structure solvers apply the same law with `[structure.porous]`).
//! - `incompressible/`, model = "incompressible": the incompressible
//!   Navier–Stokes solver of dissertation §3.2.2 (its `mod.rs` is the step
//!   of eqs. 3.18–3.20 and lists the rest), with rigid bodies and the
//!   canopy immersed in it.
//! - `euler/`, model = "euler": the compressible Euler solver of
//!   dissertation §3.2.1, with rigid bodies as moving walls.
//!
//! What the models share: the one run loop every model goes through
//! (`run.rs`) over what a model does on every rank and what rank 0 reads
//! and answers (`model.rs`); the ranks a box is split among (`comm.rs`;
//! on MPI with the `mpi` feature, `mpi_comm.rs`), the orders rank 0 shares
//! with them (`ranks.rs`) and their run checkpoints
//! (`rank_checkpoint.rs`); the ghost layout of padded arrays
//! (`layout.rs`), the WENO5 reconstruction (`weno5.rs`) and the markers
//! on a body's surface (`surface.rs`); the monitors' units (`units.rs`).
//!
//! The physics never touches IPC. The driver (`driver.rs`) joins the run
//! through the participant library and hands the scenario's model to the
//! run loop.

pub mod comm;
pub mod driver;
pub mod euler;
pub mod incompressible;
pub mod layout;
pub mod model;
#[cfg(feature = "mpi")]
pub mod mpi_comm;
pub mod porous;
pub mod rank_checkpoint;
pub mod ranks;
pub mod run;
pub mod surface;
pub mod units;
pub mod weno5;

pub use ::porous::Porous;

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
