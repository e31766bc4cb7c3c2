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

    /// f ← F(x, v), the same bits as [`System::force`], for a scheme that
    /// evaluates the force again at the same positions with other
    /// velocities (velocity Verlet: the end of a step and the start of the
    /// next): the system may keep what depends on x alone for that call.
    fn force_keeping(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        self.force(x, v, f);
    }

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

/// A system whose every force evaluation is computed afresh: what
/// [`System::force_keeping`] must equal bit for bit, for the tests and the
/// bench (`benches/parachute.rs`) to compare against.
pub struct Afresh<'a, S: System>(pub &'a S);

impl<S: System> System for Afresh<'_, S> {
    fn nodes(&self) -> usize {
        self.0.nodes()
    }

    fn inv_mass(&self) -> &[f64] {
        self.0.inv_mass()
    }

    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        self.0.force(x, v, f);
    }

    fn jacobian_product(&self, x: &[f64], v: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        self.0.jacobian_product(x, v, a, b, p, out);
    }

    fn jacobian_blocks(&self, x: &[f64], v: &[f64], a: f64, b: f64, out: &mut Vec<Block>) -> bool {
        self.0.jacobian_blocks(x, v, a, b, out)
    }

    fn couplings(&self) -> &[(usize, usize, f64)] {
        self.0.couplings()
    }
}
