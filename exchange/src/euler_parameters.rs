//! Orientation as Euler parameters e = (e₀, e₁, e₂, e₃), a unit quaternion
//! (dissertation §3.1.1, eqs. 3.2–3.5): no singular angles, unlike the Euler
//! angles of eq. (2.14).

use nalgebra::{Matrix3, Rotation3, UnitQuaternion, Vector3, Vector4};

/// e = (e₀, e₁, e₂, e₃) with e₀² + e₁² + e₂² + e₃² = 1 (eq. 3.2).
pub type EulerParameters = Vector4<f64>;

/// No rotation: e = (1, 0, 0, 0).
pub fn identity() -> EulerParameters {
    Vector4::new(1.0, 0.0, 0.0, 0.0)
}

/// The rotation by `angle` about the unit vector `u`: e₀ = cos(α/2),
/// (e₁, e₂, e₃) = u sin(α/2) (eq. 3.3).
pub fn from_axis_angle(u: Vector3<f64>, angle: f64) -> EulerParameters {
    let s = (angle / 2.0).sin();
    Vector4::new((angle / 2.0).cos(), u.x * s, u.y * s, u.z * s)
}

/// The parameters of a rotation R from body axes to world axes, so that
/// [`attitude`] gives A = Rᵀ. Normalised (eq. 3.2): a matrix off orthogonal
/// by ε gives a quaternion off unit length by about ε, which repeated
/// conversions would otherwise compound.
pub fn from_rotation(r: &Rotation3<f64>) -> EulerParameters {
    let q = UnitQuaternion::from_rotation_matrix(r);
    let e = Vector4::new(q.w, q.i, q.j, q.k);
    e / e.norm()
}

/// The rotation matrix A of eq. (3.5): x′ = A x takes world coordinates to
/// body coordinates, x = Aᵀ x′ back (the transforms of eq. 3.6).
pub fn attitude(e: &EulerParameters) -> Matrix3<f64> {
    let (e0, e1, e2, e3) = (e[0], e[1], e[2], e[3]);
    Matrix3::new(
        e0 * e0 + e1 * e1 - e2 * e2 - e3 * e3,
        2.0 * (e1 * e2 + e0 * e3),
        2.0 * (e1 * e3 - e0 * e2),
        2.0 * (e1 * e2 - e0 * e3),
        e0 * e0 - e1 * e1 + e2 * e2 - e3 * e3,
        2.0 * (e2 * e3 + e0 * e1),
        2.0 * (e1 * e3 + e0 * e2),
        2.0 * (e2 * e3 - e0 * e1),
        e0 * e0 - e1 * e1 - e2 * e2 + e3 * e3,
    )
}

/// ė for the angular velocity `w` in body (principal) axes, the w of
/// Euler's equations (2.12).
///
/// Eq. (3.4) as printed has the opposite sign on the e × w terms; with the A of
/// eq. (3.5) that form holds for w in world axes. With body-axis w it breaks
/// Ȧ = −[w]ₓA, and a torque-free body's world angular momentum drifts; the
/// test `rate_moves_the_attitude_as_the_angular_velocity_says` pins this form.
pub fn rate(e: &EulerParameters, w: &Vector3<f64>) -> EulerParameters {
    let (e0, e1, e2, e3) = (e[0], e[1], e[2], e[3]);
    0.5 * Vector4::new(
        -e1 * w.x - e2 * w.y - e3 * w.z,
        e0 * w.x + e2 * w.z - e3 * w.y,
        e0 * w.y + e3 * w.x - e1 * w.z,
        e0 * w.z + e1 * w.y - e2 * w.x,
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn attitude_is_the_transpose_of_the_rotation_it_came_from() {
        let r = Rotation3::from_scaled_axis(Vector3::new(0.3, -1.1, 0.7));
        let a = attitude(&from_rotation(&r));
        assert!((a - r.matrix().transpose()).norm() < 1e-15);
        // Eq. (3.3): a quarter turn about z takes the world x axis to body −y.
        let e = from_axis_angle(Vector3::z(), std::f64::consts::FRAC_PI_2);
        assert!((a_times(&e, Vector3::x()) - Vector3::new(0.0, -1.0, 0.0)).norm() < 1e-15);
    }

    fn a_times(e: &EulerParameters, x: Vector3<f64>) -> Vector3<f64> {
        attitude(e) * x
    }

    #[test]
    fn rate_moves_the_attitude_as_the_angular_velocity_says() {
        // A world→body matrix of a frame turning at body rate w obeys
        // Ȧ = −[w]ₓ A; compare a central difference of eq. (3.5) along ė.
        let e = from_rotation(&Rotation3::from_scaled_axis(Vector3::new(0.4, 0.9, -0.2)));
        let w = Vector3::new(0.7, -1.3, 2.1);
        let de = rate(&e, &w);
        let h = 1e-6;
        let a_dot = (attitude(&(e + h * de)) - attitude(&(e - h * de))) / (2.0 * h);
        let expected = -w.cross_matrix() * attitude(&e);
        assert!((a_dot - expected).norm() < 1e-8, "{a_dot} vs {expected}");
        // ė keeps |e| = 1 to first order (eq. 3.2).
        assert!(e.dot(&de).abs() < 1e-15);
    }
}
