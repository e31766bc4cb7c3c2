//! The structure's collision scenes (dissertation §4.3.2–4.3.3), run with
//! the coupler: a circular cloth falling on a bundle of strings meets them,
//! they meet each other, and the cloth's halves meet below them — in that
//! order, as the dissertation describes — without a crossing in any output
//! frame and without the contacts ever raising the energy; two balls in a
//! cloth meet and bounce in it together.

use canopy_tests::*;
use participant::vtu;
use structure_proc::collision::{intersections, Surface};

/// The written states of the run in `out`, from its `<series>_*.vtu` files
/// (`strings` has every node, `canopy` the fabric's).
fn frames(out: &std::path::Path, series: &str) -> Vec<Vec<f64>> {
    let mut paths: Vec<_> = std::fs::read_dir(out.join("vtk"))
        .unwrap()
        .map(|e| e.unwrap().path())
        .filter(|p| {
            p.file_name()
                .unwrap()
                .to_string_lossy()
                .starts_with(&format!("{series}_"))
        })
        .collect();
    paths.sort();
    paths.iter().map(|p| vtu::read_points(p).unwrap()).collect()
}

/// No crossing in any of the more than `least` states of `series` the run
/// of `scenario` in `out` wrote, counted on the scene's own surface.
fn assert_no_crossings(
    scenario: &std::path::Path,
    out: &std::path::Path,
    series: &str,
    least: usize,
) {
    let s = canopy_tests::Scenario::load(scenario).unwrap();
    let model = structure_proc::build_model(s.structure.as_ref().unwrap(), None, 1e-4).unwrap();
    let surface = Surface::of(&model.net);
    let states = frames(out, series);
    assert!(states.len() > least, "only {} frames", states.len());
    for (k, x) in states.iter().enumerate() {
        let found = intersections(&surface, x);
        assert_eq!(found.total(), 0, "{series} frame {k}: {found:?}");
    }
}

#[test]
fn a_cloth_on_strings_meets_them_then_they_meet_then_it_meets_itself_and_nothing_crosses() {
    // scenarios/cloth-strings.toml on a coarser mesh (10 rings, 20 segments
    // a string), to 1.5 s: the three kinds of contact begin at 0.10, 0.32
    // and 1.17 s (on 8 rings the halves only just meet, or do not, as the
    // order of the pass's impulses has it).
    let dir = scratch("cloth-strings");
    let scenario = variant("cloth-strings", &dir, |s| {
        s.run.end_time = 1.5;
        coarse_cloth_strings(s);
    });
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let t = m.column("time");
    let first = |kind: &str| {
        let c = m.column(&format!("structure.contact.{kind}"));
        let k = c.iter().position(|&n| n > 0.0);
        k.map(|k| t[k])
            .unwrap_or_else(|| panic!("no {kind} contact"))
    };
    let (fs, ss, ff) = (
        first("fabric_string"),
        first("string_string"),
        first("fabric_fabric"),
    );
    assert!(
        fs < ss && ss < ff,
        "first contacts: fabric–string {fs} s, string–string {ss} s, fabric–fabric {ff} s"
    );

    // Viscous damping and gravity only: the energy (kinetic + elastic +
    // gravitational) falls at every window; a contact that added energy
    // (a repulsion pushing too hard) would show as a rise.
    let e: Vec<f64> = m
        .column("structure.kinetic_energy")
        .iter()
        .zip(m.column("structure.potential_energy"))
        .map(|(k, p)| k + p)
        .collect();
    for w in 1..e.len() {
        assert!(
            e[w] <= e[w - 1] + 1e-12,
            "t = {}: energy rose by {:e} J",
            t[w],
            e[w] - e[w - 1]
        );
    }

    // No triangle pair, segment through a triangle or segment through a
    // segment in any written state (parry's tests, not the pass's).
    assert_no_crossings(&scenario, &out, "strings", 25);
}

#[test]
fn two_balls_meet_in_the_cloth_and_bounce_in_it_together() {
    // scenarios/ball-cloth.toml as shipped (dissertation §4.3.3, fig. 4.9):
    // the balls (radius 0.08 m), dropped at rest 0.29 m apart, fall into the
    // cloth held along two edges, which rolls them together: they meet (at
    // 0.56 s) and from 2.5 s on stay together (C_R = 0 between them, eq.
    // 3.28), the cloth's bounces parting them by less than 2.5 cm, a third
    // of the radius (17.6 mm at most, at 3.37 s, in the run as committed),
    // and by less than 1 cm over the last half second (7.9 mm), bouncing in
    // the cloth together. The cloth is frictionless: it pushes each ball
    // along its radius, so neither ever spins (10⁻¹³ rad/s; they spun at up
    // to 2 rad/s while the pass took the lever at the facets' points).
    let dir = scratch("ball-cloth");
    let out = dir.join("run");
    let scenario = scenario_path("ball-cloth");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let t = m.column("time");
    let at = |ball: &str, axis: &str| m.column(&format!("rigid.{ball}.{axis}"));
    let (lx, ly, lz) = (at("left", "x"), at("left", "y"), at("left", "z"));
    let (rx, ry, rz) = (at("right", "x"), at("right", "y"), at("right", "z"));
    let gap = |k: usize| {
        ((lx[k] - rx[k]).powi(2) + (ly[k] - ry[k]).powi(2) + (lz[k] - rz[k]).powi(2)).sqrt() - 0.16
    };
    let contacts = m.column("rigid.contact_impulses");
    let first = contacts
        .iter()
        .position(|&c| c > 0.0)
        .expect("the balls meet");
    assert!(
        gap(0) > 0.25 && t[first] < 2.5,
        "they meet at {} s, starting {} m apart",
        t[first],
        gap(0)
    );
    let together: Vec<usize> = (0..t.len()).filter(|&k| t[k] >= 2.5).collect();
    let end = t[t.len() - 1];
    for &k in &together {
        let most = if t[k] >= end - 0.5 { 1e-2 } else { 2.5e-2 };
        assert!(
            gap(k) < most,
            "t = {}: the balls are {} m apart",
            t[k],
            gap(k)
        );
    }
    for ball in ["left", "right"] {
        for axis in ["omegax", "omegay", "omegaz"] {
            let spin = at(ball, axis).iter().fold(0.0_f64, |a, w| a.max(w.abs()));
            assert!(
                spin < 1e-9,
                "the {ball} ball spins at {spin} rad/s ({axis})"
            );
        }
    }
    // Bouncing together: each ball's vertical velocity turns at least twice.
    let vz = at("left", "vz");
    let turns = together
        .windows(2)
        .filter(|w| vz[w[0]].signum() != vz[w[1]].signum())
        .count();
    assert!(
        turns >= 2,
        "the left ball's vertical velocity turned {turns} times"
    );
    // The cloth crosses itself in no written state.
    assert_no_crossings(&scenario, &out, "canopy", 100);
}

#[test]
fn a_layer_thicker_than_the_fabric_s_smallest_altitude_is_warned_of() {
    // cloth-strings' disk of 16 rings has triangles whose smallest altitude
    // is 3.2 cm (the centre's): a 5 cm layer would make neighbouring
    // features repel each other; `coupler check` says so and still accepts
    // the scene, and the shipped 3 mm layer draws no such warning.
    let dir = scratch("thick-layer");
    let thick = variant("cloth-strings", &dir, |s| {
        let st = s.structure.as_mut().unwrap();
        st.collision.as_mut().unwrap().thickness = 0.05;
    });
    let warned = |path: &std::path::Path| {
        let o = coupler(&["check", path.to_str().unwrap()]);
        assert_eq!(o.status.code(), Some(0));
        String::from_utf8_lossy(&o.stderr).contains("is not below the smallest altitude")
    };
    assert!(warned(&thick));
    assert!(!warned(&scenario_path("cloth-strings")));
}
