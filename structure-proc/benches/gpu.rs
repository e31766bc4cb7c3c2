//! The spring solver on the GPU against the CPU (issue 25, item 3), as
//! `cargo bench -p structure-proc --bench gpu`, measured side by side in one
//! run on one CPU thread, on two, and on the adapter present:
//!
//! - one Euler–Cromer step of the spring cloth (`common::spring_cloth`,
//!   edges and bending springs) of 10³ to 10⁶ springs, the adapter's timed
//!   over windows of `WINDOW` steps, each ending with the state read back
//!   (`GPU_BENCH_SPRINGS=1000000` measures one size only);
//! - the dissertation's table 5.2: one RK4 step (its GPU scheme) of each
//!   parachute preset (C-9, G-11, Intruder, T-10, T-11 as their scenes
//!   build them, canopy, lines and payload) refined to about
//!   `TABLE_CANOPY_NODES` canopy vertices, under a uniform pressure jump,
//!   by the scene's stepper on the CPU and on the GPU (`[structure]
//!   device`) in windows of `TABLE_WINDOW` sub-steps: each window sends the
//!   state and the pressure to the device and reads the state back, as a
//!   coupled run pays it once the payload is released (while it is held,
//!   or lines may break, the state crosses every sub-step)
//!   (`GPU_BENCH_TABLE_ONLY=1` skips the cloth).

mod common;

use common::spring_cloth;
use std::time::Instant;
use structure_gpu::{Gpu, Scheme, Solver};
use structure_proc::driver::{Scheme as CpuStepper, Stepper};
use structure_proc::forces::Loads;
use structure_proc::gpu::OnDevice;
use structure_proc::{build_model, gpu, integrator, Model};
use structure_section::{Integrator, Scene};

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

/// The canopy vertices of table 5.2's rows: the dissertation's C-9 has
/// about 12 000 (issue 25).
const TABLE_CANOPY_NODES: f64 = 12_000.0;

/// Sub-steps a window in table 5.2's rows, as `c9-drop-body` takes them.
const TABLE_WINDOW: u32 = 10;

/// Pressure jump on the canopy in table 5.2's rows [Pa]: about a C-9's
/// payload weight over its area (`c9-drop.toml`).
const TABLE_JUMP: f64 = 17.0;

/// The resolution of the scene's parachute.
fn resolution(scene: &mut Scene) -> &mut u32 {
    &mut scene
        .structure
        .parachute
        .as_mut()
        .expect("a parachute")
        .resolution
}

/// The preset of scene `name` refined to within 10 % of
/// `TABLE_CANOPY_NODES` canopy vertices, with RK4: the resolution found by
/// the secant method on log(vertices) against log(resolution).
fn preset(name: &str) -> (Model, Scene) {
    let path = format!("{}/../scenarios/{name}.toml", env!("CARGO_MANIFEST_DIR"));
    let mut scene =
        Scene::load_file(std::path::Path::new(&path), "structure-proc").expect("shipped scene");
    let dt = scene.structure.dt(scene.scenario.coupling.window);
    scene.structure.integrator = Integrator::Rk4;
    let build = |scene: &Scene| {
        build_model(&scene.structure, scene.rigid.as_ref(), dt).expect("preset builds")
    };
    let mut m = build(&scene);
    // Vertices grow as the resolution to this power (squared to start).
    let mut power = 2.0;
    for _ in 0..6 {
        let (r, n) = (*resolution(&mut scene) as f64, m.canopy_nodes as f64);
        if (n / TABLE_CANOPY_NODES - 1.0).abs() < 0.1 {
            break;
        }
        let next = (r * (TABLE_CANOPY_NODES / n).powf(1.0 / power))
            .round()
            .max(2.0);
        *resolution(&mut scene) = next as u32;
        m = build(&scene);
        if next != r {
            power = (m.canopy_nodes as f64 / n).ln() / (next / r).ln();
        }
    }
    (m, scene)
}

/// One sub-step of `stepper` on `m` under `jump`, timed over windows of
/// `TABLE_WINDOW` [s], on `threads` threads.
fn preset_step(
    m: &Model,
    stepper: &mut (dyn Stepper + Send),
    dt: f64,
    jump: &[f64],
    threads: usize,
    reps: usize,
) -> f64 {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .unwrap();
    let mut m = m.clone();
    let loads = Loads { pressure: jump };
    pool.install(|| {
        let mut window = || stepper.steps(&mut m, &loads, dt, TABLE_WINDOW).unwrap();
        window();
        median(reps, window) / TABLE_WINDOW as f64
    })
}

/// Table 5.2's rows: each preset's RK4 step on 1 and 2 CPU threads and the adapter.
fn table_5_2(gpu: bool) {
    println!("\ndissertation table 5.2: one RK4 step of each parachute, windows of {TABLE_WINDOW} sub-steps (medians)");
    println!(
        "{:>9} {:>7} {:>7} {:>9} {:>11} {:>12} {:>11} {:>10}",
        "parachute",
        "canopy",
        "nodes",
        "elements",
        "1 thread ms",
        "2 threads ms",
        "adapter ms",
        "1t/adapter"
    );
    for (label, name) in [
        ("C-9", "c9-drop"),
        ("G-11", "g11-descent"),
        ("Intruder", "intruder-descent"),
        ("T-10", "t10-descent"),
        ("T-11", "t11-descent"),
    ] {
        let (m, scene) = preset(name);
        let dt = scene.structure.dt(scene.scenario.coupling.window);
        let jump = vec![TABLE_JUMP; m.triangles.len()];
        let mut cpu = CpuStepper::of(&scene.structure);
        let one = preset_step(&m, &mut cpu, dt, &jump, 1, 5);
        let two = preset_step(&m, &mut cpu, dt, &jump, 2, 5);
        let device = gpu.then(|| {
            let mut on = OnDevice::new(&scene.structure, &m).expect("the adapter takes the preset");
            preset_step(&m, &mut on, dt, &jump, 2, 11)
        });
        println!(
            "{:>9} {:>7} {:>7} {:>9} {:>11.2} {:>12.2} {:>11} {:>10}",
            label,
            m.canopy_nodes,
            m.nodes(),
            m.springs.len() + 3 * m.membrane.len(),
            one * 1e3,
            two * 1e3,
            device.map_or("—".to_string(), |t| format!("{:.3}", t * 1e3)),
            device.map_or("—".to_string(), |t| format!("{:.1}", one / t)),
        );
    }
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
    if std::env::var_os("GPU_BENCH_TABLE_ONLY").is_none() {
        cloth_table(gpu.as_ref());
    }
    table_5_2(gpu.is_some());
}

/// The spring cloth's rows.
fn cloth_table(gpu: Option<&Gpu>) {
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
        let device = gpu.map(|g| gpu_step(&m, g, reps.min(21)));
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
