//! The participant library's tests' coupler: participants as threads of
//! the test, supervised by the test itself.

use participant::scheme::Scheme;
use participant::supervisor::{Report, Setup, SuperviseError, Supervisor};
use participant::{Joining, Timing};
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

pub fn timing(windows: u32, timeout: f64) -> Timing {
    Timing {
        start_time: 0.0,
        end_time: windows as f64 * 0.1,
        window: 0.1,
        output_interval: 0.0,
        impulse_substeps: 1,
        timeout,
        checkpoint_interval: 0.0,
    }
}

/// Run `play` for each of `names` as a participant thread of an explicit
/// run with `timing`, supervised here until every one has finished;
/// returns the reports, or the supervisor's error.
#[allow(dead_code)]
pub fn run(
    names: &[&str],
    timing: Timing,
    play: impl Fn(&str, Joining) + Send + Sync + Clone + 'static,
) -> Result<Vec<(usize, Report)>, SuperviseError> {
    run_with(names, timing, Scheme::Explicit, play)
}

/// The same, coupled by `scheme`.
pub fn run_with(
    names: &[&str],
    timing: Timing,
    scheme: Scheme,
    play: impl Fn(&str, Joining) + Send + Sync + Clone + 'static,
) -> Result<Vec<(usize, Report)>, SuperviseError> {
    let run = participant::supervisor::new_run_id();
    let names: Vec<String> = names.iter().map(|s| s.to_string()).collect();
    let mut sup = Supervisor::open(&run, &names, Arc::new(AtomicBool::new(false))).unwrap();
    for name in names.clone() {
        let (run, play) = (run.clone(), play.clone());
        std::thread::spawn(move || play(&name, participant::connect_as(&run, &name).unwrap()));
    }
    let dir = std::env::temp_dir();
    let setup = |_: &str| Setup {
        run_id: run.clone(),
        run_dir: dir.clone(),
        scenario_path: dir.join("test.toml"),
        scenario: String::new(),
        participants: names.clone(),
        timing,
        scheme: scheme.clone(),
        resume: None,
        coupler_pid: 0,
    };
    let limit = Duration::from_secs(30);
    sup.join(setup, limit, limit)?;
    sup.start(limit)?;
    let mut reports = Vec::new();
    let mut finished = 0;
    while finished < names.len() {
        let (p, r) = sup.next_report(limit)?.expect("a report within the limit");
        finished += matches!(r, Report::Finished(_)) as usize;
        reports.push((p, r));
    }
    Ok(reports)
}
