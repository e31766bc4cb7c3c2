//! The hanging cloth of `scenarios/cloth-hanging.toml`, stepped in process with
//! backward Euler: at rest the held corners carry the cloth's whole weight
//! (static equilibrium: Σ F = 0 over the free nodes, so the reactions balance gravity).

use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, NodeKind};
use structure_section::Scene;
use structure_section::StructureSection;

/// The structure of `scenarios/cloth-hanging.toml` on n × n nodes.
fn cloth_scene(n: u32) -> StructureSection {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenarios/cloth-hanging.toml"
    );
    let s = Scene::load_file(std::path::Path::new(path), "structure-proc").unwrap();
    let mut section = s.structure;
    let cloth = section.cloth.as_mut().unwrap();
    cloth.nodes_x = n;
    cloth.nodes_y = n;
    section
}

#[test]
fn hanging_cloth_settles_with_its_weight_on_the_corners() {
    // A coarser cloth, same physics, so the test stays quick.
    let section = &cloth_scene(13);
    let dt = 4e-3;
    let mut m = build_model(section, None, dt).unwrap();
    let mut stepper = integrator(section.scheme());
    for _ in 0..250 {
        m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
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

/// The parallel force assembly (`forces/assembly.rs`) on a cloth large enough
/// to be split between threads: the internal forces still cancel in sum
/// (Newton's third law, so linear momentum is conserved), and the result is
/// the same to the last bit on one thread and on two.
#[test]
fn parallel_force_is_balanced_and_independent_of_the_thread_count() {
    let section = &cloth_scene(60);
    let dt = 2e-3;
    let mut m = build_model(section, None, dt).unwrap();
    assert!(m.springs.len() + 3 * m.membrane.len() > 4 * structure_proc::forces::assembly::GRAIN);
    let mut stepper = integrator(section.scheme());
    for _ in 0..5 {
        m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
    }
    m.gravity = [0.0; 3];
    m.prepare();
    let force_on = |threads: usize| {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .unwrap();
        let mut f = vec![0.0; m.x.len()];
        pool.install(|| m.force(&Loads::default(), &mut f));
        f
    };
    let (one, two) = (force_on(1), force_on(2));
    assert!(one
        .iter()
        .zip(&two)
        .all(|(a, b)| a.to_bits() == b.to_bits()));
    let largest = one.iter().fold(0.0f64, |a, b| a.max(b.abs()));
    assert!(largest > 0.0, "the cloth is deformed");
    for c in 0..3 {
        let sum: f64 = one.iter().skip(c).step_by(3).sum();
        assert!(
            sum.abs() < 1e-12 * largest * m.nodes() as f64,
            "Σ F_{c} = {sum} N, largest {largest} N"
        );
    }
}
