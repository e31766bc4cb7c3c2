//! The local index coating of dissertation §3.3.2, and the pressure jump across
//! the canopy it gives.
//!
//! The canopy is an open surface: far from it no side can be told, but near
//! it each cell lies on one side. Following the dissertation:
//! 1. a cell whose centre lies within a grid spacing of the canopy takes the
//!    side of the canopy's nearest point P_s: the sign of (P − P_s)·n_s,
//!    n_s the normal of the nearest triangle's vertex order;
//! 2. three sweeps give each uncoated cell next to a coated one that side;
//! 3. a side-sensitive value at the canopy is read from cells of its own
//!    side only.
//!
//! For step 3 the pressure on each side of a triangle is the least-squares
//! plane through the pressures of that side's coated cells beyond the
//! forcing's smear (from `NEAR` to `FAR` spacings from the triangle's
//! plane, within `ASIDE` of its centre along it), taken at the centre, so a pressure
//! that varies linearly on each side gives its two limits exactly. The
//! jump is p⁻ − p⁺, p⁻ on the side the normal points away from: the sign
//! of `Field::CanopyPressure` (load = jump·area·n).

use crate::grid::{Grid, Neighbour};
use nalgebra::{Matrix3, Point3, Vector3};
use parry3d_f64::query::PointQuery;
use parry3d_f64::shape::Triangle;

/// Sweeps that spread the coating from the cells next to the canopy.
pub const SWEEPS: usize = 3;
/// The nearest cells a side's pressure is read from, in spacings from the
/// triangle's plane: the δ kernel spreads the canopy's force two cells
/// either side, and within that the pressure is the smeared one's.
pub const NEAR: f64 = 2.0;
/// The farthest, in spacings.
pub const FAR: f64 = 4.5;
/// How far along the canopy from the triangle's centre, in spacings: the
/// δ kernel smears the jump over two cells along the canopy too, so near
/// an edge the jump read from cells this far away is smeared little more.
pub const ASIDE: f64 = 1.5;

/// Each cell's side of the canopy: −1, +1, or 0 where no side is told.
#[derive(Debug, Clone)]
pub struct Coating {
    pub side: Vec<i8>,
}

/// Triangle `t`'s corners from flat positions `x` (xyz per vertex) [m].
fn corners(x: &[f64], t: &[usize; 3]) -> [Point3<f64>; 3] {
    t.map(|i| Point3::new(x[3 * i], x[3 * i + 1], x[3 * i + 2]))
}

/// The cell centres within `reach` of the box [lo, hi], by index ranges
/// (wrapping round periodic axes; clipped elsewhere; a 2-D flow's one cell
/// along its thin axis once), and `f(cell, centre)`.
fn for_cells_near(
    grid: &Grid,
    lo: [f64; 3],
    hi: [f64; 3],
    reach: f64,
    mut f: impl FnMut(usize, Point3<f64>),
) {
    let range = [0, 1, 2].map(|d| {
        if grid.n[d] == 1 {
            return (0, 0);
        }
        let h = grid.h[d];
        let first = ((lo[d] - reach) / h - 0.5).ceil() as i64;
        let last = ((hi[d] + reach) / h - 0.5).floor() as i64;
        (first, last)
    });
    for k in range[2].0..=range[2].1 {
        for j in range[1].0..=range[1].1 {
            for i in range[0].0..=range[0].1 {
                let c = [i, j, k];
                let mut index = [0usize; 3];
                let mut inside = true;
                for d in 0..3 {
                    let n = grid.n[d] as i64;
                    if grid.bc[d][0] == crate::grid::Bc::Periodic {
                        index[d] = c[d].rem_euclid(n) as usize;
                    } else if (0..n).contains(&c[d]) {
                        index[d] = c[d] as usize;
                    } else {
                        inside = false;
                    }
                }
                // A 2-D flow's one cell stands at its own centre.
                let centre = [0, 1, 2].map(|d| match grid.n[d] {
                    1 => 0.5 * grid.h[d],
                    _ => (c[d] as f64 + 0.5) * grid.h[d],
                });
                if inside {
                    f(grid.index(index), Point3::from(centre));
                }
            }
        }
    }
}

impl Coating {
    /// Coats the cells of `grid` near the canopy: `x` its vertices in the
    /// box's frame (xyz per vertex) [m], `triangles` its connectivity.
    pub fn new(grid: &Grid, x: &[f64], triangles: &[[usize; 3]]) -> Coating {
        let h = grid.spacing_range().1;
        let mut side = vec![0i8; grid.cells()];
        let mut nearest = vec![f64::INFINITY; grid.cells()];
        for t in triangles {
            let p = corners(x, t);
            let Some(n) = (p[1] - p[0]).cross(&(p[2] - p[0])).try_normalize(1e-300) else {
                continue;
            };
            let tri = Triangle::new(p[0], p[1], p[2]);
            let lo = [0, 1, 2].map(|d| p.iter().map(|q| q[d]).fold(f64::INFINITY, f64::min));
            let hi = [0, 1, 2].map(|d| p.iter().map(|q| q[d]).fold(f64::NEG_INFINITY, f64::max));
            for_cells_near(grid, lo, hi, h, |cell, centre| {
                let on = tri.project_local_point(&centre, true).point;
                let d = (centre - on).norm();
                if d <= h && d < nearest[cell] {
                    nearest[cell] = d;
                    let s = (centre - on).dot(&n);
                    side[cell] = if s < 0.0 { -1 } else { 1 };
                }
            });
        }
        let mut coating = Coating { side };
        for _ in 0..SWEEPS {
            coating.sweep(grid);
        }
        coating
    }

    /// Gives every uncoated cell beside a coated one that cell's side (the
    /// first found, should both sides touch it).
    fn sweep(&mut self, grid: &Grid) {
        let before = self.side.clone();
        for (cell, side) in self.side.iter_mut().enumerate() {
            if *side != 0 {
                continue;
            }
            let c = grid.coords(cell);
            'around: for d in (0..3).filter(|&d| grid.n[d] > 1) {
                for up in [false, true] {
                    if let Neighbour::Cell(m) = grid.neighbour(c, d, up) {
                        if before[m] != 0 {
                            *side = before[m];
                            break 'around;
                        }
                    }
                }
            }
        }
    }

    /// The pressure on side `s` (±1) of triangle `t` at its centre [Pa]:
    /// the least-squares plane through that side's coated cells from NEAR
    /// to FAR spacings off the triangle's plane. None where too few cells
    /// (fewer than the flow's dimensions + 1) are found.
    pub fn side_pressure(
        &self,
        grid: &Grid,
        p: &[f64],
        x: &[f64],
        t: &[usize; 3],
        s: i8,
    ) -> Option<f64> {
        let mut cells = Vec::new();
        self.side_cells(grid, x, t, s, &mut cells);
        fit(grid, p, x, t, &cells)
    }

    /// The cells side `s` of triangle `t` reads its pressure from, into `out`.
    fn side_cells(&self, grid: &Grid, x: &[f64], t: &[usize; 3], s: i8, out: &mut Vec<Cell>) {
        let Some((c, n)) = centre_normal(x, t) else {
            return;
        };
        let h = grid.spacing_range().1;
        let cc = c.coords.into();
        for_cells_near(grid, cc, cc, FAR.hypot(ASIDE) * h, |cell, centre| {
            if self.side[cell] != s {
                return;
            }
            let r = offset(grid, centre, c);
            let off = r.dot(&n) * s as f64;
            let aside = (r - n * r.dot(&n)).norm();
            if (NEAR..=FAR).contains(&off) && aside <= ASIDE {
                out.push((cell as u32, centre));
            }
        });
    }

    /// The cells every triangle's two sides read, as [`jumps`](Self::jumps) chooses them.
    pub fn select(&self, grid: &Grid, x: &[f64], triangles: &[[usize; 3]]) -> Selection {
        let mut sel = Selection::default();
        for t in triangles {
            for s in [-1, 1] {
                self.side_cells(grid, x, t, s, &mut sel.cells);
                sel.ends.push(sel.cells.len());
            }
        }
        sel
    }

    /// The jump p⁻ − p⁺ across every triangle [Pa] into `out`; 0 where a
    /// side has too few coated cells (a triangle at the canopy's edge, or
    /// one too close to another part of the canopy).
    pub fn jumps(
        &self,
        grid: &Grid,
        p: &[f64],
        x: &[f64],
        triangles: &[[usize; 3]],
        out: &mut [f64],
    ) {
        let selection = self.select(grid, x, triangles);
        selection.jumps(grid, p, x, triangles, out);
    }
}

/// The cells each side of each triangle reads its pressure from. Implicit
/// coupling keeps a window's first choice for its repeats: chosen again at
/// positions a little apart, a cell entering or leaving a side's band
/// would change the jump by a step, and the iteration would stall on it.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    cells: Vec<Cell>,
    /// Where each (triangle, side)'s cells end in `cells`: −1 then +1.
    ends: Vec<usize>,
}

impl Selection {
    /// The jump p⁻ − p⁺ across every triangle [Pa] into `out`, from these
    /// cells and the triangles where `x` puts them.
    pub fn jumps(
        &self,
        grid: &Grid,
        p: &[f64],
        x: &[f64],
        triangles: &[[usize; 3]],
        out: &mut [f64],
    ) {
        for (k, (t, o)) in triangles.iter().zip(out.iter_mut()).enumerate() {
            let side = |j: usize| {
                let from = if j == 0 { 0 } else { self.ends[j - 1] };
                fit(grid, p, x, t, self.cells.get(from..self.ends[j])?)
            };
            *o = match (side(2 * k), side(2 * k + 1)) {
                (Some(below), Some(above)) => below - above,
                _ => 0.0,
            };
        }
    }

    /// Whether it was chosen for `triangles` triangles.
    pub fn fits(&self, triangles: usize) -> bool {
        self.ends.len() == 2 * triangles
    }
}

/// A cell a side reads: its index, and its centre where it lies next to
/// the triangle (a periodic image's, across a periodic side).
type Cell = (u32, Point3<f64>);

/// Triangle `t`'s centre and unit normal (of its vertex order).
fn centre_normal(x: &[f64], t: &[usize; 3]) -> Option<(Point3<f64>, Vector3<f64>)> {
    let q = corners(x, t);
    let n = (q[1] - q[0]).cross(&(q[2] - q[0])).try_normalize(1e-300)?;
    Some((
        Point3::from((q[0].coords + q[1].coords + q[2].coords) / 3.0),
        n,
    ))
}

/// A cell centre's offset from `c` in spacings; none along a 2-D flow's
/// thin axis.
fn offset(grid: &Grid, centre: Point3<f64>, c: Point3<f64>) -> Vector3<f64> {
    let h = grid.spacing_range().1;
    let mut r: Vector3<f64> = (centre - c) / h;
    for d in (0..3).filter(|&d| grid.n[d] == 1) {
        r[d] = 0.0;
    }
    r
}

/// The pressure at triangle `t`'s centre from the least-squares plane
/// p ≈ p̄ + g·(x − x̄) through `cells` (offsets in spacings, about their
/// centroid x̄); None with too few cells, or cells that do not spread
/// along the normal.
fn fit(grid: &Grid, p: &[f64], x: &[f64], t: &[usize; 3], cells: &[Cell]) -> Option<f64> {
    let (c, n) = centre_normal(x, t)?;
    let mut sum_r = Vector3::<f64>::zeros();
    let mut sum_rr = Matrix3::<f64>::zeros();
    let mut sum_rp = Vector3::<f64>::zeros();
    let mut sum_p = 0.0;
    for &(cell, centre) in cells {
        let cell = cell as usize;
        let r = offset(grid, centre, c);
        sum_r += r;
        sum_rr += r * r.transpose();
        sum_rp += r * p[cell];
        sum_p += p[cell];
    }
    let dims = (0..3).filter(|&d| grid.n[d] > 1).count();
    if cells.len() < dims + 1 {
        return None;
    }
    let k = cells.len() as f64;
    let (mean_r, mean_p) = (sum_r / k, sum_p / k);
    let spread = sum_rr - mean_r * sum_r.transpose();
    let covary = sum_rp - mean_r * sum_p;
    // Directions the cells hardly spread along (a 2-D flow's thin axis)
    // get no gradient: the pseudo-inverse. Cells that do not spread
    // along the normal cannot be extrapolated to the sheet: none.
    let svd = spread.svd(true, true);
    let cutoff = 1e-2 * svd.singular_values.max();
    if !(n.dot(&(spread * n)) > cutoff) {
        return None;
    }
    let g = svd.solve(&covary, cutoff).ok()?;
    Some(mean_p - g.dot(&mean_r))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::grid::Bc;

    /// A flat sheet across a periodic box at x = x₀, and a pressure that is
    /// linear on each side with a step Δ across the sheet: the coating puts
    /// every cell near the sheet on its own side, and the jump read from it
    /// is Δ to round-off, where one plane through both sides would smear it.
    #[test]
    fn a_step_across_a_sheet_is_read_exactly() {
        let n = [32, 16, 16];
        let h = 1.0 / 16.0;
        let grid = Grid {
            n,
            h: [h; 3],
            bc: [[Bc::Periodic; 2]; 3],
        };
        let x0 = 1.03;
        // Two triangles spanning the box's y–z section at x₀, normal +x.
        let (ly, lz) = (1.0, 1.0);
        let x = [x0, 0.0, 0.0, x0, ly, 0.0, x0, ly, lz, x0, 0.0, lz];
        let triangles = [[0, 1, 2], [0, 2, 3]];
        let step = 7.0;
        let (gx, gy, gz) = (0.3, -1.1, 0.4);
        let mut p = vec![0.0; grid.cells()];
        for (cell, pc) in p.iter_mut().enumerate() {
            let c = grid.coords(cell).map(|i| (i as f64 + 0.5) * h);
            *pc = 10.0 + gx * c[0] + gy * c[1] + gz * c[2] + if c[0] < x0 { step } else { 0.0 };
        }
        let coating = Coating::new(&grid, &x, &triangles);
        // Every cell within a spacing of the sheet, and SWEEPS more, is
        // coated, on its side.
        for (cell, &s) in coating.side.iter().enumerate() {
            let cx = (grid.coords(cell)[0] as f64 + 0.5) * h;
            if (cx - x0).abs() <= (1 + SWEEPS) as f64 * h {
                assert_eq!(s, if cx < x0 { -1 } else { 1 }, "cell at x = {cx}");
            }
        }
        let mut jumps = [0.0; 2];
        coating.jumps(&grid, &p, &x, &triangles, &mut jumps);
        for j in jumps {
            assert!((j - step).abs() < 1e-10, "jump {j}");
        }
    }
}
