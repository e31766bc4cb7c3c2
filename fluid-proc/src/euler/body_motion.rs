//! How a rigid body moves through a coupling window, as the gas sees it
//! (`bodies.rs`): its pose and centre at the window's start, carried
//! on at the velocity and spin rigid-proc sent. Geometry only.

use exchange::Body;
use nalgebra::{Isometry3, Translation3, UnitQuaternion, Vector3};

/// Where a body is at `time` and how it moves on from there: at constant
/// velocity and spin over a window (rigid-proc sends them each window; a
/// prescribed body does exactly that).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Kinematics {
    /// Box ← own frame (the box's low corner at the origin).
    pub pose: Isometry3<f64>,
    /// Centre of mass in the box's frame [m].
    pub centre: Vector3<f64>,
    /// [m/s]
    pub velocity: Vector3<f64>,
    /// Angular velocity, world axes [rad/s].
    pub spin: Vector3<f64>,
    /// [s]
    pub time: f64,
}

impl Kinematics {
    /// Where rigid-proc's `body` is at time `t` [s] and how it moves, in
    /// the frame of a box whose low corner is at `origin` [m].
    pub fn of(body: &Body, origin: [f64; 3], t: f64) -> Kinematics {
        let shift = Vector3::from(origin);
        Kinematics {
            pose: Translation3::from(-shift) * body.own_pose(),
            centre: body.state.x - shift,
            velocity: body.state.v,
            spin: body.world_angular_velocity(),
            time: t,
        }
    }

    /// The 17 values of a checkpoint: the pose's translation and
    /// quaternion (i, j, k, w), the centre, velocity, spin and time.
    pub fn to_values(&self) -> [f64; 17] {
        let t = self.pose.translation.vector;
        let q = self.pose.rotation.coords;
        let mut out = [0.0; 17];
        out[..3].copy_from_slice(t.as_slice());
        out[3..7].copy_from_slice(q.as_slice());
        out[7..10].copy_from_slice(self.centre.as_slice());
        out[10..13].copy_from_slice(self.velocity.as_slice());
        out[13..16].copy_from_slice(self.spin.as_slice());
        out[16] = self.time;
        out
    }

    /// The motion [`Kinematics::to_values`] wrote.
    pub fn from_values(v: &[f64; 17]) -> Kinematics {
        let q = nalgebra::Quaternion::new(v[6], v[3], v[4], v[5]);
        Kinematics {
            pose: Isometry3::from_parts(
                Translation3::new(v[0], v[1], v[2]),
                UnitQuaternion::from_quaternion(q),
            ),
            centre: Vector3::new(v[7], v[8], v[9]),
            velocity: Vector3::new(v[10], v[11], v[12]),
            spin: Vector3::new(v[13], v[14], v[15]),
            time: v[16],
        }
    }

    /// Whether every value is finite.
    pub fn is_finite(&self) -> bool {
        let v = [self.centre, self.velocity, self.spin];
        v.iter().all(|v| v.iter().all(|x| x.is_finite()))
    }

    /// Whether the body stands still.
    pub fn at_rest(&self) -> bool {
        self.velocity == Vector3::zeros() && self.spin == Vector3::zeros()
    }

    /// The pose and the centre of mass at time `t`: turned about the
    /// centre by spin·τ and moved by velocity·τ, τ = t − time.
    pub fn at(&self, t: f64) -> (Isometry3<f64>, Vector3<f64>) {
        let tau = t - self.time;
        let centre = self.centre + self.velocity * tau;
        let turn = UnitQuaternion::from_scaled_axis(self.spin * tau);
        let pose = Translation3::from(centre) * turn * Translation3::from(-self.centre) * self.pose;
        (pose, centre)
    }

    /// The velocity of the body's point `p` when its centre is at `centre`.
    pub fn velocity_at(&self, centre: &Vector3<f64>, p: &Vector3<f64>) -> Vector3<f64> {
        self.velocity + self.spin.cross(&(p - centre))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A body spinning at ω about z and moving at v: after τ its centre
    /// has moved by vτ, and a point r from the centre has turned by ωτ
    /// about it and moves at v + ω × r.
    #[test]
    fn kinematics_turn_about_the_centre_of_mass() {
        let centre = Vector3::new(1.0, 2.0, 0.0);
        let k = Kinematics {
            pose: Isometry3::translation(0.5, 2.0, 0.0),
            centre,
            velocity: Vector3::new(3.0, 0.0, 0.0),
            spin: Vector3::new(0.0, 0.0, std::f64::consts::PI),
            time: 1.0,
        };
        // The own-frame point at the own origin is (0.5, 2) in the box,
        // 0.5 m behind the centre along x.
        let (pose, c) = k.at(1.5);
        assert!((c - Vector3::new(2.5, 2.0, 0.0)).norm() < 1e-15);
        // Half a second at π rad/s: a quarter turn, to 0.5 m below the centre.
        let p = pose * nalgebra::Point3::origin();
        assert!(
            (p.coords - Vector3::new(2.5, 1.5, 0.0)).norm() < 1e-14,
            "{p}"
        );
        let v = k.velocity_at(&c, &p.coords);
        assert!((v - Vector3::new(3.0 + 0.5 * std::f64::consts::PI, 0.0, 0.0)).norm() < 1e-14);
        // A checkpoint's 17 values give the same motion back, bit for bit.
        let turned = Kinematics {
            pose: pose * UnitQuaternion::from_scaled_axis(Vector3::new(0.3, -0.2, 0.1)),
            ..k
        };
        assert_eq!(Kinematics::from_values(&turned.to_values()), turned);
    }
}
