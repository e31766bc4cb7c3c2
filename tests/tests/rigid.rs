//! Rigid-body scenes run through the coupler (issue 5): the collision
//! benchmark of dissertation §4.3.1, torque-free tumbling (eq. 2.12), a ball
//! bouncing with restitution (eq. 3.31), and the pendulum and the C-9 drop
//! with the payload as a finite rigid body (§2.4).

use canopy_tests::*;

/// The monitors of the shipped scene `name`, run in a scratch directory.
fn run(name: &str) -> Monitors {
    let dir = scratch(name);
    let out = dir.join("run");
    run_ok(&scenario_path(name), &out);
    Monitors::read(&out)
}

fn last(m: &Monitors, name: &str) -> f64 {
    *m.column(name).last().unwrap()
}

#[test]
fn cuboids_leave_the_impact_with_the_closed_form_velocities() {
    // Eq. (4.1) for m_a = 1 kg, m_b = 2 kg at ±0.5 m/s: eq. (4.2).
    let m = run("cuboids");
    let cases = [
        ("inelastic", -1.0 / 6.0, -1.0 / 6.0),
        ("elastic", -5.0 / 6.0, 1.0 / 6.0),
    ];
    for (pair, va, vb) in cases {
        let a = last(&m, &format!("rigid.{pair}_a.vx"));
        let b = last(&m, &format!("rigid.{pair}_b.vx"));
        assert!(
            (a - va).abs() < 1e-9 && (b - vb).abs() < 1e-9,
            "{pair}: {a}, {b}"
        );
        // A head-on impact: no sideways motion, no spin.
        for k in ["vy", "vz", "omegax", "omegay", "omegaz"] {
            assert!(
                last(&m, &format!("rigid.{pair}_a.{k}")).abs() < 1e-12,
                "{pair} {k}"
            );
        }
        // Momentum 1·0.5 − 2·0.5 = −0.5 kg·m/s in each pair, kept to round-off.
        assert!(
            (a + 2.0 * b + 0.5).abs() < 1e-14,
            "{pair} momentum {}",
            a + 2.0 * b
        );
    }
    // The elastic pair keeps its kinetic energy ½·1·0.25 + ½·2·0.25 = 0.375 J.
    let e = last(&m, "rigid.elastic_a.kinetic_energy") + last(&m, "rigid.elastic_b.kinetic_energy");
    assert!((e - 0.375).abs() < 1e-14, "elastic energy {e}");
    // One impact in each pair, at t = 0.1 s (0.1 m gap closed at 1 m/s).
    assert_eq!(last(&m, "rigid.contact_impulses"), 2.0);
    let t = m.column("time");
    let va = m.column("rigid.elastic_a.vx");
    let hit = t[va.iter().position(|v| *v < 0.0).unwrap()];
    assert!((hit - 0.1).abs() <= 1.01e-3, "impact at {hit} s");
}

#[test]
fn spinning_top_keeps_energy_and_angular_momentum() {
    // Torque-free: E and |L| are invariants of eq. (2.12); RK4 with |w|Δt = 0.01
    // keeps them to 1e-10 over the scene's 20 s (≈ 20 tumbling periods).
    let m = run("spinning-top");
    for name in ["rigid.kinetic_energy", "rigid.angular_momentum"] {
        let v = m.column(name);
        let drift = v.iter().map(|x| (x / v[0] - 1.0).abs()).fold(0.0, f64::max);
        assert!(drift < 1e-10, "{name} drifted by {drift:e}");
    }
    // It tumbles: the body-axis rate w₂ changes sign.
    let w2 = m.column("rigid.block.w2");
    assert!(w2.windows(2).filter(|p| p[0] * p[1] < 0.0).count() >= 20);
}

#[test]
fn ball_drop_bounce_heights_fall_by_the_square_of_the_restitution() {
    // Rebound speed C_R·v, so each apex is C_R² = 0.64 of the one before.
    let m = run("ball-drop");
    let z = m.column("rigid.ball.z");
    let apex: Vec<f64> = (1..z.len() - 1)
        .filter(|&i| z[i] >= z[i - 1] && z[i] > z[i + 1])
        .map(|i| z[i] - 0.1)
        .collect();
    assert!(apex.len() >= 4, "apexes {apex:?}");
    let mut heights = vec![1.0];
    heights.extend(&apex[..4]);
    for p in heights.windows(2) {
        let ratio = p[1] / p[0];
        assert!(
            (ratio - 0.64).abs() < 0.64 * 2e-3,
            "ratio {ratio} in {heights:?}"
        );
    }
}

/// Total energy per monitor row: every participant's kinetic and potential energy.
fn energy(m: &Monitors) -> Vec<f64> {
    let (k, p) = (m.column("kinetic_energy"), m.column("potential_energy"));
    k.iter().zip(&p).map(|(k, p)| k + p).collect()
}

#[test]
fn pendulum_with_a_finite_ball_keeps_its_energy_and_spins_the_ball() {
    // The string pulls at the ball's top, off its centre whenever the ball
    // leans against the string, so the ball turns (eq. 2.12); the undamped
    // coupled system still keeps its energy (Euler–Cromer impulses, as in
    // the mass-point pendulum).
    let m = run("pendulum-body");
    let e = energy(&m);
    let drift = e.iter().map(|x| (x - e[0]).abs()).fold(0.0, f64::max);
    assert!(
        drift < 1e-4 * e[0].abs(),
        "energy drifted by {drift} J of {}",
        e[0]
    );
    let spin = m.column("rigid.ball.omegay");
    assert!(spin.iter().any(|w| w.abs() > 1.0), "the ball does not turn");
}

#[test]
fn c9_drop_descends_alike_with_a_mass_point_or_a_rigid_parachutist() {
    // The same 100 kg, so after 1 s of inflation the descent speed agrees
    // within 2 % (the body adds rotational inertia and an off-centre pull;
    // the porous model exerts no flow force on it).
    let dir = scratch("c9-bodies");
    let shorten = |s: &mut canopy_tests::Scenario| s.run.end_time = 1.0;
    let point = variant("c9-drop", &dir, shorten);
    let body = variant("c9-drop-body", &dir, shorten);
    run_ok(&point, &dir.join("point-run"));
    run_ok(&body, &dir.join("body-run"));
    let vp = last(
        &Monitors::read(&dir.join("point-run")),
        "structure.confluence.vz",
    );
    let vb = last(&Monitors::read(&dir.join("body-run")), "rigid.jumper.vz");
    assert!(vp < -5.0, "the mass point falls at {vp} m/s");
    assert!(
        (vb / vp - 1.0).abs() < 0.02,
        "body {vb} m/s vs point {vp} m/s"
    );
}
