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

use crate::incompressible::grid::{Grid, Neighbour};
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
        let a = &grid.axes[d];
        let first = (a.coordinate(lo[d] - reach) - 0.5).ceil() as i64;
        let last = (a.coordinate(hi[d] + reach) - 0.5).floor() as i64;
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
                    if grid.bc[d][0] == crate::incompressible::grid::Bc::Periodic {
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
                    _ => grid.axes[d].centre(c[d]),
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

    /// The cells every triangle's two sides read and how, as
    /// [`jumps`](Self::jumps) chooses them, for the triangles where `x`
    /// puts them.
    pub fn select(&self, grid: &Grid, x: &[f64], triangles: &[[usize; 3]]) -> Selection {
        let mut sel = Selection::default();
        let mut cells = Vec::new();
        for t in triangles {
            for s in [-1, 1] {
                cells.clear();
                self.side_cells(grid, x, t, s, &mut cells);
                let (coefficients, weight) =
                    plane(grid, x, t, &cells).unwrap_or_else(|| (vec![0.0; cells.len()], 0.0));
                sel.cells.extend(cells.iter().map(|c| c.0));
                sel.coefficients.extend(coefficients);
                sel.ends.push(sel.cells.len());
                sel.weights.push(weight);
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
        self.select(grid, x, triangles).jumps(p, out);
    }
}

/// The cells each side of each triangle reads its pressure from, and how:
/// the least-squares plane through them, taken at the triangle's centre,
/// is a fixed sum Σ a_c·p_c over them, and the side counts with a weight
/// from 0 (too few cells, or cells that do not spread along the normal)
/// to 1. Implicit coupling keeps a window's first choice for its repeats:
/// chosen again at positions a little apart, a cell entering or leaving a
/// side's band, or a side's weight or plane turning steeply, would change
/// the jump by a step, and the iteration would stall on it.
#[derive(Debug, Clone, Default)]
pub struct Selection {
    cells: Vec<u32>,
    /// a_c of each cell in `cells`.
    coefficients: Vec<f64>,
    /// Where each (triangle, side)'s cells end in `cells`: −1 then +1.
    ends: Vec<usize>,
    /// Each (triangle, side)'s weight.
    weights: Vec<f64>,
}

impl Selection {
    /// The jump w⁻·w⁺·(p⁻ − p⁺) across every triangle [Pa] into `out`,
    /// from the pressures `p` [Pa] of the whole box.
    pub fn jumps(&self, p: &[f64], out: &mut [f64]) {
        let side = |j: usize| {
            let from = if j == 0 { 0 } else { self.ends[j - 1] };
            let cells = self.cells[from..self.ends[j]].iter();
            let sum: f64 = (cells.zip(&self.coefficients[from..]))
                .map(|(&c, a)| a * p[c as usize])
                .sum();
            (sum, self.weights[j])
        };
        for (k, o) in out.iter_mut().enumerate().take(self.weights.len() / 2) {
            let ((below, w_below), (above, w_above)) = (side(2 * k), side(2 * k + 1));
            *o = w_below * w_above * (below - above);
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

/// A direction the cells spread along less than this fraction of their
/// largest spread gets no gradient, one beyond twice it all of it, and one
/// between a part rising smoothly (`ramp`): a hard cut would make the
/// jump read step as the sheet turns a little, and the tries of an
/// implicit window stall on such a step.
const SPREAD_CUT: f64 = 1e-2;

/// 0 up to `cut`, 1 from 2·`cut` on, and C¹ between (smoothstep).
fn ramp(s: f64, cut: f64) -> f64 {
    let t = ((s - cut) / cut).clamp(0.0, 1.0);
    t * t * (3.0 - 2.0 * t)
}

/// The least-squares plane p ≈ p̄ + g·(x − x̄) through the pressures of
/// `cells` (offsets in spacings, about their centroid x̄), taken at
/// triangle `t`'s centre, as a fixed sum Σ a_c·p_c: the coefficients a_c,
/// and how far the cells spread along the normal to be extrapolated to
/// the sheet, from 0 (not at all) to 1 ([`SPREAD_CUT`]). None with too few
/// cells.
fn plane(grid: &Grid, x: &[f64], t: &[usize; 3], cells: &[Cell]) -> Option<(Vec<f64>, f64)> {
    let (c, n) = centre_normal(x, t)?;
    let dims = (0..3).filter(|&d| grid.n[d] > 1).count();
    if cells.len() < dims + 1 {
        return None;
    }
    let r: Vec<Vector3<f64>> = cells.iter().map(|&(_, at)| offset(grid, at, c)).collect();
    let k = r.len() as f64;
    let mean_r = r.iter().sum::<Vector3<f64>>() / k;
    let spread: Matrix3<f64> = r
        .iter()
        .map(|r| (r - mean_r) * (r - mean_r).transpose())
        .sum();
    // Directions the cells hardly spread along (a 2-D flow's thin axis)
    // get no gradient: a pseudo-inverse M of the spread, its cut ramped.
    let svd = spread.svd(true, true);
    let cut = SPREAD_CUT * svd.singular_values.max();
    let (Some(u), Some(v_t)) = (svd.u, svd.v_t) else {
        return None;
    };
    if !(cut > 0.0) {
        return None;
    }
    let mut m = Matrix3::<f64>::zeros();
    for (i, &s) in svd.singular_values.iter().enumerate() {
        let part = ramp(s, cut);
        if part > 0.0 {
            m += v_t.row(i).transpose() * u.column(i).transpose() * (part / s);
        }
    }
    // g = M·Σ (r_c − r̄) p_c, so p(centre) = p̄ − g·r̄ = Σ [1/k − (Mᵀr̄)·(r_c − r̄)] p_c.
    let pull = m.transpose() * mean_r;
    let a = r
        .iter()
        .map(|rc| 1.0 / k - pull.dot(&(rc - mean_r)))
        .collect();
    // Cells that do not spread along the normal cannot be extrapolated
    // to the sheet: their weight falls to 0.
    Some((a, ramp(n.dot(&(spread * n)), cut)))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::incompressible::grid::Bc;

    /// A flat sheet across a periodic box at x = x₀, and a pressure that is
    /// linear on each side with a step Δ across the sheet: the coating puts
    /// every cell near the sheet on its own side, and the jump read from it
    /// is Δ to round-off, where one plane through both sides would smear it.
    #[test]
    fn a_step_across_a_sheet_is_read_exactly() {
        let n = [32, 16, 16];
        let h = 1.0 / 16.0;
        let grid = Grid::uniform(n, [h; 3], [[Bc::Periodic; 2]; 3]);
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
