//! What the compressible tests share: the shipped scenes and a run to
//! their end, and the piston's shock with what measures it. Each test
//! binary uses part of it.
#![allow(dead_code)]

use fluid_proc::comm::Single;
use fluid_proc::euler::gas::Primitive;
use fluid_proc::euler::setup::gas_scene;
use fluid_proc::euler::Compressible;
use fluid_section::Scene;
use std::sync::Arc;

/// One quantity of a cell's gas.
pub type Field = fn(&Primitive) -> f64;

/// The shipped scene `scenarios/{name}.toml`.
pub fn shipped(name: &str) -> Scene {
    let path = format!("{}/../scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::load_file(std::path::Path::new(&path)).expect("shipped scene")
}

/// The scene's gas, with the bodies of its `[rigid]` section in it at
/// their initial poses, moving on at their initial velocities.
pub fn start(scene: &Scene) -> Compressible {
    gas_scene(scene, Arc::new(Single))
        .expect("an euler scene")
        .gas
}

/// The scene's gas run for `duration` from its initial state (its bodies
/// moving on at their initial velocities).
pub fn run_to(scene: &Scene, duration: f64) -> Compressible {
    let mut gas = start(scene);
    gas.advance(duration).expect("the run stays physical");
    gas
}

/// The scene's gas run from its start to its end time.
pub fn run_to_end(scene: &Scene) -> Compressible {
    run_to(
        scene,
        scene.scenario.run.end_time - scene.scenario.run.start_time,
    )
}

/// The shock a piston moving at `up` drives into gas at rest at `rho1`,
/// `p1`: its speed W = (γ+1)u_p/4 + √(((γ+1)u_p/4)² + a₁²), and ρ₂ =
/// ρ₁W/(W − u_p), p₂ = p₁ + ρ₁W·u_p behind it (the Rankine–Hugoniot
/// conditions of a moving normal shock; Anderson, *Modern Compressible
/// Flow*, 3rd ed., §7.2–7.3).
pub fn piston_shock(gamma: f64, rho1: f64, p1: f64, up: f64) -> (f64, f64, f64) {
    let a1 = (gamma * p1 / rho1).sqrt();
    let half = (gamma + 1.0) * up / 4.0;
    let w = half + (half * half + a1 * a1).sqrt();
    (w, rho1 * w / (w - up), p1 + rho1 * w * up)
}

/// Where the density along `row` (cell `i` centred at `x(i)`) last falls
/// through `level` going up the row, between the cells.
pub fn front(row: &[Primitive], x: impl Fn(usize) -> f64, level: f64) -> f64 {
    let i = (0..row.len() - 1)
        .rev()
        .find(|&i| row[i].density >= level)
        .expect("a shocked slab");
    let (d0, d1) = (row[i].density, row[i + 1].density);
    x(i) + (d0 - level) / (d0 - d1) * (x(i + 1) - x(i))
}

/// The mean density, velocity along x and pressure of the cells of `row`
/// centred in `span`, each within 1 % of `exact`.
pub fn assert_slab_within_1_percent(
    row: &[Primitive],
    x: impl Fn(usize) -> f64,
    span: std::ops::Range<f64>,
    exact: [f64; 3],
) {
    let slab: Vec<_> = (0..row.len())
        .filter(|&i| span.contains(&x(i)))
        .map(|i| row[i])
        .collect();
    let mean = |f: Field| slab.iter().map(f).sum::<f64>() / slab.len() as f64;
    let got = [
        mean(|c| c.density),
        mean(|c| c.velocity[0]),
        mean(|c| c.pressure),
    ];
    eprintln!("slab: rho, u, p {got:.5?} against {exact:.5?}");
    for ((got, exact), name) in got
        .iter()
        .zip(exact)
        .zip(["density", "velocity", "pressure"])
    {
        assert!(
            (got / exact - 1.0).abs() < 0.01,
            "{name} {got}, exact {exact}"
        );
    }
}
