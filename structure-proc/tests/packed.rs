//! The packed start (issue 46, item 1): a parachute at line stretch, its
//! canopy gathered into a bundle. Built from `scenarios/c9-drop.toml` with
//! `pack_diameter` set, it is checked against what the packing promises:
//! nothing crossing at t = 0 (the collision tests' intersection counter,
//! parry's exact triangle and segment tests), every node inside the pack,
//! the seams straight down the axis at their flat length, the rings'
//! edges at their flat length, the other edges within the stated strain,
//! and every line straight and taut, at its rest length.

mod common;

use common::{c9_drop, distance, point};
use structure_proc::collision::{intersections, Surface};
use structure_proc::parachute::circular_canopy;
use structure_proc::{build_model, Model};
use structure_section::ParachuteModel;

/// The largest strain |l/l₀ − 1| of the canopy's triangle edges, l₀ in
/// the flat pattern `flat` (the fabric's rest state, xyz per node) and l
/// packed.
fn largest_edge_strain(packed: &Model, flat: &[f64]) -> f64 {
    let at = |n: usize| [flat[3 * n], flat[3 * n + 1], flat[3 * n + 2]];
    let mut most = 0.0f64;
    for t in &packed.triangles {
        for (i, j) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
            let rest = distance(at(i), at(j));
            let now = distance(point(packed, i), point(packed, j));
            most = most.max((now / rest - 1.0).abs());
        }
    }
    most
}

/// The strain the packed canopies' edges may start with (largest over
/// their triangles): the ring edges and the seams are exact, the edges
/// across rings stretch where the fold radius changes from ring to ring
/// (1.4 % measured on the C-9, in the fan round its apex).
const STRAIN: f64 = 0.02;

#[test]
fn a_packed_c9_starts_uncrossed_inside_its_pack_with_lines_taut() {
    let g = ParachuteModel::C9.geometry().unwrap();
    let pack = 0.4;
    let pleats = g.pleats(pack).unwrap();
    let s = c9_drop(|p| {
        p.resolution = 16;
        p.pack_diameter = Some(pack);
    });
    let m = build_model(&s, None, 1e-4).unwrap();
    let height = s.parachute.as_ref().unwrap().height;
    // Nothing crosses: triangle pairs, lines through fabric, line pairs.
    let crossings = intersections(&Surface::of(&m.net), &m.x);
    assert_eq!(crossings.total(), 0, "{crossings:?}");
    // Every canopy node inside the pack, the apex at the top, the bundle
    // longer than the canopy's radius less the pack's (the seams cut the
    // corner at the pack's top edge) and shorter than the radius.
    let length = 0.5 * g.diameter - pleats.radius;
    let mut lowest = f64::INFINITY;
    for n in 0..m.canopy_nodes {
        let [x, y, z] = point(&m, n);
        assert!(x.hypot(y) <= pleats.radius * (1.0 + 1e-12), "node {n}");
        assert!(z <= height + 1e-12, "node {n}");
        lowest = lowest.min(z);
    }
    let long = height - lowest;
    assert!(long > length && long < 0.5 * g.diameter, "{long} m long");
    assert!((point(&m, 0)[2] - height).abs() < 1e-12);
    // The lines: each straight (its nodes on the chord from skirt to
    // confluence) and exactly at its rest length.
    for (l, line) in m.lines.iter().enumerate() {
        let first = &m.springs[line.springs[0]];
        let last = &m.springs[*line.springs.last().unwrap()];
        let (top, hub) = (point(&m, first.i), point(&m, last.j));
        let rest: f64 = line.springs.iter().map(|&s| m.springs[s].rest).sum();
        let reach = distance(top, hub);
        assert!(
            (reach / rest - 1.0).abs() < 1e-12,
            "line {l}: {reach} of {rest} m"
        );
        assert!(
            (top[0].hypot(top[1]) - pleats.radius).abs() < 1e-12,
            "line {l}"
        );
        for &s in &line.springs {
            let p = point(&m, m.springs[s].j);
            let off = distance(top, p) + distance(p, hub) - reach;
            assert!(off < 1e-9 * reach, "line {l} bends by {off} m");
        }
    }
    // The fabric starts near its rest state: the pattern the mesh was cut
    // from, every edge within STRAIN of its flat length; the seams' springs
    // (the springs that are not strings) exactly at theirs.
    let flat = circular_canopy(&g, 16, 0.0, Some(&pleats)).unwrap();
    assert_eq!(m.triangles, flat.triangles);
    let strain = largest_edge_strain(&m, &flat.points);
    assert!(strain < STRAIN, "largest edge strain {strain}");
    let seams = m.springs.iter().filter(|s| !s.tension_only);
    assert!(seams.clone().count() > 0, "c9-drop has seam springs");
    for s in seams {
        let now = distance(point(&m, s.i), point(&m, s.j));
        assert!(
            (now / s.rest - 1.0).abs() < 1e-12,
            "seam {}-{}: {now} of {} m",
            s.i,
            s.j,
            s.rest
        );
    }
}

/// The other circular presets, with a vent (T-10, Intruder) and with 120
/// gores (G-11), packed as narrow as their meshes allow a few pleats: no
/// crossing, every edge within STRAIN of its flat length.
#[test]
fn every_circular_preset_packs_uncrossed() {
    for (model, pack) in [
        (ParachuteModel::T10, 0.5),
        (ParachuteModel::Intruder, 0.2),
        (ParachuteModel::G11, 1.2),
    ] {
        let s = c9_drop(|p| {
            p.model = model;
            p.pack_diameter = Some(pack);
        });
        let m = build_model(&s, None, 1e-4).unwrap();
        let g = model.geometry().unwrap();
        let pleats = g.pleats(pack).unwrap();
        let resolution = s.parachute.as_ref().unwrap().resolution as usize;
        let flat = circular_canopy(&g, resolution, 0.0, Some(&pleats)).unwrap();
        let crossings = intersections(&Surface::of(&m.net), &m.x);
        assert_eq!(crossings.total(), 0, "{model:?}: {crossings:?}");
        let strain = largest_edge_strain(&m, &flat.points);
        assert!(strain < STRAIN, "{model:?}: largest edge strain {strain}");
    }
}
