//! The designer's two drag coefficients of a gliding parachute (issue 45:
//! the run's C_D0 read below W/(½ρv²S₀) on the finer grids, where the
//! canopy glides). A flat C-9 from `scenarios/c9-drop.toml` under a uniform
//! pressure jump p carries the force p·A straight up (A its flat area),
//! while it moves down at w and across at u: the flight path is γ =
//! atan(u/w) from the vertical. Then exactly (a steady glide's balance,
//! Knacke 1992, ch. 5): the drag against the motion is p·A·cos γ; C_D0 on
//! the path is p·A·cos γ / (½ρ(w² + u²)S₀); C_D0 on the descent is
//! p·A / (½ρw²S₀); the first is the second times cos³γ.

mod common;

use structure_proc::opening::Record;
use structure_proc::{build_model, Model};

const RHO: f64 = 1.225;

fn flat_c9() -> Model {
    let mut m = build_model(&common::c9_drop(|_| {}), None, 1e-4).unwrap();
    m.parachute.as_mut().unwrap().air_density = Some(RHO);
    m
}

/// Σ area·n_z over the canopy's triangles: its flat area, signed by the
/// vertex order, so that a jump p pushes it by p times this along +z.
fn signed_area(m: &Model) -> f64 {
    let at = |n: usize| [m.x[3 * n], m.x[3 * n + 1]];
    let twice = |t: &[usize; 3]| {
        let [a, b, c] = t.map(at);
        (b[0] - a[0]) * (c[1] - a[1]) - (b[1] - a[1]) * (c[0] - a[0])
    };
    m.triangles.iter().map(|t| 0.5 * twice(t)).sum()
}

#[test]
fn a_gliding_canopy_reads_cos_cubed_less_drag_on_its_path_than_on_its_descent() {
    let mut m = flat_c9();
    let (w, gamma) = (5.5f64, 20f64.to_radians());
    let u = w * gamma.tan();
    for v in m.v.chunks_exact_mut(3) {
        v.copy_from_slice(&[u, 0.0, -w]);
    }
    let area = signed_area(&m);
    // The jump that carries 1000 N up, whichever way the triangles turn.
    let jump = vec![1000.0 / area; m.triangles.len()];
    let monitors = m.parachute_monitors(Some(&jump)).unwrap();
    let s0 = m.parachute.unwrap().nominal_area;
    let read = |name: &str| {
        let full = format!("parachute.{name}");
        monitors.iter().find(|x| x.name == full).unwrap().value
    };
    assert!((read("air_force_up") / 1000.0 - 1.0).abs() < 1e-12);
    assert!((read("horizontal_speed") / u - 1.0).abs() < 1e-12);
    assert!((read("drag") / (1000.0 * gamma.cos()) - 1.0).abs() < 1e-12);
    let on_descent = 1000.0 / (0.5 * RHO * w * w * s0);
    let on_path = read("drag_coefficient");
    assert!((on_path / (on_descent * gamma.cos().powi(3)) - 1.0).abs() < 1e-12);
    // The run's summary over a steady glide of these rows says both.
    let mut record = Record::new(&m.parachute.unwrap());
    for k in 0..=20 {
        record.add(0.25 * k as f64, &monitors);
    }
    let summary = record.summary().unwrap();
    let value = |key: &str| summary.values.iter().find(|(k, _)| k == key).unwrap().1;
    assert!((value("descent_drag_coefficient") / on_descent - 1.0).abs() < 1e-12);
    assert!((value("drag_coefficient") / on_path - 1.0).abs() < 1e-12);
    assert!((value("glide_angle") - 20.0).abs() < 1e-9);
    assert!(summary.line.contains("gliding 20.0°"), "{}", summary.line);
}
