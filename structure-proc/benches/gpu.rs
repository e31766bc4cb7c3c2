//! The spring solver on the GPU against the CPU (issue 25, item 3), as
//! `cargo bench -p structure-proc --bench gpu`: one Euler–Cromer step of
//! the spring cloth (`common::spring_cloth`, edges and bending springs) of
//! 10³ to 10⁶ springs on one CPU thread, on two, and on the adapter present,
//! measured side by side in one run. The adapter's step is timed over
//! windows of `WINDOW` steps, each ending with the state read back to the
//! host, as a coupled run pays it; the state stays on the device between
//! steps. `GPU_BENCH_SPRINGS=1000000` measures one size only.

mod common;

use common::spring_cloth;
use std::time::Instant;
use structure_gpu::{Gpu, Scheme, Solver};
use structure_proc::forces::Loads;
use structure_proc::{gpu, integrator, Model};

/// Steps per window on the device, read back at its end.
const WINDOW: u64 = 100;

/// Median of `reps` timings of `f` [s].
fn median(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64()
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

/// One CPU Euler–Cromer step on `threads` threads [s].
fn cpu_step(m: &Model, threads: usize, reps: usize) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut m = m.clone();
    let mut scheme = integrator(structure_section::Scheme::EulerCromer);
    pool.install(|| {
        median(reps, || {
            m.step(scheme.as_mut(), &Loads::default(), 1e-5).unwrap();
        })
    })
}

/// One device Euler–Cromer step, in windows of `WINDOW` steps read back [s].
fn gpu_step(m: &Model, gpu: &Gpu, reps: usize) -> f64 {
    let net = gpu::network(&m.net, false);
    let mut solver = Solver::new(gpu, &net, Scheme::EulerCromer).expect("the adapter takes it");
    solver.upload(&m.x, &m.v);
    let (mut x, mut v) = (m.x.clone(), m.v.clone());
    let mut window = || {
        solver.advance(1e-5, WINDOW).unwrap();
        solver.download(&mut x, &mut v).unwrap();
    };
    window(); // compiles the pipelines' code on first use
    median(reps, window) / WINDOW as f64
}

fn main() {
    let gpu = match Gpu::new() {
        Ok(g) => Some(g),
        Err(e) => {
            eprintln!("no adapter, CPU columns only: {e}");
            None
        }
    };
    if let Some(g) = &gpu {
        println!("adapter: {} in {:?}", g.name(), g.precision());
    }
    println!(
        "{:>9} {:>9} {:>11} {:>11} {:>11} {:>9} {:>14}",
        "springs",
        "nodes",
        "1 thread µs",
        "2 threads µs",
        "adapter µs",
        "1t/adapter",
        "adapter upd/s"
    );
    // n × n nodes give about 5.9 n² springs.
    let sizes: Vec<u32> = match std::env::var("GPU_BENCH_SPRINGS") {
        Ok(s) => vec![(s.parse::<f64>().expect("a spring count") / 5.9)
            .sqrt()
            .round() as u32],
        Err(_) => vec![13, 41, 130, 412],
    };
    for n in sizes {
        let m = spring_cloth(n);
        let reps = if n > 200 { 11 } else { 51 };
        let one = cpu_step(&m, 1, reps);
        let two = cpu_step(&m, 2, reps);
        let springs = m.springs.len();
        let device = gpu.as_ref().map(|g| gpu_step(&m, g, reps.min(21)));
        let cell = |t: Option<f64>, f: &dyn Fn(f64) -> String| t.map_or("—".to_string(), f);
        println!(
            "{:>9} {:>9} {:>11.1} {:>11.1} {:>11} {:>9} {:>14}",
            springs,
            m.nodes(),
            one * 1e6,
            two * 1e6,
            cell(device, &|t| format!("{:.1}", t * 1e6)),
            cell(device, &|t| format!("{:.1}", one / t)),
            cell(device, &|t| format!("{:.2e}", springs as f64 / t)),
        );
    }
}
