//! Stability estimate and divergence detection on the spring pendulum of
//! thesis §2.5.2 (two springs of K = 100 N/m on a 1 kg bob): its ω_max
//! bound, dissertation eq. (3.7) node by node, is √(2·(K + K)/M) = 20 rad/s.
//! Explicit Euler gains energy at every step (thesis §2.5.2, fig. 9), so
//! with a large step the run must stop with a diagnostic, not go on.

use canopy_tests::*;
use structure_section::Integrator;

/// ω_max of eq. (3.7) for the spring pendulum [rad/s].
const OMEGA_MAX: f64 = 20.0;

#[test]
fn check_warns_when_the_step_is_above_the_stability_limit() {
    let dir = scratch("divergence-check");
    // Velocity Verlet is stable for ω·h ≤ 2: Δt_s ≤ 0.1 s here.
    for (window, warns) in [(0.15, true), (0.05, false)] {
        let path = variant("spring-pendulum", &dir, |s| {
            s.coupling.window = window;
            s.run.end_time = 1.5;
        });
        let o = coupler(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0));
        let out = String::from_utf8_lossy(&o.stdout);
        let err = String::from_utf8_lossy(&o.stderr);
        assert!(
            out.contains("ω_max = 2.0000e1 rad/s") && out.contains("Δt_s ≤ 1.000e-1 s"),
            "{out}"
        );
        assert_eq!(
            err.contains("is above 1.000e-1 s, the step velocity-verlet is sure to be stable at"),
            warns,
            "window {window}: {err}"
        );
        if warns {
            // n_s = ⌈ω_max·Δt_f/2⌉ = ⌈1.5⌉.
            assert!(err.contains("structure_substeps = 2 or more"), "{err}");
        }
    }
}

#[test]
fn a_diverging_run_stops_within_a_window_and_names_time_node_and_quantity() {
    let dir = scratch("divergence-run");
    let window = 0.02; // ω_max·Δt = 0.4
    let path = variant("spring-pendulum", &dir, |s| {
        s.coupling.window = window;
        s.run.end_time = 30.0;
        s.structure.as_mut().unwrap().integrator = Integrator::ExplicitEuler;
    });
    let out = dir.join("run");
    let line = run_failed(&path, &out);
    assert!(line.contains("node 2 (`bob`) moves at"), "{line}");
    // The speed bound: 100 × √(2E₀/M), the speed the springs' initial energy
    // E₀ (the first monitors row; no gravity) could give the 1 kg bob.
    let m = Monitors::read(&out);
    let e0 = m.column("potential_energy")[0];
    let bound = 100.0 * (2.0 * e0 / 1.0).sqrt();
    let stated = number_after(&line, "beyond the bound ");
    assert!((stated / bound - 1.0).abs() < 1e-3, "{line}: bound {bound}");
    let t_fail = number_after(&line, "diverged at t = ");
    // What was written stays readable: monitors up to the window before, the
    // bob still under the bound there, and the manifest says why it stopped.
    let times = m.column("time");
    let last = times.len() - 1;
    assert!(
        (times[last] - (t_fail - window)).abs() < 1e-9,
        "caught within one window"
    );
    let (vx, vy) = (m.column("structure.bob.vx"), m.column("structure.bob.vy"));
    assert!(vx[last].hypot(vy[last]) <= bound);
    let manifest = manifest(&out);
    assert_eq!(manifest["status"], "failed");
    assert!(manifest["error"]
        .as_str()
        .unwrap()
        .contains("diverged at t ="));
    // The stability estimate the run used: explicit Euler has no interval,
    // so n_s is the dissertation's ω_max·Δt_s < 0.1: ⌈20·0.02/0.1⌉ = 4.
    // The structure program's --check answer, as the manifest records it.
    let st = &manifest["checked"]["structure"]["stability"];
    assert!((st["omega_max"].as_f64().unwrap() - OMEGA_MAX).abs() < 1e-12);
    assert_eq!(st["n_s"].as_u64(), Some(4));
    assert_eq!(
        manifest["checked"]["structure"]["integrator"],
        "explicit-euler"
    );
}
