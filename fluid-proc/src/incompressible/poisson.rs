//! The pressure Poisson solve A φ = b: conjugate gradients preconditioned by
//! a multigrid V-cycle (`multigrid.rs`). With no Dirichlet side A is singular
//! and b must have zero mean (the boundary fluxes balance); the solve then
//! works mean-free and returns the mean-free φ.
//!
//! On a graded grid A is self-adjoint in the inner product Σ V x y of the
//! cells' volumes (`laplacian.rs`), and the solve takes that one: its
//! dot products, norms and means weigh each cell by its volume.
//!
//! On a rank's slab (`part.rs`) every dot product is summed over the ranks,
//! so all take the same steps and stop together.

use crate::incompressible::grid::Grid;
use crate::incompressible::multigrid::{mean, remove_mean, Multigrid};
use crate::incompressible::part::{Halo, Part};
use crate::incompressible::rows;

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
    /// The whole box.
    pub grid: Grid,
    pub part: Part,
    /// A cell field's planes beyond the slab (`halo_of`).
    halo: Halo,
    mg: Multigrid,
    /// This rank's cells' volumes on a graded grid.
    volumes: Option<Vec<f64>>,
    /// Stop when ‖b − Aφ‖ ≤ tolerance·max(‖b‖, ‖b − Aφ₀‖).
    pub tolerance: f64,
    pub max_iterations: usize,
    r: Vec<f64>,
    z: Vec<f64>,
    p: Vec<f64>,
    q: Vec<f64>,
}

impl Poisson {
    /// On a whole box, one rank.
    pub fn new(grid: &Grid, tolerance: f64) -> Poisson {
        Poisson::on(
            grid,
            &Part::whole(grid.n, [[crate::incompressible::side::Side::WALL; 2]; 3]),
            tolerance,
        )
    }

    /// On this rank's `part` of the box `grid`.
    pub fn on(grid: &Grid, part: &Part, tolerance: f64) -> Poisson {
        let n = part.slab.cells().iter().product();
        Poisson {
            grid: grid.clone(),
            part: part.clone(),
            halo: Halo::default(),
            mg: Multigrid::on(grid, part),
            volumes: part.local_grid(grid).volumes(),
            tolerance,
            max_iterations: 500,
            r: vec![0.0; n],
            z: vec![0.0; n],
            p: vec![0.0; n],
            q: vec![0.0; n],
        }
    }

    /// out = A x.
    pub fn apply(&mut self, x: &[f64], out: &mut [f64]) {
        self.mg.apply(x, out);
    }

    /// The planes of cell field `x` beyond this rank's slab (empty on one
    /// rank), swapped in from the neighbours.
    pub fn halo_of(&mut self, x: &[f64]) -> &Halo {
        self.part.fill_halo(x, &mut self.halo);
        &self.halo
    }

    pub fn levels(&self) -> usize {
        self.mg.depth()
    }

    /// Solve A φ = b from the guess in `phi`; returns the iterations taken.
    pub fn solve(&mut self, b: &[f64], phi: &mut [f64]) -> Result<usize, SolveError> {
        let singular = !self.grid.has_dirichlet();
        let (part, volumes) = (&self.part, self.volumes.as_deref());
        let dot = |a: &[f64], b: &[f64]| part.sum(dot(a, b, volumes));
        self.mg.apply(phi, &mut self.r);
        rows::for_each(&mut self.r, |r, i| *r = b[i] - *r);
        if singular {
            remove_mean(&mut self.r, part, volumes);
        }
        // ‖b‖, of its mean-free part when A is singular: Σb² − N·mean²
        // (N the box's volume where the cells are weighed by theirs).
        let cells = match volumes {
            None => self.grid.cells() as f64,
            Some(v) => part.sum(v.iter().sum::<f64>()),
        };
        let mean = if singular {
            mean(b, part, volumes)
        } else {
            0.0
        };
        let norm_b = (dot(b, b) - cells * mean * mean).max(0.0).sqrt();
        let mut res = dot(&self.r, &self.r).sqrt();
        // Relative to the larger of b and the first residual: a guess far
        // from a tiny b (a field already nearly solenoidal) still stops.
        let scale = norm_b.max(res);
        let goal = self.tolerance * scale;
        if res <= goal || scale == 0.0 {
            return Ok(0);
        }
        self.mg.precondition(&self.r, &mut self.z);
        rows::copy(&mut self.p, &self.z);
        let mut rz = dot(&self.r, &self.z);
        for it in 1..=self.max_iterations {
            self.mg.apply(&self.p, &mut self.q);
            let alpha = rz / dot(&self.p, &self.q);
            if !alpha.is_finite() {
                return Err(SolveError::NonFinite);
            }
            let (p, q) = (&self.p, &self.q);
            rows::for_each(&mut self.r, |r, i| *r -= alpha * q[i]);
            let r = &self.r;
            let mut step_phi = || rows::for_each(phi, |x, i| *x += alpha * p[i]);
            // On one rank the residual's sum (one thread, `rows.rs`) runs
            // beside φ's update where the grid is worth a second thread;
            // across ranks it is a collective call and comes after it, in
            // the same order on every rank.
            res = match !part.split() && rows::worth_threads(r.len()) {
                true => rayon::join(|| dot(r, r), step_phi).0,
                false => {
                    step_phi();
                    dot(r, r)
                }
            }
            .sqrt();
            if res <= goal {
                if singular {
                    remove_mean(phi, part, volumes);
                }
                return Ok(it);
            }
            self.mg.precondition(&self.r, &mut self.z);
            let rz_new = dot(&self.r, &self.z);
            let beta = rz_new / rz;
            rz = rz_new;
            let z = &self.z;
            rows::for_each(&mut self.p, |p, i| *p = z[i] + beta * *p);
        }
        Err(SolveError::NotConverged {
            tolerance: self.tolerance,
            iterations: self.max_iterations,
            reached: res / scale,
        })
    }
}

/// Σ a b, each term weighed by its cell's volume where given: on one
/// thread, in the cells' order (`rows.rs` says why).
fn dot(a: &[f64], b: &[f64], volumes: Option<&[f64]>) -> f64 {
    match volumes {
        None => a.iter().zip(b).map(|(x, y)| x * y).sum(),
        Some(v) => a.iter().zip(b).zip(v).map(|((x, y), v)| x * y * v).sum(),
    }
}
