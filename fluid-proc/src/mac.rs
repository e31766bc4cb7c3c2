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
//!
//! On a rank's slab (`part.rs`) the grid is the slab's, and φ beyond a
//! side toward another rank comes from its halo planes.

use crate::grid::{Bc, Grid};
use crate::part::Halo;
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

    /// Largest difference of a face velocity from `other`'s [m/s].
    pub fn max_difference(&self, other: &Faces) -> f64 {
        self.u
            .iter()
            .zip(&other.u)
            .flat_map(|(a, b)| a.iter().zip(b))
            .fold(0.0, |m, (a, b)| m.max((a - b).abs()))
    }

    /// Largest face speed [m/s].
    pub fn max_abs(&self) -> f64 {
        self.u.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// Calls `f(cell, below, up)` for every cell in index order: `below[d]` is
/// the index of the cell's face normal to d on its low side, and
/// `below[d] + up[d]` the one on its high side.
pub fn for_each_cell_faces(n: [usize; 3], mut f: impl FnMut(usize, [usize; 3], [usize; 3])) {
    let m = [0, 1, 2].map(|d| face_counts(n, d));
    let up = [0, 1, 2].map(|d| [1, m[d][0], m[d][0] * m[d][1]][d]);
    let mut cell = 0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            let row = [0, 1, 2].map(|d| m[d][0] * (j + m[d][1] * k));
            for i in 0..n[0] {
                f(cell, row.map(|r| r + i), up);
                cell += 1;
            }
        }
    }
}

/// div[c] = Σ_d (u_d above − u_d below)/h_d [1/s].
pub fn divergence(g: &Grid, u: &Faces, div: &mut [f64]) {
    let inv_h = g.h.map(|h| 1.0 / h);
    for_each_cell_faces(g.n, |c, below, up| {
        div[c] = (0..3)
            .map(|d| (u.u[d][below[d] + up[d]] - u.u[d][below[d]]) * inv_h[d])
            .sum();
    });
}

/// Faces along each axis of the faces normal to d: n + 1 along d.
fn face_counts(n: [usize; 3], d: usize) -> [usize; 3] {
    let mut m = n;
    m[d] += 1;
    m
}

/// Calls `f(face index, ∂φ/∂x_d)` for every face normal to d, in index
/// order (`gradient` on the sides, a plain difference inside).
pub fn for_each_gradient(
    g: &Grid,
    phi: &[f64],
    halo: &Halo,
    d: usize,
    mut f: impl FnMut(usize, f64),
) {
    let n = g.n;
    let m = face_counts(n, d);
    let stride = [1, n[0], n[0] * n[1]][d];
    let inv_h = 1.0 / g.h[d];
    let mut face = 0;
    for k in 0..m[2] {
        for j in 0..m[1] {
            for i in 0..m[0] {
                let c = [i, j, k];
                let grad = if c[d] > 0 && c[d] < n[d] {
                    let cell = i + n[0] * (j + n[1] * k);
                    (phi[cell] - phi[cell - stride]) * inv_h
                } else {
                    gradient(g, phi, halo, d, c)
                };
                f(face, grad);
                face += 1;
            }
        }
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
    let halo = poisson.halo_of(phi);
    for (d, u) in u.u.iter_mut().enumerate() {
        // Nothing varies along a periodic axis one cell thick.
        if g.n[d] > 1 || g.bc[d][0] != Bc::Periodic {
            for_each_gradient(g, phi, halo, d, |f, grad| u[f] -= dt * grad);
        }
    }
    Ok(iterations)
}

/// ∂φ/∂x_d on face `face` normal to d (face along d, cell rows elsewhere):
/// the difference of the two cells beside it; across a periodic side the
/// cells at both ends; on a Dirichlet side φ = 0 on the face, half a cell
/// from the cell; on a Neumann side zero, so the given velocity stays;
/// toward another rank, its cell in the halo plane.
pub fn gradient(g: &Grid, phi: &[f64], halo: &Halo, d: usize, face: [usize; 3]) -> f64 {
    let n = g.n[d];
    let h = g.h[d];
    let k = face[d];
    let cell = |along: usize| {
        let mut c = face;
        c[d] = along;
        phi[g.index(c)]
    };
    if k > 0 && k < n {
        return (cell(k) - cell(k - 1)) / h;
    }
    match g.bc[d][(k == n) as usize] {
        Bc::Periodic => (cell(0) - cell(n - 1)) / h,
        Bc::Dirichlet if k == 0 => 2.0 * cell(0) / h,
        Bc::Dirichlet => -2.0 * cell(n - 1) / h,
        Bc::Neumann => 0.0,
        Bc::Rank => {
            let mut row = face;
            row[d] = 0;
            let beyond = halo[(k == n) as usize][g.index(row)];
            if k == 0 {
                (cell(0) - beyond) / h
            } else {
                (beyond - cell(n - 1)) / h
            }
        }
    }
}
