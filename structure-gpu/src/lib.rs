//! The structure's spring solver on a GPU, through wgpu compute shaders
//! (dissertation chapter 5, which ran its spring solver on CUDA).
//!
//! A solver hands its network over once ([`Network`]: masses, springs,
//! strings, dampers, gravity as plain arrays), sets the state
//! ([`Solver::upload`]), advances it on the device by any number of steps
//! of an explicit [`Scheme`] ([`Solver::advance`]) and reads it back when
//! it needs it ([`Solver::download`]): the state stays on the device
//! between windows. The arithmetic is the CPU path's, pass for pass
//! (structure-proc's `forces/assembly.rs` and `integrators/`), in f64
//! where the adapter has it ([`Precision`]).
//!
//! ```no_run
//! use structure_gpu::{Gpu, Network, Scheme, Solver, Spring};
//! let gpu = Gpu::new()?;
//! let net = Network {
//!     mass: vec![0.0, 1.0],
//!     inv_mass: vec![0.0, 1.0],
//!     gravity: [0.0, 0.0, -9.81],
//!     springs: vec![Spring { i: 0, j: 1, k: 100.0, rest: 1.0, tension_only: false, eps: 0.0 }],
//!     ..Default::default()
//! };
//! let mut solver = Solver::new(&gpu, &net, Scheme::Rk4)?;
//! let (mut x, mut v) = (vec![0.0, 0.0, 0.0, 0.0, 0.0, -1.0], vec![0.0; 6]);
//! solver.upload(&x, &v);
//! solver.advance(1e-3, 1000)?;
//! solver.download(&mut x, &mut v)?;
//! # Ok::<(), structure_gpu::GpuError>(())
//! ```

mod network;
mod program;
mod solver;

pub use gpu_device::{Gpu, GpuError, Precision};
pub use network::{Damper, DampingLaw, Membrane, Network, Spring};
pub use program::Scheme;
pub use solver::Solver;
