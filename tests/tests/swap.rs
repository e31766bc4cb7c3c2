//! The structure solver can be swapped (issue 3, item 5): the canopy-porous
//! scene with its `[participants.structure] program` line changed to
//! xpbd-proc, and nothing else, settles at the centre deflection that
//! structure-proc's force integrator reaches. Both solve the same static
//! balance of springs, gravity and the Ergun load (thesis §3.2); XPBD gets
//! there by position projections (Macklin et al. 2016) instead of forces.
//!
//! The porous load can move too (issue 3, item 1): the same scene with
//! fluid-proc's `[fluid]` keys given to `[structure.porous]` instead, and no
//! fluid process, settles at the same deflection, for one law serves both.

use canopy_tests::*;

fn final_deflection(scenario: &std::path::Path, run: &std::path::Path) -> (f64, f64) {
    run_ok(scenario, run);
    let m = Monitors::read(run);
    let d = *m.column("structure.centre_deflection").last().unwrap();
    let ke = *m.column("structure.kinetic_energy").last().unwrap();
    (d, ke)
}

#[test]
fn xpbd_proc_reaches_structure_procs_equilibrium() {
    let dir = scratch("swap");
    let shipped = scenario_path("canopy-porous");
    let text = std::fs::read_to_string(&shipped).unwrap();
    let line = "program = \"structure-proc\"";
    assert_eq!(text.matches(line).count(), 1, "one structure program line");
    let swapped = dir.join("canopy-porous.toml");
    std::fs::write(&swapped, text.replace(line, "program = \"xpbd-proc\"")).unwrap();

    let (reference, _) = final_deflection(&shipped, &dir.join("structure-proc"));
    let (d, ke) = final_deflection(&swapped, &dir.join("xpbd-proc"));
    let manifest = std::fs::read_to_string(dir.join("xpbd-proc/manifest.json")).unwrap();
    assert!(manifest.contains("xpbd-proc"), "the run used xpbd-proc");
    assert!(ke < 1e-6, "xpbd-proc still moving: {ke} J");
    assert!(
        (d / reference - 1.0).abs() < 0.05,
        "xpbd-proc {d} m, structure-proc {reference} m"
    );
}

#[test]
fn the_porous_load_applied_by_the_structure_matches_fluid_procs() {
    let dir = scratch("porous-in-structure");
    let alone = variant("canopy-porous", &dir, |s| {
        s.participants.fluid = None;
        let fluid = s.fluid.take().expect("canopy-porous has a [fluid] section");
        s.structure.as_mut().unwrap().porous = Some(fluid.porous_load().expect("porous keys"));
    });
    let (reference, _) = final_deflection(&scenario_path("canopy-porous"), &dir.join("fluid"));
    let (d, ke) = final_deflection(&alone, &dir.join("alone"));
    let processes = manifest(&dir.join("alone"))["processes"].to_string();
    assert!(
        !processes.contains("fluid-proc"),
        "no fluid process ran: {processes}"
    );
    assert!(ke < 1e-6, "still moving: {ke} J");
    // The only difference: fluid-proc's jump lags one window behind the
    // structure; at rest that lag vanishes.
    assert!(
        (d / reference - 1.0).abs() < 1e-6,
        "structure alone {d} m, with fluid-proc {reference} m"
    );
}
