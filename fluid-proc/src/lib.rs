//! fluid-proc: the flow models that load the canopy. For now the porous
//! free-stream model of seed 003 §2.1, whose law lives in the `porous` crate
//! (structure solvers apply the same law with `[structure.porous]`); the
//! physics never touches IPC.

pub use porous::Porous;

/// Triangles from the flat index field the structure sends once.
pub fn triangles_from_field(field: &[f64]) -> Vec<[usize; 3]> {
    field
        .chunks_exact(3)
        .map(|t| [t[0] as usize, t[1] as usize, t[2] as usize])
        .collect()
}
