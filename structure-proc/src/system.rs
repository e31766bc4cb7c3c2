//! What a time integrator needs from the mechanical system it advances.
//!
//! The integrators of [`crate::integrators`] see only this trait, so one
//! implementation of each scheme serves the canopy, strings, cloth and the
//! reference systems of the tests alike. Data are flat: `x`, `v`, `f` hold
//! three values per node.

pub use crate::forces::jacobian::Block;

pub trait System: Sync {
    fn nodes(&self) -> usize;

    /// 1/m per node; 0 for nodes the integrator must not accelerate: fixed
    /// nodes (v = 0) and nodes carried by a rigid body at constant velocity.
    fn inv_mass(&self) -> &[f64];

    /// f ← F(x, v), the total force on every node.
    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]);

    /// out ← (a·K + b·C)·p with K = −∂F/∂x and C = −∂F/∂v at (x, v). Implicit
    /// schemes solve with it by conjugate gradients, so it must be symmetric and
    /// positive semi-definite; it may approximate the true Jacobian (compressed
    /// springs lose their geometric stiffness), Newton then converges more slowly.
    fn jacobian_product(&self, x: &[f64], v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]);

    /// The matrix of [`System::jacobian_product`] as 3×3 blocks between
    /// nodes into `out`, for solvers that factorize it; `false` (the
    /// default) where the system gives none, and the implicit schemes
    /// solve by conjugate gradients.
    fn jacobian_blocks(&self, x: &[f64], v: &[f64], a: f64, b: f64, out: &mut Vec<Block>) -> bool {
        let _ = (x, v, a, b, out);
        false
    }

    /// Node pairs coupled by a stiffness k_ij [N/m], for Kang's eq. (55).
    fn couplings(&self) -> &[(usize, usize, f64)];
}
