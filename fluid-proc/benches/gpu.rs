//! The flow's step on the GPU against two CPU threads (issue 47, item 3),
//! as `cargo bench -p fluid-proc --bench gpu`: one step of the lid-driven
//! cube (lid 1 m/s, ν = 0.01 m²/s, Courant number 0.4) on 64³, 128³ and
//! 256³ cells (`CANOPY_BENCH_CELLS="32 64"` chooses others), each timed on
//! two threads of the CPU path and on the first adapter wgpu finds, in the
//! same run. A device step is what a run pays for a window of one step:
//! the step on the device, then u and q read back to the host for the
//! monitors and the exchanged fields. Prints a table with the adapter's
//! name and precision; a size the adapter cannot hold says so.

use fluid_gpu::Gpu;
use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible};
use std::time::Instant;

/// The unit cube of n³ cells, walls all round, the top (z) side sliding
/// along x at 1 m/s (flow.rs's cube).
fn cube(n: usize) -> Incompressible {
    let mut sides = [[Side::WALL; 2]; 3];
    sides[2][1] = Side::Velocity([1.0, 0.0, 0.0]);
    Incompressible::new(FlowSetup {
        grid: Grid::uniform([n; 3], [1.0 / n as f64; 3], bcs(&sides)),
        sides,
        density: 1.0,
        nu: 0.01,
    })
}

/// Mean seconds a step and pressure iterations a step over `timed` steps
/// after `warm`, on the device where `gpu` is given.
fn time_steps(n: usize, gpu: Option<&Gpu>, warm: usize, timed: usize) -> Result<[f64; 2], String> {
    let mut flow = cube(n);
    if let Some(gpu) = gpu {
        flow.to_device(gpu)?;
    }
    let dt = 0.4 / n as f64;
    for _ in 0..warm {
        flow.step(dt).map_err(|e| e.to_string())?;
    }
    let mut iterations = 0;
    let clock = Instant::now();
    for _ in 0..timed {
        iterations += flow
            .step(dt)
            .map_err(|e| e.to_string())?
            .pressure_iterations;
    }
    let t = timed as f64;
    Ok([clock.elapsed().as_secs_f64() / t, iterations as f64 / t])
}

fn main() {
    let gpu = match Gpu::new() {
        Ok(gpu) => gpu,
        Err(e) => {
            println!("no GPU column: {e}");
            return;
        }
    };
    let sizes: Vec<usize> = std::env::var("CANOPY_BENCH_CELLS")
        .ok()
        .map(|s| {
            s.split_whitespace()
                .filter_map(|x| x.parse().ok())
                .collect()
        })
        .unwrap_or(vec![64, 128, 256]);
    println!(
        "One flow step of the lid-driven cube (Courant number 0.4 at the lid), two CPU threads \
         against {} in {:?}:\n",
        gpu.name(),
        gpu.precision()
    );
    println!("| cells | 2 threads ms | pressure iterations | GPU ms | pressure iterations | 2 threads / GPU |");
    println!("|---|---|---|---|---|---|");
    let two = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .expect("a pool");
    for n in sizes {
        let (warm, timed) = if n >= 128 { (1, 3) } else { (3, 10) };
        let device = time_steps(n, Some(&gpu), warm + 2, timed);
        let cpu = two.install(|| time_steps(n, None, warm, timed));
        match (cpu, device) {
            (Ok([c, ci]), Ok([g, gi])) => println!(
                "| {n}³ | {:.1} | {ci:.1} | {:.2} | {gi:.1} | {:.1} |",
                1e3 * c,
                1e3 * g,
                c / g
            ),
            (cpu, device) => println!("| {n}³ | {cpu:?} | | {device:?} | | |"),
        }
    }
}
