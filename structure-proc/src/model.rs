//! The spring-mass model: the state a step moves (positions, velocities),
//! the [`Network`] it reads, and what ties it to the other processes: the
//! attachment points on rigid bodies, the suspension lines that can break,
//! the named points and the vent the monitors report.

use crate::forces::{Dynamics, Loads};
use crate::integrators::{Integrator, StepError};
use crate::lines::Line;
pub use crate::network::{Network, NodeKind, Spring};
use crate::system::System;
use exchange::fields::ATTACHMENT_STATE_LEN;

/// An attachment point on a rigid body, prescribed over one impulse sub-step as
/// x(τ) = x0 + v0·τ, and the impulse the structure gives back.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
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
    /// What the step reads: masses, elements, gravity (also read through
    /// the model, `m.springs`).
    pub net: Network,
    /// Canopy nodes on the inner (vent) edge, for the centre deflection.
    pub vent: Vec<usize>,
    /// Height of the undeformed canopy plane [m].
    pub canopy_height: f64,
    pub attachments: Vec<Attachment>,
    /// Suspension lines of a parachute, for uneven lengths and breaks.
    pub lines: Vec<Line>,
    /// Named points of a hand-built network, with their node, for the monitors.
    pub points: Vec<(String, usize)>,
    /// A payload that holds the parachute until its release (`release.rs`).
    pub hold: Option<crate::release::Hold>,
    /// A parachute's parts the designer's monitors read (`designer.rs`).
    pub parachute: Option<crate::designer::ParachuteParts>,
}

impl std::ops::Deref for Model {
    type Target = Network;

    fn deref(&self) -> &Network {
        &self.net
    }
}

impl std::ops::DerefMut for Model {
    fn deref_mut(&mut self) -> &mut Network {
        &mut self.net
    }
}

impl Model {
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
        crate::forces::elastic_energy(&self.net, &self.x)
            + crate::forces::gravity_energy(&self.net, &self.x)
    }

    /// Advance by one step of `dt` under `loads` with `integrator`: attached
    /// nodes follow their body and collect the impulse the step gave them.
    pub fn step(
        &mut self,
        integrator: &mut dyn Integrator,
        loads: &Loads,
        dt: f64,
    ) -> Result<(), StepError> {
        let net = &self.net;
        let result = integrator.step(&Dynamics { net, loads }, dt, &mut self.x, &mut self.v);
        result?;
        self.finish_step(integrator.reaction(), dt);
        Ok(())
    }

    /// End a step of `dt` of any method: the attachments collect the impulse
    /// `reaction` (3 per node, read at the attached nodes) and move on with
    /// their body.
    pub fn finish_step(&mut self, reaction: &[f64], dt: f64) {
        for a in &mut self.attachments {
            for c in 0..3 {
                a.impulse[c] += reaction[3 * a.node + c];
            }
            a.tau += dt;
        }
        self.place_attached();
    }

    /// Break the lines whose time has come at `time` or whose tension is too
    /// high ([`crate::lines::break_lines`]); a message per break.
    pub fn break_lines(&mut self, time: f64) -> Vec<String> {
        crate::lines::break_lines(&mut self.lines, &mut self.net, &self.x, time)
    }

    /// The total force at the current state, as the integrators see it.
    pub fn force(&self, loads: &Loads, f: &mut [f64]) {
        Dynamics {
            net: &self.net,
            loads,
        }
        .force(&self.x, &self.v, f);
    }

    /// Set the attachment points at the start of an impulse sub-step
    /// (`state`: position then velocity, 6 per attachment) and clear the impulses.
    pub fn set_attachments(&mut self, state: &[f64]) {
        for (a, s) in self
            .attachments
            .iter_mut()
            .zip(state.chunks_exact(ATTACHMENT_STATE_LEN))
        {
            a.x0 = [s[0], s[1], s[2]];
            a.v0 = [s[3], s[4], s[5]];
            a.tau = 0.0;
            a.impulse = [0.0; 3];
        }
        self.place_attached();
    }

    /// Set the attachment points to move over a step of `dt` along the
    /// chord from their positions in `start` to those in `end` (both
    /// position then velocity, 6 per attachment), and clear the impulses.
    pub fn set_attachments_along(&mut self, start: &[f64], end: &[f64], dt: f64) {
        let points = start
            .chunks_exact(ATTACHMENT_STATE_LEN)
            .zip(end.chunks_exact(ATTACHMENT_STATE_LEN));
        for (a, (s, e)) in self.attachments.iter_mut().zip(points) {
            a.x0 = [s[0], s[1], s[2]];
            a.v0 = [0, 1, 2].map(|c| (e[c] - s[c]) / dt);
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
