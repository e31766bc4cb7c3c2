//! A moving rigid body in the structure's contact pass (issue 24, items 3
//! and 4; the dissertation §2.5: each rigid body one impact zone that takes
//! the reaction of what it gives): a thin rod pushed up through a cloth
//! between two columns of its nodes lifts the cloth by its edges and faces,
//! and the momentum the cloth gains the rod loses.

use exchange::fields::STATE_LEN;
use structure_proc::collision::{triangles_through, Contacts, Obstacles};
use structure_proc::forces::Loads;

/// What a lift showed.
struct Lift {
    /// Most cloth triangles crossing the rod at any check.
    through_rod: usize,
    /// The cloth's highest node at the end [m].
    cloth_top: f64,
    /// The rod's top at the end [m].
    rod_top: f64,
    /// |Δ(cloth momentum + rod momentum) − cloth weight × time| [N·s].
    momentum_error: f64,
    /// The rod's momentum change [N·s] (z).
    rod_gave: f64,
    body_impulses: u64,
}

/// A 0.6 m square cloth (13 × 13 nodes, 5 cm apart) at rest at z = 0 and a
/// 5 mm square rod of 10 kg along y at x = 2.5 cm, midway between two node
/// columns, rising from z = −1 cm at 1 m/s, for 0.1 s; the rod's surface in
/// the contact pass when `surfaces`, else only the node–body pass meets it.
/// The test moves the rod as rigid-proc would with one impulse sub-step per
/// structure step: by its velocity, after the momentum the cloth gave it.
fn lift(surfaces: bool) -> Lift {
    let s: structure_section::StructureSection = toml::from_str(
        r#"
        integrator = "velocity-verlet"
        [collision]
        thickness = 1e-3
        [cloth]
        width = 0.6
        depth = 0.6
        nodes_x = 13
        nodes_y = 13
        origin = [-0.3, -0.3, 0.0]
        bending_stiffness = 0.2
        [cloth.fabric]
        areal_density = 0.1
        membrane = { young_modulus = 1.0e6, poisson_ratio = 0.3, thickness = 2.0e-4 }
        "#,
    )
    .unwrap();
    let rigid: rigid_section::RigidSection = toml::from_str(
        r#"
        [[bodies]]
        name = "rod"
        shape = { type = "cuboid", size = [0.005, 1.0, 0.005] }
        mass = 10.0
        position = [0.025, 0.0, -0.01]
        velocity = [0.0, 0.0, 1.0]
        "#,
    )
    .unwrap();
    let spec = s.collision.unwrap();
    let dt = 5e-5;
    let mut m = structure_proc::build_model(&s, None, dt).unwrap();
    let mut stepper = structure_proc::integrator(s.scheme());
    let mut contacts = Contacts::with_bodies(&m.net, &spec, surfaces.then_some(&rigid))
        .unwrap()
        .unwrap();
    let mut rod = Obstacles::new(&rigid, &spec).unwrap();
    let momentum = |m: &structure_proc::Model, rod: &Obstacles| {
        let cloth: f64 = (0..m.nodes()).map(|n| m.net.mass[n] * m.v[3 * n + 2]).sum();
        cloth + rod.bodies[0].mass.mass * rod.bodies[0].state.v.z
    };
    let rod_momentum = |rod: &Obstacles| rod.bodies[0].mass.mass * rod.bodies[0].state.v.z;
    let (p0, rod_p0) = (momentum(&m, &rod), rod_momentum(&rod));
    let weight: f64 = m.net.mass.iter().sum::<f64>() * s.gravity[2];
    let mut lift = Lift {
        through_rod: 0,
        cloth_top: 0.0,
        rod_top: 0.0,
        momentum_error: 0.0,
        rod_gave: 0.0,
        body_impulses: 0,
    };
    let steps = 2000;
    for k in 1..=steps {
        contacts.begin_step(&m.x);
        rod.begin_step(&m.x);
        m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
        contacts.move_bodies(&rod.bodies, dt);
        let (mass, inv) = (m.net.mass.clone(), m.net.inv_mass.clone());
        contacts
            .resolve(&mut m.x, &mut m.v, &mass, &inv, dt)
            .unwrap();
        for (b, lin, ang) in contacts.body_momenta().collect::<Vec<_>>() {
            rod.push(b, &lin, &ang);
        }
        rod.resolve(&mut m.x, &mut m.v, &inv, dt);
        // rigid-proc's part: the rod moves on with its new velocity.
        let mut state = vec![0.0; STATE_LEN];
        let body = &mut rod.bodies[0];
        body.state.x += body.state.v * dt;
        body.write_state(&mut state);
        rod.set_states(&state, k as f64 * dt);
        contacts.place_bodies(&rod.bodies);
        if k % 100 == 0 {
            let pose = rod.bodies[0].shape_pose();
            let shape = rod.bodies[0].shape.clone().unwrap();
            let through = triangles_through(shape.shape.as_ref(), &pose, &m.x, &m.triangles);
            lift.through_rod = lift.through_rod.max(through);
        }
    }
    let t = steps as f64 * dt;
    lift.momentum_error = (momentum(&m, &rod) - p0 - weight * t).abs();
    lift.rod_gave = rod_p0 - rod_momentum(&rod);
    lift.cloth_top = (0..m.nodes())
        .map(|n| m.x[3 * n + 2])
        .fold(f64::NEG_INFINITY, f64::max);
    lift.rod_top = rod.bodies[0].state.x.z + 0.0025;
    lift.body_impulses = contacts.stats.structure_body;
    lift
}

#[test]
fn a_rod_rising_between_a_cloths_nodes_lifts_it_and_loses_the_momentum_it_gives() {
    let with = lift(true);
    assert_eq!(with.through_rod, 0, "the rod crossed the cloth");
    assert!(with.body_impulses > 0);
    // The rod (top from −7.5 mm to about 9.2 cm) carries the cloth up by
    // the edges that cross it; free, the cloth would have fallen 4.9 cm.
    assert!(with.rod_top > 0.08, "rod top at {} m", with.rod_top);
    assert!(with.cloth_top > 0.05, "cloth's top at {} m", with.cloth_top);
    // Momentum: what the rod lost the cloth gained, less the cloth's
    // weight × time, to round-off (10 kg·m/s in play).
    assert!(with.rod_gave > 0.01, "the rod gave {} N·s", with.rod_gave);
    assert!(
        with.momentum_error < 1e-9,
        "momentum off by {} N·s",
        with.momentum_error
    );
    // The node–body pass alone: no node meets the rod, which passes
    // through the cloth between them, untouched.
    let without = lift(false);
    assert!(without.through_rod > 0, "the rod should cross the cloth");
    assert_eq!(without.rod_gave, 0.0);
}
