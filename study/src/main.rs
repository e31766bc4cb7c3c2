//! `study`, run as `coupler study …`: integrators compared by error against
//! CPU time. A thin command line over the `study` library.

use clap::{Args, Parser, Subcommand};
use std::path::{Path, PathBuf};
use structure_section::Integrator;
use study::{accuracy, plot, reference, report, scene, stability};

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
    /// Reference system: damped-oscillator (default), oscillator, pendulum or spring-pendulum.
    #[arg(long)]
    system: Option<String>,
    /// Integrators to compare, comma-separated scenario names (default: all).
    #[arg(long, value_delimiter = ',')]
    integrators: Vec<String>,
    /// Largest time step [s]; must divide the error sampling interval (0.5 s).
    #[arg(long, default_value_t = 0.125)]
    dt_max: f64,
    /// Number of steps on the ladder, each half the one before (default 13;
    /// 5 for a scenario).
    #[arg(long)]
    levels: Option<u32>,
    /// Study a scenario instead of a reference system: each run goes through
    /// `coupler run`, its structure step halved from the scenario's own, and
    /// is compared with an RK4 run at a step 2³ times smaller than the smallest.
    #[arg(long, conflicts_with = "system")]
    scenario: Option<PathBuf>,
    /// With --scenario: simulate only up to this time [s].
    #[arg(long, requires = "scenario")]
    end_time: Option<f64>,
    /// Error whose CPU cost the table reports.
    #[arg(long, default_value_t = 1e-4)]
    target_error: f64,
    /// Study directory (default: studies/accuracy-<system or scene>).
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
    let levels = a
        .levels
        .unwrap_or(if a.scenario.is_some() { 5 } else { 13 });
    if !(1..=20).contains(&levels) {
        return bad_input(format!("--levels {levels}: must lie in 1..=20"));
    }
    if !(a.target_error > 0.0 && a.target_error.is_finite()) {
        return bad_input(format!("--target-error {}: must be > 0", a.target_error));
    }
    let integrators = match integrators(&a.integrators) {
        Ok(i) => i,
        Err(code) => return code,
    };
    if let Some(path) = &a.scenario {
        return scenario_study(&a, path, &integrators, levels);
    }
    let name = a.system.as_deref().unwrap_or("damped-oscillator");
    let Some(system) = reference::by_name(name) else {
        let names: Vec<&str> = reference::all().iter().map(|r| r.name()).collect();
        return bad_input(format!(
            "--system {name}: no such reference system (choose one of {})",
            names.join(", ")
        ));
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
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("studies/accuracy-{}", system.name())));
    if let Err(code) = study_dir(&out) {
        return code;
    }
    let steps = accuracy::ladder(a.dt_max, levels);
    eprintln!(
        "study accuracy: {} integrators × {} steps on `{}`",
        integrators.len(),
        steps.len(),
        system.name()
    );
    let runs = accuracy::sweep(system.as_ref(), &integrators, &steps, print_run);
    let setup = report::reference_setup(system.as_ref(), &steps);
    write_accuracy(&out, system.name(), &setup, &runs, a.target_error)
}

/// A progress line for one run.
fn print_run(r: &accuracy::Run) {
    eprintln!(
        "  {:<30} dt = {:<10.3e} error = {:<10.3e} cpu = {:.3e} s  {}",
        r.integrator.name(),
        r.dt,
        r.error,
        r.cpu_seconds,
        r.status.label()
    );
}

/// `coupler study accuracy --scenario PATH`.
fn scenario_study(a: &AccuracyArgs, path: &Path, integrators: &[Integrator], levels: u32) -> i32 {
    let probe = match scene::ScenarioStudy::new(path, Path::new("."), a.end_time) {
        Ok(s) => s,
        Err(e) => return bad_input(e),
    };
    let out = a
        .out
        .clone()
        .unwrap_or_else(|| PathBuf::from(format!("studies/accuracy-{}", probe.name())));
    if let Err(code) = study_dir(&out) {
        return code;
    }
    let study = scene::ScenarioStudy {
        dir: out.clone(),
        ..probe
    };
    let base = study.structure.substeps as u64;
    let finest = base << (levels - 1 + scene::REFERENCE_HALVINGS);
    if finest as f64 > scenario::MAX_SUBSTEPS {
        return bad_input(format!(
            "--levels {levels}: the reference would need {finest} sub-steps per window, more than {}",
            scenario::MAX_SUBSTEPS
        ));
    }
    let finest = finest as u32;
    let substeps: Vec<u32> = (0..levels).map(|l| (base as u32) << l).collect();
    eprintln!(
        "study accuracy: {} integrators × {} steps on scenario `{}`; reference {} at Δt_s = {:e} s",
        integrators.len(),
        substeps.len(),
        study.name(),
        scene::REFERENCE.name(),
        study.step(finest)
    );
    let result = study
        .reference(finest)
        .and_then(|r| study.sweep(integrators, &substeps, &r, print_run));
    let runs = match result {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: {e}");
            return 1;
        }
    };
    let steps: Vec<f64> = substeps.iter().map(|&n| study.step(n)).collect();
    let damping = Some(study.structure.damping);
    let caveat = if damping == Some(structure_section::Damping::RelativeVelocity) {
        "- **Caveat:** the scenario's damping = \"relative-velocity\" is thesis eq. (68), c = k·Δt_s: the model itself changes with the step, so every scheme's error includes that change and converges at first order at best.\n"
    } else {
        ""
    };
    if !caveat.is_empty() {
        eprintln!("warning: damping = \"relative-velocity\" scales with Δt_s (thesis eq. 68): the errors include the model's change with the step");
    }
    let setup = format!(
        "- Scenario: {} ({} s simulated, coupling window {} s), every run through `coupler run`.\n- Error: {}.\n- Reference: {} at Δt_s = {:e} s ({} sub-steps per window).\n- Steps: Δt_s = {:e} s down to {:e} s, halving; an adaptive scheme runs at the scenario's own step with tolerances from {:e} down to {:e}.\n- CPU time: the structure process's, from each run's manifest.\n",
        study.path.display(),
        study.scenario.run.end_time - study.scenario.run.start_time,
        study.scenario.coupling.window,
        scene::ERROR_MEASURE,
        scene::REFERENCE.name(),
        study.step(finest),
        finest,
        steps[0],
        steps[steps.len() - 1],
        accuracy::ADAPTIVE_TOLERANCES.0,
        accuracy::ADAPTIVE_TOLERANCES.1,
    ) + caveat;
    write_accuracy(&out, study.name(), &setup, &runs, a.target_error)
}

/// Write the CSV, the Markdown table and the work-precision plot into `out`.
fn write_accuracy(out: &Path, name: &str, setup: &str, runs: &[accuracy::Run], target: f64) -> i32 {
    let summaries = accuracy::summarise(runs, target);
    let table = report::markdown(name, setup, &summaries, target);
    let written = std::fs::write(out.join("accuracy.csv"), report::csv(runs))
        .and_then(|_| std::fs::write(out.join("accuracy.md"), &table));
    if let Err(e) = written {
        eprintln!("error: cannot write into {}: {e}", out.display());
        return 1;
    }
    let title = format!("Work precision: {name}");
    if let Err(e) = plot::work_precision(
        runs,
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
