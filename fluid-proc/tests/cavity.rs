//! The lid-driven cavity at Re = 100 (`scenarios/cavity.toml`) against Ghia,
//! Ghia & Shin, J. Comput. Phys. 48, 387–411 (1982), Tables I and II: u
//! along the vertical centre line and v along the horizontal one at their
//! tabulated points; and its extrema against the converged values of
//! Botella & Peyret (1998).

use fluid_proc::incompressible::profile::{
    extremum, face_line, value_at, CAVITY_RE100_EXTREMA as CONVERGED,
};
use fluid_proc::incompressible::setup::flow_from;
use fluid_section::flow::SideSpec;

/// Ghia et al. Table I, Re = 100: (y, u) on x = 0.5.
const GHIA_U: [(f64, f64); 17] = [
    (0.0000, 0.00000),
    (0.0547, -0.03717),
    (0.0625, -0.04192),
    (0.0703, -0.04775),
    (0.1016, -0.06434),
    (0.1719, -0.10150),
    (0.2813, -0.15662),
    (0.4531, -0.21090),
    (0.5000, -0.20581),
    (0.6172, -0.13641),
    (0.7344, 0.00332),
    (0.8516, 0.23151),
    (0.9531, 0.68717),
    (0.9609, 0.73722),
    (0.9688, 0.78871),
    (0.9766, 0.84123),
    (1.0000, 1.00000),
];

/// Ghia et al. Table II, Re = 100: (x, v) on y = 0.5.
const GHIA_V: [(f64, f64); 17] = [
    (0.0000, 0.00000),
    (0.0625, 0.09233),
    (0.0703, 0.10091),
    (0.0781, 0.10890),
    (0.0938, 0.12317),
    (0.1563, 0.16077),
    (0.2266, 0.17507),
    (0.2344, 0.17527),
    (0.5000, 0.05454),
    (0.8047, -0.24533),
    (0.8594, -0.22445),
    (0.9063, -0.16914),
    (0.9453, -0.10313),
    (0.9531, -0.08864),
    (0.9609, -0.07391),
    (0.9688, -0.05906),
    (1.0000, 0.00000),
];

#[test]
fn the_cavity_at_re_100_matches_ghia_and_the_converged_extrema() {
    // The shipped scene, run to its end (t = 15 s, steady to a few 1e-5
    // m/s²) by the library without the coupler.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/cavity.toml");
    let scene = fluid_section::Scene::load_file(std::path::Path::new(path)).expect("shipped scene");
    let section = &scene.fluid;
    let lid = match section.resolved_sides().unwrap()[1][1] {
        SideSpec::Velocity(v) => v[0],
        s => panic!("the lid is {s:?}"),
    };
    let mut flow = flow_from(section).expect("a flow box");
    for w in 0..scene.scenario.windows() {
        flow.step(scene.scenario.window_span(w).1).unwrap();
    }
    // u on the vertical centre line x = ½ (face n/2 along x), v on the
    // horizontal one.
    let n = flow.grid().n[0];
    let u = face_line(&flow, 0, 1, [n / 2, 0, 0]);
    let v = face_line(&flow, 1, 0, [0, n / 2, 0]);
    // Every tabulated point of Ghia et al. within 2 % of the lid speed. The
    // largest difference is about 0.009 (v at x = 0.8594): Ghia's values are
    // those of a 129² grid, and their extrema lie 1.3–3.2 % inside the
    // converged ones (icoFoam, converged on 128², is as far from them).
    for (line, table, name) in [(&u, &GHIA_U, "u"), (&v, &GHIA_V, "v")] {
        for &(s, ghia) in table {
            let ours = value_at(line, s);
            assert!(
                (ours - ghia).abs() <= 0.02 * lid,
                "{name}({s}) = {ours}, Ghia et al. {ghia}"
            );
        }
    }
    // The extrema against the converged values, within 0.5 %.
    let ours = [extremum(&u, -1.0), extremum(&v, 1.0), extremum(&v, -1.0)];
    for (o, c) in ours.iter().zip(CONVERGED) {
        assert!(
            (o / c - 1.0).abs() < 5e-3,
            "extrema {ours:?}, converged {CONVERGED:?}"
        );
    }
}
