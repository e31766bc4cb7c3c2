//! Moving bodies in the contact pass: their faceted surfaces ride with
//! them over each step (v + ω × r), no impulse moves them within it, the
//! facets find the contacts while the body pushes along its true normal,
//! and each body takes the reaction of every impulse it gives (the
//! dissertation §2.5: each rigid body one impact zone), which the driver
//! hands to the rigid solver with the node–body pass's.

use super::geometry::{Stencil, V3};
use super::Contacts;
use rigid_proc::body::Body;

impl Contacts {
    /// Put the moving bodies' surfaces where `bodies` (every `[rigid]` body,
    /// in order, as the rigid solver sends them) are.
    pub fn place_bodies(&mut self, bodies: &[Body]) {
        let structure = self.nodes;
        for (k, c) in self.bodies.carried.iter().enumerate() {
            let body = &bodies[c.body];
            let pose = body.own_pose();
            for (i, p) in c.own.iter().enumerate() {
                let at = 3 * (c.first - structure + i);
                self.bodies.points[at..at + 3].copy_from_slice((pose * p).coords.as_slice());
            }
            self.centres[k].0 = body.state.x;
            self.placed[k] = (body.shape_pose(), body.state.x);
        }
    }

    /// Let the moving bodies carry their surfaces over the coming step of
    /// `dt` with `bodies`' velocities: each point by v + ω × r over the step
    /// (the body taken as moving rigidly, too heavy for one impulse to turn
    /// within the step; it takes the momentum afterwards).
    pub fn move_bodies(&mut self, bodies: &[Body], dt: f64) {
        let structure = self.nodes;
        for (k, c) in self.bodies.carried.iter().enumerate() {
            let body = &bodies[c.body];
            // About where the centre is now, not where it was placed.
            let (v, omega, centre) = (
                body.state.v,
                body.world_angular_velocity(),
                self.centres[k].0,
            );
            for i in 0..c.own.len() {
                let at = 3 * (c.first - structure + i);
                let p = V3::from_column_slice(&self.bodies.points[at..at + 3]);
                let d = (v + omega.cross(&(p - centre))) * dt;
                self.carried_dx[at..at + 3].copy_from_slice(d.as_slice());
            }
            self.centres[k].1 = v * dt;
        }
    }

    /// The momentum each moving body took in the last [`Contacts::resolve`]:
    /// its place in `[rigid]`, the linear and the angular momentum about its
    /// centre [N·s, N·m·s], world axes. The structure's nodes took the
    /// opposite.
    pub fn body_momenta(&self) -> impl Iterator<Item = (usize, V3, V3)> + '_ {
        self.bodies
            .carried
            .iter()
            .zip(&self.momenta)
            .map(|(c, (lin, ang))| (c.body, *lin, *ang))
    }

    /// The moving body that carries node `n`, by its place in
    /// [`BodySurfaces::carried`], if any.
    pub(super) fn carrier(&self, n: usize) -> Option<usize> {
        if n < self.nodes {
            return None;
        }
        self.bodies
            .carried
            .iter()
            .position(|c| (c.first..c.first + c.own.len()).contains(&n))
    }

    /// Give the moving bodies of `st` the reaction of the impulse
    /// `jdt`/Δt the pair took with weights `w`: node i took wᵢ·J, so a
    /// body's points, which no impulse moves, take theirs as the body's
    /// momentum, and linear momentum is kept. The body's feature is its
    /// faceted surface; its torque is taken where the true surface is, along
    /// its true normal (plus the tangential part when there is friction),
    /// so facets do not spin a frictionless ball.
    pub(super) fn credit(&mut self, st: &Stencil, w: &[f64; 4], jdt: V3) {
        if st.nodes.iter().all(|&n| n < self.nodes) {
            return;
        }
        let j = jdt / self.repulsion.dt;
        let carriers: Vec<(usize, f64, V3)> = st
            .nodes
            .iter()
            .zip(w)
            .filter_map(|(&n, &wi)| {
                let at = V3::from_column_slice(&self.start[3 * n..3 * n + 3]);
                self.carrier(n).map(|k| (k, wi, at * wi))
            })
            .collect();
        for (i, &(k, _, _)) in carriers.iter().enumerate() {
            if carriers[..i].iter().any(|c| c.0 == k) {
                continue;
            }
            let (weight, at) = carriers
                .iter()
                .filter(|c| c.0 == k)
                .fold((0.0, V3::zeros()), |(s, a), c| (s + c.1, a + c.2));
            if weight == 0.0 {
                continue;
            }
            let push = j * weight;
            let torque = self.torque(k, &(at / weight), &push);
            self.momenta[k].0 += push;
            self.momenta[k].1 += torque;
        }
    }

    /// The true outward normal of the moving body that takes part in `st`
    /// (weights `w`, nodes moved by `s`·`dx` from the step's start) where
    /// its feature's nearest point lies, pointing from the pair's second
    /// feature to its first as separations do; None if no moving body
    /// takes part. The facets find the contact; the body's shape says
    /// which way it pushes, so a round body pushes radially.
    pub(super) fn body_normal(&self, st: &Stencil, w: &[f64; 4], dx: &[f64], s: f64) -> Option<V3> {
        if st.nodes.iter().all(|&n| n < self.nodes) {
            return None;
        }
        let (first, _) = st.features();
        let mut found = None;
        let (mut weight, mut at) = (0.0, V3::zeros());
        for (i, &n) in st.nodes.iter().enumerate() {
            if let Some(k) = self.carrier(n) {
                found = Some((k, i < first.len()));
                let x = V3::from_column_slice(&self.start[3 * n..3 * n + 3]);
                let d = V3::from_column_slice(&dx[3 * n..3 * n + 3]);
                weight += w[i];
                at += (x + d * s) * w[i];
            }
        }
        let (k, body_first) = found?;
        if weight == 0.0 {
            return None;
        }
        let (pose, placed) = &self.placed[k];
        let centre = self.centres[k].0 + self.centres[k].1 * s;
        let (_, outward) =
            self.bodies.carried[k].surface_at(pose, &(at / weight - (centre - placed)));
        Some(if body_first { -outward } else { outward })
    }

    /// The torque about carried body k's centre of the push `push` on its
    /// faceted surface at `at`: applied at the true surface's nearest point,
    /// along its normal there (all of it when there is friction).
    fn torque(&self, k: usize, at: &V3, push: &V3) -> V3 {
        let carried = &self.bodies.carried[k];
        let (pose, placed) = &self.placed[k];
        // The body has moved by this since it was placed.
        let shift = self.centres[k].0 - placed;
        let (surface, normal) = carried.surface_at(pose, &(at - shift));
        let along = if self.repulsion.friction > 0.0 {
            *push
        } else {
            normal * normal.dot(push)
        };
        (surface - placed).cross(&along)
    }

    /// The linear and angular momentum (about carried body k's centre) of
    /// `zone`'s structure nodes moving by `dx` over the step.
    pub(super) fn zone_momentum(
        &self,
        zone: &[usize],
        k: usize,
        dx: &[f64],
        mass: &[f64],
    ) -> (V3, V3) {
        let dt = self.repulsion.dt;
        let centre = self.centres[k].0;
        zone.iter().filter(|&&n| n < self.nodes).fold(
            (V3::zeros(), V3::zeros()),
            |(lin, ang), &n| {
                let p = V3::from_column_slice(&dx[3 * n..3 * n + 3]) * (mass[n] / dt);
                let r = V3::from_column_slice(&self.start[3 * n..3 * n + 3]) - centre;
                (lin + p, ang + r.cross(&p))
            },
        )
    }

    /// Move the bodies' points and centres to the step's end.
    pub(super) fn carry(&mut self) {
        for (p, d) in self.bodies.points.iter_mut().zip(&mut self.carried_dx) {
            *p += *d;
            *d = 0.0;
        }
        for (centre, d) in &mut self.centres {
            *centre += *d;
            *d = V3::zeros();
        }
    }
}
