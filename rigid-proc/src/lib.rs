//! rigid-proc: bodies that carry payloads and hold strings. This first version
//! moves each body as a point mass at its centre of mass; rotation (seed 000
//! §2.1, Euler's equations) comes with the rigid-body solver.

pub mod body;

pub use body::{Bodies, Body};
