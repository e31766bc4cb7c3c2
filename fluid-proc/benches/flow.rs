//! Speed of the incompressible solver (issue 6, item 7), as
//! `cargo bench -p fluid-proc`. Prints two tables:
//!
//! - one flow step of a lid-driven cube (lid 1 m/s, ν = 0.01 m²/s, Courant
//!   number 0.4) on 32³, 64³ and 128³ cells, on 1 and 2 threads: time per
//!   step, cell updates per second, pressure-solve iterations and time;
//! - `scenarios/cavity.toml` (Re = 100, 128²) run from rest: the run time
//!   until its three centre-line extrema stay within 1 % of the converged
//!   values (Botella & Peyret 1998), and until max|∂u/∂t| < 1e-4 m/s².
//!
//! Each entry is one run, so expect a few per cent of noise.

use fluid_proc::grid::Grid;
use fluid_proc::incompressible::{FlowSetup, Incompressible, StepReport};
use fluid_proc::profile::{extremum, face_line, CAVITY_RE100_EXTREMA};
use fluid_proc::setup::flow_from;
use fluid_proc::side::{bcs, Side};
use std::time::Instant;

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// The unit cube of n³ cells, walls all round, the top (z) side sliding
/// along x at 1 m/s.
fn cube(n: usize) -> Incompressible {
    let mut sides = [[Side::WALL; 2]; 3];
    sides[2][1] = Side::Velocity([1.0, 0.0, 0.0]);
    Incompressible::new(FlowSetup {
        grid: Grid {
            n: [n; 3],
            h: [1.0 / n as f64; 3],
            bc: bcs(&sides),
        },
        sides,
        density: 1.0,
        nu: 0.01,
    })
}

fn steps_table() {
    println!("One flow step, lid-driven cube (Courant number 0.4 at the lid):\n");
    println!("| cells | threads | ms per step | cell updates/s | pressure iterations | pressure solve ms |");
    println!("|---|---|---|---|---|---|");
    for (n, warm, timed) in [(32, 5, 20), (64, 5, 10), (128, 3, 3)] {
        for threads in [1, 2] {
            pool(threads).install(|| {
                let mut flow = cube(n);
                let dt = 0.4 / n as f64;
                for _ in 0..warm {
                    flow.step(dt).expect("a stable step");
                }
                let (mut iterations, mut pressure) = (0, 0.0);
                let clock = Instant::now();
                for _ in 0..timed {
                    let r: StepReport = flow.step(dt).expect("a stable step");
                    iterations += r.pressure_iterations;
                    pressure += r.pressure_seconds;
                }
                let step = clock.elapsed().as_secs_f64() / timed as f64;
                let cells = (n * n * n) as f64;
                println!(
                    "| {n}³ | {threads} | {:.1} | {:.2e} | {:.1} | {:.1} |",
                    1e3 * step,
                    cells / step,
                    iterations as f64 / timed as f64,
                    1e3 * pressure / timed as f64
                );
            });
        }
    }
}

fn cavity_table() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/cavity.toml");
    let scenario = coupler::Scenario::load(std::path::Path::new(path)).expect("shipped scenario");
    let section = scenario.fluid.as_ref().expect("[fluid]");
    println!(
        "\nscenarios/cavity.toml (Re = 100, 128², Δt = {} s), from rest:\n",
        scenario.coupling.window
    );
    println!("| threads | within 1 % of the converged extrema | max\\|∂u/∂t\\| < 1e-4 m/s² | steps | extrema at the end |");
    println!("|---|---|---|---|---|");
    for threads in [1, 2] {
        pool(threads).install(|| {
            let mut flow = flow_from(section).expect("a flow box");
            let n = flow.grid().n[0];
            let clock = Instant::now();
            let (mut accurate, mut steady): (Option<(f64, f64)>, Option<(f64, f64)>) = (None, None);
            let mut extrema = [0.0; 3];
            let mut steps = 0;
            let mut before = flow.u.clone();
            for w in 0..scenario.windows() {
                before.clone_from(&flow.u);
                let dt = scenario.window_span(w).1;
                flow.step(dt).expect("a stable step");
                steps += 1;
                let u = face_line(&flow, 0, 1, [n / 2, 0, 0]);
                let v = face_line(&flow, 1, 0, [0, n / 2, 0]);
                extrema = [extremum(&u, -1.0), extremum(&v, 1.0), extremum(&v, -1.0)];
                let close = extrema
                    .iter()
                    .zip(CAVITY_RE100_EXTREMA)
                    .all(|(e, c)| (e / c - 1.0).abs() < 0.01);
                let now = (flow.time, clock.elapsed().as_secs_f64());
                // "Stays within": the first time from which it never leaves.
                match (close, accurate) {
                    (true, None) => accurate = Some(now),
                    (false, Some(_)) => accurate = None,
                    _ => {}
                }
                let change = flow.u.max_difference(&before);
                if steady.is_none() && change / dt < 1e-4 {
                    steady = Some(now);
                }
            }
            let show = |t: Option<(f64, f64)>| {
                t.map_or("not reached".to_string(), |(sim, wall)| {
                    format!("{wall:.1} s (t = {sim:.2} s)")
                })
            };
            println!(
                "| {threads} | {} | {} | {steps} | {:.5}, {:.5}, {:.5} |",
                show(accurate),
                show(steady),
                extrema[0],
                extrema[1],
                extrema[2]
            );
        });
    }
    println!(
        "\nConverged (Botella & Peyret 1998): {:?}",
        CAVITY_RE100_EXTREMA
    );
}

fn main() {
    steps_table();
    cavity_table();
}
