//! How large a step a spring-mass model allows: the highest eigenfrequency
//! bound of seed 000 eq. (3.7) and each scheme's stability interval on
//! undamped oscillation, ω·h ≤ y*. Together they give the sub-step count n_s
//! that a coupling window needs.

use crate::integrators::Scheme;

/// Seed 000 §3.1.2: ω_max·h < 0.1 "for stability and accuracy", the rule
/// behind the seed's choice of sub-steps.
pub const SEED_OMEGA_H: f64 = 0.1;

/// Upper bound on the highest angular eigenfrequency [rad/s] of the spring
/// network, seed 000 eq. (3.7) taken node by node: ω_max² ≤ max_i 2·Σ_j k_ij/m_i
/// over free nodes i (Gershgorin's theorem on M⁻¹K with axial stiffnesses).
/// With M neighbours of stiffness k and equal masses m this is eq. (3.7),
/// √(2Mk/m); node by node it stays tight when masses or stiffnesses vary.
/// Held nodes (1/m = 0) do not oscillate; 0 if no node is free and coupled.
pub fn omega_max(inv_mass: &[f64], couplings: &[(usize, usize, f64)]) -> f64 {
    let mut ksum = vec![0.0; inv_mass.len()];
    for &(i, j, k) in couplings {
        ksum[i] += k;
        ksum[j] += k;
    }
    ksum.iter()
        .zip(inv_mass)
        .map(|(k, w)| 2.0 * k * w)
        .fold(0.0, f64::max)
        .sqrt()
}

/// Where a scheme is stable on an undamped linear oscillation of angular
/// frequency ω with step h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interval {
    /// Stable at every step (A-stable, or claimed so by its authors).
    Unconditional,
    /// Stable for ω·h ≤ the value given.
    Bounded(f64),
    /// Unstable at every step: the amplification exceeds 1 on the whole
    /// imaginary axis, so energy grows however small h is (seed 003 §2.5.2).
    Empty,
}

/// The stability interval of `scheme` on ẍ = −ω²x, from its amplification:
/// - explicit Euler |1 + iy|² = 1 + y², explicit midpoint (Euler–Richardson)
///   and Heun (improved Euler) |1 + iy − y²/2|² = 1 + y⁴/4: empty;
/// - symplectic Euler (Euler–Cromer) and velocity Verlet: y ≤ 2;
/// - RK4: |R(iy)|² = 1 − y⁶/72 + y⁸/576 ≤ 1 for y ≤ 2√2;
/// - Newmark (seed 003 eq. 27, for α = 0): unconditional for 2β ≥ γ ≥ ½,
///   else y ≤ 1/√(γ/2 − β); HHT's parameters satisfy 2β ≥ γ;
/// - backward Euler: A-stable; Kang's method: unconditionally stable (Kang et al. 2000).
pub fn interval(scheme: Scheme) -> Interval {
    match scheme {
        Scheme::ExplicitEuler | Scheme::EulerRichardson | Scheme::ImprovedEuler => Interval::Empty,
        Scheme::EulerCromer | Scheme::VelocityVerlet => Interval::Bounded(2.0),
        Scheme::Rk4 => Interval::Bounded(2.0 * std::f64::consts::SQRT_2),
        Scheme::Newmark { beta, gamma, .. } => {
            if gamma < 0.5 - 1e-12 {
                Interval::Empty
            } else if 2.0 * beta >= gamma - 1e-12 {
                Interval::Unconditional
            } else {
                Interval::Bounded(1.0 / (gamma / 2.0 - beta).sqrt())
            }
        }
        Scheme::Kang | Scheme::BackwardEuler { .. } => Interval::Unconditional,
    }
}

/// The sub-step estimate for one coupling window of length `window` [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// ω_max of eq. (3.7) [rad/s].
    pub omega_max: f64,
    /// Largest step the scheme's interval allows, y*/ω_max [s]; None when
    /// the scheme is unconditionally stable, 0 when its interval is empty.
    pub stable_dt: Option<f64>,
    /// Smallest n_s with ω_max·window/n_s within the scheme's interval: 1 when
    /// unconditional; for an empty interval, the seed's ω_max·h < 0.1.
    pub n_s: u64,
    /// Smallest n_s with ω_max·h < 0.1, the seed's rule for any scheme.
    pub n_s_seed: u64,
}

/// Sub-steps of a window for `scheme` on a network with highest frequency `omega_max`.
pub fn estimate(omega_max: f64, window: f64, scheme: Scheme) -> Estimate {
    let steps = |y: f64| ((omega_max * window / y).ceil() as u64).max(1);
    let n_s_seed = steps(SEED_OMEGA_H);
    let (stable_dt, n_s) = match interval(scheme) {
        Interval::Unconditional => (None, 1),
        Interval::Bounded(y) => (Some(y / omega_max), steps(y)),
        Interval::Empty => (Some(0.0), n_s_seed),
    };
    Estimate {
        omega_max,
        stable_dt,
        n_s,
        n_s_seed,
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_bound_of_eq_3_7_holds_and_is_tight_on_a_uniform_chain() {
        // Fixed–fixed chain of n equal masses m and springs k: the exact
        // highest frequency is 2√(k/m)·sin(nπ/(2(n+1))) (e.g. Strang, Linear
        // Algebra and its Applications, §1.5), below eq. (3.7)'s √(2·2k/m).
        let (n, k, m) = (9usize, 50.0, 0.2);
        let mut inv_mass = vec![1.0 / m; n + 2];
        inv_mass[0] = 0.0;
        inv_mass[n + 1] = 0.0;
        let couplings: Vec<_> = (0..=n).map(|i| (i, i + 1, k)).collect();
        let bound = omega_max(&inv_mass, &couplings);
        let exact = 2.0
            * (k / m).sqrt()
            * (n as f64 * std::f64::consts::PI / (2.0 * (n as f64 + 1.0))).sin();
        assert!((bound - (4.0 * k / m).sqrt()).abs() < 1e-12 * bound);
        assert!(bound >= exact && bound < 1.02 * exact);
    }

    #[test]
    fn newmark_linear_acceleration_has_seed_003_eq_27_limit() {
        // Eq. (27): δt/T ≤ 1/(π√2·√(γ − 2β)) = 0.551 for β = 1/6, γ = 1/2.
        let s = Scheme::Newmark {
            beta: 1.0 / 6.0,
            gamma: 0.5,
            alpha: 0.0,
            newton: Default::default(),
        };
        let Interval::Bounded(y) = interval(s) else {
            panic!("linear acceleration is conditionally stable")
        };
        let dt_over_t = y / (2.0 * std::f64::consts::PI);
        assert!((dt_over_t - 0.5513).abs() < 1e-4);
    }
}
