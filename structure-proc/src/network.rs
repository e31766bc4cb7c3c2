//! The spring-mass network: what a step reads and does not move. The
//! nodes' masses and kinds, the springs, membrane triangles and dampers, the
//! canopy's triangles, gravity and the porous load, and what [`Network::prepare`]
//! derives from them for the integrators and the force assembly. The state
//! (positions, velocities) and the step's inputs (Δt, time, loads) are apart
//! (`model.rs`, [`crate::forces::Loads`]), in the manner of Rapier's step functions.

use crate::forces::assembly::{Assembly, Scratch};
use crate::forces::damper_batch::DamperBatch;
use crate::forces::damping::{Damper, Law};
use crate::forces::delingette::TriangleSprings;
use crate::forces::kept::Kept;
use crate::forces::membrane_batch::MembraneBatch;
pub use crate::forces::spring::Spring;
use crate::forces::spring_blocks::SpringBlocks;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    Free,
    /// Held in place (Dirichlet condition, e.g. the canopy rim of thesis §2.2).
    Fixed,
    /// Moved by a rigid body; the index is into [`crate::Model::attachments`].
    Attached(usize),
}

#[derive(Debug, Clone, Default)]
pub struct Network {
    /// Lumped masses [kg]; zero for fixed and attached nodes.
    pub mass: Vec<f64>,
    pub kind: Vec<NodeKind>,
    pub springs: Vec<Spring>,
    /// Delingette's triangular springs of a membrane fabric.
    pub membrane: Vec<TriangleSprings>,
    /// Dampers along springs and triangle edges, and the law they follow (None:
    /// undamped). When damped, `dampers[i]` belongs to `springs[i]`; the membrane
    /// edges' dampers follow (a broken line silences both).
    pub dampers: Vec<Damper>,
    pub damping: Option<Law>,
    /// Canopy triangles (nodes `0..canopy_nodes`), counter-clockwise seen along +n.
    pub triangles: Vec<[usize; 3]>,
    /// The canopy occupies nodes `0..canopy_nodes`; strings follow.
    pub canopy_nodes: usize,
    pub gravity: [f64; 3],
    /// The Darcy–Forchheimer load of a free stream through the canopy
    /// triangles (thesis eqs. 6–10), when the structure applies it itself.
    pub porous: Option<porous::Porous>,
    /// 1/m for free nodes, 0 for fixed and attached ones; set by [`Network::prepare`].
    pub inv_mass: Vec<f64>,
    /// Stiffness between node pairs, for Kang's method; set by [`Network::prepare`].
    pub couplings: Vec<(usize, usize, f64)>,
    /// Which slots each node sums; set by [`Network::prepare`].
    pub assembly: Assemblies,
    /// The springs' forces block by block of nodes; set by [`Network::prepare`].
    pub spring_blocks: SpringBlocks,
    /// The membrane's triangles field by field, for the force; set by [`Network::prepare`].
    pub membrane_batch: MembraneBatch,
    /// The dampers field by field, for the force; set by [`Network::prepare`].
    pub damper_batch: DamperBatch,
    /// The slot buffer of the force evaluations, reused from step to step.
    pub scratch: Scratch,
    /// The force's position-only terms from the last evaluation that kept
    /// them; forgotten by [`Network::prepare`].
    pub kept: Kept,
}

impl Network {
    pub fn nodes(&self) -> usize {
        self.mass.len()
    }

    /// Derive what the integrators read from the nodes and elements: the
    /// inverse masses, the stiffness couplings, the force assembly and its
    /// batches, and forget the force's kept terms (`forces/kept.rs`). Call
    /// after building or changing anything here: nodes (masses, kinds),
    /// elements, gravity, the porous law.
    pub fn prepare(&mut self) {
        self.inv_mass = (0..self.nodes())
            .map(|n| match self.kind[n] {
                NodeKind::Free if self.mass[n] > 0.0 => 1.0 / self.mass[n],
                _ => 0.0,
            })
            .collect();
        self.couplings = self.springs.iter().map(|s| (s.i, s.j, s.k)).collect();
        for t in &self.membrane {
            self.couplings.extend(t.edge_stiffness());
        }
        self.assembly = assembly(self);
        self.spring_blocks = SpringBlocks::new(&self.springs, self.nodes());
        self.membrane_batch = MembraneBatch::new(&self.membrane, self.nodes());
        self.damper_batch = DamperBatch::new(&self.dampers, self.nodes());
        self.kept = Kept::default();
    }
}

/// Where each family of elements keeps its slots: springs (one each),
/// membrane edges (three per triangle), dampers (one each). Ends at `end`.
/// The pressure triangles have an assembly of their own (one slot per
/// triangle, shared by its three vertices), summed only when a fluid sends a load.
pub(crate) struct Layout {
    pub membrane: usize,
    pub dampers: usize,
    pub end: usize,
}

impl Layout {
    pub(crate) fn of(m: &Network) -> Layout {
        let membrane = m.springs.len();
        let dampers = membrane + 3 * m.membrane.len();
        Layout {
            membrane,
            dampers,
            end: dampers + m.dampers.len(),
        }
    }
}

/// Which slots each node sums.
#[derive(Debug, Clone, Default)]
pub struct Assemblies {
    /// The elastic and viscous elements: springs, membrane edges, dampers
    /// ([`Layout`]), for the Jacobian products.
    pub elements: Assembly,
    /// The membrane's edges alone (slot 0 is the first edge's), and then
    /// the dampers alone, for the force: the springs' part is
    /// [`SpringBlocks`]'s. A node adds its membrane slots and then its
    /// dampers' in the order of `elements`, so the two passes sum as one.
    pub membrane: Assembly,
    pub dampers: Assembly,
    /// The pressure triangles.
    pub pressure: Assembly,
}

/// Which slots every node sums: the elastic and viscous elements, then the
/// pressure triangles. Built by [`Network::prepare`].
fn assembly(m: &Network) -> Assemblies {
    let at = Layout::of(m);
    let pair =
        |base: usize, k: usize, i: usize, j: usize| [(i, base + k, false), (j, base + k, true)];
    let springs = || {
        m.springs
            .iter()
            .enumerate()
            .flat_map(move |(k, s)| pair(0, k, s.i, s.j))
    };
    // Membrane edges and dampers, their slots counted from `base`.
    let membrane = move |base: usize| {
        m.membrane.iter().enumerate().flat_map(move |(k, t)| {
            (0..3).flat_map(move |e| {
                let (a, b) = t.edge(e);
                pair(base, 3 * k + e, a, b)
            })
        })
    };
    let dampers = move |base: usize| {
        m.dampers
            .iter()
            .enumerate()
            .flat_map(move |(k, d)| pair(base, k, d.i, d.j))
    };
    let pressure = Assembly::new(m.nodes(), m.triangles.len(), || {
        m.triangles
            .iter()
            .enumerate()
            .flat_map(|(k, tri)| tri.map(|n| (n, k, false)))
    });
    Assemblies {
        elements: Assembly::new(m.nodes(), at.end, || {
            springs()
                .chain(membrane(at.membrane))
                .chain(dampers(at.dampers))
        }),
        membrane: Assembly::new(m.nodes(), at.dampers - at.membrane, || membrane(0)),
        dampers: Assembly::new(m.nodes(), at.end - at.dampers, || dampers(0)),
        pressure,
    }
}
