//! A window repeated from its checkpoint gives the flow it gave the first
//! time, bit for bit (issue 22: implicit coupling repeats each window from
//! its checkpoint until the interface converges, so the repeat must not
//! drift). The flow: a 2-D channel with a stream, a moving cylinder and a
//! porous canopy sheet in it, taken a few steps in so that every piece of
//! history is live (Adams–Bashforth's Nⁿ and last Δt, the pressure and
//! viscous solvers' first guesses, the bodies' recorded forcing).

use exchange::Shape;
use fluid_proc::incompressible::canopy::{porous_law, sheet_markers};
use fluid_proc::incompressible::checkpoint::{Checkpoint, History};
use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::immersed::{place_markers, ImmersedBody};
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible, StepReport};
use fluid_proc::surface::Surface;
use nalgebra::Isometry3;

const SPEED: f64 = 1.0;
const H: f64 = 1.0 / 24.0;

/// Air (ρ = 1.2 kg/m³, μ = 1.8·10⁻⁵ Pa·s) through a fabric of porosity 0.5,
/// grain 2 mm, 0.1 mm thick: the porous screen's fabric.
fn fabric() -> [f64; 2] {
    porous_law(&porous::Porous::new(&porous::Params {
        free_stream: [0.0; 3],
        density: 1.2,
        viscosity: 1.8e-5,
        porosity: 0.5,
        diameter: 2e-3,
        thickness: 1e-4,
    }))
}

fn channel() -> Incompressible {
    let (nx, ny) = (48, 24);
    let sides = [
        [Side::Velocity([SPEED, 0.0, 0.0]), Side::Outflow],
        [Side::Velocity([0.0; 3]); 2],
        [Side::Periodic; 2],
    ];
    let mut flow = Incompressible::new(FlowSetup {
        grid: Grid::uniform([nx, ny, 1], [H; 3], bcs(&sides)),
        sides,
        density: 1.2,
        nu: 1e-3,
    });
    flow.u.u[0].fill(SPEED);
    flow.impose_sides();
    flow.canopy = Some(sheet(0.2));
    flow
}

/// A sheet across the lower half of the channel at x = 1.4 m, moving
/// downstream at `speed` [m/s].
fn sheet(speed: f64) -> ImmersedBody {
    let x = [1.4, 0.1, 0.0, 1.4, 0.6, 0.0, 1.4, 0.6, H, 1.4, 0.1, H];
    let v: Vec<f64> = (0..12)
        .map(|i| if i % 3 == 0 { speed } else { 0.0 })
        .collect();
    let (markers, velocities) = sheet_markers(&x, &v, &[[0, 1, 2], [0, 2, 3]], H);
    let mut s = ImmersedBody::default();
    s.place_sheet(markers, velocities);
    s.porous = Some(fabric());
    s
}

/// A cylinder of radius 0.15 m at (0.6, 0.5 + y) m moving at `v` across
/// the stream, placed as fluid-proc places a body each window.
fn place_cylinder(flow: &mut Incompressible, y: f64, v: f64) {
    let shape = Shape::cylinder(0.15, 1.0);
    let surface = Surface::of(&shape, H);
    let centre = [0.6, 0.5 + y, 0.0];
    let pose = Isometry3::translation(centre[0], centre[1], 0.0);
    let (markers, volume) = place_markers(&surface, &pose, flow.grid(), [0.0; 3]);
    if flow.bodies.is_empty() {
        flow.bodies.push(ImmersedBody::default());
    }
    flow.bodies[0].place(markers, centre, [0.0, v, 0.0], [0.0; 3], volume);
}

/// One try of a window as fluid-proc takes it: the cylinder placed from
/// the window's inputs and the canopy where the try puts it (moving at
/// `speed` [m/s]), then three steps of unequal length, the first the
/// window's; returns the fields' bits, the body's load, and the first
/// step's report (whether it took the window's kept prediction, its
/// pressure iterations).
fn window(flow: &mut Incompressible, speed: f64) -> (Vec<u64>, [f64; 3], StepReport) {
    place_cylinder(flow, 0.02, 0.3);
    flow.canopy = Some(sheet(speed));
    let dt = 0.15 * H / SPEED;
    let first = flow.step_in_window(dt, true).unwrap();
    for s in [0.8, 1.1] {
        flow.step_in_window(s * dt, false).unwrap();
    }
    let bits = flow
        .u
        .u
        .iter()
        .flatten()
        .chain(&flow.q)
        .map(|v| v.to_bits());
    (bits.collect(), flow.bodies[0].take_load(1.2).0, first)
}

/// The largest difference of two windows' fields (`window`'s bits) over
/// the largest value of the first.
fn relative_difference(a: &[u64], b: &[u64]) -> f64 {
    let values = |v: &[u64]| v.iter().map(|&x| f64::from_bits(x)).collect::<Vec<_>>();
    let (a, b) = (values(a), values(b));
    let most = a.iter().fold(0.0f64, |m, x| m.max(x.abs()));
    let diff = a
        .iter()
        .zip(&b)
        .fold(0.0f64, |d, (x, y)| d.max((x - y).abs()));
    diff / most
}

/// The channel a few steps in, and its checkpoint there.
fn started() -> (Incompressible, Checkpoint) {
    let mut flow = channel();
    place_cylinder(&mut flow, 0.0, 0.0);
    for _ in 0..4 {
        flow.step(0.15 * H / SPEED).unwrap();
    }
    let mut start = Checkpoint::default();
    flow.save(&mut start);
    (flow, start)
}

/// The repeat is bit-identical; a repeat that starts from the warm starts
/// and step history of the window's end instead of its start is not (so
/// the checkpoint's history is what makes it identical).
#[test]
fn a_window_repeated_from_its_checkpoint_gives_the_same_flow_bit_for_bit() {
    let (mut flow, start) = started();
    let first = window(&mut flow, 0.25);
    let mut end = History::default();
    flow.save_history(&mut end);
    for _ in 0..2 {
        flow.restore(&start);
        let again = window(&mut flow, 0.25);
        assert!(first.0 == again.0, "the repeated window's fields differ");
        assert_eq!(
            first.1.map(f64::to_bits),
            again.1.map(f64::to_bits),
            "the body's load differs"
        );
    }
    flow.restore(&start);
    flow.restore_history(&end);
    let stale = window(&mut flow, 0.25);
    assert!(first.0 != stale.0, "the history made no difference");
}

/// A window's later tries take the prediction (advection, viscous solves)
/// its first try computed, and the last try's pressure correction as their
/// solve's first guess (`prediction.rs`), though the canopy moves
/// differently in each try. The first try gives the bits a flow computing
/// afresh gives; the later ones the same flow to the pressure solve's
/// tolerance (its residual 10⁻⁸ of ‖b‖; measured 2–4·10⁻¹⁰ of the largest
/// value, asserted under 10⁻⁷) in fewer iterations (measured 4 against 7). A try from another state (one face
/// velocity changed by one ulp) computes its prediction again and starts
/// its solve from the window's guess: the bits of a fresh flow.
#[test]
fn later_tries_take_the_first_prediction_and_the_last_correction() {
    let ((mut kept, start), (mut fresh, fresh_start)) = (started(), started());
    kept.keep_predictions();
    for (k, speed) in [0.25, 0.3, 0.28].into_iter().enumerate() {
        kept.restore(&start);
        fresh.restore(&fresh_start);
        let (a, _, taken) = window(&mut kept, speed);
        let (b, _, computed) = window(&mut fresh, speed);
        assert_eq!(taken.kept_prediction, k > 0, "try {k}: {taken:?}");
        let difference = relative_difference(&a, &b);
        let (fewer, than) = (taken.pressure_iterations, computed.pressure_iterations);
        match k {
            0 => assert!(a == b, "try 0: the fields differ from a fresh flow's"),
            _ => assert!(
                difference < 1e-7 && fewer < than,
                "try {k}: {difference:e} from a fresh flow's, {fewer} pressure iterations against {than}"
            ),
        }
    }
    kept.restore(&start);
    fresh.restore(&fresh_start);
    for flow in [&mut kept, &mut fresh] {
        let u = &mut flow.u.u[0][100];
        *u = f64::from_bits(u.to_bits() + 1);
    }
    let (a, _, taken) = window(&mut kept, 0.25);
    let (b, _, _) = window(&mut fresh, 0.25);
    assert!(
        !taken.kept_prediction,
        "a try from another state took the kept prediction"
    );
    assert!(
        a == b,
        "the nudged try's fields differ from a fresh prediction's"
    );
}
