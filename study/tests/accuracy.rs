//! The accuracy study's measured orders against each scheme's theoretical
//! order (thesis §2.4), on systems with exact solutions: the damped
//! oscillator of thesis appendix A (eqs. 77–81) and the undamped simple
//! pendulum (thesis eqs. 58–61, exact through Jacobi's elliptic functions).

use structure_section::Integrator;
use study::accuracy::{ladder, summarise, sweep, Status};
use study::reference::{by_name, Reference};

/// The default ladder of `coupler study accuracy`: 0.125 s down by 13 halvings.
fn default_ladder() -> Vec<f64> {
    ladder(0.125, 13)
}

/// Every fixed-step integrator; the adaptive one has its own test below.
fn fixed_step() -> Vec<Integrator> {
    Integrator::ALL
        .into_iter()
        .filter(|i| !i.is_adaptive())
        .collect()
}

fn check_orders(system: &dyn Reference) {
    let runs = sweep(system, &fixed_step(), &default_ladder(), |_| {});
    let mut failures = Vec::new();
    for s in summarise(&runs, 1e-4) {
        let p = s.theoretical_order as f64;
        match s.order {
            Some(o) if (o - p).abs() <= 0.15 => {}
            other => failures.push(format!(
                "{}: measured {other:?}, theory {p}",
                s.integrator.name()
            )),
        }
    }
    assert!(failures.is_empty(), "{}: {failures:#?}", system.name());
}

#[test]
fn measured_orders_match_theory_on_the_damped_oscillator() {
    check_orders(by_name("damped-oscillator").unwrap().as_ref());
}

#[test]
fn measured_orders_match_theory_on_the_simple_pendulum() {
    check_orders(by_name("pendulum").unwrap().as_ref());
}

/// Thesis §2.5.2: on the undamped spring pendulum explicit Euler gains
/// energy until it diverges, while velocity Verlet, being symplectic, keeps
/// the energy within O(ω²dt²) at the same step.
#[test]
fn explicit_euler_diverges_on_the_spring_pendulum_where_verlet_keeps_its_energy() {
    let system = by_name("spring-pendulum").unwrap();
    let runs = sweep(
        system.as_ref(),
        &[Integrator::ExplicitEuler, Integrator::VelocityVerlet],
        &[1.0 / 64.0],
        |_| {},
    );
    assert!(
        matches!(runs[0].status, Status::Diverged(_)),
        "explicit Euler: {:?}",
        runs[0]
    );
    assert_eq!(runs[1].status, Status::Ok);
    // ω = √(2K/M) ≈ 14 s⁻¹, (ω·dt)² ≈ 0.05: Verlet's energy error is a tenth of that.
    assert!(runs[1].error < 1e-2, "velocity Verlet: {:?}", runs[1]);
}

/// Adaptive Dormand–Prince 5(4) on the damped oscillator: the global error
/// follows the tolerance (Hairer, Nørsett & Wanner, Solving ODEs I, §II.4:
/// "tolerance proportionality"), and against its mean internal step it
/// converges at the pair's fifth order.
#[test]
fn adaptive_error_follows_its_tolerance_at_fifth_order() {
    let system = by_name("damped-oscillator").unwrap();
    let runs = sweep(
        system.as_ref(),
        &[Integrator::DormandPrince],
        &default_ladder(),
        |_| {},
    );
    let tight: Vec<_> = runs
        .iter()
        .filter(|r| r.tolerance.unwrap() <= 1e-5)
        .collect();
    assert!(tight.len() >= 6);
    for r in &tight {
        assert_eq!(r.status, Status::Ok);
        let ratio = r.error / r.tolerance.unwrap();
        assert!(
            (0.1..=10.0).contains(&ratio),
            "tolerance {:e}: error {:e}",
            r.tolerance.unwrap(),
            r.error
        );
    }
    for w in tight.windows(2) {
        assert!(w[1].error < w[0].error && w[1].steps > w[0].steps);
    }
    let order = summarise(&runs, 1e-4)[0].order.unwrap();
    assert!((order - 5.0).abs() < 0.5, "order {order}");
}
