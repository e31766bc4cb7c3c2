//! Advancing one body over one step (dissertation §2.4 and §3.1.1): the centre
//! of mass under the total force, the rotation by Euler's equations (2.12)
//! in principal axes with the orientation as Euler parameters (3.4), all
//! with the fourth-order Runge–Kutta step (3.1); e is renormalised after
//! every step to keep eq. (3.2).

use crate::rk4::rk4;
use exchange::euler_parameters as ep;
use exchange::Motion;
use exchange::{Body, State};
use nalgebra::{Rotation3, Vector3, Vector4};

/// Force and torque about the centre of mass [N, N·m], world axes, held
/// over a step (the fluid's eq. 2.40 load, for instance).
#[derive(Debug, Clone, Copy, Default, PartialEq)]
pub struct Load {
    pub force: Vector3<f64>,
    pub torque: Vector3<f64>,
}

/// Advance `body` by `h` under `load` and `gravity`.
pub fn advance(body: &mut Body, load: &Load, gravity: &Vector3<f64>, h: f64) {
    match body.motion {
        Motion::Static => {}
        Motion::Prescribed => prescribed(body, h),
        Motion::Dynamic => dynamic(body, load, gravity, h),
    }
}

/// Constant velocity and world angular velocity, whatever acts on the body.
fn prescribed(body: &mut Body, h: f64) {
    let omega = body.world_angular_velocity();
    let s = &mut body.state;
    s.x += s.v * h;
    let turn = Rotation3::from_scaled_axis(omega * h);
    let r = turn * Rotation3::from_matrix_unchecked(ep::attitude(&s.e).transpose());
    s.e = ep::from_rotation(&r);
    s.w = ep::attitude(&s.e) * omega;
}

fn dynamic(body: &mut Body, load: &Load, gravity: &Vector3<f64>, h: f64) {
    let m = body.mass.mass;
    let i = body.mass.principal;
    let b = body.damping;
    let u = pack(&body.state);
    let next = rk4(&u, h, |u| {
        let s = unpack(u);
        let accel = load.force / m + gravity - s.v * (b / m);
        // Torque in principal axes at this stage's orientation.
        let tau = ep::attitude(&s.e) * load.torque;
        let w = s.w;
        // Eq. (2.12): Iᵢ ẇᵢ = τᵢ + (I_j − I_k) w_j w_k, (i, j, k) cyclic. A
        // mass point (all Iᵢ = 0) does not rotate.
        let w_dot = Vector3::from_fn(|n, _| {
            let (j, k) = ((n + 1) % 3, (n + 2) % 3);
            if i[n] > 0.0 {
                (tau[n] + (i[j] - i[k]) * w[j] * w[k]) / i[n]
            } else {
                0.0
            }
        });
        pack(&State {
            x: s.v,
            v: accel,
            e: ep::rate(&s.e, &s.w),
            w: w_dot,
        })
    });
    let mut s = unpack(&next);
    s.e /= s.e.norm();
    body.state = s;
}

/// A state's 13 values: centre, velocity, Euler parameters, w.
pub(crate) fn pack(s: &State) -> [f64; 13] {
    let mut u = [0.0; 13];
    u[0..3].copy_from_slice(s.x.as_slice());
    u[3..6].copy_from_slice(s.v.as_slice());
    u[6..10].copy_from_slice(s.e.as_slice());
    u[10..13].copy_from_slice(s.w.as_slice());
    u
}

/// The state [`pack`] gave.
pub(crate) fn unpack(u: &[f64; 13]) -> State {
    State {
        x: Vector3::new(u[0], u[1], u[2]),
        v: Vector3::new(u[3], u[4], u[5]),
        e: Vector4::new(u[6], u[7], u[8], u[9]),
        w: Vector3::new(u[10], u[11], u[12]),
    }
}
