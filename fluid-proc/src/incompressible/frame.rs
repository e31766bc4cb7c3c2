//! A flow box that follows the parachute down (`[fluid.frame]`).
//!
//! Only the air is solved in the box's frame. The structure and the bodies
//! stay in the ground's, where no fictitious force acts on them, so their
//! solvers (a user's own among them) need nothing new and their monitors
//! read altitudes and descent speeds directly.
//!
//! The box's velocity V(t) over the ground is piecewise linear: over each
//! window it goes from its value at the window's start to the followed
//! body's (or the canopy's mean) velocity at that start, one window behind
//! it. So the box's frame is one continuous frame, and the Adams–Bashforth
//! history of the advection (the step before's Nⁿ⁻¹) stays in it. With
//! u' = u − V, the air obeys there
//!
//!   ∂u'/∂t + (u'·∇)u' = −∇p/ρ + ν∇²u' − a,   a = dV/dt,
//!
//! the ground frame's equations with the frame's acceleration as one
//! uniform body force on all the air; the pressure p is the ground frame's.
//! The body force is constant over a step, so u* takes −a·Δt exactly.
//! A side with a velocity gives the air's velocity over the ground (still
//! air: zero), and the box sees it less V. Bodies and canopy are placed
//! where they are less the box's displacement and held to their ground
//! velocities less V (`immersed::force`); the loads sent back are the
//! ground frame's: the pressure jump, and a body's load from its ground
//! acceleration (Uhlmann's inner-fluid term, `ImmersedBody::take_load`),
//! which with the body force −a on the inner fluid too is the force of the
//! ground frame.

use crate::incompressible::side::Side;
use crate::incompressible::Incompressible;

/// Where the box is and how it moves over the ground.
#[derive(Debug, Clone, Copy, Default, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Frame {
    /// The box's velocity over the ground now [m/s].
    pub velocity: [f64; 3],
    /// How far the box has moved from where `[fluid.box]` put it [m].
    pub offset: [f64; 3],
    /// Its acceleration over the present window [m/s²].
    pub acceleration: [f64; 3],
}

impl Frame {
    /// Moves the box on by `dt` [s] at its acceleration (its offset by the
    /// trapezoid rule, exact for a velocity linear in time); returns the
    /// change of velocity.
    fn advance(&mut self, dt: f64) -> [f64; 3] {
        let dv = self.acceleration.map(|a| a * dt);
        for ((x, v), dv) in self.offset.iter_mut().zip(&mut self.velocity).zip(dv) {
            *x += (*v + 0.5 * dv) * dt;
            *v += dv;
        }
        dv
    }

    fn encode(&self) -> [f64; 9] {
        let mut x = [0.0; 9];
        x[..3].copy_from_slice(&self.velocity);
        x[3..6].copy_from_slice(&self.offset);
        x[6..].copy_from_slice(&self.acceleration);
        x
    }

    fn decode(x: &[f64; 9]) -> Frame {
        let part = |i: usize| [x[i], x[i + 1], x[i + 2]];
        Frame {
            velocity: part(0),
            offset: part(3),
            acceleration: part(6),
        }
    }
}

impl Incompressible {
    /// The box follows from now on, moving at `velocity` [m/s] over the
    /// ground: the air, at the velocities over the ground it was given,
    /// takes them less `velocity`, and so do the sides. Along a 2-D flow's
    /// thin axis the box does not move.
    pub fn start_following(&mut self, velocity: [f64; 3]) {
        let v = self.along_flow(velocity);
        for (u, v) in self.u.u.iter_mut().zip(v) {
            u.iter_mut().for_each(|u| *u -= v);
        }
        self.frame = Some(Frame {
            velocity: v,
            ..Frame::default()
        });
        self.frame_sides();
        self.impose_sides();
    }

    /// Over the next `dt` [s] the box's velocity goes to `target` [m/s].
    pub fn aim_frame(&mut self, target: [f64; 3], dt: f64) {
        let target = self.along_flow(target);
        if let Some(f) = &mut self.frame {
            f.acceleration = [0, 1, 2].map(|d| (target[d] - f.velocity[d]) / dt);
        }
    }

    /// The box's velocity over the ground [m/s] (zero for a fixed box).
    pub fn frame_velocity(&self) -> [f64; 3] {
        self.frame.map_or([0.0; 3], |f| f.velocity)
    }

    /// How far the box has moved from where `[fluid.box]` put it [m].
    pub fn frame_offset(&self) -> [f64; 3] {
        self.frame.map_or([0.0; 3], |f| f.offset)
    }

    /// Where the box's low corner is now in the world [m], `[fluid.box]`
    /// having put it at `lower`.
    pub fn box_origin(&self, lower: [f64; 3]) -> [f64; 3] {
        let offset = self.frame_offset();
        [0, 1, 2].map(|d| lower[d] + offset[d])
    }

    /// Rank 0's frame on every rank (nothing to do on one rank).
    pub fn share_frame(&mut self) {
        let comm = self.part.comm.as_ref();
        let Some(f) = &mut self.frame else { return };
        if comm.ranks() > 1 {
            let mut x = f.encode();
            comm.broadcast(&mut x);
            *f = Frame::decode(&x);
        }
    }

    /// Moves the box on by a step of `dt` [s] and gives its sides their
    /// velocities at the step's end; returns the change of the box's
    /// velocity, which the air takes as the body force −a·Δt.
    pub(crate) fn move_frame(&mut self, dt: f64) -> [f64; 3] {
        let Some(f) = &mut self.frame else {
            return [0.0; 3];
        };
        let dv = f.advance(dt);
        self.frame_sides();
        dv
    }

    /// Each side with a velocity gives the air's ground velocity less the
    /// box's.
    pub(crate) fn frame_sides(&mut self) {
        let v = self.frame_velocity();
        for d in 0..3 {
            for s in 0..2 {
                let Side::Velocity(ground) = self.ground_sides[d][s] else {
                    continue;
                };
                let seen = Side::Velocity([0, 1, 2].map(|a| ground[a] - v[a]));
                self.setup.sides[d][s] = seen;
                if let Side::Velocity(_) = self.sides[d][s] {
                    self.sides[d][s] = seen;
                }
            }
        }
    }

    /// `v` with no component along a 2-D flow's thin axis.
    fn along_flow(&self, v: [f64; 3]) -> [f64; 3] {
        let n = self.setup.grid.n;
        [0, 1, 2].map(|d| if n[d] > 1 { v[d] } else { 0.0 })
    }
}
