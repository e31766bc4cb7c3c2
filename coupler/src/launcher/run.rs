//! `coupler run`: launch the participants a scenario lists, drive the schedule,
//! supervise, and leave a run directory.

use super::coupling::{self, CouplingError, Shared};
use super::iterations::Iterations;
use super::manifest::manifest;
use super::programs::Program;
use super::progress::Progress;
use super::supervise::{self, Child, Exit};
use super::{EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_RUN_FAILED};
use participant::supervisor::{self as names, Setup, SuperviseError, Supervisor};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::{mpsc, oneshot};

/// How a run ended, before it is turned into an exit code.
pub(super) enum End {
    Completed(coupling::Outcome),
    /// The participant to blame (if one is) and the reason.
    Failed(Option<String>, String),
    /// The scenario's participants do not fit together (bad input).
    Refused(String),
    Interrupted,
}

pub fn run(scenario_path: &Path, out: Option<PathBuf>) -> i32 {
    // Checking asks every program, so any first-run build happens here.
    let checked = match super::load_checked(scenario_path) {
        Ok(c) => c,
        Err(problems) => return super::refuse(&problems),
    };
    super::warn(&checked);
    // Timing starts after any first-run build of the solvers.
    let started = Instant::now();
    let run_id = names::new_run_id();
    let run_dir = out.unwrap_or_else(|| {
        PathBuf::from("runs").join(format!("{}-{run_id}", checked.scenario.run.name))
    });
    let run_dir = match claim_run_dir(&run_dir, &checked.text) {
        Ok(d) => d,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_BAD_INPUT;
        }
    };
    launch(&checked, &run_id, &run_dir, None, started)
}

/// A completed run's summaries into `manifest` and their pictures into
/// `run_dir`; the lines to print once the run's end is told.
fn summaries(end: &End, run_dir: &Path, manifest: &mut serde_json::Value) -> Vec<String> {
    let End::Completed(outcome) = end else {
        return Vec::new();
    };
    for (participant, s) in &outcome.summaries {
        super::manifest::add_summary(manifest, s);
        if let Err(e) = super::report::summary_page(run_dir, participant, s) {
            let _ = std::fs::remove_file(run_dir.join(format!("{}.png", s.name)));
            eprintln!("warning: cannot write {}.png: {e}", s.name);
        }
    }
    outcome
        .summaries
        .iter()
        .map(|(_, s)| s.line.clone())
        .collect()
}

/// The manifest's record of the scenario file a run was started from.
pub(super) const SCENARIO_FILE: &str = "scenario_file";

/// Run `checked` in `run_dir`, from the start or from the run checkpoint
/// at the end of window `resume`; the exit code.
pub(super) fn launch(
    checked: &super::Checked,
    run_id: &str,
    run_dir: &Path,
    resume: Option<u64>,
    started: Instant,
) -> i32 {
    let scenario_path = &checked.path;
    let scenario_file = scenario_path
        .canonicalize()
        .unwrap_or(scenario_path.clone());
    // Replaced when the run ends; if the coupler itself is killed, this says so.
    let early = json!({
        "status": "running",
        "run_id": run_id,
        "scenario": scenario_path.display().to_string(),
        SCENARIO_FILE: scenario_file,
        "command_line": std::env::args().collect::<Vec<_>>(),
        "resumed_after_window": resume,
    });
    // Written aside and renamed: a coupler killed here leaves no empty manifest.
    let _ = super::manifest::write_early(&run_dir.join("manifest.json"), &early);
    // Stale resources of earlier runs that died are removed before this one starts.
    names::cleanup_dead_nodes();

    let runtime = match tokio::runtime::Builder::new_current_thread()
        .enable_all()
        .build()
    {
        Ok(r) => r,
        Err(e) => {
            eprintln!("error: cannot start the launcher runtime: {e}");
            return EXIT_RUN_FAILED;
        }
    };
    let (end, children) = runtime.block_on(supervise_run(checked, run_id, run_dir, resume));
    names::cleanup_dead_nodes();
    // Every participant has been reaped: a file still aside is one a
    // participant was killed while writing.
    participant::atomic::remove_left_aside(run_dir);

    let (status, code) = match &end {
        End::Completed(_) => ("completed", 0),
        End::Failed(..) => ("failed", EXIT_RUN_FAILED),
        End::Refused(_) => ("refused", EXIT_BAD_INPUT),
        End::Interrupted => ("interrupted", EXIT_INTERRUPTED),
    };
    let iterations = Iterations::gather(&run_dir.join("monitors.csv"));
    if let Some(Err(e)) = iterations.as_ref().map(|i| i.write(run_dir)) {
        // A picture cut short (a full disk) is no picture: none is left.
        let _ = std::fs::remove_file(run_dir.join("iterations.png"));
        eprintln!("warning: cannot write iterations.csv or iterations.png: {e}");
    }
    if let Err(e) = super::report::write(run_dir) {
        let _ = std::fs::remove_file(run_dir.join("monitors.png"));
        eprintln!("warning: cannot write monitors.png: {e}");
    }
    let mut manifest = manifest(checked, run_id, &end, &children, status, started);
    manifest["implicit"] = iterations.map_or(serde_json::Value::Null, |i| i.summary());
    manifest["resumed_after_window"] = json!(resume);
    let summary_lines = summaries(&end, run_dir, &mut manifest);
    manifest[SCENARIO_FILE] = json!(scenario_file);
    if let Err(e) = super::manifest::write_final(&run_dir.join("manifest.json"), &manifest) {
        eprintln!("warning: {e}");
    }
    tell(&end, &children, run_dir, started, scenario_path);
    for line in summary_lines {
        eprintln!("{line}");
    }
    let names: Vec<String> = checked.programs.iter().map(|(n, _)| n.clone()).collect();
    let stopped = matches!(end, End::Failed(..) | End::Interrupted);
    if stopped && !participant::restart::complete(run_dir, &names).is_empty() {
        eprintln!(
            "to go on from its last run checkpoint: coupler run --restart {}",
            run_dir.display()
        );
    }
    code
}

/// Says on stderr how the run ended, where its outputs are, and, for a
/// participant that failed, its last stderr lines.
fn tell(end: &End, children: &[Child], run_dir: &Path, started: Instant, scenario_path: &Path) {
    match end {
        End::Completed(o) => {
            eprintln!(
                "run completed: {} windows in {:.2} s; outputs in {}",
                o.windows,
                started.elapsed().as_secs_f64(),
                run_dir.display()
            );
        }
        End::Failed(role, reason) => {
            eprintln!("run failed: {reason}");
            if let Some(child) = role
                .as_ref()
                .and_then(|r| children.iter().find(|c| &c.role == r))
            {
                let tail = child.tail();
                if !tail.is_empty() {
                    eprintln!("last stderr lines of `{}` ({}):", child.role, child.program);
                    for l in tail {
                        eprintln!("  | {l}");
                    }
                }
            }
            match run_dir.join("monitors.csv").is_file() {
                true => eprintln!("outputs written so far are in {}", run_dir.display()),
                false => eprintln!(
                    "it stopped before its first monitor row: no output was written; the \
                     participants' logs are in {}",
                    run_dir.join("logs").display()
                ),
            }
        }
        End::Refused(reason) => eprintln!("error: {}: {reason}", scenario_path.display()),
        End::Interrupted => eprintln!(
            "interrupted: all participants stopped; outputs so far are in {}",
            run_dir.display()
        ),
    }
}

/// Make `dir` this run's: it must be new or empty. The scenario file, as
/// read, is its first file, created only if it does not exist, so of two runs
/// started into one directory at once one gets it and the other stops.
fn claim_run_dir(dir: &Path, scenario: &str) -> Result<PathBuf, String> {
    use std::io::Write;
    let taken = || {
        format!(
            "{} is not empty; choose another --out or remove it",
            dir.display()
        )
    };
    let unwritable =
        |e: std::io::Error| format!("cannot write the run directory {}: {e}", dir.display());
    if std::fs::read_dir(dir).is_ok_and(|mut d| d.next().is_some()) {
        return Err(taken());
    }
    std::fs::create_dir_all(dir).map_err(unwritable)?;
    let path = dir.join("scenario.toml");
    let mut file = match std::fs::OpenOptions::new()
        .write(true)
        .create_new(true)
        .open(&path)
    {
        Ok(f) => f,
        Err(e) if e.kind() == std::io::ErrorKind::AlreadyExists => return Err(taken()),
        Err(e) => return Err(unwritable(e)),
    };
    file.write_all(scenario.as_bytes()).map_err(unwritable)?;
    Ok(dir.canonicalize().unwrap_or_else(|_| dir.to_path_buf()))
}

/// What the launcher and the coupling thread share.
#[derive(Clone)]
struct Flags {
    /// Set to stop the coupling thread's waits.
    abort: Arc<AtomicBool>,
    /// The participants that have sent their statistics, so that their
    /// exits are expected.
    finished: Arc<Mutex<Vec<String>>>,
}

type Done = oneshot::Receiver<Result<coupling::Outcome, CouplingError>>;

async fn supervise_run(
    checked: &super::Checked,
    run_id: &str,
    run_dir: &Path,
    resume: Option<u64>,
) -> (End, Vec<Child>) {
    let flags = Flags {
        abort: Arc::new(AtomicBool::new(false)),
        finished: Arc::new(Mutex::new(Vec::new())),
    };
    let (thread, ready_rx, mut done_rx) = coupling_thread(checked, run_id, run_dir, resume, &flags);
    // Signals are caught from before the first child starts to the end.
    let mut signals = Signals::install();
    let mut children: Vec<Child> = Vec::new();
    let (exit_tx, mut exit_rx) = mpsc::unbounded_channel::<Exit>();
    let mut end = match ready_rx.await {
        Ok(Ok(())) => spawn_all(checked, run_id, run_dir, &exit_tx, &mut children).err(),
        Ok(Err(e)) => Some(End::Failed(
            None,
            format!("cannot open the coupling channels: {e}"),
        )),
        Err(_) => Some(End::Failed(
            None,
            "the coupling thread ended before it was ready".into(),
        )),
    };
    if end.is_none() {
        let watched = watch(
            &mut children,
            &mut exit_rx,
            &mut done_rx,
            &flags,
            &mut signals,
        );
        end = Some(match watched.await {
            Ok(outcome) => completed(outcome, &mut children, &mut exit_rx).await,
            Err(end) => end,
        });
    }
    // A participant that reported failure is about to exit by itself; a moment's
    // grace lets it finish writing its stderr, which the message quotes.
    if let Some(End::Failed(Some(role), _)) = &end {
        let role = role.clone();
        let grace = Duration::from_millis(500);
        await_exits(&mut children, &mut exit_rx, grace, |c| c.role == role).await;
    }
    // Stop whatever still runs, and reap everything.
    flags.abort.store(true, Ordering::SeqCst);
    for c in &children {
        c.kill();
    }
    await_exits(&mut children, &mut exit_rx, Duration::from_secs(5), |_| {
        true
    })
    .await;
    for c in &mut children {
        c.drain().await;
    }
    let _ = tokio::task::spawn_blocking(move || thread.join()).await;
    (end.unwrap_or(End::Interrupted), children)
}

/// Start the thread that speaks to the participants; it says on the first
/// channel when its ports are open, and on the second how the run ended.
fn coupling_thread(
    checked: &super::Checked,
    run_id: &str,
    run_dir: &Path,
    resume: Option<u64>,
    flags: &Flags,
) -> (
    std::thread::JoinHandle<()>,
    oneshot::Receiver<Result<(), String>>,
    Done,
) {
    let (ready_tx, ready_rx) = oneshot::channel::<Result<(), String>>();
    let (done_tx, done_rx) = oneshot::channel();
    let scenario = checked.scenario.clone();
    let names: Vec<String> = checked.programs.iter().map(|(n, _)| n.clone()).collect();
    let setup = Setup {
        run_id: run_id.to_string(),
        run_dir: run_dir.to_path_buf(),
        scenario_path: checked.path.clone(),
        scenario: checked.text.clone(),
        participants: names.clone(),
        timing: super::timing(&scenario),
        scheme: super::scheme(&scenario),
        resume,
        coupler_pid: std::process::id(),
    };
    let monitors_path = run_dir.join("monitors.csv");
    let (run_id, flags) = (run_id.to_string(), flags.clone());
    let thread = std::thread::spawn(move || {
        let mut sup = match Supervisor::open(&run_id, &names, flags.abort.clone()) {
            Ok(s) => s,
            Err(e) => {
                let _ = ready_tx.send(Err(e.to_string()));
                return;
            }
        };
        let _ = ready_tx.send(Ok(()));
        let run = &scenario.run;
        let mut progress = Progress::new(&run.name, run.start_time, run.end_time);
        let shared = Shared {
            finished: &flags.finished,
        };
        let result = coupling::run(
            &mut sup,
            &scenario,
            |_| setup.clone(),
            (&monitors_path, resume),
            &mut progress,
            shared,
        );
        match &result {
            Ok(o) => progress.finish(run.end_time, o.windows),
            Err(_) => progress.abandon(),
        }
        let _ = done_tx.send(result);
    });
    (thread, ready_rx, done_rx)
}

/// Start every participant's program; the end of the run if one cannot start.
fn spawn_all(
    checked: &super::Checked,
    run_id: &str,
    run_dir: &Path,
    exit_tx: &mpsc::UnboundedSender<Exit>,
    children: &mut Vec<Child>,
) -> Result<(), End> {
    for (name, program) in &checked.programs {
        let Program::Found(path) = program else {
            continue;
        };
        let spec = checked
            .scenario
            .participants
            .get(name)
            .expect("a listed participant");
        let mut env = vec![
            (names::ENV_RUN_ID, run_id.to_string()),
            (names::ENV_PARTICIPANT, name.clone()),
        ];
        let (path, args) = match (&checked.mpirun, spec.ranks()) {
            (Some(mpirun), ranks) if ranks > 1 => {
                env.extend(participant::mpirun::env(ranks));
                (mpirun, participant::mpirun::args(ranks, path, &spec.args))
            }
            _ => (path, spec.args.clone()),
        };
        match supervise::spawn(name, path, &args, &env, run_dir, exit_tx.clone()) {
            Ok(c) => children.push(c),
            Err(e) => {
                let msg = format!(
                    "cannot start `{}` for participant `{name}`: {e}",
                    path.display()
                );
                return Err(End::Failed(Some(name.clone()), msg));
            }
        }
    }
    Ok(())
}

/// Ctrl-C, SIGTERM and a closed terminal.
struct Signals {
    int: Option<tokio::signal::unix::Signal>,
    term: Option<tokio::signal::unix::Signal>,
    hup: Option<tokio::signal::unix::Signal>,
}

impl Signals {
    fn install() -> Signals {
        use tokio::signal::unix::{signal, SignalKind};
        Signals {
            int: signal(SignalKind::interrupt()).ok(),
            term: signal(SignalKind::terminate()).ok(),
            hup: signal(SignalKind::hangup()).ok(),
        }
    }

    async fn next(&mut self) {
        tokio::select! {
            _ = next_signal(&mut self.int) => {}
            _ = next_signal(&mut self.term) => {}
            _ = next_signal(&mut self.hup) => {}
        }
    }
}

/// Watch the children and the coupling thread until the run completes,
/// fails or is interrupted.
async fn watch(
    children: &mut [Child],
    exits: &mut mpsc::UnboundedReceiver<Exit>,
    done: &mut Done,
    flags: &Flags,
    signals: &mut Signals,
) -> Result<coupling::Outcome, End> {
    loop {
        tokio::select! {
            Some(exit) = exits.recv() => {
                record_exit(children, &exit);
                let ok = matches!(&exit.status, Ok(s) if s.success());
                if !ok || !finished(&flags.finished, &exit.role).await {
                    return Err(early_exit(children, &exit, done).await);
                }
            }
            result = &mut *done => return match result {
                Ok(Ok(outcome)) => Ok(outcome),
                Ok(Err(e)) => Err(failed(e)),
                Err(_) => Err(End::Failed(None, "the coupling thread stopped unexpectedly".into())),
            },
            _ = signals.next() => return Err(End::Interrupted),
        }
    }
}

/// Whether participant `name` has sent its statistics; a participant that
/// exits right after sending them may be seen to exit first, so this
/// waits a moment for them.
async fn finished(list: &Mutex<Vec<String>>, name: &str) -> bool {
    let has = || list.lock().is_ok_and(|l| l.iter().any(|n| n == name));
    for _ in 0..100 {
        if has() {
            return true;
        }
        tokio::time::sleep(Duration::from_millis(10)).await;
    }
    has()
}

/// How the coupling thread's error ends the run.
fn failed(e: CouplingError) -> End {
    match e {
        CouplingError::Supervise(SuperviseError::Mismatch(why)) => End::Refused(why),
        e => End::Failed(e.culprit(), e.to_string()),
    }
}

/// A participant exited before the run ended. One that said why (it
/// failed, or it waited in vain for another) exits right after saying so,
/// and one may exit because the coupler itself stopped (it could not write
/// monitors.csv): the coupling thread's reason, if it comes, is the better
/// message.
async fn early_exit(children: &[Child], exit: &Exit, done: &mut Done) -> End {
    let said = tokio::time::timeout(Duration::from_millis(500), &mut *done).await;
    if let Ok(Ok(Err(e))) = said {
        return failed(e);
    }
    let how = match &exit.status {
        Ok(s) => supervise::describe(s),
        Err(e) => format!("could not be waited on: {e}"),
    };
    let program = children
        .iter()
        .find(|c| c.role == exit.role)
        .map(|c| c.program.clone())
        .unwrap_or_default();
    let msg = format!(
        "participant `{}` ({program}) {how} before the run ended",
        exit.role
    );
    End::Failed(Some(exit.role.clone()), msg)
}

/// Every participant finished: they exit by themselves; give them a moment.
async fn completed(
    outcome: coupling::Outcome,
    children: &mut [Child],
    exits: &mut mpsc::UnboundedReceiver<Exit>,
) -> End {
    let bad = await_exits(children, exits, Duration::from_secs(10), |_| true).await;
    match bad.first() {
        Some(role) => {
            let msg = format!("participant `{role}` exited badly after finishing");
            End::Failed(Some(role.clone()), msg)
        }
        None => End::Completed(outcome),
    }
}

/// Record exits until every child that `which` selects has exited, or `within`
/// has passed. Returns the roles that exited unsuccessfully.
async fn await_exits(
    children: &mut [Child],
    exits: &mut mpsc::UnboundedReceiver<Exit>,
    within: Duration,
    which: impl Fn(&Child) -> bool,
) -> Vec<String> {
    let deadline = tokio::time::Instant::now() + within;
    let mut bad = Vec::new();
    while children.iter().any(|c| which(c) && c.exited.is_none()) {
        match tokio::time::timeout_at(deadline, exits.recv()).await {
            Ok(Some(exit)) => {
                record_exit(children, &exit);
                if !matches!(&exit.status, Ok(s) if s.success()) {
                    bad.push(exit.role.clone());
                }
            }
            _ => break,
        }
    }
    bad
}

/// The next delivery of a signal; never, when the handler could not be installed.
async fn next_signal(s: &mut Option<tokio::signal::unix::Signal>) {
    match s.as_mut() {
        Some(s) => {
            s.recv().await;
        }
        None => std::future::pending::<()>().await,
    }
}

fn record_exit(children: &mut [Child], exit: &Exit) {
    if let Some(c) = children.iter_mut().find(|c| c.role == exit.role) {
        if let Ok(s) = &exit.status {
            c.exited = Some((*s, exit.at));
        }
    }
}
