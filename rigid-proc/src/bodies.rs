//! All the bodies of a scene and one impulse sub-step for them: the
//! structure's impulses at their attachment points, rigid–rigid contacts,
//! then every body advanced under gravity and the fluid's loads.

use crate::contact;
use crate::motion::{advance, Load};
use exchange::body::{self, Body};
use exchange::fields::{MOMENTUM_LEN, STATE_LEN};
use nalgebra::Vector3;
use rigid_section::AttachmentSpec;
use rigid_section::{pair_restitution, RigidSection};

#[derive(Clone)]
pub struct Bodies {
    pub bodies: Vec<Body>,
    pub gravity: Vector3<f64>,
    /// Each attachment point (in `StructureSection::attachments` order): its
    /// body and its place in that body's principal axes about the centre.
    pub attachments: Vec<(usize, Vector3<f64>)>,
    /// C_R of each body, from its own value or the scene's.
    restitution: Vec<f64>,
    /// Contact impulses applied so far.
    pub contact_impulses: u64,
    /// Each body's motion as the scene gives it; one with a release time
    /// moves as a prescribed body before it (`Body::motion_at`).
    motions: Vec<exchange::Motion>,
    /// Time since the start [s], summed over the steps.
    pub time: f64,
}

impl Bodies {
    /// The bodies of `[rigid]`; `attached` lists the attachment points.
    pub fn new(s: &RigidSection, attached: &[AttachmentSpec]) -> Result<Bodies, String> {
        let bodies = s.bodies()?;
        let attachments = attached
            .iter()
            .map(|a| {
                let i = bodies
                    .iter()
                    .position(|b| b.name == a.body)
                    .ok_or_else(|| format!("no rigid body is named `{}`", a.body))?;
                Ok((i, bodies[i].principal_point(Vector3::from(a.point))))
            })
            .collect::<Result<Vec<_>, String>>()?;
        let restitution = (0..s.bodies.len()).map(|i| s.body_restitution(i)).collect();
        let mut all = Bodies {
            motions: bodies.iter().map(|b| b.motion).collect(),
            bodies,
            gravity: Vector3::from(s.gravity),
            attachments,
            restitution,
            contact_impulses: 0,
            time: 0.0,
        };
        all.hold();
        Ok(all)
    }

    /// Each body's motion at the present time: held until its release.
    pub fn hold(&mut self) {
        body::hold(&mut self.bodies, &self.motions, self.time);
    }

    /// One sub-step of `h`: the impulses `impulse` (3 per attachment point,
    /// world axes) act at their points, contacts are resolved, and every body
    /// moves under gravity and `loads` (one per body, or none).
    pub fn step(&mut self, h: f64, impulse: &[f64], loads: &[Load]) {
        self.hold();
        for (&(b, r), j) in self.attachments.iter().zip(impulse.chunks_exact(3)) {
            let p = self.bodies[b].world_point(&r);
            self.bodies[b].apply_impulse(&p, &Vector3::new(j[0], j[1], j[2]));
        }
        let contacts = contact::detect(&self.bodies, h);
        if !contacts.is_empty() {
            let cr = &self.restitution;
            let n = contact::resolve(
                &mut self.bodies,
                &contacts,
                |a, b| pair_restitution(cr[a], cr[b]),
                h,
            );
            self.contact_impulses += n as u64;
        }
        let none = Load::default();
        for (i, body) in self.bodies.iter_mut().enumerate() {
            advance(body, loads.get(i).unwrap_or(&none), &self.gravity, h);
        }
        self.time += h;
        self.hold();
    }

    /// `loads` (one per body, or none) with the impulses `impulse` (3 per
    /// attachment point, world axes) spread as constant forces over `dt`,
    /// acting at the points where they are now: how a body takes the
    /// structure's impulse when the two iterate each window
    /// (`CouplingSection::bodies_iterate`).
    pub fn with_impulses_as_forces(&self, impulse: &[f64], dt: f64, loads: &[Load]) -> Vec<Load> {
        let mut out: Vec<Load> = (0..self.bodies.len())
            .map(|i| loads.get(i).copied().unwrap_or_default())
            .collect();
        for (&(b, r), j) in self.attachments.iter().zip(impulse.chunks_exact(3)) {
            let body = &self.bodies[b];
            let f = Vector3::new(j[0], j[1], j[2]) / dt;
            out[b].force += f;
            out[b].torque += (body.world_point(&r) - body.state.x).cross(&f);
        }
        out
    }

    /// Every body's state, [`STATE_LEN`] values per body.
    pub fn write_states(&self, out: &mut [f64]) {
        for (o, body) in out.chunks_exact_mut(STATE_LEN).zip(&self.bodies) {
            body.write_state(o);
        }
    }

    /// The momentum the structure's collisions gave each body,
    /// [`MOMENTUM_LEN`] per body: linear then angular impulse about the
    /// centre (world axes).
    pub fn apply_momenta(&mut self, momenta: &[f64]) {
        for (body, m) in self
            .bodies
            .iter_mut()
            .zip(momenta.chunks_exact(MOMENTUM_LEN))
        {
            body.apply_momentum(
                &Vector3::new(m[0], m[1], m[2]),
                &Vector3::new(m[3], m[4], m[5]),
            );
        }
    }

    /// Position then velocity of every attachment point, 6 per point.
    pub fn attachment_state(&self, out: &mut [f64]) {
        for (o, &(b, r)) in out.chunks_exact_mut(6).zip(&self.attachments) {
            let body = &self.bodies[b];
            let p = body.world_point(&r);
            o[..3].copy_from_slice(p.as_slice());
            o[3..].copy_from_slice(body.velocity_at(&p).as_slice());
        }
    }

    pub fn kinetic_energy(&self) -> f64 {
        self.bodies.iter().map(Body::kinetic_energy).sum()
    }

    /// Gravitational potential energy −Σ m g·x of the dynamic bodies [J].
    pub fn potential_energy(&self) -> f64 {
        self.bodies
            .iter()
            .filter(|b| b.inv_mass() > 0.0)
            .map(|b| -b.mass.mass * self.gravity.dot(&b.state.x))
            .sum()
    }

    /// Total linear momentum of the dynamic bodies [kg·m/s].
    pub fn momentum(&self) -> Vector3<f64> {
        self.bodies
            .iter()
            .filter(|b| b.inv_mass() > 0.0)
            .map(|b| b.state.v * b.mass.mass)
            .sum()
    }

    /// Total angular momentum of the dynamic bodies about the world origin:
    /// Σ x × m v + Aᵀ I w [kg·m²/s].
    pub fn angular_momentum(&self) -> Vector3<f64> {
        self.bodies
            .iter()
            .filter(|b| b.inv_mass() > 0.0)
            .map(|b| b.state.x.cross(&(b.state.v * b.mass.mass)) + b.spin_momentum())
            .sum()
    }

    pub fn first_non_finite(&self) -> Option<&str> {
        self.bodies
            .iter()
            .find(|b| {
                let s = &b.state;
                s.x.iter()
                    .chain(&s.v)
                    .chain(&s.e)
                    .chain(&s.w)
                    .any(|v| !v.is_finite())
            })
            .map(|b| b.name.as_str())
    }
}
