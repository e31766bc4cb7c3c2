//! Rigid bodies in the incompressible flow through the coupler: rigid-proc
//! sends the poses, fluid-proc holds the fluid to them at the bodies'
//! surfaces (an immersed boundary) and sends back the fluid's load.

use canopy_tests::*;

/// Schäfer & Turek's c_D for their benchmark 2D-1 (Notes Numer. Fluid Mech.
/// 52, 547–566, 1996): 5.57–5.59.
const SCHAFER_TUREK_DRAG: f64 = 5.58;

#[test]
fn the_cylinder_scene_feels_schafer_and_tureks_drag() {
    // `scenarios/cylinder.toml` as shipped, to 2 s: c_D is within 0.2 % of
    // its steady value by then (5.661 against 5.651 at 5 s, measured).
    let dir = scratch("cylinder");
    let scenario = variant("cylinder", &dir, |s| s.run.end_time = 2.0);
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let force = m.column("fluid.cylinder_fluid_force_x");
    // c_D = 2F_x/(ρŪ²D) with F_x over the box's depth of 6.25 mm.
    let drag = force.last().unwrap() / (0.5 * 0.2 * 0.2 * 0.1 * 6.25e-3);
    assert!(
        (drag / SCHAFER_TUREK_DRAG - 1.0).abs() < 0.05,
        "c_D = {drag}"
    );
}

/// A free body in a periodic box of moving fluid, no gravity, nothing else
/// acting: the fluid drags the body along, and momentum passes from one to
/// the other without loss. The fluid inside the body moves with it, so the
/// load on the body is minus what the forcing gave the fluid plus the inner
/// fluid's change of momentum ρ_f·V·ΔU (Uhlmann, J. Comput. Phys. 209,
/// 2005, eq. 29). In the explicit coupling the fluid learns ΔU a window
/// late, so what is conserved after window i is
///   P_fluid(i) + P_body(i) − ρ_f·V·U_body(i − 1),
/// to the area of the section's polygon (within (2π/n)²/6 < 0.2 % of the
/// circle's at the segments the grid asks for).
const MOMENTUM_SCENE: &str = r#"
[run]
name = "drag-along"
end_time = 1.0
output_interval = 1.0

[coupling]
window = 0.01

[participants.fluid]
program = "fluid-proc"

[participants.rigid]
program = "rigid-proc"

[fluid]
model = "incompressible"
density = 1.0
viscosity = 0.01
initial_velocity = [0.5, 0.0, 0.0]

[fluid.box]
lower = [0.0, 0.0, 0.0]
upper = [1.0, 1.0, 0.03125]
cells = [32, 32, 1]

[fluid.sides]
x_low = "periodic"
x_high = "periodic"
y_low = "periodic"
y_high = "periodic"

[rigid]
gravity = [0.0, 0.0, 0.0]

[[rigid.bodies]]
name = "disc"
shape = { type = "cylinder", radius = 0.15, height = 0.03125 }
density = 2.0
position = [0.5, 0.5, 0.015625]
"#;

#[test]
fn a_body_dragged_by_the_flow_takes_the_momentum_the_fluid_loses() {
    let dir = scratch("drag-along");
    let scenario = dir.join("drag-along.toml");
    std::fs::write(&scenario, MOMENTUM_SCENE).unwrap();
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let fluid = m.column("fluid.momentum_x");
    let body = m.column("rigid.momentum.x");
    let depth = 0.03125;
    let volume = std::f64::consts::PI * 0.15 * 0.15 * depth;
    let body_mass = 2.0 * volume;
    let speed = |i: usize| body[i] / body_mass;
    let total = |i: usize| fluid[i] + body[i] - volume * speed(i.saturating_sub(1));
    let n = fluid.len();
    // The body gains a good share of the momentum: the test has teeth.
    assert!(
        body[n - 1] > 0.2 * body_mass * 0.5,
        "body momentum {}",
        body[n - 1]
    );
    let top = (0..n).map(speed).fold(0.0, f64::max);
    for i in 0..n {
        let error = (total(i) - total(0)).abs();
        assert!(
            error <= 2e-3 * volume * top + 1e-12,
            "momentum after window {i}: {} against {}",
            total(i),
            total(0)
        );
    }
    // Nor does the fluid's own momentum change except by what the body took.
    assert!(fluid[n - 1] < fluid[0]);
}

/// The rising stream of `scenarios/wake.toml` [m/s].
const STREAM: f64 = 6.0;

/// w on the box's centre line (the mean of the two middle columns) at
/// height z [m], from the last `.vti` of a run of `scenarios/wake.toml`
/// (64 × 1 × 128 cells of 62.5 mm from (−2, ·, −4)).
fn centre_line(run: &std::path::Path) -> impl Fn(f64) -> f64 {
    let velocity = participant::vtu::read_cell_data(&last_vti(run), "velocity").unwrap();
    assert_eq!(velocity.len(), 3 * 64 * 128);
    move |z: f64| {
        let k = ((z + 4.0) / 0.0625) as usize;
        0.5 * (velocity[3 * (31 + 64 * k) + 2] + velocity[3 * (32 + 64 * k) + 2])
    }
}

/// Dissertation §4.2.2 (fig. 4.3): a parachutist with a finite volume leaves a
/// wake in the stream and feels an upward force from it; as a mass point
/// it leaves none. The mass point is outside the flow, so the uniform
/// stream, an exact solution with these sides, passes unchanged to
/// round-off. The finite body (a 0.4 m × 1.8 m section standing in a 6 m/s
/// stream) sends the air back down behind it, as behind any bluff body
/// above Re ≈ 50, and still slows it by a quarter 2 m beyond its top,
/// while 1.5 m below it the stream arrives disturbed by under 5 %.
#[test]
fn a_finite_parachutist_leaves_a_wake_and_a_mass_point_does_not() {
    let dir = scratch("wake");
    let out = dir.join("body");
    run_ok(&scenario_path("wake"), &out);
    let w = centre_line(&out);
    let behind = (0..32)
        .map(|k| w(-0.1 + 0.0625 * k as f64))
        .fold(f64::INFINITY, f64::min);
    assert!(
        behind < 0.0,
        "no reverse flow behind the body: least w {behind}"
    );
    assert!(
        w(1.9) < 0.75 * STREAM,
        "no wake 2 m beyond the body: w = {}",
        w(1.9)
    );
    assert!(
        (w(-3.4) / STREAM - 1.0).abs() < 0.05,
        "the stream ahead of the body: w = {}",
        w(-3.4)
    );
    let m = Monitors::read(&out);
    let lift = m.column("fluid.jumper_fluid_force_z");
    let half = lift.len() / 2;
    let mean = lift[half..].iter().sum::<f64>() / (lift.len() - half) as f64;
    assert!(mean > 0.0, "the air pushes the body down: {mean} N");

    let point = variant("wake", &dir, |s| {
        let body = &mut s.rigid.as_mut().unwrap().bodies[0];
        body.shape = None;
        body.mass = Some(100.0);
    });
    let out = dir.join("point");
    run_ok(&point, &out);
    let velocity = participant::vtu::read_cell_data(&last_vti(&out), "velocity").unwrap();
    for (i, v) in velocity.iter().enumerate() {
        let exact = if i % 3 == 2 { STREAM } else { 0.0 };
        assert!((v - exact).abs() < 1e-12, "velocity component {i}: {v}");
    }
}
