//! Hookean springs (thesis eq. 67) and strings that carry tension only, beyond
//! a compressive tolerance (thesis eq. 3).

use nalgebra::{Matrix3, Vector3};

#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Spring {
    pub i: usize,
    pub j: usize,
    /// Stiffness k_ij [N/m].
    pub k: f64,
    /// Rest length l⁰_ij [m].
    pub rest: f64,
    /// Strings carry tension only, beyond the compressive tolerance eps (thesis eq. 3).
    pub tension_only: bool,
    pub eps: f64,
}

#[inline]
pub fn point(x: &[f64], n: usize) -> Vector3<f64> {
    Vector3::new(x[3 * n], x[3 * n + 1], x[3 * n + 2])
}

/// ∂²l/∂x_j² of a length l = |d|: (I − e eᵀ)/l. Shared with the Delingette springs.
#[inline]
pub fn length_hessian(e: &Vector3<f64>, l: f64) -> Matrix3<f64> {
    (Matrix3::identity() - e * e.transpose()) / l
}

impl Spring {
    /// Stretch that produces force: l − l⁰ for a spring (eq. 67),
    /// max(l − l⁰ − eps, 0) for a string (eq. 3).
    #[inline]
    pub fn stretch(&self, l: f64) -> f64 {
        if self.tension_only {
            (l - self.rest - self.eps).max(0.0)
        } else {
            l - self.rest
        }
    }

    /// Tension k δ [N] at `x`, δ the active stretch.
    pub fn tension(&self, x: &[f64]) -> f64 {
        self.k * self.stretch((point(x, self.j) - point(x, self.i)).norm())
    }

    /// Elastic energy ½ k δ², δ the active stretch.
    pub fn energy(&self, x: &[f64]) -> f64 {
        let l = (point(x, self.j) - point(x, self.i)).norm();
        0.5 * self.k * self.stretch(l).powi(2)
    }

    /// The spring force k δ e on node i (eq. 67); node j gets its opposite.
    #[inline]
    pub fn force(&self, x: &[f64]) -> Vector3<f64> {
        let d = point(x, self.j) - point(x, self.i);
        let l = d.norm();
        // No branch on a zero tension: springs near rest would mispredict it.
        let per_length = if l > 0.0 {
            self.k * self.stretch(l) / l
        } else {
            0.0
        };
        d * per_length
    }

    /// The direction e, length l and tension T⁺ ≥ 0 the stiffness reads;
    /// `None` for a zero length or a slack string (no stiffness).
    #[inline]
    fn stiffness_geometry(&self, x: &[f64]) -> Option<(Vector3<f64>, f64, f64)> {
        let d = point(x, self.j) - point(x, self.i);
        let l = d.norm();
        let stretch = self.stretch(l);
        if l == 0.0 || (self.tension_only && stretch == 0.0) {
            return None;
        }
        Some((d / l, l, (self.k * stretch).max(0.0)))
    }

    /// The block S = s·(k e eᵀ + T⁺/l (I − e eᵀ)) of s·K: K couples the ends
    /// as [S −S; −S S] ([`Spring::stiffness_product`] is −S·(p_j − p_i) at i).
    pub fn stiffness_block(&self, x: &[f64], s: f64) -> Matrix3<f64> {
        let Some((e, l, t)) = self.stiffness_geometry(x) else {
            return Matrix3::zeros();
        };
        (e * e.transpose() * self.k + length_hessian(&e, l) * t) * s
    }

    /// −(s·K·p) at node i, K = ∂²E/∂x²; node j gets its opposite. The
    /// geometric part (T/l)(I − eeᵀ) is kept only under tension so that K stays
    /// positive semi-definite.
    #[inline]
    pub fn stiffness_product(&self, x: &[f64], s: f64, p: &[f64]) -> Vector3<f64> {
        let Some((e, l, t)) = self.stiffness_geometry(x) else {
            return Vector3::zeros();
        };
        let q = point(p, self.j) - point(p, self.i);
        -(e * (self.k * e.dot(&q)) + length_hessian(&e, l) * q * t) * s
    }
}
