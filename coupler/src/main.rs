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
        #[arg(required_unless_present = "restart")]
        scenario: Option<PathBuf>,
        /// Run directory, new or empty (default: runs/<scene>-<run id>).
        #[arg(long)]
        out: Option<PathBuf>,
        /// Go on with the stopped, failed or killed run in this directory
        /// from its last complete run checkpoint (`[run] checkpoint_interval`).
        #[arg(long, value_name = "RUN_DIR", conflicts_with_all = ["scenario", "out"])]
        restart: Option<PathBuf>,
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
        #[command(subcommand)]
        peer: PeerCmd,
    },
}

#[derive(Subcommand)]
enum BenchCmd {
    /// Field round trip of 10³…10⁶ values (median, p99) four ways, and the
    /// exchange share of coupled scenes.
    Exchange {
        #[arg(long, default_value_t = 2000)]
        rounds: usize,
        /// Scenes whose exchange share of wall time is measured (repeat the
        /// flag for several; default: canopy-porous, pendulum, c9-drop-body).
        #[arg(long = "scene")]
        scenes: Vec<PathBuf>,
        /// Only the round trips, no scene.
        #[arg(long)]
        no_scenes: bool,
        /// Runs of each scene, quiet and beside the busy process in turn;
        /// each column is the run of median wall time.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
    },
    /// An implicit window's cost against an explicit one's on a scene both
    /// run, and the share of checkpoints and relaxation.
    Implicit {
        /// The scene (default scenarios/sheet-updraft.toml).
        #[arg(long, default_value = "scenarios/sheet-updraft.toml")]
        scene: PathBuf,
        /// Runs of each scheme; the fastest is kept.
        #[arg(long, default_value_t = 3)]
        repeats: usize,
    },
    /// What the structure's contact pass costs a run of an open canopy:
    /// the scene with and without `[structure.collision]`, in turn.
    Contact {
        /// The scene (default scenarios/c9-drop.toml).
        #[arg(long, default_value = "scenarios/c9-drop.toml")]
        scene: PathBuf,
        /// Simulated end of each run [s] (default: before c9-drop's lines
        /// and folds first touch, at 2.2 s).
        #[arg(long, default_value_t = 2.0)]
        end_time: f64,
        /// The contact layer's thickness [m].
        #[arg(long, default_value_t = 5e-3)]
        layer: f64,
        /// Runs of each variant, in turn; the medians are compared.
        #[arg(long, default_value_t = 5)]
        repeats: usize,
    },
    /// The C-9 on the original code's grid (60 × 60 × 120 cells, 11 173
    /// canopy vertices): seconds per window, explicit, implicit and
    /// parallel-implicit, split into the solvers, acceleration, checkpoints
    /// and waiting; FronTier++'s step beside them.
    Parachute {
        /// The scene (default scenarios/c9-frontier-grid.toml).
        #[arg(long, default_value = "scenarios/c9-frontier-grid.toml")]
        scene: PathBuf,
        /// Windows each variant runs (and FronTier++'s steps).
        #[arg(long, default_value_t = 4)]
        windows: u32,
        /// FronTier++'s `airfoil` executable (shared/peers/frontier/build.sh
        /// builds it): its own C-9 then runs right after, on one process.
        #[arg(long)]
        frontier: Option<PathBuf>,
        /// FronTier++'s C-9 input.
        #[arg(long, default_value = "../shared/peers/frontier/in-C9")]
        frontier_input: PathBuf,
        /// "gpu": the scene on the CPU and with both solvers on the GPU
        /// (issue 47), instead of the three CPU variants.
        #[arg(long, default_value = "cpu", value_parser = ["cpu", "gpu"])]
        device: String,
    },
}

#[derive(Subcommand)]
enum PeerCmd {
    /// A participant of the bench's two-participant run.
    Library {
        #[arg(long)]
        rounds: usize,
    },
    /// iceoryx2 with a copy at each end.
    Copy {
        #[arg(long)]
        run_id: String,
        #[arg(long)]
        rounds: usize,
    },
    /// A Unix socket with bincode.
    Socket {
        #[arg(long)]
        path: PathBuf,
        #[arg(long)]
        rounds: usize,
    },
}

/// The scenes `bench exchange` measures by default: fluid and structure,
/// impulse sub-steps, and three processes.
const BENCH_SCENES: [&str; 3] = [
    "scenarios/canopy-porous.toml",
    "scenarios/pendulum.toml",
    "scenarios/c9-drop-body.toml",
];

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
        Cmd::Run {
            restart: Some(run_dir),
            ..
        } => launcher::restart::run(&run_dir),
        Cmd::Run {
            scenario: Some(scenario),
            out,
            ..
        } => launcher::run::run(&scenario, out),
        Cmd::Run { .. } => unreachable!("clap requires a scenario or --restart"),
        Cmd::Check { scenario } => launcher::check(&scenario),
        Cmd::Bench {
            what:
                BenchCmd::Exchange {
                    rounds,
                    mut scenes,
                    no_scenes,
                    repeats,
                },
        } => {
            if scenes.is_empty() && !no_scenes {
                scenes = BENCH_SCENES.iter().map(PathBuf::from).collect();
            }
            launcher::bench::exchange(rounds.max(10), &scenes, repeats.max(1))
        }
        Cmd::Bench {
            what: BenchCmd::Implicit { scene, repeats },
        } => launcher::bench::implicit(&scene, repeats.max(1)),
        Cmd::Bench {
            what:
                BenchCmd::Contact {
                    scene,
                    end_time,
                    layer,
                    repeats,
                },
        } => launcher::bench::contact(&scene, end_time, layer, repeats.max(1)),
        Cmd::Bench {
            what:
                BenchCmd::Parachute {
                    scene,
                    windows,
                    frontier,
                    frontier_input,
                    device,
                },
        } => {
            let peer = frontier.as_deref().map(|f| (f, frontier_input.as_path()));
            launcher::bench::parachute(&scene, windows.max(1), peer, device == "gpu")
        }
        Cmd::Study { args } => launcher::study::study(&args),
        Cmd::BenchPeer { peer } => match peer {
            PeerCmd::Library { rounds } => launcher::bench::library_peer(rounds),
            PeerCmd::Copy { run_id, rounds } => launcher::bench::copy_peer(&run_id, rounds),
            PeerCmd::Socket { path, rounds } => launcher::bench::socket_peer(&path, rounds),
        },
    };
    std::process::exit(code);
}
