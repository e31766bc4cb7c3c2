//! The pressure Poisson solve A φ = b: conjugate gradients preconditioned by
//! a multigrid V-cycle (`multigrid.rs`). With no Dirichlet side A is singular
//! and b must have zero mean (the boundary fluxes balance); the solve then
//! works mean-free and returns the mean-free φ.

use crate::grid::Grid;
use crate::multigrid::{remove_mean, Multigrid};

#[derive(Debug, thiserror::Error)]
pub enum SolveError {
    #[error("the pressure solve did not reach a relative residual of {tolerance:e} in {iterations} iterations (reached {reached:e})")]
    NotConverged {
        tolerance: f64,
        iterations: usize,
        reached: f64,
    },
    #[error("the pressure solve met a non-finite value")]
    NonFinite,
}

pub struct Poisson {
    pub grid: Grid,
    mg: Multigrid,
    /// Stop when ‖b − Aφ‖ ≤ tolerance·max(‖b‖, ‖b − Aφ₀‖).
    pub tolerance: f64,
    pub max_iterations: usize,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

impl Poisson {
    pub fn new(grid: &Grid, tolerance: f64) -> Poisson {
        let n = grid.cells();
        Poisson {
            grid: grid.clone(),
            mg: Multigrid::new(grid),
            tolerance,
            max_iterations: 500,
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// out = A x.
    pub fn apply(&self, x: &[f64], out: &mut [f64]) {
        self.mg.stencil().apply(x, out);
    }

    pub fn levels(&self) -> usize {
        self.mg.depth()
    }

    /// Solve A φ = b from the guess in `phi`; returns the iterations taken.
    pub fn solve(&mut self, b: &[f64], phi: &mut [f64]) -> Result<usize, SolveError> {
        let singular = !self.grid.has_dirichlet();
        self.mg.stencil().apply(phi, &mut self.r);
        for (r, bi) in self.r.iter_mut().zip(b) {
            *r = bi - *r;
        }
        if singular {
            remove_mean(&mut self.r);
        }
        // ‖b‖, of its mean-free part when A is singular: Σb² − N·mean².
        let mean = if singular {
            b.iter().sum::<f64>() / b.len() as f64
        } else {
            0.0
        };
        let norm_b = (dot(b, b) - b.len() as f64 * mean * mean).max(0.0).sqrt();
        let mut res = dot(&self.r, &self.r).sqrt();
        // Relative to the larger of b and the first residual: a guess far
        // from a tiny b (a field already nearly solenoidal) still stops.
        let scale = norm_b.max(res);
        let goal = self.tolerance * scale;
        if res <= goal || scale == 0.0 {
            return Ok(0);
        }
        self.mg.precondition(&self.r, &mut self.z);
        self.p.copy_from_slice(&self.z);
        let mut rz = dot(&self.r, &self.z);
        for it in 1..=self.max_iterations {
            self.mg.stencil().apply(&self.p, &mut self.q);
            let alpha = rz / dot(&self.p, &self.q);
            if !alpha.is_finite() {
                return Err(SolveError::NonFinite);
            }
            for ((x, r), (p, q)) in phi
                .iter_mut()
                .zip(&mut self.r)
                .zip(self.p.iter().zip(&self.q))
            {
                *x += alpha * p;
                *r -= alpha * q;
            }
            res = dot(&self.r, &self.r).sqrt();
            if res <= goal {
                if singular {
                    remove_mean(phi);
                }
                return Ok(it);
            }
            self.mg.precondition(&self.r, &mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            for (p, z) in self.p.iter_mut().zip(&self.z) {
                *p = z + beta * *p;
            }
        }
        Err(SolveError::NotConverged {
            tolerance: self.tolerance,
            iterations: self.max_iterations,
            reached: res / scale,
        })
    }
}

fn dot(a: &[f64], b: &[f64]) -> f64 {
    a.iter().zip(b).map(|(x, y)| x * y).sum()
}
