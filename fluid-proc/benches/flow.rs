//! Speed of the incompressible solver (issue 6, item 7), as
//! `cargo bench -p fluid-proc`. Prints two tables:
//!
//! - one flow step of a lid-driven cube (lid 1 m/s, ν = 0.01 m²/s, Courant
//!   number 0.4) on 32³, 64³ and 128³ cells, on 1 and 2 threads and on 2
//!   MPI ranks of one thread each: time per step, cell updates per second,
//!   pressure-solve iterations and time. The ranks rows need the `mpi`
//!   feature (`cargo bench -p fluid-proc --features mpi`): the benchmark
//!   then starts itself under `mpirun` for them;
//! - `scenarios/cavity.toml` (Re = 100, 128²) run from rest: the run time
//!   until its three centre-line extrema stay within 1 % of the converged
//!   values (Botella & Peyret 1998), and until max|∂u/∂t| < 1e-4 m/s².
//!
//! Each entry is one run, so expect a few per cent of noise.

use fluid_proc::comm::{Comm, Single};
use fluid_proc::incompressible::grid::Grid;
use fluid_proc::incompressible::part::Part;
use fluid_proc::incompressible::profile::{extremum, face_line, CAVITY_RE100_EXTREMA};
use fluid_proc::incompressible::setup::flow_from;
use fluid_proc::incompressible::side::{bcs, Side};
use fluid_proc::incompressible::{FlowSetup, Incompressible, StepReport};
use std::sync::Arc;
use std::time::Instant;

/// Set in the environment of the benchmark started under `mpirun`: the
/// cube's cells, warm-up steps and timed steps of the row to time.
const RANKS_ROW: &str = "CANOPY_BENCH_RANKS_ROW";

fn pool(threads: usize) -> rayon::ThreadPool {
    rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .build()
        .expect("thread pool")
}

/// This rank's part of the unit cube of n³ cells, walls all round, the top
/// (z) side sliding along x at 1 m/s.
fn cube(n: usize, comm: Arc<dyn Comm>) -> Incompressible {
    let mut sides = [[Side::WALL; 2]; 3];
    sides[2][1] = Side::Velocity([1.0, 0.0, 0.0]);
    let setup = FlowSetup {
        grid: Grid::uniform([n; 3], [1.0 / n as f64; 3], bcs(&sides)),
        sides,
        density: 1.0,
        nu: 0.01,
    };
    Incompressible::on(setup, Part::on(comm, [n; 3], sides))
}

/// One step's mean time, pressure iterations and pressure-solve time [s]
/// over `timed` steps of the cube after `warm` ones.
fn time_steps(n: usize, comm: Arc<dyn Comm>, warm: usize, timed: usize) -> [f64; 3] {
    let mut flow = cube(n, comm);
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
    let t = timed as f64;
    [
        clock.elapsed().as_secs_f64() / t,
        iterations as f64 / t,
        pressure / t,
    ]
}

/// The row on two MPI ranks of one thread each: this benchmark started
/// under `mpirun` (None without the `mpi` feature or without mpirun).
fn ranks_row(n: usize, warm: usize, timed: usize) -> Option<[f64; 3]> {
    if !cfg!(feature = "mpi") {
        return None;
    }
    let exe = std::env::current_exe().ok()?;
    let out = std::process::Command::new("mpirun")
        .args(participant::mpirun::args(2, &exe, &[]))
        .envs(participant::mpirun::env(2))
        .env(RANKS_ROW, format!("{n} {warm} {timed}"))
        .env("RAYON_NUM_THREADS", "1")
        .output()
        .ok()?;
    if !out.status.success() {
        eprintln!(
            "the run on 2 ranks failed: {}",
            String::from_utf8_lossy(&out.stderr)
        );
        return None;
    }
    let text = String::from_utf8_lossy(&out.stdout);
    let row = text.lines().find_map(|l| l.strip_prefix("ROW "))?;
    let v: Vec<f64> = row.split(' ').filter_map(|x| x.parse().ok()).collect();
    v.try_into().ok()
}

/// Under `mpirun`: times the row `RANKS_ROW` names; rank 0 prints it.
#[cfg(feature = "mpi")]
fn ranks_worker(row: &str) {
    let v: Vec<usize> = row.split(' ').filter_map(|x| x.parse().ok()).collect();
    let universe = mpi::initialize().expect("MPI starts");
    let comm = Arc::new(fluid_proc::mpi_comm::MpiComm::new(&universe));
    let rank = comm.rank();
    let [step, iterations, pressure] = time_steps(v[0], comm, v[1], v[2]);
    if rank == 0 {
        println!("ROW {step} {iterations} {pressure}");
    }
}

#[cfg(not(feature = "mpi"))]
fn ranks_worker(_: &str) {}

fn steps_table() {
    println!("One flow step, lid-driven cube (Courant number 0.4 at the lid):\n");
    println!("| cells | threads × ranks | ms per step | cell updates/s | pressure iterations | pressure solve ms |");
    println!("|---|---|---|---|---|---|");
    for (n, warm, timed) in [(32, 5, 20), (64, 5, 10), (128, 3, 3)] {
        let rows = [1, 2].map(|threads| {
            let row = pool(threads).install(|| time_steps(n, Arc::new(Single), warm, timed));
            (format!("{threads} × 1"), Some(row))
        });
        let ranks = ("1 × 2".to_string(), ranks_row(n, warm, timed));
        for (setting, row) in rows.into_iter().chain([ranks]) {
            let Some([step, iterations, pressure]) = row else {
                println!("| {n}³ | {setting} | — (`--features mpi` and mpirun) | | | |");
                continue;
            };
            println!(
                "| {n}³ | {setting} | {:.1} | {:.2e} | {:.1} | {:.1} |",
                1e3 * step,
                (n * n * n) as f64 / step,
                iterations,
                1e3 * pressure
            );
        }
    }
}

fn cavity_table() {
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/../scenarios/cavity.toml");
    let scene =
        fluid_section::Scene::load_file(std::path::Path::new(path)).expect("shipped scenario");
    let section = &scene.fluid;
    println!(
        "\nscenarios/cavity.toml (Re = 100, 128², Δt = {} s), from rest:\n",
        scene.scenario.coupling.window
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
            for w in 0..scene.scenario.windows() {
                before.clone_from(&flow.u);
                let dt = scene.scenario.window_span(w).1;
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
    if let Ok(row) = std::env::var(RANKS_ROW) {
        ranks_worker(&row);
        return;
    }
    steps_table();
    cavity_table();
}
