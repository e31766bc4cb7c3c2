//! The structure's self-contact pass (dissertation §2.5, §3.4; Bridson,
//! Fedkiw & Anderson 2002): the coplanarity cubic's impact times against
//! hand-solved ones, sheets that would pass through each other in one step
//! stopped without an intersection and with momentum kept, a strip twisted
//! on itself and a crumpled cloth collapsing in layers (`dropped.rs` has
//! cloths dropped on static bodies, `repulsion.rs` the proximity impulses
//! and the bodies' normals).

mod common;

use common::{network, section, step};
use structure_proc::collision::{intersections, Contacts, Kind, Stencil, Surface};
use structure_proc::NodeKind;
use structure_section::collision::ContactModel;
use structure_section::Collision;

/// Both contact models, by name.
const MODELS: [(&str, ContactModel); 2] = [
    ("pairwise", ContactModel::Pairwise),
    ("layered", ContactModel::Layered),
];

#[test]
fn a_point_meets_a_turning_triangle_at_the_root_of_the_cubic() {
    // Triangle a = 0, b = (1, 0, 0), c = (0, 1, s) turning about the x axis
    // as s goes 0 → 1; the point (0.2, 0.2 + 0.4 s, 0.5 − s). They are
    // coplanar when 0.5 − s = s (0.2 + 0.4 s), 0.4 s² + 1.2 s − 0.5 = 0:
    // s = (√2.24 − 1.2)/0.8, and the point is then inside the triangle
    // (x + y = 0.548 < 1).
    let x = [0.2, 0.2, 0.5, 0.0, 0.0, 0.0, 1.0, 0.0, 0.0, 0.0, 1.0, 0.0];
    let dx = [0.0, 0.4, -1.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 0.0, 1.0];
    let st = Stencil {
        kind: Kind::PointTriangle,
        nodes: [0, 1, 2, 3],
    };
    let exact = (2.24_f64.sqrt() - 1.2) / 0.8;
    let s = st.impact(&x, &dx, 1e-9).expect("they meet");
    assert!((s - exact).abs() < 1e-12, "s = {s}, exact {exact}");
    // Moving half as far, they do not meet.
    let half: Vec<f64> = dx.iter().map(|d| d * 0.5 * exact).collect();
    assert_eq!(st.impact(&x, &half, 1e-9), None);
}

#[test]
fn two_edges_meet_at_the_root_of_the_cubic() {
    // Edge a from (−1, 0, 1) to (1, 0, 1) falls by 2; edge b from
    // (0, −1, −1) to (0, 1, −1) rises by 2 at one end and 1 at the other.
    // They cross at x = y = 0 when 1 − 2s = −1 + 1.5 s: s = 4/7.
    let x = [
        -1.0, 0.0, 1.0, 1.0, 0.0, 1.0, 0.0, -1.0, -1.0, 0.0, 1.0, -1.0,
    ];
    let dx = [0.0, 0.0, -2.0, 0.0, 0.0, -2.0, 0.0, 0.0, 2.0, 0.0, 0.0, 1.0];
    let st = Stencil {
        kind: Kind::EdgeEdge,
        nodes: [0, 1, 2, 3],
    };
    let s = st.impact(&x, &dx, 1e-9).expect("they meet");
    assert!((s - 4.0 / 7.0).abs() < 1e-12, "s = {s}");
    // Shifted 1.5 along x, edge b passes beside edge a's end: no impact.
    let mut beside = x;
    beside[6] += 1.5;
    beside[9] += 1.5;
    assert_eq!(st.impact(&beside, &dx, 1e-9), None);
}

/// An n × n sheet of side 1 m at height z, shifted by (sx, sy), its nodes
/// numbered from `first`; positions appended to `x`, triangles to `tris`.
fn sheet(
    n: usize,
    z: f64,
    shift: (f64, f64),
    first: usize,
    x: &mut Vec<f64>,
    tris: &mut Vec<[usize; 3]>,
) {
    let h = 1.0 / (n - 1) as f64;
    for j in 0..n {
        for i in 0..n {
            x.extend([shift.0 + i as f64 * h, shift.1 + j as f64 * h, z]);
        }
    }
    for j in 0..n - 1 {
        for i in 0..n - 1 {
            let a = first + j * n + i;
            tris.push([a, a + 1, a + n + 1]);
            tris.push([a, a + n + 1, a + n]);
        }
    }
}

#[test]
fn sheets_that_would_pass_through_each_other_in_one_step_are_stopped() {
    // Two 6 × 6 sheets 0.1 m apart close at 10 m/s each over a 0.02 s step:
    // each would move 0.2 m, through the other. The pass must leave no
    // intersection and keep the upper sheet above the lower, while the
    // impulses (equal and opposite by construction) keep the momentum to
    // round-off and, inelastic, do not add kinetic energy: in both models.
    for (name, model) in MODELS {
        println!("{name}");
        sheets_pass(model);
    }
}

fn sheets_pass(model: ContactModel) {
    let n = 6;
    let (mut x0, mut tris) = (Vec::new(), Vec::new());
    sheet(n, 0.05, (0.0, 0.0), 0, &mut x0, &mut tris);
    sheet(n, -0.05, (0.13, 0.07), n * n, &mut x0, &mut tris);
    let nodes = 2 * n * n;
    // Uneven masses, so the sharing by mass is tested too.
    let mass: Vec<f64> = (0..nodes)
        .map(|k| 0.01 * (1.0 + 0.37 * ((k * 7) % 5) as f64))
        .collect();
    let net = network(&x0, &mass, tris, nodes, &[]);
    let (dt, speed) = (0.02, 10.0);
    let mut v: Vec<f64> = (0..nodes)
        .flat_map(|k| [0.3, -0.2, if k < n * n { -speed } else { speed }])
        .collect();
    let mut x: Vec<f64> = x0.iter().zip(&v).map(|(a, b)| a + b * dt).collect();
    let spec = Collision {
        model,
        ..Collision::default()
    };
    let mut contacts = Contacts::new(&net, &spec).expect("a surface");
    let momentum = |v: &[f64]| -> [f64; 3] {
        let mut p = [0.0; 3];
        for k in 0..nodes {
            for c in 0..3 {
                p[c] += mass[k] * v[3 * k + c];
            }
        }
        p
    };
    let energy = |v: &[f64]| {
        (0..nodes)
            .map(|k| 0.5 * mass[k] * (0..3).map(|c| v[3 * k + c].powi(2)).sum::<f64>())
            .sum::<f64>()
    };
    let (p0, e0) = (momentum(&v), energy(&v));
    let surface = Surface::of(&net);
    let lower: Vec<[usize; 3]> = net.triangles[2 * (n - 1) * (n - 1)..].to_vec();
    // The least height of an upper node over the lower sheet, where it is over it.
    let gap = |x: &[f64]| {
        (0..n * n)
            .filter_map(|k| Some(x[3 * k + 2] - height_under(x, &lower, x[3 * k], x[3 * k + 1])?))
            .fold(f64::INFINITY, f64::min)
    };
    // Unresolved, the sheets end the step swapped: a pure end-state test
    // would see nothing wrong.
    assert!(gap(&x) < -0.2 && intersections(&surface, &x).total() == 0);
    contacts.begin_step(&x0);
    contacts
        .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt)
        .unwrap();
    assert_eq!(
        intersections(&surface, &x).total(),
        0,
        "the sheets cross after the pass"
    );
    assert!(
        gap(&x) > 0.0,
        "the upper sheet is {} below the lower",
        -gap(&x)
    );
    let p = momentum(&v);
    for c in 0..3 {
        assert!(
            (p[c] - p0[c]).abs() < 1e-13,
            "momentum {p:?} against {p0:?}"
        );
    }
    assert!(energy(&v) < e0, "kinetic energy {} from {e0}", energy(&v));
    assert!(contacts.stats.collisions + contacts.stats.zone_steps > 0);
}

/// The height of the triangles `tris` straight under (px, py), if any is.
fn height_under(x: &[f64], tris: &[[usize; 3]], px: f64, py: f64) -> Option<f64> {
    tris.iter().find_map(|t| {
        let p = t.map(|n| [x[3 * n], x[3 * n + 1], x[3 * n + 2]]);
        let det =
            (p[1][0] - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (p[1][1] - p[0][1]);
        let b1 =
            ((px - p[0][0]) * (p[2][1] - p[0][1]) - (p[2][0] - p[0][0]) * (py - p[0][1])) / det;
        let b2 =
            ((p[1][0] - p[0][0]) * (py - p[0][1]) - (px - p[0][0]) * (p[1][1] - p[0][1])) / det;
        let inside = b1 >= 0.0 && b2 >= 0.0 && b1 + b2 <= 1.0;
        inside.then(|| p[0][2] + b1 * (p[1][2] - p[0][2]) + b2 * (p[2][2] - p[0][2]))
    })
}

#[test]
fn a_strip_twisted_on_itself_never_crosses_itself() {
    // A 1 m × 0.1 m strip (41 × 5 nodes), its short edges held and turned
    // 3 turns each in opposite directions about its long axis over 1 s
    // while they close to 0.2 m apart: it twists, buckles and wraps around
    // itself (a plectoneme), so its fabric meets itself. Every 0.05 s no
    // triangle pair may cross (counted by parry's BVH and GJK, not by the
    // pass); without the pass the same strip crosses itself (211 pairs).
    let (crossings, stats) = twist(true, "pairwise");
    assert_eq!(crossings, 0, "{stats:?}");
    assert!(
        stats.fabric_fabric > 100,
        "the strip hardly met itself: {stats:?}"
    );
    let (crossings, _) = twist(false, "pairwise");
    assert!(
        crossings > 0,
        "without the pass the strip should cross itself"
    );
}

#[test]
fn a_strip_twisted_on_itself_never_crosses_itself_in_the_layered_model() {
    // The strip above with one point–triangle push a contact and the
    // edge–edge approaches of fabric left to the continuous test.
    let (crossings, stats) = twist(true, "layered");
    assert_eq!(crossings, 0, "{stats:?}");
    assert!(
        stats.fabric_fabric > 100,
        "the strip hardly met itself: {stats:?}"
    );
}

/// Twist the strip, with or without the self-contact pass of `model`;
/// the most crossing pairs seen at any check, and what the pass did.
fn twist(with_pass: bool, model: &str) -> (usize, structure_proc::collision::Stats) {
    let s = section(&format!(
        r#"
        integrator = "velocity-verlet"
        gravity = [0.0, 0.0, 0.0]
        damping = "viscous"
        damping_coefficient = 0.02
        [collision]
        thickness = 2e-3
        model = "{model}"
        [cloth]
        width = 1.0
        depth = 0.1
        nodes_x = 41
        nodes_y = 5
        origin = [-0.5, -0.05, 0.0]
        fixed = ["edge-x0", "edge-x1"]
        bending_stiffness = 0.2
        [cloth.fabric]
        areal_density = 0.1
        membrane = {{ young_modulus = 1.0e6, poisson_ratio = 0.3, thickness = 2.0e-4 }}
        "#
    ));
    let dt = 2e-5;
    let mut m = structure_proc::build_model(&s, None, dt).unwrap();
    let mut stepper = structure_proc::integrator(s.scheme());
    let mut contacts = Contacts::new(&m.net, s.collision.as_ref().unwrap()).unwrap();
    let surface = Surface::of(&m.net);
    let held: Vec<(usize, [f64; 3])> = (0..m.nodes())
        .filter(|&n| m.kind[n] == NodeKind::Fixed)
        .map(|n| (n, [m.x[3 * n], m.x[3 * n + 1], m.x[3 * n + 2]]))
        .collect();
    let (turns, end, close) = (3.0, 1.0, 0.4);
    let steps = (end / dt) as usize;
    let mut most = 0;
    for k in 1..=steps {
        let t = k as f64 * dt;
        let angle = 2.0 * std::f64::consts::PI * turns * t / end;
        for &(n, p) in &held {
            // The x < 0 edge turns one way and moves right, the other the other way.
            let sign = p[0].signum();
            let (c, s) = ((sign * angle).cos(), (sign * angle).sin());
            m.x[3 * n] = p[0] - sign * close * t / end;
            m.x[3 * n + 1] = c * p[1] - s * p[2];
            m.x[3 * n + 2] = s * p[1] + c * p[2];
        }
        step(
            &mut m,
            stepper.as_mut(),
            with_pass.then_some(&mut contacts),
            dt,
        );
        if k % 2500 == 0 {
            most = most.max(intersections(&surface, &m.x).total());
        }
    }
    (most, contacts.stats)
}

#[test]
fn a_crumpled_cloth_collapsing_in_layers_never_crosses_and_keeps_its_momentum() {
    // A 31 × 31 cloth (1 cm cells) pleated along x into six layers 0.6 of
    // the 1 mm layer apart, the layer k closing at k·0.5 m/s on the one
    // below, for 200 steps of 0.1 ms without forces: the fabric pressed in
    // layers of a packed canopy. Each layer lands on the one below; the
    // impulses, equal and opposite (dissertation eqs. 3.28-3.30), keep the
    // momentum to round-off and, inelastic, lower the kinetic energy; no
    // triangle pair crosses at any step (parry's intersection test), in
    // both models, and each stops the approach: no two layers end closer
    // than a tenth of the layer. Forgetting what the pass holds between
    // steps, as a restart does, changes nothing to the bit.
    for (name, model) in MODELS {
        collapse(name, model);
    }
}

fn collapse(name: &str, model: ContactModel) {
    let n = 31;
    let m = structure_proc::rectangle::rectangle(0.3, 0.3, n, n, [0.0; 3]);
    let layer = Collision::default().thickness;
    let gap = 0.6 * layer;
    let x0 = m.pleated(5, gap);
    let nodes = n * n;
    let mass = vec![1e-5; nodes];
    let net = network(&x0, &mass, m.triangles.clone(), nodes, &[]);
    let spec = Collision {
        model,
        ..Collision::default()
    };
    let mut contacts = Contacts::new(&net, &spec).expect("a surface");
    let surface = Surface::of(&net);
    let dt = 1e-4;
    let mut v: Vec<f64> = (0..3 * nodes)
        .map(|i| {
            if i % 3 == 2 {
                -(x0[i] / gap).round() * 0.5
            } else {
                0.0
            }
        })
        .collect();
    let momentum = |v: &[f64]| (0..nodes).map(|k| mass[k] * v[3 * k + 2]).sum::<f64>();
    let energy = |v: &[f64]| {
        (0..3 * nodes)
            .map(|i| 0.5 * mass[i / 3] * v[i] * v[i])
            .sum::<f64>()
    };
    let (p0, e0) = (momentum(&v), energy(&v));
    let mut x = x0.clone();
    // The same collapse with the candidates or groups forgotten every
    // seventh step, as a restarted run has them: the pairs that act are
    // a function of the positions alone, so it ends the same to the bit.
    let mut again = Contacts::new(&net, &spec).expect("a surface");
    let (mut x2, mut v2) = (x.clone(), v.clone());
    for step in 0..200 {
        contacts.begin_step(&x);
        x.iter_mut().zip(&v).for_each(|(a, u)| *a += u * dt);
        contacts
            .resolve(&mut x, &mut v, &net.mass, &net.inv_mass, dt)
            .unwrap();
        if step % 7 == 3 {
            again.forget_candidates();
        }
        again.begin_step(&x2);
        x2.iter_mut().zip(&v2).for_each(|(a, u)| *a += u * dt);
        again
            .resolve(&mut x2, &mut v2, &net.mass, &net.inv_mass, dt)
            .unwrap();
        let crossings = intersections(&surface, &x).total();
        assert_eq!(crossings, 0, "{name}, step {step}: {:?}", contacts.stats);
    }
    assert!(
        x == x2 && v == v2,
        "{name}: forgetting the held pairs changed the run"
    );
    let p = momentum(&v);
    assert!(
        (p - p0).abs() < 1e-12 * p0.abs(),
        "{name}: momentum {p} against {p0}"
    );
    assert!(
        energy(&v) < e0,
        "{name}: kinetic energy {} from {e0}",
        energy(&v)
    );
    // The layers' least distance: node k against the triangles of the others.
    let closest = (0..nodes)
        .flat_map(|k| m.triangles.iter().map(move |t| (k, t)))
        .filter(|(k, t)| !t.contains(k))
        .map(|(k, t)| {
            let st = Stencil {
                kind: Kind::PointTriangle,
                nodes: [k, t[0], t[1], t[2]],
            };
            st.closest(&st.at(&x, &x, 0.0)).distance()
        })
        .fold(f64::INFINITY, f64::min);
    assert!(closest > 0.1 * layer, "{name}: layers {closest} m apart");
    assert!(
        contacts.stats.fabric_fabric > 1000,
        "{name}: {:?}",
        contacts.stats
    );
}
