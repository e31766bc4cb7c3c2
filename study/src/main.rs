//! `study`, run as `coupler study …`: integrators compared by error against
//! CPU time. A thin command line over the `study` library.

use clap::{Args, Parser, Subcommand};
use coupler::scenario::structure::Integrator;
use std::path::{Path, PathBuf};
use study::{accuracy, plot, reference, report, stability};

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
    /// Every integrator over a grid of spring stiffness and time step on a
    /// linear spring chain: a stable/unstable map (CSV, PNG, SVG) with the
    /// theoretical limits over it, and a Markdown table of the largest stable
    /// step measured against the predicted one.
    Stability(StabilityArgs),
}

#[derive(Args)]
struct StabilityArgs {
    /// Integrators to compare, comma-separated scenario names (default: all).
    #[arg(long, value_delimiter = ',')]
    integrators: Vec<String>,
    /// Smallest spring stiffness [N/m].
    #[arg(long, default_value_t = 1.0)]
    k_min: f64,
    /// Largest spring stiffness [N/m].
    #[arg(long, default_value_t = 1e6)]
    k_max: f64,
    /// Stiffness values, log-spaced.
    #[arg(long, default_value_t = 13)]
    k_count: usize,
    /// Smallest time step [s].
    #[arg(long, default_value_t = 1e-6)]
    dt_min: f64,
    /// Largest time step [s].
    #[arg(long, default_value_t = 1.0)]
    dt_max: f64,
    /// Time steps, log-spaced.
    #[arg(long, default_value_t = 25)]
    dt_count: usize,
    /// Study directory.
    #[arg(long, default_value = "studies/stability")]
    out: PathBuf,
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
        What::Stability(a) => stability_study(a),
    };
    std::process::exit(code);
}

fn bad_input(msg: String) -> i32 {
    eprintln!("error: {msg}");
    EXIT_BAD_INPUT
}

/// The integrators `names` call for; all when empty. Err: the exit code.
fn integrators(names: &[String]) -> Result<Vec<Integrator>, i32> {
    let mut out = Vec::new();
    for name in names {
        match Integrator::ALL.iter().find(|i| i.name() == name) {
            Some(i) => out.push(*i),
            None => {
                let all: Vec<&str> = Integrator::ALL.iter().map(|i| i.name()).collect();
                return Err(bad_input(format!(
                    "--integrators: no integrator is called `{name}` (choose from {})",
                    all.join(", ")
                )));
            }
        }
    }
    if out.is_empty() {
        out = Integrator::ALL.to_vec();
    }
    Ok(out)
}

/// Create the study directory `out`. Err: the exit code.
fn study_dir(out: &Path) -> Result<(), i32> {
    std::fs::create_dir_all(out).map_err(|e| {
        bad_input(format!(
            "cannot create the study directory {}: {e}",
            out.display()
        ))
    })
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
    let integrators = match integrators(&a.integrators) {
        Ok(i) => i,
        Err(code) => return code,
    };
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
    if let Err(code) = study_dir(&out) {
        return code;
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

fn stability_study(a: StabilityArgs) -> i32 {
    let mut integrators = match integrators(&a.integrators) {
        Ok(i) => i,
        Err(code) => return code,
    };
    // An adaptive scheme takes internal steps until its error holds: stable
    // at any outer step by construction, so the map says nothing about it.
    if let Some(i) = integrators.iter().find(|i| i.is_adaptive()) {
        if !a.integrators.is_empty() {
            return bad_input(format!(
                "--integrators: {} chooses its own steps, so it has no stability map",
                i.name()
            ));
        }
    }
    integrators.retain(|i| !i.is_adaptive());
    let range = |name: &str, lo: f64, hi: f64, count: usize| {
        if !(lo > 0.0 && hi >= lo && hi.is_finite()) {
            Err(bad_input(format!(
                "--{name}-min {lo}, --{name}-max {hi}: need 0 < min ≤ max < ∞"
            )))
        } else if !(1..=200).contains(&count) {
            Err(bad_input(format!(
                "--{name}-count {count}: must lie in 1..=200"
            )))
        } else {
            Ok(stability::log_grid(lo, hi, count))
        }
    };
    let (ks, dts) = match (
        range("k", a.k_min, a.k_max, a.k_count),
        range("dt", a.dt_min, a.dt_max, a.dt_count),
    ) {
        (Ok(k), Ok(d)) => (k, d),
        (Err(code), _) | (_, Err(code)) => return code,
    };
    if let Err(code) = study_dir(&a.out) {
        return code;
    }
    let chain = stability::Chain::default();
    eprintln!(
        "study stability: {} integrators × {} stiffnesses × {} steps",
        integrators.len(),
        ks.len(),
        dts.len()
    );
    let cells = stability::map(&chain, &integrators, &ks, &dts, |i, mine| {
        let stable = mine
            .iter()
            .filter(|c| matches!(c.outcome, stability::Outcome::Stable(_)))
            .count();
        eprintln!("  {:<30} {stable} of {} cells stable", i.name(), mine.len());
    });
    let limits = stability::limits(&chain, &cells);
    let table = report::stability_markdown(&chain, &limits, &ks, &dts);
    let out = &a.out;
    let written = std::fs::write(out.join("stability.csv"), report::stability_csv(&cells))
        .and_then(|_| std::fs::write(out.join("stability.md"), &table));
    if let Err(e) = written {
        eprintln!("error: cannot write into {}: {e}", out.display());
        return 1;
    }
    if let Err(e) = plot::stability_map(
        &chain,
        &cells,
        &limits,
        &out.join("stability-map.png"),
        &out.join("stability-map.svg"),
    ) {
        eprintln!("error: cannot draw the stability map: {e}");
        return 1;
    }
    println!("{table}");
    println!(
        "wrote {0}/stability.csv, {0}/stability.md, {0}/stability-map.png and .svg",
        out.display()
    );
    0
}
