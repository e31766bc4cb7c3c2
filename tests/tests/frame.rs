//! A flow box that follows what falls through it (`[fluid.frame]`, issue
//! 23): the air is solved in the box's frame, the bodies in the ground's.

use canopy_tests::*;

/// A sphere of 1 m falling under g = 0.5 m/s² (its own density 4 kg/m³ in
/// air of 1 kg/m³ and μ = 0.05 Pa·s: Re ≈ 16 at its terminal speed), in a
/// 4 m × 4 m column periodic across, its centre 2.5 m above the box's
/// bottom. Six cells across the sphere.
const FOLLOWED_SPHERE: &str = r#"
[run]
name = "sphere-followed"
end_time = 12.0
output_interval = 12.0

[coupling]
window = 0.03

[participants.fluid]
program = "fluid-proc"

[participants.rigid]
program = "rigid-proc"

[fluid]
model = "incompressible"
density = 1.0
viscosity = 0.05

[fluid.box]
lower = [-2.0, -2.0, -2.5]
upper = [2.0, 2.0, 5.5]
cells = [24, 24, 48]

[fluid.sides]
x_low = "periodic"
x_high = "periodic"
y_low = "periodic"
y_high = "periodic"
z_low = { inflow = [0.0, 0.0, 0.0] }   # still air, over the ground
z_high = "outflow"

[fluid.frame]
follow = "ball"

[rigid]
gravity = [0.0, 0.0, -0.5]

[[rigid.bodies]]
name = "ball"
shape = { type = "sphere", radius = 0.5 }
density = 4.0
position = [0.0, 0.0, 0.0]
"#;

/// The same sphere in a fixed box 16 m tall, closed below and open above:
/// it falls 10 m in the 12 s and stays 6 m above the bottom.
fn fixed_sphere() -> String {
    FOLLOWED_SPHERE
        .replace("sphere-followed", "sphere-fixed")
        .replace("upper = [2.0, 2.0, 5.5]", "upper = [2.0, 2.0, 13.5]")
        .replace("cells = [24, 24, 48]", "cells = [24, 24, 96]")
        .replace("{ inflow = [0.0, 0.0, 0.0] }", "\"wall\"")
        .replace("[fluid.frame]\nfollow = \"ball\"\n", "")
        .replace("position = [0.0, 0.0, 0.0]", "position = [0.0, 0.0, 11.0]")
}

/// The followed sphere in a box graded along z (`[fluid.box.core]`, issue
/// 45): cells of 1/6 m in a core 2 m tall round the sphere, as the
/// uniform boxes' cells, growing by at most 1.2 toward the bottom and the
/// top (24 × 24 × 28 cells for the uniform box's 24 × 24 × 48). Across,
/// the core spans the periodic 4 m: the same blockage as the fixed box.
fn graded_sphere() -> String {
    FOLLOWED_SPHERE
        .replace("sphere-followed", "sphere-graded")
        .replace(
            "cells = [24, 24, 48]",
            "[fluid.box.core]\nlower = [-2.0, -2.0, -1.0]\nupper = [2.0, 2.0, 1.0]\n\
         spacing = 0.16666666666666666\ngrowth = 1.2",
        )
}

/// The terminal speed a speed approaching it exponentially tends to,
/// Aitken's Δ² on three equally spaced values of the run's last half.
fn terminal_speed(m: &Monitors) -> f64 {
    let v: Vec<f64> = m.column("rigid.ball.vz").iter().map(|v| -v).collect();
    let n = v.len();
    let (a, b, c) = (v[n - 1 - n / 3], v[n - 1 - n / 6], v[n - 1]);
    c - (c - b) * (c - b) / ((c - b) - (b - a))
}

#[test]
fn a_sphere_falls_at_the_same_terminal_speed_in_a_box_that_follows_it() {
    let dir = scratch("frame-sphere");
    let mut speeds = Vec::new();
    for (name, text) in [
        ("followed", FOLLOWED_SPHERE.to_string()),
        ("fixed", fixed_sphere()),
        ("graded", graded_sphere()),
    ] {
        let scenario = dir.join(format!("{name}.toml"));
        std::fs::write(&scenario, text).unwrap();
        let out = dir.join(name);
        run_ok(&scenario, &out);
        let m = Monitors::read(&out);
        // Near its terminal speed: the fluid carries the weight m·g within 1 %.
        let weight = 4.0 * std::f64::consts::PI / 6.0 * 0.5;
        let force = *m.column("fluid.ball_fluid_force_z").last().unwrap();
        assert!(
            (force / weight - 1.0).abs() < 0.01,
            "{name}: {force} N against {weight} N"
        );
        speeds.push(terminal_speed(&m));
        if name != "fixed" {
            // The box fell with the sphere: the frame's monitors read its
            // descent over the ground, one window behind the sphere's own.
            let z = *m.column("rigid.ball.z").last().unwrap();
            let altitude = *m.column("fluid.frame_altitude").last().unwrap();
            let speed = *m.column("fluid.frame_descent_speed").last().unwrap();
            let vz = *m.column("rigid.ball.vz").last().unwrap();
            assert!(
                z < -7.0 && (altitude - z).abs() < 0.05,
                "{altitude} m against {z} m"
            );
            assert!(
                (speed + vz).abs() < 1e-3 * vz.abs(),
                "{speed} m/s against {vz} m/s"
            );
        }
    }
    // The issue's bound, 1 %. Measured 0.75 %: the sphere held in a stream
    // drags a little more than one moving through the cells (the immersed
    // boundary is not Galilean-invariant on a coarse grid: a sphere held at
    // a constant speed in the fixed box and in the following one differs
    // alike), not the frame's doing.
    let [followed, fixed, graded] = [speeds[0], speeds[1], speeds[2]];
    assert!(
        (followed / fixed - 1.0).abs() < 0.01,
        "terminal speed {followed} m/s in the following box, {fixed} m/s in the fixed one"
    );
    // Issue 45's bound for a graded box that follows the sphere against
    // the fixed box of its core's cells, 1 %.
    assert!(
        (graded / fixed - 1.0).abs() < 0.01,
        "terminal speed {graded} m/s in the graded following box, {fixed} m/s in the fixed one"
    );
    eprintln!("terminal speeds: followed {followed}, fixed {fixed}, graded {graded} m/s");
}

/// A box that follows a mass point in free fall (no shape: nothing in the
/// flow). The air is still over the ground, so in the box it must move at
/// exactly minus the box's velocity everywhere: the frame's body force,
/// its inflow and its sides agree, or the air would stir.
const FALLING_POINT: &str = r#"
[run]
name = "point-followed"
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
density = 1.2
viscosity = 1.8e-5

[fluid.box]
lower = [-1.0, -1.0, -1.0]
upper = [1.0, 1.0, 3.0]
cells = [8, 8, 16]

[fluid.sides]
x_low = "periodic"
x_high = "periodic"
y_low = "periodic"
y_high = "periodic"
z_low = { inflow = [0.0, 0.0, 0.0] }
z_high = "outflow"

[fluid.frame]
follow = "stone"
altitude = 1000.0

[rigid]
gravity = [0.3, 0.0, -9.81]

[[rigid.bodies]]
name = "stone"
mass = 1.0
position = [0.0, 0.0, 0.0]
velocity = [0.0, 0.0, -2.0]
"#;

#[test]
fn the_air_at_rest_stays_at_rest_in_a_box_that_falls_freely() {
    let dir = scratch("frame-point");
    let scenario = dir.join("point.toml");
    std::fs::write(&scenario, FALLING_POINT).unwrap();
    let out = dir.join("run");
    run_ok(&scenario, &out);
    let m = Monitors::read(&out);
    let volume = 2.0 * 2.0 * 4.0;
    let (t, vz) = (m.column("time"), m.column("rigid.stone.vz"));
    let descent = m.column("fluid.frame_descent_speed");
    let momentum = [m.column("fluid.momentum_x"), m.column("fluid.momentum_z")];
    let vx = m.column("rigid.stone.vx");
    for i in 1..t.len() {
        // The box moves at the stone's velocity one window before.
        let (vx0, vz0) = (vx[i - 1], vz[i - 1]);
        assert!(
            (descent[i] + vz0).abs() < 1e-12 * vz0.abs(),
            "t = {}: {}",
            t[i],
            descent[i]
        );
        // The air's momentum in the box: ρ·V·(0 − V_box), to round-off.
        let expected = [-1.2 * volume * vx0, -1.2 * volume * vz0];
        for (p, e) in momentum.iter().zip(expected) {
            assert!(
                (p[i] - e).abs() < 1e-9 * e.abs().max(1.0),
                "t = {}: {} against {e}",
                t[i],
                p[i]
            );
        }
    }
    // The box's z = 0 fell as the stone did, from 1000 m over the ground,
    // by the trapezoid rule on the velocities one window behind.
    let altitude = *m.column("fluid.frame_altitude").last().unwrap();
    let dt = 0.01;
    let fallen: f64 = (1..vz.len())
        .map(|i| 0.5 * (vz[i - 1] + vz[i.saturating_sub(2)]) * dt)
        .sum();
    assert!((altitude - (1000.0 + fallen)).abs() < 1e-9, "{altitude} m");
    let steady = m.column("fluid.max_divergence");
    assert!(steady.iter().all(|d| *d < 1e-9), "{steady:?}");
}
