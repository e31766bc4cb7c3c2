//! Preconditioned conjugate gradients for the symmetric positive definite
//! systems of the implicit schemes, applied matrix-free.

#[derive(Default)]
pub struct Cg {
    /// Whether the last solve met its tolerance.
    pub converged: bool,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}

impl Cg {
    /// Solve A·y = rhs from y = 0 until ‖r‖ ≤ tol·‖rhs‖ or `max_iterations`.
    /// `precond[i]` approximates 1/A_ii. Returns the iterations used; stops
    /// early, with the best y so far, if A shows a non-positive curvature.
    pub fn solve(
        &mut self,
        apply: impl FnMut(&[f64], &mut [f64]),
        rhs: &[f64],
        precond: &[f64],
        y: &mut [f64],
        tol: f64,
        max_iterations: u32,
    ) -> u32 {
        let diagonal = |r: &[f64], z: &mut [f64]| {
            for i in 0..r.len() {
                z[i] = precond[i] * r[i];
            }
        };
        self.solve_with(apply, rhs, diagonal, y, tol, max_iterations)
    }

    /// [`Cg::solve`] with any symmetric positive definite preconditioner:
    /// `precondition(r, z)` sets z ≈ A⁻¹·r.
    pub fn solve_with(
        &mut self,
        mut apply: impl FnMut(&[f64], &mut [f64]),
        rhs: &[f64],
        mut precondition: impl FnMut(&[f64], &mut [f64]),
        y: &mut [f64],
        tol: f64,
        max_iterations: u32,
    ) -> u32 {
        let n = rhs.len();
        for b in [&mut self.r, &mut self.z, &mut self.p, &mut self.q] {
            b.resize(n, 0.0);
        }
        y.fill(0.0);
        self.converged = false;
        self.r.copy_from_slice(rhs);
        let stop = tol * dot(rhs, rhs).sqrt();
        precondition(&self.r, &mut self.z);
        self.p.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        for it in 0..max_iterations {
            if dot(&self.r, &self.r).sqrt() <= stop {
                self.converged = true;
                return it;
            }
            apply(&self.p, &mut self.q);
            let curvature = dot(&self.p, &self.q);
            if !(curvature > 0.0) {
                return it;
            }
            let alpha = rz / curvature;
            for i in 0..n {
                y[i] += alpha * self.p[i];
                self.r[i] -= alpha * self.q[i];
            }
            precondition(&self.r, &mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for i in 0..n {
                self.p[i] = self.z[i] + beta * self.p[i];
            }
        }
        max_iterations
    }
}
