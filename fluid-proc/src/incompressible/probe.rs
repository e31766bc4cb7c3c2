//! Flow probes (`[[fluid.probes]]`): the pressure and velocity at named
//! points, as monitors, as OpenFOAM's `probes` function object reports
//! them. The value at a point is the trilinear interpolation of the cell
//! values around it, whose centres lie half a spacing in from the cells'
//! corners; across a periodic side it wraps, and within half a spacing of
//! any other side it takes the nearest cells' value.

use crate::incompressible::grid::{Bc, Grid};
use fluid_section::flow::Probe;
use participant::Monitor;

/// Each probe's monitors, in the order [`monitors`] reports them.
pub fn names(probes: &[Probe]) -> Vec<String> {
    probes
        .iter()
        .flat_map(|p| {
            let q = &p.name;
            [
                format!("probe_{q}_pressure"),
                format!("probe_{q}_velocity_x"),
                format!("probe_{q}_velocity_y"),
                format!("probe_{q}_velocity_z"),
            ]
        })
        .collect()
}

/// Each probe's pressure [Pa] and velocity [m/s] from the cell pressures
/// and velocities (`fields`, over the whole box `grid` whose low corner
/// is `origin`); NaN without them.
pub fn monitors(
    probes: &[Probe],
    grid: &Grid,
    origin: [f64; 3],
    fields: Option<(&[f64], &[f64])>,
) -> Vec<Monitor> {
    let values = probes.iter().flat_map(|p| {
        let x = [0, 1, 2].map(|d| p.point[d] - origin[d]);
        match fields {
            Some((pressure, velocity)) => {
                let v = value_at(grid, velocity, 3, x);
                [value_at(grid, pressure, 1, x)[0], v[0], v[1], v[2]]
            }
            None => [f64::NAN; 4],
        }
    });
    names(probes)
        .into_iter()
        .zip(values)
        .map(|(name, v)| Monitor::new(name, v))
        .collect()
}

/// The cells around point `x` (box frame [m]) and their weights: eight
/// (cell, weight) pairs, some repeated where the point lies on an axis of
/// one cell or near a side.
fn around(grid: &Grid, x: [f64; 3]) -> [(usize, f64); 8] {
    // Per axis: the lower and upper cell and the upper one's weight.
    let axis = |d: usize| -> (usize, usize, f64) {
        let n = grid.n[d];
        if n == 1 {
            return (0, 0, 0.0);
        }
        let s = grid.axes[d].coordinate(x[d]) - 0.5;
        let below = s.floor();
        let t = s - below;
        let periodic = grid.bc[d][0] == Bc::Periodic;
        let at = |i: f64| -> usize {
            match periodic {
                true => (i as i64).rem_euclid(n as i64) as usize,
                false => i.clamp(0.0, (n - 1) as f64) as usize,
            }
        };
        (at(below), at(below + 1.0), t)
    };
    let [(i0, i1, tx), (j0, j1, ty), (k0, k1, tz)] = [axis(0), axis(1), axis(2)];
    let mut out = [(0, 0.0); 8];
    for (m, o) in out.iter_mut().enumerate() {
        let (a, b, c) = (m & 1 == 1, m & 2 == 2, m & 4 == 4);
        let cell = [
            if a { i1 } else { i0 },
            if b { j1 } else { j0 },
            if c { k1 } else { k0 },
        ];
        let w = [(a, tx), (b, ty), (c, tz)]
            .iter()
            .map(|&(up, t)| if up { t } else { 1.0 - t })
            .product();
        *o = (grid.index(cell), w);
    }
    out
}

/// The value at point `x` (box frame [m]) of a cell field `values` with
/// `per` components per cell over the whole box `grid`.
pub fn value_at(grid: &Grid, values: &[f64], per: usize, x: [f64; 3]) -> Vec<f64> {
    let mut out = vec![0.0; per];
    for (cell, w) in around(grid, x) {
        for (c, o) in out.iter_mut().enumerate() {
            *o += w * values[per * cell + c];
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A field linear in the cell centres is read exactly between them;
    /// near a wall the nearest cells' value is taken, and across a
    /// periodic side the interpolation wraps.
    #[test]
    fn a_linear_field_is_read_exactly_between_cell_centres() {
        let grid = Grid::uniform(
            [6, 5, 4],
            [0.5, 0.25, 1.0],
            [[Bc::Neumann; 2], [Bc::Neumann; 2], [Bc::Periodic; 2]],
        );
        let f = |x: [f64; 3]| 2.0 + 0.3 * x[0] - 1.1 * x[1] + 0.7 * x[2];
        // f of each cell's centre, in spacings (c + ½ along each axis).
        let values: Vec<f64> = (0..grid.cells())
            .map(|i| f(grid.coords(i).map(|c| c as f64 + 0.5)))
            .collect();
        // A point given in spacings, in metres.
        let centre = |c: [f64; 3]| [0, 1, 2].map(|d| c[d] * grid.h[d]);
        let point = centre([2.9, 1.3, 1.75]);
        let read = value_at(&grid, &values, 1, point)[0];
        assert!((read - f([2.9, 1.3, 1.75])).abs() < 1e-12, "{read}");
        // Within half a spacing of a wall: the nearest centres' value along x.
        let near_wall = value_at(&grid, &values, 1, centre([0.2, 1.3, 1.75]))[0];
        assert!(
            (near_wall - f([0.5, 1.3, 1.75])).abs() < 1e-12,
            "{near_wall}"
        );
        // Across the periodic z side: halfway between the last and first cells.
        let wrapped = value_at(&grid, &values, 1, centre([2.9, 1.3, 4.0]))[0];
        let expect = 0.5 * (f([2.9, 1.3, 3.5]) + f([2.9, 1.3, 0.5]));
        assert!(
            (wrapped - expect).abs() < 1e-12,
            "{wrapped} against {expect}"
        );
    }
}
