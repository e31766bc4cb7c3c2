//! Geometric multigrid for A φ = b (`laplacian.rs`): one V-cycle is the
//! preconditioner of the conjugate-gradient solve (`poisson.rs`), which keeps
//! the iteration count flat as the grid is refined, so the pressure solve
//! costs O(cells).
//!
//! Cell-centred coarsening halves every axis that can. A graded axis
//! (`axis.rs`) merges a pair of cells only where the two are no wider than
//! the level's spacing allows (`Axis::coarse_plan`): a semi-coarsening that
//! follows the cells' shapes, for the point smoother is weak along a long
//! cell, and halving every axis of a graded box (cells up to nine times as
//! long as wide) took 36 iterations where its uniform box takes 7; merged
//! so, 7. Restriction averages the children weighted
//! by their volumes (R = V_c⁻¹PᵀV, plainly Pᵀ/2^d on a uniform grid),
//! prolongation copies the parent to them, and the coarse operators are
//! rediscretised. Symmetric red–black Gauss–Seidel
//! (red then black before the coarse correction, black then red after) keeps
//! the V-cycle symmetric, as conjugate gradients need.
//!
//! Split among ranks (`part.rs`), each rank smooths its slab of each level,
//! its halo swapped before every sweep, as long as the slabs halve with the
//! grid. At the last level (the coarsest, or the first whose slabs cannot
//! halve again: the next level's cells would straddle two ranks), rank 0
//! gathers the level and runs the rest of the cycle on the whole of it: the
//! same cycle as on one rank. Slab bounds that are not even (32 cells on 3
//! ranks) gather the finest level itself, and the preconditioner then runs
//! on rank 0 alone: correct, but slow.
//!
//! On a periodic slab axis of an odd number of cells the first and last
//! cells have one colour, so one rank's sweep reads the other's new value
//! where split ranks read its old one: the fields then agree to the solve's
//! tolerance rather than to round-off.

use crate::incompressible::grid::Grid;
use crate::incompressible::laplacian::Stencil;
use crate::incompressible::part::{Halo, Part};
use crate::incompressible::rows;

/// Smoothing sweeps before and after the coarse correction.
const SWEEPS: usize = 2;
/// The coarsest level has at most this many cells…
const COARSEST_CELLS: usize = 64;
/// …and is solved by this many symmetric sweeps.
const COARSEST_SWEEPS: usize = 40;

/// The cells of each level a one-rank multigrid on `fine` has, finest
/// first, as [`Multigrid::on`] builds them: each halves the axes whose
/// counts are even (`Grid::coarse_plans`) until at most `COARSEST_CELLS`
/// are left or none halves.
pub fn level_cells(fine: &Grid) -> Vec<[usize; 3]> {
    let mut grids = vec![fine.clone()];
    while grids.last().unwrap().cells() > COARSEST_CELLS {
        let Some(plan) = grids.last().unwrap().coarse_plans() else {
            break;
        };
        let next = grids.last().unwrap().coarsened(&plan);
        grids.push(next);
    }
    grids.iter().map(|g| g.n).collect()
}

/// The coarsest of `levels`' share of one V-cycle's cell updates: its
/// `COARSEST_SWEEPS` symmetric sweeps (each cell twice a sweep) against
/// `SWEEPS` sweeps before and after and a residual on every other level.
/// Where counts do not halve, the coarsest level is large and this share
/// nears one: the solve then costs several times what it would.
pub fn coarsest_share(levels: &[[usize; 3]]) -> f64 {
    let cells = |n: &[usize; 3]| n.iter().product::<usize>() as f64;
    let Some((last, others)) = levels.split_last() else {
        return 0.0;
    };
    let coarsest = 2.0 * COARSEST_SWEEPS as f64 * cells(last);
    let others: f64 = others
        .iter()
        .map(|n| (2 * SWEEPS + 1) as f64 * cells(n))
        .sum();
    coarsest / (coarsest + others)
}

struct Level {
    part: Part,
    halo: Halo,
    stencil: Stencil,
    /// Right-hand side, solution and residual of this level's correction.
    b: Vec<f64>,
    x: Vec<f64>,
    r: Vec<f64>,
    /// Parent cell on the next coarser level.
    parent: Vec<usize>,
    /// Each coarser cell's children on this level, ascending: those of
    /// cell p are `kids[first_kid[p]..first_kid[p + 1]]`.
    first_kid: Vec<usize>,
    kids: Vec<usize>,
    /// Each cell's share of its parent's volume (2^−axes halved on a
    /// uniform grid).
    share: Vec<f64>,
    /// Each cell's volume where the grid is graded (`Grid::volumes`).
    volumes: Option<Vec<f64>>,
}

pub struct Multigrid {
    /// This rank's slab of each level it smooths.
    levels: Vec<Level>,
    /// No Dirichlet side: A is singular and every level works mean-free.
    singular: bool,
    /// Split among ranks: what the last level is solved with.
    rest: Option<Rest>,
}

/// The last level of a split multigrid, whole.
struct Rest {
    /// Its correction, from rank 0.
    whole: Vec<f64>,
    /// The cycle from it on one rank (on rank 0; None on the others).
    serial: Option<Box<Multigrid>>,
}

impl Multigrid {
    /// On a whole box, one rank.
    pub fn new(fine: &Grid) -> Multigrid {
        Multigrid::on(
            fine,
            &Part::whole(fine.n, [[crate::incompressible::side::Side::WALL; 2]; 3]),
        )
    }

    /// On this rank's `part` of the box `fine` (the whole box's grid).
    pub fn on(fine: &Grid, part: &Part) -> Multigrid {
        let mut grids = vec![fine.clone()];
        let mut parts = vec![part.clone()];
        // Each level's cells' parents along each axis on the next.
        let mut plans: Vec<[Vec<usize>; 3]> = Vec::new();
        while grids.last().unwrap().cells() > COARSEST_CELLS {
            let g = grids.last().unwrap();
            let Some(plan) = g.coarse_plans() else {
                break;
            };
            let c = g.coarsened(&plan);
            let Some(p) = parts.last().unwrap().coarsened(c.n, &plan[part.slab.axis]) else {
                break;
            };
            grids.push(c);
            parts.push(p);
            plans.push(plan);
        }
        let rest = part.split().then(|| {
            let last = grids.last().unwrap();
            Rest {
                whole: vec![0.0; last.cells()],
                serial: (part.comm.rank() == 0).then(|| Box::new(Multigrid::new(last))),
            }
        });
        let locals: Vec<Grid> = grids
            .iter()
            .zip(&parts)
            .map(|(g, p)| {
                if p.split() {
                    p.local_grid(g)
                } else {
                    g.clone()
                }
            })
            .collect();
        let offsets: Vec<usize> = parts.iter().map(|p| p.slab.lo).collect();
        let levels = locals
            .iter()
            .zip(parts)
            .enumerate()
            .map(|(l, (g, part))| {
                let cells = g.cells();
                let (parent, share) = match locals.get(l + 1) {
                    Some(c) => transfer(
                        g,
                        c,
                        &plans[l],
                        part.slab.axis,
                        [offsets[l], offsets[l + 1]],
                    ),
                    None => (Vec::new(), Vec::new()),
                };
                let coarse_cells = locals.get(l + 1).map_or(0, |c| c.cells());
                let (first_kid, kids) = children_of(&parent, coarse_cells);
                Level {
                    stencil: Stencil::on(g, part.slab.lo),
                    halo: Halo::default(),
                    part,
                    b: vec![0.0; cells],
                    x: vec![0.0; cells],
                    r: vec![0.0; cells],
                    parent,
                    first_kid,
                    kids,
                    share,
                    volumes: g.volumes(),
                }
            })
            .collect();
        Multigrid {
            levels,
            singular: !fine.has_dirichlet(),
            rest,
        }
    }

    /// out = A x on the finest level, x's halo swapped first.
    pub fn apply(&mut self, x: &[f64], out: &mut [f64]) {
        let f = &mut self.levels[0];
        f.part.fill_halo(x, &mut f.halo);
        f.stencil.apply(x, &f.halo, out);
    }

    /// Number of levels, the finest included.
    pub fn depth(&self) -> usize {
        self.levels.len()
    }

    /// z = M⁻¹ r: one V-cycle from a zero guess.
    pub fn precondition(&mut self, r: &[f64], z: &mut [f64]) {
        rows::copy(&mut self.levels[0].b, r);
        self.cycle(0);
        rows::copy(z, &self.levels[0].x);
        if self.singular {
            let f = &self.levels[0];
            remove_mean(z, &f.part, f.volumes.as_deref());
        }
    }

    fn cycle(&mut self, l: usize) {
        let last = l + 1 == self.levels.len();
        let level = &mut self.levels[l];
        rows::for_each(&mut level.x, |x, _| *x = 0.0);
        if let (true, Some(rest)) = (last, &mut self.rest) {
            // Rank 0 runs the cycle on the whole level; each takes its slab.
            let part = &level.part;
            let whole = &mut rest.whole;
            if let (Some(b), Some(serial)) = (part.gather(&level.b), &mut rest.serial) {
                serial.levels[0].b.copy_from_slice(&b);
                serial.cycle(0);
                whole.copy_from_slice(&serial.levels[0].x);
            }
            part.comm.broadcast(whole);
            let plane = whole.len() / part.slab.n[part.slab.axis];
            level
                .x
                .copy_from_slice(&whole[part.slab.lo * plane..part.slab.hi * plane]);
            return;
        }
        if last {
            for _ in 0..COARSEST_SWEEPS {
                sweep(level, 0);
                sweep(level, 1);
                sweep(level, 1);
                sweep(level, 0);
            }
            if self.singular {
                remove_mean(&mut level.x, &level.part, level.volumes.as_deref());
            }
            return;
        }
        for _ in 0..SWEEPS {
            sweep(level, 0);
            sweep(level, 1);
        }
        level.part.fill_halo(&level.x, &mut level.halo);
        level.stencil.apply(&level.x, &level.halo, &mut level.r);
        let b = &level.b;
        rows::for_each(&mut level.r, |r, i| *r = b[i] - *r);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&mut fine[l], &mut coarse[0]);
        // Restriction: each coarse cell sums its children in ascending order.
        rows::for_each(&mut c.b, |b, p| {
            *b = 0.0;
            for &i in &f.kids[f.first_kid[p]..f.first_kid[p + 1]] {
                *b += f.r[i] * f.share[i];
            }
        });
        self.cycle(l + 1);
        let (fine, coarse) = self.levels.split_at_mut(l + 1);
        let (f, c) = (&mut fine[l], &coarse[0]);
        let parent = &f.parent;
        rows::for_each(&mut f.x, |x, i| *x += c.x[parent[i]]);
        for _ in 0..SWEEPS {
            sweep(f, 1);
            sweep(f, 0);
        }
    }
}

/// Each cell of the rank's level `g` its parent on the next level `c` and
/// its share of the parent's volume, from the whole box's `plans`
/// (`Grid::coarse_plans`): along the slab's `axis` the slabs start at the
/// whole box's cells `offsets` (this level's, the next one's).
fn transfer(
    g: &Grid,
    c: &Grid,
    plans: &[Vec<usize>; 3],
    axis: usize,
    offsets: [usize; 2],
) -> (Vec<usize>, Vec<f64>) {
    let of = |f: [usize; 3]| {
        [0, 1, 2].map(|d| match d == axis {
            true => plans[d][f[d] + offsets[0]] - offsets[1],
            false => plans[d][f[d]],
        })
    };
    let share = |f: [usize; 3]| -> f64 {
        let p = of(f);
        (0..3)
            .map(|d| g.axes[d].width(f[d] as isize) / c.axes[d].width(p[d] as isize))
            .product()
    };
    let cells = 0..g.cells();
    let parent = cells.clone().map(|i| c.index(of(g.coords(i)))).collect();
    (parent, cells.map(|i| share(g.coords(i))).collect())
}

/// One colour's sweep, the other colour's values beyond the slab swapped in
/// first (a cell's neighbours are all of the other colour).
fn sweep(level: &mut Level, colour: usize) {
    level.part.fill_halo(&level.x, &mut level.halo);
    level
        .stencil
        .gauss_seidel(&level.b, &mut level.x, &level.halo, colour);
}

/// Takes the mean over the whole box (all of `part`'s ranks) from `x`:
/// weighted by the cells' `volumes` on a graded grid.
pub fn remove_mean(x: &mut [f64], part: &Part, volumes: Option<&[f64]>) {
    let mean = mean(x, part, volumes);
    rows::for_each(x, |v, _| *v -= mean);
}

/// The mean of `x` over the whole box, weighted by `volumes` where given.
pub fn mean(x: &[f64], part: &Part, volumes: Option<&[f64]>) -> f64 {
    // The sums on one thread, in the cells' order (`rows.rs` says why).
    match volumes {
        None => {
            let count = part.slab.n.iter().product::<usize>() as f64;
            part.sum(x.iter().sum::<f64>()) / count
        }
        Some(v) => {
            let weighted: f64 = x.iter().zip(v).map(|(x, v)| x * v).sum();
            part.sum(weighted) / part.sum(v.iter().sum::<f64>())
        }
    }
}

/// The children of each of `coarse` cells from the fine cells' parents, as
/// (first child per cell and one past the last, children ascending).
fn children_of(parent: &[usize], coarse: usize) -> (Vec<usize>, Vec<usize>) {
    let mut first = vec![0; coarse + 1];
    for &p in parent {
        first[p + 1] += 1;
    }
    for p in 0..coarse {
        first[p + 1] += first[p];
    }
    let mut next = first.clone();
    let mut kids = vec![0; parent.len()];
    for (i, &p) in parent.iter().enumerate() {
        kids[next[p]] = i;
        next[p] += 1;
    }
    (first, kids)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::incompressible::grid::Bc;

    /// `level_cells` is the chain the solver builds, and its cost model
    /// counts cell updates: a periodic 45 × 45 × 90 box halves only along
    /// z, to 45³, whose 40 symmetric sweeps (80 updates a cell) against the
    /// fine level's 5 make 80·45³/(80·45³ + 5·45²·90) = 8/9 of a V-cycle;
    /// FronTier++'s 60 × 60 × 120 goes down to 15³, a tenth.
    #[test]
    fn the_levels_are_the_solvers_and_an_odd_box_spends_its_cycle_at_the_bottom() {
        let periodic_xy = |n: [usize; 3]| {
            let bc = [[Bc::Periodic; 2], [Bc::Periodic; 2], [Bc::Neumann; 2]];
            Grid::uniform(n, [1.0; 3], bc)
        };
        let odd = periodic_xy([45, 45, 90]);
        let levels = level_cells(&odd);
        assert_eq!(levels, vec![[45, 45, 90], [45, 45, 45]]);
        let built = Multigrid::new(&odd);
        let built: Vec<[usize; 3]> = built.levels.iter().map(|l| l.stencil.grid.n).collect();
        assert_eq!(levels, built, "the solver's own levels");
        assert!((coarsest_share(&levels) - 8.0 / 9.0).abs() < 1e-12);
        let c9 = level_cells(&periodic_xy([60, 60, 120]));
        assert_eq!(c9.last(), Some(&[15, 15, 15]));
        let share = coarsest_share(&c9);
        assert!((0.09..0.11).contains(&share), "{share}");
    }
}
