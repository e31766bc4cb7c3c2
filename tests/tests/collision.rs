//! Structure nodes against rigid bodies across the two processes (the dissertation
//! §3.4): a mass point strikes a ball and they part with the velocities of
//! eq. (4.1), and a circular cloth dropped on a cuboid (§4.3.3, fig. 4.8)
//! never enters it nor crosses itself, obeys the momentum balance with the
//! impulses the cuboid gives, and at rest lies on it with its whole weight.

use canopy_tests::*;
use participant::vtu;
use rigid_section::STANDARD_GRAVITY;

fn last(m: &Monitors, name: &str) -> f64 {
    *m.column(name).last().unwrap()
}

#[test]
fn a_mass_point_and_a_ball_part_with_the_closed_form_velocities() {
    // Eq. (4.1) with m₁ = 1 kg (the structure's node) at 1 m/s and m₂ = 2 kg
    // (rigid-proc's ball) at rest: v₁' = (1 − 2·C_R)/3, v₂' = (1 + C_R)/3.
    let dir = scratch("point-ball");
    let out = dir.join("run");
    run_ok(&scenario_path("point-ball"), &out);
    let m = Monitors::read(&out);
    for (pair, cr) in [("inelastic", 0.0), ("elastic", 1.0)] {
        let v1 = last(&m, &format!("structure.{pair}_point.vx"));
        let v2 = last(&m, &format!("rigid.{pair}_ball.vx"));
        let (e1, e2) = ((1.0 - 2.0 * cr) / 3.0, (1.0 + cr) / 3.0);
        assert!(
            (v1 - e1).abs() < 1e-12 && (v2 - e2).abs() < 1e-12,
            "{pair}: {v1}, {v2}"
        );
        // Head on: no sideways motion, no spin.
        for k in ["vy", "vz", "omegax", "omegay", "omegaz"] {
            let s = last(&m, &format!("rigid.{pair}_ball.{k}"));
            assert!(s.abs() < 1e-12, "{pair} ball {k} = {s}");
        }
        if cr == 1.0 {
            let e = 0.5 * v1 * v1 + 0.5 * 2.0 * v2 * v2;
            assert!((e - 0.5).abs() < 1e-12, "elastic energy {e} J, was 0.5 J");
        }
    }
    // The momentum of 2 kg·m/s (two points at 1 m/s) is shared between the
    // processes and kept to round-off at every window.
    let ps = m.column("structure.momentum.x");
    let pr = m.column("rigid.momentum.x");
    for (a, b) in ps.iter().zip(&pr) {
        assert!((a + b - 2.0).abs() < 1e-14, "momentum {}", a + b);
    }
    assert_eq!(last(&m, "structure.collision_impulses"), 2.0);
}

#[test]
fn a_dropped_cloth_stays_out_of_the_cuboid_and_rests_on_it_with_its_weight() {
    let dir = scratch("cloth-drop");
    // A coarser cloth than the scene's, for a quicker test; same physics.
    let scenario = variant("cloth-drop", &dir, |s| {
        s.structure.as_mut().unwrap().disk.as_mut().unwrap().rings = 8;
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let s = canopy_tests::Scenario::load(&scenario).unwrap();
    let st = s.structure.as_ref().unwrap();
    let layer = st.collision.as_ref().unwrap().thickness;
    let model = structure_proc::build_model(st, None, 1e-4).unwrap();
    let weight = model.mass.iter().sum::<f64>() * STANDARD_GRAVITY;
    let surface = structure_proc::collision::Surface::of(&model.net);

    // Momentum balance of the cloth, which starts at rest: its internal
    // forces cancel, so p_z(t) = −W·t + I_z(t) with I the impulses the cuboid
    // gave; the position corrections move no momentum. Kept to round-off.
    let t = m.column("time");
    let pz = m.column("structure.momentum.z");
    let iz = m.column("structure.collision_impulse.z");
    for k in 0..t.len() {
        let balance = pz[k] + weight * t[k] - iz[k];
        assert!(balance.abs() < 1e-11, "t = {}: off by {balance:e}", t[k]);
    }
    assert!(last(&m, "structure.collision_impulses") > 0.0);

    // No node ever closer to the cuboid (half size 0.2 m at the origin) than
    // the layer, in any written state.
    let half = 0.2;
    let mut outputs = 0;
    for entry in std::fs::read_dir(out.join("vtk")).unwrap() {
        let path = entry.unwrap().path();
        if !path.to_string_lossy().ends_with(".vtu")
            || !path
                .file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with("canopy_")
        {
            continue;
        }
        outputs += 1;
        let x = vtu::read_points(&path).unwrap();
        let crossings = structure_proc::collision::intersections(&surface, &x);
        assert_eq!(crossings.total(), 0, "{}: {crossings:?}", path.display());
        for p in x.chunks_exact(3) {
            let d: Vec<f64> = p.iter().map(|c| c.abs() - half).collect();
            let outside = d.iter().map(|x| x.max(0.0).powi(2)).sum::<f64>().sqrt();
            let signed = if outside > 0.0 {
                outside
            } else {
                d.iter().cloned().fold(f64::MIN, f64::max)
            };
            assert!(
                signed > layer - 1e-12,
                "{}: a node {signed} m from the cuboid",
                path.display()
            );
        }
    }
    assert!(outputs > 10, "only {outputs} outputs");

    // At rest over the last half second, the cuboid carries the cloth's whole
    // weight: the impulse it gives grows at W (Δp of the settled cloth is small).
    let n = t.len() - 1;
    let k = t.iter().position(|&x| x >= t[n] - 0.5).unwrap();
    let force = (iz[n] - iz[k]) / (t[n] - t[k]);
    assert!(
        (force / weight - 1.0).abs() < 0.02,
        "support {force} N against the weight {weight} N"
    );
}
