//! The projection of dissertation eq. (3.19): u^{n+1} = u* − Δt∇φ with
//! ∇·u^{n+1} = 0, φ from A φ = −∇·u*/Δt (`poisson.rs`), on the faces of
//! the staggered grid (`faces.rs`).
//!
//! The gradient is the negative adjoint of the divergence with the same
//! sides as the Laplacian (a Neumann side leaves its given face velocity
//! alone, a Dirichlet side sees φ = 0 on the face), so the projected field
//! is discretely divergence-free to the tolerance of the solve. On a rank's
//! slab (`part.rs`) φ beyond a side toward another rank comes from its
//! halo planes.

use crate::incompressible::faces::{divergence, face_counts, Faces};
use crate::incompressible::grid::{Bc, Grid};
use crate::incompressible::part::Halo;
use crate::incompressible::poisson::{Poisson, SolveError};
use crate::incompressible::rows;

/// Calls `f(&mut out[face], ∂φ/∂x_d)` for every face normal to d
/// (`gradient` on the sides, a plain difference inside), rows of faces
/// along x on the pool's threads.
pub fn gradients(
    g: &Grid,
    phi: &[f64],
    halo: &Halo,
    d: usize,
    out: &mut [f64],
    f: impl Fn(&mut f64, f64) + Sync,
) {
    let n = g.n;
    let m = face_counts(n, d);
    let stride = [1, n[0], n[0] * n[1]][d];
    // 1/g per face along d (`axis.rs`: 1/h on a uniform axis).
    let inv_gap: Vec<f64> = (0..=n[d])
        .map(|f| 1.0 / g.axes[d].gap(f as isize))
        .collect();
    rows::each_plain(out, m, |j, k, row| {
        for (i, o) in row.iter_mut().enumerate() {
            let c = [i, j, k];
            let grad = if c[d] > 0 && c[d] < n[d] {
                let cell = i + n[0] * (j + n[1] * k);
                (phi[cell] - phi[cell - stride]) * inv_gap[c[d]]
            } else {
                gradient(g, phi, halo, d, c)
            };
            f(o, grad);
        }
    });
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
            gradients(g, phi, halo, d, u, |u, grad| *u -= dt * grad);
        }
    }
    Ok(iterations)
}

/// ∂φ/∂x_d on face `face` normal to d (face along d, cell rows elsewhere):
/// the difference of the two cells beside it over the face's gap; across a
/// periodic side the cells at both ends; on a Dirichlet side φ = 0 on the
/// face, half a cell from the cell; on a Neumann side zero, so the given
/// velocity stays; toward another rank, its cell in the halo plane.
pub fn gradient(g: &Grid, phi: &[f64], halo: &Halo, d: usize, face: [usize; 3]) -> f64 {
    let n = g.n[d];
    let k = face[d];
    let (axis, ki) = (&g.axes[d], face[d] as isize);
    let h = axis.gap(ki);
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
        Bc::Dirichlet if k == 0 => 2.0 * cell(0) / axis.width(0),
        Bc::Dirichlet => -2.0 * cell(n - 1) / axis.width(ki - 1),
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
