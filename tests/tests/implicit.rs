//! Implicit coupling through the coupler (issue 22): the added-mass case
//! of `scenarios/sheet-closed.toml`, a closed sheet a hundred times lighter
//! than the air column it pushes, which explicit coupling cannot run.

use canopy_tests::*;
use scenario::implicit::{AccelerationName, OnMax};

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

/// The same with only the fluid's pressure accelerated, under the serial
/// scheme: the fluid first writes it at window 0's end, so that window's
/// first try has nothing to be measured against. It is taken again and
/// measured (a first try once counted as converged and the window went
/// explicitly, without a word), and the sheet rises with the inflow as
/// above, within 0.5 %.
#[test]
fn a_field_first_written_at_a_windows_end_is_measured_before_it_converges() {
    let dir = scratch("sheet-closed-pressure");
    let scenario = variant("sheet-closed", &dir, |s| {
        s.run.end_time = 0.3;
        s.coupling.implicit = Some(scenario::ImplicitSection {
            accelerate: Some(vec!["canopy.pressure".into()]),
            ..Default::default()
        });
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let tries = m.header.iter().find(|h| h.ends_with("implicit.tries"));
    let tries = m.column(tries.expect("a tries monitor"));
    assert!(tries[1] >= 2.0, "window 0 took {} tries", tries[1]);
    let speed = m.column("structure.momentum.z").last().unwrap() / AREAL_DENSITY;
    eprintln!(
        "window 0: {} tries; the sheet rises at {speed} m/s",
        tries[1]
    );
    assert!(
        (speed / UPDRAFT - 1.0).abs() < 5e-3,
        "the sheet rises at {speed} m/s against {UPDRAFT} m/s"
    );
    // Allowed one try, window 0 cannot be measured, and the run says so.
    let once = variant("sheet-closed", &dir, |s| {
        s.coupling.implicit = Some(scenario::ImplicitSection {
            accelerate: Some(vec!["canopy.pressure".into()]),
            max_iterations: 1,
            ..Default::default()
        });
    });
    let msg = run_failed(&once, &dir.join("once"));
    assert!(
        msg.contains("window 0 did not converge")
            && msg.contains("`canopy.pressure` of `fluid`: not measured"),
        "{msg}"
    );
}

/// Mean and largest tries per window of scene `name` over `end` seconds
/// with `acceleration` at ω = `relaxation` and at most `max_iterations`
/// tries, going on where a window does not converge; `edit` changes the
/// scene further.
fn tries(
    name: &str,
    end: f64,
    (acceleration, relaxation, max_iterations): (AccelerationName, f64, u32),
    edit: impl FnOnce(&mut Scenario),
) -> (f64, f64) {
    let dir = scratch(&format!("{name}-{acceleration:?}"));
    let scenario = variant(name, &dir, |s| {
        edit(s);
        s.run.end_time = end;
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
    let windows = m["implicit"]["windows"].as_f64().unwrap();
    let iterations = std::fs::read_to_string(out.join("iterations.csv")).unwrap();
    assert_eq!(
        iterations.lines().count() as f64,
        windows + 1.0,
        "a row per window"
    );
    (mean, largest)
}

/// The guide's table of tries per window (docs/src/implicit.md) on the
/// added-mass case over 0.3 s: constant relaxation at ω = 0.01 does not converge within 20
/// tries; Aitken takes 6.5 on average, IQN-ILS 3.2 (measured), fewer than
/// Aitken as the issue asks (preCICE's perpendicular flap: 3–4 with
/// IQN-ILS). Every run carries the sheet at the inflow's speed.
#[test]
fn iqn_ils_needs_fewer_tries_than_aitken_on_the_added_mass_case() {
    let tries = |acceleration, relaxation, max_iterations| {
        let how = (acceleration, relaxation, max_iterations);
        tries("sheet-closed", 0.3, how, |_| {})
    };
    let constant = tries(AccelerationName::Constant, 0.01, 20);
    assert_eq!(constant, (20.0, 20.0), "constant ω = 0.01");
    let aitken = tries(AccelerationName::Aitken, 0.1, 50);
    let iqn = tries(AccelerationName::IqnIls, 0.1, 50);
    assert!((aitken.0 - 6.5).abs() < 0.5, "Aitken: {aitken:?}");
    assert!((iqn.0 - 3.2).abs() < 0.3, "IQN-ILS: {iqn:?}");
    assert!(iqn.0 < aitken.0 && iqn.1 <= aitken.1);
}

/// `scenarios/canopy-closed.toml` on a coarser box of 0.25 m cells, for
/// the tests' time.
fn coarse_closed_canopy(s: &mut Scenario) {
    let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
    b.cells = [12, 12, 16];
}

/// The closed annulus canopy: explicit coupling diverges within a few
/// windows (measured: t = 0.015 s).
#[test]
fn explicit_coupling_diverges_on_the_closed_canopy() {
    let dir = scratch("canopy-closed-explicit");
    let scenario = variant("canopy-closed", &dir, |s| {
        coarse_closed_canopy(s);
        s.coupling.scheme = scenario::SchemeName::Explicit;
        s.coupling.implicit = None;
        s.run.end_time = 0.1;
    });
    let msg = run_failed(&scenario, &dir.join("run"));
    assert!(msg.contains("diverged"), "{msg}");
}

/// Implicit coupling runs the closed canopy to rest: every window
/// converges (the scene stops at 50 tries), in 6.2 tries on average
/// (measured; largest 11), and the canopy's swings die away. Measured
/// over 4 s: the largest kinetic energy in each half second falls from
/// 1.3 % of its peak (0.35 J) at 2–2.5 s to 0.14 % at 3.5–4 s, and the
/// centre's deflection in the last half second stays within 7 % of its
/// mean, 0.40 m.
#[test]
fn the_closed_canopy_comes_to_rest_under_implicit_coupling() {
    let dir = scratch("canopy-closed");
    let scenario = variant("canopy-closed", &dir, |s| {
        coarse_closed_canopy(s);
        s.run.output_interval = 1.0;
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let tries = &manifest(&out)["implicit"];
    let mean = tries["mean_iterations"].as_f64().unwrap();
    assert!(mean < 8.0, "{tries}");
    let m = Monitors::read(&out);
    let (t, energy) = (m.column("time"), m.column("structure.kinetic_energy"));
    let deflection = m.column("structure.centre_deflection");
    let peak = energy.iter().copied().fold(0.0, f64::max);
    // Each half second's largest kinetic energy, from 1.5 s on.
    let halves: Vec<f64> = (3..8)
        .map(|k| {
            let within = |i: &usize| t[*i] > 0.5 * k as f64 && t[*i] <= 0.5 * (k + 1) as f64;
            (0..t.len())
                .filter(within)
                .map(|i| energy[i])
                .fold(0.0, f64::max)
        })
        .collect();
    assert!(halves.windows(2).all(|w| w[1] < w[0]), "{halves:?}");
    assert!(
        halves[4] < 3e-3 * peak,
        "{halves:?} against a peak of {peak}"
    );
    let last: Vec<f64> = (0..t.len())
        .filter(|&i| t[i] > 3.5)
        .map(|i| deflection[i])
        .collect();
    let mean_deflection = last.iter().sum::<f64>() / last.len() as f64;
    let range = last.iter().copied().fold(f64::MIN, f64::max)
        - last.iter().copied().fold(f64::MAX, f64::min);
    assert!(
        range < 0.1 * mean_deflection,
        "{range} about {mean_deflection}"
    );
}

/// The guide's table row (docs/src/implicit.md) for the closed canopy
/// over 0.5 s: constant relaxation at ω = 0.1 converges in no window within 20 tries, Aitken
/// takes 22.5 on average and reaches 50 in some windows, IQN-ILS 7.4 with
/// 11 at most (measured).
#[test]
fn iqn_ils_needs_fewer_tries_than_aitken_on_the_closed_canopy() {
    let tries = |acceleration, max_iterations| {
        let how = (acceleration, 0.1, max_iterations);
        tries("canopy-closed", 0.5, how, coarse_closed_canopy)
    };
    let constant = tries(AccelerationName::Constant, 20);
    assert_eq!(constant, (20.0, 20.0), "constant ω = 0.1");
    let aitken = tries(AccelerationName::Aitken, 50);
    let iqn = tries(AccelerationName::IqnIls, 50);
    assert!((aitken.0 - 22.5).abs() < 2.0, "Aitken: {aitken:?}");
    assert!((iqn.0 - 7.4).abs() < 0.5, "IQN-ILS: {iqn:?}");
    assert!(iqn.0 < aitken.0 && iqn.1 < aitken.1);
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

/// A window of many tries may take far longer than `[coupling] timeout`
/// while every try answers in time (the C-9 at FronTier++'s resolution: 40
/// tries of 1.5 s): the coupler, which hears no monitor row until the
/// window goes on, must not take the run for hung. Here one window of the
/// closed sheet is taken 1500 times (about 6 ms each, 9 s in all) under a
/// timeout of 1.5 s, which the coupler would enforce after 3.5 s of
/// silence.
#[test]
fn a_window_of_many_tries_longer_than_the_timeout_is_not_taken_for_a_hung_run() {
    let dir = scratch("sheet-closed-long-window");
    let scenario = variant("sheet-closed", &dir, |s| {
        s.run.end_time = s.coupling.window;
        s.coupling.timeout = 1.5;
        s.coupling.implicit = Some(scenario::ImplicitSection {
            min_iterations: 1500,
            max_iterations: 1500,
            ..Default::default()
        });
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let tries = manifest(&out)["implicit"]["largest_iterations"].as_f64();
    assert_eq!(tries, Some(1500.0));
    std::fs::remove_dir_all(&dir).unwrap();
}
