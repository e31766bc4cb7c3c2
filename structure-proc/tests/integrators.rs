//! Every time integrator against the exact damped oscillator of the thesis
//! appendix A (k = 3 N/m, m = 2 kg, x₀ = 2 m): the measured order of convergence
//! must lie within 0.15 of the scheme's theoretical order.

mod common;

use common::*;
use structure_proc::forces::damping::{Damper, Law};
use structure_proc::forces::Loads;
use structure_proc::integrators::theoretical_order;
use structure_proc::network::Network;
use structure_proc::{Model, NodeKind, Spring};

const K: f64 = 3.0;
const M: f64 = 2.0;
const X0: f64 = 2.0;
/// Damping c [N·s/m]: a damping ratio c/(2√(km)) of about 0.1.
const C: f64 = 0.5;
/// Rest length of the spring; the mass moves along it, so the spring stays linear.
const REST: f64 = 10.0;

/// Thesis eqs. (77)–(81) with v₀ = 0: x(t) = A e^{−ct/2m} sin(ωt + φ), and
/// its derivative; the study crate's reference oscillator has the same k, m, x₀, c.
fn exact(t: f64) -> (f64, f64) {
    let r = study::reference::Oscillator::damped();
    assert_eq!((r.k, r.m, r.x0, r.c), (K, M, X0, C), "the same oscillator");
    r.exact(t)
}

/// The oscillator as a spring-mass model: a fixed node at the origin, the mass
/// at REST + x₀ on the x axis, a spring and an axial dashpot (dissertation eq. 2.38).
fn oscillator() -> Model {
    let mut m = Model {
        x: vec![0.0, 0.0, 0.0, REST + X0, 0.0, 0.0],
        v: vec![0.0; 6],
        net: Network {
            mass: vec![0.0, M],
            kind: vec![NodeKind::Fixed, NodeKind::Free],
            ..Default::default()
        },
        ..Default::default()
    };
    m.springs.push(Spring {
        i: 0,
        j: 1,
        k: K,
        rest: REST,
        tension_only: false,
        eps: 0.0,
    });
    m.dampers.push(Damper {
        i: 0,
        j: 1,
        c: C,
        slack_below: 0.0,
    });
    m.damping = Some(Law::Axial);
    m.prepare();
    m
}

/// Largest error |x − x_e| + |v − v_e|/ω₀ over the samples t = 0.5, 1, …, 10 s.
fn error(scheme: Scheme, dt: f64) -> f64 {
    let mut m = oscillator();
    let mut integrator = structure_proc::integrator(scheme);
    let w0 = (K / M).sqrt();
    let steps_per_sample = (0.5 / dt).round() as usize;
    let mut worst: f64 = 0.0;
    for sample in 1..=20 {
        for _ in 0..steps_per_sample {
            m.step(integrator.as_mut(), &Loads::default(), dt).unwrap();
        }
        let (x, v) = exact(sample as f64 * 0.5);
        worst = worst.max((m.x[3] - REST - x).abs() + (m.v[3] - v).abs() / w0);
    }
    assert!(
        m.x[4] == 0.0 && m.x[5] == 0.0,
        "the motion stays on the spring's axis"
    );
    worst
}

#[test]
fn every_integrator_converges_at_its_theoretical_order() {
    let mut report = String::new();
    let mut failures = Vec::new();
    for scheme in all_schemes() {
        let p = theoretical_order(scheme) as f64;
        // Steps in the asymptotic range, above round-off: errors from ~1e-2 down.
        let base = match p as u32 {
            1 => 1.0 / 400.0,
            2 => 1.0 / 50.0,
            _ => 1.0 / 10.0,
        };
        let dts = [base, base / 2.0, base / 4.0];
        let errors: Vec<f64> = dts.iter().map(|&dt| error(scheme, dt)).collect();
        let errors_text: Vec<String> = errors.iter().map(|e| format!("{e:.3e}")).collect();
        let order = (errors[1] / errors[2]).log2();
        report += &format!("{scheme:?}: errors {errors_text:?}, order {order:.3} (theory {p})\n");
        if (order - p).abs() > 0.15 {
            failures.push(format!("{scheme:?}: order {order:.3}, theory {p}"));
        }
    }
    eprintln!("{report}");
    assert!(failures.is_empty(), "{failures:#?}\n{report}");
}

/// Undamped (c = 0), velocity Verlet and Euler–Cromer keep the oscillator's
/// energy bounded over 100 periods, and explicit Euler gains it (thesis §2.5.2).
#[test]
fn symplectic_schemes_keep_the_energy_and_explicit_euler_gains_it() {
    let energy = |m: &Model| 0.5 * M * m.v[3].powi(2) + 0.5 * K * (m.x[3] - REST).powi(2);
    let e0 = 0.5 * K * X0 * X0;
    let run = |scheme: Scheme| {
        let mut m = oscillator();
        m.dampers.clear();
        m.prepare();
        let dt = 0.01;
        let mut integrator = structure_proc::integrator(scheme);
        let mut worst: f64 = 0.0;
        for _ in 0..(100.0 * 2.0 * std::f64::consts::PI / (K / M).sqrt() / dt) as usize {
            m.step(integrator.as_mut(), &Loads::default(), dt).unwrap();
            worst = worst.max((energy(&m) / e0 - 1.0).abs());
        }
        (worst, energy(&m) / e0)
    };
    for scheme in [Scheme::VelocityVerlet, Scheme::EulerCromer] {
        let (worst, _) = run(scheme);
        // Bounded by O(ω dt) for Euler–Cromer, O((ω dt)²) for Verlet.
        assert!(worst < 0.02, "{scheme:?}: energy drifts by {worst}");
    }
    let (_, last) = run(Scheme::ExplicitEuler);
    assert!(
        last > 2.0,
        "explicit Euler should gain energy: E/E₀ = {last}"
    );
}
