//! The simple pendulum of thesis §2.5.1 (m = 1 kg, L = 1 m) split over
//! rigid-proc (the ball) and structure-proc (a stiff string from a fixed point).

use canopy_tests::*;
use std::f64::consts::PI;
use structure_section::Integrator;

const L: f64 = 1.0;

/// Complete elliptic integral of the first kind K(k), by the arithmetic–geometric
/// mean: K(k) = π / (2·AGM(1, √(1−k²))) (Abramowitz & Stegun 17.6).
fn elliptic_k(k: f64) -> f64 {
    let (mut a, mut b) = (1.0f64, (1.0 - k * k).sqrt());
    while (a - b).abs() > 1e-15 {
        (a, b) = (0.5 * (a + b), (a * b).sqrt());
    }
    PI / (2.0 * a)
}

/// Exact period of the undamped pendulum released from rest at θ₀:
/// T = 4·K(sin(θ₀/2))·√(L/g).
fn exact_period(theta0: f64, g: f64) -> f64 {
    4.0 * elliptic_k((theta0 / 2.0).sin()) * (L / g).sqrt()
}

/// Run the pendulum scenario released at `theta0` with damping `c` (thesis eq. 61).
fn run(name: &str, theta0: f64, c: f64, end_time: f64) -> (Monitors, f64) {
    run_with(name, theta0, c, end_time, |_| {})
}

/// [`run`] with the scenario edited further by `edit`.
fn run_with(
    name: &str,
    theta0: f64,
    c: f64,
    end_time: f64,
    edit: impl FnOnce(&mut Scenario),
) -> (Monitors, f64) {
    let dir = scratch(name);
    let mut g = 0.0;
    let path = variant("pendulum", &dir, |s| {
        edit(s);
        s.run.end_time = end_time;
        s.run.output_interval = 0.0;
        let rigid = s.rigid.as_mut().unwrap();
        g = -rigid.gravity[2];
        let ball = &mut rigid.bodies[0];
        ball.position = [L * theta0.sin(), 0.0, -L * theta0.cos()];
        // A damping torque −c·θ̇ on a ball at distance L is the force −(c/L²)·v.
        ball.linear_damping = c / (L * L);
    });
    run_ok(&path, &dir.join("run"));
    (Monitors::read(&dir.join("run")), g)
}

/// Mean period from upward zero crossings of x, linearly interpolated.
fn measured_period(m: &Monitors) -> f64 {
    let (t, x) = (m.column("time"), m.column("rigid.ball.x"));
    let crossings: Vec<f64> = (1..t.len())
        .filter(|&i| x[i - 1] < 0.0 && x[i] >= 0.0)
        .map(|i| t[i - 1] - x[i - 1] * (t[i] - t[i - 1]) / (x[i] - x[i - 1]))
        .collect();
    assert!(crossings.len() >= 2, "fewer than two periods recorded");
    (crossings[crossings.len() - 1] - crossings[0]) / (crossings.len() - 1) as f64
}

#[test]
fn elliptic_period_ratio_matches_the_issue_value() {
    // T/T₀ = 2K(sin 30°)/π = 1.07318 for a 60° release.
    let ratio = exact_period(PI / 3.0, 9.81) / (2.0 * PI * (L / 9.81).sqrt());
    assert!((ratio - 1.07318).abs() < 1e-5, "{ratio}");
}

#[test]
fn small_amplitude_period_is_two_pi_root_l_over_g() {
    let (m, g) = run("small", 5f64.to_radians(), 0.0, 5.0);
    let t0 = 2.0 * PI * (L / g).sqrt();
    let t = measured_period(&m);
    assert!((t / t0 - 1.0).abs() < 0.01, "T = {t}, 2π√(L/g) = {t0}");
}

#[test]
fn sixty_degree_period_matches_the_elliptic_integral() {
    let (m, g) = run("sixty", PI / 3.0, 0.0, 5.0);
    let exact = exact_period(PI / 3.0, g);
    let t = measured_period(&m);
    assert!((t / exact - 1.0).abs() < 0.01, "T = {t}, exact {exact}");
    // Undamped: the coupled run conserves energy (kinetic + gravitational
    // + string) to 0.5 % of the energy that sloshes.
    let drift = energy_drift(&m, PI / 3.0, g);
    assert!(drift < 5e-3, "energy drift {drift:.3e}");
}

/// Largest departure of kinetic + potential energy from its start, as a
/// fraction of m·g·L(1 − cos θ₀), the energy that sloshes.
fn energy_drift(m: &Monitors, theta0: f64, g: f64) -> f64 {
    let e: Vec<f64> = m
        .column("kinetic_energy")
        .iter()
        .zip(m.column("potential_energy"))
        .map(|(k, p)| k + p)
        .collect();
    let drift = e.iter().map(|v| (v - e[0]).abs()).fold(0.0, f64::max);
    drift / (g * L * (1.0 - theta0.cos()))
}

/// Velocity Verlet across the process boundary. Under implicit coupling
/// with one impulse exchange per window the string's impulse is its force
/// integrated (by the sub-steps' trapezoids) along the chord of the ball's
/// path, and the ball takes it as a constant force: converged, the
/// average-vector-field method (McLachlan, Quispel & Robidoux 1999), which
/// keeps the energy exactly but for that quadrature. Measured: 4·10⁻⁷ of
/// the sloshing energy over 5 s, in 2.0 tries per window; the bound is
/// 25 times that. Explicit, the impulse is that of a predicted path and
/// 3.9 % of the energy goes in 5 s.
#[test]
fn velocity_verlet_keeps_the_energy_under_implicit_coupling() {
    let theta0 = PI / 3.0;
    let verlet = |s: &mut Scenario, scheme| {
        s.coupling.impulse_substeps = 1;
        s.coupling.scheme = scheme;
        s.structure.as_mut().unwrap().integrator = Integrator::VelocityVerlet;
    };
    let implicit = |s: &mut Scenario| verlet(s, scenario::SchemeName::Implicit);
    let (m, g) = run_with("verlet-implicit", theta0, 0.0, 5.0, implicit);
    let drift = energy_drift(&m, theta0, g);
    assert!(drift < 1e-5, "implicit: energy drift {drift:.3e}");
    let (t, exact) = (measured_period(&m), exact_period(theta0, g));
    assert!((t / exact - 1.0).abs() < 0.01, "T = {t}, exact {exact}");
    let tries = m.column("structure.implicit.tries");
    assert!(
        tries.iter().skip(1).all(|&n| n >= 2.0),
        "the loop was not iterated"
    );

    let explicit = |s: &mut Scenario| verlet(s, scenario::SchemeName::Explicit);
    let (m, g) = run_with("verlet-explicit", theta0, 0.0, 5.0, explicit);
    let lost = energy_drift(&m, theta0, g);
    assert!(lost > 1e-2, "explicit: energy drift {lost:.3e}");
}

/// θ(t) of thesis eqs. (60)–(61) by classical RK4 with a fine step.
fn reference_theta(theta0: f64, c: f64, g: f64, times: &[f64]) -> Vec<f64> {
    let m = 1.0;
    let f = |th: f64, om: f64| (om, -(g / L) * th.sin() - om * c / (m * L * L));
    let h: f64 = 1e-5;
    let (mut th, mut om, mut t) = (theta0, 0.0f64, 0.0f64);
    let mut out = Vec::with_capacity(times.len());
    for &target in times {
        while t < target - 1e-12 {
            let dt = h.min(target - t);
            let k1 = f(th, om);
            let k2 = f(th + 0.5 * dt * k1.0, om + 0.5 * dt * k1.1);
            let k3 = f(th + 0.5 * dt * k2.0, om + 0.5 * dt * k2.1);
            let k4 = f(th + dt * k3.0, om + dt * k3.1);
            th += dt / 6.0 * (k1.0 + 2.0 * k2.0 + 2.0 * k3.0 + k4.0);
            om += dt / 6.0 * (k1.1 + 2.0 * k2.1 + 2.0 * k3.1 + k4.1);
            t += dt;
        }
        out.push(th);
    }
    out
}

fn peaks(t: &[f64], y: &[f64]) -> Vec<(f64, f64)> {
    (1..y.len() - 1)
        .filter(|&i| y[i] > y[i - 1] && y[i] >= y[i + 1])
        .map(|i| (t[i], y[i]))
        .collect()
}

#[test]
fn damped_amplitude_decays_as_seed_equations_60_61() {
    let (theta0, c) = (PI / 3.0, 0.1);
    let (m, g) = run("damped", theta0, c, 10.0);
    let t = m.column("time");
    let (x, z) = (m.column("rigid.ball.x"), m.column("rigid.ball.z"));
    let theta: Vec<f64> = x.iter().zip(&z).map(|(x, z)| x.atan2(-z)).collect();
    let reference = reference_theta(theta0, c, g, &t);
    let (sim, exact) = (peaks(&t, &theta), peaks(&t, &reference));
    assert!(
        sim.len() >= 4 && sim.len() == exact.len(),
        "{} vs {} peaks",
        sim.len(),
        exact.len()
    );
    for ((ts, a), (te, b)) in sim.iter().zip(&exact) {
        assert!(
            (a / b - 1.0).abs() < 0.01,
            "peak at t = {ts}: amplitude {a} vs {b} (t = {te})"
        );
    }
    // And it really decays: the last peak is well below the release angle.
    assert!(sim.last().unwrap().1 < 0.8 * theta0);
}

/// Every window taken twice from its checkpoint while string and ball
/// trade four impulses per window: each try starts where the window
/// started and takes the exchanges in turn, so the run is the explicit run
/// bit for bit (a try must not start from where the last one ended).
#[test]
fn a_window_taken_twice_with_four_impulse_exchanges_is_the_explicit_window() {
    let theta0 = PI / 3.0;
    let (explicit, _) = run("twice-explicit", theta0, 0.0, 0.5);
    let (twice, _) = run_with("twice-implicit", theta0, 0.0, 0.5, |s| {
        assert_eq!(s.coupling.impulse_substeps, 4);
        s.coupling.scheme = scenario::SchemeName::Implicit;
        s.coupling.implicit = Some(scenario::ImplicitSection {
            accelerate: Some(vec!["body.states".into()]),
            min_iterations: 2,
            ..Default::default()
        });
    });
    assert!(twice.column("structure.implicit.tries")[1..]
        .iter()
        .all(|&n| n == 2.0));
    for name in &explicit.header {
        let (a, b) = (explicit.column(name), twice.column(name));
        let same = a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits());
        assert!(same && a.len() == b.len(), "{name} differs");
    }
}
