//! Sod's shock tube (`scenarios/sod.toml`; Sod, J. Comput. Phys. 27, 1978)
//! run by the compressible Euler solver of dissertation §3.2.1 and checked
//! against the exact solution of its Riemann problem (Toro, *Riemann
//! Solvers and Numerical Methods for Fluid Dynamics*, ch. 4;
//! `fluid_proc::euler::riemann`), whose star state is p* = 0.30313, u* = 0.92745
//! (Toro Table 4.3).

mod common;
use common::*;
use fluid_proc::euler::gas::{Gas, Primitive};
use fluid_proc::euler::riemann::Riemann;

/// The tube's two gases and where they meet.
const SPLIT: f64 = 0.5;

fn exact(gas: Gas) -> Riemann {
    let at_rest = |density, pressure| Primitive {
        density,
        velocity: [0.0; 3],
        pressure,
    };
    Riemann {
        gas,
        left: at_rest(1.0, 1.0),
        right: at_rest(0.125, 0.1),
    }
}

fn total_variation(v: &[f64]) -> f64 {
    v.windows(2).map(|p| (p[1] - p[0]).abs()).sum()
}

#[test]
fn sods_star_state_matches_the_exact_solution_within_1_percent() {
    let scene = shipped("sod");
    let t = scene.scenario.run.end_time;
    let gas = run_to_end(&scene);
    let n = gas.setup.n[0];
    let x = |i: usize| (i as f64 + 0.5) / n as f64;
    let riemann = exact(gas.setup.gas);
    let star = riemann.star();
    assert!((star.pressure - 0.30313).abs() < 5e-6 && (star.velocity - 0.92745).abs() < 5e-6);
    let solution: Vec<Primitive> = (0..n)
        .map(|i| riemann.sample(star, (x(i) - SPLIT) / t))
        .collect();
    let w = gas.primitives();

    // The star region runs from the rarefaction's tail to the shock; the
    // cells more than 8 from either end are its plateau (the contact in
    // between carries no jump in p or u).
    let in_star = |i: usize| (solution[i].pressure - star.pressure).abs() < 1e-12;
    let plateau: Vec<usize> = (8..n - 8)
        .filter(|&i| (i - 8..=i + 8).all(in_star))
        .collect();
    assert!(plateau.len() > 100, "{} plateau cells", plateau.len());
    let mean = |f: fn(&Primitive) -> f64| {
        plateau.iter().map(|&i| f(&w[i])).sum::<f64>() / plateau.len() as f64
    };
    let (p, u) = (mean(|w| w.pressure), mean(|w| w.velocity[0]));
    // Deliver item 5: within 1 % (measured: 0.30313 and 0.92746).
    assert!((p / 0.30313 - 1.0).abs() < 0.01, "p* = {p}");
    assert!((u / 0.92745 - 1.0).abs() < 0.01, "u* = {u}");

    // The whole profile: the L1 density error is set by the smeared
    // contact and shock (measured 1.6e-3 on 400 cells).
    let l1: f64 = (0..n)
        .map(|i| (w[i].density - solution[i].density).abs() / n as f64)
        .sum();
    assert!(l1 < 2.5e-3, "L1 density error {l1:e}");

    // No oscillations: the exact ρ and p fall monotonically and u rises and
    // falls once, so their total variation is the size of the jumps; new
    // wiggles would add to it (measured: 0.37 %, 0.38 %, 0.32 % above).
    let fields: [(&str, Field); 3] = [
        ("density", |w| w.density),
        ("velocity", |w| w.velocity[0]),
        ("pressure", |w| w.pressure),
    ];
    for (name, f) in fields {
        let tv = total_variation(&w.iter().map(f).collect::<Vec<_>>());
        let exact_tv = total_variation(&solution.iter().map(f).collect::<Vec<_>>());
        assert!(
            tv < 1.01 * exact_tv,
            "{name}: total variation {tv} against the exact {exact_tv}"
        );
    }
}

#[test]
fn mass_and_energy_are_conserved_and_momentum_grows_by_the_end_pressures() {
    // No wave reaches the transmissive ends by t = 0.2, so nothing crosses
    // them but the momentum flux p: d(Σ ρu V)/dt = (p_left − p_right)·A.
    let scene = shipped("sod");
    let t = scene.scenario.run.end_time;
    let b = scene.fluid.flow_box.unwrap();
    let area = (b.upper[1] - b.lower[1]) * (b.upper[2] - b.lower[2]);
    let before = common::run_to(&scene, 0.0).totals();
    let after = run_to_end(&scene).totals();
    assert!((after[0] / before[0] - 1.0).abs() < 1e-13, "mass");
    assert!((after[4] / before[4] - 1.0).abs() < 1e-13, "energy");
    let momentum = (1.0 - 0.1) * area * t;
    assert!((after[1] / momentum - 1.0).abs() < 1e-12, "{after:?}");
    assert!(after[2] == 0.0 && after[3] == 0.0, "{after:?}");
}

#[test]
fn a_closed_tube_keeps_its_mass_and_energy_through_the_reflections() {
    // Reflecting walls at both ends, run to t = 1: the shock and the
    // rarefaction cross the tube and reflect several times. The walls let
    // no mass or energy through, so both stay put to round-off.
    let mut scene = shipped("sod");
    let fluid = &mut scene.fluid;
    let mut sides = fluid.sides.unwrap();
    sides.x_low = Some(fluid_section::flow::SideSpec::Wall);
    sides.x_high = Some(fluid_section::flow::SideSpec::Wall);
    fluid.sides = Some(sides);
    scene.scenario.run.end_time = 1.0;
    let before = common::run_to(&scene, 0.0).totals();
    let after = run_to_end(&scene).totals();
    assert!((after[0] / before[0] - 1.0).abs() < 1e-13, "mass {after:?}");
    assert!(
        (after[4] / before[4] - 1.0).abs() < 1e-13,
        "energy {after:?}"
    );
}

#[test]
fn the_tube_gives_the_same_gas_along_y_and_z() {
    // The flux along each axis is the x formula on permuted momenta
    // (`Gas::rotated`): the tube laid along y or z must give the x result.
    let scene = shipped("sod");
    let along_x: Vec<Primitive> = run_to_end(&scene).primitives();
    for axis in [1, 2] {
        let mut turned = scene.clone();
        let fluid = &mut turned.fluid;
        let b = fluid.flow_box.as_mut().unwrap();
        let turn = |v: [f64; 3]| {
            let mut t = v;
            t.swap(0, axis);
            t
        };
        b.lower = turn(b.lower);
        b.upper = turn(b.upper);
        b.cells.swap(0, axis);
        for r in fluid.regions.as_mut().unwrap() {
            r.upper = r.upper.map(turn);
        }
        let mut sides = fluid.sides.unwrap();
        let ends = [sides.x_low.take(), sides.x_high.take()];
        match axis {
            1 => [sides.y_low, sides.y_high] = ends,
            _ => [sides.z_low, sides.z_high] = ends,
        }
        fluid.sides = Some(sides);
        let w = run_to_end(&turned).primitives();
        for (a, b) in w.iter().zip(&along_x) {
            assert!((a.density - b.density).abs() < 1e-14);
            assert!((a.pressure - b.pressure).abs() < 1e-14);
            assert!((a.velocity[axis] - b.velocity[0]).abs() < 1e-14);
        }
    }
}
