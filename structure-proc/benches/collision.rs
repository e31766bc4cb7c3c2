//! Speed of the structure's collision pass (issue 24, item 7; issue 46,
//! item 2), as `cargo bench -p structure-proc --bench collision`: on the
//! cloth of `scenarios/cloth-hanging.toml` at n × n nodes, one step of the
//! pass in each contact model (`pairwise`, `layered`) against one
//! evaluation of the same cloth's force, measured side by side:
//!
//! - `flat`: the cloth as built, falling 0.1 mm in the step (for the
//!   pairwise model the tree's refit and its cone test; no pair is tested);
//! - `anew` and `held`: the same cloth pleated like an accordion into
//!   layers 0.6 of the layer apart, so every node has neighbours in
//!   proximity, each layer closing on the one below at 0.5 m/s: the pass
//!   stops thousands of approaches. Measured with the candidates (or
//!   groups) found anew, a run's first step, and held from the step
//!   before, every later step while they hold (issue 46 asks the layered
//!   model's held pass for at most 10 force evaluations);
//! - `run`: the mean of 20 steps of that cloth as a run pays them, its
//!   lowest layer held, each layer keeping the velocity the pass leaves it
//!   under gravity: the stack collapses onto the held layer, its top layer
//!   at 0.5·(n/5) m/s, and the pass finds pairs again as it does.
//!
//! It prints a table of medians and their ratios to the force, and the
//! proximity impulses of a run's step. Two threads, as a run uses them.
//! `COLLISION_BENCH_N=100` measures one size, `COLLISION_BENCH_MODEL=layered`
//! one model; `COLLISION_BENCH_HELD_ONLY=1` times the crumpled cloth's held
//! pass alone, 100 times, for a profiler.

mod common;

use common::cloth_section;
use std::time::Instant;
use structure_proc::collision::Contacts;
use structure_proc::forces::Loads;
use structure_proc::{build_model, Model};
use structure_section::collision::ContactModel;
use structure_section::Collision;

/// The cloth of `scenarios/cloth-hanging.toml` on n × n nodes, nothing held.
fn cloth(n: u32) -> Model {
    let (mut section, _) = cloth_section(n);
    section.cloth.as_mut().expect("cloth").fixed.clear();
    build_model(&section, None, 1e-4).expect("cloth builds")
}

/// How far each layer of the crumpled cloth closes on the one below in
/// the step, in layers: 0.5 m/s at Δt = 10⁻⁴ s.
const CLOSING: f64 = 0.05;

/// Fold the n × n cloth along x into pleats of five cells, stacked `gap`
/// apart in z.
fn pleat(m: &mut Model, n: usize, gap: f64) {
    m.x = structure_proc::rectangle::rectangle(1.0, 1.0, n, n, [0.0; 3]).pleated(5, gap);
}

/// The median of `reps` timings of `f` [µs].
fn median(reps: usize, mut f: impl FnMut()) -> f64 {
    let mut t: Vec<f64> = (0..reps)
        .map(|_| {
            let start = Instant::now();
            f();
            start.elapsed().as_secs_f64() * 1e6
        })
        .collect();
    t.sort_by(f64::total_cmp);
    t[reps / 2]
}

/// One step of the pass from `x0` moved by `dx` [µs]: with the candidates
/// held from the step before (a run's steps after its first), or, if
/// `anew`, found anew (a run's first step).
fn pass(
    m: &Model,
    x0: &[f64],
    dx: &[f64],
    reps: usize,
    anew: bool,
    model: ContactModel,
) -> (f64, u64) {
    let spec = Collision {
        model,
        ..Collision::default()
    };
    let mut contacts = Contacts::new(&m.net, &spec).expect("a surface");
    let dt = 1e-4;
    let t = median(reps, || {
        let mut x: Vec<f64> = x0.iter().zip(dx).map(|(a, b)| a + b).collect();
        let mut v: Vec<f64> = dx.iter().map(|d| d / dt).collect();
        if anew {
            contacts.forget_candidates();
        }
        contacts.begin_step(x0);
        contacts
            .resolve(&mut x, &mut v, &m.net.mass, &m.net.inv_mass, dt)
            .expect("resolved");
    });
    (t, contacts.stats.proximity / reps as u64)
}

/// The mean time of a step [µs] over `steps` steps of the pass from `x0`
/// as a run pays it: the cloth starts with the velocity `dx`/Δt, its
/// lowest layer held, and keeps the velocity each step leaves it, under
/// gravity, so its layers close on each other and come to rest on the
/// held one; and the impulses a step.
fn run(m: &Model, x0: &[f64], dx: &[f64], steps: usize, model: ContactModel) -> (f64, u64) {
    let spec = Collision {
        model,
        ..Collision::default()
    };
    let mut contacts = Contacts::new(&m.net, &spec).expect("a surface");
    let dt = 1e-4;
    let lowest = x0
        .iter()
        .skip(2)
        .step_by(3)
        .fold(f64::INFINITY, |a, &z| a.min(z));
    let mut inv_mass = m.net.inv_mass.clone();
    for (n, w) in inv_mass.iter_mut().enumerate() {
        if x0[3 * n + 2] < lowest + 1e-9 {
            *w = 0.0;
        }
    }
    let mut x = x0.to_vec();
    let mut v: Vec<f64> = (0..x.len())
        .map(|i| {
            if inv_mass[i / 3] > 0.0 {
                dx[i] / dt
            } else {
                0.0
            }
        })
        .collect();
    let start = Instant::now();
    for _ in 0..steps {
        contacts.begin_step(&x);
        for (i, (a, u)) in x.iter_mut().zip(&mut v).enumerate() {
            if i % 3 == 2 && inv_mass[i / 3] > 0.0 {
                *u -= GRAVITY * dt;
            }
            *a += *u * dt;
        }
        let t = Instant::now();
        contacts
            .resolve(&mut x, &mut v, &m.net.mass, &inv_mass, dt)
            .expect("resolved");
        if std::env::var("DBG_C").is_ok() {
            eprintln!(
                "step {:.1} ms {:?}",
                t.elapsed().as_secs_f64() * 1e3,
                contacts.stats
            );
        }
    }
    let each = start.elapsed().as_secs_f64() * 1e6 / steps as f64;
    (each, contacts.stats.proximity / steps as u64)
}

/// Standard gravity [m/s²] on the `run` column's cloth.
const GRAVITY: f64 = 9.80665;

/// The model `COLLISION_BENCH_MODEL` names ("pairwise" or "layered"), or both.
fn models() -> Vec<(&'static str, ContactModel)> {
    let all = [
        ("pairwise", ContactModel::Pairwise),
        ("layered", ContactModel::Layered),
    ];
    match std::env::var("COLLISION_BENCH_MODEL") {
        Ok(name) => all.into_iter().filter(|(n, _)| *n == name).collect(),
        Err(_) => all.to_vec(),
    }
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        println!("collision pass against the force, one step, 2 threads (medians; run: mean of {RUN_STEPS} steps)");
        println!(
            "{:>9} {:>9} {:>9} {:>9} {:>7} {:>9} {:>8} {:>9} {:>8} {:>9} {:>8} {:>10}",
            "cloth", "model", "triangles", "force µs", "flat/F", "anew µs", "anew/F", "held µs", "held/F", "run µs", "run/F", "impulses"
        );
        // `COLLISION_BENCH_N=100` measures one size only.
        let sizes: Vec<usize> = match std::env::var("COLLISION_BENCH_N") {
            Ok(n) => vec![n.parse().expect("COLLISION_BENCH_N is a node count")],
            Err(_) => vec![25, 50, 100, 200],
        };
        for n in sizes {
            let mut m = cloth(n as u32);
            let reps = if n >= 200 { 5 } else { 21 };
            let mut f = vec![0.0; m.x.len()];
            let force = median(reps, || m.force(&Loads::default(), &mut f));
            let fall: Vec<f64> = (0..m.x.len()).map(|i| if i % 3 == 2 { -1e-4 } else { 0.0 }).collect();
            let flat_x = m.x.clone();
            let layer = structure_section::collision::DEFAULT_THICKNESS;
            let gap = 0.6 * layer;
            pleat(&mut m, n, gap);
            let x0 = m.x.clone();
            // Each layer closes on the one below by CLOSING layers a step.
            let closing: Vec<f64> = (0..m.x.len())
                .map(|i| if i % 3 == 2 { -(x0[i] / gap).round() * CLOSING * layer } else { 0.0 })
                .collect();
            for (name, model) in models() {
                // `COLLISION_BENCH_HELD_ONLY=1`: the held pass alone, for a profiler.
                if std::env::var("COLLISION_BENCH_HELD_ONLY").is_ok() {
                    let (held, impulses) = pass(&m, &x0, &closing, 100, false, model);
                    println!("{name}: held {held:.0} µs, {:.1} force evaluations ({impulses} impulses)", held / force);
                    continue;
                }
                let (flat, _) = pass(&m, &flat_x, &fall, reps, false, model);
                let (anew, _) = pass(&m, &x0, &closing, reps, true, model);
                let (held, _) = pass(&m, &x0, &closing, reps, false, model);
                let (run, impulses) = run(&m, &x0, &closing, RUN_STEPS, model);
                println!(
                    "{:>9} {:>9} {:>9} {:>9.0} {:>7.2} {:>9.0} {:>8.1} {:>9.0} {:>8.1} {:>9.0} {:>8.1} {:>10}",
                    format!("{n}x{n}"),
                    name,
                    m.triangles.len(),
                    force,
                    flat / force,
                    anew,
                    anew / force,
                    held,
                    held / force,
                    run,
                    run / force,
                    impulses,
                );
            }
        }
    });
}

/// Steps of the `run` column.
const RUN_STEPS: usize = 20;
