//! The implicit solve's growth with the node count (issue 25, item 5), as
//! `cargo bench -p structure-proc --bench implicit`: one backward-Euler step
//! of `scenarios/cloth-hanging.toml`'s membrane cloth (its 2 ms window, 20
//! times the explicit limit) on n × n nodes from 529 to 50 176, its Newton
//! systems solved by conjugate gradients and by the sparse Cholesky
//! factorization (`[structure.newton] linear_solver`), side by side in one
//! run on two threads. Each size starts from the cloth 5 steps into its
//! fall and takes 11 steps with a new stepper. It prints the first step
//! (a Cholesky run factorizes there) and the mean of the 10 after it (what
//! a run pays), their ratio, the time per n·log n (flat where the cost
//! grows like n log n), and the growth exponents between the smallest and
//! the largest size. `IMPLICIT_BENCH_N=100` measures one
//! size; `IMPLICIT_BENCH_NO_CG=1` leaves out conjugate gradients.

mod common;

use common::cloth_section;
use std::time::Instant;
use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, Model};
use structure_section::LinearSolver;

/// Backward-Euler steps from `m` with a new stepper: the first step's time
/// (a Cholesky run factorizes there) and the mean of the `steps` after it
/// (where it solves by conjugate gradients preconditioned with a kept
/// factorization, factorizing anew when they stall) [s].
fn steps(m: &Model, solver: LinearSolver, n: u32, dt: f64, steps: usize) -> (f64, f64) {
    let mut section = cloth_section(n).0;
    section.newton.linear_solver = solver;
    let mut stepper = integrator(section.scheme());
    let mut m = m.clone();
    let mut step = || {
        let start = Instant::now();
        m.step(stepper.as_mut(), &Loads::default(), dt)
            .expect("step");
        start.elapsed().as_secs_f64()
    };
    let first = step();
    let rest: f64 = (0..steps).map(|_| step()).sum();
    (first, rest / steps as f64)
}

/// The cloth on n × n nodes, 5 steps into its fall.
fn falling(n: u32) -> (Model, f64) {
    let (mut section, dt) = cloth_section(n);
    section.newton.linear_solver = LinearSolver::Cholesky;
    let mut m = build_model(&section, None, dt).expect("cloth builds");
    let mut stepper = integrator(section.scheme());
    for _ in 0..5 {
        m.step(stepper.as_mut(), &Loads::default(), dt)
            .expect("step");
    }
    (m, dt)
}

fn main() {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(2)
        .build()
        .unwrap();
    let with_cg = std::env::var_os("IMPLICIT_BENCH_NO_CG").is_none();
    let sizes: Vec<u32> = match std::env::var("IMPLICIT_BENCH_N") {
        Ok(n) => vec![n.parse().expect("IMPLICIT_BENCH_N is a node count a side")],
        Err(_) => vec![23, 50, 100, 160, 224],
    };
    println!("backward-Euler steps of the membrane cloth, 2 threads: the first, and the mean of the 10 after it");
    println!(
        "{:>8} {:>12} {:>12} {:>14} {:>14} {:>7} {:>18}",
        "nodes",
        "CG first ms",
        "CG next ms",
        "Chol. first ms",
        "Chol. next ms",
        "CG/Ch.",
        "Ch. next/nlogn ns"
    );
    let mut rows = Vec::new();
    pool.install(|| {
        for n in sizes {
            let (m, dt) = falling(n);
            let nodes = m.nodes() as f64;
            let direct = steps(&m, LinearSolver::Cholesky, n, dt, 10);
            let cg = with_cg.then(|| steps(&m, LinearSolver::Cg, n, dt, 10));
            let ms = |t: Option<f64>| t.map_or("—".into(), |t| format!("{:.1}", t * 1e3));
            println!(
                "{:>8} {:>12} {:>12} {:>14.1} {:>14.1} {:>7} {:>18.1}",
                m.nodes(),
                ms(cg.map(|c| c.0)),
                ms(cg.map(|c| c.1)),
                direct.0 * 1e3,
                direct.1 * 1e3,
                cg.map_or("—".into(), |c| format!("{:.1}", c.1 / direct.1)),
                direct.1 * 1e9 / (nodes * nodes.ln()),
            );
            rows.push((nodes, cg.map(|c| c.1), direct.1));
        }
    });
    if let (Some(first), Some(last)) = (rows.first(), rows.last()) {
        if rows.len() > 1 {
            let growth = |a: f64, b: f64| (b / a).ln() / (last.0 / first.0).ln();
            print!(
                "growth exponent of a step from {} to {} nodes: Cholesky {:.2}",
                first.0,
                last.0,
                growth(first.2, last.2)
            );
            if let (Some(a), Some(b)) = (first.1, last.1) {
                print!(", CG {:.2}", growth(a, b));
            }
            println!(
                " (n log n over this range: {:.2})",
                growth(first.0 * first.0.ln(), last.0 * last.0.ln())
            );
        }
    }
}
