//! The spring-mass model: nodes, springs, canopy triangles, attachments.

use crate::forces::assembly::{Assembly, Scratch};
use crate::forces::damping::{Damper, Law};
use crate::forces::delingette::TriangleSprings;
pub use crate::forces::spring::Spring;
use crate::forces::{Dynamics, Loads};
use crate::integrators::{Integrator, StepError};
use crate::system::System;

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NodeKind {
    Free,
    /// Held in place (Dirichlet condition, e.g. the canopy rim of thesis §2.2).
    Fixed,
    /// Moved by a rigid body; the index is into [`Model::attachments`].
    Attached(usize),
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

#[derive(Debug, Clone, Default)]
pub struct Model {
    /// Positions [m], 3 per node.
    pub x: Vec<f64>,
    /// Velocities [m/s], 3 per node.
    pub v: Vec<f64>,
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
    /// Canopy nodes on the inner (vent) edge, for the centre deflection.
    pub vent: Vec<usize>,
    /// Height of the undeformed canopy plane [m].
    pub canopy_height: f64,
    pub attachments: Vec<Attachment>,
    /// Suspension lines of a parachute, for uneven lengths and breaks.
    pub lines: Vec<crate::lines::Line>,
    /// Simulated time [s], advanced by [`Model::step`].
    pub time: f64,
    /// Named points of a hand-built network, with their node, for the monitors.
    pub points: Vec<(String, usize)>,
    pub gravity: [f64; 3],
    /// The Darcy–Forchheimer load of a free stream through the canopy
    /// triangles (thesis eqs. 6–10), when the structure applies it itself.
    pub porous: Option<porous::Porous>,
    /// Structure time step Δt_s [s] of the current step (the last window may be shorter).
    pub dt: f64,
    /// 1/m for free nodes, 0 for fixed and attached ones; set by [`Model::prepare`].
    pub inv_mass: Vec<f64>,
    /// Stiffness between node pairs, for Kang's method; set by [`Model::prepare`].
    pub couplings: Vec<(usize, usize, f64)>,
    /// Which slots each node sums in the force, for the elastic and viscous
    /// elements and for the pressure triangles; set by [`Model::prepare`].
    pub assembly: (Assembly, Assembly),
    /// The slot buffer of the force evaluations, reused from step to step.
    pub scratch: Scratch,
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

    /// Linear momentum Σ m v of the free nodes [kg·m/s].
    pub fn momentum(&self) -> [f64; 3] {
        let mut p = [0.0; 3];
        for n in 0..self.nodes() {
            for (c, pc) in p.iter_mut().enumerate() {
                *pc += self.mass[n] * self.v[3 * n + c];
            }
        }
        p
    }

    /// Elastic energy of springs and membrane plus gravitational energy of the masses [J].
    pub fn potential_energy(&self) -> f64 {
        crate::forces::elastic_energy(self, &self.x) + crate::forces::gravity_energy(self, &self.x)
    }

    /// Derive what the integrators read from the nodes and elements: the
    /// inverse masses, the stiffness couplings and the force assembly. Call after building or
    /// changing nodes and elements.
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
        self.assembly = crate::forces::assembly(self);
    }

    /// Advance by one step of `self.dt` with `integrator`: attached nodes follow
    /// their body and collect the impulse the step gave them.
    pub fn step(
        &mut self,
        integrator: &mut dyn Integrator,
        loads: &Loads,
    ) -> Result<(), StepError> {
        let mut x = std::mem::take(&mut self.x);
        let mut v = std::mem::take(&mut self.v);
        let result = integrator.step(&Dynamics { model: self, loads }, self.dt, &mut x, &mut v);
        self.x = x;
        self.v = v;
        result?;
        self.finish_step(integrator.reaction());
        Ok(())
    }

    /// End a step of any method: the attachments collect the impulse
    /// `reaction` (3 per node, read at the attached nodes) and move on with
    /// their body, and the time advances by `self.dt`.
    pub fn finish_step(&mut self, reaction: &[f64]) {
        for a in &mut self.attachments {
            for c in 0..3 {
                a.impulse[c] += reaction[3 * a.node + c];
            }
            a.tau += self.dt;
        }
        self.place_attached();
        self.time += self.dt;
    }

    /// The total force at the current state, as the integrators see it.
    pub fn force(&self, loads: &Loads, f: &mut [f64]) {
        Dynamics { model: self, loads }.force(&self.x, &self.v, f);
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
