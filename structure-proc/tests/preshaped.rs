//! The pre-shaped start (issue 23, item 2): a parachute laid on a spherical
//! cap instead of flat. Built from `scenarios/c9-drop.toml` with
//! `preshaped_diameter` set, its geometry is checked against the mapping's
//! exact relations: the skirt at the asked projected diameter, every point
//! on the sphere, the gore seams at their flat (rest) length, the lines
//! reaching the confluence at their rest length, and the fabric's mass the
//! flat canopy's.

mod common;

use common::{c9_drop, distance, point};
use structure_proc::{build_model, Model};
use structure_section::ParachuteModel;

/// Length of line `l` end to end (skirt to confluence) and its rest length.
fn line_reach(m: &Model, l: usize) -> (f64, f64) {
    let springs = &m.lines[l].springs;
    let (first, last) = (&m.springs[springs[0]], &m.springs[*springs.last().unwrap()]);
    let rest: f64 = springs.iter().map(|&s| m.springs[s].rest).sum();
    (distance(point(m, first.i), point(m, last.j)), rest)
}

#[test]
fn a_preshaped_c9_sits_on_its_sphere_with_seams_and_lines_at_rest_length() {
    let flat = build_model(&c9_drop(|_| {}), None, 1e-4).unwrap();
    let g = ParachuteModel::C9.geometry().unwrap();
    let projected = 0.7 * g.diameter;
    let s = c9_drop(|p| p.preshaped_diameter = Some(projected));
    let m = build_model(&s, None, 1e-4).unwrap();
    let radius = g.dome_radius(projected).unwrap();
    let height = s.parachute.as_ref().unwrap().height;
    // The apex (centre node) at `height`, every canopy node on the sphere.
    assert!((point(&m, 0)[2] - height).abs() < 1e-12);
    for n in 0..m.canopy_nodes {
        let p = point(&m, n);
        let centre = [0.0, 0.0, height - radius];
        assert!((distance(p, centre) - radius).abs() < 1e-9, "node {n}");
    }
    // The designer's monitor reads the asked projected diameter.
    let read = |m: &Model, name: &str| {
        let all = m.parachute_monitors(None).unwrap();
        all.iter().find(|x| x.name.ends_with(name)).unwrap().value
    };
    let d = read(&m, "projected_diameter");
    assert!((d / projected - 1.0).abs() < 1e-9, "{d} m");
    // Seams (and every radial edge) keep their rest length; the same
    // springs, rest lengths and masses as the flat build.
    assert_eq!(m.springs.len(), flat.springs.len());
    assert_eq!(m.mass, flat.mass);
    let mut hoop_shorter = 0;
    for (a, b) in m.springs.iter().zip(&flat.springs) {
        assert_eq!(a.rest.to_bits(), b.rest.to_bits());
        let now = distance(point(&m, a.i), point(&m, a.j));
        assert!(now <= a.rest * (1.0 + 1e-12), "no spring starts stretched");
        hoop_shorter += (now < a.rest * (1.0 - 1e-6)) as usize;
    }
    assert!(hoop_shorter > 0, "the hoops are gathered");
    // All 28 lines equally long: each reaches its rest length exactly.
    for l in 0..m.lines.len() {
        let (reach, rest) = line_reach(&m, l);
        assert!(
            (reach / rest - 1.0).abs() < 1e-12,
            "line {l}: {reach} of {rest} m"
        );
    }
}

#[test]
fn a_preshaped_cross_has_its_tightest_line_just_taut() {
    let s = c9_drop(|p| {
        p.model = ParachuteModel::T11;
        p.preshaped_diameter = Some(0.75 * ParachuteModel::T11.geometry().unwrap().diameter);
    });
    let m = build_model(&s, None, 1e-4).unwrap();
    let ratios: Vec<f64> = (0..m.lines.len())
        .map(|l| {
            let (reach, rest) = line_reach(&m, l);
            reach / rest
        })
        .collect();
    let tightest = ratios.iter().cloned().fold(0.0, f64::max);
    assert!((tightest - 1.0).abs() < 1e-12, "{ratios:?}");
}
