//! Inflow, outflow and walls together: a uniform stream U enters a plane
//! channel of height H between two walls and leaves at p = 0. Downstream of
//! the entrance length (about 0.05·Re·H; Schlichting & Gersten, Boundary-
//! Layer Theory, 8th ed., §15.1.4) it is plane Poiseuille flow, the exact
//! solution of the Navier–Stokes equations with
//!   u(y) = 6U·y(H − y)/H², so u = 1.5U on the centre line,
//!   dp/dx = −12μU/H².

use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible};

const HEIGHT: f64 = 1.0;
const SPEED: f64 = 1.0;

/// Largest error of u(y) and the relative error of dp/dx at x = 3H, with
/// `ny` cells across the channel.
fn channel(ny: usize) -> (f64, f64) {
    let (height, length, speed) = (HEIGHT, 4.0 * HEIGHT, SPEED);
    let (density, nu) = (1.0, 0.1); // Re = UH/ν = 10: entrance length ≈ 0.5 H
    let nx = 4 * ny;
    let h = height / ny as f64;
    let sides = [
        [Side::Velocity([speed, 0.0, 0.0]), Side::Outflow],
        [Side::WALL; 2],
        [Side::Periodic; 2],
    ];
    let mut flow = Incompressible::new(FlowSetup {
        grid: Grid::uniform([nx, ny, 1], [length / nx as f64, h, h], bcs(&sides)),
        sides,
        density,
        nu,
    });
    // Courant number 1.5U·Δt/h = 0.4 on the developed centre line; 3 s is
    // well past the viscous settling time H²/(π²ν) ≈ 1 s.
    let dt = 0.4 * h / (1.5 * speed);
    let steps = (3.0 / dt) as usize;
    for _ in 0..steps {
        flow.step(dt).unwrap();
    }
    // The x-faces and pressures of the column at x = 3H (a face column).
    let i = 3 * nx / 4;
    let u = |j: usize| flow.u.u[0][i + (nx + 1) * j];
    let mut worst: f64 = 0.0;
    for j in 0..ny {
        let y = (j as f64 + 0.5) * h;
        let exact = 6.0 * speed * y * (height - y) / (height * height);
        worst = worst.max((u(j) - exact).abs());
    }
    let p = flow.pressure();
    let mean_p = |i: usize| (0..ny).map(|j| p[i + nx * j]).sum::<f64>() / ny as f64;
    let dx = length / nx as f64;
    let gradient = (mean_p(i) - mean_p(i - 1)) / dx;
    let exact = -12.0 * density * nu * speed / (height * height);
    (worst, gradient / exact - 1.0)
}

#[test]
fn a_channel_develops_plane_poiseuille_flow() {
    // Second order in both: observed u(y) errors 5.8e-3, 1.5e-3, 3.7e-4 of
    // U (ratios 3.95, 3.99) and dp/dx errors 0.78 %, 0.19 %, 0.049 % (ratios
    // 3.98, 3.99) on 16, 32 and 64 cells across.
    let runs: Vec<(f64, f64)> = [16, 32, 64].iter().map(|&n| channel(n)).collect();
    for w in runs.windows(2) {
        let ratios = (w[0].0 / w[1].0, w[0].1 / w[1].1);
        assert!(
            ratios.0 > 3.6 && ratios.1 > 3.6,
            "error ratios {ratios:?} in {runs:?}"
        );
    }
    assert!(
        runs[2].0 < 1e-3 * SPEED && runs[2].1.abs() < 1e-3,
        "{runs:?}"
    );
}
