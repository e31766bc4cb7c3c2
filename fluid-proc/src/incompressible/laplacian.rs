//! The cell-centred operator A = −∇²ₕ of the pressure Poisson equation
//! (dissertation eq. 3.19 after eliminating u^{n+1}): the 7-point stencil, a
//! Neumann side dropping its term (the ghost equals the cell), a Dirichlet
//! side φ = 0 on the face doubling it (the ghost is −φ_c). A is symmetric and
//! positive semi-definite; its null space is the constants when no side is
//! Dirichlet.
//!
//! The stencil works line by line along x: each line knows where the lines
//! beside it start (or that a side is there), so the inner loop over a line
//! holds no index arithmetic beyond ±1 and the line offsets.
//!
//! On a graded axis (`axis.rs`) the term of the face between cells i and
//! i + 1 is (φ_{i+1} − φ_i)/(w_i·g_{i+1}): the finite-volume stencil, whose
//! rows scaled by the cells' volumes V are symmetric, so A is self-adjoint
//! in the inner product Σ V x y that the solve then takes (`poisson.rs`).
//!
//! On a rank's slab (`part.rs`) a side toward another rank reads that
//! rank's cells from a halo plane, which the caller fills first; the
//! red–black colours follow the cells' places in the whole box.

use crate::incompressible::grid::{Bc, Grid, Neighbour};
use crate::incompressible::part::Halo;
use rayon::prelude::*;
use std::sync::atomic::{AtomicU64, Ordering};

/// Lines shorter than this many cells per task are not worth a thread.
const CELLS_PER_TASK: usize = 4096;

/// One line of cells along x: its first cell, and the first cells of the
/// lines below and above it along y and z (None at a side that is not
/// periodic, or on an axis one cell thick, where the neighbour is the cell
/// itself and cancels).
#[derive(Debug, Clone, Copy)]
pub struct Line {
    pub start: usize,
    pub beside: [Option<usize>; 4],
    /// The weights of the lines beside it, 1/(w·g) [1/m²].
    pub weight: [f64; 4],
    /// Where the line's row starts in the halo plane below and above,
    /// where another rank's cells are there (the slab's axis, y or z).
    pub halo: [Option<usize>; 2],
    /// The weights of the halo rows below and above [1/m²].
    pub halo_weight: [f64; 2],
}

/// A = −∇²ₕ on one grid, ready to apply and to smooth with.
#[derive(Debug, Clone)]
pub struct Stencil {
    pub grid: Grid,
    /// 1/h² along a uniform x [1/m²].
    w: f64,
    /// Along a graded x, the weights of each cell's neighbours below and
    /// above (None on a uniform x).
    x_weights: Option<[Vec<f64>; 2]>,
    /// A's diagonal per cell.
    pub diag: Vec<f64>,
    lines: Vec<Line>,
    /// x wraps (periodic and more than one cell).
    x_wraps: bool,
    /// The first cell's place along the slab's axis in the whole box, mod 2.
    parity: usize,
    /// Whether y and z are odd and periodic: their last lines then touch
    /// their first of the same colour across the wrap (see `seam_phase`).
    seams: [bool; 2],
}

impl Stencil {
    /// On a rank's slab `g`, whose first cell along the slab's axis is the
    /// box's cell `offset` there.
    pub fn on(g: &Grid, offset: usize) -> Stencil {
        let [nx, ny, nz] = g.n;
        let beside = |c: usize, n: usize, d: usize, stride: usize, up: bool| {
            if n == 1 {
                return None;
            }
            let at_side = if up { c + 1 == n } else { c == 0 };
            match (at_side, up) {
                (false, false) => Some(-(stride as isize)),
                (false, true) => Some(stride as isize),
                (true, _) if g.bc[d][up as usize] != Bc::Periodic => None,
                (true, false) => Some(((n - 1) * stride) as isize),
                (true, true) => Some(-(((n - 1) * stride) as isize)),
            }
        };
        // A side toward another rank is on the slowest axis that has one.
        let rank_axis = (1..3).find(|&d| g.bc[d].contains(&Bc::Rank));
        let mut lines = Vec::with_capacity(ny * nz);
        for k in 0..nz {
            for j in 0..ny {
                let start = g.index([0, j, k]);
                let off = [
                    beside(j, ny, 1, nx, false),
                    beside(j, ny, 1, nx, true),
                    beside(k, nz, 2, nx * ny, false),
                    beside(k, nz, 2, nx * ny, true),
                ];
                let halo = [false, true].map(|up| {
                    let d = rank_axis?;
                    let c = [0, j, k][d];
                    let at_side = if up { c + 1 == g.n[d] } else { c == 0 };
                    let mut row = [0, j, k];
                    row[d] = 0;
                    (at_side && g.bc[d][up as usize] == Bc::Rank).then(|| g.index(row))
                });
                let weight = [(1, j, false), (1, j, true), (2, k, false), (2, k, true)]
                    .map(|(d, c, up)| face_weight(g, d, c, up));
                let halo_weight = [false, true]
                    .map(|up| rank_axis.map_or(0.0, |d| face_weight(g, d, [0, j, k][d], up)));
                lines.push(Line {
                    start,
                    beside: off.map(|o| o.map(|o| (start as isize + o) as usize)),
                    weight,
                    halo,
                    halo_weight,
                });
            }
        }
        let diag = (0..g.cells())
            .map(|i| {
                let c = g.coords(i);
                (0..6).map(|t| diagonal_term(g, c, t / 2, t % 2 == 1)).sum()
            })
            .collect();
        let x_weights = (!g.axes[0].is_uniform())
            .then(|| [false, true].map(|up| (0..nx).map(|i| face_weight(g, 0, i, up)).collect()));
        Stencil {
            grid: g.clone(),
            // The one width of a uniform x (a coarse level's nominal spacing
            // need not be it where a graded axis merged to equal widths).
            w: 1.0 / (g.axes[0].width(0) * g.axes[0].width(0)),
            x_weights,
            diag,
            lines,
            x_wraps: nx > 1 && g.bc[0][0] == Bc::Periodic,
            parity: offset % 2,
            seams: [1, 2].map(|d| g.n[d] % 2 == 1 && g.n[d] > 1 && g.bc[d][0] == Bc::Periodic),
        }
    }

    /// The lines beside `line` that exist, with their weights.
    #[inline(always)]
    fn rows(&self, line: &Line) -> ([(usize, f64); 4], usize) {
        let mut rows = [(0, 0.0); 4];
        let mut count = 0;
        for (b, &w) in line.beside.iter().zip(&line.weight) {
            if let Some(b) = b {
                rows[count] = (*b, w);
                count += 1;
            }
        }
        (rows, count)
    }

    /// The rows of `halo` beside `line` (none inside a slab).
    #[inline(always)]
    fn halo_rows<'a>(&self, line: &Line, halo: &'a Halo) -> ([(&'a [f64], f64); 2], usize) {
        let mut rows: [(&[f64], f64); 2] = [(&[], 0.0), (&[], 0.0)];
        let mut count = 0;
        for ((h, row), w) in halo.iter().zip(line.halo).zip(line.halo_weight) {
            if let Some(row) = row {
                rows[count] = (&h[row..row + self.grid.n[0]], w);
                count += 1;
            }
        }
        (rows, count)
    }

    /// Σ of the neighbours' weighted values of cell `i` on a line starting
    /// at `start` with the lines `rows` beside it and the halo rows
    /// `beyond`: the off-diagonal part of A with its sign flipped.
    #[inline(always)]
    fn beside_sum(
        &self,
        x: impl Fn(usize) -> f64,
        start: usize,
        rows: &[(usize, f64)],
        beyond: &[(&[f64], f64)],
        i: usize,
    ) -> f64 {
        let nx = self.grid.n[0];
        let c = start + i;
        let below = match (i > 0, self.x_wraps) {
            (true, _) => Some(c - 1),
            (false, true) => Some(c + nx - 1),
            (false, false) => None,
        };
        let above = match (i + 1 < nx, self.x_wraps) {
            (true, _) => Some(c + 1),
            (false, true) => Some(start),
            (false, false) => None,
        };
        let value = |n: Option<usize>| n.map_or(0.0, &x);
        let mut s = match &self.x_weights {
            Some([lo, hi]) => lo[i] * value(below) + hi[i] * value(above),
            None => self.w * (value(below) + value(above)),
        };
        for &(b, w) in rows {
            s += w * x(b + i);
        }
        for (h, w) in beyond {
            s += w * h[i];
        }
        s
    }

    /// out = A x, the neighbours' cells beyond a slab's sides in `halo`
    /// (empty on a whole box).
    pub fn apply(&self, x: &[f64], halo: &Halo, out: &mut [f64]) {
        let nx = self.grid.n[0];
        let per_task = (CELLS_PER_TASK / nx).max(1);
        let line_of = |(o, line): (&mut [f64], &Line)| {
            let (rows, count) = self.rows(line);
            let rows = &rows[..count];
            let (beyond, halos) = self.halo_rows(line, halo);
            let beyond = &beyond[..halos];
            for (i, o) in o.iter_mut().enumerate() {
                let c = line.start + i;
                *o = self.diag[c] * x[c] - self.beside_sum(|c| x[c], line.start, rows, beyond, i);
            }
        };
        match self.lines.len() > per_task {
            true => out
                .par_chunks_mut(nx)
                .zip(self.lines.par_iter())
                .with_min_len(per_task)
                .for_each(line_of),
            // A coarse level: not worth waking another thread.
            false => out.chunks_mut(nx).zip(&self.lines).for_each(line_of),
        }
    }

    /// One Gauss–Seidel pass over the cells of one colour ((i + j + k) mod 2
    /// in the whole box) for A x = b. A cell with a zero diagonal (a lone
    /// cell with no sides to speak of) is left alone.
    ///
    /// A cell's neighbours are all of the other colour, so the lines are
    /// independent and go to the pool's threads, with the same result on
    /// any number: a line writes only its cells of this colour and reads
    /// only cells of the other. The cells are read and written as atomics
    /// (plain loads and stores on x86-64) since a line reads lines that
    /// other threads write at the cells it does not read. Across the wrap
    /// of an odd periodic axis a cell's neighbour has its colour: along x
    /// a line takes its cells in order, and along y and z the lines go in
    /// seam phases (`seam_phase`), the last line after the first, as one
    /// thread would take them in order.
    pub fn gauss_seidel(&self, b: &[f64], x: &mut [f64], halo: &Halo, colour: usize) {
        let nx = self.grid.n[0];
        let ny = self.grid.n[1];
        let cells = as_atomic(x);
        let get = |c: usize| f64::from_bits(cells[c].load(Ordering::Relaxed));
        let per_task = (CELLS_PER_TASK / nx).max(1);
        let sweep = |(l, line): (usize, &Line)| {
            let (rows, count) = self.rows(line);
            let rows = &rows[..count];
            let (beyond, halos) = self.halo_rows(line, halo);
            let beyond = &beyond[..halos];
            let (j, k) = (l % ny, l / ny);
            let first = (colour + j + k + self.parity) % 2;
            for i in (first..nx).step_by(2) {
                let c = line.start + i;
                let d = self.diag[c];
                if d != 0.0 {
                    let v = (b[c] + self.beside_sum(get, line.start, rows, beyond, i)) / d;
                    cells[c].store(v.to_bits(), Ordering::Relaxed);
                }
            }
        };
        let phases = 1 + self.seams.iter().filter(|&&s| s).count();
        for phase in 0..phases {
            let in_phase = |(l, line): (usize, &Line)| {
                if self.seam_phase(l) == phase {
                    sweep((l, line));
                }
            };
            // A coarse level, or the few last lines of a later phase: not
            // worth waking another thread.
            match phase == 0 && self.lines.len() > per_task {
                true => self
                    .lines
                    .par_iter()
                    .enumerate()
                    .with_min_len(per_task)
                    .for_each(in_phase),
                false => self.lines.iter().enumerate().for_each(in_phase),
            }
        }
    }

    /// On how many of y and z line `l` is the last of an odd periodic
    /// axis, whose first line has its colours: a sweep takes such lines
    /// after the first ones (fluid-gpu's `seam_phase` is the same rule per
    /// cell), so that no two lines of one phase touch and every thread
    /// count gives what one thread's ordered sweep gives.
    fn seam_phase(&self, l: usize) -> usize {
        let [_, ny, nz] = self.grid.n;
        let last = [l % ny + 1 == ny, l / ny + 1 == nz];
        (0..2).filter(|&a| self.seams[a] && last[a]).count()
    }
}

/// `x` as atomics of its bits, for as long as it is borrowed.
fn as_atomic(x: &mut [f64]) -> &[AtomicU64] {
    const _: () = assert!(
        std::mem::size_of::<f64>() == std::mem::size_of::<AtomicU64>()
            && std::mem::align_of::<f64>() == std::mem::align_of::<AtomicU64>()
    );
    // SAFETY: AtomicU64 has f64's size and alignment (checked above), any
    // bits are a valid u64, and x stays mutably borrowed for as long as the
    // atomics live, so nothing reads or writes it but through them.
    unsafe { &*(x as *mut [f64] as *const [AtomicU64]) }
}

/// The weight 1/(w·g) of the face of cell i along d below (`up = false`)
/// or above it: a side's gap as a mirrored ghost's (`axis.rs`) [1/m²].
fn face_weight(g: &Grid, d: usize, i: usize, up: bool) -> f64 {
    let a = &g.axes[d];
    let i = i as isize;
    1.0 / (a.width(i) * a.gap(i + up as isize))
}

/// What the face of cell `c` along d (below or above) puts on the diagonal.
fn diagonal_term(g: &Grid, c: [usize; 3], d: usize, up: bool) -> f64 {
    let w = face_weight(g, d, c[d], up);
    match g.neighbour(c, d, up) {
        Neighbour::Cell(m) if m == g.index(c) => 0.0,
        Neighbour::Cell(_) | Neighbour::Side(Bc::Rank) => w,
        Neighbour::Side(Bc::Dirichlet) => 2.0 * w,
        Neighbour::Side(_) => 0.0,
    }
}
