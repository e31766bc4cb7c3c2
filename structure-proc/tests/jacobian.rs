//! The assembled Jacobian (`forces/jacobian.rs`) is the matrix the implicit
//! schemes' products apply: Σ blocks·p equals `jacobian_product(p)` for
//! every element family, and backward Euler solving each Newton step by a
//! sparse Cholesky factorization or by multigrid (`[structure.newton]
//! linear_solver = "cholesky" | "multigrid"`) follows the conjugate-gradient
//! run to the Newton tolerance, on the cloth and on a parachute.

use structure_proc::forces::{Dynamics, Loads};
use structure_proc::{build_model, integrator, Model, System};
use structure_section::{Integrator, LinearSolver, Scene, StructureSection};

fn scene(name: &str) -> Scene {
    let path = format!("{}/../scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    Scene::load_file(std::path::Path::new(&path), "structure-proc").expect("shipped scenario")
}

/// A reproducible pseudo-random number in [−1, 1) (a 64-bit LCG).
fn noise(seed: &mut u64) -> f64 {
    *seed = seed
        .wrapping_mul(6364136223846793005)
        .wrapping_add(1442695040888963407);
    (*seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
}

/// The model of `section`, its positions moved by up to `jiggle` [m] and
/// given velocities up to 1 m/s, so that every spring and membrane edge
/// is stretched or slack and every damper and porous triangle acts.
fn jiggled(
    section: &StructureSection,
    rigid: Option<&rigid_section::RigidSection>,
    jiggle: f64,
) -> Model {
    let mut m = build_model(section, rigid, 1e-3).expect("builds");
    let mut seed = 7;
    for x in &mut m.x {
        *x += jiggle * noise(&mut seed);
    }
    for v in &mut m.v {
        *v = noise(&mut seed);
    }
    m
}

/// Σ blocks·p against the product, for a·K + b·C with a, b of a backward
/// Euler step's size, on three random p.
fn blocks_apply_the_product(m: &Model, what: &str) {
    let sys = Dynamics {
        net: &m.net,
        loads: &Loads::default(),
    };
    let (a, b) = (1e-6, 1e-3);
    let mut blocks = Vec::new();
    assert!(
        sys.jacobian_blocks(&m.x, &m.v, a, b, &mut blocks),
        "{what}: blocks"
    );
    let mut seed = 11;
    for _ in 0..3 {
        let p: Vec<f64> = m.x.iter().map(|_| noise(&mut seed)).collect();
        let mut product = vec![0.0; p.len()];
        sys.jacobian_product(&m.x, &m.v, a, b, &p, &mut product);
        let mut assembled = vec![0.0; p.len()];
        for &(i, j, s) in &blocks {
            for r in 0..3 {
                for c in 0..3 {
                    assembled[3 * i + r] += s[(r, c)] * p[3 * j + c];
                }
            }
        }
        let scale = product.iter().fold(0.0f64, |m, v| m.max(v.abs()));
        let worst = product
            .iter()
            .zip(&assembled)
            .map(|(x, y)| (x - y).abs())
            .fold(0.0, f64::max);
        assert!(
            scale > 0.0 && worst <= 1e-12 * scale,
            "{what}: blocks·p is {worst:e} off a product of {scale:e}"
        );
    }
}

#[test]
fn the_blocks_apply_the_jacobian_product_of_every_element() {
    // Delingette's membrane, bending springs, axial dampers (eq. 2.38).
    let cloth = scene("cloth-hanging").structure;
    blocks_apply_the_product(&jiggled(&cloth, None, 5e-3), "membrane cloth");
    // Springs, dampers of thesis eq. (68), the porous load (eqs. 6–10).
    let mut annulus = scene("canopy-porous").structure;
    annulus.porous = scene("canopy-stiff").structure.porous;
    blocks_apply_the_product(&jiggled(&annulus, None, 5e-3), "porous annulus");
    // Strings, tension only (eq. 3), some slack, on a rigid body.
    let c9 = scene("c9-drop-body");
    blocks_apply_the_product(
        &jiggled(&c9.structure, c9.rigid.as_ref(), 5e-2),
        "C-9 on its body",
    );
}

/// `cloth-hanging` (backward Euler at 20 times the explicit limit) for 20
/// steps with each linear solver: the same cloth to far below the
/// accuracy of the step.
#[test]
fn backward_euler_is_the_same_by_every_linear_solver() {
    let s = scene("cloth-hanging");
    assert_eq!(s.structure.integrator, Integrator::BackwardEuler);
    let dt = s.structure.dt(s.scenario.coupling.window);
    same_by_every_linear_solver(&s.structure, dt, 20);
}

/// The same on the C-9 of `c9-drop` (structure alone, falling under
/// gravity by backward Euler at the coupling window), whose hub node, 28
/// lines of 8 segments and seams the cloth does not have: the coarsening
/// meets nodes of degree 28 and chains.
#[test]
fn backward_euler_on_a_parachute_is_the_same_by_every_linear_solver() {
    let s = scene("c9-drop");
    let mut section = s.structure.clone();
    section.integrator = Integrator::BackwardEuler;
    section.gravity = [0.0, 0.0, -9.81];
    same_by_every_linear_solver(&section, s.scenario.coupling.window, 20);
}

/// `steps` backward-Euler steps of `section` with each linear solver: the
/// nodes where conjugate gradients put them, within 10⁻⁶ of the motion.
fn same_by_every_linear_solver(section: &StructureSection, dt: f64, steps: usize) {
    let run = |solver: LinearSolver| {
        let mut section = section.clone();
        section.newton.linear_solver = solver;
        let mut m = build_model(&section, None, dt).unwrap();
        let mut stepper = integrator(section.scheme());
        for _ in 0..steps {
            m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
        }
        m
    };
    let cg = run(LinearSolver::Cg);
    let start = build_model(section, None, dt).unwrap();
    let apart = |a: &[f64], b: &[f64]| {
        a.iter()
            .zip(b)
            .map(|(a, b)| (a - b).abs())
            .fold(0.0, f64::max)
    };
    let moved = apart(&start.x, &cg.x);
    assert!(moved > 1e-3, "it falls: {moved} m");
    eprintln!("{} nodes", start.nodes());
    for solver in [LinearSolver::Cholesky, LinearSolver::Multigrid] {
        let other = run(solver);
        let gap = apart(&other.x, &cg.x);
        eprintln!("{solver:?} and CG {gap:.3e} m apart after a motion of {moved:.3e} m");
        // Each stops when the Newton correction is 10⁻¹⁰ of the extent; the
        // iterative solves' inexact steps (10⁻⁴ residual) leave their
        // results within that too.
        assert!(gap < 1e-6 * moved, "{solver:?}: {gap:e} m apart");
    }
}
