//! Openings from line stretch (issue 46): the C-9 of
//! `scenarios/c9-deploy.toml`, packed into a 1 m bundle, its lines taut,
//! its payload held at 40 m/s (Knacke, *Parachute Recovery Systems Design
//! Manual*, 1992, ch. 5: an "infinite-mass" opening).
//!
//! CI runs the first 0.15 s, through the skirt's flutter right after line
//! stretch, reefed with the cutters firing at 0.05 s, and the first 0.1 s
//! of the free payload's opening. The shipped scenes' whole openings,
//! held, free and reefed (about 15, 15 and 12 minutes), are in the
//! validation tier, run with
//! `cargo test --release -p canopy-tests --test deploy -- --ignored`.

use std::path::Path;

use canopy_tests::*;
use structure_section::parachute::Reefing;

/// The C-9's nominal area S₀ [m²] and the air's density [kg/m³].
const S0: f64 = 57.2;
const RHO: f64 = fluid_section::AIR_DENSITY;
/// The speed at line stretch [m/s], the scenes'.
const SPEED: f64 = 40.0;
/// The payload's mass [kg], the scenes'.
const PAYLOAD: f64 = 100.0;
/// The cutters' time in the CI run [s].
const CUT: f64 = 0.05;

/// `scenarios/c9-deploy.toml` as shipped, run once for every test here
/// that reads it: its output directory.
fn held_run() -> &'static Path {
    shipped_run("c9-deploy")
}

#[test]
fn the_packed_c9_comes_through_its_flutter_with_every_window_converged_and_is_disreefed_on_time() {
    let dir = scratch("c9-deploy-start");
    let path = variant("c9-deploy", &dir, |s| {
        s.run.end_time = 0.15;
        s.run.output_interval = 0.15;
        s.parachute_mut().reefing = Some(Reefing {
            ratio: 0.3,
            cut_time: Some(CUT),
        });
    });
    let out = dir.join("run");
    // Every window converges within max_iterations at the shipped 1 ms
    // window: run_ok fails on a window that does not (on_max = "stop").
    run_ok(&path, &out);
    let log = std::fs::read_to_string(out.join("logs/structure.log")).unwrap();
    let cuts: Vec<&str> = log
        .lines()
        .filter(|l| l.contains("reefing line was cut"))
        .collect();
    // One message for the whole line, at the first sub-step past the time
    // (Δt_s = 1 ms / 30).
    assert_eq!(cuts.len(), 1, "{log}");
    let at: f64 = cuts[0]
        .split("t = ")
        .nth(1)
        .and_then(|s| s.split(' ').next())
        .and_then(|s| s.parse().ok())
        .unwrap();
    assert!((CUT..CUT + 1e-3 / 30.0 + 1e-9).contains(&at), "{}", cuts[0]);
    let m = Monitors::read(&out);
    // The mouth has started to open: the skirt's flutter spreads the
    // bundle (1 m at line stretch; at 0.15 s measured 3.09 m unreefed,
    // 1.76 m reefed to the end, whose cord weighs on the skirt).
    let dp = m.column("structure.parachute.projected_diameter");
    assert!(*dp.last().unwrap() > 1.3, "D_p = {:?} m", dp.last());
}

/// `scenarios/c9-deploy-free.toml`'s first 0.1 s, its payload free from
/// line stretch, through the lines' snatch and the skirt's flutter: the
/// payload's loss of momentum is the lines' impulse less its weight's
/// (Newton's second law; the monitors hold every 1 ms window, the impulse
/// their trapezoid sum). Measured 70.1 against 70.0 N·s, 0.2 %; asserted
/// within 2 %, as over the whole opening. A payload the release left held
/// would lose nothing.
#[test]
fn the_free_payload_loses_the_momentum_the_lines_take_from_it() {
    let dir = scratch("c9-deploy-free-start");
    let path = variant("c9-deploy-free", &dir, |s| {
        s.run.end_time = 0.1;
        s.run.output_interval = 0.1;
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    let m = Monitors::read(&out);
    let (lost, pushed) = payload_momentum(&m, 0.1);
    assert!(lost > 20.0, "the payload lost {lost} N·s");
    assert!(
        (lost / pushed - 1.0).abs() < 0.02,
        "{lost} against {pushed} N·s"
    );
}

/// The 100 kg payload's loss of momentum from line stretch to `until` [s],
/// and the lines' impulse on it less its weight's over that time [N·s].
fn payload_momentum(m: &Monitors, until: f64) -> (f64, f64) {
    let (t, pull, v) = (
        m.column("time"),
        m.column("structure.parachute.payload_force"),
        m.column("structure.parachute.descent_speed"),
    );
    let end = t.iter().rposition(|&t| t <= until + 1e-9).unwrap();
    let impulse: f64 = (0..end)
        .map(|k| 0.5 * (pull[k] + pull[k + 1]) * (t[k + 1] - t[k]))
        .sum();
    let lost = PAYLOAD * (v[0] - v[end]);
    (
        lost,
        impulse - PAYLOAD * rigid_section::STANDARD_GRAVITY * t[end],
    )
}

/// The shipped scene's whole opening, against Newton and what this
/// grid gives (docs/src/parachutes-in-flow.md, "Opening from line
/// stretch"). Knacke's table 5-1 gives n ≈ 8 and C_x ≈ 1.7 for flat
/// circular canopies; on these 0.5 m cells the canopy opens about four
/// times sooner (n 2.0) and with no overshoot (C_x 1.03), because the
/// pleated bundle, two cells across, lets the air straight through it.
/// The numbers are pinned here as measured, so that a change that moves
/// them toward (or away from) the handbook's is seen.
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn the_c9_opens_from_line_stretch_at_40_m_s_as_this_grid_gives() {
    let out = held_run();
    let summary = &manifest(out)["parachute"];
    let number = |key: &str| summary[key].as_f64().unwrap_or(f64::NAN);
    // Held at 40 m/s, steady over its last half second, the lines pull the
    // payload with the air's drag on the canopy (Newton's second law: the
    // canopy and lines, 3.8 kg, do not accelerate on average; their weight
    // is 0.1 % of the pull). Measured 2.7 % (the canopy still breathes, its
    // D_p easing from 6.9 to 6.3 m); asserted within 5 %.
    let m = Monitors::read(out);
    let (t, pull, drag) = (
        m.column("time"),
        m.column("structure.parachute.payload_force"),
        m.column("structure.parachute.drag"),
    );
    let steady: Vec<usize> = (0..t.len())
        .filter(|&k| t[k] >= number("steady_from"))
        .collect();
    let mean = |c: &[f64]| steady.iter().map(|&k| c[k]).sum::<f64>() / steady.len() as f64;
    let (pull, drag) = (mean(&pull), mean(&drag));
    assert!((pull / drag - 1.0).abs() < 0.05, "{pull} against {drag} N");
    // Open, its drag is the handbook's: C_D0 0.75–0.80 (Knacke, table
    // 5-1), widened by the 5 % the grid moves it (measured 0.81).
    let cd = number("drag_coefficient");
    assert!((0.75..=0.84).contains(&cd), "C_D0 = {cd}: {summary}");
    // The opening, as measured on this grid: n = 2.0, C_x = 1.03.
    let (n, cx) = (
        number("filling_constant"),
        number("opening_force_coefficient"),
    );
    assert!((n / 2.0 - 1.0).abs() < 0.25, "n = {n}: {summary}");
    assert!((cx / 1.03 - 1.0).abs() < 0.15, "C_x = {cx}: {summary}");
    assert_eq!(number("start_speed"), SPEED, "{summary}");
}

/// `scenarios/c9-deploy-free.toml`: the same opening with the 100 kg
/// payload free from line stretch (Knacke 1992, ch. 5, a finite-mass
/// opening). The payload's loss of momentum is the lines' impulse less
/// its weight's (Newton's second law, over the opening to 0.75 s: measured
/// 0.8 %, the lines' pull a little off the vertical; asserted within 2 %);
/// the peak, 11.6 kN at 0.53 s and 20.8 m/s, is a quarter of the held
/// opening's, and within 30 % of the handbook's mass-ratio method (Pflanz's
/// linear drag-area growth over the held run's filling time: X₁ = 0.21,
/// 9.6 kN; measured 21 % above it). The agreement is in the force only:
/// the method puts the peak at t_f/√(3B) = 0.16 s and 30 m/s, the run at
/// 0.53 s and 20.8 m/s, its drag area growing from near nothing only after
/// 0.25 s. The peak and its speed are pinned as measured within 15 %.
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn the_c9_free_at_line_stretch_slows_its_payload_and_peaks_as_the_mass_ratio_method_says() {
    let out = shipped_run("c9-deploy-free");
    let (lost, pushed) = payload_momentum(&Monitors::read(out), 0.75);
    assert!(
        (lost / pushed - 1.0).abs() < 0.02,
        "{lost} against {pushed} N·s"
    );
    let summary = &manifest(out)["parachute"];
    let number = |key: &str| summary[key].as_f64().unwrap_or(f64::NAN);
    let (peak, speed) = (number("peak_opening_force"), number("speed_at_peak"));
    assert!((peak / 11.6e3 - 1.0).abs() < 0.15, "{summary}");
    assert!((speed / 20.8 - 1.0).abs() < 0.15, "{summary}");
    // Pflanz (Knacke 1992, ch. 5): with the drag area growing linearly to
    // (C_DS)₀ over t_f, B = ρ·v_s·(C_DS)₀·t_f/(4m); the force peaks at
    // t/t_f = 1/√(3B) when that is under 1, at X₁ = 9/(16√(3B)) of the
    // infinite-mass (C_DS)₀·q_s.
    let held = &manifest(held_run())["parachute"];
    let (tf, cd) = (
        held["filling_time"].as_f64().unwrap(),
        held["drag_coefficient"].as_f64().unwrap(),
    );
    let mass = PAYLOAD + S0 * 0.05 + 28.0 * 7.0 * 0.005;
    let b = RHO * SPEED * cd * S0 * tf / (4.0 * mass);
    assert!(3.0 * b > 1.0, "B = {b}");
    let pflanz = 9.0 / (16.0 * (3.0 * b).sqrt()) * 0.5 * RHO * SPEED * SPEED * cd * S0;
    assert!(
        (peak / pflanz - 1.0).abs() < 0.3,
        "{peak} against {pflanz} N"
    );
    assert!(
        peak < 0.5 * held["peak_opening_force"].as_f64().unwrap(),
        "{held}"
    );
}

/// The largest pull of the lines on the payload in a run's monitors over
/// the times (from, to] [N].
fn largest_pull(m: &Monitors, from: f64, to: f64) -> f64 {
    let (t, pull) = (
        m.column("time"),
        m.column("structure.parachute.payload_force"),
    );
    (0..t.len())
        .filter(|&k| t[k] > from && t[k] <= to)
        .map(|k| pull[k])
        .fold(0.0, f64::max)
}

/// `scenarios/c9-deploy-reefed.toml`: the held opening reefed at τ = 0.3
/// and cut at 0.5 s (Knacke 1992, ch. 6), against the held unreefed run
/// over the same spans. Reefed, the canopy's drag area settles well under
/// the open one's (measured 0.36), so the reefed stage peaks at a fraction
/// of the unreefed opening's pull by 0.5 s (measured 16.3 against
/// 46.9 kN, 0.35; asserted under half); held at 40 m/s nothing slows, so
/// disreefed it meets the open canopy's drag at the same speed: its
/// largest pull over 0.5–1 s is the unreefed run's (measured 46.5 against
/// 47.9 kN, 3 % under; asserted within 10 %).
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn the_reefed_c9_peaks_low_reefed_and_as_the_unreefed_one_disreefed() {
    let reefed = Monitors::read(shipped_run("c9-deploy-reefed"));
    let held = Monitors::read(held_run());
    let (stage, open) = (
        largest_pull(&reefed, 0.0, 0.5),
        largest_pull(&held, 0.0, 0.5),
    );
    assert!(stage < 0.5 * open, "{stage} against {open} N");
    let (disreefed, open) = (
        largest_pull(&reefed, 0.5, 1.0),
        largest_pull(&held, 0.5, 1.0),
    );
    assert!(
        (disreefed / open - 1.0).abs() < 0.1,
        "{disreefed} against {open} N"
    );
}

/// `scenarios/c9-deploy-reefed.toml` with its payload free from line
/// stretch: the finite-mass case, where reefing is meant to lower the
/// peak (Knacke 1992, ch. 6), against the unreefed free opening
/// (`c9-deploy-free`). Measured on the 0.5 m cells: the reefed stage
/// peaks at 10.6 kN at 0.47 s and 26.7 m/s, the disreefed canopy at
/// 9.7 kN at 0.52 s and 22.3 m/s, against the unreefed free opening's
/// 11.6 kN: the largest pull 9 % lower, and carried by the reefed stage,
/// which on this grid already pulls hard while the payload is still fast
/// (26.7 m/s at its peak, 23.7 m/s at the cut). Both peaks are pinned
/// as measured within 15 %, and the largest under the unreefed one's.
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn the_reefed_c9_on_a_free_payload_peaks_lower_than_unreefed() {
    let dir = scratch("c9-deploy-reefed-free");
    let path = variant("c9-deploy-reefed", &dir, |s| {
        s.parachute_mut().release_time = Some(0.0);
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    let reefed = Monitors::read(&out);
    let (stage, disreefed) = (
        largest_pull(&reefed, 0.0, 0.5),
        largest_pull(&reefed, 0.5, 1.2),
    );
    assert!((stage / 10.6e3 - 1.0).abs() < 0.15, "{stage} N");
    assert!((disreefed / 9.7e3 - 1.0).abs() < 0.15, "{disreefed} N");
    let unreefed = largest_pull(&Monitors::read(shipped_run("c9-deploy-free")), 0.0, 1.5);
    assert!(
        stage.max(disreefed) < unreefed,
        "{stage} and {disreefed} against {unreefed} N"
    );
}
