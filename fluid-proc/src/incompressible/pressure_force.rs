//! The pressure force on a body, dissertation eq. (2.40):
//! F_p = ∫_S (p − p₀) n̂ dA with n̂ into the body, that is −∮ p n dA with n
//! the outward normal (a uniform p₀ gives nothing over a closed surface),
//! and its torque −∮ (x − c) × p n dA.
//!
//! The pressure at the surface must come from the fluid's side only: inside
//! a body, and across the smeared forcing, the grid's pressure is not the
//! fluid's. As the dissertation's local index coating does for the canopy
//! (§3.3.2), it is read on the body's own side: sampled at 3 h and 4 h
//! along the outward normal, where the linear interpolation's cells lie
//! beyond the δ kernel's two cells from the (retracted) markers, and
//! extrapolated linearly to the surface. Within 5 cells of a wall the
//! samples read the wall's cells.

use crate::incompressible::grid::{Bc, Grid};
use crate::surface::Marker;

/// Where the pressure is sampled outside the surface, in grid spacings.
pub const SAMPLES: [f64; 2] = [3.0, 4.0];

/// A cell-centred value at point x (in the box's frame) [same unit],
/// linear between the nearest cell centres; a point beyond the outermost
/// centres takes the side cells' values (periodic axes wrap).
pub fn cell_value_at(grid: &Grid, values: &[f64], x: [f64; 3]) -> f64 {
    let mut index = [[0usize; 2]; 3];
    let mut weight = [[0.0; 2]; 3];
    for d in 0..3 {
        let n = grid.n[d] as i64;
        let r = grid.axes[d].coordinate(x[d]) - 0.5;
        let i = r.floor() as i64;
        let f = r - i as f64;
        let periodic = grid.bc[d][0] == Bc::Periodic;
        let place = |i: i64| {
            if periodic {
                i.rem_euclid(n) as usize
            } else {
                i.clamp(0, n - 1) as usize
            }
        };
        index[d] = [place(i), place(i + 1)];
        weight[d] = [1.0 - f, f];
    }
    let mut sum = 0.0;
    for (k, wk) in index[2].iter().zip(weight[2]) {
        for (j, wj) in index[1].iter().zip(weight[1]) {
            for (i, wi) in index[0].iter().zip(weight[0]) {
                sum += wk * wj * wi * values[i + grid.n[0] * (j + grid.n[1] * k)];
            }
        }
    }
    sum
}

/// The pressure at surface point `x` with outward normal `n`, read on the
/// fluid's side (`SAMPLES`) [Pa], `spacing` the grid's [m].
pub fn surface_pressure(grid: &Grid, p: &[f64], x: [f64; 3], n: [f64; 3], spacing: f64) -> f64 {
    let at = |a: f64| cell_value_at(grid, p, [0, 1, 2].map(|d| x[d] + a * spacing * n[d]));
    let [a, b] = SAMPLES;
    let (pa, pb) = (at(a), at(b));
    pa - a * (pb - pa) / (b - a)
}

/// Eq. (2.40) over a body's markers: the force [N] and the torque about
/// `centre` [N·m] of the pressure `p` [Pa]. `surface` is how far outside
/// the markers the surface lies [m] (the retraction).
pub fn pressure_load(
    grid: &Grid,
    p: &[f64],
    markers: &[Marker],
    centre: [f64; 3],
    spacing: f64,
    surface: f64,
) -> ([f64; 3], [f64; 3]) {
    let mut force = [0.0; 3];
    let mut torque = [0.0; 3];
    for m in markers {
        let x = [0, 1, 2].map(|d| m.x[d] + surface * m.normal[d]);
        let ps = surface_pressure(grid, p, x, m.normal, spacing);
        let f = m.normal.map(|n| -ps * n * m.area);
        // Along a 2-D flow's thin axis there is no moment arm.
        let r = [0, 1, 2].map(|d| {
            if grid.n[d] == 1 {
                0.0
            } else {
                x[d] - centre[d]
            }
        });
        for d in 0..3 {
            force[d] += f[d];
            torque[d] += r[(d + 1) % 3] * f[(d + 2) % 3] - r[(d + 2) % 3] * f[(d + 1) % 3];
        }
    }
    (force, torque)
}
