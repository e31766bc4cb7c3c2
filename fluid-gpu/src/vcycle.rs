//! The multigrid V-cycle that preconditions the pressure solve, as a list
//! of dispatches (fluid-proc's multigrid.rs): two red–black sweeps before
//! and after each level's coarse correction, the coarsest level on one
//! workgroup.

use crate::memory::slot;
use crate::pass::{Kernel, Pass, Rec};
use crate::plan::{Builder, Guard};

/// Red–black sweeps before and after a level's coarse correction
/// (fluid-proc's multigrid.rs).
const SWEEPS: usize = 2;

impl Builder<'_> {
    /// z = M⁻¹r: one V-cycle from zero, mean-free where A is singular.
    pub(crate) fn precondition(&mut self, list: &mut Vec<Pass>, g: Guard) {
        self.cycle(list, 0, g);
        if self.b.singular() {
            self.remove_mean(list, self.mem.z, g);
        }
    }

    /// The V-cycle from level l (fluid-proc's multigrid.rs): two red–black
    /// sweeps before and after the coarse correction.
    fn cycle(&mut self, list: &mut Vec<Pass>, l: usize, g: Guard) {
        let levels = self.mem.levels.clone();
        let level = levels[l];
        let count = level.count();
        let here = Rec {
            comp: l,
            ..Rec::flat(count)
        };
        // Each colour is swept in its seam phases (spec.rs's `seam_phase`).
        let phases = self.b.seam_phases(level.cells) as u32;
        if l + 1 == levels.len() {
            let rec = Rec {
                o: [level.b, level.x, 0, 0],
                kind: phases,
                ..here
            };
            self.push(list, Kernel::Coarsest, rec, g);
            return;
        }
        self.lin(list, here, level.x, None, (false, slot::ZERO), level.x, g);
        let sweep = |x: &mut Builder, list: &mut Vec<Pass>, colour: usize| {
            for phase in 0..phases {
                let rec = Rec {
                    o: [level.b, level.x, 0, 0],
                    aux: colour,
                    kind: phase,
                    ..here
                };
                x.push(list, Kernel::Smooth, rec, g);
            }
        };
        for _ in 0..SWEEPS {
            sweep(self, list, 0);
            sweep(self, list, 1);
        }
        let rec = Rec {
            o: [level.x, level.r, level.b, 0],
            kind: 1,
            ..here
        };
        self.push(list, Kernel::PoissonApply, rec, g);
        let coarse = levels[l + 1];
        let rec = Rec {
            o: [level.r, coarse.b, 0, 0],
            comp: l,
            ..Rec::flat(coarse.count())
        };
        self.push(list, Kernel::Restrict, rec, g);
        self.cycle(list, l + 1, g);
        let rec = Rec {
            o: [level.x, coarse.x, 0, 0],
            ..here
        };
        self.push(list, Kernel::Prolong, rec, g);
        for _ in 0..SWEEPS {
            sweep(self, list, 1);
            sweep(self, list, 0);
        }
    }
}
