//! Rigid-body dynamics against closed forms and conservation laws
//! (dissertation §2.1 eq. 2.12, §3.1.1 eqs. 3.1–3.6).

use exchange::euler_parameters as ep;
use exchange::mass::MassProperties;
use exchange::{Body, Motion, State};
use nalgebra::{Matrix3, Vector3};
use rigid_proc::motion::{advance, Load};

/// A free body with principal moments `i` [kg·m²], mass 1 kg, at rest at the
/// origin with orientation `e` and body angular velocity `w`.
fn body(i: [f64; 3], e: ep::EulerParameters, w: [f64; 3]) -> Body {
    Body {
        name: "b".into(),
        motion: Motion::Dynamic,
        mass: MassProperties::from_tensor(
            1.0,
            Vector3::zeros(),
            Matrix3::from_diagonal(&Vector3::from(i)),
        ),
        shape: None,
        damping: 0.0,
        release_time: None,
        state: State {
            x: Vector3::zeros(),
            v: Vector3::zeros(),
            e,
            w: Vector3::from(w),
        },
    }
}

const NO_GRAVITY: Vector3<f64> = Vector3::new(0.0, 0.0, 0.0);

#[test]
fn torque_free_tumbling_keeps_energy_and_angular_momentum() {
    // Principal moments 1, 2, 3; w starts off every axis, so the body tumbles:
    // L²/2E = 1.59 < I₂ puts the polhode round axis 1, w₂ changing sign twice
    // a period. Euler's equations (2.12) keep E and L (world vector) exactly.
    let e0 = ep::from_axis_angle(Vector3::new(1.0, 2.0, 2.0) / 3.0, 0.7);
    let mut b = body([1.0, 2.0, 3.0], e0, [1.0, 0.5, 0.3]);
    let (energy0, l0) = (b.kinetic_energy(), b.spin_momentum());
    let h = 1e-3;
    let (mut crossings, mut last, mut t) = (0, b.state.w.y, 0.0);
    let (mut worst_e, mut worst_l, mut worst_vec): (f64, f64, f64) = (0.0, 0.0, 0.0);
    while crossings < 200 {
        advance(&mut b, &Load::default(), &NO_GRAVITY, h);
        t += h;
        if b.state.w.y * last < 0.0 {
            crossings += 1;
        }
        last = b.state.w.y;
        worst_e = worst_e.max((b.kinetic_energy() / energy0 - 1.0).abs());
        worst_l = worst_l.max((b.spin_momentum().norm() / l0.norm() - 1.0).abs());
        worst_vec = worst_vec.max((b.spin_momentum() - l0).norm() / l0.norm());
        // Eq. (3.2) holds after every step.
        assert!((b.state.e.norm() - 1.0).abs() < 1e-14);
    }
    assert!(t > 100.0, "100 periods took only {t} s");
    assert!(
        worst_e < 1e-10,
        "energy drifted by {worst_e:e} over 100 periods ({t} s)"
    );
    assert!(worst_l < 1e-10, "|L| drifted by {worst_l:e}");
    // The world-axis vector too: this checks the Euler-parameter kinematics
    // (eq. 3.4 in its body-axis form) and the transform of eq. (3.5).
    assert!(worst_vec < 1e-8, "L drifted in direction by {worst_vec:e}");
}

/// Largest excursion of w off the axis it started on, over `t_end` seconds.
fn wobble(axis: usize, eps: f64, t_end: f64) -> f64 {
    let mut w = [eps; 3];
    w[axis] = 1.0;
    let mut b = body([1.0, 2.0, 3.0], ep::identity(), w);
    let h = 1e-3;
    let mut worst: f64 = 0.0;
    for _ in 0..(t_end / h) as usize {
        advance(&mut b, &Load::default(), &NO_GRAVITY, h);
        let off = (0..3)
            .filter(|&k| k != axis)
            .map(|k| b.state.w[k].abs())
            .fold(0.0, f64::max);
        worst = worst.max(off);
    }
    worst
}

#[test]
fn rotation_near_the_intermediate_axis_is_unstable_and_near_the_others_is_not() {
    // The tennis-racket theorem from eq. (2.12): perturbations about axes 1
    // and 3 oscillate with ω² = w²(I₂−I₁)(I₃−I₁)/(I₂I₃) (bounded); about
    // axis 2 they grow like exp(w·√((I₂−I₁)(I₃−I₂)/(I₁I₃)) t) = exp(0.58 t).
    let eps = 1e-4;
    let (a1, a2, a3) = (
        wobble(0, eps, 60.0),
        wobble(1, eps, 60.0),
        wobble(2, eps, 60.0),
    );
    assert!(a1 < 10.0 * eps, "axis 1 wobbled to {a1}");
    assert!(a3 < 10.0 * eps, "axis 3 wobbled to {a3}");
    assert!(a2 > 0.5, "axis 2 stayed within {a2} of its start");
}

#[test]
fn constant_torque_about_a_principal_axis_matches_the_closed_form() {
    // τ along principal axis 3 from rest: w₃ = τt/I₃, turned angle θ = τt²/(2I₃),
    // e = (cos θ/2, 0, 0, sin θ/2) by eq. (3.3); the other axes stay at rest.
    let (tau, i3) = (0.3, 3.0);
    let mut b = body([1.0, 2.0, i3], ep::identity(), [0.0; 3]);
    let load = Load {
        force: Vector3::zeros(),
        torque: Vector3::new(0.0, 0.0, tau),
    };
    let (h, steps) = (1e-3, 5000);
    for _ in 0..steps {
        advance(&mut b, &load, &NO_GRAVITY, h);
    }
    let t = h * steps as f64;
    let theta = tau * t * t / (2.0 * i3);
    assert!(
        (b.state.w.z - tau * t / i3).abs() < 1e-12,
        "w₃ = {}",
        b.state.w.z
    );
    assert!(b.state.w.x.abs() < 1e-15 && b.state.w.y.abs() < 1e-15);
    let expected = ep::from_axis_angle(Vector3::z(), theta);
    assert!(
        (b.state.e - expected).norm() < 1e-10,
        "e = {} vs {expected}",
        b.state.e
    );
}

#[test]
fn an_off_centre_impulse_changes_spin_as_inverse_inertia_times_its_moment() {
    // J at r from the centre: Δv = J/m and Δω = I⁻¹(r × J) in world axes,
    // I = AᵀΛA (eqs. 2.5, 2.7, 3.5) — equivalently ΔL = r × J.
    let e = ep::from_axis_angle(Vector3::new(0.0, 0.6, 0.8), 1.1);
    let mut b = body([1.0, 2.0, 3.0], e, [0.2, -0.1, 0.4]);
    b.mass.mass = 2.5;
    let (v0, omega0, l0) = (b.state.v, b.world_angular_velocity(), b.spin_momentum());
    let r = Vector3::new(0.3, -0.2, 0.5);
    let j = Vector3::new(1.0, 2.0, -0.5);
    let p = b.state.x + r;
    b.apply_impulse(&p, &j);
    let a = ep::attitude(&b.state.e);
    let inertia = a.transpose() * Matrix3::from_diagonal(&b.mass.principal) * a;
    let d_omega = inertia.try_inverse().unwrap() * r.cross(&j);
    assert!((b.state.v - v0 - j / 2.5).norm() < 1e-15);
    assert!((b.world_angular_velocity() - omega0 - d_omega).norm() < 1e-14);
    assert!((b.spin_momentum() - l0 - r.cross(&j)).norm() < 1e-14);
}

#[test]
fn gravity_alone_gives_the_free_fall_parabola() {
    // x = x₀ + v₀t + ½gt²: RK4 (eq. 3.1) is exact for a constant force.
    let mut b = body([1.0, 1.0, 1.0], ep::identity(), [0.0; 3]);
    b.state.v = Vector3::new(1.0, 0.0, 3.0);
    let g = Vector3::new(0.0, 0.0, -9.81);
    for _ in 0..1000 {
        advance(&mut b, &Load::default(), &g, 1e-3);
    }
    let expected = Vector3::new(1.0, 0.0, 3.0 - 0.5 * 9.81);
    assert!((b.state.x - expected).norm() < 1e-12, "{}", b.state.x);
}

#[test]
fn a_prescribed_body_follows_its_motion_whatever_acts_on_it() {
    // Constant v and world ω: after t, x = v t and the body has turned by |ω|t
    // about ω, exactly (eq. 3.3), under gravity, a load and an impulse alike.
    let mut b = body([1.0, 2.0, 3.0], ep::identity(), [0.0; 3]);
    b.motion = Motion::Prescribed;
    b.state.v = Vector3::new(0.5, 0.0, -0.2);
    let omega = Vector3::new(0.0, 0.0, 1.5);
    b.state.w = ep::attitude(&b.state.e) * omega;
    let load = Load {
        force: Vector3::new(10.0, 0.0, 0.0),
        torque: Vector3::new(1.0, 2.0, 3.0),
    };
    let p = b.state.x + Vector3::new(0.1, 0.0, 0.0);
    b.apply_impulse(&p, &Vector3::new(0.0, 5.0, 0.0));
    let (h, steps) = (1e-3, 2000);
    for _ in 0..steps {
        advance(&mut b, &load, &Vector3::new(0.0, 0.0, -9.81), h);
    }
    let t = h * steps as f64;
    assert!((b.state.x - Vector3::new(0.5, 0.0, -0.2) * t).norm() < 1e-13);
    let expected = ep::from_axis_angle(Vector3::z(), 1.5 * t);
    assert!(
        (b.state.e - expected).norm() < 1e-12,
        "{} vs {expected}",
        b.state.e
    );
    assert!((b.world_angular_velocity() - omega).norm() < 1e-12);
}
