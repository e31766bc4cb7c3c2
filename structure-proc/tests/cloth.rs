//! The hanging cloth of `scenarios/cloth-hanging.toml`, stepped in process with
//! backward Euler: at rest the held corners carry the cloth's whole weight
//! (static equilibrium: Σ F = 0 over the free nodes, so the reactions balance gravity).

use coupler::Scenario;
use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, NodeKind};

#[test]
fn hanging_cloth_settles_with_its_weight_on_the_corners() {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenarios/cloth-hanging.toml"
    );
    let mut s = Scenario::load(std::path::Path::new(path)).unwrap();
    let section = s.structure.as_mut().unwrap();
    // A coarser cloth, same physics, so the test stays quick.
    let cloth = section.cloth.as_mut().unwrap();
    cloth.nodes_x = 13;
    cloth.nodes_y = 13;
    let dt = 4e-3;
    let mut m = build_model(section, None, dt).unwrap();
    let mut stepper = integrator(section.scheme());
    for _ in 0..250 {
        m.step(stepper.as_mut(), &Loads::default()).unwrap();
    }
    assert!(
        m.kinetic_energy() < 1e-12,
        "still moving: {} J",
        m.kinetic_energy()
    );
    let weight: f64 = m.mass.iter().sum::<f64>() * m.gravity[2];
    let mut f = vec![0.0; m.x.len()];
    m.force(&Loads::default(), &mut f);
    let held: Vec<usize> = (0..m.nodes())
        .filter(|&n| m.kind[n] == NodeKind::Fixed)
        .collect();
    assert_eq!(held.len(), 2, "two corners are held");
    // The force the cloth exerts on the corners is its weight.
    let on_corners: f64 = held.iter().map(|&n| f[3 * n + 2]).sum();
    assert!(
        (on_corners / weight - 1.0).abs() < 1e-6,
        "corners carry {on_corners} N of {weight} N"
    );
    // And it sags: the bottom edge hangs below its flat start.
    let lowest = (0..m.nodes())
        .map(|n| m.x[3 * n + 2])
        .fold(f64::INFINITY, f64::min);
    assert!(lowest < 0.0, "lowest node at {lowest} m");
}
