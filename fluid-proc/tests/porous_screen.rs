//! The canopy in the flow, on an exact solution: a porous screen across a
//! stream. A 2-D box, uniform inflow U at x = 0, outflow at p = 0 at x = 2 m,
//! periodic in y; a fabric sheet at rest spanning the box at x = 1 m. With
//! no variation along y, continuity keeps u = U everywhere, so the exact
//! steady flow is the uniform stream, and the pressure drops across the
//! sheet by the Darcy–Forchheimer law at the stream's speed,
//! Δp = e(A·v_f + B·v_f²) with v_f = ε·U (thesis eqs. 6–9), and is
//! uniform on either side. The jump read through the index coating
//! (dissertation §3.3.2) must give it.

use fluid_proc::incompressible::canopy::{porous_law, sheet_markers};
use fluid_proc::incompressible::coating::Coating;
use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::immersed::ImmersedBody;
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible};
use porous::Porous;

const SPEED: f64 = 1.0;
const PLACE: f64 = 1.0;

/// What a screen run leaves: the jump per triangle [Pa], and the largest
/// difference of a face velocity from the uniform stream [m/s].
struct Screen {
    jumps: Vec<f64>,
    off_stream: f64,
}

/// The screen after `steps`, porous with `law` (closed with None), in a
/// stream of SPEED along x and `along` [m/s] along y, the sheet's plane.
/// The sheet's vertices move at `sheet` [m/s] along x (held in place: only
/// the velocity relative to the air matters to the law, eq. 10).
fn screen(law: Option<[f64; 2]>, sheet: f64, along: f64, steps: usize) -> Screen {
    let (nx, ny) = (64, 32);
    let h = 1.0 / ny as f64;
    let sides = [
        [Side::Velocity([SPEED, along, 0.0]), Side::Outflow],
        [Side::Periodic; 2],
        [Side::Periodic; 2],
    ];
    let mut flow = Incompressible::new(FlowSetup {
        grid: Grid::uniform([nx, ny, 1], [h; 3], bcs(&sides)),
        sides,
        density: 1.2,
        nu: 1.5e-5,
    });
    flow.u.u[0].fill(SPEED);
    flow.u.u[1].fill(along);
    flow.impose_sides();
    // The sheet: two triangles over the box's y–z section, normal +x.
    let x = [
        PLACE, 0.0, 0.0, PLACE, 1.0, 0.0, PLACE, 1.0, h, PLACE, 0.0, h,
    ];
    let v: Vec<f64> = (0..12)
        .map(|i| if i % 3 == 0 { sheet } else { 0.0 })
        .collect();
    let triangles = [[0, 1, 2], [0, 2, 3]];
    let (markers, velocities) = sheet_markers(&x, &v, &triangles, h);
    let mut fabric = ImmersedBody::default();
    fabric.place_sheet(markers, velocities);
    fabric.porous = law;
    flow.canopy = Some(fabric);
    let dt = 0.3 * h / SPEED;
    for _ in 0..steps {
        flow.step(dt).unwrap();
    }
    let coating = Coating::new(flow.grid(), &x, &triangles);
    let mut jumps = vec![0.0; 2];
    coating.jumps(flow.grid(), &flow.pressure(), &x, &triangles, &mut jumps);
    let off = |u: &[f64], v: f64| u.iter().map(|u| (u - v).abs()).fold(0.0, f64::max);
    Screen {
        jumps,
        off_stream: off(&flow.u.u[0], SPEED).max(off(&flow.u.u[1], along)),
    }
}

/// Darcy–Forchheimer coefficients for ε = 0.5, grain 2 mm, fabric 0.1 mm
/// thick in air (ρ = 1.2 kg/m³, μ = 1.8·10⁻⁵ Pa·s): about 0.5 Pa at 1 m/s.
fn fabric() -> Porous {
    Porous::new(&porous::Params {
        free_stream: [0.0; 3],
        density: 1.2,
        viscosity: 1.8e-5,
        porosity: 0.5,
        diameter: 2e-3,
        thickness: 1e-4,
    })
}

/// The jump equals the law's at the stream's speed to 10⁻⁸ (measured
/// 10⁻¹³).
#[test]
fn a_porous_screen_drops_the_darcy_forchheimer_pressure() {
    let fabric = fabric();
    let exact = fabric.jump(fabric.porosity * SPEED);
    for j in screen(Some(porous_law(&fabric)), 0.0, 0.0, 400).jumps {
        assert!((j / exact - 1.0).abs() < 1e-8, "jump {j} against {exact}");
    }
}

/// A fabric moving with the stream along its normal at 0.4 U feels only the
/// 0.6 U through it (thesis eq. 10: the air's velocity relative to the
/// fabric).
#[test]
fn the_screen_feels_the_air_relative_to_it() {
    let fabric = fabric();
    let exact = fabric.jump(fabric.porosity * 0.6 * SPEED);
    for j in screen(Some(porous_law(&fabric)), 0.4 * SPEED, 0.0, 400).jumps {
        assert!((j / exact - 1.0).abs() < 1e-8, "jump {j} against {exact}");
    }
}

/// The fabric's load is the pressure jump, a normal force, so the air gets
/// only a normal force back and slips along the fabric (Newton's third
/// law; dissertation eq. 3.27 spreads a normal force too). A stream crossing
/// the screen obliquely, half as fast along it as through it, is then
/// still the exact steady flow: it stays uniform to 10⁻⁹ m/s, and the drop
/// is still the law's at the normal speed, closed or porous.
#[test]
fn the_air_slips_along_the_fabric() {
    let along = 0.5 * SPEED;
    let fabric = fabric();
    let porous = screen(Some(porous_law(&fabric)), 0.0, along, 200);
    let exact = fabric.jump(fabric.porosity * SPEED);
    assert!(
        porous.off_stream < 1e-9,
        "porous: {} m/s off",
        porous.off_stream
    );
    for j in porous.jumps {
        assert!((j / exact - 1.0).abs() < 1e-8, "jump {j} against {exact}");
    }
    // A closed fabric moving with the stream across it: nothing to push.
    let closed = screen(None, SPEED, along, 200);
    assert!(
        closed.off_stream < 1e-9,
        "closed: {} m/s off",
        closed.off_stream
    );
    for j in closed.jumps {
        assert!(
            j.abs() < 1e-9,
            "jump {j} Pa across a closed sheet in step with the air"
        );
    }
}
