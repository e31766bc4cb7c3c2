//! `coupler run --restart RUN_DIR`: a stopped, failed or killed run goes
//! on from its last complete run checkpoint (`[run] checkpoint_interval`;
//! the files are `participant::restart`'s). The run directory is brought
//! back to that window's end: `monitors.csv` keeps the rows up to it, and
//! the checkpoints after it are removed (they are written again). Each
//! participant rewrites its `.pvd` files as it resumes, and outputs after
//! the checkpoint are written again as the run reaches them.

use participant::restart;
use scenario::Scenario;
use std::path::{Path, PathBuf};
use std::time::Instant;

/// The scenario a restart of the run in `run_dir` reads: the file the run
/// was started from, when it is there still as the run's copy holds it
/// (so paths relative to its folder, a mesh or a program, resolve as they
/// did), else the run directory's copy.
fn restart_scenario(run_dir: &Path) -> PathBuf {
    let copy = run_dir.join("scenario.toml");
    let manifest = std::fs::read_to_string(run_dir.join("manifest.json")).unwrap_or_default();
    let original = serde_json::from_str::<serde_json::Value>(&manifest)
        .ok()
        .and_then(|m| m[super::run::SCENARIO_FILE].as_str().map(PathBuf::from));
    match original {
        Some(o) if o.is_file() && std::fs::read(&o).ok() == std::fs::read(&copy).ok() => o,
        _ => copy,
    }
}

/// `coupler run --restart RUN_DIR`: the run in `run_dir` goes on from its
/// last complete run checkpoint, with the scenario it was started with.
pub fn run(run_dir: &Path) -> i32 {
    if !run_dir.join("scenario.toml").is_file() {
        eprintln!(
            "error: {} is not a run directory: it has no scenario.toml",
            run_dir.display()
        );
        return super::EXIT_BAD_INPUT;
    }
    let checked = match super::load_checked(&restart_scenario(run_dir)) {
        Ok(c) => c,
        Err(problems) => return super::refuse(&problems),
    };
    super::warn(&checked);
    let started = Instant::now();
    let names: Vec<String> = checked.programs.iter().map(|(n, _)| n.clone()).collect();
    let window = match prepare(run_dir, &checked.scenario, &names) {
        Ok(w) => w,
        Err(e) => {
            eprintln!("error: {e}");
            return super::EXIT_BAD_INPUT;
        }
    };
    let (t, dt) = super::timing(&checked.scenario).window_span(window);
    eprintln!(
        "restarting {} from its run checkpoint at t = {} s (window {window})",
        run_dir.display(),
        t + dt
    );
    let run_dir = run_dir
        .canonicalize()
        .unwrap_or_else(|_| run_dir.to_path_buf());
    super::run::launch(
        &checked,
        &participant::supervisor::new_run_id(),
        &run_dir,
        Some(window),
        started,
    )
}

/// Where the restarted run in `run_dir` goes on: the window of its latest
/// complete run checkpoint whose monitor rows `monitors.csv` holds.
/// `names` are the run's participants. Leaves the directory as it was at
/// that window's end.
pub fn prepare(run_dir: &Path, scenario: &Scenario, names: &[String]) -> Result<u64, String> {
    let shown = run_dir.display();
    if finished(run_dir) {
        return Err(format!(
            "the run in {shown} completed: there is nothing to go on with"
        ));
    }
    let monitors = run_dir.join("monitors.csv");
    let rows = std::fs::read(&monitors)
        .map(|t| t.iter().filter(|&&b| b == b'\n').count().saturating_sub(1) as u64)
        .unwrap_or(0);
    // A checkpoint at the end of window w goes with the first w + 2 rows;
    // a participant completes its part only once the coupler has them on
    // disk, so every complete checkpoint has its rows.
    let complete = restart::complete(run_dir, names);
    let window = complete.iter().rev().find(|&&w| w + 2 <= rows).copied();
    let Some(window) = window else {
        return Err(match (scenario.run.checkpoint_interval, complete.last()) {
            (None, _) => format!(
                "{shown} has no run checkpoint to go on from: its scenario sets no \
                 [run] checkpoint_interval"
            ),
            (Some(every), None) => format!(
                "{shown} has no complete run checkpoint to go on from: the run stopped \
                 before its first was complete (checkpoint_interval = {every} s)"
            ),
            (Some(_), Some(_)) => format!(
                "{shown} has no run checkpoint to go on from whose monitor rows are in \
                 {}: it holds {rows} rows, and the oldest checkpoint kept (window {}) \
                 needs {}",
                monitors.display(),
                complete[0],
                complete[0] + 2
            ),
        });
    };
    let cut = super::monitors::keep_rows(&monitors, window + 2)
        .map_err(|e| format!("cannot cut back {}: {e}", monitors.display()))?;
    debug_assert!(cut, "the rows were counted");
    remove_after(run_dir, window)?;
    // What the killed run's processes were writing when they died.
    participant::atomic::remove_left_aside(run_dir);
    Ok(window)
}

/// Whether the run's manifest says it completed.
fn finished(run_dir: &Path) -> bool {
    let text = std::fs::read_to_string(run_dir.join("manifest.json")).unwrap_or_default();
    serde_json::from_str::<serde_json::Value>(&text).is_ok_and(|m| m["status"] == "completed")
}

/// Remove the run checkpoints after `window`, complete or not.
fn remove_after(run_dir: &Path, window: u64) -> Result<(), String> {
    let dir = run_dir.join(restart::DIR);
    let Ok(entries) = std::fs::read_dir(&dir) else {
        return Ok(());
    };
    for entry in entries.flatten() {
        let later = entry
            .file_name()
            .to_str()
            .and_then(|n| n.parse::<u64>().ok())
            .is_some_and(|w| w > window);
        if later {
            std::fs::remove_dir_all(entry.path())
                .map_err(|e| format!("cannot remove {}: {e}", entry.path().display()))?;
        }
    }
    Ok(())
}
