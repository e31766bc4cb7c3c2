//! The passes of a step, as lists of dispatches, each with its `Op`
//! record (flow.wgsl): the step's start (ghosts, advection, the viscous
//! solves' first residuals), one iteration of the viscous solves, the
//! projection's start, one iteration of the pressure solve, and the step's
//! end (the gradient, the pressure update, the next step's Courant number).
//! The solves' iterations are lists of their own, which the host repeats
//! until every solve's flag says it is done (`flow.rs`).

use crate::memory::{block, slot, Memory};
use crate::pass::{Kernel, Pass, Rec, FORCING_RECORDS, WORKGROUP};
use crate::spec::FlowBox;
use gpu_device::workgroups;

/// Which solve a pass belongs to and whether it stops with it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Guard {
    solve: usize,
    guard: u32,
}

pub(crate) const NONE: Guard = Guard { solve: 0, guard: 0 };

/// The step's lists of passes and their records.
pub(crate) struct Plan {
    pub records: Vec<[u32; 20]>,
    /// The step's start, by the parity of the slot Nⁿ goes to.
    pub start: [Vec<Pass>; 2],
    pub viscous_iteration: Vec<Pass>,
    /// u* = uⁿ + δ with its sides.
    pub change: Vec<Pass>,
    /// The sides again, after the forcing.
    pub impose: Vec<Pass>,
    pub projection: Vec<Pass>,
    pub pressure_iteration: Vec<Pass>,
    pub end: Vec<Pass>,
    /// The Courant number of the state as it is (after an upload).
    pub measure: Vec<Pass>,
    /// u copied as the window's start, and the monitors since (`MON`).
    pub remember: Vec<Pass>,
    pub monitors: Vec<Pass>,
    /// Most partial sums a reduction writes.
    pub partials: usize,
    /// The first of the FORCING_RECORDS records the markers' passes take
    /// (written when the markers are, `flow.rs`).
    pub forcing: usize,
}

pub(crate) struct Builder<'a> {
    pub(crate) b: &'a FlowBox,
    pub(crate) mem: &'a Memory,
    records: Vec<[u32; 20]>,
    partials: usize,
}

impl Plan {
    pub fn of(b: &FlowBox, mem: &Memory) -> Plan {
        let mut x = Builder {
            b,
            mem,
            records: Vec::new(),
            partials: 1,
        };
        let start = [0, 1].map(|parity| x.start(parity));
        let viscous_iteration = x.viscous_iteration();
        let change = x.change();
        let mut impose = Vec::new();
        for (c, a) in x.active() {
            x.ghosts_from(&mut impose, c, a.u, false, slot::SIDE_END, NONE);
        }
        let projection = x.projection();
        let pressure_iteration = x.pressure_iteration();
        let end = x.end();
        let mut measure = Vec::new();
        x.courant(&mut measure, NONE);
        let remember = x.remember();
        let monitors = x.monitors();
        let forcing = x.records.len();
        x.records
            .extend(std::iter::repeat_n([0; 20], FORCING_RECORDS));
        Plan {
            records: x.records,
            start,
            viscous_iteration,
            change,
            impose,
            projection,
            pressure_iteration,
            end,
            measure,
            remember,
            monitors,
            partials: x.partials,
            forcing,
        }
    }
}

impl Builder<'_> {
    pub(crate) fn push(&mut self, list: &mut Vec<Pass>, kernel: Kernel, rec: Rec, g: Guard) {
        let rec = Rec {
            solve: g.solve,
            guard: g.guard,
            ..rec
        };
        let groups = match kernel {
            Kernel::Finish | Kernel::Scalar | Kernel::Coarsest => (1, 1),
            Kernel::Ghosts
            | Kernel::Divergence
            | Kernel::PoissonApply
            | Kernel::Smooth
            | Kernel::Restrict
            | Kernel::Prolong
            | Kernel::PressureUpdate
            | Kernel::Courant
            | Kernel::CellMonitor => workgroups(rec.count as u32, WORKGROUP),
            _ => workgroups(rec.threads() as u32, WORKGROUP),
        };
        list.push(Pass {
            kernel,
            op: self.records.len() as u32,
            groups,
        });
        self.records.push(rec.words());
    }

    fn pressure(&self) -> Guard {
        Guard {
            solve: block(self.mem.levels.len(), 3),
            guard: 1,
        }
    }

    fn viscous(&self, c: usize) -> Guard {
        Guard {
            solve: block(self.mem.levels.len(), c),
            guard: 1,
        }
    }

    /// Component c's box of faces: the unknown ones, or all (not the ghosts).
    fn faces(&self, c: usize, unknown: bool) -> Rec {
        let g = self.b.ghosts();
        let box_ = match unknown {
            true => self.b.unknown(c),
            false => [0, 1, 2].map(|a| [0, self.b.n[a] + (a == c) as usize]),
        };
        Rec {
            lo: [0, 1, 2].map(|a| box_[a][0] + g[a]),
            e: box_.map(|[lo, hi]| hi - lo),
            s: self.b.strides(c),
            comp: c,
            ..Rec::default()
        }
    }

    /// The ghosts of component c's array at `off` along every axis, the
    /// sides' velocities at the step's start.
    fn ghosts(&mut self, list: &mut Vec<Pass>, c: usize, off: usize, homogeneous: bool, g: Guard) {
        self.ghosts_from(list, c, off, homogeneous, slot::SIDE_U, g);
    }

    /// [`Builder::ghosts`] with the sides' velocities from `sides` on.
    fn ghosts_from(
        &mut self,
        list: &mut Vec<Pass>,
        c: usize,
        off: usize,
        homogeneous: bool,
        sides: usize,
        g: Guard,
    ) {
        let dims = self.b.dims(c);
        for a in (0..3).filter(|&a| self.b.ghosts()[a] > 0) {
            let rec = Rec {
                o: [off, 0, 0, 0],
                comp: c,
                aux: a,
                kind: homogeneous as u32,
                slot: sides,
                count: dims[(a + 1) % 3] * dims[(a + 2) % 3],
                ..Rec::default()
            };
            self.push(list, Kernel::Ghosts, rec, g);
        }
    }

    /// out = y + sign·s[coef]·z over `rec`'s box (no y: `y = None`); with
    /// `coef` the zero slot, out = y (or 0) without reading z, so that a
    /// NaN a failed step left there does not outlive the zeroing.
    #[allow(clippy::too_many_arguments)]
    pub(crate) fn lin(
        &mut self,
        list: &mut Vec<Pass>,
        rec: Rec,
        out: usize,
        y: Option<usize>,
        (negate, coef): (bool, usize),
        z: usize,
        g: Guard,
    ) {
        let rec = Rec {
            o: [out, y.unwrap_or(0), z, 0],
            kind: negate as u32 | (y.is_none() as u32) << 1 | ((coef == slot::ZERO) as u32) << 2,
            slot: coef,
            ..rec
        };
        self.push(list, Kernel::Lin, rec, g);
    }

    /// s[slot] ← the sum over `rec`'s box of x·y (kind 0), x (1) or the
    /// largest |x| (2); `mean` divides the sum by the box's size.
    #[allow(clippy::too_many_arguments)]
    fn reduce(
        &mut self,
        list: &mut Vec<Pass>,
        rec: Rec,
        (x, y): (usize, usize),
        kind: u32,
        mean: bool,
        slot: usize,
        g: Guard,
    ) {
        let threads = rec.threads();
        let (gx, gy) = workgroups(threads as u32, WORKGROUP);
        let partials = (gx * gy) as usize;
        self.partials = self.partials.max(partials);
        let r = Rec {
            o: [x, y, 0, 0],
            kind,
            ..rec
        };
        self.push(list, Kernel::Reduce, r, g);
        let finish = Rec {
            kind: match (kind, mean) {
                (2, _) => 1,
                (_, true) => 2,
                _ => 0,
            },
            aux: threads,
            slot,
            count: partials,
            ..Rec::default()
        };
        self.push(list, Kernel::Finish, finish, g);
    }

    /// The scalar step `kind` (flow.wgsl's `scalar`) of `g`'s solve.
    fn scalar(&mut self, list: &mut Vec<Pass>, kind: u32, g: Guard) {
        let rec = Rec {
            kind,
            ..Rec::default()
        };
        self.push(list, Kernel::Scalar, rec, g);
    }

    /// x ← x − its mean over the cells.
    pub(crate) fn remove_mean(&mut self, list: &mut Vec<Pass>, x: usize, g: Guard) {
        let cells = Rec::flat(self.b.cells());
        self.reduce(list, cells, (x, 0), 1, true, slot::TMP, g);
        let rec = Rec {
            o: [x, 0, 0, 0],
            slot: slot::TMP,
            ..cells
        };
        self.push(list, Kernel::Shift, rec, g);
    }

    /// The ghosts of u, Nⁿ into slot `parity` and each component's
    /// right-hand side; each viscous solve's first residual.
    fn start(&mut self, parity: usize) -> Vec<Pass> {
        let mut list = Vec::new();
        for (c, arrays) in self.active() {
            self.ghosts(&mut list, c, arrays.u, false, NONE);
        }
        for (c, a) in self.active() {
            let rec = Rec {
                o: [a.n[parity], a.n[1 - parity], a.b, 0],
                ..self.faces(c, true)
            };
            self.push(&mut list, Kernel::Rhs, rec, NONE);
        }
        for (c, a) in self.active() {
            let (g, unknown) = (self.viscous(c), self.faces(c, true));
            self.ghosts(&mut list, c, a.delta, true, NONE);
            let rec = Rec {
                o: [a.delta, a.b, a.r, a.p],
                ..unknown
            };
            self.push(&mut list, Kernel::HelmResidual, rec, NONE);
            self.reduce(
                &mut list,
                unknown,
                (a.b, a.b),
                0,
                false,
                g.solve + slot::BB,
                NONE,
            );
            self.reduce(
                &mut list,
                unknown,
                (a.r, a.r),
                0,
                false,
                g.solve + slot::RR,
                NONE,
            );
            self.scalar(&mut list, 0, Guard { guard: 0, ..g });
            // b = 0: δ = 0 exactly, whatever the guess.
            let zero = Guard { guard: 2, ..g };
            self.lin(
                &mut list,
                unknown,
                a.delta,
                None,
                (false, slot::ZERO),
                a.delta,
                zero,
            );
        }
        list
    }

    /// One conjugate-gradient iteration of every viscous solve.
    fn viscous_iteration(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        for (c, a) in self.active() {
            let (g, unknown) = (self.viscous(c), self.faces(c, true));
            self.ghosts(&mut list, c, a.p, true, g);
            let rec = Rec {
                o: [a.p, a.q, 0, 0],
                ..unknown
            };
            self.push(&mut list, Kernel::HelmApply, rec, g);
            self.reduce(
                &mut list,
                unknown,
                (a.p, a.q),
                0,
                false,
                g.solve + slot::PQ,
                g,
            );
            self.scalar(&mut list, 1, g);
            let step = g.solve + slot::STEP;
            self.lin(
                &mut list,
                unknown,
                a.delta,
                Some(a.delta),
                (false, step),
                a.p,
                g,
            );
            self.lin(&mut list, unknown, a.r, Some(a.r), (true, step), a.q, g);
            self.reduce(
                &mut list,
                unknown,
                (a.r, a.r),
                0,
                false,
                g.solve + slot::RRN,
                g,
            );
            self.scalar(&mut list, 3, g);
            let beta = (false, g.solve + slot::BETA);
            self.lin(&mut list, unknown, a.p, Some(a.r), beta, a.p, g);
        }
        list
    }

    /// u* = uⁿ + δ − Δv with its sides at the step's end.
    fn change(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        for (c, a) in self.active() {
            let unknown = self.faces(c, true);
            let one = (false, slot::ONE);
            self.lin(&mut list, unknown, a.u, Some(a.u), one, a.delta, NONE);
            // A box that follows the parachute: the air takes the frame's
            // body force −a·Δt (fluid-proc's frame.rs).
            let rec = Rec {
                o: [a.u, 0, 0, 0],
                slot: slot::DV + c,
                ..unknown
            };
            self.push(&mut list, Kernel::Shift, rec, NONE);
            self.ghosts_from(&mut list, c, a.u, false, slot::SIDE_END, NONE);
        }
        list
    }

    /// −∇·u*/Δt, and the pressure solve's first residual and direction.
    fn projection(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        let m = self.mem.clone();
        let cells = Rec::flat(self.b.cells());
        let g = self.pressure();
        let rec = Rec {
            o: [m.rhs, 0, 0, 0],
            ..cells
        };
        self.push(&mut list, Kernel::Divergence, rec, NONE);
        let rec = Rec {
            o: [m.phi, m.r, m.rhs, 0],
            kind: 1,
            ..cells
        };
        self.push(&mut list, Kernel::PoissonApply, rec, NONE);
        if self.b.singular() {
            self.remove_mean(&mut list, m.r, NONE);
            self.reduce(
                &mut list,
                cells,
                (m.rhs, 0),
                1,
                true,
                g.solve + slot::MEANB,
                NONE,
            );
        }
        self.reduce(
            &mut list,
            cells,
            (m.rhs, m.rhs),
            0,
            false,
            g.solve + slot::BB,
            NONE,
        );
        self.reduce(
            &mut list,
            cells,
            (m.r, m.r),
            0,
            false,
            g.solve + slot::RR,
            NONE,
        );
        self.scalar(&mut list, 4, Guard { guard: 0, ..g });
        self.precondition(&mut list, g);
        self.lin(&mut list, cells, m.p, None, (false, slot::ONE), m.z, g);
        self.reduce(
            &mut list,
            cells,
            (m.r, m.z),
            0,
            false,
            g.solve + slot::RZ,
            g,
        );
        list
    }

    /// One iteration of the pressure solve (fluid-proc's poisson.rs).
    fn pressure_iteration(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        let m = self.mem.clone();
        let cells = Rec::flat(self.b.cells());
        let g = self.pressure();
        let rec = Rec {
            o: [m.p, m.ap, 0, 0],
            ..cells
        };
        self.push(&mut list, Kernel::PoissonApply, rec, g);
        self.reduce(
            &mut list,
            cells,
            (m.p, m.ap),
            0,
            false,
            g.solve + slot::PQ,
            g,
        );
        self.scalar(&mut list, 2, g);
        let step = g.solve + slot::STEP;
        self.lin(&mut list, cells, m.r, Some(m.r), (true, step), m.ap, g);
        self.lin(&mut list, cells, m.phi, Some(m.phi), (false, step), m.p, g);
        self.reduce(
            &mut list,
            cells,
            (m.r, m.r),
            0,
            false,
            g.solve + slot::RRN,
            g,
        );
        self.scalar(&mut list, 5, g);
        self.precondition(&mut list, g);
        self.reduce(
            &mut list,
            cells,
            (m.r, m.z),
            0,
            false,
            g.solve + slot::RZN,
            g,
        );
        self.scalar(&mut list, 6, g);
        let beta = (false, g.solve + slot::BETA);
        self.lin(&mut list, cells, m.p, Some(m.z), beta, m.p, g);
        list
    }

    /// φ mean-free, u ← u* − Δt∇φ, the pressure update, and the Courant
    /// number of the new state.
    /// Submitted behind each batch of the pressure solve's iterations,
    /// each pass running only once the solve is done (guard 3), so that a
    /// step whose solve converges within its batch needs no submit more.
    fn end(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        let m = self.mem.clone();
        let g = Guard {
            guard: 3,
            ..self.pressure()
        };
        if self.b.singular() {
            self.remove_mean(&mut list, m.phi, g);
        }
        for (c, _) in self.active() {
            let rec = self.faces(c, false);
            self.push(&mut list, Kernel::Gradient, rec, g);
        }
        let cells = Rec::flat(self.b.cells());
        self.push(&mut list, Kernel::PressureUpdate, cells, g);
        self.courant(&mut list, g);
        list
    }

    /// Each component's u, ghosts and all, copied as the window's start.
    fn remember(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        for (c, a) in self.active() {
            let all = Rec {
                e: self.b.dims(c),
                s: self.b.strides(c),
                ..Rec::default()
            };
            self.lin(
                &mut list,
                all,
                a.before,
                None,
                (false, slot::ONE),
                a.u,
                NONE,
            );
        }
        list
    }

    /// The monitors into s[MON …]: Σ|v|², Σv and the largest |∇·u| over
    /// the cells, and each component's largest change since `remember`.
    fn monitors(&mut self) -> Vec<Pass> {
        let mut list = Vec::new();
        let cells = Rec::flat(self.b.cells());
        let scratch = self.mem.scratch;
        for kind in 0..5 {
            let rec = Rec {
                o: [scratch, 0, 0, 0],
                kind,
                ..cells
            };
            self.push(&mut list, Kernel::CellMonitor, rec, NONE);
            let reduce = if kind == 4 { 2 } else { 1 };
            let at = slot::MON + kind as usize;
            self.reduce(&mut list, cells, (scratch, 0), reduce, false, at, NONE);
        }
        for (c, a) in self.active() {
            let faces = Rec {
                o: [a.u, a.q, a.before, 0],
                ..self.faces(c, false)
            };
            self.push(&mut list, Kernel::FaceChange, faces, NONE);
            let at = slot::MON + 5 + c;
            self.reduce(&mut list, faces, (a.q, 0), 2, false, at, NONE);
        }
        list
    }

    /// s[COURANT] ← max over the cells of Σ_a|u_a|/h_a; s[FINITE] their
    /// sum, not finite where a velocity is not.
    fn courant(&mut self, list: &mut Vec<Pass>, g: Guard) {
        let cells = Rec::flat(self.b.cells());
        let scratch = self.mem.scratch;
        let rec = Rec {
            o: [scratch, 0, 0, 0],
            ..cells
        };
        self.push(list, Kernel::Courant, rec, g);
        self.reduce(list, cells, (scratch, 0), 2, false, slot::COURANT, g);
        self.reduce(list, cells, (scratch, 0), 1, false, slot::FINITE, g);
    }

    fn active(&self) -> Vec<(usize, crate::memory::Component)> {
        (0..3)
            .filter_map(|c| self.mem.comp[c].map(|a| (c, a)))
            .collect()
    }
}
