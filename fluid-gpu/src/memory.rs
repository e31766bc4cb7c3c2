//! Where each array sits in the device's one buffer of reals, and each
//! scalar in its buffer of scalars (flow.wgsl's slots).

use crate::spec::FlowBox;

/// One velocity component's arrays, each in its padded layout.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Component {
    /// uⁿ on its faces, ghosts filled at a step's start.
    pub u: usize,
    /// N = ∇·(u u_c) of the last two steps (which is which: `Flow`'s parity).
    pub n: [usize; 2],
    /// The right-hand side of the viscous solve.
    pub b: usize,
    /// δ = u* − uⁿ, kept as the next step's first guess.
    pub delta: usize,
    /// The conjugate-gradient direction, residual and operator's image.
    pub p: usize,
    pub r: usize,
    pub q: usize,
    /// uⁿ at the window's start, for the steady residual (`monitors`).
    pub before: usize,
}

/// One multigrid level's right-hand side, correction and residual.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Level {
    pub b: usize,
    pub x: usize,
    pub r: usize,
    pub cells: [usize; 3],
}

impl Level {
    pub fn count(&self) -> usize {
        self.cells.iter().product()
    }
}

/// The arrays of one box.
#[derive(Debug, Clone)]
pub(crate) struct Memory {
    pub comp: [Option<Component>; 3],
    /// Cell fields: the kinematic pressure q, the correction φ, the
    /// Poisson right-hand side, its CG's residual, preconditioned residual,
    /// direction and A·direction, and scratch.
    pub q: usize,
    pub phi: usize,
    pub rhs: usize,
    pub r: usize,
    pub z: usize,
    pub p: usize,
    pub ap: usize,
    pub scratch: usize,
    /// The multigrid's levels; level 0 takes the CG's r as b and z as x.
    pub levels: Vec<Level>,
    /// Reals in all.
    pub len: usize,
}

impl Memory {
    pub fn of(b: &FlowBox) -> Memory {
        let mut next = 0;
        let mut take = |len: usize| {
            let at = next;
            next += len;
            at
        };
        let comp = [0, 1, 2].map(|c| {
            b.active(c).then(|| {
                let len = b.padded_len(c);
                Component {
                    u: take(len),
                    n: [take(len), take(len)],
                    b: take(len),
                    delta: take(len),
                    p: take(len),
                    r: take(len),
                    q: take(len),
                    before: take(len),
                }
            })
        });
        let cells = b.cells();
        let [q, phi, rhs, r, z, p, ap, scratch] = [0; 8].map(|_| take(cells));
        let levels = b
            .levels()
            .iter()
            .enumerate()
            .map(|(l, &(n, _))| {
                let count = n.iter().product();
                match l {
                    0 => Level {
                        b: r,
                        x: z,
                        r: take(count),
                        cells: n,
                    },
                    _ => Level {
                        b: take(count),
                        x: take(count),
                        r: take(count),
                        cells: n,
                    },
                }
            })
            .collect();
        Memory {
            comp,
            q,
            phi,
            rhs,
            r,
            z,
            p,
            ap,
            scratch,
            levels,
            len: next,
        }
    }
}

/// The scalar slots every pass may read (flow.wgsl's constants of the
/// same names), then the multigrid levels' 1/h², then the solves' blocks.
pub(crate) mod slot {
    pub const DT: usize = 0;
    pub const AB0: usize = 1;
    pub const AB1: usize = 2;
    pub const ALPHA: usize = 3;
    pub const NU: usize = 4;
    pub const ONE: usize = 5;
    pub const ZERO: usize = 6;
    pub const HUGE: usize = 7;
    pub const TOL_V: usize = 8;
    pub const TOL_P: usize = 9;
    pub const CELLS: usize = 10;
    pub const COURANT: usize = 11;
    pub const FINITE: usize = 12;
    pub const TMP: usize = 13;
    pub const INV_H: usize = 14;
    pub const INV_H2: usize = 17;
    /// The given velocity of side (axis a, high) at 3(2a + high).
    pub const SIDE_U: usize = 20;
    /// The fluid's density [kg/m³], the markers' spacing h (the geometric
    /// mean across the flow's axes) and a cell's volume, for the forcing.
    pub const RHO: usize = 38;
    pub const SPACING: usize = 39;
    pub const CELL: usize = 40;
    /// The sides' given velocities after the step's change (they differ
    /// from SIDE_U's in a box that follows the parachute), the box's
    /// velocity over the ground then and its change over the step.
    pub const SIDE_END: usize = 41;
    pub const FRAME: usize = 59;
    pub const DV: usize = 62;
    /// The flow's monitors, summed on the device (flow.rs's `Monitors`):
    /// Σ|v|², Σv (3) and the largest |∇·u| over the cells, then the largest
    /// change of a face velocity since the window's start, per component.
    pub const MON: usize = 65;
    pub const LEVEL_H2: usize = 73;
    /// Slots a solve's block holds (flow.wgsl's DONE … SCALE).
    pub const BLOCK: usize = 16;
    pub const DONE: usize = 0;
    pub const ITER: usize = 1;
    pub const RR: usize = 2;
    pub const PQ: usize = 3;
    pub const STEP: usize = 4;
    pub const BETA: usize = 5;
    pub const RRN: usize = 7;
    pub const RZ: usize = 8;
    pub const RZN: usize = 9;
    pub const BB: usize = 10;
    pub const MEANB: usize = 11;
    pub const FAIL: usize = 12;
    pub const SCALE: usize = 13;

    /// The named constants the kernels read, as (name, slot).
    pub const NAMED: [(&str, usize); 26] = [
        ("DT", DT),
        ("AB0", AB0),
        ("AB1", AB1),
        ("ALPHA", ALPHA),
        ("NU", NU),
        ("ONE", ONE),
        ("ZERO", ZERO),
        ("HUGE", HUGE),
        ("TOL_V", TOL_V),
        ("TOL_P", TOL_P),
        ("CELLS", CELLS),
        ("COURANT", COURANT),
        ("FINITE", FINITE),
        ("TMP", TMP),
        ("INV_H", INV_H),
        ("INV_H2", INV_H2),
        ("SIDE_U", SIDE_U),
        ("LEVEL_H2", LEVEL_H2),
        ("RHO", RHO),
        ("SPACING", SPACING),
        ("CELL", CELL),
        ("SIDE_END", SIDE_END),
        ("FRAME", FRAME),
        ("DV", DV),
        ("MON", MON),
        ("BLOCK", BLOCK),
    ];
}

/// The first slot of solve k's block (0–2 the viscous components', 3 the
/// pressure's) on a box of `levels` multigrid levels.
pub(crate) fn block(levels: usize, k: usize) -> usize {
    slot::LEVEL_H2 + 3 * levels + slot::BLOCK * k
}

/// Scalar slots in all.
pub(crate) fn slots(levels: usize) -> usize {
    block(levels, 4)
}
