//! The pressure Poisson solve of the projection (dissertation eq. 3.19): second
//! order against an exact solution, and an iteration count that stays flat
//! as the grid is refined (multigrid-preconditioned conjugate gradients).

use fluid_proc::incompressible::grid::{Bc, Grid};
use fluid_proc::incompressible::poisson::Poisson;
use std::f64::consts::PI;

/// A unit box of n cells per axis (nz = 1 for 2-D, periodic in z).
fn unit_box(n: usize, dims: usize, bc: [[Bc; 2]; 2]) -> Grid {
    let nz = if dims == 2 { 1 } else { n };
    let z = if dims == 2 { [Bc::Periodic; 2] } else { bc[1] };
    Grid::uniform([n, n, nz], [1.0 / n as f64; 3], [bc[0], bc[1], z])
}

fn centre(g: &Grid, i: usize) -> [f64; 3] {
    let c = g.coords(i);
    [0, 1, 2].map(|d| (c[d] as f64 + 0.5) * g.h[d])
}

/// Max error of the discrete solution of −∇²φ = f against the exact φ.
fn error(
    n: usize,
    dims: usize,
    bc: [[Bc; 2]; 2],
    exact: &impl Fn([f64; 3]) -> f64,
    f: &impl Fn([f64; 3]) -> f64,
) -> (f64, usize) {
    let g = unit_box(n, dims, bc);
    let b: Vec<f64> = (0..g.cells()).map(|i| f(centre(&g, i))).collect();
    let mut phi = vec![0.0; g.cells()];
    let mut p = Poisson::new(&g, 1e-12);
    let it = p.solve(&b, &mut phi).unwrap();
    let mut shift = 0.0;
    if !g.has_dirichlet() {
        // Defined up to a constant: compare mean-free.
        let m: f64 = (0..g.cells()).map(|i| exact(centre(&g, i))).sum::<f64>() / g.cells() as f64;
        shift = m;
    }
    let err = (0..g.cells())
        .map(|i| (phi[i] + shift - exact(centre(&g, i))).abs())
        .fold(0.0, f64::max);
    (err, it)
}

/// The two sets of sides the flow scenes use: a closed box (the cavity) and
/// the C-9 set-up of dissertation §4.2.1 (periodic sides, given inflow below,
/// p = 0 at the top outflow).
const WALLS: [[Bc; 2]; 2] = [[Bc::Neumann; 2], [Bc::Neumann; 2]];
const C9: [[Bc; 2]; 2] = [[Bc::Periodic; 2], [Bc::Neumann, Bc::Dirichlet]];

/// φ fitting each set of sides, and −∇²φ. In 3-D, z has the sides of y.
fn solution(bc: [[Bc; 2]; 2], dims: usize) -> (impl Fn([f64; 3]) -> f64, impl Fn([f64; 3]) -> f64) {
    // Walls: cos(πx)cos(πy)(cos(πz)); C-9: cos(2πx)cos(πy/2)(cos(πz/2)).
    let k = if bc == WALLS {
        [PI, PI, PI]
    } else {
        [2.0 * PI, PI / 2.0, PI / 2.0]
    };
    let used = if dims == 2 { 2 } else { 3 };
    let exact = move |x: [f64; 3]| (0..used).map(|d| (k[d] * x[d]).cos()).product::<f64>();
    let k2: f64 = k[..used].iter().map(|k| k * k).sum();
    (exact, move |x: [f64; 3]| k2 * exact(x))
}

#[test]
fn the_solve_converges_at_second_order_in_a_flat_number_of_iterations() {
    // The 7-point stencil is second order: the error falls 4-fold per
    // halving of h (ratio above 3.8 here). Multigrid-preconditioned CG to a
    // relative residual of 1e-12 takes the same number of iterations on
    // every grid (at most one more on the finest than on the coarsest), so
    // the solve costs O(cells).
    for bc in [WALLS, C9] {
        for dims in [2, 3] {
            let sizes: &[usize] = if dims == 2 {
                &[32, 64, 128, 256]
            } else {
                &[16, 32, 64]
            };
            let (exact, f) = solution(bc, dims);
            let runs: Vec<(f64, usize)> = sizes
                .iter()
                .map(|&n| error(n, dims, bc, &exact, &f))
                .collect();
            for w in runs.windows(2) {
                let ratio = w[0].0 / w[1].0;
                assert!(
                    ratio > 3.8 && ratio < 4.2,
                    "{bc:?} {dims}-D: error ratio {ratio} in {runs:?}"
                );
            }
            let (first, last) = (runs[0].1, runs[runs.len() - 1].1);
            assert!(
                last <= first + 1 && last <= 15,
                "{bc:?} {dims}-D: iterations {runs:?}"
            );
        }
    }
}
