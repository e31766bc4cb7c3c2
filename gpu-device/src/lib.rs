//! What every wgpu solver of canopy shares: the adapter and its device
//! ([`Gpu`]), the precision its kernels run in ([`Precision`]: f64 where
//! the adapter has it), one error type ([`GpuError`]) and the buffer
//! helpers (`buffers.rs`): sizes checked against the adapter's limits,
//! workgroup counts past 65 535, and reading a buffer back; compute
//! pipelines from one WGSL source (`pipelines.rs`).

mod buffers;
mod device;
mod pipelines;

pub use buffers::{binding_limit, buffer, check_size, non_empty, read_back, workgroups};
pub use device::{Gpu, GpuError, Precision, REQUIRE_GPU};
pub use pipelines::pipelines;
