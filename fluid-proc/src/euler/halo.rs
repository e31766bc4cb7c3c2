//! The gas's ghost layers (part of `mod.rs`): beyond a side of
//! the box from the side's condition, and at a side another rank's slab
//! shares from that rank, three planes deep, or as deep as the bodies'
//! image points reach along the slab's axis when bodies stand in the gas.

use super::{for_cells, Compressible, GasSide};
use crate::comm::swap;
use crate::euler::gas::State;
use crate::layout::{Layout, GHOSTS};

impl Compressible {
    /// Takes `planes` ghost planes from each neighbouring rank along the
    /// slab's axis instead of GHOSTS (on one rank nothing changes): the
    /// reach of the bodies' image points
    /// (`fluid_section::flow::body_halo_cells`). Each slab must be at
    /// least that thick.
    pub fn widen_halo(&mut self, planes: usize) {
        let a = self.slab.axis;
        if self.comm.ranks() == 1 || planes <= self.lay.g[a] {
            return;
        }
        assert!(self.n[a] >= planes, "a slab thinner than its halo");
        let mut g = self.lay.g;
        g[a] = planes;
        let lay = Layout::cells_with(self.n, g);
        let mut u = vec![[0.0; 5]; lay.dims().iter().product()];
        for_cells(self.n, |c, _| {
            u[lay.at(c.map(|x| x as isize))] = self.u[self.at(c)]
        });
        self.lay = lay;
        self.start.clone_from(&u);
        self.u = u;
    }

    /// The ghosts of every axis more than one cell thick, axis by axis over
    /// the whole range of the others (edges and corners too): from the
    /// sides' conditions, or from the neighbouring rank at a side shared
    /// with it.
    pub(super) fn fill_ghosts(&mut self) {
        let lay = self.lay;
        let g = GHOSTS as isize;
        for a in 0..3 {
            if lay.g[a] == 0 {
                continue;
            }
            let (s, m) = (lay.stride[a] as isize, lay.m[a] as isize);
            let sides = self.setup.sides[a];
            let held = sides.map(|side| match side {
                GasSide::State(w) => self.setup.gas.conserved(w),
                _ => State::default(),
            });
            let shared = self.shared_sides(a);
            let u = &mut self.u;
            lay.for_each_line(a, |base| {
                let ix = |k: isize| (base as isize + k * s) as usize;
                if shared.iter().all(Option::is_some) {
                    return;
                }
                if sides == [GasSide::Periodic; 2] {
                    for k in 1..=g {
                        u[ix(-k)] = u[ix(m - k)];
                        u[ix(m - 1 + k)] = u[ix(k - 1)];
                    }
                    return;
                }
                for (side, up, held) in [(sides[0], false, held[0]), (sides[1], true, held[1])] {
                    if shared[up as usize].is_some() {
                        continue;
                    }
                    let (edge, dir) = if up { (m - 1, 1) } else { (0, -1) };
                    for k in 1..=g {
                        let ghost = match side {
                            GasSide::Wall => {
                                let mut v = u[ix(edge - dir * (k - 1))];
                                v[1 + a] = -v[1 + a];
                                v
                            }
                            GasSide::Outflow => u[ix(edge)],
                            // A periodic side facing another kind is
                            // refused by the scenario check.
                            GasSide::Periodic => u[ix(edge)],
                            GasSide::State(_) => held,
                        };
                        u[ix(edge + dir * k)] = ghost;
                    }
                }
            });
            if shared.iter().any(Option::is_some) {
                self.exchange_halo(a, shared);
            }
        }
    }

    /// The ranks this rank's low and high sides along `a` face, if any.
    pub(super) fn shared_sides(&self, a: usize) -> [Option<usize>; 2] {
        if a != self.slab.axis {
            return [None; 2];
        }
        let periodic = self.setup.sides[a] == [GasSide::Periodic; 2];
        self.slab.neighbours(self.comm.as_ref(), periodic)
    }

    /// The ghost layers along `a` from the neighbouring ranks: this rank's
    /// last planes (as many as its ghost layers, GHOSTS or the wider halo
    /// bodies need) go up as the next rank's low ghosts, its first ones
    /// down as the previous rank's high ghosts (wrapping round on a
    /// periodic axis). Planes span the whole padded range of the other axes.
    fn exchange_halo(&mut self, a: usize, shared: [Option<usize>; 2]) {
        let m = self.lay.m[a] as isize;
        let g = self.lay.g[a] as isize;
        let planes = |k0: isize| self.planes(a, k0..k0 + g);
        let (top, bottom) = (planes(m - g), planes(0));
        let mut from_below = vec![0.0; top.len()];
        let mut from_above = vec![0.0; bottom.len()];
        let comm = self.comm.as_ref();
        swap(
            comm,
            shared,
            &bottom,
            &mut from_above,
            &top,
            &mut from_below,
        );
        if shared[0].is_some() {
            self.set_planes(a, -g..0, &from_below);
        }
        if shared[1].is_some() {
            self.set_planes(a, m..m + g, &from_above);
        }
    }

    /// The states of the planes `k` along `a`, flattened.
    fn planes(&self, a: usize, k: std::ops::Range<isize>) -> Vec<f64> {
        let mut out = Vec::new();
        self.for_plane_cells(a, k, |p| out.extend_from_slice(&self.u[p]));
        out
    }

    fn set_planes(&mut self, a: usize, k: std::ops::Range<isize>, values: &[f64]) {
        let mut at = Vec::new();
        self.for_plane_cells(a, k, |p| at.push(p));
        for (p, v) in at.into_iter().zip(values.chunks_exact(5)) {
            self.u[p].copy_from_slice(v);
        }
    }

    /// Calls `f` with the index of every cell of planes `k` along `a`, over
    /// the whole padded range of the other axes, in one fixed order.
    fn for_plane_cells(&self, a: usize, k: std::ops::Range<isize>, mut f: impl FnMut(usize)) {
        let lay = self.lay;
        let s = lay.stride[a] as isize;
        for kk in k {
            lay.for_each_line(a, |base| f((base as isize + kk * s) as usize));
        }
    }
}
