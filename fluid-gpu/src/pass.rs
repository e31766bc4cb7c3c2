//! A dispatch of a step: its kernel, its `Op` record (flow.wgsl) and its
//! workgroups; the forcing's fixed counts.

/// Threads a workgroup (flow.wgsl's WG).
pub(crate) const WORKGROUP: u32 = 256;

/// The kernels, in the order `KERNELS` names their entry points.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Kernel {
    Ghosts,
    Rhs,
    HelmResidual,
    HelmApply,
    Lin,
    Shift,
    Reduce,
    Finish,
    Scalar,
    Divergence,
    PoissonApply,
    Smooth,
    Restrict,
    Prolong,
    Coarsest,
    Gradient,
    PressureUpdate,
    Courant,
    Interpolate,
    Pushes,
    Spread,
    CellMonitor,
    FaceChange,
}

pub(crate) const KERNELS: [&str; 23] = [
    "ghosts",
    "rhs",
    "helm_residual",
    "helm_apply",
    "lin",
    "shift",
    "reduce",
    "finish",
    "scalar",
    "divergence",
    "poisson_apply",
    "sweep",
    "restriction",
    "prolongation",
    "coarsest",
    "gradient",
    "pressure_update",
    "courant",
    "interpolate",
    "pushes",
    "spread",
    "cell_monitor",
    "face_change",
];

/// Threads a workgroup of `spread` (flow.wgsl): a thread a block.
pub(crate) const SPREAD_WORKGROUP: u32 = 64;

/// Forcing passes a step (fluid-proc's FORCING_PASSES, and the porous
/// sheets' one before them).
pub(crate) const FORCING_PASSES: usize = 1 + 4;

/// Colours a block may have (3 along each axis).
const COLOURS: usize = 27;

/// Records the forcing's passes may take: each pass's interpolation,
/// pushes and a spread per colour.
pub(crate) const FORCING_RECORDS: usize = FORCING_PASSES * (2 + COLOURS);

/// One dispatch: its kernel, its `Op` record and its workgroups.
#[derive(Debug, Clone, Copy)]
pub(crate) struct Pass {
    // (kernel, record, workgroups)
    pub kernel: Kernel,
    pub op: u32,
    pub groups: (u32, u32),
}

/// An `Op` record (flow.wgsl), field for field.
#[derive(Debug, Clone, Copy, Default)]
pub(crate) struct Rec {
    pub o: [usize; 4],
    pub lo: [usize; 3],
    pub kind: u32,
    pub e: [usize; 3],
    pub comp: usize,
    pub s: [usize; 3],
    pub aux: usize,
    pub slot: usize,
    pub solve: usize,
    pub guard: u32,
    pub count: usize,
}

impl Rec {
    pub fn words(&self) -> [u32; 20] {
        let w = |x: usize| x as u32;
        [
            w(self.o[0]),
            w(self.o[1]),
            w(self.o[2]),
            w(self.o[3]),
            w(self.lo[0]),
            w(self.lo[1]),
            w(self.lo[2]),
            self.kind,
            w(self.e[0]),
            w(self.e[1]),
            w(self.e[2]),
            w(self.comp),
            w(self.s[0]),
            w(self.s[1]),
            w(self.s[2]),
            w(self.aux),
            w(self.slot),
            w(self.solve),
            self.guard,
            w(self.count),
        ]
    }

    /// A box over `count` cells in a row.
    pub fn flat(count: usize) -> Rec {
        Rec {
            e: [count, 1, 1],
            s: [1, 0, 0],
            count,
            ..Rec::default()
        }
    }

    pub fn threads(&self) -> usize {
        self.e.iter().product()
    }
}

/// Bytes of a record in the uniform buffer.
pub(crate) const RECORD_BYTES: usize = 80;
