//! The stability sweep against theory on a linear spring chain: the bound
//! ω_max of dissertation eq. (3.7) times each scheme's stability interval.

use structure_proc::stability::{interval, Interval};
use structure_section::Integrator;
use study::accuracy::scheme;
use study::stability::{self, log_grid, Chain, Outcome};

/// Measured limits may differ from the predicted ones by this much (issue 4).
const TOLERANCE: f64 = 0.10;

#[test]
fn explicit_limits_match_theory_and_unconditional_schemes_stay_stable() {
    let chain = Chain::default();
    let ks = [1e2, 1e5];
    // ω_max·h from 2e-4 to 200 at k = 1e2, from 6e-3 to 6e3 at k = 1e5.
    let dts = log_grid(1e-6, 1.0, 25);
    let fixed: Vec<Integrator> = Integrator::ALL
        .into_iter()
        .filter(|i| !i.is_adaptive())
        .collect();
    let cells = stability::map(&chain, &fixed, &ks, &dts, |_, _| {});
    let limits = stability::limits(&chain, &cells);
    assert!(
        chain.omega_max(ks[0]) * dts[dts.len() - 1] > 199.0,
        "the grid reaches ω_max·h = 200"
    );
    assert_eq!(limits.len(), fixed.len() * ks.len());
    for l in &limits {
        let name = l.integrator.name();
        match interval(scheme(l.integrator)) {
            Interval::Unconditional => {
                // Stable at every step of the grid, up to ω_max·h = 200 and 6e3,
                // far beyond every explicit limit.
                assert_eq!(l.measured, None, "{name} at k = {}", l.k);
            }
            // Explicit Euler, the midpoint rule, Heun: no interval, so the
            // limit is where |R(iy)|^(2n) reaches the growth factor of the rule.
            Interval::Bounded(_) | Interval::Empty => {
                let measured = l.measured.expect("an explicit scheme has a limit");
                let predicted = l.predicted.expect("a predicted limit");
                let deviation = (measured / predicted - 1.0).abs();
                assert!(
                    deviation < TOLERANCE,
                    "{name} at k = {}: measured {measured:e} s, predicted {predicted:e} s",
                    l.k
                );
            }
        }
    }
    // Euler–Cromer and velocity Verlet: ω·h ≤ 2 on the exact ω_max; the
    // measured limit brackets it closely (thesis §2.4; Hairer, Lubich &
    // Wanner, Geometric Numerical Integration, §I.5).
    for l in limits.iter().filter(|l| {
        matches!(
            l.integrator,
            Integrator::EulerCromer | Integrator::VelocityVerlet
        )
    }) {
        let y = l.measured.unwrap() * chain.exact_omega_max(l.k);
        assert!(
            (y / 2.0 - 1.0).abs() < 0.03,
            "{}: ω·h = {y}",
            l.integrator.name()
        );
    }
}

#[test]
fn the_rule_separates_stable_from_unstable_runs_of_one_scheme() {
    // RK4 just inside and just outside ω·h = 2√2 on the exact ω_max.
    let chain = Chain::default();
    let k = 1e3;
    let limit = 2.0 * std::f64::consts::SQRT_2 / chain.exact_omega_max(k);
    assert!(matches!(
        stability::probe(&chain, Integrator::Rk4, k, 0.97 * limit),
        Outcome::Stable(r) if r <= 1.0 + 1e-6
    ));
    assert!(matches!(
        stability::probe(&chain, Integrator::Rk4, k, 1.05 * limit),
        Outcome::Unstable { .. }
    ));
}
