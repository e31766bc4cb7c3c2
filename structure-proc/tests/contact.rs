//! The structure's self-contact pass (dissertation §2.5, §3.4; Bridson,
//! Fedkiw & Anderson 2002): the coplanarity cubic's impact times against
//! hand-solved ones, sheets that would pass through each other in one step
//! stopped without an intersection and with momentum kept, a strip twisted
//! on itself and cloths dropped on static bodies (`repulsion.rs` has the
//! proximity impulses and the bodies' normals).

mod common;

use common::network;
use structure_proc::collision::{
    intersections, triangles_through, Contacts, Kind, Stencil, Surface,
};
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

/// One structure step of `dt` without loads, then the contact pass if given.
fn step(
    m: &mut structure_proc::Model,
    stepper: &mut dyn structure_proc::Integrator,
    contacts: Option<&mut Contacts>,
    dt: f64,
) {
    let start = m.x.clone();
    m.step(stepper, &structure_proc::forces::Loads::default(), dt)
        .unwrap();
    if let Some(c) = contacts {
        c.begin_step(&start);
        let (mass, inv) = (m.net.mass.clone(), m.net.inv_mass.clone());
        c.resolve(&mut m.x, &mut m.v, &mass, &inv, dt).unwrap();
    }
}

/// The structure of a TOML `[structure]` section.
fn section(text: &str) -> structure_section::StructureSection {
    toml::from_str(text).unwrap()
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

/// What a cloth dropped on a static body did: the most self-crossing
/// triangle pairs, cloth triangles through the body and nodes inside it
/// seen at any check, and the cloth's lowest node at the end [m].
struct Drop {
    self_crossings: usize,
    through_body: usize,
    nodes_inside: usize,
    lowest: f64,
    stats: structure_proc::collision::Stats,
    /// The cloth's end state, positions then velocities, and the steps
    /// the pass skipped in quiet spells.
    end: Vec<f64>,
    quiet_steps: u64,
}

/// A 0.6 m square cloth (13 × 13 nodes, 5 cm apart) dropped from 5 cm above
/// the body of `rigid` (TOML) for 0.4 s; the body's surface in the contact
/// pass of `model` when `surfaces`, else only the node–body pass meets it.
fn drop_cloth(rigid: &str, surfaces: bool, model: &str) -> Drop {
    drop_cloth_forgetting(rigid, surfaces, model, false)
}

/// [`drop_cloth`], the pass made to forget what it holds before every
/// step when `forget` (no candidates held, no quiet spell).
fn drop_cloth_forgetting(rigid: &str, surfaces: bool, model: &str, forget: bool) -> Drop {
    let s = section(&format!(
        r#"
        integrator = "velocity-verlet"
        damping = "viscous"
        damping_coefficient = 0.05
        [collision]
        thickness = 1e-3
        model = "{model}"
        [cloth]
        width = 0.6
        depth = 0.6
        nodes_x = 13
        nodes_y = 13
        origin = [-0.3, -0.3, 0.05]
        bending_stiffness = 0.2
        [cloth.fabric]
        areal_density = 0.1
        membrane = {{ young_modulus = 1.0e6, poisson_ratio = 0.3, thickness = 2.0e-4 }}
        "#
    ));
    let rigid: rigid_section::RigidSection = toml::from_str(rigid).unwrap();
    let spec = s.collision.unwrap();
    let dt = 5e-5;
    let mut m = structure_proc::build_model(&s, None, dt).unwrap();
    let mut stepper = structure_proc::integrator(s.scheme());
    let body_surfaces = surfaces.then_some(&rigid);
    let mut contacts = Contacts::with_bodies(&m.net, &spec, body_surfaces)
        .unwrap()
        .unwrap();
    let mut nodes = structure_proc::collision::Obstacles::new(&rigid, &spec).unwrap();
    let surface = Surface::of(&m.net);
    let body = rigid.bodies[0].body().unwrap();
    let shape = body.shape.clone().unwrap();
    let pose = body.shape_pose();
    let mut drop = Drop {
        self_crossings: 0,
        through_body: 0,
        nodes_inside: 0,
        lowest: 0.0,
        stats: Default::default(),
        end: Vec::new(),
        quiet_steps: 0,
    };
    for k in 1..=8000 {
        if forget {
            contacts.forget_candidates();
        }
        nodes.begin_step(&m.x);
        step(&mut m, stepper.as_mut(), Some(&mut contacts), dt);
        nodes.resolve(&mut m.x, &mut m.v, &m.net.inv_mass, dt);
        if k % 400 == 0 {
            drop.self_crossings = drop
                .self_crossings
                .max(intersections(&surface, &m.x).total());
            let p = |n: usize| nalgebra::Point3::new(m.x[3 * n], m.x[3 * n + 1], m.x[3 * n + 2]);
            let through = triangles_through(shape.shape.as_ref(), &pose, &m.x, &m.triangles);
            drop.through_body = drop.through_body.max(through);
            let inside = (0..m.nodes())
                .filter(|&n| shape.shape.contains_point(&pose, &p(n)))
                .count();
            drop.nodes_inside = drop.nodes_inside.max(inside);
        }
    }
    drop.lowest = (0..m.nodes())
        .map(|n| m.x[3 * n + 2])
        .fold(f64::INFINITY, f64::min);
    drop.stats = contacts.stats;
    drop.end = [m.x.clone(), m.v.clone()].concat();
    drop.quiet_steps = contacts.quiet_steps();
    drop
}

#[test]
fn a_cloth_falling_on_a_thin_rod_between_its_nodes_stays_on_it() {
    // A static 5 mm square rod along y at x = 2.5 cm, midway between two
    // columns of the cloth's nodes (5 cm apart), top at z = 2.5 mm: no node
    // ever meets it, so the node–body test alone lets the cloth fall
    // through; with the rod's surface in the contact pass its edges stop
    // the cloth's edges, and the cloth hangs over it (Bridson et al. 2002's
    // edge–edge test; the dissertation §3.4).
    let rod = r#"
        [[bodies]]
        name = "rod"
        shape = { type = "cuboid", size = [0.005, 1.0, 0.005] }
        motion = "static"
        mass = 1.0
        position = [0.025, 0.0, 0.0]
        "#;
    let with = drop_cloth(rod, true, "pairwise");
    assert_eq!(
        with.through_body, 0,
        "the cloth crossed the rod: {:?}",
        with.stats
    );
    assert_eq!(with.nodes_inside, 0);
    assert_eq!(with.self_crossings, 0);
    assert!(with.stats.structure_body > 0);
    assert!(with.lowest > -0.35, "the cloth fell to {} m", with.lowest);
    let without = drop_cloth(rod, false, "pairwise");
    assert!(
        without.lowest < -0.5,
        "without the rod's surface the cloth should fall through ({} m)",
        without.lowest
    );
}

/// A static ball of radius 0.1 m with its top at the origin (TOML).
const BALL: &str = r#"
    [[bodies]]
    name = "ball"
    shape = { type = "sphere", radius = 0.1 }
    motion = "static"
    mass = 1.0
    position = [0.0, 0.0, -0.1]
    "#;

#[test]
fn a_cloth_draped_over_a_sphere_never_crosses_itself() {
    // The case the issue reports: a cloth dropped over a 0.1 m static ball
    // folds on itself as it drapes; no triangle pair may cross and no node
    // enter the ball. (A flat 5 cm triangle over a ball of radius 0.1 m
    // dips 3 mm into it between its nodes, so triangles are not tested
    // against the exact ball.)
    let d = drop_cloth(BALL, true, "pairwise");
    assert_eq!(d.self_crossings, 0, "{:?}", d.stats);
    assert_eq!(d.nodes_inside, 0, "{:?}", d.stats);
    assert!(
        d.stats.fabric_fabric + d.stats.structure_body > 0,
        "{:?}",
        d.stats
    );
}

#[test]
fn the_pass_skips_the_quiet_steps_of_a_falling_cloth_and_changes_no_bit() {
    // The draped cloth falls 5 cm before it meets the ball: its own
    // triangles are centimetres apart and nothing is within the 1 mm layer,
    // so the pass can skip those steps (`quiet.rs`: while no pair can have
    // come within the layer by the nodes' motion relative to each other
    // since the clearance was measured). Skipped or not, the end state is
    // the same to the bit, the node–body pass moving nodes between steps
    // included; the pass run at every step is the reference. (The layered
    // model's groups always hold a mesh's neighbouring patches: it has no
    // quiet spells.)
    let quiet = drop_cloth(BALL, true, "pairwise");
    let every = drop_cloth_forgetting(BALL, true, "pairwise", true);
    assert_eq!(every.quiet_steps, 0);
    assert!(
        quiet.quiet_steps > 1000,
        "{} of 8000 steps skipped",
        quiet.quiet_steps
    );
    assert!(quiet.stats.structure_body > 0, "{:?}", quiet.stats);
    assert_eq!(quiet.stats, every.stats);
    let differ = quiet.end.iter().zip(&every.end).filter(|(a, b)| a != b);
    assert_eq!(differ.count(), 0, "coordinates differ");
}

#[test]
fn a_cloth_draped_over_a_sphere_never_crosses_itself_in_the_layered_model() {
    // The draped cloth above with the layered model: its folds and the
    // ball's surface met by one point–triangle push a contact.
    let d = drop_cloth(BALL, true, "layered");
    assert_eq!(d.self_crossings, 0, "{:?}", d.stats);
    assert_eq!(d.nodes_inside, 0, "{:?}", d.stats);
    assert!(d.stats.fabric_fabric > 0, "{:?}", d.stats);
    assert!(d.stats.structure_body > 0, "{:?}", d.stats);
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
