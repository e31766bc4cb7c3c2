//! A body in the flow: steady 2-D flow past a fixed cylinder at Re = 20,
//! the benchmark "2D-1" of Schäfer & Turek, "Benchmark computations of
//! laminar flow around a cylinder", Notes Numer. Fluid Mech. 52, 547–566
//! (1996). A channel 2.2 m long and H = 0.41 m high between no-slip walls,
//! a cylinder of diameter D = 0.1 m centred at (0.2, 0.2) (slightly below
//! the middle, so it has a small lift), the parabolic inflow
//! U(y) = 4·0.3·y(H − y)/H² (mean Ū = 0.2 m/s), an outflow at p = 0, ρ = 1,
//! ν = 10⁻³: Re = ŪD/ν = 20. Their reference values, bounds from the
//! finest solutions of the benchmark's groups:
//!   c_D = 2F_x/(ρŪ²D) ∈ [5.57, 5.59],  c_L = 2F_y/(ρŪ²D) ∈ [0.0104, 0.0110],
//!   Δp = p(front) − p(back) ∈ [0.1172, 0.1176] Pa.
//! (John, Int. J. Numer. Meth. Fluids 44, 777–788, 2004, refined them to
//! c_D = 5.5795, c_L = 0.010619, Δp = 0.11752.)

use exchange::Shape;
use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::immersed::{place_markers, ImmersedBody, RETRACTION};
use fluid_proc::incompressible::pressure_force::{pressure_load, surface_pressure};
use fluid_proc::incompressible::side::{bcs, parabola, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible};
use fluid_proc::surface::Surface;
use nalgebra::Isometry3;

const LENGTH: f64 = 2.2;
const HEIGHT: f64 = 0.41;
const DIAMETER: f64 = 0.1;
const CENTRE: [f64; 2] = [0.2, 0.2];
const PEAK: f64 = 0.3;
const MEAN: f64 = 2.0 * PEAK / 3.0;
const NU: f64 = 1e-3;
/// Schäfer & Turek's c_D, the middle of their bounds [5.57, 5.59].
const DRAG: f64 = 5.58;
/// Their Δp = p(front) − p(back), John's (2004) refined value [Pa].
const PRESSURE_DROP: f64 = 0.11752;

struct Measured {
    drag: f64,
    /// Δp = p(front) − p(back) on the cylinder [Pa].
    dp: f64,
    /// The pressure's share of c_D, eq. (2.40).
    pressure_drag: f64,
    /// The largest change of c_D over the last half second.
    drift: f64,
}

/// The flow on `nx` × `ny` cells, run for `time` seconds from the
/// channel's own Poiseuille flow.
fn cylinder(nx: usize, ny: usize, time: f64) -> Measured {
    let h = [LENGTH / nx as f64, HEIGHT / ny as f64];
    let thickness = h[0];
    let sides = [
        [Side::Parabolic([PEAK, 0.0, 0.0]), Side::Outflow],
        [Side::WALL; 2],
        [Side::Periodic; 2],
    ];
    let mut flow = Incompressible::new(FlowSetup {
        grid: Grid::uniform([nx, ny, 1], [h[0], h[1], thickness], bcs(&sides)),
        sides,
        density: 1.0,
        nu: NU,
    });
    for j in 0..ny {
        let u = PEAK * parabola((j as f64 + 0.5) / ny as f64);
        flow.u.u[0][(nx + 1) * j..(nx + 1) * (j + 1)].fill(u);
    }
    flow.impose_sides();
    let shape = Shape::cylinder(DIAMETER / 2.0, 1.0);
    let surface = Surface::of(&shape, h[0]);
    let pose = Isometry3::translation(CENTRE[0], CENTRE[1], 0.0);
    let (markers, volume) = place_markers(&surface, &pose, flow.grid(), [0.0; 3]);
    let mut body = ImmersedBody::default();
    body.place(
        markers,
        [CENTRE[0], CENTRE[1], 0.0],
        [0.0; 3],
        [0.0; 3],
        volume,
    );
    flow.bodies.push(body);
    // Courant number 0.4 at twice the peak speed, the potential flow's
    // speed beside the cylinder in the first steps.
    let dt = 0.4 * h[0] / (2.0 * PEAK);
    let steps = (time / dt).round() as usize;
    let per_half_second = (0.5 / dt).round() as usize;
    // c_D = 2F_x/(ρŪ²D), F_x per unit depth.
    let coefficient = 2.0 / (MEAN * MEAN * DIAMETER * thickness);
    let mut history = Vec::new();
    for _ in 0..steps {
        flow.step(dt).unwrap();
        history.push(flow.bodies[0].take_load(1.0).0[0] * coefficient);
    }
    let drag = history[steps - 1];
    let p = flow.pressure();
    let g = flow.grid().clone();
    let spacing = h[0].min(h[1]);
    let z = 0.5 * thickness;
    let r = DIAMETER / 2.0;
    let front = surface_pressure(
        &g,
        &p,
        [CENTRE[0] - r, CENTRE[1], z],
        [-1.0, 0.0, 0.0],
        spacing,
    );
    let back = surface_pressure(
        &g,
        &p,
        [CENTRE[0] + r, CENTRE[1], z],
        [1.0, 0.0, 0.0],
        spacing,
    );
    let b = &flow.bodies[0];
    let (fp, _) = pressure_load(&g, &p, &b.markers, b.centre, spacing, RETRACTION * spacing);

    let drift = history[steps - per_half_second..]
        .iter()
        .fold(0.0f64, |m, c| m.max((c - drag).abs()));
    Measured {
        drag,
        dp: front - back,
        pressure_drag: fp[0] * coefficient,
        drift,
    }
}

/// c_D within 5 % of Schäfer & Turek's on 352 × 64 cells (15.6 across the
/// cylinder), steady to 0.1 % over the last half second. Measured: 5.652,
/// 1.3 % above (5.9 % above with the markers on the surface rather than
/// retracted; see `immersed::RETRACTION`). The surface pressure read on
/// the fluid's side (`pressure_force.rs`) gives their Δp within 5 %
/// (measured 0.11632, 1.0 % below), and the pressure force of eq. (2.40)
/// is part of the drag, the friction the rest (measured 3.45 of 5.65).
#[test]
fn drag_of_a_cylinder_at_re_20_matches_schafer_turek() {
    let m = cylinder(352, 64, 4.0);
    eprintln!(
        "c_D = {:.4} (pressure {:.4}), Δp = {:.5}, drifting {:.1e}",
        m.drag, m.pressure_drag, m.dp, m.drift
    );
    assert!(m.drift < 1e-3 * DRAG, "not steady: c_D drifts {}", m.drift);
    assert!((m.drag / DRAG - 1.0).abs() < 0.05, "c_D = {}", m.drag);
    assert!((m.dp / PRESSURE_DROP - 1.0).abs() < 0.05, "Δp = {}", m.dp);
    assert!(
        m.pressure_drag > 0.0 && m.pressure_drag < m.drag,
        "pressure drag {} of {}",
        m.pressure_drag,
        m.drag
    );
}
