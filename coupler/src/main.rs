//! `coupler`: check and run canopy scenarios.

use clap::{Parser, Subcommand};
use coupler::launcher;
use std::path::PathBuf;

#[derive(Parser)]
#[command(
    name = "coupler",
    version,
    about = "canopy: launch and couple parachute FSI solvers"
)]
struct Cli {
    #[command(subcommand)]
    command: Cmd,
}

#[derive(Subcommand)]
enum Cmd {
    /// Run a scenario: start its participants, couple them to the end time, write a run directory.
    Run {
        scenario: PathBuf,
        /// Run directory, new or empty (default: runs/<scene>-<run id>).
        #[arg(long)]
        out: Option<PathBuf>,
    },
    /// Check a scenario without running it, and estimate its stable structure step.
    Check { scenario: PathBuf },
    /// Benchmarks that print a table.
    Bench {
        #[command(subcommand)]
        what: BenchCmd,
    },
    /// Integrator studies: `coupler study accuracy …` (see `coupler study --help`).
    #[command(disable_help_flag = true)]
    Study {
        /// Arguments for the `study` executable.
        #[arg(trailing_var_arg = true, allow_hyphen_values = true)]
        args: Vec<String>,
    },
    /// The other end of `bench exchange` (started by it).
    #[command(hide = true)]
    BenchPeer {
        #[arg(long)]
        run_id: String,
        /// Copy every value back (for bit-exactness checks).
        #[arg(long)]
        echo: bool,
    },
}

#[derive(Subcommand)]
enum BenchCmd {
    /// Field round trip of 10³…10⁶ values (median, p99) and the exchange share of a scene.
    Exchange {
        #[arg(long, default_value_t = 2000)]
        rounds: usize,
        /// Scene whose exchange share of wall time is measured.
        #[arg(long, default_value = "scenarios/canopy-porous.toml")]
        scene: PathBuf,
    },
}

fn main() {
    let cli = match Cli::try_parse() {
        Ok(c) => c,
        Err(e) => {
            let code = if e.use_stderr() {
                launcher::EXIT_BAD_INPUT
            } else {
                0
            };
            let _ = e.print();
            std::process::exit(code);
        }
    };
    let code = match cli.command {
        Cmd::Run { scenario, out } => launcher::run::run(&scenario, out),
        Cmd::Check { scenario } => launcher::check(&scenario),
        Cmd::Bench {
            what: BenchCmd::Exchange { rounds, scene },
        } => launcher::bench::exchange(rounds.max(10), Some(&scene)),
        Cmd::Study { args } => launcher::study::study(&args),
        Cmd::BenchPeer { run_id, echo } => launcher::bench::peer(&run_id, echo),
    };
    std::process::exit(code);
}
