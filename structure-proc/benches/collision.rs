//! Speed of the structure's collision pass (issue 24, item 7), as
//! `cargo bench -p structure-proc --bench collision`: on the cloth of
//! `scenarios/cloth-hanging.toml` at n × n nodes, one step of the pass
//! against one evaluation of the same cloth's force, measured side by side:
//!
//! - `flat`: the cloth as built, falling 0.1 mm in the step: the pass is
//!   the tree's refit and its cone test (no pair is tested);
//! - `crumpled`: the same cloth pleated like an accordion into layers 0.6
//!   of the layer apart, so every node has neighbours in proximity, each
//!   layer closing on the one below at 0.5 m/s: the pass stops thousands
//!   of approaches. Measured twice: with the candidates found anew (a
//!   run's first step) and held from the step before (every later step
//!   while the nodes stay within the boxes they were found for).
//!
//! It prints a table of medians: the force, the passes, their ratios to
//! the force, and the crumpled pass per n log n (flat as n grows if the cost
//! grows like n log n). Two threads, as a run uses them.
//! `COLLISION_BENCH_N=100` measures one size; `COLLISION_BENCH_HELD_ONLY=1`
//! times the crumpled cloth's held pass alone, 100 times, for a profiler.

mod common;

use common::cloth_section;
use std::time::Instant;
use structure_proc::collision::Contacts;
use structure_proc::forces::Loads;
use structure_proc::{build_model, Model};
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
fn pass(m: &Model, x0: &[f64], dx: &[f64], reps: usize, anew: bool) -> (f64, u64) {
    let spec = Collision::default();
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

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    pool.install(|| {
        println!("collision pass against the force, one step, 2 threads (medians)");
        println!(
            "{:>9} {:>9} {:>9} {:>9} {:>7} {:>11} {:>8} {:>11} {:>8} {:>13}",
            "cloth",
            "triangles",
            "force µs",
            "flat µs",
            "flat/F",
            "crump. µs",
            "crump/F",
            "held µs",
            "held/F",
            "crump/nlogn ns"
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
            let x0 = m.x.clone();
            let (flat, _) = pass(&m, &x0, &fall, reps, false);
            if std::env::var("COLLISION_BENCH_FLAT_ONLY").is_ok() {
                let (flat, _) = pass(&m, &x0, &fall, 400, false);
                println!("flat {flat:.0} µs");
                continue;
            }
            let layer = structure_section::collision::DEFAULT_THICKNESS;
            let gap = 0.6 * layer;
            pleat(&mut m, n, gap);
            let x0 = m.x.clone();
            // Each layer closes on the one below by CLOSING layers a step.
            let closing: Vec<f64> = (0..m.x.len())
                .map(|i| if i % 3 == 2 { -(x0[i] / gap).round() * CLOSING * layer } else { 0.0 })
                .collect();
            // `COLLISION_BENCH_HELD_ONLY=1`: the held pass alone, for a profiler.
            if std::env::var("COLLISION_BENCH_HELD_ONLY").is_ok() {
                let (held, impulses) = pass(&m, &x0, &closing, 100, false);
                println!("held {held:.0} µs, {:.1} force evaluations ({impulses} impulses)", held / force);
                continue;
            }
            let (crumpled, impulses) = pass(&m, &x0, &closing, reps, true);
            let (held, _) = pass(&m, &x0, &closing, reps, false);
            let tris = m.triangles.len() as f64;
            println!(
                "{:>9} {:>9} {:>9.0} {:>9.0} {:>7.2} {:>11.0} {:>8.1} {:>11.0} {:>8.1} {:>13.2}   ({impulses} impulses a step)",
                format!("{n}x{n}"),
                m.triangles.len(),
                force,
                flat,
                flat / force,
                crumpled,
                crumpled / force,
                held,
                held / force,
                crumpled * 1e3 / (tris * tris.ln()),
            );
        }
    });
}
