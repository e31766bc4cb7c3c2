//! The porous annulus canopy of thesis §3.2, coupled between fluid-proc
//! (porous free-stream Ergun load, thesis eqs. 6–10) and structure-proc.

use canopy_tests::*;
use fluid_proc::Porous;
use participant::vtu;
use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator};

#[test]
fn canopy_settles_to_equilibrium() {
    let dir = scratch("settle");
    run_ok(&scenario_path("canopy-porous"), &dir.join("run"));
    let m = Monitors::read(&dir.join("run"));
    let ke = m.column("kinetic_energy");
    let d = m.column("structure.centre_deflection");
    let peak = ke.iter().cloned().fold(0.0, f64::max);
    let last = *ke.last().unwrap();
    assert!(
        peak >= 1e3 * last,
        "kinetic energy fell only from {peak} to {last}"
    );
    let tail = &d[d.len() * 9 / 10..];
    let (lo, hi) = tail
        .iter()
        .fold((f64::MAX, f64::MIN), |(l, h), v| (l.min(*v), h.max(*v)));
    let final_d = *d.last().unwrap();
    assert!(
        final_d > 0.0,
        "the upward stream must push the canopy up, got {final_d}"
    );
    assert!(
        (hi - lo) < 1e-3 * final_d.abs(),
        "deflection still moves: {lo}..{hi}"
    );
}

#[test]
fn transport_changes_no_number() {
    let dir = scratch("bitexact");
    let path = variant("canopy-porous", &dir, |s| {
        s.run.end_time = 0.5;
        s.run.output_interval = 0.0;
    });
    run_ok(&path, &dir.join("run"));
    let s = canopy_tests::Scenario::load(&path).unwrap();

    // The same model stepped in this process, with no IPC, in the schedule's order:
    // per window the fluid load from the last published state, then n_s structure steps.
    let section = s.structure.as_ref().unwrap();
    let mut model = build_model(section, None, section.dt(s.coupling.window)).unwrap();
    let mut integrator = integrator(section.scheme());
    let porous = Porous::new(
        &s.fluid
            .as_ref()
            .unwrap()
            .porous_load()
            .expect("porous keys")
            .params(),
    );
    let n = model.canopy_nodes;
    let mut pressure = vec![0.0; model.triangles.len()];
    for w in 0..s.base().windows() {
        let (_, dt) = s.base().window_span(w);
        porous.pressure(
            &model.triangles,
            &model.x[..3 * n],
            &model.v[..3 * n],
            &mut pressure,
        );
        let h = dt / section.substeps as f64;
        for _ in 0..section.substeps {
            let loads = Loads {
                pressure: &pressure,
            };
            model.step(integrator.as_mut(), &loads, h).unwrap();
        }
    }
    let written = vtu::read_points(&dir.join("run/vtk/canopy_000001.vtu")).unwrap();
    assert_eq!(written.len(), 3 * n);
    let differing = written
        .iter()
        .zip(&model.x)
        .filter(|(a, b)| a.to_bits() != b.to_bits())
        .count();
    assert_eq!(differing, 0, "{differing} of {} coordinates differ", 3 * n);
}

/// `integrator` is one key: every scheme of thesis §2.4 (and backward Euler)
/// carries the canopy to the same equilibrium, where damping and inertia vanish
/// and only the springs, gravity and the Ergun load remain.
#[test]
fn every_integrator_reaches_the_same_equilibrium() {
    use structure_section::Integrator;
    let mut finals = Vec::new();
    for integrator in Integrator::ALL {
        let dir = scratch(&format!("integrator-{}", integrator.name()));
        let path = variant("canopy-porous", &dir, |s| {
            s.run.end_time = 6.0;
            s.run.output_interval = 0.0;
            s.structure.as_mut().unwrap().integrator = integrator;
        });
        run_ok(&path, &dir.join("run"));
        let m = Monitors::read(&dir.join("run"));
        let d = *m.column("structure.centre_deflection").last().unwrap();
        finals.push((integrator.name(), d));
    }
    let reference = finals[0].1;
    for (name, d) in &finals {
        // Still ringing down at 6 s: within 1e-4 of each other, not yet to round-off.
        assert!(
            (d / reference - 1.0).abs() < 1e-4,
            "{name}: {d} m, explicit Euler {reference} m\n{finals:?}"
        );
    }
}
