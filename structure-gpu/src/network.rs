//! The spring-mass network as the device reads it: plain arrays, handed
//! over once, and the node-by-node assembly of element slots built from them.

use gpu_device::GpuError;

/// A Hookean spring (thesis eq. 67), or a string that carries tension only
/// beyond its compressive tolerance (thesis eq. 3).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    pub i: usize,
    pub j: usize,
    /// Stiffness [N/m].
    pub k: f64,
    /// Rest length [m].
    pub rest: f64,
    pub tension_only: bool,
    /// Compressive tolerance of a string [m].
    pub eps: f64,
}

/// A dashpot between two nodes, idle below its slack length.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    pub i: usize,
    pub j: usize,
    /// Coefficient [N·s/m].
    pub c: f64,
    /// Length [m] below which it is idle (a slack string's).
    pub slack_below: f64,
}

/// Delingette's triangular springs of a membrane (dissertation eqs.
/// 2.29–2.37): the edges' rest lengths and the stiffness matrix Q.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Membrane {
    pub nodes: [usize; 3],
    /// Rest lengths of the edges (0→1, 1→2, 2→0) [m].
    pub rest: [f64; 3],
    /// Q, row by row [N/m]: the edges' tensions are Q·dl.
    pub q: [[f64; 3]; 3],
}

/// How the dampers act.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DampingLaw {
    /// Thesis eq. (68): the whole relative velocity.
    RelativeVelocity,
    /// Dissertation eq. (2.38): the relative velocity along the spring.
    Axial,
}

/// What the device's step reads and does not move.
#[derive(Debug, Clone, Default)]
pub struct Network {
    /// Lumped masses [kg].
    pub mass: Vec<f64>,
    /// 1/m, 0 for a node the step must not accelerate.
    pub inv_mass: Vec<f64>,
    /// [m/s²].
    pub gravity: [f64; 3],
    pub springs: Vec<Spring>,
    pub membrane: Vec<Membrane>,
    pub dampers: Vec<Damper>,
    /// The dampers' law; `None` leaves them out.
    pub damping: Option<DampingLaw>,
    /// The triangles a pressure jump pushes (a third of jump·area·n on each
    /// vertex, counter-clockwise seen along n): the fluid's jump, set by
    /// [`crate::Solver::set_pressure`], plus the porous law's. Empty where
    /// neither acts.
    pub triangles: Vec<[usize; 3]>,
    /// The Darcy–Forchheimer law of a free stream through the canopy
    /// (thesis eqs. 6–10), applied by the structure itself.
    pub porous: Option<porous::Porous>,
}

impl Network {
    pub fn nodes(&self) -> usize {
        self.mass.len()
    }

    /// The dampers that act: none without a law.
    pub(crate) fn acting_dampers(&self) -> &[Damper] {
        match self.damping {
            Some(_) => &self.dampers,
            None => &[],
        }
    }

    /// The nodes of every element, family by family: springs (2 each),
    /// membrane triangles (3), acting dampers (2), pressure triangles (3).
    pub(crate) fn element_nodes(&self) -> Result<Vec<u32>, GpuError> {
        let springs = self.springs.iter().flat_map(|s| [s.i, s.j]);
        let membrane = self.membrane.iter().flat_map(|t| t.nodes);
        let dampers = self.acting_dampers().iter().flat_map(|d| [d.i, d.j]);
        let triangles = self.triangles.iter().flatten().copied();
        springs
            .chain(membrane)
            .chain(dampers)
            .chain(triangles)
            .map(|n| {
                assert!(
                    n < self.nodes(),
                    "an element's node is past the network's {} nodes",
                    self.nodes()
                );
                u32::try_from(n).map_err(|_| GpuError::TooManyElements("the nodes"))
            })
            .collect()
    }

    /// The elements' reals, family by family: springs k, rest, eps, 1 for a
    /// string (4 each); membrane rest lengths then Q by rows (12);
    /// dampers c, slack length (2).
    pub(crate) fn element_reals(&self) -> Vec<f64> {
        let flag = |s: &Spring| if s.tension_only { 1.0 } else { 0.0 };
        let springs = self
            .springs
            .iter()
            .flat_map(|s| [s.k, s.rest, s.eps, flag(s)]);
        let membrane = self
            .membrane
            .iter()
            .flat_map(|t| t.rest.into_iter().chain(t.q.into_iter().flatten()));
        let dampers = self
            .acting_dampers()
            .iter()
            .flat_map(|d| [d.c, d.slack_below]);
        springs.chain(membrane).chain(dampers).collect()
    }

    /// Slots, one per spring, membrane edge, acting damper and pressure triangle.
    pub(crate) fn slots(&self) -> usize {
        self.springs.len()
            + 3 * self.membrane.len()
            + self.acting_dampers().len()
            + self.triangles.len()
    }

    /// Every contribution as (node, slot, subtracted), in the order
    /// structure-proc's CPU assembly sums them: springs, membrane edges,
    /// dampers (the first node adds, the second subtracts), then the
    /// pressure triangles (every vertex adds).
    fn touches(&self) -> Vec<(usize, usize, bool)> {
        let mut out = Vec::new();
        let mut slot = 0;
        let mut pair = |out: &mut Vec<_>, i: usize, j: usize| {
            out.push((i, slot, false));
            out.push((j, slot, true));
            slot += 1;
        };
        for s in &self.springs {
            pair(&mut out, s.i, s.j);
        }
        for t in &self.membrane {
            for (a, b) in EDGES {
                pair(&mut out, t.nodes[a], t.nodes[b]);
            }
        }
        for d in self.acting_dampers() {
            pair(&mut out, d.i, d.j);
        }
        for tri in &self.triangles {
            out.extend(tri.map(|n| (n, slot, false)));
            slot += 1;
        }
        out
    }

    /// Mass and 1/m, node by node.
    pub(crate) fn node_reals(&self) -> Vec<f64> {
        assert_eq!(
            self.mass.len(),
            self.inv_mass.len(),
            "a mass and 1/m per node"
        );
        self.mass
            .iter()
            .zip(&self.inv_mass)
            .flat_map(|(&m, &w)| [m, w])
            .collect()
    }

    /// start[0..=nodes], then slot << 1 | subtracted: which slots each node
    /// sums, in the order of [`Network::touches`].
    pub(crate) fn assembly(&self) -> Result<Vec<u32>, GpuError> {
        let touches = self.touches();
        let nodes = self.nodes();
        if 2 * self.slots() >= u32::MAX as usize || nodes + touches.len() >= u32::MAX as usize {
            return Err(GpuError::TooManyElements("the elements"));
        }
        let mut start = vec![0u32; nodes + 1];
        for &(n, _, _) in &touches {
            start[n + 1] += 1;
        }
        for n in 0..nodes {
            start[n + 1] += start[n];
        }
        let mut next = start.clone();
        let mut entries = vec![0u32; touches.len()];
        for (n, slot, minus) in touches {
            entries[next[n] as usize] = (slot as u32) << 1 | minus as u32;
            next[n] += 1;
        }
        start.extend(entries);
        Ok(start)
    }
}

/// A membrane triangle's edges as (from, to) vertex pairs, as structure-proc's
/// `forces/delingette.rs` orders them.
const EDGES: [(usize, usize); 3] = [(0, 1), (1, 2), (2, 0)];
