//! The spring-mass model: nodes, springs, canopy triangles, attachments.

use coupler::scenario::structure::Damping;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    Free,
    /// Held in place (Dirichlet condition, e.g. the canopy rim of seed 003 §2.2).
    Fixed,
    /// Moved by a rigid body; the index is into [`Model::attachments`].
    Attached(usize),
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    pub i: usize,
    pub j: usize,
    /// Stiffness k_ij [N/m].
    pub k: f64,
    /// Rest length l⁰_ij [m].
    pub rest: f64,
    /// Strings carry tension only, beyond the compressive tolerance eps (seed 003 eq. 3).
    pub tension_only: bool,
    pub eps: f64,
}

/// An attachment point on a rigid body, prescribed over one impulse sub-step as
/// x(τ) = x0 + v0·τ, and the impulse the structure gives back.
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Attachment {
    pub node: usize,
    pub x0: [f64; 3],
    pub v0: [f64; 3],
    /// Time since the start of the impulse sub-step [s].
    pub tau: f64,
    /// Impulse of the structure on the body accumulated in this sub-step [N·s].
    pub impulse: [f64; 3],
}

#[derive(Debug, Clone)]
pub struct Model {
    /// Positions [m], 3 per node.
    pub x: Vec<f64>,
    /// Velocities [m/s], 3 per node.
    pub v: Vec<f64>,
    /// Lumped masses [kg]; zero for fixed and attached nodes.
    pub mass: Vec<f64>,
    pub kind: Vec<NodeKind>,
    pub springs: Vec<Spring>,
    /// Canopy triangles (nodes `0..canopy_nodes`), counter-clockwise seen along +n.
    pub triangles: Vec<[usize; 3]>,
    /// The canopy occupies nodes `0..canopy_nodes`; strings follow.
    pub canopy_nodes: usize,
    /// Canopy nodes on the inner (vent) edge, for the centre deflection.
    pub vent: Vec<usize>,
    /// Height of the undeformed canopy plane [m].
    pub canopy_height: f64,
    pub attachments: Vec<Attachment>,
    pub gravity: [f64; 3],
    pub damping: Damping,
    /// Structure time step Δt_s [s] of the current step (the last window may be shorter).
    pub dt: f64,
    /// The scenario's structure step Δt_f/n_s [s]; seed 003 eq. (68) scales the
    /// damping with it, and it stays fixed when a last, shorter window shrinks `dt`.
    pub damping_dt: f64,
}

impl Model {
    pub fn nodes(&self) -> usize {
        self.mass.len()
    }

    /// Kinetic energy ½ Σ m v² [J].
    pub fn kinetic_energy(&self) -> f64 {
        (0..self.nodes())
            .map(|n| 0.5 * self.mass[n] * (0..3).map(|c| self.v[3 * n + c].powi(2)).sum::<f64>())
            .sum()
    }

    /// Elastic energy of the springs plus gravitational energy of the masses [J].
    pub fn potential_energy(&self) -> f64 {
        let elastic: f64 = self
            .springs
            .iter()
            .map(|s| crate::forces::spring_energy(s, &self.x))
            .sum();
        let gravity: f64 = (0..self.nodes())
            .map(|n| {
                -self.mass[n]
                    * (0..3)
                        .map(|c| self.gravity[c] * self.x[3 * n + c])
                        .sum::<f64>()
            })
            .sum();
        elastic + gravity
    }

    /// Set the attachment points at the start of an impulse sub-step
    /// (`state`: position then velocity, 6 per attachment) and clear the impulses.
    pub fn set_attachments(&mut self, state: &[f64]) {
        for (a, s) in self.attachments.iter_mut().zip(state.chunks_exact(6)) {
            a.x0 = [s[0], s[1], s[2]];
            a.v0 = [s[3], s[4], s[5]];
            a.tau = 0.0;
            a.impulse = [0.0; 3];
        }
        self.place_attached();
    }

    /// Move attached nodes to x0 + v0·τ.
    pub fn place_attached(&mut self) {
        for a in &self.attachments {
            for c in 0..3 {
                self.x[3 * a.node + c] = a.x0[c] + a.v0[c] * a.tau;
                self.v[3 * a.node + c] = a.v0[c];
            }
        }
    }

    /// Mean displacement along z of the vent edge from the undeformed plane [m].
    pub fn centre_deflection(&self) -> f64 {
        if self.vent.is_empty() {
            return 0.0;
        }
        let sum: f64 = self.vent.iter().map(|&n| self.x[3 * n + 2]).sum();
        sum / self.vent.len() as f64 - self.canopy_height
    }

    /// First non-finite position or velocity, as (node, quantity).
    pub fn first_non_finite(&self) -> Option<(usize, &'static str)> {
        (0..self.nodes()).find_map(|n| {
            if self.x[3 * n..3 * n + 3].iter().any(|v| !v.is_finite()) {
                Some((n, "position"))
            } else if self.v[3 * n..3 * n + 3].iter().any(|v| !v.is_finite()) {
                Some((n, "velocity"))
            } else {
                None
            }
        })
    }
}
