//! `coupler bench exchange`: what exchanging a field costs, and what share
//! of a coupled scene's wall time the coupling takes.
//!
//! The round trips run between two processes, each a `coupler bench-peer`,
//! all measured in the same run so that the ways of moving data compare on
//! the same machine state:
//!
//! - the participant library, the values left untouched (only the first
//!   and last are stamped and checked): the exchange itself;
//! - the participant library, every value written into the loan by the
//!   sender and read in place by the receiver: what a solver pays;
//! - iceoryx2 with a copy at each end (the sender copies its values into
//!   the loan, the receiver copies them out before reading them);
//! - a Unix socket carrying the values encoded with bincode.
//!
//! The scene rows run `coupler run` and read the manifest's
//! `coupling.exchange_share`: the share of the coupled run's wall time in
//! which no participant computes, run as the machine is and beside a busy
//! process (a user's other work: a coupled run must not spin against it),
//! in turn, `--repeats` times each: each column is the run of median wall
//! time (this machine's timings move by 2× from one run to the next).
//! Beside it, the floor: the share that the same number of hand-offs would
//! take if each cost no more than moving one cache line from core to core
//! ([`floor`]), measured in the same run.

mod contact;
mod floor;
mod frontier;
mod implicit;
mod library;
mod parachute;
mod pingpong;
mod raw;
mod socket;

pub use contact::contact;
pub use implicit::implicit;
pub use library::peer as library_peer;
pub use parachute::parachute;
pub use raw::peer as copy_peer;
pub use socket::peer as socket_peer;

use std::path::{Path, PathBuf};

/// Values per field in the round-trip table.
pub const SIZES: [usize; 4] = [1_000, 10_000, 100_000, 1_000_000];

/// Median and 99th percentile of one row's round trips [µs].
#[derive(Debug, Clone, Copy)]
pub struct Times {
    pub median_us: f64,
    pub p99_us: f64,
}

/// `coupler bench exchange`: prints the tables; returns the exit code.
pub fn exchange(rounds: usize, scenes: &[PathBuf], repeats: usize) -> i32 {
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the coupler executable: {e}");
            return 1;
        }
    };
    println!("field round trip between two processes, {rounds} rounds per size (after a tenth as many to warm up)");
    let measured = library::columns(&exe, rounds).and_then(|[ends, every]| {
        Ok([
            ("library, untouched", ends),
            ("library, written+read", every),
            ("iceoryx2 + 2 copies", raw::rows(&exe, rounds)?),
            ("socket + bincode", socket::rows(&exe, rounds)?),
        ])
    });
    match measured {
        Ok(table) => print_table(&table),
        Err(e) => {
            eprintln!("error: {e}");
            return 1;
        }
    }
    let floor_us = floor::round_trip_us();
    match floor_us {
        Some(us) => println!(
            "floor: one cache line from core to core and back (two threads on atomics): {us:.3} µs"
        ),
        None => println!("floor: not measured (one core)"),
    }
    match beside_a_busy_process(|| Ok(floor::sleeping_round_trip_us())) {
        Ok(Some(us)) => println!(
            "floor beside one busy process, where nobody spins: a hand-off there and back between two processes sleeping on a futex: {us:.2} µs"
        ),
        Ok(None) => println!("floor beside one busy process: not measured (no shared page or no fork)"),
        Err(e) => println!("floor beside one busy process: not measured ({e})"),
    }
    if !scenes.is_empty() {
        println!();
        println!("exchange share of a coupled run: time inside the library's calls and between a value's sending and its");
        println!("waiting reader seeing it, summed over participants, against the coupled run's wall time (from start to finish);");
        println!("floor: the share its hand-offs (values read) would take at half the cache-line round trip each;");
        println!("busy: the same run again right after, beside one busy process (`sh -c 'while :; do :; done'`);");
        println!("{repeats} runs of each, in turn; each column is the run of median wall time");
        println!(
            "{:<34} {:>8} {:>8} {:>10} {:>10} {:>10} {:>9} {:>7} {:>7} {:>8} {:>7} {:>7}",
            "scene",
            "wall s",
            "run s",
            "compute s",
            "exchange s",
            "latency s",
            "hand-offs",
            "share",
            "floor",
            "busy s",
            "share",
            "× quiet"
        );
    }
    for scene in scenes {
        match scene_rows(&exe, scene, floor_us.unwrap_or(f64::NAN), repeats) {
            Ok(line) => println!("{line}"),
            Err(e) => {
                eprintln!("error: {}: {e}", scene.display());
                return 1;
            }
        }
    }
    0
}

fn print_table(table: &[(&str, Vec<Times>)]) {
    let mut head = format!("{:>10}", "values");
    let mut sub = format!("{:>10}", "");
    for (name, _) in table {
        head.push_str(&format!(" {name:>23}"));
        sub.push_str(&format!(" {:>11} {:>11}", "median µs", "p99 µs"));
    }
    println!("{head}\n{sub}");
    for (i, n) in SIZES.iter().enumerate() {
        let mut line = format!("{n:>10}");
        for (_, rows) in table {
            line.push_str(&format!(
                " {:>11.1} {:>11.1}",
                rows[i].median_us, rows[i].p99_us
            ));
        }
        println!("{line}");
    }
}

/// Run `scene` with the coupler `exe` into a scratch directory, removed
/// after; its manifest, or why the run failed.
pub(super) fn run_manifest(exe: &Path, scene: &Path) -> Result<serde_json::Value, String> {
    run_reading(exe, scene, None).map(|(m, _)| m)
}

/// [`run_manifest`], with the text of the run directory's file `file`
/// (empty if it has none) read before the directory goes.
pub(super) fn run_reading(
    exe: &Path,
    scene: &Path,
    file: Option<&str>,
) -> Result<(serde_json::Value, String), String> {
    let dir = std::env::temp_dir().join(format!(
        "canopy-bench-{}",
        participant::supervisor::new_run_id()
    ));
    let status = std::process::Command::new(exe)
        .arg("run")
        .arg(scene)
        .arg("--out")
        .arg(&dir)
        .stderr(std::process::Stdio::null())
        .status()
        .map_err(|e| format!("cannot run it: {e}"))?;
    let manifest = std::fs::read_to_string(dir.join("manifest.json"))
        .ok()
        .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
    let read = file
        .and_then(|f| std::fs::read_to_string(dir.join(f)).ok())
        .unwrap_or_default();
    let _ = std::fs::remove_dir_all(&dir);
    match (status.success(), manifest) {
        (true, Some(m)) => Ok((m, read)),
        (false, Some(m)) => Err(format!(
            "the run failed: {}",
            m["error"].as_str().unwrap_or("(no reason in its manifest)")
        )),
        _ => Err("the run failed before it wrote its manifest".into()),
    }
}

/// A scene's row: its runs on the machine as it is and beside a busy
/// process, in turn, `repeats` times each; the run of median wall time of
/// each kind.
fn scene_rows(exe: &Path, scene: &Path, floor_us: f64, repeats: usize) -> Result<String, String> {
    let wall = |m: &serde_json::Value| m["coupler"]["wall_s"].as_f64().unwrap_or(f64::NAN);
    let (mut quiet, mut busy) = (Vec::new(), Vec::new());
    for _ in 0..repeats {
        quiet.push(run_manifest(exe, scene)?);
        busy.push(beside_a_busy_process(|| run_manifest(exe, scene))?);
    }
    let median = |mut runs: Vec<serde_json::Value>| {
        runs.sort_by(|a, b| wall(a).total_cmp(&wall(b)));
        runs.swap_remove(runs.len() / 2)
    };
    let (quiet, busy) = (median(quiet), median(busy));
    let share =
        |m: &serde_json::Value| m["coupling"]["exchange_share"].as_f64().unwrap_or(f64::NAN);
    Ok(format!(
        "{} {:>8.3} {:>6.2}% {:>7.2}",
        scene_share(scene, &quiet, floor_us),
        wall(&busy),
        100.0 * share(&busy),
        wall(&busy) / wall(&quiet)
    ))
}

/// Run `f` while one process spins on a core (a user's other work),
/// stopped after.
fn beside_a_busy_process<T>(f: impl FnOnce() -> Result<T, String>) -> Result<T, String> {
    let mut busy = std::process::Command::new("sh")
        .args(["-c", "while :; do :; done"])
        .spawn()
        .map_err(|e| format!("cannot start a busy process (sh): {e}"))?;
    let result = f();
    let _ = busy.kill();
    let _ = busy.wait();
    result
}

fn scene_share(scene: &Path, m: &serde_json::Value, floor_us: f64) -> String {
    let f = |v: &serde_json::Value| v.as_f64().unwrap_or(f64::NAN);
    let c = &m["coupling"];
    let reads = c["reads"].as_u64().unwrap_or(0);
    let floor = reads as f64 * 0.5 * floor_us * 1e-6 / f(&c["run_s"]);
    format!(
        "{:<34} {:>8.3} {:>8.3} {:>10.3} {:>10.3} {:>10.3} {:>9} {:>6.2}% {:>6.2}%",
        scene.display(),
        f(&m["coupler"]["wall_s"]),
        f(&c["run_s"]),
        f(&c["compute_s"]),
        f(&c["exchange_s"]),
        f(&c["latency_s"]),
        reads,
        100.0 * f(&c["exchange_share"]),
        100.0 * floor
    )
}
