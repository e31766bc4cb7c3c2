//! How large a step a spring-mass model allows: the highest eigenfrequency
//! bound of dissertation eq. (3.7), computed from the model; each scheme's
//! stability interval on undamped oscillation, ω·h ≤ y*; and from both the
//! sub-step count n_s a coupling window needs, which structure-proc's
//! `--check` answer gives to `coupler check`, the run's warning and the
//! manifest.

use crate::damped::{damped_bound, DampingRate};
use crate::network::Network;
use structure_section::Scheme;

/// The monitor in which the structure reports its ω_max [rad/s].
pub const OMEGA_MAX_MONITOR: &str = "omega_max";

/// Dissertation §3.1.2: ω_max·h < 0.1 "for stability and accuracy", the rule
/// behind the dissertation's choice of sub-steps.
pub const SEED_OMEGA_H: f64 = 0.1;

/// Where a scheme is stable on an undamped linear oscillation of angular
/// frequency ω with step h.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Interval {
    /// Stable at every step (A-stable, or claimed so by its authors).
    Unconditional,
    /// Stable for ω·h ≤ the value given.
    Bounded(f64),
    /// Unstable at every step: the amplification exceeds 1 on the whole
    /// imaginary axis, so energy grows however small h is (thesis §2.5.2).
    Empty,
}

/// The stability interval of `scheme` on ẍ = −ω²x, from its amplification:
/// - explicit Euler |1 + iy|² = 1 + y², explicit midpoint (Euler–Richardson)
///   and Heun (improved Euler) |1 + iy − y²/2|² = 1 + y⁴/4: empty;
/// - symplectic Euler (Euler–Cromer) and velocity Verlet: y ≤ 2;
/// - RK4: |R(iy)|² = 1 − y⁶/72 + y⁸/576 ≤ 1 for y ≤ 2√2;
/// - Newmark (thesis eq. 27, for α = 0): unconditional for 2β ≥ γ ≥ ½,
///   else y ≤ 1/√(γ/2 − β); HHT's parameters satisfy 2β ≥ γ;
/// - backward Euler: A-stable; Kang's method: unconditionally stable (Kang et al. 2000);
/// - adaptive Dormand–Prince: its step control takes internal steps as small as needed.
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
        // Dormand–Prince shrinks its internal steps until its error estimate
        // holds, which keeps it stable at any outer step, at a cost.
        Scheme::Kang | Scheme::BackwardEuler { .. } | Scheme::DormandPrince { .. } => {
            Interval::Unconditional
        }
    }
}

impl Interval {
    /// A stable name for files: "unconditional", "bounded" or "empty".
    pub fn label(&self) -> &'static str {
        match self {
            Interval::Unconditional => "unconditional",
            Interval::Bounded(_) => "bounded",
            Interval::Empty => "empty",
        }
    }
}

/// The sub-step estimate for one coupling window of length `window` [s].
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Estimate {
    /// ω_max of eq. (3.7) [rad/s].
    pub omega_max: f64,
    /// The scheme's interval with the network's damping (`damped.rs`).
    pub interval: Interval,
    /// Largest step the scheme's interval allows, y*/ω_max [s]; None when
    /// the scheme is unconditionally stable, 0 when its interval is empty.
    pub stable_dt: Option<f64>,
    /// Smallest n_s with ω_max·window/n_s within the scheme's interval: 1 when
    /// unconditional; for an empty interval, the dissertation's ω_max·h < 0.1.
    pub n_s: u64,
    /// Smallest n_s with ω_max·h < 0.1, the dissertation's rule for any scheme.
    pub n_s_seed: u64,
}

/// Sub-steps of a window for `scheme` on a network with highest frequency
/// `omega_max` and the given `damping`.
pub fn estimate(omega_max: f64, window: f64, scheme: Scheme, damping: DampingRate) -> Estimate {
    let steps = |y: f64| ((omega_max * window / y).ceil() as u64).max(1);
    let n_s_seed = steps(SEED_OMEGA_H);
    let interval = match interval(scheme) {
        Interval::Bounded(y) => Interval::Bounded(damped_bound(scheme, y, omega_max, damping)),
        other => other,
    };
    let (stable_dt, n_s) = match interval {
        Interval::Unconditional => (None, 1),
        Interval::Bounded(y) => (Some(y / omega_max), steps(y)),
        Interval::Empty => (Some(0.0), n_s_seed),
    };
    Estimate {
        omega_max,
        interval,
        stable_dt,
        n_s,
        n_s_seed,
    }
}

/// The network's damping rate (`damped.rs`): max_i 2·Σ_j c_ij/m_i over the
/// free nodes, its dampers built for the step `dt` [s] (thesis eq. 68's
/// coefficients grow with it).
pub fn damping_rate(net: &Network, dt: f64) -> DampingRate {
    let Some(law) = net.damping else {
        return DampingRate::None;
    };
    let mut csum = vec![0.0; net.inv_mass.len()];
    for d in &net.dampers {
        csum[d.i] += d.c;
        csum[d.j] += d.c;
    }
    let gamma = csum
        .iter()
        .zip(&net.inv_mass)
        .map(|(c, w)| 2.0 * c * w)
        .fold(0.0, f64::max);
    match law {
        _ if gamma == 0.0 => DampingRate::None,
        crate::forces::damping::Law::RelativeVelocity => DampingRate::PerStep(gamma / dt),
        crate::forces::damping::Law::Axial => DampingRate::Constant(gamma),
    }
}

/// Why `substeps` sub-steps of a window are too few for `scheme`, if they
/// are: the structure step lies above the scheme's stability limit, or, for a
/// scheme with no interval, above the dissertation's ω_max·h < 0.1.
pub fn warning(est: &Estimate, window: f64, substeps: u32, integrator: &str) -> Option<String> {
    let dt = window / substeps as f64;
    let y = est.omega_max * dt;
    match est.stable_dt {
        Some(limit) if limit > 0.0 => (dt > limit).then(|| {
            format!(
                "the structure step Δt_s = {dt:e} s is above {limit:.3e} s, the step {integrator} \
                 is sure to be stable at (ω_max·Δt_s = {y:.3} with ω_max = {:.4e} rad/s, the dissertation \
                 eq. 3.7's upper bound); [structure] substeps = {} or more guarantees it",
                est.omega_max, est.n_s
            )
        }),
        Some(_) => (y > SEED_OMEGA_H).then(|| {
            format!(
                "{integrator} gains energy at every step on undamped oscillation, and \
                 ω_max·Δt_s = {y:.3} (ω_max = {:.4e} rad/s, dissertation eq. 3.7) is above the dissertation's 0.1; \
                 [structure] substeps = {} or more keeps ω_max·Δt_s < 0.1",
                est.omega_max, est.n_s_seed
            )
        }),
        None => None,
    }
}

/// Upper bound on the highest angular frequency [rad/s] of a rigid body on
/// the strings that hold it, eq. (3.7) node by node as [`omega_max`] does:
/// each attached node, of effective inverse mass `weights[a]` (its body's
/// 1/m plus the turn its point takes, |r|²/I_min), against the stiffness of
/// the springs that reach it. The structure holds such a node on its path
/// over an impulse sub-step while rigid-proc moves the body by the impulse:
/// on a string to a fixed point that exchange has the one-step map of
/// determinant 1 and trace 2 − y² (y = ω·Δt_i), stable for y ≤ 2.
pub fn attached_omega(
    attached: &[usize],
    weights: &[f64],
    couplings: &[(usize, usize, f64)],
) -> f64 {
    let stiffness = |node: usize| -> f64 {
        let touching = couplings
            .iter()
            .filter(|(i, j, _)| *i == node || *j == node);
        touching.map(|c| c.2).sum()
    };
    attached
        .iter()
        .zip(weights)
        .map(|(&n, w)| (2.0 * stiffness(n) * w).sqrt())
        .fold(0.0, f64::max)
}

/// The stability interval of a body's exchange of impulses with its
/// strings, ω·Δt_i ≤ 2 ([`attached_omega`]).
pub const ATTACHED_INTERVAL: f64 = 2.0;

/// Upper bound on the highest angular eigenfrequency [rad/s] of the spring
/// network, dissertation eq. (3.7) taken node by node: ω_max² ≤ max_i 2·Σ_j k_ij/m_i
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

#[cfg(test)]
mod tests {
    use super::*;

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
}
