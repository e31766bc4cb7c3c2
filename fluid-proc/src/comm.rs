//! What a flow solver split among ranks needs from the others, and how its
//! cells are split. The solvers see only the [`Comm`] trait: [`Single`] is
//! one rank alone (the default build), and `mpi_comm.rs` (feature `mpi`)
//! is the same on MPI.
//!
//! The box is cut into slabs ([`Slab`]): the simplest decomposition that is
//! exactly as correct as the whole box. Every cell is computed from the
//! same neighbours either way (the halo carries the stencil's layers), so
//! the fields do not depend on the number of ranks; only sums over cells
//! change by round-off. The gas is cut along its longest axis
//! ([`Slab::axis`]), the incompressible flow along its slowest thick one
//! (`part.rs`).

use std::fmt::Debug;

/// The ranks a solver runs on.
pub trait Comm: Send + Sync + Debug {
    fn rank(&self) -> usize;
    fn ranks(&self) -> usize;
    /// Sends `to.1` to rank `to.0` and receives `from.1` from rank `from.0`
    /// at once, either left out at the end of a chain. `tag` tells the two
    /// directions apart when both neighbours are the same rank.
    fn shift(&self, to: Option<(usize, &[f64])>, from: Option<(usize, &mut [f64])>, tag: i32);
    /// The smallest `x` over the ranks, on every rank.
    fn min(&self, x: f64) -> f64;
    /// Adds `x` over the ranks, on every rank.
    fn sum(&self, x: &mut [f64]);
    /// Rank 0 gets every rank's `local`, in rank order; the others get None.
    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>>;
    /// Rank 0's `x` on every rank (the same length everywhere).
    fn broadcast(&self, x: &mut [f64]);
    /// Rank 0's text on every rank.
    fn broadcast_text(&self, text: &mut String);
}

/// One rank alone.
#[derive(Debug, Clone, Copy, Default)]
pub struct Single;

impl Comm for Single {
    fn rank(&self) -> usize {
        0
    }
    fn ranks(&self) -> usize {
        1
    }
    fn shift(&self, _: Option<(usize, &[f64])>, _: Option<(usize, &mut [f64])>, _: i32) {
        unreachable!("one rank has no neighbours to shift to")
    }
    fn min(&self, x: f64) -> f64 {
        x
    }
    fn sum(&self, _: &mut [f64]) {}
    fn gather(&self, local: &[f64]) -> Option<Vec<Vec<f64>>> {
        Some(vec![local.to_vec()])
    }
    fn broadcast(&self, _: &mut [f64]) {}
    fn broadcast_text(&self, _: &mut String) {}
}

/// The cells of one rank: `[lo, hi)` along `axis` of a box of `n` cells,
/// all of them along the other axes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct Slab {
    pub n: [usize; 3],
    pub axis: usize,
    pub lo: usize,
    pub hi: usize,
}

impl Slab {
    /// The axis the gas's box is cut along: the one with the most cells, the last
    /// of equals (the slowest in memory, so a slab is one block).
    pub fn axis(n: [usize; 3]) -> usize {
        (0..3).rev().max_by_key(|&d| (n[d], d)).unwrap_or(0)
    }

    /// Rank `rank`'s slab of `ranks`: the cells along the axis shared as
    /// evenly as they go, the first ranks taking one more.
    pub fn of(n: [usize; 3], ranks: usize, rank: usize) -> Slab {
        Slab::along(n, Slab::axis(n), ranks, rank)
    }

    /// Rank `rank`'s slab of `ranks` along `axis`.
    pub fn along(n: [usize; 3], axis: usize, ranks: usize, rank: usize) -> Slab {
        let (each, extra) = (n[axis] / ranks, n[axis] % ranks);
        let lo = rank * each + rank.min(extra);
        let hi = lo + each + (rank < extra) as usize;
        Slab { n, axis, lo, hi }
    }

    /// The whole box as one slab.
    pub fn whole(n: [usize; 3]) -> Slab {
        Slab::of(n, 1, 0)
    }

    /// The slab's own cells per axis.
    pub fn cells(&self) -> [usize; 3] {
        let mut m = self.n;
        m[self.axis] = self.hi - self.lo;
        m
    }

    /// The global coordinates of local cell `c`.
    pub fn global(&self, mut c: [usize; 3]) -> [usize; 3] {
        c[self.axis] += self.lo;
        c
    }

    /// The ranks of `comm` beyond the slab's low and high sides, wrapping
    /// round a `periodic` axis; None where a side of the box is there, and
    /// on one rank.
    pub fn neighbours(&self, comm: &dyn Comm, periodic: bool) -> [Option<usize>; 2] {
        let (r, ranks) = (comm.rank(), comm.ranks());
        let inside = [self.lo > 0, self.hi < self.n[self.axis]];
        let step = [ranks - 1, 1];
        [0, 1].map(|s| (ranks > 1 && (inside[s] || periodic)).then(|| (r + step[s]) % ranks))
    }
}

/// Swaps planes with the `neighbours` below and above (`Slab::neighbours`):
/// sends `down` to the rank below while receiving `from_up` from the rank
/// above, then `up` to the rank above while receiving `from_down` (each
/// only where that neighbour exists).
pub fn swap(
    comm: &dyn Comm,
    [below, above]: [Option<usize>; 2],
    down: &[f64],
    from_up: &mut [f64],
    up: &[f64],
    from_down: &mut [f64],
) {
    comm.shift(below.map(|r| (r, down)), above.map(|r| (r, from_up)), 0);
    comm.shift(above.map(|r| (r, up)), below.map(|r| (r, from_down)), 1);
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slabs_cover_the_box_once_in_rank_order() {
        for ranks in 1..=5 {
            let n = [10, 1, 7];
            let slabs: Vec<Slab> = (0..ranks).map(|r| Slab::of(n, ranks, r)).collect();
            assert_eq!(slabs[0].axis, 0);
            assert_eq!(slabs[0].lo, 0);
            assert_eq!(slabs[ranks - 1].hi, 10);
            for w in slabs.windows(2) {
                assert_eq!(w[0].hi, w[1].lo);
                assert!(w[0].hi - w[0].lo >= w[1].hi - w[1].lo);
            }
        }
        assert_eq!(Slab::axis([8, 8, 8]), 2);
        assert_eq!(Slab::axis([8, 9, 8]), 1);
    }
}
