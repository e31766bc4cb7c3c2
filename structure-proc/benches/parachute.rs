//! The structure's step on the C-9 at FronTier++'s resolution (issue 43,
//! item 4), as `cargo bench -p structure-proc --bench parachute`: the canopy
//! and lines of `scenarios/c9-frontier-grid.toml` (11 173 canopy vertices,
//! 28 lines of 140 segments, velocity Verlet with relative-velocity damping,
//! 250 sub-steps of 20 µs a window) under a uniform pressure jump of 30 Pa
//! (the order of the C-9's at 6 m/s, where ½ρv² ≈ 22 Pa), on one and two
//! threads. Per row:
//! - `afresh`, `sub-step`, `ratio`: one sub-step (what a window pays 250
//!   times per try) with every force evaluated afresh and with the
//!   position-only terms kept from one evaluation to the next
//!   (`forces/kept.rs`), each the faster of two runs taken in turn, and
//!   their ratio;
//! - `force` and its parts: the springs (seams and lines), the membrane's
//!   edges four triangles at a time and (`1 by 1`) one at a time, the
//!   dampers likewise, the node sums of the membrane and the dampers, and
//!   the pressure load (slots and sums).
//! `PARACHUTE_BENCH_WINDOWS=N` takes N windows per sub-step measurement
//! (default 2).

use std::path::Path;
use std::time::Instant;
use structure_proc::forces::assembly::{fill, Slot};
use structure_proc::forces::{pressure, total_force, Dynamics, Loads};
use structure_proc::stepper::{Scheme, Stepper};
use structure_proc::system::Afresh;
use structure_proc::{build_model, Model};

/// The jump across the canopy [Pa].
const JUMP: f64 = 30.0;

fn section() -> structure_section::Scene {
    let path = concat!(
        env!("CARGO_MANIFEST_DIR"),
        "/../scenarios/c9-frontier-grid.toml"
    );
    structure_section::Scene::load_file(Path::new(path), "structure-proc")
        .expect("shipped scenario")
}

fn scene() -> (Model, Scheme, f64, u32) {
    let s = section();
    let n = s.structure.substeps;
    let h = s.structure.dt(s.scenario.coupling.window);
    let m = build_model(&s.structure, None, h).expect("the C-9 builds");
    (m, Scheme::of(&s.structure), h, n)
}

/// Seconds per call of `f`, the least mean over three rounds of `reps`.
fn time(reps: usize, mut f: impl FnMut()) -> f64 {
    (0..3)
        .map(|_| {
            let start = Instant::now();
            for _ in 0..reps {
                f();
            }
            start.elapsed().as_secs_f64() / reps as f64
        })
        .fold(f64::INFINITY, f64::min)
}

fn main() {
    let windows: u32 = std::env::var("PARACHUTE_BENCH_WINDOWS")
        .ok()
        .and_then(|s| s.parse().ok())
        .unwrap_or(2);
    let (m0, _, h, n) = scene();
    let jumps = vec![JUMP; m0.triangles.len()];
    let loads = Loads { pressure: &jumps };
    println!(
        "C-9 of c9-frontier-grid.toml: {} nodes, {} springs, {} membrane triangles, {} dampers; \
         {n} sub-steps of {:.1} µs a window, {windows} window(s) per measurement",
        m0.nodes(),
        m0.springs.len(),
        m0.membrane.len(),
        m0.dampers.len(),
        h * 1e6
    );
    println!(
        "{:>7} | {:>8} {:>8} {:>5} | {:>6} {:>7} {:>8} {:>6} {:>7} {:>6} {:>6} {:>8}   [ms]",
        "threads",
        "afresh",
        "sub-step",
        "ratio",
        "force",
        "springs",
        "membrane",
        "1 by 1",
        "dampers",
        "1 by 1",
        "sums",
        "pressure"
    );
    for threads in [1, 2] {
        let pool = rayon::ThreadPoolBuilder::new()
            .num_threads(threads)
            .build()
            .expect("thread pool");
        pool.install(|| row(threads, &loads, h, n * windows));
    }
}

/// Seconds per sub-step over `steps` sub-steps from the scene's start,
/// the force kept between evaluations or (`fresh`) not.
fn substeps(loads: &Loads, h: f64, steps: u32, fresh: bool) -> (f64, Model) {
    let (mut m, mut scheme, _, _) = scene();
    let start = Instant::now();
    for _ in 0..steps {
        if fresh {
            let sys = Dynamics { net: &m.net, loads };
            let integrator = scheme.integrator.as_mut();
            integrator
                .step(&Afresh(&sys), h, &mut m.x, &mut m.v)
                .expect("sub-step");
            m.finish_step(integrator.reaction(), h);
        } else {
            scheme.step(&mut m, loads, h).expect("sub-step");
        }
    }
    (start.elapsed().as_secs_f64() / steps as f64, m)
}

/// One row: a sub-step afresh and kept (each the faster of two runs,
/// alternated), then the force and its parts at the state reached.
fn row(threads: usize, loads: &Loads, h: f64, steps: u32) {
    let (mut fresh, mut kept) = (f64::INFINITY, f64::INFINITY);
    let mut m = Model::default();
    for _ in 0..2 {
        fresh = fresh.min(substeps(loads, h, steps, true).0);
        let (t, reached) = substeps(loads, h, steps, false);
        (kept, m) = (kept.min(t), reached);
    }
    let net = &m.net;
    let (x, v) = (&m.x, &m.v);
    let mut f = vec![0.0; x.len()];
    let force = time(50, || total_force(net, loads, x, v, &mut f));
    let springs = time(50, || net.spring_blocks.forces(x, |_| Slot::ZERO, &mut f));
    let mut edges = vec![Slot::ZERO; 3 * net.membrane.len()];
    let membrane = time(50, || net.membrane_batch.forces(x, &mut edges));
    let membrane_1by1 = time(50, || {
        fill(&mut edges, &net.membrane, |_, t| t.edge_forces(x))
    });
    let law = net.damping.expect("the scene is damped");
    let mut dampers = vec![Slot::ZERO; net.dampers.len()];
    let damping = time(50, || net.damper_batch.forces(law, x, v, &mut dampers));
    let dampers_1by1 = time(50, || {
        fill(&mut dampers, &net.dampers, |_, d| [d.force(law, x, v)])
    });
    let sums = time(50, || {
        net.assembly.membrane.gather_add(&edges, &mut f);
        net.assembly.dampers.gather_add(&dampers, &mut f);
    });
    let mut tri = vec![Slot::ZERO; net.triangles.len()];
    let pressure = time(50, || {
        fill(&mut tri, &net.triangles, |k, t| {
            [pressure::vertex_load(x, t, loads.pressure[k])]
        });
        net.assembly.pressure.gather_add(&tri, &mut f);
    });
    let ms = |s: f64| s * 1e3;
    println!(
        "{threads:>7} | {:>8.3} {:>8.3} {:>5.2} | {:>6.3} {:>7.3} {:>8.3} {:>6.3} {:>7.3} {:>6.3} {:>6.3} {:>8.3}",
        ms(fresh),
        ms(kept),
        fresh / kept,
        ms(force),
        ms(springs),
        ms(membrane),
        ms(membrane_1by1),
        ms(damping),
        ms(dampers_1by1),
        ms(sums),
        ms(pressure)
    );
}
