//! This rank's part of the incompressible flow's box: a slab of its cells
//! along the slowest axis more than one cell thick, so that a rank's cells,
//! and each plane it swaps with a neighbour, are one block in memory.
//!
//! A side of a slab that faces another rank is [`Side::Rank`]: the values
//! beyond it are that rank's, swapped into ghost layers (the velocity's
//! three, `padded.rs`) or a halo plane (the pressure's one, [`Halo`]) before
//! they are read. Every cell is then computed from the same values as on one
//! rank, so the fields do not depend on the number of ranks; only sums over
//! cells (dot products, monitors) and over the ranks' shares of a marker's
//! kernel (`immersed.rs`) change, by round-off.
//!
//! On one rank the part is the whole box and nothing is swapped.

use crate::comm::{Comm, Single, Slab};
use crate::incompressible::grid::Grid;
use crate::incompressible::side::{bcs, Side, Sides};
use std::sync::Arc;

/// The cell planes just beyond a slab's low and high sides (empty where a
/// side of the box is there, and on one rank).
pub type Halo = [Vec<f64>; 2];

#[derive(Debug, Clone)]
pub struct Part {
    pub comm: Arc<dyn Comm>,
    pub slab: Slab,
    /// The whole box's sides.
    pub sides: Sides,
    /// Every rank's first cell along the slab's axis, and the box's count.
    bounds: Arc<[usize]>,
}

impl Part {
    /// The axis a box of `n` cells is cut along.
    pub fn axis(n: [usize; 3]) -> usize {
        (0..3).rev().find(|&d| n[d] > 1).unwrap_or(0)
    }

    /// This rank's part of a box of `n` cells with `sides`: slabs of at
    /// least `layout::GHOSTS` cells (the scenario check makes sure), so
    /// that each rank's ghosts come from its two neighbours.
    pub fn on(comm: Arc<dyn Comm>, n: [usize; 3], sides: Sides) -> Part {
        let (axis, ranks) = (Part::axis(n), comm.ranks());
        let slab = Slab::along(n, axis, ranks, comm.rank());
        let mut bounds: Vec<usize> = (0..ranks)
            .map(|r| Slab::along(n, axis, ranks, r).lo)
            .collect();
        bounds.push(n[axis]);
        Part {
            comm,
            slab,
            sides,
            bounds: bounds.into(),
        }
    }

    /// The whole box on one rank.
    pub fn whole(n: [usize; 3], sides: Sides) -> Part {
        Part::on(Arc::new(Single), n, sides)
    }

    pub fn axis_of(&self) -> usize {
        self.slab.axis
    }

    /// Whether the box is split among ranks.
    pub fn split(&self) -> bool {
        self.comm.ranks() > 1
    }

    /// The rank beyond the slab's low (`up = false`) or high side, wrapping
    /// round a periodic axis; None where a side of the box is there.
    pub fn neighbour(&self, up: bool) -> Option<usize> {
        self.neighbours()[up as usize]
    }

    fn neighbours(&self) -> [Option<usize>; 2] {
        let periodic = self.sides[self.slab.axis][0] == Side::Periodic;
        self.slab.neighbours(self.comm.as_ref(), periodic)
    }

    /// The slab's own sides: the box's, but [`Side::Rank`] toward a neighbour.
    pub fn local_sides(&self) -> Sides {
        let mut s = self.sides;
        for up in [false, true] {
            if self.neighbour(up).is_some() {
                s[self.slab.axis][up as usize] = Side::Rank;
            }
        }
        s
    }

    /// The slab's cells as a grid of their own (`global` is the box's).
    pub fn local_grid(&self, global: &Grid) -> Grid {
        let mut axes = global.axes.clone();
        let a = self.slab.axis;
        axes[a] = global.axes[a].slice(self.slab.lo, self.slab.hi);
        Grid {
            n: self.slab.cells(),
            h: global.h,
            bc: bcs(&self.local_sides()),
            axes,
        }
    }

    /// The same ranks' parts of a coarser box of `n` cells (a multigrid
    /// level), each cell along the slab's axis going to its parent in
    /// `plan` (`Grid::coarse_plans`). None when a slab's bounds fall inside
    /// a merged pair (the coarse cells would straddle two ranks).
    pub fn coarsened(&self, n: [usize; 3], plan: &[usize]) -> Option<Part> {
        let mut bounds = Vec::with_capacity(self.bounds.len());
        for &b in self.bounds.iter() {
            let at_coarse_face = b == 0 || b == plan.len() || plan[b - 1] != plan[b];
            if !at_coarse_face {
                return None;
            }
            bounds.push(if b == plan.len() {
                plan[b - 1] + 1
            } else {
                plan[b]
            });
        }
        let rank = self.comm.rank();
        let slab = Slab {
            n,
            lo: bounds[rank],
            hi: bounds[rank + 1],
            ..self.slab
        };
        Some(Part {
            slab,
            bounds: bounds.into(),
            ..self.clone()
        })
    }

    /// Σ over the ranks of `x`, on every rank.
    pub fn sum(&self, x: f64) -> f64 {
        let mut v = [x];
        self.comm.sum(&mut v);
        v[0]
    }

    /// The largest `x` over the ranks, on every rank (infinite if any is
    /// not a number, so a failure is seen everywhere).
    pub fn max(&self, x: f64) -> f64 {
        let x = if x.is_nan() { f64::INFINITY } else { x };
        -self.comm.min(-x)
    }

    /// Sends `down` to the rank below while receiving `from_up` from the
    /// rank above, then `up` to the rank above while receiving `from_down`
    /// (each only where that neighbour exists).
    pub fn swap(&self, down: &[f64], from_up: &mut [f64], up: &[f64], from_down: &mut [f64]) {
        let comm = self.comm.as_ref();
        crate::comm::swap(comm, self.neighbours(), down, from_up, up, from_down);
    }

    /// Fills `halo` with the neighbours' planes next to this slab of the
    /// cell values `x` (nothing on one rank).
    pub fn fill_halo(&self, x: &[f64], halo: &mut Halo) {
        if !self.split() {
            return;
        }
        let plane = x.len() / self.slab.cells()[self.slab.axis];
        for h in halo.iter_mut() {
            h.resize(plane, 0.0);
        }
        let [below, above] = halo;
        let top = &x[x.len() - plane..];
        self.swap(&x[..plane], above, top, below);
    }

    /// Rank 0 gets the whole box's values of `local` (the cells of each
    /// slab, in turn: the slab axis is the slowest); the others get None.
    pub fn gather(&self, local: &[f64]) -> Option<Vec<f64>> {
        if !self.split() {
            return Some(local.to_vec());
        }
        self.comm.gather(local).map(|parts| parts.concat())
    }
}
