//! The nonlinear solve shared by the implicit schemes (Newmark, HHT-α, backward
//! Euler): find the end-of-step acceleration a with
//!   M·a = w·F(x̂ + b·a, v̂ + g·a) + e,
//! where x̂, v̂ are the scheme's predictors. Newton's method linearises it to
//!   (M + w·(b·K + g·C))·Δa = w·F + e − M·a,
//! K = −∂F/∂x, C = −∂F/∂v, and conjugate gradients solve that sparse symmetric
//! system matrix-free, in the manner of Baraff & Witkin (SIGGRAPH 1998).

use super::cg::Cg;
use super::cholesky::Cholesky;
use super::multigrid::Multigrid;
use super::{NewtonParams, StepError, System};
use structure_section::LinearSolver;

/// One scheme's equation for a.
pub struct Target<'a> {
    pub xhat: &'a [f64],
    pub vhat: &'a [f64],
    pub b: f64,
    pub g: f64,
    pub w: f64,
    /// e, when the scheme has one (HHT's −α·F_n).
    pub extra: Option<&'a [f64]>,
}

#[derive(Default)]
pub struct Newton {
    pub params: NewtonParams,
    /// Force at the converged state.
    pub f: Vec<f64>,
    /// Converged positions x̂ + b·a and velocities v̂ + g·a.
    pub x: Vec<f64>,
    pub v: Vec<f64>,
    rhs: Vec<f64>,
    da: Vec<f64>,
    precond: Vec<f64>,
    /// Axial stiffness on each dof's diagonal, for the preconditioner.
    diag: Vec<f64>,
    cg: Cg,
    cholesky: Cholesky,
    multigrid: Multigrid,
    /// Linear solves so far and the seconds they took, for the benches.
    pub solves: (u64, f64),
}

/// Length of the bounding-box diagonal of the points in `x`.
pub fn extent(x: &[f64]) -> f64 {
    let mut lo = [f64::INFINITY; 3];
    let mut hi = [f64::NEG_INFINITY; 3];
    for p in x.chunks_exact(3) {
        for c in 0..3 {
            lo[c] = lo[c].min(p[c]);
            hi[c] = hi[c].max(p[c]);
        }
    }
    (0..3).map(|c| (hi[c] - lo[c]).powi(2)).sum::<f64>().sqrt()
}

impl Newton {
    pub fn new(params: NewtonParams) -> Newton {
        Newton {
            params,
            ..Default::default()
        }
    }

    /// Solve for `a` (in: initial guess; held dofs stay 0). Converged when the
    /// position change a correction implies, max(b, g·h)·‖Δa‖∞, falls below
    /// `tolerance` times the extent of the structure.
    pub fn solve(
        &mut self,
        sys: &dyn System,
        h: f64,
        t: &Target,
        a: &mut [f64],
    ) -> Result<(), StepError> {
        let n = a.len();
        for buf in [
            &mut self.f,
            &mut self.x,
            &mut self.v,
            &mut self.rhs,
            &mut self.da,
            &mut self.precond,
        ] {
            buf.resize(n, 0.0);
        }
        self.precondition(sys, t, a);
        let tolerance = self.params.tolerance * extent(t.xhat).max(f64::MIN_POSITIVE);
        let lever = t.b.max(t.g * h);
        let mut correction = f64::INFINITY;
        for iteration in 0..=self.params.max_iterations {
            for d in 0..n {
                self.x[d] = t.xhat[d] + t.b * a[d];
                self.v[d] = t.vhat[d] + t.g * a[d];
            }
            sys.force(&self.x, &self.v, &mut self.f);
            if iteration > 0 && correction <= tolerance {
                return Ok(());
            }
            if iteration == self.params.max_iterations {
                break;
            }
            self.residual(sys, t, a)?;
            let start = std::time::Instant::now();
            correction = lever * self.correct(sys, t, a);
            self.solves.0 += 1;
            self.solves.1 += start.elapsed().as_secs_f64();
            if !correction.is_finite() {
                return Err(StepError::NonFinite);
            }
        }
        Err(StepError::NoConvergence {
            iterations: self.params.max_iterations,
            correction,
        })
    }

    /// Jacobi preconditioner: 1/(M + w·b·K)_dd, with K's diagonal taken from
    /// the axial stiffness of every coupling along its current direction e,
    /// k·e_c² (geometric and damping terms left out). With M alone, conjugate
    /// gradients need about ω_max·Δt iterations once the stiffness dominates
    /// (ω_max·Δt ≫ 1); per direction, the in-plane stiffness of a flat
    /// membrane does not also weigh on its soft out-of-plane motion. Nodes
    /// the step does not accelerate get a = 0.
    fn precondition(&mut self, sys: &dyn System, t: &Target, a: &mut [f64]) {
        let (n, inv_mass) = (a.len(), sys.inv_mass());
        self.diag.clear();
        self.diag.resize(n, 0.0);
        for &(i, j, k) in sys.couplings() {
            let d: [f64; 3] = std::array::from_fn(|c| t.xhat[3 * j + c] - t.xhat[3 * i + c]);
            let l2 = d[0] * d[0] + d[1] * d[1] + d[2] * d[2];
            if l2 > 0.0 {
                for c in 0..3 {
                    let kc = k * d[c] * d[c] / l2;
                    self.diag[3 * i + c] += kc;
                    self.diag[3 * j + c] += kc;
                }
            }
        }
        for d in 0..n {
            let w = inv_mass[d / 3];
            self.precond[d] = if w == 0.0 {
                0.0
            } else {
                1.0 / (1.0 / w + t.w * t.b * self.diag[d])
            };
            if w == 0.0 {
                a[d] = 0.0;
            }
        }
    }

    /// The Newton residual at the current iterate, w·F + extra − M·a, into
    /// `rhs` (0 on nodes the step does not accelerate).
    fn residual(&mut self, sys: &dyn System, t: &Target, a: &[f64]) -> Result<(), StepError> {
        let inv_mass = sys.inv_mass();
        for (d, r) in self.rhs.iter_mut().enumerate() {
            let w = inv_mass[d / 3];
            *r = if w == 0.0 {
                0.0
            } else {
                t.w * self.f[d] + t.extra.map_or(0.0, |e| e[d]) - a[d] / w
            };
        }
        if self.rhs.iter().any(|r| !r.is_finite()) {
            return Err(StepError::NonFinite);
        }
        Ok(())
    }

    /// Solves (M + w·b·K + w·g·C)·Δa = residual (by conjugate gradients
    /// preconditioned with the diagonal, a Cholesky factorization or
    /// multigrid: `linear_solver`), adds Δa to `a`, and returns the largest |Δa|.
    fn correct(&mut self, sys: &dyn System, t: &Target, a: &mut [f64]) -> f64 {
        let n = a.len();
        let (kb, kg) = (t.w * t.b, t.w * t.g);
        let tol = self.params.cg_tolerance;
        let solved = {
            let (x, v) = (&self.x, &self.v);
            let apply = operator(sys, x, v, kb, kg);
            match self.params.linear_solver {
                LinearSolver::Cg => false,
                LinearSolver::Cholesky => {
                    self.cholesky
                        .solve(sys, x, v, (kb, kg), apply, &self.rhs, &mut self.da, tol)
                }
                LinearSolver::Multigrid => {
                    let limit = self.params.max_cg_iterations;
                    let (rhs, da) = (&self.rhs, &mut self.da);
                    self.multigrid
                        .solve(sys, x, v, (kb, kg), apply, rhs, da, tol, limit)
                }
            }
        };
        if !solved {
            self.iterative(sys, kb, kg);
        }
        let mut largest = 0.0f64;
        for d in 0..n {
            a[d] += self.da[d];
            largest = largest.max(self.da[d].abs());
        }
        largest
    }

    /// da ← the conjugate-gradient solution of the Newton system.
    fn iterative(&mut self, sys: &dyn System, kb: f64, kg: f64) {
        self.cg.solve(
            operator(sys, &self.x, &self.v, kb, kg),
            &self.rhs,
            &self.precond,
            &mut self.da,
            self.params.cg_tolerance,
            self.params.max_cg_iterations,
        );
    }
}

/// p ↦ (M + kb·K + kg·C)·p at (x, v) over the free degrees of freedom, 0
/// on the held ones: the Newton system's matrix.
pub(super) fn operator<'a>(
    sys: &'a dyn System,
    x: &'a [f64],
    v: &'a [f64],
    kb: f64,
    kg: f64,
) -> impl FnMut(&[f64], &mut [f64]) + 'a {
    let inv_mass = sys.inv_mass();
    move |p, out| {
        sys.jacobian_product(x, v, kb, kg, p, out);
        for (d, o) in out.iter_mut().enumerate() {
            let w = inv_mass[d / 3];
            *o = if w == 0.0 { 0.0 } else { *o + p[d] / w };
        }
    }
}
