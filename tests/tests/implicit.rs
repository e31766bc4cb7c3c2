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

/// On `canopy-flow.toml` (a porous annulus in a 50 m/s stream), where
/// explicit coupling is stable, the two schemes approach the same solution
/// as the window shrinks: the implicit fluid sees the canopy at the
/// window's end, the explicit one at its start, a first-order difference.
/// Measured over 0.09 s at windows 9, 4.5 and 2.25·10⁻⁴ s: the centre
/// deflection's largest difference 9.6, 4.9, 2.5·10⁻⁵ m (of 0.09 m) and
/// the canopy's momentum's 4.4, 2.4, 1.2·10⁻³ kg·m/s (of 4 kg·m/s),
/// halving with the window. (Later, as the centre nears the next cell
/// plane 0.15 m on, the fluid's choice of cells under each triangle
/// changes by a step at a time that depends on the window, and the
/// differences stop shrinking.)
#[test]
fn implicit_and_explicit_approach_each_other_as_the_window_shrinks() {
    let end = 0.09;
    let run = |scheme: scenario::SchemeName, window: f64| {
        let name = format!("canopy-flow-{scheme:?}-{window:e}");
        let dir = scratch(&name);
        let scenario = variant("canopy-flow", &dir, |s| {
            s.run.end_time = end;
            s.run.output_interval = 0.0;
            s.coupling.window = window;
            s.coupling.scheme = scheme;
            let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
            b.cells = [20, 20, 27];
        });
        run_ok(&scenario, &dir.join("run"));
        Monitors::read(&dir.join("run"))
    };
    // Largest difference of `name` between the runs at the times every
    // window size reaches (multiples of 9 ms), and its largest magnitude.
    let apart = |a: &Monitors, b: &Monitors, name: &str| {
        let on_grid = |t: f64| ((t / 9e-3).round() - t / 9e-3).abs() < 1e-6;
        let (t, x, y) = (a.column("time"), a.column(name), b.column(name));
        let grid = (0..t.len()).filter(|&i| on_grid(t[i]));
        let d = grid
            .clone()
            .map(|i| (x[i] - y[i]).abs())
            .fold(0.0, f64::max);
        (d, grid.map(|i| x[i].abs()).fold(0.0, f64::max))
    };
    let names = ["structure.centre_deflection", "structure.momentum.z"];
    let mut last = [f64::INFINITY; 2];
    for window in [9e-4, 4.5e-4, 2.25e-4] {
        let explicit = run(scenario::SchemeName::Explicit, window);
        let implicit = run(scenario::SchemeName::Implicit, window);
        for (k, name) in names.iter().enumerate() {
            let (d, scale) = apart(&explicit, &implicit, name);
            assert!(
                d < 2e-3 * scale,
                "{name} at {window:e} s: {d:.3e} of {scale:.3e}"
            );
            // First order: halved with the window (measured 1.8–2.0 times less).
            assert!(
                d < 0.6 * last[k],
                "{name}: {d:.3e} at {window:e} s against {:.3e} at twice the window",
                last[k]
            );
            last[k] = d;
        }
    }
}
