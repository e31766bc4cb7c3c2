//! The contact pass's proximity impulses and the bodies' normals
//! (Bridson, Fedkiw & Anderson 2002, §7.2; the dissertation eq. 3.30):
//! eq. 3.30's repulsion with Coulomb friction against its formula, a pair
//! deep in the layer moved out by its positions alone, the pass never
//! raising the kinetic energy whatever the motion, and a static ball
//! stopping a node along its true normal.

mod common;

use common::network;
use structure_proc::collision::Contacts;
use structure_section::Collision;

#[test]
fn a_string_sliding_on_a_fixed_triangle_feels_repulsion_and_coulomb_friction() {
    // A short free string (two 0.01 kg nodes) lies 0.4 mm over a fixed
    // triangle, inside the 1 mm layer, sinking at 0.05 m/s and sliding at
    // 1 m/s. Per node (w = 1 against a fixed triangle) the proximity
    // impulse stops the sinking, adds eq. 3.30's repulsion
    // Δvₙ = min(Δt·k·d/m, 0.1·d/Δt) with d = 0.6 mm, and friction takes
    // μ·Δvₙ off the sliding speed.
    let z = 4e-4;
    let x0 = vec![
        -1.0, -1.0, 0.0, 2.0, -1.0, 0.0, -1.0, 2.0, 0.0, // fixed triangle
        0.0, 0.0, z, 0.05, 0.0, z, // the string
    ];
    let mass = [0.0, 0.0, 0.0, 0.01, 0.01];
    let net = network(&x0, &mass, vec![[0, 1, 2]], 3, &[(3, 4)]);
    let (dt, mu, k) = (1e-3, 0.3, 50.0);
    let spec = Collision {
        friction: mu,
        repulsion_stiffness: Some(k),
        ..Collision::default()
    };
    let mut contacts = Contacts::new(&net, &spec).unwrap();
    let (vt, vn) = (1.0, -0.05);
    let mut v = vec![0.0; 15];
    for node in [3, 4] {
        v[3 * node] = vt;
        v[3 * node + 2] = vn;
    }
    let mut x: Vec<f64> = x0.iter().zip(&v).map(|(a, b)| a + b * dt).collect();
    contacts.begin_step(&x0);
    contacts
        .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt)
        .unwrap();
    let d = spec.thickness - z;
    let repel = (dt * k * d / 0.01).min(0.1 * d / dt);
    let dvn = -vn + repel;
    for node in [3, 4] {
        let (vx, vz) = (v[3 * node], v[3 * node + 2]);
        assert!(
            (vz - repel).abs() < 1e-12,
            "node {node}: v_n = {vz}, want {repel}"
        );
        assert!(
            (vx - (vt - mu * dvn)).abs() < 1e-12,
            "node {node}: v_t = {vx}, want {}",
            vt - mu * dvn
        );
    }
    assert_eq!(contacts.stats.proximity, 2);
}

#[test]
fn a_resting_pair_deep_in_the_layer_is_moved_out_without_a_velocity() {
    // A free string at rest over a fixed triangle, inside the 1 mm layer:
    // there is no approach to stop and no velocity to give back, so a
    // string deeper than half the layer is moved out to half the layer by
    // its positions alone and its velocity stays zero; in the layer's
    // outer half it is left as it is (`PUSH_WITHIN`).
    let layer = Collision::default().thickness;
    for (z, moved) in [(0.2 * layer, true), (0.6 * layer, false)] {
        let x0 = vec![
            -1.0, -1.0, 0.0, 2.0, -1.0, 0.0, -1.0, 2.0, 0.0, // fixed triangle
            0.0, 0.0, z, 0.05, 0.0, z, // the string
        ];
        let net = network(
            &x0,
            &[0.0, 0.0, 0.0, 0.01, 0.01],
            vec![[0, 1, 2]],
            3,
            &[(3, 4)],
        );
        let spec = Collision {
            repulsion_stiffness: Some(1e5),
            ..Collision::default()
        };
        let mut contacts = Contacts::new(&net, &spec).unwrap();
        let (mut x, mut v) = (x0.clone(), vec![0.0; 15]);
        contacts.begin_step(&x0);
        contacts
            .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, 1e-3)
            .unwrap();
        let want = if moved { 0.5 * layer } else { z };
        for node in [3, 4] {
            assert!(
                (x[3 * node + 2] - want).abs() < 1e-15,
                "z = {z}: node {node} at {}, want {want}",
                x[3 * node + 2]
            );
            assert_eq!(
                &v[3 * node..3 * node + 3],
                &[0.0; 3],
                "z = {z}: node {node} moves"
            );
        }
    }
}

#[test]
fn the_pass_never_raises_the_kinetic_energy_whatever_the_motion() {
    // A 21 × 21 cloth pleated into layers 0.6 of the layer apart, every
    // node in proximity with the layers beside it, sliding along the folds
    // by a tenth of the layer in the step and moving at random by up to a
    // fiftieth (folds pressed together, pulled apart and rubbing). Every impulse of the pass acts on one pair's relative
    // motion: an inelastic stop, friction and a repulsion that parts the
    // pair no faster than it came change the pair's relative displacement
    // from r to r + c with |r + c| ≤ |r|, and the kinetic energy by
    // (|r + c|² − |r|²)/(2·Σwᵢ²/mᵢ·Δt²); an impact zone keeps its nodes'
    // momentum and angular momentum, the least-energy rigid motion that
    // does. So the energy cannot rise, in any order of impulses; the
    // momentum is kept (Bridson et al. 2002, §7; Provot 1997). Eq. 3.30's
    // repulsion uncapped (m(0.1·d/Δt − vₙ) for a pair parting slower than
    // that) raises it here.
    let n = 21;
    let layer = Collision::default().thickness;
    let m = structure_proc::rectangle::rectangle(0.2, 0.2, n, n, [0.0; 3]);
    let x0 = m.pleated(4, 0.6 * layer);
    let net = network(&x0, &vec![1e-3; n * n], m.triangles.clone(), n * n, &[]);
    let spec = Collision {
        friction: 0.3,
        repulsion_stiffness: Some(1e6),
        ..Collision::default()
    };
    let dt = 1e-4;
    let mut s = 7u64;
    let mut r = move || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    };
    let mut v: Vec<f64> = (0..3 * n * n)
        .map(|i| (0.02 * r() + if i % 3 == 1 { 0.1 } else { 0.0 }) * layer / dt)
        .collect();
    let mut x: Vec<f64> = x0.iter().zip(&v).map(|(a, b)| a + b * dt).collect();
    let energy = |v: &[f64]| 0.5 * 1e-3 * v.iter().map(|c| c * c).sum::<f64>();
    let momentum = |v: &[f64]| -> [f64; 3] {
        let mut p = [0.0; 3];
        for (i, c) in v.iter().enumerate() {
            p[i % 3] += 1e-3 * c;
        }
        p
    };
    let (e0, p0) = (energy(&v), momentum(&v));
    let mut contacts = Contacts::new(&net, &spec).unwrap();
    contacts.begin_step(&x0);
    contacts
        .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt)
        .unwrap();
    let (e1, p1) = (energy(&v), momentum(&v));
    assert!(
        contacts.stats.proximity > 200,
        "{} proximity impulses",
        contacts.stats.proximity
    );
    assert!(
        e1 <= e0 * (1.0 + 1e-12),
        "kinetic energy rose from {e0} J to {e1} J"
    );
    for c in 0..3 {
        assert!(
            (p1[c] - p0[c]).abs() < 1e-15,
            "momentum {c} changed by {:e} N·s",
            p1[c] - p0[c]
        );
    }
}

#[test]
fn a_static_ball_stops_a_node_along_its_true_normal() {
    // A free string end falls straight at the centre of a static ball
    // (radius 0.1 m, meshed with 24 facets round) where no facet is square
    // to the fall: the ball stops it along its own normal, the radius, so
    // the node keeps no sliding velocity (a frictionless ball). Stopped
    // along the facet's normal (3.6° off the radius there), it slid on at
    // 0.12 m/s, 6 % of its speed.
    let rigid: rigid_section::RigidSection = toml::from_str(
        r#"
        [[bodies]]
        name = "ball"
        shape = { type = "sphere", radius = 0.1 }
        motion = "static"
        mass = 1.0
        position = [0.0, 0.0, 0.0]
        "#,
    )
    .unwrap();
    let (theta, phi) = (0.37_f64, 0.21_f64);
    let u = [
        theta.sin() * phi.cos(),
        theta.sin() * phi.sin(),
        theta.cos(),
    ];
    let (r, speed, dt) = (0.1005, 2.0, 1e-3);
    // The string runs out along the radius to a fixed node 0.5 m away.
    let x0: Vec<f64> = [r, 0.6].iter().flat_map(|&a| u.map(|c| a * c)).collect();
    let net = network(&x0, &[0.01, 0.0], vec![], 0, &[(0, 1)]);
    let spec = Collision::default();
    let mut contacts = Contacts::with_bodies(&net, &spec, Some(&rigid))
        .unwrap()
        .unwrap();
    let mut v = vec![0.0; 6];
    (0..3).for_each(|c| v[c] = -speed * u[c]);
    let mut x: Vec<f64> = x0.iter().zip(&v).map(|(a, b)| a + b * dt).collect();
    contacts.begin_step(&x0);
    contacts
        .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt)
        .unwrap();
    let along: f64 = (0..3).map(|c| v[c] * u[c]).sum();
    let across = (0..3)
        .map(|c| (v[c] - along * u[c]).powi(2))
        .sum::<f64>()
        .sqrt();
    assert!(along > -speed, "not stopped: {along} m/s along the radius");
    assert!(
        across < 1e-12 * speed,
        "the node slides at {across} m/s across the radius"
    );
}

/// The pass measures, detects and searches in parallel and applies its
/// impulses in the order of the pairs' kinds and node numbers: on a
/// 61 × 61 cloth pleated into layers 0.6 of the layer apart and pressed
/// together, tens of thousands of impulses give the same positions and
/// velocities to the last bit on one thread and on four, and keep the
/// momentum (the impulses are internal, Bridson et al. 2002, §7).
#[test]
fn the_pass_gives_the_same_result_on_any_number_of_threads() {
    let n = 61;
    let layer = Collision::default().thickness;
    let m = structure_proc::rectangle::rectangle(0.6, 0.6, n, n, [0.0; 3]);
    let x0 = m.pleated(5, 0.6 * layer);
    let net = network(&x0, &vec![1e-3; n * n], m.triangles.clone(), n * n, &[]);
    let dt = 1e-4;
    // Each layer closes on the one below at 0.5 m/s and slides along y.
    let v0: Vec<f64> = (0..3 * n * n)
        .map(|i| match i % 3 {
            1 => 0.2,
            2 => -(x0[i] / (0.6 * layer)).round() * 0.5,
            _ => 0.0,
        })
        .collect();
    let on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut contacts = Contacts::new(&net, &Collision::default()).unwrap();
        let mut v = v0.clone();
        let mut x: Vec<f64> = x0.iter().zip(&v).map(|(a, b)| a + b * dt).collect();
        contacts.begin_step(&x0);
        pool.install(|| contacts.resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt))
            .unwrap();
        (x, v, contacts.stats.proximity)
    };
    let (x1, v1, impulses) = on(1);
    let (x4, v4, _) = on(4);
    assert!(impulses > 20_000, "{impulses} proximity impulses");
    let differ = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .filter(|(p, q)| p.to_bits() != q.to_bits())
            .count()
    };
    assert_eq!(differ(&x1, &x4), 0, "coordinates differ");
    assert_eq!(differ(&v1, &v4), 0, "velocity components differ");
    for c in 0..3 {
        let p = |v: &[f64]| v.iter().skip(c).step_by(3).sum::<f64>() * 1e-3;
        let scale = v0.iter().skip(c).step_by(3).map(|a| a.abs()).sum::<f64>() * 1e-3;
        assert!(
            (p(&v1) - p(&v0)).abs() <= 1e-12 * scale.max(1e-3),
            "momentum {c} changed"
        );
    }
}
