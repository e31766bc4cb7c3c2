//! fluid-proc: the flow models that load the canopy and the bodies.
//!
//! - The porous free-stream model of seed 003 §2.1, whose law lives in the
//!   `porous` crate (structure solvers apply the same law with
//!   `[structure.porous]`); it is what the scenes run today.
//! - The incompressible solver of seed 000 §3.2.2, being built (issue 6):
//!   the uniform box of cells and its sides (`grid.rs`), the pressure
//!   operator (`laplacian.rs`), its multigrid-preconditioned conjugate
//!   gradient solve (`multigrid.rs`, `poisson.rs`), the projection on the
//!   staggered grid (`mac.rs`) and the WENO5 reconstruction (`weno5.rs`).
//!
//! The physics never touches IPC.

pub mod grid;
pub mod laplacian;
pub mod mac;
pub mod multigrid;
pub mod poisson;
pub mod weno5;

pub use porous::Porous;

/// Triangles from the flat index field the structure sends once.
pub fn triangles_from_field(field: &[f64]) -> Vec<[usize; 3]> {
    field
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .collect()
}
