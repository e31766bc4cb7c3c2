//! The lid-driven cavity at Re = 100 against Ghia, Ghia & Shin, J. Comput.
//! Phys. 48, 387–411 (1982), Tables I and II: u along the vertical centre
//! line and v along the horizontal one, at their tabulated points.

use coupler::scenario::flow::SideSpec;
use fluid_proc::incompressible::Incompressible;
use fluid_proc::setup::flow_from;

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

/// Botella & Peyret, Comput. Fluids 27, 421–433 (1998): the extrema at
/// Re = 100 of their Chebyshev spectral solution, converged to all digits
/// shown: u_min on x = ½, v_max and v_min on y = ½.
const CONVERGED: [f64; 3] = [-0.2140424, 0.1795728, -0.2538030];

/// Component d (0: u on x = ½, 1: v on y = ½) along its centre line, as
/// (position, value) from side to side: the side velocities at 0 and 1,
/// the faces on the line at the cell centres between.
fn centre_line(flow: &Incompressible, d: usize, lid: f64) -> Vec<(f64, f64)> {
    let n = flow.grid().n[0];
    let h = 1.0 / n as f64;
    let mut m = [n, n];
    m[d] += 1;
    let mut line = vec![(0.0, 0.0)];
    for k in 0..n {
        let mut f = [0; 2];
        f[d] = n / 2;
        f[1 - d] = k;
        line.push(((k as f64 + 0.5) * h, flow.u.u[d][f[0] + m[0] * f[1]]));
    }
    // The top side moves (u = lid); the right side is a wall.
    line.push((1.0, if d == 0 { lid } else { 0.0 }));
    line
}

/// The line's value at `s`, linear between its points.
fn at(line: &[(f64, f64)], s: f64) -> f64 {
    let k = line.partition_point(|p| p.0 <= s).clamp(1, line.len() - 1);
    let ((a, fa), (b, fb)) = (line[k - 1], line[k]);
    fa + (fb - fa) * (s - a) / (b - a)
}

/// The line's extremum (the minimum for `sign` = −1), from the parabola
/// through the extreme point and its neighbours (points equally spaced).
fn extremum(line: &[(f64, f64)], sign: f64) -> f64 {
    let k = (2..line.len() - 2)
        .max_by(|&a, &b| (sign * line[a].1).total_cmp(&(sign * line[b].1)))
        .unwrap();
    let (a, b, c) = (line[k - 1].1, line[k].1, line[k + 1].1);
    let curvature = a - 2.0 * b + c;
    b - 0.125 * (c - a) * (c - a) / curvature
}

#[test]
fn the_cavity_at_re_100_matches_ghia_and_the_converged_extrema() {
    // The shipped scene, run to its end (t = 15 s, steady to a few 1e-5
    // m/s²) by the library without the coupler.
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/cavity.toml");
    let scenario = coupler::Scenario::load(std::path::Path::new(path)).expect("shipped scenario");
    let section = scenario.fluid.as_ref().expect("[fluid]");
    let lid = match section.resolved_sides().unwrap()[1][1] {
        SideSpec::Velocity(v) => v[0],
        s => panic!("the lid is {s:?}"),
    };
    let mut flow = flow_from(section).expect("a flow box");
    for w in 0..scenario.windows() {
        flow.step(scenario.window_span(w).1).unwrap();
    }
    let u = centre_line(&flow, 0, lid);
    let v = centre_line(&flow, 1, lid);
    // Every tabulated point of Ghia et al. within 2 % of the lid speed. The
    // largest difference is about 0.009 (v at x = 0.8594): Ghia's values are
    // those of a 129² grid, and their extrema lie 1.3–3.2 % inside the
    // converged ones (icoFoam, converged on 128², is as far from them).
    for (line, table, name) in [(&u, &GHIA_U, "u"), (&v, &GHIA_V, "v")] {
        for &(s, ghia) in table {
            let ours = at(line, s);
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
