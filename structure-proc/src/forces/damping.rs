//! Viscous damping between the two ends of a spring. Two laws, one per seed:
//! - thesis eq. (68): F_v,i = Σ_j k_ij·Δt·(v_j − v_i), the whole relative velocity;
//! - dissertation eq. (2.38): F_d = c·V⁽ⁱⁿᵗ⁾. We read V⁽ⁱⁿᵗ⁾, "the velocity due to the
//!   spring force only", as the rate of change of each spring's length, so the
//!   dashpot acts along the spring: F_d,i = c·((v_j − v_i)·e)·e. Rigid motion, and
//!   with it linear and angular momentum, is left alone.
//! Neither has an energy; both dissipate.

use super::spring::point;
use nalgebra::{Matrix3, Vector3};

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Law {
    /// Thesis eq. (68).
    RelativeVelocity,
    /// Dissertation eq. (2.38), along the spring.
    Axial,
}

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Damper {
    pub i: usize,
    pub j: usize,
    /// Coefficient [N·s/m]: k_ij·Δt for eq. (68), c for eq. (2.38).
    pub c: f64,
    /// Length below which the damper is idle: a slack string carries no force,
    /// viscous or elastic (thesis eq. 3). 0 for springs.
    pub slack_below: f64,
}

impl Damper {
    #[inline]
    fn geometry(&self, x: &[f64]) -> Option<Vector3<f64>> {
        let d = point(x, self.j) - point(x, self.i);
        let q = d.norm_squared();
        // d.norm() is q.sqrt(), the same bits.
        self.acts(q).then(|| d / q.sqrt())
    }

    /// Whether the damper acts when its ends are q = l² apart: its length
    /// above `slack_below` and above zero. √q > 0 exactly when q > 0, so a
    /// spring's damper (slack_below = 0) takes no square root.
    #[inline]
    fn acts(&self, q: f64) -> bool {
        if self.slack_below == 0.0 {
            q > 0.0
        } else {
            q.sqrt() > self.slack_below && q > 0.0
        }
    }

    /// The damping force on node i; node j gets its opposite.
    #[inline]
    pub fn force(&self, law: Law, x: &[f64], v: &[f64]) -> Vector3<f64> {
        let d = point(x, self.j) - point(x, self.i);
        let q = d.norm_squared();
        if !self.acts(q) {
            return Vector3::zeros();
        }
        let dv = point(v, self.j) - point(v, self.i);
        match law {
            Law::RelativeVelocity => dv * self.c,
            Law::Axial => {
                let e = d / q.sqrt();
                e * (self.c * e.dot(&dv))
            }
        }
    }

    /// The block S of s·C, C coupling the ends as [S −S; −S S]
    /// ([`Damper::damping_product`] is −S·(p_j − p_i) at i).
    pub fn damping_block(&self, law: Law, x: &[f64], s: f64) -> Matrix3<f64> {
        let Some(e) = self.geometry(x) else {
            return Matrix3::zeros();
        };
        match law {
            Law::RelativeVelocity => Matrix3::identity() * (self.c * s),
            Law::Axial => e * e.transpose() * (self.c * s),
        }
    }

    /// −(s·C·p) at node i, C = −∂F/∂v (symmetric, positive semi-definite); node j gets its opposite.
    #[inline]
    pub fn damping_product(&self, law: Law, x: &[f64], s: f64, p: &[f64]) -> Vector3<f64> {
        let Some(e) = self.geometry(x) else {
            return Vector3::zeros();
        };
        let q = point(p, self.j) - point(p, self.i);
        -match law {
            Law::RelativeVelocity => q * (self.c * s),
            Law::Axial => e * (self.c * s * e.dot(&q)),
        }
    }
}
