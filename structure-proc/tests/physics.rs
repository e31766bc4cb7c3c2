//! Physics checks of the spring-mass model (seed 003 §2.1, §3.2).

use coupler::scenario::structure::{Annulus, Damping, Integrator as Scheme, StructureSection};
use std::f64::consts::PI;
use structure_proc::annulus::annulus;
use structure_proc::forces::{total_force, Loads};
use structure_proc::{build_model, Integrator, Model, NodeKind};

fn section(gravity: [f64; 3], damping: Damping) -> StructureSection {
    StructureSection {
        integrator: Scheme::VelocityVerlet,
        gravity,
        damping,
        annulus: Some(Annulus {
            inner_radius: 0.1,
            outer_radius: 1.0,
            rings: 12,
            outer_nodes: 107,
            stiffness: 100.0,
            areal_density: 1.0,
            height: 0.0,
        }),
        strings: vec![],
    }
}

#[test]
fn annulus_mesh_is_a_valid_annulus_of_about_703_nodes() {
    let m = annulus(0.1, 1.0, 12, 107, 0.0).unwrap();
    let nodes = m.points.len() / 3;
    assert!(
        (690..=720).contains(&nodes),
        "{nodes} nodes (seed 003 table 3: 703)"
    );
    // An annulus has Euler characteristic V − E + F = 0.
    let mut edges = std::collections::BTreeSet::new();
    let mut area = 0.0;
    for t in &m.triangles {
        for k in 0..3 {
            let (i, j) = (t[k], t[(k + 1) % 3]);
            edges.insert((i.min(j), i.max(j)));
        }
        let n = structure_proc::forces::area_normal2(&m.points, t);
        assert!(n[2] > 0.0, "every triangle faces +z");
        area += 0.5 * n[2];
    }
    assert_eq!(
        nodes as i64 - edges.len() as i64 + m.triangles.len() as i64,
        0
    );
    // Inscribed polygons lose a little area; within 1% of π(R² − r²).
    let exact = PI * (1.0 - 0.01);
    assert!((area / exact - 1.0).abs() < 0.01, "area {area} vs {exact}");
}

/// Elastic energy of the whole network.
fn energy(m: &Model, x: &[f64]) -> f64 {
    m.springs
        .iter()
        .map(|s| structure_proc::forces::spring_energy(s, x))
        .sum()
}

#[test]
fn spring_forces_are_minus_the_gradient_of_their_energy() {
    let mut m = build_model(&section([0.0; 3], Damping::None), None, 1e-3).unwrap();
    // Deform the canopy so every spring is stretched or compressed.
    for n in 0..m.nodes() {
        let (x, y) = (m.x[3 * n], m.x[3 * n + 1]);
        m.x[3 * n + 2] = 0.3 * (1.0 - x * x - y * y) + 0.01 * (7.0 * x).sin();
        m.x[3 * n] *= 1.0 + 0.02 * y;
    }
    let mut f = vec![0.0; m.x.len()];
    total_force(&m, &Loads::default(), &m.x, &m.v, &mut f);
    let h = 1e-6;
    let mut worst: f64 = 0.0;
    for i in (0..m.x.len()).step_by(7) {
        if m.kind[i / 3] != NodeKind::Free {
            continue;
        }
        let mut xp = m.x.clone();
        xp[i] += h;
        let mut xm = m.x.clone();
        xm[i] -= h;
        let grad = (energy(&m, &xp) - energy(&m, &xm)) / (2.0 * h);
        worst = worst.max((f[i] + grad).abs() / (1.0 + f[i].abs()));
    }
    assert!(worst < 1e-6, "force differs from −∂E/∂x by {worst}");
}

#[test]
fn free_network_conserves_momentum_to_round_off() {
    let mut m = build_model(&section([0.0; 3], Damping::RelativeVelocity), None, 1e-3).unwrap();
    // Free every node (no rim) and give it mass; start from a stretched, moving state.
    for n in 0..m.nodes() {
        m.kind[n] = NodeKind::Free;
        m.mass[n] = 4e-3;
        m.x[3 * n] *= 1.05;
        m.v[3 * n + 2] = (3.0 * m.x[3 * n]).sin();
    }
    let momentum = |m: &Model| -> [f64; 3] {
        let mut p = [0.0; 3];
        for n in 0..m.nodes() {
            for c in 0..3 {
                p[c] += m.mass[n] * m.v[3 * n + c];
            }
        }
        p
    };
    let p0 = momentum(&m);
    let mut integrator = Integrator::new(Scheme::VelocityVerlet, &m);
    for _ in 0..200 {
        integrator.step(&mut m, &Loads::default());
    }
    let p1 = momentum(&m);
    let scale: f64 = (0..m.nodes())
        .map(|n| m.mass[n] * m.v[3 * n + 2].abs())
        .sum();
    for c in 0..3 {
        assert!(
            (p1[c] - p0[c]).abs() < 1e-12 * scale.max(1.0),
            "component {c}: {} → {}",
            p0[c],
            p1[c]
        );
    }
}
