//! Bodies in the contact pass: the facets of their surfaces find the
//! contacts while the body pushes along its true normal (a ball radially),
//! static or moving. A moving body's surface rides with it over each step
//! (v + ω × r), no impulse moves it within it, and the body takes the
//! reaction of every impulse it gives (the dissertation §2.5: each rigid
//! body one impact zone), which the driver hands to the rigid solver with
//! the node–body pass's.

use super::bodies::Carried;
use super::geometry::{Stencil, V3};
use super::Contacts;
use exchange::Body;

impl Contacts {
    /// Put the moving bodies' surfaces where `bodies` (every `[rigid]` body,
    /// in order, as the rigid solver sends them) are.
    pub fn place_bodies(&mut self, bodies: &[Body]) {
        let structure = self.nodes;
        for (k, c) in moving(&self.bodies.carried) {
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
        for (k, c) in moving(&self.bodies.carried) {
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
            .filter(|(c, _)| c.moves)
            .map(|(c, (lin, ang))| (c.body, *lin, *ang))
    }

    /// The body whose surface node `n` is, static or moving, by its place
    /// in [`BodySurfaces::carried`], if any.
    pub(super) fn carrier(&self, n: usize) -> Option<usize> {
        if n < self.nodes {
            return None;
        }
        self.bodies
            .carried
            .iter()
            .position(|c| (c.first..c.first + c.own.len()).contains(&n))
    }

    /// The moving body that carries node `n`, if any.
    pub(super) fn mover(&self, n: usize) -> Option<usize> {
        self.carrier(n).filter(|&k| self.bodies.carried[k].moves)
    }

    /// Give the moving body of `st` the reaction of the impulse `jdt`/Δt
    /// the pair took with weights `w`: node i took wᵢ·J, so the body's
    /// points, which no impulse moves, take theirs as the body's momentum,
    /// and linear momentum is kept. The torque is taken at the true
    /// surface's point nearest the structure's feature
    /// ([`Contacts::body_contact`]) and, without friction, of the push's
    /// part along the true normal there, so a frictionless ball is never
    /// spun, whatever normal the impulse took.
    pub(super) fn credit(&mut self, st: &Stencil, w: &[f64; 4], jdt: V3) {
        if st.nodes.iter().all(|&n| self.mover(n).is_none()) {
            return;
        }
        let Some(contact) = self.body_contact(st, w, None) else {
            return;
        };
        let push = jdt / self.repulsion.dt * contact.weight;
        let along = match contact.outward {
            Some(n) if self.repulsion.friction == 0.0 => n * n.dot(&push),
            _ => push,
        };
        self.momenta[contact.body].0 += push;
        self.momenta[contact.body].1 += contact.arm.cross(&along);
    }

    /// The true outward normal of the body that takes part in `st`
    /// (weights `w`, nodes moved by `s`·`dx` from the step's start),
    /// pointing from the pair's second feature to its first as separations
    /// do; None if no body takes part. The facets find the contact; the
    /// body's shape says which way it pushes, so a round body pushes
    /// radially.
    pub(super) fn body_normal(&self, st: &Stencil, w: &[f64; 4], dx: &[f64], s: f64) -> Option<V3> {
        let c = self.body_contact(st, w, Some((dx, s)))?;
        c.outward.map(|n| if c.body_first { -n } else { n })
    }

    /// Where the body that takes part in `st` (weights `w`) meets it, the
    /// nodes at the step's start moved by s·dx if `moved`: the true
    /// surface's point nearest the structure's feature and the outward
    /// normal there; the normal nearest the body's feature if the
    /// structure's touches the surface (the body's own feature lies on its
    /// facets, where a flat face says nothing), or none if that touches it
    /// too (the facets' geometry then decides).
    fn body_contact(
        &self,
        st: &Stencil,
        w: &[f64; 4],
        moved: Option<(&[f64], f64)>,
    ) -> Option<BodyContact> {
        if st.nodes.iter().all(|&n| n < self.nodes) {
            return None;
        }
        let (first, _) = st.features();
        let mut found = None;
        // Weight and weighted point of the body's feature, then the structure's.
        let mut sums = [(0.0, V3::zeros()); 2];
        for (i, &n) in st.nodes.iter().enumerate() {
            let mut x = V3::from_column_slice(&self.start[3 * n..3 * n + 3]);
            if let Some((dx, s)) = moved {
                x += V3::from_column_slice(&dx[3 * n..3 * n + 3]) * s;
            }
            let side = match self.carrier(n) {
                Some(k) => {
                    found = Some((k, i < first.len()));
                    0
                }
                None => 1,
            };
            sums[side].0 += w[i];
            sums[side].1 += x * w[i];
        }
        let (body, body_first) = found?;
        let (pose, placed) = &self.placed[body];
        let s = moved.map_or(0.0, |m| m.1);
        // The body has moved by this since it was placed.
        let shift = self.centres[body].0 + self.centres[body].1 * s - placed;
        let carried = &self.bodies.carried[body];
        // Each feature's point (weights ±1 each), its nearest point on the
        // true surface and the normal there if the point stands off it.
        let near = |side: usize| {
            let at = sums[side].1 / sums[side].0 - shift;
            let (surface, outward) = carried.surface_at(pose, &at);
            let clear = (at - surface).norm() > 1e-9 * self.repulsion.thickness;
            (surface, clear.then_some(outward))
        };
        let (surface, outward) = near(1);
        let outward = outward.or_else(|| near(0).1);
        Some(BodyContact {
            body,
            body_first,
            weight: sums[0].0,
            arm: surface - placed,
            outward,
        })
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

/// The moving bodies among `carried`, with their places in it.
fn moving(carried: &[Carried]) -> impl Iterator<Item = (usize, &Carried)> {
    carried.iter().enumerate().filter(|(_, c)| c.moves)
}

/// Where a body meets a pair ([`Contacts::body_contact`]).
struct BodyContact {
    /// The body's place in [`BodySurfaces::carried`](super::bodies::BodySurfaces).
    body: usize,
    /// Whether the body's feature is the pair's first.
    body_first: bool,
    /// The summed weight of the body's nodes in the pair.
    weight: f64,
    /// The contact point on the true surface, from the body's centre.
    arm: V3,
    /// The true surface's outward normal there, if it can be told.
    outward: Option<V3>,
}
