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
//! size; `IMPLICIT_BENCH_NO_CG=1` leaves out conjugate gradients. Multigrid
//! (`linear_solver = "multigrid"`) runs beside them.

mod common;

use common::cloth_section;
use std::time::Instant;
use structure_proc::forces::Loads;
use structure_proc::{build_model, integrator, Model};
use structure_section::LinearSolver;

/// Backward-Euler steps from `m` with a new stepper: the first step's time
/// (a Cholesky run factorizes there), the mean of the `steps` after it
/// (where it solves by conjugate gradients preconditioned with a kept
/// factorization or hierarchy, made anew when they stall) [s], and the mean
/// time of a Newton iteration's linear solve over those steps [s].
fn steps(m: &Model, solver: LinearSolver, n: u32, dt: f64, steps: usize) -> (f64, f64, f64) {
    let mut section = cloth_section(n).0;
    section.newton.linear_solver = solver;
    let mut stepper = integrator(section.scheme());
    let mut m = m.clone();
    let mut step = |stepper: &mut Box<dyn structure_proc::Integrator>| {
        let start = Instant::now();
        m.step(stepper.as_mut(), &Loads::default(), dt)
            .expect("step");
        start.elapsed().as_secs_f64()
    };
    let first = step(&mut stepper);
    let before = stepper.linear_solves().expect("an implicit scheme");
    let rest: f64 = (0..steps).map(|_| step(&mut stepper)).sum();
    let after = stepper.linear_solves().expect("an implicit scheme");
    let per_solve = (after.1 - before.1) / (after.0 - before.0).max(1) as f64;
    (first, rest / steps as f64, per_solve)
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
    let mut solvers = vec![LinearSolver::Cholesky, LinearSolver::Multigrid];
    if with_cg {
        solvers.insert(0, LinearSolver::Cg);
    }
    println!("backward-Euler steps of the membrane cloth, 2 threads: the first, the mean of the 10 after it,");
    println!("and the mean linear solve of a Newton iteration over those [ms]");
    print!("{:>8}", "nodes");
    for solver in &solvers {
        let name = format!("{solver:?}");
        print!(
            " {:>16} {:>15} {:>16}",
            name.clone() + " first",
            name.clone() + " next",
            name + " solve"
        );
    }
    println!(" {:>18}", "solve/(n ln n) ns");
    let mut rows: Vec<(f64, Vec<(f64, f64)>)> = Vec::new();
    pool.install(|| {
        for n in sizes {
            let (m, dt) = falling(n);
            let nodes = m.nodes() as f64;
            print!("{:>8}", m.nodes());
            let mut next = Vec::new();
            for &solver in &solvers {
                let (first, mean, solve) = steps(&m, solver, n, dt, 10);
                print!(
                    " {:>16.1} {:>15.1} {:>16.2}",
                    first * 1e3,
                    mean * 1e3,
                    solve * 1e3
                );
                next.push((mean, solve));
            }
            let per = next
                .iter()
                .map(|t| format!("{:.0}", t.1 * 1e9 / (nodes * nodes.ln())));
            println!(" {:>18}", per.collect::<Vec<_>>().join(" / "));
            rows.push((nodes, next));
        }
    });
    if let (Some(first), Some(last)) = (rows.first(), rows.last()) {
        if rows.len() > 1 {
            let growth = |a: f64, b: f64| (b / a).ln() / (last.0 / first.0).ln();
            println!(
                "growth exponents from {} to {} nodes (n log n over this range: {:.2}):",
                first.0,
                last.0,
                growth(first.0 * first.0.ln(), last.0 * last.0.ln())
            );
            for (k, solver) in solvers.iter().enumerate() {
                println!(
                    "  {solver:?}: a step {:.2}, a linear solve {:.2}",
                    growth(first.1[k].0, last.1[k].0),
                    growth(first.1[k].1, last.1[k].1)
                );
            }
        }
    }
}
