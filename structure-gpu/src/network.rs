//! The spring-mass network as the device reads it: plain arrays, handed
//! over once, and the node-by-node assembly of element slots built from them.

use crate::device::GpuError;

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
    pub dampers: Vec<Damper>,
    /// The dampers' law; `None` leaves them out.
    pub damping: Option<DampingLaw>,
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

    /// Both ends of every spring, then of every acting damper.
    pub(crate) fn ends(&self) -> Result<Vec<u32>, GpuError> {
        let springs = self.springs.iter().map(|s| (s.i, s.j));
        let dampers = self.acting_dampers().iter().map(|d| (d.i, d.j));
        let mut out = Vec::with_capacity(2 * (self.springs.len() + self.acting_dampers().len()));
        for (i, j) in springs.chain(dampers) {
            assert!(
                i < self.nodes() && j < self.nodes(),
                "an element's node is past the network's {} nodes",
                self.nodes()
            );
            out.push(u32::try_from(i).map_err(|_| GpuError::TooManyElements("the nodes"))?);
            out.push(u32::try_from(j).map_err(|_| GpuError::TooManyElements("the nodes"))?);
        }
        Ok(out)
    }

    /// Four reals an element: k, rest, eps, string (springs); c, slack, 0, 0 (dampers).
    pub(crate) fn element_reals(&self) -> Vec<f64> {
        let springs = self
            .springs
            .iter()
            .map(|s| [s.k, s.rest, s.eps, if s.tension_only { 1.0 } else { 0.0 }]);
        let dampers = self
            .acting_dampers()
            .iter()
            .map(|d| [d.c, d.slack_below, 0.0, 0.0]);
        springs.chain(dampers).flatten().collect()
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
    /// sums, in the order structure-proc's CPU assembly sums them (springs,
    /// then dampers; the first node adds, the second subtracts).
    pub(crate) fn assembly(&self) -> Result<Vec<u32>, GpuError> {
        let ends = self.ends()?;
        let nodes = self.nodes();
        if 2 * ends.len() >= u32::MAX as usize || nodes >= u32::MAX as usize / 2 {
            return Err(GpuError::TooManyElements("the springs and dampers"));
        }
        let mut start = vec![0u32; nodes + 1];
        for &n in &ends {
            start[n as usize + 1] += 1;
        }
        for n in 0..nodes {
            start[n + 1] += start[n];
        }
        let mut next = start.clone();
        let mut entries = vec![0u32; ends.len()];
        for (e, &n) in ends.iter().enumerate() {
            // Entry e is end e % 2 of slot e / 2.
            entries[next[n as usize] as usize] = ((e / 2) as u32) << 1 | (e % 2) as u32;
            next[n as usize] += 1;
        }
        start.extend(entries);
        Ok(start)
    }
}
