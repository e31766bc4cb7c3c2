//! The Darcy–Forchheimer load applied by the structure itself
//! (`[structure.porous]`, thesis eqs. 6–10), no fluid process involved.

use structure_proc::forces::{Dynamics, Loads};
use structure_proc::{build_model, integrator, Model, System};
use structure_section::Scene as Scenario;

/// A free, flat, horizontal 1 m × 1 m cloth of 9 × 9 nodes (σ = 0.05 kg/m²,
/// uniform springs) in the porous free stream `stream`, integrated by `scheme`.
fn free_cloth(scheme: &str, stream: [f64; 3]) -> (Scenario, Model) {
    let text = format!(
        r#"
[run]
name = "porous-cloth"
end_time = 1.0
[coupling]
window = 1e-3
[participants.structure]
program = "structure-proc"
[structure]
integrator = "{scheme}"
[structure.porous]
free_stream = {stream:?}
porosity = 0.1
diameter = 1.0e-3
thickness = 1.0e-4
[structure.cloth]
width = 1.0
depth = 1.0
nodes_x = 9
nodes_y = 9
[structure.cloth.fabric]
areal_density = 0.05
stiffness = 10.0
"#
    );
    let s = Scenario::load(
        std::path::Path::new("porous-cloth.toml"),
        &text,
        "structure-proc",
    )
    .unwrap();
    let m = build_model(&s.structure, None, 1e-3).unwrap();
    (s, m)
}

/// A flat sheet falling through still air reaches the terminal speed at which
/// the Ergun jump carries its weight: e·(A·ε·v + B·ε²·v²) = σ·g, the positive
/// root of thesis eq. (6) with v_f = ε·v (eq. 9) and the whole fall speed
/// normal to the sheet (eq. 10). Masses and loads are both lumped by a third
/// of each triangle's area, so every node falls alike and the sheet stays flat.
#[test]
fn a_flat_sheet_falls_at_the_ergun_terminal_speed() {
    for (scheme, dt, steps) in [
        ("velocity-verlet", 1e-4, 6000),
        ("backward-euler", 5e-3, 120),
    ] {
        let (s, mut m) = free_cloth(scheme, [0.0; 3]);
        let law = porous::Porous::new(&s.structure.porous.as_ref().unwrap().params());
        let g = -m.gravity[2];
        let sigma = 0.05;
        let (lin, quad) = (
            law.thickness * law.a * law.porosity,
            law.thickness * law.b * law.porosity.powi(2),
        );
        let terminal = (-lin + (lin * lin + 4.0 * quad * sigma * g).sqrt()) / (2.0 * quad);
        let mut stepper = integrator(s.structure.scheme());
        for _ in 0..steps {
            m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
        }
        let n = m.nodes();
        let speed = -(0..n).map(|k| m.v[3 * k + 2]).sum::<f64>() / n as f64;
        assert!(
            (speed / terminal - 1.0).abs() < 1e-6,
            "{scheme}: falls at {speed} m/s, terminal {terminal} m/s"
        );
        let z = (0..n).map(|k| m.x[3 * k + 2]);
        let spread = z.clone().fold(f64::MIN, f64::max) - z.fold(f64::MAX, f64::min);
        assert!(spread < 1e-9, "{scheme}: the sheet bent by {spread} m");
    }
}

/// The porous load's resistance to motion in the implicit schemes' Jacobian
/// product, C = −∂F/∂v, against central differences of the force in v.
#[test]
fn porous_damping_matches_finite_differences_of_the_force() {
    let (_, mut m) = free_cloth("backward-euler", [1.0, -2.0, 10.0]);
    for k in 0..m.nodes() {
        // A wavy sheet with nodes moving at different speeds, seepage everywhere upward.
        let (x, y) = (m.x[3 * k], m.x[3 * k + 1]);
        m.x[3 * k + 2] = 0.05 * (4.0 * x).sin() * (3.0 * y).cos();
        m.v[3 * k] = 0.3 * y;
        m.v[3 * k + 2] = (5.0 * x).cos();
    }
    let loads = Loads::default();
    let sys = Dynamics {
        net: &m.net,
        loads: &loads,
    };
    let p: Vec<f64> = (0..m.v.len())
        .map(|i| ((i * 7919) % 13) as f64 / 13.0 - 0.5)
        .collect();
    let h = 1e-6;
    let force = |s: f64| {
        let v: Vec<f64> = m.v.iter().zip(&p).map(|(v, p)| v + s * p).collect();
        let mut f = vec![0.0; v.len()];
        sys.force(&m.x, &v, &mut f);
        f
    };
    let (fp, fm) = (force(h), force(-h));
    let mut out = vec![0.0; m.v.len()];
    sys.jacobian_product(&m.x, &m.v, 0.0, 1.0, &p, &mut out);
    let scale = out.iter().fold(0.0f64, |s, v| s.max(v.abs()));
    assert!(scale > 0.0, "the stream damps the sheet");
    for i in 0..out.len() {
        let expect = -(fp[i] - fm[i]) / (2.0 * h);
        assert!(
            (out[i] - expect).abs() < 1e-7 * scale,
            "component {i}: {} against {expect}",
            out[i]
        );
    }
}
