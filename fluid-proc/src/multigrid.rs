//! Geometric multigrid for A φ = b (`laplacian.rs`): one V-cycle is the
//! preconditioner of the conjugate-gradient solve (`poisson.rs`), which keeps
//! the iteration count flat as the grid is refined, so the pressure solve
//! costs O(cells).
//!
//! Cell-centred coarsening halves every axis that can; restriction averages
//! the children, prolongation copies the parent to them (R = Pᵀ/2^d), and the
//! coarse operators are rediscretised. Symmetric red–black Gauss–Seidel
//! (red then black before the coarse correction, black then red after) keeps
//! the V-cycle symmetric, as conjugate gradients need.

use crate::grid::Grid;
use crate::laplacian::Stencil;

/// Smoothing sweeps before and after the coarse correction.
const SWEEPS: usize = 2;
/// The coarsest level has at most this many cells…
const COARSEST_CELLS: usize = 64;
/// …and is solved by this many symmetric sweeps.
const COARSEST_SWEEPS: usize = 40;

struct Level {
    stencil: Stencil,
    /// Right-hand side, solution and residual of this level's correction.
    b: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    /// Parent cell on the next coarser level.
    parent: Vec<usize>,
    /// Children per coarse cell (2^axes halved).
    children: f64,
}

pub struct Multigrid {
    levels: Vec<Level>,
    /// No Dirichlet side: A is singular and every level works mean-free.
    singular: bool,
}

impl Multigrid {
    pub fn new(fine: &Grid) -> Multigrid {
        let mut grids = vec![fine.clone()];
        while grids.last().unwrap().cells() > COARSEST_CELLS {
            match grids.last().unwrap().coarsened() {
                Some(g) => grids.push(g),
                None => break,
            }
        }
        let levels = grids
            .iter()
            .enumerate()
            .map(|(l, g)| {
                let cells = g.cells();
                let (parent, children) = match grids.get(l + 1) {
                    Some(c) => {
                        let ratio: Vec<usize> = (0..3).map(|d| g.n[d] / c.n[d]).collect();
                        let parent = (0..cells)
                            .map(|i| {
                                let f = g.coords(i);
                                c.index([f[0] / ratio[0], f[1] / ratio[1], f[2] / ratio[2]])
                            })
                            .collect();
                        (parent, ratio.iter().product::<usize>() as f64)
                    }
                    None => (Vec::new(), 1.0),
                };
                Level {
                    stencil: Stencil::new(g),
                    b: vec![0.0; cells],
                    x: vec![0.0; cells],
                    r: vec![0.0; cells],
                    parent,
                    children,
                }
            })
            .collect();
        Multigrid {
            levels,
            singular: !fine.has_dirichlet(),
        }
    }

    /// The finest level's operator.
    pub fn stencil(&self) -> &Stencil {
        &self.levels[0].stencil
    }

    /// Number of levels, the finest included.
    pub fn depth(&self) -> usize {
        self.levels.len()
    }

    /// z = M⁻¹ r: one V-cycle from a zero guess.
    pub fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        self.levels[0].b.copy_from_slice(r);
        self.cycle(0);
        z.copy_from_slice(&self.levels[0].x);
        if self.singular {
            remove_mean(z);
        }
    }

    fn cycle(&mut self, l: usize) {
        let last = l + 1 == self.levels.len();
        let level = &mut self.levels[l];
        level.x.fill(0.0);
        if last {
            for _ in 0..COARSEST_SWEEPS {
                sweep(level, 0);
                sweep(level, 1);
                sweep(level, 1);
                sweep(level, 0);
            }
            if self.singular {
                remove_mean(&mut level.x);
            }
            return;
        }
        for _ in 0..SWEEPS {
            sweep(level, 0);
            sweep(level, 1);
        }
        level.stencil.apply(&level.x, &mut level.r);
        for (r, b) in level.r.iter_mut().zip(&level.b) {
            *r = b - *r;
        }
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&mut fine[l], &mut coarse[0]);
        c.b.fill(0.0);
        for (i, &p) in f.parent.iter().enumerate() {
            c.b[p] += f.r[i] / f.children;
        }
        self.cycle(l + 1);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&mut fine[l], &coarse[0]);
        for (i, &p) in f.parent.iter().enumerate() {
            f.x[i] += c.x[p];
        }
        for _ in 0..SWEEPS {
            sweep(f, 1);
            sweep(f, 0);
        }
    }
}

fn sweep(level: &mut Level, colour: usize) {
    level.stencil.gauss_seidel(&level.b, &mut level.x, colour);
}

pub fn remove_mean(x: &mut [f64]) {
    let mean = x.iter().sum::<f64>() / x.len() as f64;
    x.iter_mut().for_each(|v| *v -= mean);
}
