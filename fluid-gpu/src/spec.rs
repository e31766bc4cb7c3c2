//! The box the device steps: its cells, spacings, sides and viscosity, and
//! the layouts that follow from them: each velocity component on its faces
//! with three ghost layers a side (fluid-proc's `Padded`), the faces the
//! momentum equation updates, and the multigrid's levels.

/// What a side of the box does (fluid-proc's `side::Side`, less another
/// rank, which the device does not cover).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Side {
    /// The velocity on the side is given [m/s]: a wall, a lid, an inflow.
    Velocity([f64; 3]),
    /// A channel inflow: this peak velocity [m/s] times 4s(1 − s) across
    /// each direction along the side that is not periodic.
    Parabolic([f64; 3]),
    /// An outflow at p = 0.
    Outflow,
    /// Wraps to the opposite side, which must be periodic too.
    Periodic,
}

impl Side {
    /// The kind the kernels read (flow.wgsl's GIVEN, OUTFLOW, PERIODIC).
    pub(crate) fn kind(self) -> u32 {
        match self {
            Side::Velocity(_) => 0,
            Side::Outflow => 1,
            Side::Periodic => 2,
            Side::Parabolic(_) => 3,
        }
    }
}

/// Ghost layers a side along an axis more than one cell thick: WENO5
/// reads three values beyond a face.
pub const GHOSTS: usize = 3;

/// A uniform box of cells and its fluid.
#[derive(Debug, Clone, PartialEq)]
pub struct FlowBox {
    /// Cells along x, y, z (one along z: a 2-D flow, periodic in z).
    pub n: [usize; 3],
    /// Spacings [m].
    pub h: [f64; 3],
    /// `sides[d] = [low, high]` along axis d.
    pub sides: [[Side; 2]; 3],
    /// Kinematic viscosity ν [m²/s].
    pub nu: f64,
    /// Density ρ [kg/m³] (the porous fabric's drag on the air).
    pub density: f64,
}

/// The coarsest multigrid level has at most this many cells (fluid-proc's
/// multigrid.rs)…
const COARSEST_CELLS: usize = 64;

impl FlowBox {
    pub fn cells(&self) -> usize {
        self.n.iter().product()
    }

    /// Whether component c has faces to update (an axis one cell thick
    /// carries none: the z of a 2-D flow).
    pub fn active(&self, c: usize) -> bool {
        self.n[c] > 1
    }

    pub(crate) fn ghosts(&self) -> [usize; 3] {
        self.n.map(|n| if n > 1 { GHOSTS } else { 0 })
    }

    /// Component c's padded array: n + 1 faces along c, n cells elsewhere,
    /// and the ghosts.
    pub(crate) fn dims(&self, c: usize) -> [usize; 3] {
        let g = self.ghosts();
        [0, 1, 2].map(|a| self.n[a] + (a == c) as usize + 2 * g[a])
    }

    pub(crate) fn strides(&self, c: usize) -> [usize; 3] {
        let d = self.dims(c);
        [1, d[0], d[0] * d[1]]
    }

    pub fn padded_len(&self, c: usize) -> usize {
        self.dims(c).iter().product()
    }

    /// The faces of component c the momentum equation updates, as face
    /// coordinates [low, high) per axis: not a side face with a given
    /// velocity, nor the periodic repeat of face 0 (fluid-proc's `Padded::on`).
    pub(crate) fn unknown(&self, c: usize) -> [[usize; 2]; 3] {
        let [low, high] = self.sides[c];
        [0, 1, 2].map(|a| match a == c {
            true => [
                matches!(low, Side::Velocity(_) | Side::Parabolic(_)) as usize,
                self.n[c] + (high == Side::Outflow) as usize,
            ],
            false => [0, self.n[a]],
        })
    }

    /// φ is fixed nowhere (no outflow): A is singular, the solve mean-free.
    pub fn singular(&self) -> bool {
        !self.sides.iter().flatten().any(|&s| s == Side::Outflow)
    }

    /// The markers' spacing h: the geometric mean of the spacings across
    /// the flow's axes (fluid-proc's immersed.rs: ΔV_k = ΔA_k·h).
    pub(crate) fn spacing(&self) -> f64 {
        let active: Vec<f64> = (0..3)
            .filter(|&d| self.n[d] > 1)
            .map(|d| self.h[d])
            .collect();
        active
            .iter()
            .product::<f64>()
            .powf(1.0 / active.len() as f64)
    }

    /// The multigrid's levels, finest first: each halves every axis that
    /// has an even count of at least 4 cells (2 where periodic), as
    /// fluid-proc's `Grid::coarse_plans` does on a uniform box, until it
    /// has at most 64 cells or no axis halves. Cells and spacings.
    pub(crate) fn levels(&self) -> Vec<([usize; 3], [f64; 3])> {
        let mut levels = vec![(self.n, self.h)];
        loop {
            let (n, h) = *levels.last().unwrap();
            if n.iter().product::<usize>() <= COARSEST_CELLS {
                break;
            }
            let halves = [0, 1, 2].map(|d| {
                let least = if self.sides[d][0] == Side::Periodic {
                    2
                } else {
                    4
                };
                n[d].is_multiple_of(2) && n[d] >= least
            });
            if !halves.contains(&true) {
                break;
            }
            let next = [0, 1, 2].map(|d| if halves[d] { n[d] / 2 } else { n[d] });
            let h = [0, 1, 2].map(|d| if halves[d] { 2.0 * h[d] } else { h[d] });
            levels.push((next, h));
        }
        levels
    }

    /// The seam phase of cell `c` of a level of `n` cells: on how many
    /// axes it is the last cell of an odd periodic axis. There the cell's
    /// neighbour across the wrap, the axis's first cell, has its colour,
    /// and red–black Gauss–Seidel's colour is no longer a set of
    /// independent updates: fluid-proc sweeps a colour's cells in order,
    /// so the last cell reads the first's new value and the first the
    /// last's old one. The device sweeps each colour phase by phase (the
    /// same rule in projection.wgsl's `seam_phase`), which is that order
    /// with no two cells of one dispatch touching. (The kernels compute
    /// it; here for the rule's test.)
    #[cfg(test)]
    pub(crate) fn seam_phase(&self, n: [usize; 3], c: [usize; 3]) -> usize {
        (0..3)
            .filter(|&d| self.odd_seam(n, d) && c[d] + 1 == n[d])
            .count()
    }

    /// The seam phases a level of `n` cells has (1 where no axis is odd and
    /// periodic).
    pub(crate) fn seam_phases(&self, n: [usize; 3]) -> usize {
        1 + (0..3).filter(|&d| self.odd_seam(n, d)).count()
    }

    /// Whether axis d of a level of `n` cells wraps onto a cell of the
    /// same colour.
    fn odd_seam(&self, n: [usize; 3], d: usize) -> bool {
        self.sides[d][0] == Side::Periodic && n[d] % 2 == 1 && n[d] >= 3
    }

    /// Why the device cannot step this box, if it cannot.
    pub fn refused(&self) -> Option<String> {
        for d in 0..3 {
            let periodic = self.sides[d].map(|s| s == Side::Periodic);
            if periodic[0] != periodic[1] {
                return Some(format!("axis {d} is periodic on one side only"));
            }
            if self.n[d] == 0 || (self.n[d] == 1 && !periodic[0]) {
                return Some(format!("axis {d} one cell thick must be periodic"));
            }
            if self.h[d].is_nan() || self.h[d] <= 0.0 {
                return Some(format!("spacing {} along axis {d}", self.h[d]));
            }
        }
        (u32::try_from(self.padded_len(0) * 16).is_err())
            .then(|| "more faces than 32-bit indices reach".to_string())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Red–black Gauss–Seidel with the seam phases: on levels with odd
    /// periodic axes (5 × 3 periodic, 7 walled; 3 × 5 × 7 periodic), no
    /// two neighbours of one colour share a phase (a dispatch's updates are
    /// independent), and of two such neighbours the one fluid-proc sweeps
    /// first (the lower index: x fastest) has the lower phase, so the
    /// device reads what the CPU's ordered sweep reads.
    #[test]
    fn seam_phases_order_a_colours_neighbours_as_the_cpu_sweeps_them() {
        let wall = Side::Velocity([0.0; 3]);
        for (n, z) in [([5, 3, 7], wall), ([3, 5, 7], Side::Periodic)] {
            let b = FlowBox {
                n,
                h: [1.0; 3],
                sides: [[Side::Periodic; 2], [Side::Periodic; 2], [z; 2]],
                nu: 1.0,
                density: 1.0,
            };
            let index = |c: [usize; 3]| c[0] + n[0] * (c[1] + n[1] * c[2]);
            let mut across = 0;
            for k in 0..n[2] {
                for j in 0..n[1] {
                    for i in 0..n[0] {
                        let c = [i, j, k];
                        for d in 0..3 {
                            if b.sides[d][0] != Side::Periodic {
                                continue;
                            }
                            let mut m = c;
                            m[d] = (c[d] + 1) % n[d];
                            let colour = |c: [usize; 3]| c.iter().sum::<usize>() % 2;
                            if colour(m) != colour(c) {
                                continue;
                            }
                            across += 1;
                            let (pc, pm) = (b.seam_phase(n, c), b.seam_phase(n, m));
                            assert_ne!(pc, pm, "{c:?} and {m:?} share phase {pc}");
                            assert_eq!(index(m) < index(c), pm < pc, "{c:?}, {m:?}");
                        }
                    }
                }
            }
            let odd = (0..3).filter(|&d| b.sides[d][0] == Side::Periodic).count();
            assert_eq!(b.seam_phases(n), 1 + odd);
            assert!(across > 0, "{n:?}: the seams were crossed");
        }
    }
}
