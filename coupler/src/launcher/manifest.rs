//! The run's `manifest.json`: what ran (versions, command, scenario), how
//! it ended, what each participant's `--check` answered, and where the wall
//! time went (per process, and the coupling's share).

use super::coupling;
use super::run::End;
use super::supervise::{self, Child};
use serde_json::json;
use std::time::Instant;

fn git_revision() -> Option<String> {
    let out = std::process::Command::new("git")
        .args(["rev-parse", "HEAD"])
        .output()
        .ok()?;
    out.status
        .success()
        .then(|| String::from_utf8_lossy(&out.stdout).trim().to_string())
}

pub(super) fn manifest(
    checked: &super::Checked,
    run_id: &str,
    end: &End,
    children: &[Child],
    status: &str,
    started: Instant,
) -> serde_json::Value {
    let s = &checked.scenario;
    let outcome = match end {
        End::Completed(o) => Some(o),
        _ => None,
    };
    let (error, culprit) = match end {
        End::Failed(r, reason) => (Some(reason.clone()), r.clone()),
        End::Refused(reason) => (Some(reason.clone()), None),
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
            "windows": super::timing(s).windows(),
            "structure_dt_s": s.coupling.structure_dt(),
        },
        "checked": checked_json(&checked.answers),
        "coupler": {
            "wall_s": started.elapsed().as_secs_f64(),
            "cpu_s": participant::cpu_seconds(),
            "send_s": outcome.map(|o| o.coupler_send_s),
        },
        "coupling": outcome.map(coupling_json),
        "processes": processes_json(children, outcome),
        "exchange_total_s": outcome.map(|o| {
            o.stats.iter().map(|(_, s)| s.exchange_s).sum::<f64>() + o.coupler_send_s
        }),
    })
}

/// What each participant's `--check` answer gives the manifest (a
/// structure's integrator and stability estimate, for example).
fn checked_json(answers: &[(String, scenario::Answer)]) -> serde_json::Value {
    let by_name: serde_json::Map<String, serde_json::Value> = answers
        .iter()
        .map(|(name, a)| {
            let values = serde_json::to_value(&a.manifest).unwrap_or_default();
            (name.clone(), values)
        })
        .collect();
    serde_json::Value::Object(by_name)
}

/// Where the coupled run's wall time went: the participants' own work,
/// and what the coupling cost them, summed over participants: the time
/// inside the library's calls (waits excluded), and the time between a
/// value's sending and its reader seeing it, for values a reader waited
/// for. Waiting while the writer computes is the staggered schedule's,
/// not the exchange's, and is left out.
fn coupling_json(o: &coupling::Outcome) -> serde_json::Value {
    let sum = |f: fn(&participant::supervisor::Stats) -> f64| -> f64 {
        o.stats.iter().map(|(_, s)| f(s)).sum()
    };
    let exchange = sum(|s| s.exchange_s) + o.coupler_send_s;
    let latency = sum(|s| s.latency_s);
    json!({
        "run_s": o.run_s,
        "compute_s": sum(|s| s.compute_s),
        "exchange_s": exchange,
        "latency_s": latency,
        "reads": o.stats.iter().map(|(_, s)| s.reads).sum::<u64>(),
        "exchange_share": (exchange + latency) / o.run_s,
        "checkpoint_s": sum(|s| s.checkpoint_s),
        "accelerate_s": sum(|s| s.accelerate_s),
    })
}

fn processes_json(children: &[Child], outcome: Option<&coupling::Outcome>) -> serde_json::Value {
    let processes: Vec<_> = children
        .iter()
        .map(|c| {
            let st = outcome
                .and_then(|o| o.stats.iter().find(|(n, _)| *n == c.role))
                .map(|(_, s)| s);
            json!({
                "role": c.role,
                "program": c.program,
                "pid": c.pid,
                "exit": c.exited.map(|(s, _)| supervise::describe(&s)),
                "wall_s": c.wall_s(),
                "cpu_s": st.map(|s| s.cpu_s),
                "run_s": st.map(|s| s.run_s),
                "compute_s": st.map(|s| s.compute_s),
                "exchange_s": st.map(|s| s.exchange_s),
                "wait_s": st.map(|s| s.wait_s),
                "latency_s": st.map(|s| s.latency_s),
                "sleeps": st.map(|s| s.sleeps),
                "commands": st.map(|s| s.commands),
                "reads": st.map(|s| s.reads),
                "substeps": st.map(|s| s.substeps),
            })
        })
        .collect();
    serde_json::Value::Array(processes)
}
