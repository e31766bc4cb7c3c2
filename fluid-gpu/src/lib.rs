//! The incompressible flow's step on a GPU, through wgpu compute shaders:
//! the projection method of dissertation §3.2.2 as fluid-proc's
//! `incompressible` module runs it on the CPU, pass for pass (WENO5
//! advection with Adams–Bashforth, the Crank–Nicolson viscous solves by
//! conjugate gradients, the multigrid-preconditioned pressure solve, the
//! pressure update), in f64 where the adapter has it.
//!
//! A solver hands it its box once ([`FlowBox`]), sets the state
//! ([`Flow::upload`]), steps it on the device ([`Flow::step`]) and reads it
//! back when it needs it ([`Flow::download`]): the state stays on the
//! device between steps, and a solve's iterations run there too, its sums
//! and flags in a buffer of scalars, the host reading back only the flags.
//!
//! It covers a uniform box on one rank, every kind of side, the box
//! moving with the parachute ([`Moving`]), and bodies and the canopy in the
//! flow ([`Flow::set_markers`]: Peskin's δ, spread race-free by colouring,
//! `markers.rs`); under implicit coupling a window's start and its first
//! prediction stay on the device (`window.rs`). A graded box and several
//! ranks stay on the CPU for now (fluid-section's check refuses them with
//! `device = "gpu"`).
//!
//! The files: `flow.rs` (the solver and its step), `state.rs` (what
//! crosses to the host), `window.rs`, `markers.rs`, `plan.rs` and `pass.rs`
//! (the step's dispatches), `memory.rs` (where each array and scalar
//! lies), `kernels.rs` (the WGSL, its bindings and pipelines), `spec.rs`
//! (the box); the kernels in `flow.wgsl` (bindings, layouts, sides),
//! `advection.wgsl`, `solve.wgsl`, `projection.wgsl`, `forcing.wgsl`.

mod flow;
mod kernels;
mod markers;
mod memory;
mod pass;
mod plan;
mod spec;
mod state;
mod vcycle;
mod window;

pub use flow::{given, Flow, FlowError, Monitors, Moving, Report, TOLERANCE, TOLERANCE_F32};
pub use gpu_device::{Gpu, GpuError, Precision};
pub use markers::{Law, Marker};
pub use spec::{FlowBox, Side, GHOSTS};
pub use state::History;
