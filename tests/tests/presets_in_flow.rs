//! The T-10, G-11, T-11 and Intruder in the flow (issue 23, item 3): each
//! shipped scene on a coarser grid (6 to 7 cells across the inflated
//! canopy against 10 to 15 shipped; the same window and structure) starts
//! pre-shaped at about its descent speed, is held (0.5 s; the G-11, 2 s)
//! and falls free to t = 4 s in a box that follows it. Over its last
//! second each must
//! - stay inflated: D_p/D₀ within 10 % of the handbook's range (Knacke,
//!   *Parachute Recovery Systems Design Manual*, 1992, table 5-1: flat
//!   circular 0.67–0.70, cross 0.66–0.72);
//! - obey Newton's second law upright, as a whole: weight less the air's
//!   upward force on the canopy equals the total mass times the payload's
//!   downward acceleration, within 3 % of the weight (the canopy breathes
//!   and swings about the payload, which carries 95 % of the mass);
//! - descend at the speed the handbook's C_D0 gives, v = √(2W/ρS₀C_D0)
//!   (flat circular 0.75–0.80, cross 0.60–0.85), within 25 %. That bound
//!   catches a canopy that does not hold its load (collapsed, streaming)
//!   or a drag gone wrong; it validates nothing finer. At about ten cells
//!   across a canopy the drag is not converged (the C-9 descends 10 %
//!   slower at 8.5 cells than at 17), and a canopy's wake takes several
//!   diameters of fall to build (the table of
//!   docs/src/parachutes-in-flow.md gives each scene's numbers on its
//!   shipped grid). The C-9's C_D0 is validated on fine
//!   grids in tests/tests/c9_in_flow.rs.
//!
//! CI runs the T-11 (the cross) and the Intruder (a flat circular canopy,
//! the smallest): the four together took 18 minutes of CI's 90. The T-10
//! and the G-11, the same checks on the flat circular family, are in the
//! validation tier, ignored in CI: `cargo test --release -p canopy-tests
//! --test presets_in_flow -- --ignored` runs them (about 8 minutes).

use canopy_tests::*;

/// The handbook's bands for one canopy type.
struct Handbook {
    drag_coefficient: (f64, f64),
    inflated_ratio: (f64, f64),
}

const FLAT: Handbook = Handbook {
    drag_coefficient: (0.75, 0.80),
    inflated_ratio: (0.67, 0.70),
};
const CROSS: Handbook = Handbook {
    drag_coefficient: (0.60, 0.85),
    inflated_ratio: (0.66, 0.72),
};

/// The coarse runs end here [s]; the checks cover their last second.
const END: f64 = 4.0;

/// Run `name` coarsened to `cells` (the window kept: the air rushing past
/// the filling canopy sets it), and check its last second against `book`.
fn descends_as_the_handbook_says(name: &str, cells: [u32; 3], book: &Handbook) {
    let dir = scratch(name);
    let mut shipped = None;
    let path = variant(name, &dir, |s| {
        shipped = Some(s.clone());
        s.run.end_time = END;
        s.run.output_interval = END;
        s.fluid.as_mut().unwrap().flow_box.as_mut().unwrap().cells = cells;
    });
    let out = dir.join("run");
    run_ok(&path, &out);
    let m = Monitors::read(&out);
    let s = shipped.unwrap();
    let structure = s.structure.as_ref().unwrap();
    let p = s.parachute();
    let g = p.geometry();
    let rho = s.fluid.as_ref().unwrap().density();
    let mass = falling_mass(p, p.payload_mass.unwrap());
    let weight = -mass * structure.gravity[2];
    let from = END - 1.0;
    let monitor = |n: &str| format!("structure.parachute.{n}");
    let ratio = m.mean_over(&monitor("projected_diameter"), from, END) / g.diameter;
    let (lo, hi) = book.inflated_ratio;
    assert!(
        (0.9 * lo..=1.1 * hi).contains(&ratio),
        "{name}: D_p/D₀ = {ratio}"
    );
    let up = m.mean_over(&monitor("air_force_up"), from, END);
    let speed = |t: f64| m.at(&monitor("descent_speed"), t);
    let accelerating = mass * (speed(END) - speed(from));
    assert!(
        (weight - up - accelerating).abs() < 0.03 * weight,
        "{name}: weight {weight} N, the air's upward force {up} N, m·a {accelerating} N"
    );
    let v = |cd: f64| (2.0 * weight / (rho * g.nominal_area() * cd)).sqrt();
    let (slow, fast) = (v(book.drag_coefficient.1), v(book.drag_coefficient.0));
    let descent = m.mean_over(&monitor("descent_speed"), from, END);
    assert!(
        (0.75 * slow..=1.25 * fast).contains(&descent),
        "{name}: {descent} m/s against the handbook's {slow}–{fast} m/s"
    );
}

#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn t10_descends_as_the_handbook_says() {
    descends_as_the_handbook_says("t10-descent", [20, 20, 42], &FLAT);
}

#[test]
#[ignore = "validation tier, too long for CI: run with --ignored"]
fn g11_descends_as_the_handbook_says() {
    descends_as_the_handbook_says("g11-descent", [16, 16, 36], &FLAT);
}

#[test]
fn t11_descends_as_the_handbook_says() {
    descends_as_the_handbook_says("t11-descent", [20, 20, 42], &CROSS);
}

#[test]
fn intruder_descends_as_the_handbook_says() {
    descends_as_the_handbook_says("intruder-descent", [20, 20, 42], &FLAT);
}
