//! How damping narrows an explicit scheme's stability interval. Viscous
//! damping is a velocity-dependent force, which an explicit step takes
//! explicitly too; on ẍ = −ω²x − γẋ the step's amplification then depends
//! on y = ω·h and g = γ·h, and the largest stable y falls as g grows (for
//! central differences, ω·h ≤ 2(√(1 + ξ²) − ξ) with ξ = γ/(2ω): Belytschko,
//! Liu & Moran, *Nonlinear Finite Elements*, 2000, §6.3). Thesis eq. (68)'s
//! damping, c_ij = k_ij·Δt, gives γ ≈ ω²·Δt at the top mode, so g = y²:
//! velocity Verlet is then stable to y = √2, Euler–Cromer to 2/√3, not 2.
//!
//! Rather than a formula per scheme, the interval is found by stepping the
//! damped oscillator with the scheme's own code and bisecting on the
//! spectral radius of its one-step map (x, v) → (x', v').

use crate::integrators::integrator;
use crate::system::System;
use structure_section::Scheme;

/// How the network's damping rate γ [1/s] scales with the step h: the
/// largest rate over the nodes, max_i 2·Σ_j c_ij/m_i (Gershgorin on M⁻¹C,
/// as eq. 3.7 bounds ω_max on M⁻¹K).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum DampingRate {
    None,
    /// γ = r·h [r in 1/s²]: thesis eq. (68)'s c_ij = k_ij·Δt.
    PerStep(f64),
    /// γ fixed [1/s]: dissertation eq. (2.38)'s c.
    Constant(f64),
}

impl DampingRate {
    /// g = γ·h at y = ω·h.
    fn g(self, y: f64, omega: f64) -> f64 {
        let h = y / omega;
        match self {
            DampingRate::None => 0.0,
            DampingRate::PerStep(r) => r * h * h,
            DampingRate::Constant(gamma) => gamma * h,
        }
    }
}

/// ẍ = −x − γẋ on one node of unit mass (its x component).
struct Oscillator {
    gamma: f64,
    inv_mass: [f64; 1],
}

impl System for Oscillator {
    fn nodes(&self) -> usize {
        1
    }

    fn inv_mass(&self) -> &[f64] {
        &self.inv_mass
    }

    fn force(&self, x: &[f64], v: &[f64], f: &mut [f64]) {
        f[0] = -x[0] - self.gamma * v[0];
        f[1] = 0.0;
        f[2] = 0.0;
    }

    fn jacobian_product(&self, _: &[f64], _: &[f64], a: f64, b: f64, p: &[f64], out: &mut [f64]) {
        out[0] = (a + b * self.gamma) * p[0];
        out[1] = 0.0;
        out[2] = 0.0;
    }

    fn couplings(&self) -> &[(usize, usize, f64)] {
        &[]
    }
}

/// The spectral radius of one step of `scheme` on the oscillator at ω = 1,
/// h = y, γ = g/y.
fn spectral_radius(scheme: Scheme, y: f64, g: f64) -> f64 {
    let sys = Oscillator {
        gamma: g / y,
        inv_mass: [1.0],
    };
    let mut columns = [[0.0; 2]; 2];
    for (c, (x0, v0)) in [(1.0, 0.0), (0.0, 1.0)].into_iter().enumerate() {
        let (mut x, mut v) = ([x0, 0.0, 0.0], [v0, 0.0, 0.0]);
        // A fresh integrator: its step from (x, v) alone.
        if integrator(scheme).step(&sys, y, &mut x, &mut v).is_err() {
            return f64::INFINITY;
        }
        columns[c] = [x[0], v[0]];
    }
    let [[a, c], [b, d]] = columns;
    let (trace, det) = (a + d, a * d - b * c);
    let disc = trace * trace - 4.0 * det;
    match disc >= 0.0 {
        true => 0.5 * (trace.abs() + disc.sqrt()),
        false => det.sqrt(),
    }
}

/// The largest y = ω_max·h in (0, `undamped`] at which the one-step
/// `scheme` stays stable with the network's `damping` at `omega` [rad/s]:
/// scanned upward, then bisected at the first instability.
pub fn damped_bound(scheme: Scheme, undamped: f64, omega: f64, damping: DampingRate) -> f64 {
    if damping == DampingRate::None || !one_step(scheme) {
        return undamped;
    }
    let stable = |y: f64| spectral_radius(scheme, y, damping.g(y, omega)) <= 1.0 + 1e-12;
    const SCAN: usize = 400;
    let mut lo = 0.0;
    for i in 1..=SCAN {
        let y = undamped * i as f64 / SCAN as f64;
        if !stable(y) {
            let mut hi = y;
            for _ in 0..50 {
                let mid = 0.5 * (lo + hi);
                match stable(mid) {
                    true => lo = mid,
                    false => hi = mid,
                }
            }
            return lo;
        }
        lo = y;
    }
    undamped
}

/// Schemes whose step is a map of (x, v) alone: a 2 × 2 amplification.
/// Newmark carries its acceleration, so its damped interval is not this.
fn one_step(scheme: Scheme) -> bool {
    matches!(
        scheme,
        Scheme::EulerCromer | Scheme::VelocityVerlet | Scheme::Rk4
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Undamped, the scan finds the analytic intervals: y = 2 for velocity
    /// Verlet and Euler–Cromer, 2√2 for RK4.
    #[test]
    fn undamped_the_intervals_are_the_analytic_ones() {
        for (scheme, y) in [
            (Scheme::VelocityVerlet, 2.0),
            (Scheme::EulerCromer, 2.0),
            (Scheme::Rk4, 2.0 * std::f64::consts::SQRT_2),
        ] {
            let tiny = DampingRate::Constant(1e-300);
            let found = damped_bound(scheme, y, 1.0, tiny);
            assert!((found - y).abs() < 1e-9, "{scheme:?}: {found}");
        }
    }

    /// Thesis eq. (68)'s damping (γ = ω²h, g = y²): Euler–Cromer's one-step
    /// map has trace 2 − 2y², determinant 1 − y², so |trace| ≤ 1 + det gives
    /// y ≤ 2/√3; velocity Verlet, whose damping reads the Euler predictor,
    /// is stable to √2.
    #[test]
    fn relative_velocity_damping_narrows_the_intervals() {
        let omega = 1.0;
        let damping = DampingRate::PerStep(omega * omega);
        let ec = damped_bound(Scheme::EulerCromer, 2.0, omega, damping);
        let vv = damped_bound(Scheme::VelocityVerlet, 2.0, omega, damping);
        assert!((ec - 2.0 / 3f64.sqrt()).abs() < 1e-9, "{ec}");
        assert!((vv - 2f64.sqrt()).abs() < 1e-9, "{vv}");
    }

    /// Central differences with damping ratio ξ (Belytschko et al. §6.3):
    /// ω·h ≤ 2(√(1 + ξ²) − ξ); Euler–Cromer is the same map.
    #[test]
    fn a_fixed_damping_ratio_gives_the_central_difference_limit() {
        let xi: f64 = 0.3;
        let found = damped_bound(
            Scheme::EulerCromer,
            2.0,
            1.0,
            DampingRate::Constant(2.0 * xi),
        );
        let exact = 2.0 * ((1.0 + xi * xi).sqrt() - xi);
        assert!((found - exact).abs() < 1e-9, "{found} against {exact}");
    }
}
