//! `study`, run as `coupler study …`: integrators compared by error against
//! CPU time. A thin command line over the `study` library.

use clap::{Args, Parser, Subcommand};
use coupler::scenario::structure::Integrator;
use std::path::PathBuf;
use study::{accuracy, plot, reference, report};

/// Exit code for bad input, as the coupler's.
const EXIT_BAD_INPUT: i32 = 2;

#[derive(Parser)]
#[command(
    name = "coupler study",
    bin_name = "coupler study",
    about = "Compare canopy's time integrators: error against run time"
)]
struct Cli {
    #[command(subcommand)]
    what: What,
}

#[derive(Subcommand)]
enum What {
    /// Every integrator over a ladder of time steps on a reference system with
    /// an exact solution: CSV, work-precision plot (PNG, SVG) and a Markdown
    /// table of measured orders and the CPU time to reach an error.
    Accuracy(AccuracyArgs),
}

#[derive(Args)]
struct AccuracyArgs {
    /// Reference system: damped-oscillator, oscillator, pendulum or spring-pendulum.
    #[arg(long, default_value = "damped-oscillator")]
    system: String,
    /// Integrators to compare, comma-separated scenario names (default: all).
    #[arg(long, value_delimiter = ',')]
    integrators: Vec<String>,
    /// Largest time step [s]; must divide the error sampling interval (0.5 s).
    #[arg(long, default_value_t = 0.125)]
    dt_max: f64,
    /// Number of steps on the ladder, each half the one before.
    #[arg(long, default_value_t = 13)]
    levels: u32,
    /// Error whose CPU cost the table reports.
    #[arg(long, default_value_t = 1e-4)]
    target_error: f64,
    /// Study directory (default: studies/accuracy-<system>).
    #[arg(long)]
    out: Option<PathBuf>,
}

fn main() {
    let cli = Cli::parse();
    let code = match cli.what {
        What::Accuracy(a) => accuracy_study(a),
    };
    std::process::exit(code);
}

fn bad_input(msg: String) -> i32 {
    eprintln!("error: {msg}");
    EXIT_BAD_INPUT
}

fn accuracy_study(a: AccuracyArgs) -> i32 {
    let Some(system) = reference::by_name(&a.system) else {
        let names: Vec<&str> = reference::all().iter().map(|r| r.name()).collect();
        return bad_input(format!(
            "--system {}: no such reference system (choose one of {})",
            a.system,
            names.join(", ")
        ));
    };
    let mut integrators = Vec::new();
    for name in &a.integrators {
        match Integrator::ALL.iter().find(|i| i.name() == name) {
            Some(i) => integrators.push(*i),
            None => {
                let names: Vec<&str> = Integrator::ALL.iter().map(|i| i.name()).collect();
                return bad_input(format!(
                    "--integrators: no integrator is called `{name}` (choose from {})",
                    names.join(", ")
                ));
            }
        }
    }
    if integrators.is_empty() {
        integrators = Integrator::ALL.to_vec();
    }
    let per_sample = system.sample_interval() / a.dt_max;
    if !(a.dt_max > 0.0
        && per_sample >= 1.0 - 1e-9
        && (per_sample - per_sample.round()).abs() < 1e-9)
    {
        return bad_input(format!(
            "--dt-max {}: must divide the sampling interval {} s (e.g. 0.125)",
            a.dt_max,
            system.sample_interval()
        ));
    }
    if !(1..=20).contains(&a.levels) {
        return bad_input(format!("--levels {}: must lie in 1..=20", a.levels));
    }
    if !(a.target_error > 0.0 && a.target_error.is_finite()) {
        return bad_input(format!("--target-error {}: must be > 0", a.target_error));
    }
    let out = a
        .out
        .unwrap_or_else(|| PathBuf::from(format!("studies/accuracy-{}", system.name())));
    if let Err(e) = std::fs::create_dir_all(&out) {
        return bad_input(format!(
            "cannot create the study directory {}: {e}",
            out.display()
        ));
    }
    let steps = accuracy::ladder(a.dt_max, a.levels);
    eprintln!(
        "study accuracy: {} integrators × {} steps on `{}`",
        integrators.len(),
        steps.len(),
        system.name()
    );
    let runs = accuracy::sweep(system.as_ref(), &integrators, &steps, |r| {
        eprintln!(
            "  {:<30} dt = {:<10.3e} error = {:<10.3e} cpu = {:.3e} s  {}",
            r.integrator.name(),
            r.dt,
            r.error,
            r.cpu_seconds,
            r.status.label()
        );
    });
    let summaries = accuracy::summarise(&runs, a.target_error);
    let table = report::markdown(system.as_ref(), &summaries, &steps, a.target_error);
    let written = std::fs::write(out.join("accuracy.csv"), report::csv(&runs))
        .and_then(|_| std::fs::write(out.join("accuracy.md"), &table));
    if let Err(e) = written {
        eprintln!("error: cannot write into {}: {e}", out.display());
        return 1;
    }
    let title = format!("Work precision: {}", system.name());
    if let Err(e) = plot::work_precision(
        &runs,
        &title,
        &out.join("work-precision.png"),
        &out.join("work-precision.svg"),
    ) {
        eprintln!("error: cannot draw the work-precision plot: {e}");
        return 1;
    }
    println!("{table}");
    println!(
        "wrote {0}/accuracy.csv, {0}/accuracy.md, {0}/work-precision.png and .svg",
        out.display()
    );
    0
}
