//! One rigid body: its mass properties, its shape, and its state — centre of
//! mass x, velocity v, Euler parameters e and angular velocity w in
//! principal axes (dissertation §2.1, §3.1.1).

use crate::euler_parameters::{self as ep, EulerParameters};
use crate::fields::STATE_LEN;
use crate::mass::MassProperties;
use crate::shape::Shape;
use crate::Motion;
use nalgebra::{Isometry3, Matrix3, Rotation3, Translation3, UnitQuaternion, Vector3};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct State {
    /// Centre of mass [m], world axes.
    pub x: Vector3<f64>,
    /// Velocity of the centre of mass [m/s], world axes.
    pub v: Vector3<f64>,
    /// Orientation: A(e) takes world axes to principal body axes (eq. 3.5).
    pub e: EulerParameters,
    /// Angular velocity [rad/s] in principal body axes (eq. 2.12).
    pub w: Vector3<f64>,
}

/// How a body starts: what a scenario's `[[rigid.bodies]]` entry says of it
/// (rigid-section's `BodySpec::body` fills it).
#[derive(Debug, Clone)]
pub struct Start {
    pub name: String,
    pub motion: Motion,
    /// Density of a shaped body [kg/m³].
    pub density: f64,
    /// Mass of a body without a shape [kg].
    pub point_mass: f64,
    /// Where the own frame's origin starts [m].
    pub position: Vector3<f64>,
    /// Own axes → world axes at the start.
    pub rotation: Rotation3<f64>,
    /// [m/s]
    pub velocity: Vector3<f64>,
    /// World axes [rad/s].
    pub angular_velocity: Vector3<f64>,
    /// Linear viscous drag b [N·s/m].
    pub damping: f64,
    /// Held (moving as a prescribed body) until this time [s].
    pub release_time: Option<f64>,
}

#[derive(Clone)]
pub struct Body {
    pub name: String,
    pub motion: Motion,
    pub mass: MassProperties,
    pub shape: Option<Shape>,
    /// Linear viscous drag b [N·s/m].
    pub damping: f64,
    /// Held (moving as a prescribed body) until this time [s].
    pub release_time: Option<f64>,
    pub state: State,
}

impl Body {
    /// A body as it `start`s, of `shape` (a mass point without one): a
    /// shaped body's mass properties are its shape's at its density
    /// (dissertation eqs. 2.5–2.7).
    pub fn new(start: Start, shape: Option<Shape>) -> Body {
        let mass = match &shape {
            Some(s) => MassProperties::of_shape(s, start.density),
            None => MassProperties::point(start.point_mass),
        };
        // World ← own frame is the scenario's rotation R₀; world ← principal
        // is then R₀·Q, so A = (R₀Q)ᵀ.
        let r0 = start.rotation;
        let principal_to_world = Rotation3::from_matrix(&(r0.matrix() * mass.axes));
        let x = start.position + r0 * mass.centre;
        let e = ep::from_rotation(&principal_to_world);
        let w = ep::attitude(&e) * start.angular_velocity;
        Body {
            name: start.name,
            motion: start.motion,
            mass,
            shape,
            damping: start.damping,
            release_time: start.release_time,
            state: State {
                x,
                v: start.velocity,
                e,
                w,
            },
        }
    }

    /// The body's motion over a step from `time` [s]: a dynamic body held
    /// until its release time moves as a prescribed one before it.
    pub fn motion_at(&self, time: f64, scene: Motion) -> Motion {
        match self.release_time {
            // Within round-off of the sub-steps' summed time.
            Some(t) if time < t - 1e-9 * t.abs().max(1e-3) => Motion::Prescribed,
            _ => scene,
        }
    }

    /// Write the state as the bodies' fields carry it ([`STATE_LEN`] values):
    /// x, v, e₀…e₃, and ω in world axes.
    pub fn write_state(&self, out: &mut [f64]) {
        let s = &self.state;
        out[0..3].copy_from_slice(s.x.as_slice());
        out[3..6].copy_from_slice(s.v.as_slice());
        out[6..10].copy_from_slice(s.e.as_slice());
        out[10..13].copy_from_slice(self.world_angular_velocity().as_slice());
    }

    /// Take the state [`Body::write_state`] wrote.
    pub fn read_state(&mut self, c: &[f64]) {
        self.state.x = Vector3::new(c[0], c[1], c[2]);
        self.state.v = Vector3::new(c[3], c[4], c[5]);
        self.state.e = EulerParameters::new(c[6], c[7], c[8], c[9]);
        self.state.w = self.attitude() * Vector3::new(c[10], c[11], c[12]);
    }

    /// A(e): world axes → principal axes.
    pub fn attitude(&self) -> Matrix3<f64> {
        ep::attitude(&self.state.e)
    }

    /// Angular velocity in world axes: Aᵀw.
    pub fn world_angular_velocity(&self) -> Vector3<f64> {
        self.attitude().transpose() * self.state.w
    }

    /// A point of the body's own frame in principal axes about the centre.
    pub fn principal_point(&self, own: Vector3<f64>) -> Vector3<f64> {
        self.mass.axes.transpose() * (own - self.mass.centre)
    }

    /// World position of a point given in principal axes: x + Aᵀr (eq. 3.6's
    /// body → world transform).
    pub fn world_point(&self, r: &Vector3<f64>) -> Vector3<f64> {
        self.state.x + self.attitude().transpose() * r
    }

    /// Velocity of the body at world point `p`: v + ω × (p − x).
    pub fn velocity_at(&self, p: &Vector3<f64>) -> Vector3<f64> {
        self.state.v + self.world_angular_velocity().cross(&(p - self.state.x))
    }

    /// 1/m for a dynamic body; 0 for static and prescribed ones, which no
    /// load moves.
    pub fn inv_mass(&self) -> f64 {
        match self.motion {
            Motion::Dynamic if self.mass.mass > 0.0 => 1.0 / self.mass.mass,
            _ => 0.0,
        }
    }

    /// I⁻¹ in world axes, Aᵀ diag(1/Iᵢ) A; zero where a moment is zero (a
    /// mass point) or the body is not dynamic.
    pub fn world_inv_inertia(&self) -> Matrix3<f64> {
        if self.inv_mass() == 0.0 {
            return Matrix3::zeros();
        }
        let inv = self
            .mass
            .principal
            .map(|i| if i > 0.0 { 1.0 / i } else { 0.0 });
        let a = self.attitude();
        a.transpose() * Matrix3::from_diagonal(&inv) * a
    }

    /// An impulse `j` [N·s] at world point `p`: Δv = j/m and, about the
    /// centre, ΔL = r × j.
    pub fn apply_impulse(&mut self, p: &Vector3<f64>, j: &Vector3<f64>) {
        self.apply_momentum(j, &(p - self.state.x).cross(j));
    }

    /// A linear impulse `j` [N·s] and an angular impulse `l` about the centre
    /// [N·m·s], world axes: Δv = j/m and Δw = I⁻¹ A l in principal axes.
    pub fn apply_momentum(&mut self, j: &Vector3<f64>, l: &Vector3<f64>) {
        let inv_m = self.inv_mass();
        if inv_m == 0.0 {
            return;
        }
        self.state.v += j * inv_m;
        let body_l = self.attitude() * l;
        for i in 0..3 {
            if self.mass.principal[i] > 0.0 {
                self.state.w[i] += body_l[i] / self.mass.principal[i];
            }
        }
    }

    /// How readily the body's velocity at world point `p` along the unit
    /// normal `n` yields to an impulse along `n` [1/kg]: 1/m + n·((I⁻¹(r×n))×r),
    /// the body's term in the denominator of the contact impulse.
    pub fn inv_effective_mass(&self, p: &Vector3<f64>, n: &Vector3<f64>) -> f64 {
        let r = p - self.state.x;
        self.inv_mass() + n.dot(&(self.world_inv_inertia() * r.cross(n)).cross(&r))
    }

    /// ½ m v² + ½ Σ Iᵢ wᵢ² [J].
    pub fn kinetic_energy(&self) -> f64 {
        let s = &self.state;
        let rotation: f64 = (0..3)
            .map(|i| self.mass.principal[i] * s.w[i] * s.w[i])
            .sum();
        0.5 * (self.mass.mass * s.v.norm_squared() + rotation)
    }

    /// Angular momentum about the centre of mass, world axes: Aᵀ(I w) (eq. 2.5).
    pub fn spin_momentum(&self) -> Vector3<f64> {
        self.attitude().transpose() * self.mass.principal.component_mul(&self.state.w)
    }

    /// World ← shape frame, for contact queries: the own-frame pose after
    /// the shape's placement.
    pub fn shape_pose(&self) -> Isometry3<f64> {
        let placement = self
            .shape
            .as_ref()
            .map_or(Isometry3::identity(), |s| s.placement);
        self.own_pose() * placement
    }

    /// World ← own frame: an own-frame point p lands at x + AᵀQᵀ(p − c).
    pub fn own_pose(&self) -> Isometry3<f64> {
        let r = Rotation3::from_matrix_unchecked(
            self.attitude().transpose() * self.mass.axes.transpose(),
        );
        let rotation = UnitQuaternion::from_rotation_matrix(&r);
        let own_origin = self.state.x - r * self.mass.centre;
        Isometry3::from_parts(Translation3::from(own_origin), rotation)
    }
}

/// Takes the states the rigid bodies sent ([`STATE_LEN`] per body, as
/// [`Body::write_state`] writes them) into `bodies`; an error if their
/// number does not match.
pub fn read_states(bodies: &mut [Body], states: &[f64]) -> Result<(), String> {
    if states.len() != STATE_LEN * bodies.len() {
        return Err(format!(
            "the rigid bodies sent {} values for {} bodies",
            states.len(),
            bodies.len()
        ));
    }
    for (b, s) in bodies.iter_mut().zip(states.chunks_exact(STATE_LEN)) {
        b.read_state(s);
    }
    Ok(())
}

/// Each of `bodies` moving at `time` [s] as its scene's motion (`motions`,
/// in order) says, or held (prescribed) until its release time: what
/// rigid-proc steps and what the structure's nodes meet.
pub fn hold(bodies: &mut [Body], motions: &[Motion], time: f64) {
    for (body, &scene) in bodies.iter_mut().zip(motions) {
        body.motion = body.motion_at(time, scene);
    }
}
