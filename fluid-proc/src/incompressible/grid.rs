//! A box of cells for the cell-centred pressure (dissertation §3.2.2):
//! sizes, the cells along each axis (uniform or graded, `axis.rs`), and
//! what each of the six sides imposes on the pressure correction φ. A 2-D
//! flow is one cell thick in z with periodic z sides.
//!
//! Cells are numbered x fastest: `i + nx·(j + ny·k)`.

use crate::incompressible::axis::Axis;

/// What a side of the box imposes on φ in the projection (eq. 3.19).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Bc {
    /// ∂φ/∂n = 0: a wall or an inflow, where the normal velocity is given.
    Neumann,
    /// φ = 0 on the side: an outflow at p = 0.
    Dirichlet,
    /// Wraps to the opposite side (which must be periodic too).
    Periodic,
    /// Another rank's cells are beyond (a side of a slab, `part.rs`), read
    /// from a halo plane.
    Rank,
}

/// Where a cell's neighbour across one of its faces lies.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Neighbour {
    Cell(usize),
    /// The face is a side of the box with this condition (not periodic).
    Side(Bc),
}

/// A box of `n` cells and one condition per side (`bc[d] = [low, high]`
/// along axis d).
#[derive(Debug, Clone, PartialEq)]
pub struct Grid {
    pub n: [usize; 3],
    /// The spacing along each axis: a graded axis's finest, its core's.
    pub h: [f64; 3],
    pub bc: [[Bc; 2]; 3],
    /// The cells' widths along each axis.
    pub axes: [Axis; 3],
}

impl Grid {
    /// A box of `n` cells of spacings `h`.
    pub fn uniform(n: [usize; 3], h: [f64; 3], bc: [[Bc; 2]; 3]) -> Grid {
        Grid {
            n,
            h,
            bc,
            axes: [0, 1, 2].map(|d| Axis::uniform(n[d], h[d])),
        }
    }

    /// A box of the cells of `axes`.
    pub fn of_axes(axes: [Axis; 3], bc: [[Bc; 2]; 3]) -> Grid {
        Grid {
            n: [0, 1, 2].map(|d| axes[d].n()),
            h: [0, 1, 2].map(|d| axes[d].width_range().0),
            bc,
            axes,
        }
    }

    /// Whether any axis is graded.
    pub fn is_graded(&self) -> bool {
        self.axes.iter().any(|a| !a.is_uniform())
    }

    /// Volume of cell `c` [m³].
    pub fn volume(&self, c: [usize; 3]) -> f64 {
        (0..3).map(|d| self.axes[d].width(c[d] as isize)).product()
    }

    /// Each cell's volume, in the cells' order, on a graded box (None on a
    /// uniform one, where every cell's is Π h).
    pub fn volumes(&self) -> Option<Vec<f64>> {
        self.is_graded().then(|| {
            (0..self.cells())
                .map(|i| self.volume(self.coords(i)))
                .collect()
        })
    }

    pub fn cells(&self) -> usize {
        self.n[0] * self.n[1] * self.n[2]
    }

    pub fn index(&self, c: [usize; 3]) -> usize {
        c[0] + self.n[0] * (c[1] + self.n[1] * c[2])
    }

    pub fn coords(&self, mut i: usize) -> [usize; 3] {
        let x = i % self.n[0];
        i /= self.n[0];
        [x, i % self.n[1], i / self.n[1]]
    }

    /// The neighbour of cell `c` along axis `d`, below (`up = false`) or above.
    pub fn neighbour(&self, c: [usize; 3], d: usize, up: bool) -> Neighbour {
        let n = self.n[d];
        let at_side = if up { c[d] + 1 == n } else { c[d] == 0 };
        if !at_side {
            let mut m = c;
            m[d] = if up { c[d] + 1 } else { c[d] - 1 };
            return Neighbour::Cell(self.index(m));
        }
        match self.bc[d][up as usize] {
            Bc::Periodic => {
                let mut m = c;
                m[d] = if up { 0 } else { n - 1 };
                Neighbour::Cell(self.index(m))
            }
            side => Neighbour::Side(side),
        }
    }

    /// The finest and the coarsest spacing over the axes more than one
    /// cell thick (a 2-D flow's thin axis left out; a graded axis's core) [m].
    pub fn spacing_range(&self) -> (f64, f64) {
        (0..3)
            .filter(|&d| self.n[d] > 1)
            .map(|d| self.h[d])
            .fold((f64::INFINITY, 0.0), |(lo, hi), h| (lo.min(h), hi.max(h)))
    }

    /// Whether φ is fixed anywhere; if not, it is defined up to a constant.
    pub fn has_dirichlet(&self) -> bool {
        self.bc.iter().flatten().any(|&b| b == Bc::Dirichlet)
    }

    /// A side named periodic whose opposite side is not.
    pub fn unpaired_periodic(&self) -> Option<usize> {
        (0..3).find(|&d| (self.bc[d][0] == Bc::Periodic) != (self.bc[d][1] == Bc::Periodic))
    }

    /// Each cell's parent along each axis on the next coarser grid
    /// (`Axis::coarse_plan`: a uniform axis halves from an even count of at
    /// least 4 cells, periodic axes also from 2; the cell itself where the
    /// axis does not coarsen), or None when no axis does.
    pub fn coarse_plans(&self) -> Option<[Vec<usize>; 3]> {
        let plans = [0, 1, 2].map(|d| {
            let least = if self.bc[d][0] == Bc::Periodic { 2 } else { 4 };
            self.axes[d].coarse_plan(self.h[d], least)
        });
        plans.iter().any(Option::is_some).then(|| {
            let n = self.n;
            let mut plans = plans.into_iter();
            [0, 1, 2].map(|d| {
                plans
                    .next()
                    .flatten()
                    .unwrap_or_else(|| (0..n[d]).collect())
            })
        })
    }

    /// The next coarser grid, merged by `plans` (`coarse_plans`).
    pub fn coarsened(&self, plans: &[Vec<usize>; 3]) -> Grid {
        let mut g = self.clone();
        for d in 0..3 {
            let n = plans[d].last().map_or(1, |&p| p + 1);
            if n < self.n[d] {
                g.n[d] = n;
                g.h[d] = 2.0 * self.h[d];
                g.axes[d] = self.axes[d].coarsened(&plans[d], self.bc[d][0] == Bc::Periodic);
            }
        }
        g
    }
}
