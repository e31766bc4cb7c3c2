//! A side held at a gas state (`[fluid.sides] x_low = { state = { density,
//! velocity, pressure } }`): gas entering a tube at rest with the velocity
//! u_p and the state a piston moving at u_p leaves behind its shock makes
//! that shock. Into gas at rest (ρ₁, p₁, a₁) it runs at
//!   W = (γ+1)u_p/4 + √(((γ+1)u_p/4)² + a₁²)
//! and leaves ρ₂ = ρ₁W/(W − u_p), p₂ = p₁ + ρ₁W·u_p behind it: the
//! Rankine–Hugoniot conditions of a moving normal shock (Anderson, *Modern
//! Compressible Flow*, 3rd ed., §7.2–7.3). With γ = 1.4, ρ₁ = p₁ = u_p = 1:
//! W = 1.926650, ρ₂ = 2.079156, p₂ = 2.926650.

mod common;
use common::*;
use fluid_section::flow::SideSpec;
use fluid_section::gas::{GasRegion, GasState};

const UP: f64 = 1.0;

#[test]
fn gas_entering_at_a_shocks_state_makes_that_shock_within_1_percent() {
    let mut scene = shipped("sod");
    let gamma = scene.fluid.gamma();
    let (w, rho2, p2) = piston_shock(gamma, 1.0, 1.0, UP);
    assert!((w - 1.926650).abs() < 1e-6 && (rho2 - 2.079156).abs() < 1e-6);
    let fluid = &mut scene.fluid;
    let mut sides = fluid.sides.unwrap();
    sides.x_low = Some(SideSpec::State(GasState {
        density: rho2,
        velocity: [UP, 0.0, 0.0],
        pressure: p2,
    }));
    fluid.sides = Some(sides);
    fluid.regions = Some(vec![GasRegion {
        lower: None,
        upper: None,
        density: 1.0,
        velocity: [0.0; 3],
        pressure: 1.0,
        density_wave: None,
    }]);
    scene.scenario.run.end_time = 0.25;
    let t = scene.scenario.run.end_time - scene.scenario.run.start_time;
    let gas = run_to_end(&scene);
    let cells = gas.primitives();
    let n = gas.setup.n[0];
    let x = |i: usize| (i as f64 + 0.5) / n as f64;
    // The shock: where the density crosses halfway from ρ₂ to ρ₁.
    let front = front(&cells, x, 0.5 * (rho2 + 1.0));
    let travelled = w * t;
    eprintln!("shock at {front:.5} m, exact {travelled:.5} m");
    assert!(
        (front / travelled - 1.0).abs() < 0.01,
        "shock at {front} m, exact {travelled} m"
    );
    // Behind it, the middle half of the slab (the face's start-up and the
    // smeared front left out): the state the side holds, within 1 %.
    let span = 0.25 * travelled..0.75 * travelled;
    assert_slab_within_1_percent(&cells, x, span, [rho2, UP, p2]);
}
