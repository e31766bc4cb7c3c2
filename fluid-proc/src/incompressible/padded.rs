//! One velocity component on its MAC faces with three layers of ghost values
//! on every side, so that the WENO5 stencils of the advection term and the
//! Laplacian of the viscous term read the same way at a side as inside.
//!
//! The ghosts carry the side conditions (`side.rs`):
//! - a given velocity U: the normal component's side face is U itself and
//!   its ghosts mirror oddly about it (2U − u); the tangential components'
//!   ghosts mirror oddly about the side, half a cell away (2U − u);
//! - a parabolic inflow: the same, U times the profile at the face's place;
//! - an outflow: constant extrapolation of the last face or cell;
//! - periodic: the values from the other end;
//! - another rank's slab (`part.rs`): its faces, swapped in.
//!
//! An axis one cell thick (the z of a 2-D flow) has no ghosts: it is
//! periodic, and nothing varies along it.

use crate::incompressible::axis::Axis;
use crate::incompressible::faces::Faces;
use crate::incompressible::grid::Grid;
use crate::incompressible::part::Part;
use crate::incompressible::rows;
use crate::incompressible::side::{parabola, Side, Sides};
use crate::layout::Layout;

/// Component `c` of the velocity on its faces, with ghosts: on this
/// rank's slab of the box. Along the slab's axis its last face is the next
/// rank's first, which that rank updates.
#[derive(Debug, Clone)]
pub struct Padded {
    /// The component (the axis its faces are normal to).
    pub c: usize,
    pub lay: Layout,
    pub data: Vec<f64>,
    part: Part,
    /// The whole box's axes, for where a line lies across a parabolic side.
    axes: [Axis; 3],
}

impl Padded {
    /// On this rank's slab of the box `grid`.
    pub fn on(part: &Part, grid: &Grid, c: usize) -> Padded {
        let n = part.slab.cells();
        let sides = part.local_sides();
        // The faces normal to c: one more than the cells along c.
        let mut lay = Layout::cells(n);
        lay.m[c] += 1;
        let dims = lay.dims();
        lay.stride = [1, dims[0], dims[0] * dims[1]];
        lay.unknown[c] = [
            sides[c][0].given(1.0).is_some() as usize,
            n[c] + matches!(sides[c][1], Side::Outflow) as usize,
        ];
        Padded {
            c,
            lay,
            data: vec![0.0; dims.iter().product()],
            part: part.clone(),
            axes: grid.axes.clone(),
        }
    }

    /// The rank's part of the box the faces are on.
    pub fn part(&self) -> &Part {
        &self.part
    }

    /// Copies the component's faces (ghosts untouched).
    pub fn load(&mut self, u: &Faces) {
        self.load_from(&u.u[self.c]);
    }

    /// [`Padded::load`] from this component's faces `src`.
    pub fn load_from(&mut self, src: &[f64]) {
        let m = self.lay.m;
        let all = [0, 1, 2].map(|a| [0, m[a] as isize]);
        rows::each(&self.lay, all, [&mut self.data], |row, [d]| {
            let [_, j, k] = row.first.map(|x| x as usize);
            let s = m[0] * (j + m[1] * k);
            d[row.offset..row.offset + m[0]].copy_from_slice(&src[s..s + m[0]]);
        });
    }

    /// Copies every face back, sides and periodic repeats included.
    pub fn store(&self, u: &mut Faces) {
        self.store_into(&mut u.u[self.c]);
    }

    /// [`Padded::store`] into this component's faces `u`.
    pub fn store_into(&self, u: &mut [f64]) {
        let m = self.lay.m;
        let lay = self.lay;
        rows::each_plain(u, m, |j, k, dst| {
            let s = lay.at([0, j as isize, k as isize]);
            dst.copy_from_slice(&self.data[s..s + m[0]]);
        });
    }

    /// Sets the side faces and fills the ghosts from the values inside, axis
    /// by axis over the whole range of the others, so edges and corners
    /// come out right too. The slab's axis is the last with ghosts, so the
    /// planes swapped with the neighbours carry their edges already.
    pub fn fill_ghosts(&mut self, sides: &Sides) {
        let lay = self.lay;
        for (a, &pair) in sides.iter().enumerate() {
            if lay.g[a] > 0 {
                lay.for_each_line(a, |base| {
                    let profile = self.profile(sides, base, a);
                    self.fill_line(base, a, pair, profile)
                });
            }
        }
        self.swap_ghosts();
    }

    /// The ghost planes along the slab's axis from the neighbouring ranks:
    /// the three planes of cells (or faces) beyond each side; for the
    /// normal component also the last face, the next rank's first.
    fn swap_ghosts(&mut self) {
        if !self.part.split() {
            return;
        }
        let a = self.part.axis_of();
        let (g, m) = (self.lay.g[a], self.lay.m[a]);
        let plane = self.lay.stride[a];
        // The entries of planes [from, to) along a (the slowest axis).
        let planes = |from: usize, to: usize| from * plane..to * plane;
        let shared = (self.c == a) as usize;
        let down = self.data[planes(g, 2 * g + shared)].to_vec();
        let up = self.data[planes(m - shared, m + g - shared)].to_vec();
        let mut from_up = vec![0.0; down.len()];
        let mut from_down = vec![0.0; up.len()];
        self.part.swap(&down, &mut from_up, &up, &mut from_down);
        if self.part.neighbour(true).is_some() {
            self.data[planes(g + m - shared, 2 * g + m)].copy_from_slice(&from_up);
        }
        if self.part.neighbour(false).is_some() {
            self.data[planes(0, g)].copy_from_slice(&from_down);
        }
    }

    /// The shape factor of a parabolic side for the line along `a` whose
    /// entry 0 is at `base`: `parabola` of the line's place across each
    /// other axis that is not periodic (1 on a line of a uniform side), in
    /// the whole box.
    fn profile(&self, sides: &Sides, base: usize, a: usize) -> f64 {
        if !sides[a].iter().any(|s| matches!(s, Side::Parabolic(_))) {
            return 1.0;
        }
        let lay = &self.lay;
        let dims = lay.dims();
        let slab = &self.part.slab;
        let mut f = 1.0;
        for t in (0..3).filter(|&t| t != a && self.part.sides[t][0] != Side::Periodic) {
            let i = (base / lay.stride[t]) % dims[t];
            let mut i = i as f64 - lay.g[t] as f64;
            let mut m = lay.m[t];
            if t == slab.axis {
                i += slab.lo as f64;
                m += slab.n[t] - (slab.hi - slab.lo);
            }
            // Faces along c sit at i·h, cells elsewhere at (i + ½)·h; on a
            // graded axis, where its faces and centres are.
            let axis = &self.axes[t];
            let s = match (axis.is_uniform(), t == self.c) {
                (true, true) => i / (m - 1) as f64,
                (true, false) => (i + 0.5) / m as f64,
                (false, true) => {
                    let f = (i.max(0.0) as usize).min(axis.n());
                    axis.face(f) / axis.length() + (i - f as f64)
                }
                (false, false) => axis.centre(i as i64) / axis.length(),
            };
            // A ghost line beyond a wall takes the wall's value (zero).
            f *= parabola(s.clamp(0.0, 1.0));
        }
        f
    }

    /// The ghosts of one line along axis a, whose face 0 is at `base`.
    fn fill_line(&mut self, base: usize, a: usize, sides: [Side; 2], profile: f64) {
        let s = self.lay.stride[a] as isize;
        let g = self.lay.g[a] as isize;
        let m = self.lay.m[a] as isize;
        let c = self.c;
        let normal = a == c;
        // The last face or cell (for the normal component face n = m − 1).
        let last = m - 1;
        let d = &mut self.data;
        let ix = |k: isize| (base as isize + k * s) as usize;
        match sides {
            [Side::Periodic, Side::Periodic] => {
                // Normal: face n repeats face 0, and the period is n = m − 1.
                let period = if normal { m - 1 } else { m };
                if normal {
                    d[ix(last)] = d[ix(0)];
                }
                for k in 1..=g {
                    d[ix(-k)] = d[ix(period - k)];
                    d[ix(last + k)] = d[ix(last - period + k)];
                }
            }
            [low, high] => {
                for (side, up) in [(low, false), (high, true)] {
                    let (edge, dir) = if up { (last, 1) } else { (0, -1) };
                    match (side, side.given(profile)) {
                        (_, Some(u)) if normal => {
                            d[ix(edge)] = u[c];
                            for k in 1..=g {
                                d[ix(edge + dir * k)] = 2.0 * u[c] - d[ix(edge - dir * k)];
                            }
                        }
                        (_, Some(u)) => {
                            for k in 1..=g {
                                d[ix(edge + dir * k)] = 2.0 * u[c] - d[ix(edge - dir * (k - 1))];
                            }
                        }
                        (Side::Outflow, _) => {
                            for k in 1..=g {
                                d[ix(edge + dir * k)] = d[ix(edge)];
                            }
                        }
                        // A periodic side facing a non-periodic one is
                        // refused when the flow is built.
                        _ => {}
                    }
                }
            }
        }
    }
}
