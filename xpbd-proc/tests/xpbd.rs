//! XPBD against closed forms: a hanging chain settles where Hooke's law puts
//! it, the support carries the chain's weight, and a slack string lets its
//! mass fall freely (thesis eq. 3: strings carry tension only).

use structure_proc::driver::Stepper;
use structure_proc::forces::damping::{Damper, Law};
use structure_proc::forces::Loads;
use structure_proc::network::Network;
use structure_proc::{Model, NodeKind, Spring};
use xpbd_proc::Xpbd;

const G: f64 = 9.81;

/// A fixed node at the origin and `masses` hanging below it on springs of
/// stiffness `k` and rest length 1 m, each with an axial dashpot `c`.
fn chain(masses: &[f64], k: f64, c: f64, tension_only: bool) -> Model {
    let mut m = Model {
        x: vec![0.0; 3],
        v: vec![0.0; 3],
        net: Network {
            mass: vec![0.0],
            kind: vec![NodeKind::Fixed],
            gravity: [0.0, 0.0, -G],
            damping: Some(Law::Axial),
            ..Default::default()
        },
        ..Default::default()
    };
    for (n, &mass) in masses.iter().enumerate() {
        m.x.extend([0.0, 0.0, -(n as f64 + 1.0)]);
        m.v.extend([0.0; 3]);
        m.mass.push(mass);
        m.kind.push(NodeKind::Free);
        m.springs.push(Spring {
            i: n,
            j: n + 1,
            k,
            rest: 1.0,
            tension_only,
            eps: 0.0,
        });
        m.dampers.push(Damper {
            i: n,
            j: n + 1,
            c,
            slack_below: 0.0,
        });
    }
    m.prepare();
    m
}

/// Hooke's law in series: spring s carries the weight of the masses below it,
/// so it stretches by g·Σ_{below} m / k. Steps of 0.2 s are far beyond the
/// explicit limit 2/ω_max ≈ 0.07 s here; the converged XPBD step is implicit.
#[test]
fn hanging_chain_settles_at_hookes_stretch_with_its_weight_on_the_support() {
    let masses = [2.0, 1.0, 0.5];
    let k = 50.0;
    let mut m = chain(&masses, k, 20.0, false);
    let dt = 0.2;
    let mut xpbd = Xpbd::new(&m).unwrap();
    for _ in 0..500 {
        xpbd.step(&mut m, &Loads::default(), dt).unwrap();
    }
    let mut z_expected = 0.0;
    for n in 0..masses.len() {
        let below: f64 = masses[n..].iter().sum();
        z_expected -= 1.0 + G * below / k;
        let z = m.x[3 * (n + 1) + 2];
        assert!(
            (z - z_expected).abs() < 1e-9,
            "mass {n} at z = {z} m, Hooke: {z_expected} m"
        );
    }
    // The support receives the whole weight as impulse over the step.
    let weight: f64 = masses.iter().sum::<f64>() * G;
    let pull = -xpbd.reaction()[2] / dt;
    assert!(
        (pull / weight - 1.0).abs() < 1e-9,
        "support carries {pull} N of {weight} N"
    );
}

/// A string 0.5 m longer than the gap is slack: the mass falls as if free,
/// v = −g·t after every step, and the support feels nothing.
#[test]
fn slack_string_lets_its_mass_fall_freely() {
    let mut m = chain(&[1.0], 1e4, 10.0, true);
    m.springs[0].rest = 1.5;
    m.prepare();
    let dt = 1e-3;
    let mut xpbd = Xpbd::new(&m).unwrap();
    for step in 1..=200 {
        xpbd.step(&mut m, &Loads::default(), dt).unwrap();
        let t = step as f64 * dt;
        // (x − x_prev)/h loses a few digits to round-off; a pull would show at 1e-3.
        assert!((m.v[5] + G * t).abs() < 1e-9, "v = {} at t = {t}", m.v[5]);
        assert_eq!(xpbd.reaction()[2], 0.0);
    }
    // 0.2 s of free fall: 0.196 m, not yet the 0.5 m of slack.
    assert!(m.x[5] > -1.5);
}

#[test]
fn membrane_fabric_is_refused_with_a_reason() {
    let mut m = chain(&[1.0], 1.0, 0.0, false);
    let x = [0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    m.membrane.push(
        structure_proc::forces::delingette::TriangleSprings::new(&x, [0, 1, 2], 1.0, 1.0).unwrap(),
    );
    let e = Xpbd::new(&m).err().expect("refused");
    assert!(e.to_string().contains("stiffness"), "{e}");
}
