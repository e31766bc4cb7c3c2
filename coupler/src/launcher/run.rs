//! `coupler run`: launch the participants a scenario lists, drive the schedule,
//! supervise, and leave a run directory.

use super::control::{Control, ControlError};
use super::monitors::Monitors;
use super::programs::{self, Program};
use super::progress::Progress;
use super::supervise::{self, Child, Exit};
use super::{schedule, EXIT_BAD_INPUT, EXIT_INTERRUPTED, EXIT_RUN_FAILED};
use crate::protocol::{Role, Setup};
use crate::scenario::stability::{self, Estimate};
use crate::{channel, names};
use serde_json::json;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};
use tokio::sync::{mpsc, oneshot};

/// How a run ended, before it is turned into an exit code.
enum End {
    Completed(schedule::Outcome),
    /// The participant to blame (if one is) and the reason.
    Failed(Option<Role>, String),
    Interrupted,
}

pub fn run(scenario_path: &Path, out: Option<PathBuf>) -> i32 {
    let mut checked = match super::load_checked(scenario_path) {
        Ok(c) => c,
        Err(e) => {
            eprintln!("error: {e}");
            return EXIT_BAD_INPUT;
        }
    };
    for (_, program) in &mut checked.programs {
        if let Err(e) = programs::ensure_built(program) {
            eprintln!("error: {}: {e}", scenario_path.display());
            return EXIT_BAD_INPUT;
        }
    }
    // Timing starts after any first-run build of the solvers.
    let started = Instant::now();
    let scenario = checked.scenario.clone();
    let run_id = names::new_run_id();
    let run_dir = out
        .unwrap_or_else(|| PathBuf::from("runs").join(format!("{}-{run_id}", scenario.run.name)));
    if std::fs::read_dir(&run_dir)
        .map(|mut d| d.next().is_some())
        .unwrap_or(false)
    {
        eprintln!(
            "error: {} is not empty; choose another --out or remove it",
            run_dir.display()
        );
        return EXIT_BAD_INPUT;
    }
    if let Err(e) = std::fs::create_dir_all(&run_dir)
        .and_then(|_| std::fs::write(run_dir.join("scenario.toml"), scenario.to_toml()))
    {
        eprintln!(
            "error: cannot write the run directory {}: {e}",
            run_dir.display()
        );
        return EXIT_BAD_INPUT;
    }
    let run_dir = run_dir.canonicalize().unwrap_or(run_dir);
    // Replaced when the run ends; if the coupler itself is killed, this says so.
    let early = json!({
        "status": "running",
        "run_id": run_id,
        "scenario": scenario_path.display().to_string(),
        "command_line": std::env::args().collect::<Vec<_>>(),
    });
    let _ = std::fs::write(run_dir.join("manifest.json"), early.to_string());
    // Stale resources of earlier runs that died are removed before this one starts.
    channel::cleanup_dead_nodes();

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
    let (end, children, estimate) = runtime.block_on(supervise_run(&checked, &run_id, &run_dir));
    channel::cleanup_dead_nodes();

    let (status, code) = match &end {
        End::Completed(_) => ("completed", 0),
        End::Failed(..) => ("failed", EXIT_RUN_FAILED),
        End::Interrupted => ("interrupted", EXIT_INTERRUPTED),
    };
    let manifest = manifest(
        &checked, &run_id, &end, &children, estimate, status, started,
    );
    let _ = std::fs::write(
        run_dir.join("manifest.json"),
        serde_json::to_string_pretty(&manifest).unwrap_or_default(),
    );
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
            if let Some(child) = role.and_then(|r| children.iter().find(|c| c.role == r)) {
                let tail = child.tail();
                if !tail.is_empty() {
                    eprintln!(
                        "last stderr lines of `{}` ({}):",
                        child.role.name(),
                        child.program
                    );
                    for l in tail {
                        eprintln!("  | {l}");
                    }
                }
            }
            eprintln!("outputs written so far are in {}", run_dir.display());
        }
        End::Interrupted => eprintln!(
            "interrupted: all participants stopped; outputs so far are in {}",
            run_dir.display()
        ),
    }
    code
}

async fn supervise_run(
    checked: &super::Checked,
    run_id: &str,
    run_dir: &Path,
) -> (End, Vec<Child>, Option<Estimate>) {
    let scenario = checked.scenario.clone();
    let roles = scenario.participants.roles();
    let abort = Arc::new(AtomicBool::new(false));
    let stopping = Arc::new(AtomicBool::new(false));
    let (ready_tx, ready_rx) = oneshot::channel::<Result<(), String>>();
    let (done_tx, mut done_rx) = oneshot::channel::<Result<schedule::Outcome, ControlError>>();
    let estimate = Arc::new(Mutex::new(None));

    let thread = {
        let (abort, stopping, estimate) = (abort.clone(), stopping.clone(), estimate.clone());
        let setup = Setup {
            run_id: run_id.to_string(),
            run_dir: run_dir.to_path_buf(),
            scenario_toml: scenario.to_toml(),
            present: roles.clone(),
        };
        let monitors_path = run_dir.join("monitors.csv");
        let (run_id, roles, scenario) = (run_id.to_string(), roles.clone(), scenario.clone());
        std::thread::spawn(move || {
            let mut ctl = match Control::open(&run_id, &roles, abort) {
                Ok(c) => c,
                Err(e) => {
                    let _ = ready_tx.send(Err(e.to_string()));
                    return;
                }
            };
            let mut monitors = match Monitors::create(&monitors_path) {
                Ok(m) => m,
                Err(e) => {
                    let _ = ready_tx.send(Err(format!("cannot create monitors.csv: {e}")));
                    return;
                }
            };
            let _ = ready_tx.send(Ok(()));
            let mut progress = Progress::new(
                &scenario.run.name,
                scenario.run.start_time,
                scenario.run.end_time,
            );
            let result = schedule::run(
                &mut ctl,
                &scenario,
                &setup,
                &mut monitors,
                &mut progress,
                &stopping,
                &estimate,
            );
            match &result {
                Ok(o) => progress.finish(scenario.run.end_time, o.windows),
                Err(_) => progress.abandon(),
            }
            let _ = monitors.flush();
            let _ = done_tx.send(result);
        })
    };

    // Signals are caught from before the first child starts to the end.
    use tokio::signal::unix::{signal, SignalKind};
    let mut sigint = signal(SignalKind::interrupt()).ok();
    let mut sigterm = signal(SignalKind::terminate()).ok();
    let mut sighup = signal(SignalKind::hangup()).ok();
    let mut children: Vec<Child> = Vec::new();
    let (exit_tx, mut exit_rx) = mpsc::unbounded_channel::<Exit>();
    let mut end = match ready_rx.await {
        Ok(Ok(())) => None,
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
        let env = [(names::ENV_RUN_ID, run_id.to_string())];
        for (role, program) in &checked.programs {
            let Program::Found(path) = program else {
                continue;
            };
            let spec = scenario.participants.get(*role).expect("listed role");
            let mut env = env.to_vec();
            env.push((names::ENV_ROLE, role.name().to_string()));
            let (path, args) = match (&checked.mpirun, spec.ranks()) {
                (Some(mpirun), ranks) if ranks > 1 => {
                    env.extend(crate::mpirun::env(ranks));
                    (mpirun, crate::mpirun::args(ranks, path, &spec.args))
                }
                _ => (path, spec.args.clone()),
            };
            match supervise::spawn(*role, path, &args, &env, run_dir, exit_tx.clone()) {
                Ok(c) => children.push(c),
                Err(e) => {
                    end = Some(End::Failed(
                        Some(*role),
                        format!(
                            "cannot start `{}` for participant `{}`: {e}",
                            path.display(),
                            role.name()
                        ),
                    ));
                    break;
                }
            }
        }
    }

    let mut completed = None;
    while end.is_none() {
        tokio::select! {
            Some(exit) = exit_rx.recv() => {
                record_exit(&mut children, &exit);
                let stopping = stopping.load(Ordering::SeqCst);
                let ok = matches!(&exit.status, Ok(s) if s.success());
                if !stopping || !ok {
                    // A participant that said why it fails exits right after; its
                    // reason, already on its way to the coupling thread, is the better message.
                    if let Ok(Ok(Err(e @ ControlError::Failed { .. }))) = tokio::time::timeout(Duration::from_millis(200), &mut done_rx).await {
                        end = Some(End::Failed(Some(exit.role), e.to_string()));
                        continue;
                    }
                    let how = match &exit.status {
                        Ok(s) => supervise::describe(s),
                        Err(e) => format!("could not be waited on: {e}"),
                    };
                    let program = children.iter().find(|c| c.role == exit.role).map(|c| c.program.clone()).unwrap_or_default();
                    end = Some(End::Failed(Some(exit.role), format!("participant `{}` ({program}) {how} before the run ended", exit.role.name())));
                }
            }
            result = &mut done_rx => {
                match result {
                    Ok(Ok(outcome)) => { completed = Some(outcome); break; }
                    Ok(Err(e)) => {
                        let role = match &e {
                            ControlError::Failed { role, .. } | ControlError::Timeout { role, .. } | ControlError::Protocol { role, .. } => Role::from_name(role),
                            _ => None,
                        };
                        end = Some(End::Failed(role, e.to_string()));
                    }
                    Err(_) => end = Some(End::Failed(None, "the coupling thread stopped unexpectedly".into())),
                }
            }
            _ = next_signal(&mut sigint) => end = Some(End::Interrupted),
            _ = next_signal(&mut sigterm) => end = Some(End::Interrupted),
            _ = next_signal(&mut sighup) => end = Some(End::Interrupted),
        }
    }

    if let Some(outcome) = completed {
        // Participants exit by themselves after `Finished`; give them a moment.
        let bad = await_exits(&mut children, &mut exit_rx, Duration::from_secs(10), |_| {
            true
        })
        .await;
        if let Some(role) = bad.first() {
            let msg = format!("participant `{}` exited badly after finishing", role.name());
            end = Some(End::Failed(Some(*role), msg));
        }
        if end.is_none() {
            end = Some(End::Completed(outcome));
        }
    }

    // A participant that reported failure is about to exit by itself; a moment's
    // grace lets it finish writing its stderr, which the message quotes.
    if let Some(End::Failed(Some(role), _)) = &end {
        let role = *role;
        await_exits(
            &mut children,
            &mut exit_rx,
            Duration::from_millis(500),
            |c| c.role == role,
        )
        .await;
    }
    // Stop whatever still runs, and reap everything.
    abort.store(true, Ordering::SeqCst);
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
    let estimate = estimate.lock().ok().and_then(|e| *e);
    (end.unwrap_or(End::Interrupted), children, estimate)
}

/// Record exits until every child that `which` selects has exited, or `within`
/// has passed. Returns the roles that exited unsuccessfully.
async fn await_exits(
    children: &mut [Child],
    exits: &mut mpsc::UnboundedReceiver<Exit>,
    within: Duration,
    which: impl Fn(&Child) -> bool,
) -> Vec<Role> {
    let deadline = tokio::time::Instant::now() + within;
    let mut bad = Vec::new();
    while children.iter().any(|c| which(c) && c.exited.is_none()) {
        match tokio::time::timeout_at(deadline, exits.recv()).await {
            Ok(Some(exit)) => {
                record_exit(children, &exit);
                if !matches!(&exit.status, Ok(s) if s.success()) {
                    bad.push(exit.role);
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

fn git_revision() -> Option<String> {
    let out = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

fn manifest(
    checked: &super::Checked,
    run_id: &str,
    end: &End,
    children: &[Child],
    estimate: Option<Estimate>,
    status: &str,
    started: Instant,
) -> serde_json::Value {
    let s = &checked.scenario;
    let stats = match end {
        End::Completed(o) => Some(o),
        _ => None,
    };
    let processes: Vec<_> = children
        .iter()
        .map(|c| {
            let st = stats.and_then(|o| o.stats.get(&c.role));
            json!({
                "role": c.role.name(),
                "program": c.program,
                "pid": c.pid,
                "exit": c.exited.map(|(s, _)| supervise::describe(&s)),
                "wall_s": c.wall_s(),
                "cpu_s": st.map(|s| s.cpu_s),
                "exchange_s": st.map(|s| s.exchange_s),
                "wait_s": st.map(|s| s.wait_s),
                "commands": st.map(|s| s.commands),
                "substeps": st.map(|s| s.substeps),
            })
        })
        .collect();
    let exchange_total =
        stats.map(|o| o.stats.values().map(|s| s.exchange_s).sum::<f64>() + o.coupler_send_s);
    let (error, culprit) = match end {
        End::Failed(r, reason) => (Some(reason.clone()), r.map(|r| r.name())),
        _ => (None, None),
    };
    json!({
        "canopy_version": env!("CARGO_PKG_VERSION"),
        "git_revision": git_revision(),
        "command_line": std::env::args().collect::<Vec<_>>(),
        "scenario": checked.path.display().to_string(),
        "scene": s.run.name,
        "run_id": run_id,
        "status": status,
        "error": error,
        "culprit": culprit,
        "schedule": {
            "window_s": s.coupling.window,
            "structure_substeps": s.coupling.structure_substeps,
            "impulse_substeps": s.coupling.impulse_substeps,
            "windows": s.windows(),
            "integrator": s.structure.as_ref().map(|st| st.integrator.name()),
            "structure_dt_s": s.coupling.structure_dt(),
        },
        // From the ω_max the structure reported (seed 000 eq. 3.7): the largest
        // stable step of the integrator and the sub-steps it needs.
        "stability": estimate.map(|e| json!({
            "omega_max": e.omega_max,
            "interval": s.structure.as_ref().map(|st| stability::interval(st.scheme()).label()),
            "interval_omega_h": s.structure.as_ref().and_then(|st| match stability::interval(st.scheme()) {
                stability::Interval::Bounded(y) => Some(y),
                _ => None,
            }),
            "stable_dt_s": e.stable_dt,
            "n_s": e.n_s,
            "n_s_seed": e.n_s_seed,
        })),
        "coupler": {
            "wall_s": started.elapsed().as_secs_f64(),
            "cpu_s": crate::usage::cpu_seconds(),
            "send_s": stats.map(|o| o.coupler_send_s),
        },
        "processes": processes,
        "exchange_total_s": exchange_total,
    })
}
