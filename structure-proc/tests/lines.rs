//! Uneven and breaking suspension lines (dissertation §4.2.3) on the C-9 of
//! `scenarios/c9-drop.toml`: 10 of 28 lines 0.3 m shorter than 7 m, and lines
//! that break at a time or above a tension.

use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, Model};
use structure_section::Scene;
use structure_section::{LineBreak, LineChange};

fn c9() -> structure_section::StructureSection {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/c9-drop.toml");
    Scene::load_file(std::path::Path::new(path), "structure-proc")
        .unwrap()
        .structure
}

fn line_rest(m: &Model, line: usize) -> f64 {
    m.lines[line]
        .springs
        .iter()
        .map(|&s| m.springs[s].rest)
        .sum()
}

#[test]
fn ten_of_28_lines_are_0_3_m_shorter() {
    let mut s = c9();
    let p = s.parachute.as_mut().unwrap();
    p.line_changes.push(LineChange {
        lines: (0..10).collect(),
        rest_length_change: -0.3,
    });
    let m = build_model(&s, None, 1e-4).unwrap();
    for line in 0..28 {
        let expect = if line < 10 { 6.7 } else { 7.0 };
        assert!(
            (line_rest(&m, line) - expect).abs() < 1e-12,
            "line {line}: {} m",
            line_rest(&m, line)
        );
    }
    // The skirt is where the lines start: on the canopy's rim, 28 seams apart.
    let radius = 0.5 * 28.0 * 0.3048;
    for line in &m.lines {
        let top = m.springs[line.springs[0]].i;
        let r = m.x[3 * top].hypot(m.x[3 * top + 1]);
        assert!((r - radius).abs() < 1e-9, "line starts at r = {r} m");
    }
}

/// Step the C-9 (structure only: gravity, no air) until `t_end`.
fn fall(s: &structure_section::StructureSection, t_end: f64) -> Model {
    let dt = 1e-4;
    let mut m = build_model(s, None, dt).unwrap();
    let mut stepper = integrator(s.scheme());
    let mut time = 0.0;
    while time < t_end - 0.5 * dt {
        m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
        time += dt;
        m.break_lines(time);
    }
    m
}

#[test]
fn lines_break_at_their_time() {
    let mut s = c9();
    s.parachute.as_mut().unwrap().line_breaks.push(LineBreak {
        lines: (0..10).collect(),
        time: Some(0.05),
        tension: None,
    });
    let m = fall(&s, 0.04);
    assert!(
        m.lines.iter().all(|l| !l.broken),
        "nothing breaks before t = 0.05 s"
    );
    let m = fall(&s, 0.06);
    let broken: Vec<usize> = (0..28).filter(|&l| m.lines[l].broken).collect();
    assert_eq!(broken, (0..10).collect::<Vec<_>>());
    assert_eq!(
        m.springs[m.lines[3].springs[0]].k, 0.0,
        "a broken line carries no force"
    );
}

#[test]
fn lines_break_above_their_tension() {
    // Under gravity alone everything falls together; hold the canopy (a wind
    // tunnel's mount) so the 100 kg payload hangs on the lines: 981 N over 28
    // lines at cos θ = √(1 − (4.27/7)²), about 44 N each.
    let mut s = c9();
    s.parachute.as_mut().unwrap().line_breaks.push(LineBreak {
        lines: vec![5],
        time: None,
        tension: Some(20.0),
    });
    s.parachute.as_mut().unwrap().line_breaks.push(LineBreak {
        lines: vec![6],
        time: None,
        tension: Some(1e5),
    });
    let dt = 1e-4;
    let mut m = build_model(&s, None, dt).unwrap();
    for n in 0..m.canopy_nodes {
        m.kind[n] = structure_proc::NodeKind::Fixed;
    }
    m.prepare();
    let mut stepper = integrator(s.scheme());
    let mut time = 0.0;
    for _ in 0..3000 {
        m.step(stepper.as_mut(), &Loads::default(), dt).unwrap();
        time += dt;
        m.break_lines(time);
    }
    assert!(
        m.lines[5].broken,
        "a 20 N line breaks under a 100 kg payload"
    );
    assert!(!m.lines[6].broken, "a 100 kN line holds");
}
