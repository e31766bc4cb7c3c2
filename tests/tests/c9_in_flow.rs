//! Parachutes in the flow (issue 23): the C-9 of dissertation §4.2.1
//! inflating and descending in a box that follows it, against the
//! handbooks' numbers for flat circular canopies (Knacke, *Parachute
//! Recovery Systems Design Manual*, 1992, table 5-1; Ewing, Bixby & Knacke,
//! *Recovery System Design Guide*, 1978): C_D0 = 0.75–0.80 on the nominal
//! area, inflated (projected) diameter D_p/D₀ = 0.67–0.70.
//!
//! The shipped scenes' own runs (the C-9's descent and C_D0, its closed
//! twin's harder shock, the finer grid) are the validation tier: about 30
//! minutes together, more than CI can give them, so they are ignored there
//! and run with `cargo test --release -p canopy-tests --test c9_in_flow --
//! --ignored` (docs/src/commands.md). CI runs the coarse variants
//! below (1 m cells).

use std::path::Path;

use canopy_tests::*;

/// The C-9's nominal diameter [m].
const C9_DIAMETER: f64 = 8.534;

/// `scenarios/c9-inflation.toml` as shipped, run once for every test here
/// that reads it: its output directory.
fn shipped_c9() -> &'static Path {
    shipped_run("c9-inflation")
}

#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn the_c9_inflates_and_descends_steadily_at_its_handbook_drag_coefficient() {
    // Released flat at 6 m/s, held 1 s, steady over its last 2 s (from
    // t = 3 s).
    let out = shipped_c9();
    let summary = &manifest(out)["parachute"];
    let number = |key: &str| summary[key].as_f64().unwrap_or(f64::NAN);
    let (cd, spread) = (number("drag_coefficient"), number("descent_speed_spread"));
    assert!((0.75..=0.80).contains(&cd), "C_D0 = {cd}: {summary}");
    // Steady: over the last 2 s the descent speed varies by less than the
    // opening swings it (6 → 5.4 → 6 m/s, over 10 %). How much less
    // depends on round-off: the canopy's slow breathing after 3 s is
    // sensitive to it, and the same scene has measured a spread of 1.8 %
    // and, with IQN-ILS solved from its Gram matrix instead of a QR
    // decomposition (issue 43), 5.1 % (6.08 m/s, the speed rising from
    // 5.97 to 6.27 m/s over the last second as C_D falls from 0.80 to
    // 0.73, the tilt under 0.6°). Asserted under 8 %.
    assert!(spread < 0.08, "{summary}");
    // Steady, the air carries the weight (Newton's second law, the mean
    // acceleration nil): C_D0 on the descent times ½ρS₀w̄² is the air's
    // mean force up, which must be the parachute's weight, payload 100 kg,
    // fabric 57.2 m² at 0.05 kg/m², lines 28 × 7 m at 5 g/m (measured
    // 1024.9 N against 1018.3 N, 0.6 %; C_D0 0.816 on the descent, 0.787 on
    // the path, gliding 7.1°). Asserted within 2 %.
    let s0 = 0.25 * std::f64::consts::PI * C9_DIAMETER * C9_DIAMETER;
    let w = number("descent_speed");
    let up = number("descent_drag_coefficient") * 0.5 * fluid_section::AIR_DENSITY * s0 * w * w;
    let mass = 100.0 + s0 * 0.05 + 28.0 * 7.0 * 0.005;
    let weight = mass * rigid_section::STANDARD_GRAVITY;
    assert!((up / weight - 1.0).abs() < 0.02, "{up} N up: {summary}");
    // Inflated: the projected diameter within 5 % of the handbook's range.
    let ratio = number("projected_diameter") / C9_DIAMETER;
    assert!(
        (0.67 * 0.95..=0.70 * 1.05).contains(&ratio),
        "D_p/D₀ = {ratio}: {summary}"
    );
    // The canopy opened: it narrowed below its steady diameter and came back.
    let opening = number("opening_time");
    assert!(opening > 0.0 && opening < 3.0, "{summary}");
    // The opening shock: the lines pulled the payload harder than its
    // weight while the canopy filled, as they do (Knacke ch. 6).
    let weight = 100.0 * 9.81;
    assert!(number("peak_opening_force") > 2.0 * weight, "{summary}");
    // The box followed: the canopy fell 27 m and stayed in it.
    let m = Monitors::read(out);
    let fallen = m.column("fluid.frame_altitude");
    assert!(*fallen.last().unwrap() < -25.0, "{:?}", fallen.last());
}

/// A finer fluid grid (h = 0.33 m, 26 cells across the canopy) changes the
/// shipped C-9's steady descent speed by under 5 % (measured 2.3 %: 5.94
/// against 6.08 m/s, 1.6 % against 6.04 before issue 43's IQN-ILS change;
/// it settles later, so its last 2 s spread 4 %). The fine run alone takes
/// 7.5 minutes on a quiet machine, 19 beside the other tests.
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn a_finer_grid_moves_the_c9s_descent_by_under_5_percent() {
    let dir = scratch("c9-inflation-fine");
    let fine = variant("c9-inflation", &dir, |s| {
        let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
        b.cells = [48, 48, 108];
        s.run.output_interval = 1.0;
    });
    let fine_out = dir.join("run");
    run_ok(&fine, &fine_out);
    let speed = |out: &Path| {
        manifest(out)["parachute"]["descent_speed"]
            .as_f64()
            .unwrap()
    };
    let (fine_speed, speed) = (speed(&fine_out), speed(shipped_c9()));
    assert!(
        (fine_speed / speed - 1.0).abs() < 0.05,
        "{fine_speed} against {speed} m/s"
    );
}

/// A coarse variant (h = 1 m) of a §4.2.3 scene, to `end` [s], changed by
/// `change`; its monitors.
fn coarse(name: &str, run: &str, end: f64, change: impl FnOnce(&mut Scenario)) -> Monitors {
    let dir = scratch(&format!("{name}-{run}"));
    let path = variant(name, &dir, |s| {
        s.run.end_time = end;
        s.run.output_interval = end;
        s.coupling.window = 0.02;
        s.structure_mut().substeps = 200;
        s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap().cells = [12, 12, 24];
        change(s);
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    Monitors::read(&out)
}

/// Dissertation §4.2.3: ten suspension lines 0.3 m short "lead to an angled
/// deployment". On the coarse grid the even C-9 flies within 5° of level
/// until about 4 s (measured 2.7° on average over 2–4 s), the uneven one
/// tilted (measured 22–24°); ten lines breaking at 5 s tilt a canopy that
/// flew level (34° over 5.5–6.5 s), and it falls faster on the lines that
/// are left (8.0 m/s against 5.0 m/s over the second before the break;
/// the even canopy, run on, keeps 4.9 m/s over 5.5–6.5 s). Until the break
/// c9-broken-lines is the even canopy bit for bit (measured on these runs;
/// `line_breaks.rs` asserts it of a break not yet due on the C-9 drop), so
/// its first 5 s stand for the even one.
#[test]
fn uneven_and_broken_lines_tilt_the_c9() {
    let tilt = "structure.parachute.tilt";
    let uneven = coarse("c9-uneven-lines", "uneven", 4.0, |_| {});
    let broken = coarse("c9-broken-lines", "broken", 6.5, |_| {});
    let (level, angled) = (
        broken.mean_over(tilt, 2.0, 4.0),
        uneven.mean_over(tilt, 2.0, 4.0),
    );
    assert!(
        level < 5.0 && angled > 15.0,
        "tilt {level}° even, {angled}° uneven"
    );
    let after = broken.mean_over(tilt, 5.5, 6.5);
    let speed = "structure.parachute.descent_speed";
    let (slow, fast) = (
        broken.mean_over(speed, 4.0, 5.0),
        broken.mean_over(speed, 5.5, 6.5),
    );
    assert!(after > 15.0, "tilt {after}° after the break");
    assert!(
        fast > 1.2 * slow,
        "{fast} m/s on 18 lines, {slow} m/s on 28 before the break"
    );
}

/// Dissertation §4.2.2: `scenarios/c9-wake.toml`, the C-9 on a finite
/// rigid parachutist in the flow, all three processes running, against the
/// same scene with the body's shape removed (a mass point of rigid-proc,
/// outside the flow), on 1 m cells to t = 4 s. The body moving down
/// through the air feels it push up, and Newton's second law holds for
/// the whole parachute, both ways: weight less the air's force on canopy and body
/// equals the total mass times the payload's acceleration, within 3 % of
/// the weight, over the last second. The body is under one cell across,
/// so the descent-speed difference is the under-resolved wake's (the
/// guide gives it on the shipped grid, docs/src/parachutes-in-flow.md);
/// it is printed, not asserted.
#[test]
fn the_parachutists_body_in_the_flow_feels_the_air_and_the_whole_obeys_newton() {
    let (end, from) = (4.0, 3.0);
    let wake = |run: &str, change: fn(&mut Scenario)| {
        let dir = scratch(&format!("c9-wake-{run}"));
        let path = variant("c9-wake", &dir, |s| {
            s.run.end_time = end;
            s.run.output_interval = end;
            // 1 m cells, 2 m more below: the immersed body keeps three
            // cells of air under it.
            let b = s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap();
            b.lower[2] -= 2.0;
            b.cells = [16, 16, 38];
            change(s);
        });
        let out = dir.join("run");
        run_ok(&path, &out);
        Monitors::read(&out)
    };
    let finite = wake("finite", |_| {});
    let point = wake("point", |s| {
        s.rigid.as_mut().unwrap().bodies[0].shape = None
    });
    let scenario = canopy_tests::Scenario::load(&scenario_path("c9-wake")).unwrap();
    let p = scenario.parachute();
    let body_mass = scenario.rigid.as_ref().unwrap().bodies[0].mass.unwrap();
    let mass = falling_mass(p, body_mass);
    let weight = -mass * scenario.rigid.as_ref().unwrap().gravity[2];
    let lift = finite.mean_over("fluid.jumper_fluid_force_z", 1.0, end);
    assert!(lift > 0.0, "the air pushes the falling body up: {lift} N");
    // Weight less the air's upward force (on the canopy, and on the body
    // where it is in the flow) against the mass times the acceleration.
    let newton = |m: &Monitors, body_in_flow: bool| {
        let mut air = m.mean_over("structure.parachute.air_force_up", from, end);
        if body_in_flow {
            air += m.mean_over("fluid.jumper_fluid_force_z", from, end);
        }
        let speed = |t: f64| -m.at("rigid.jumper.vz", t);
        let accelerating = mass * (speed(end) - speed(from));
        assert!(
            (weight - air - accelerating).abs() < 0.03 * weight,
            "body in the flow {body_in_flow}: weight {weight} N, air {air} N, m·a {accelerating} N"
        );
    };
    newton(&finite, true);
    newton(&point, false);
    let descent = |m: &Monitors| m.mean_over("structure.parachute.descent_speed", from, end);
    eprintln!(
        "descent over {from}–{end} s: finite body {} m/s, mass point {} m/s",
        descent(&finite),
        descent(&point)
    );
}

/// Issue 23, item 5: closed fabric at the porous canopy's areal density
/// (50 g/m²) and modulus runs at its scene's settings
/// (`scenarios/c9-closed.toml`), and, letting no air through, it opens
/// with a harder shock than the porous canopy of `c9-inflation.toml`
/// (Knacke 1992, ch. 6: opening forces fall as porosity rises). Both on
/// the shipped grid over the first 1.5 s, past the opening (the porous
/// one's from the shipped run the other tests read): measured 9.9 kN
/// closed against 6.0 kN porous; asserted 1.3 times, and both above twice
/// the payload's weight.
#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn a_closed_c9_opens_with_a_harder_shock_than_the_porous_one() {
    let end = 1.5;
    let peak = |out: &Path| {
        let m = Monitors::read(out);
        let opening = m.column("time").iter().filter(|&&t| t <= end).count();
        let pull = m.column("structure.parachute.payload_force");
        pull[..opening].iter().cloned().fold(0.0, f64::max)
    };
    let dir = scratch("c9-closed-opening");
    let path = variant("c9-closed", &dir, |s| {
        s.run.end_time = end;
        s.run.output_interval = end;
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    let (closed, porous) = (peak(&out), peak(shipped_c9()));
    let weight = 100.0 * 9.81;
    assert!(
        porous > 2.0 * weight && closed > 1.3 * porous,
        "peak pull on the payload: closed {closed} N, porous {porous} N"
    );
}
