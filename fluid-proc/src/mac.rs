//! Velocities on the faces of the staggered (MAC) grid, their divergence in
//! each cell, and the projection of seed 000 eq. (3.19): u^{n+1} = u* − Δt∇φ
//! with ∇·u^{n+1} = 0, φ from A φ = −∇·u*/Δt (`poisson.rs`).
//!
//! The x-velocities sit on the n_x + 1 faces normal to x of every row of
//! cells, and so on. On a periodic axis faces 0 and n are one face, kept
//! equal. The gradient is the negative adjoint of the divergence with the
//! same sides as the Laplacian (a Neumann side leaves its given face
//! velocity alone, a Dirichlet side sees φ = 0 on the face), so the projected
//! field is discretely divergence-free to the tolerance of the solve.

use crate::grid::{Bc, Grid};
use crate::poisson::{Poisson, SolveError};

/// Face velocities [m/s]: `u[d]` on the faces normal to axis d.
#[derive(Debug, Clone, PartialEq)]
pub struct Faces {
    pub n: [usize; 3],
    pub u: [Vec<f64>; 3],
}

impl Faces {
    pub fn zeros(g: &Grid) -> Faces {
        let n = g.n;
        let count = |d: usize| {
            let mut m = n;
            m[d] += 1;
            m[0] * m[1] * m[2]
        };
        Faces {
            n,
            u: [
                vec![0.0; count(0)],
                vec![0.0; count(1)],
                vec![0.0; count(2)],
            ],
        }
    }

    /// Index of face `f` (face f[d] along d, cell rows elsewhere) normal to d.
    pub fn index(&self, d: usize, f: [usize; 3]) -> usize {
        let mut m = self.n;
        m[d] += 1;
        f[0] + m[0] * (f[1] + m[1] * f[2])
    }

    /// The face normal to d below (`up = false`) or above cell `c`.
    pub fn of_cell(&self, d: usize, c: [usize; 3], up: bool) -> usize {
        let mut f = c;
        f[d] += up as usize;
        self.index(d, f)
    }

    /// Largest face speed [m/s].
    pub fn max_abs(&self) -> f64 {
        self.u.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// div[c] = Σ_d (u_d above − u_d below)/h_d [1/s].
pub fn divergence(g: &Grid, u: &Faces, div: &mut [f64]) {
    for (i, out) in div.iter_mut().enumerate() {
        let c = g.coords(i);
        *out = (0..3)
            .map(|d| (u.u[d][u.of_cell(d, c, true)] - u.u[d][u.of_cell(d, c, false)]) / g.h[d])
            .sum();
    }
}

/// Project `u` (u* on entry) onto divergence-free fields: solve for φ
/// (starting from its previous value, which `phi` holds) and set
/// u ← u − Δt∇φ. Returns the solver's iterations.
pub fn project(
    g: &Grid,
    poisson: &mut Poisson,
    u: &mut Faces,
    dt: f64,
    phi: &mut [f64],
    scratch: &mut [f64],
) -> Result<usize, SolveError> {
    divergence(g, u, scratch);
    scratch.iter_mut().for_each(|v| *v *= -1.0 / dt);
    let iterations = poisson.solve(scratch, phi)?;
    for d in 0..3 {
        let n = g.n[d];
        let h = g.h[d];
        let periodic = g.bc[d][0] == Bc::Periodic;
        for f in 0..u.u[d].len() {
            let face = face_coords(u, d, f);
            let k = face[d];
            let cell = |along: usize| {
                let mut c = face;
                c[d] = along;
                phi[g.index(c)]
            };
            let grad = if k > 0 && k < n {
                (cell(k) - cell(k - 1)) / h
            } else if periodic {
                (cell(0) - cell(n - 1)) / h
            } else {
                let side = g.bc[d][(k == n) as usize];
                match (side, k == n) {
                    (Bc::Dirichlet, false) => 2.0 * cell(0) / h,
                    (Bc::Dirichlet, true) => -2.0 * cell(n - 1) / h,
                    _ => 0.0,
                }
            };
            u.u[d][f] -= dt * grad;
        }
    }
    Ok(iterations)
}

/// The (face along d, cell rows elsewhere) coordinates of face `f` normal to d.
fn face_coords(u: &Faces, d: usize, mut f: usize) -> [usize; 3] {
    let mut m = u.n;
    m[d] += 1;
    let x = f % m[0];
    f /= m[0];
    [x, f % m[1], f / m[1]]
}
