//! The spring pendulum of thesis §2.5.2, run by structure-proc alone: the
//! trajectory follows an independent solution of eqs. (63)–(64) and the energy
//! of eq. (62) is conserved without damping.

use canopy_tests::*;

const M: f64 = 1.0;
const K: f64 = 100.0;
const A: f64 = 1.0;
const L: f64 = 0.8;

/// Thesis eqs. (63)–(64): the accelerations of the mass.
fn accel(x: f64, y: f64) -> (f64, f64) {
    let r1 = (x * x + (y - A).powi(2)).sqrt();
    let r2 = (x * x + (y + A).powi(2)).sqrt();
    let ax = -K / M * (2.0 * x - L * (x / r1 + x / r2));
    let ay = -K / M * (2.0 * y - L * ((y - A) / r1 + (y + A) / r2));
    (ax, ay)
}

/// Eqs. (63)–(64) by classical RK4 with a step of 1e-5 s, to `t_end`.
fn reference(t_end: f64) -> [f64; 4] {
    let f = |s: [f64; 4]| {
        let (ax, ay) = accel(s[0], s[1]);
        [s[2], s[3], ax, ay]
    };
    let h = 1e-5;
    let mut s = [0.3, 0.2, 0.0, 0.0];
    for _ in 0..(t_end / h).round() as usize {
        let add = |s: [f64; 4], k: [f64; 4], c: f64| std::array::from_fn(|i| s[i] + c * k[i]);
        let k1 = f(s);
        let k2 = f(add(s, k1, h / 2.0));
        let k3 = f(add(s, k2, h / 2.0));
        let k4 = f(add(s, k3, h));
        s = std::array::from_fn(|i| s[i] + h / 6.0 * (k1[i] + 2.0 * k2[i] + 2.0 * k3[i] + k4[i]));
    }
    s
}

#[test]
fn spring_pendulum_follows_eqs_63_64_and_keeps_its_energy() {
    let dir = scratch("spring-pendulum");
    let path = variant("spring-pendulum", &dir, |s| {
        s.run.end_time = 5.0;
        s.run.output_interval = 0.0;
    });
    run_ok(&path, &dir.join("run"));
    let m = Monitors::read(&dir.join("run"));
    let (x, y) = (m.column("structure.bob.x"), m.column("structure.bob.y"));
    let t = m.column("time");
    let last = t.len() - 1;
    assert!((t[last] - 5.0).abs() < 1e-9, "ends at {}", t[last]);
    let exact = reference(5.0);
    let miss = ((x[last] - exact[0]).powi(2) + (y[last] - exact[1]).powi(2)).sqrt();
    // Velocity Verlet at ω·Δt ≈ 0.014: a phase error of order 1e-3 rad after 5 s.
    assert!(
        miss < 2e-3,
        "bob at ({}, {}) vs ({}, {}): {miss} m apart",
        x[last],
        y[last],
        exact[0],
        exact[1]
    );
    let (ke, pe) = (
        m.column("structure.kinetic_energy"),
        m.column("structure.potential_energy"),
    );
    let e0 = ke[0] + pe[0];
    let worst = (0..t.len())
        .map(|i| ((ke[i] + pe[i]) / e0 - 1.0).abs())
        .fold(0.0, f64::max);
    assert!(
        worst < 1e-3,
        "energy of eq. (62) drifts by {worst} of {e0} J"
    );
}
