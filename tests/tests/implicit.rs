//! Implicit coupling through the coupler (issue 22): the added-mass case
//! of `scenarios/sheet-closed.toml`, a closed sheet a hundred times lighter
//! than the air column it pushes, which explicit coupling cannot run.

use canopy_tests::*;

/// The scene's inflow [m/s], the sheet's areal density [kg/m²] and
/// standard gravity [m/s²].
const UPDRAFT: f64 = 1.8;
const AREAL_DENSITY: f64 = 0.05;
const G: f64 = 9.81;

/// Explicit staggered coupling diverges within a few windows (Causin,
/// Gerbeau & Nobile 2005: the added mass exceeds the sheet's).
#[test]
fn explicit_coupling_diverges_on_the_closed_sheet() {
    let dir = scratch("sheet-closed-explicit");
    let scenario = variant("sheet-closed", &dir, |s| {
        s.coupling.scheme = scenario::SchemeName::Explicit;
        s.run.end_time = 0.1;
    });
    let msg = run_failed(&scenario, &dir.join("run"));
    assert!(msg.contains("diverged"), "{msg}");
}

/// Implicit coupling runs it to its exact motion: by continuity the sheet
/// rises with the inflow, carried by a jump equal to its weight per area.
/// Measured: the jump 0.01 % and the speed 0.13 % off (the discrete sheet
/// lets a little air through between its markers).
#[test]
fn implicit_coupling_carries_the_closed_sheet_at_the_inflow_speed() {
    let dir = scratch("sheet-closed");
    let scenario = variant("sheet-closed", &dir, |s| s.run.end_time = 0.3);
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let weight = AREAL_DENSITY * G;
    let jump = *m.column("fluid.mean_pressure_jump").last().unwrap();
    let speed = m.column("structure.momentum.z").last().unwrap() / AREAL_DENSITY;
    assert!(
        (jump / weight - 1.0).abs() < 5e-3,
        "jump {jump} Pa against the weight {weight} Pa"
    );
    assert!(
        (speed / UPDRAFT - 1.0).abs() < 5e-3,
        "the sheet rises at {speed} m/s against {UPDRAFT} m/s"
    );
}

/// The README's table of tries per window on the added-mass case over
/// 0.3 s: constant relaxation at ω = 0.01 does not converge within 20
/// tries; Aitken takes 6.5 on average, IQN-ILS 3.2 (measured), fewer than
/// Aitken as the issue asks (preCICE's perpendicular flap: 3–4 with
/// IQN-ILS). Every run carries the sheet at the inflow's speed.
#[test]
fn iqn_ils_needs_fewer_tries_than_aitken_on_the_added_mass_case() {
    use scenario::implicit::{AccelerationName, OnMax};
    let tries = |acceleration: AccelerationName, relaxation: f64, max_iterations: u32| {
        let name = format!("sheet-closed-{acceleration:?}");
        let dir = scratch(&name);
        let scenario = variant("sheet-closed", &dir, |s| {
            s.run.end_time = 0.3;
            s.coupling.implicit = Some(scenario::ImplicitSection {
                acceleration,
                relaxation,
                max_iterations,
                on_max: OnMax::GoOn,
                ..Default::default()
            });
        });
        let out = dir.join("run");
        run_ok(&scenario, &out);
        let m = manifest(&out);
        let mean = m["implicit"]["mean_iterations"].as_f64().unwrap();
        let largest = m["implicit"]["largest_iterations"].as_f64().unwrap();
        let iterations = std::fs::read_to_string(out.join("iterations.csv")).unwrap();
        assert_eq!(iterations.lines().count(), 31, "a row per window");
        (mean, largest)
    };
    let constant = tries(AccelerationName::Constant, 0.01, 20);
    assert_eq!(constant, (20.0, 20.0), "constant ω = 0.01");
    let aitken = tries(AccelerationName::Aitken, 0.1, 50);
    let iqn = tries(AccelerationName::IqnIls, 0.1, 50);
    assert!((aitken.0 - 6.5).abs() < 0.5, "Aitken: {aitken:?}");
    assert!((iqn.0 - 3.2).abs() < 0.3, "IQN-ILS: {iqn:?}");
    assert!(iqn.0 < aitken.0 && iqn.1 <= aitken.1);
}
