//! The run's `manifest.json`: what ran (versions, command, scenario), how
//! it ended, what each participant's `--check` answered, and where the wall
//! time went (per process, and the coupling's share).

use super::coupling;
use super::run::End;
use super::supervise::{self, Child};
use participant::atomic::write_atomic;
use serde_json::json;
use std::path::Path;
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
            "impulse_substeps": s.coupling.impulse_substeps,
            "windows": super::timing(s).windows(),
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
                "ready": st.map(|s| s.ready),
                "commands": st.map(|s| s.commands),
                "reads": st.map(|s| s.reads),
                "substeps": st.map(|s| s.substeps),
            })
        })
        .collect();
    serde_json::Value::Array(processes)
}

/// What a running run's `manifest.json` takes on disk: its JSON, then
/// spaces up to this many bytes. The manifest written when the run ends
/// goes over it in place, in the room already taken, if the disk is too
/// full for a new file then (a run stopped by a full disk must still say
/// so rather than keep saying it runs).
const RESERVED: usize = 32 << 10;

/// A participant's summary of its run under the key it declared: its
/// values by name, NaN as null. A key the manifest has already (its own,
/// or another participant's) is not overwritten: a warning says so.
pub(super) fn add_summary(manifest: &mut serde_json::Value, s: &participant::Summary) {
    if manifest.get(&s.name).is_some_and(|v| !v.is_null()) {
        eprintln!(
            "warning: the manifest already has `{}`: a summary of that name is left out",
            s.name
        );
        return;
    }
    let values: serde_json::Map<String, serde_json::Value> = s
        .values
        .iter()
        .map(|(k, v)| {
            (
                k.clone(),
                if v.is_finite() {
                    json!(v)
                } else {
                    serde_json::Value::Null
                },
            )
        })
        .collect();
    manifest[&s.name] = serde_json::Value::Object(values);
}

/// Write the manifest of a run that starts: aside and renamed, and padded
/// to [`RESERVED`] bytes.
pub(super) fn write_early(path: &Path, manifest: &serde_json::Value) -> std::io::Result<()> {
    let mut text = manifest.to_string();
    let room = RESERVED.saturating_sub(text.len() + 1);
    text.extend(std::iter::repeat_n(' ', room));
    text.push('\n');
    write_atomic(path, &text)
}

/// Write the manifest of a run that ended: aside and renamed; on a disk
/// with no room for that, over the early manifest in place (pretty if it
/// fits, else on one line).
pub(super) fn write_final(path: &Path, manifest: &serde_json::Value) -> std::io::Result<()> {
    let pretty = serde_json::to_string_pretty(manifest).unwrap_or_default();
    write_atomic(path, &pretty).or_else(|e| {
        overwrite(path, &pretty)
            .or_else(|_| overwrite(path, &manifest.to_string()))
            .map_err(|_| e)
    })
}

/// Write `text` over the file at `path` in the bytes it already has, the
/// rest of them spaces: no new block of the disk is needed.
fn overwrite(path: &Path, text: &str) -> std::io::Result<()> {
    use std::io::Write;
    let len = std::fs::metadata(path)?.len() as usize;
    if text.len() + 1 > len {
        return Err(std::io::Error::other(format!(
            "{} bytes do not fit in the {len} of {}",
            text.len() + 1,
            path.display()
        )));
    }
    let mut bytes = text.as_bytes().to_vec();
    bytes.resize(len - 1, b' ');
    bytes.push(b'\n');
    let mut file = std::fs::OpenOptions::new().write(true).open(path)?;
    file.write_all(&bytes)?;
    file.sync_data()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The final manifest written over the early one in place (as on a
    /// full disk) reads back as itself: the padding is JSON whitespace.
    #[test]
    fn a_manifest_written_in_place_reads_back() {
        let dir = std::env::temp_dir().join(format!("canopy-manifest-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("manifest.json");
        write_early(&path, &json!({"status": "running"})).unwrap();
        assert_eq!(std::fs::metadata(&path).unwrap().len(), RESERVED as u64);
        let last = json!({"status": "failed", "error": "cannot write monitors.csv"});
        overwrite(&path, &serde_json::to_string_pretty(&last).unwrap()).unwrap();
        let text = std::fs::read_to_string(&path).unwrap();
        assert_eq!(
            serde_json::from_str::<serde_json::Value>(&text).unwrap(),
            last
        );
        assert!(overwrite(&path, &" ".repeat(RESERVED)).is_err(), "too long");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}
