//! `coupler check`'s stability estimate: ask the structure program for the
//! ω_max of the model the scenario builds (dissertation eq. 3.7), and warn when
//! the scenario's structure step is above its integrator's stability limit.

use super::programs;
use super::Checked;
use scenario::stability::{self, Interval, OMEGA_MAX_FLAG};
use std::io::Read;
use std::path::Path;
use std::process::{Command, Stdio};
use std::time::{Duration, Instant};

/// How long a structure program may take to build its model and answer.
const ANSWER_WITHIN: Duration = Duration::from_secs(60);

/// Print the estimate for the structure of `checked`, and a warning on
/// stderr when its step is too large. Silent without a structure.
pub fn report(checked: &mut Checked) {
    let s = &checked.scenario;
    let Some(section) = s.structure.as_ref() else {
        return;
    };
    let Some((_, program)) = checked
        .programs
        .iter_mut()
        .find(|(name, _)| name == "structure")
    else {
        return;
    };
    let omega_max =
        match programs::ensure_built(program).and_then(|p| ask_omega_max(&p, &checked.path)) {
            Ok(w) => w,
            Err(e) => {
                println!("  stability not estimated: {e}");
                return;
            }
        };
    if omega_max == 0.0 {
        println!("  stability: no spring holds a free node, so eq. 3.7 sets no step limit");
        return;
    }
    let c = &s.coupling;
    let name = section.integrator.name();
    let scheme = section.scheme();
    let est = stability::estimate(omega_max, c.window, scheme);
    let limit = match (stability::interval(scheme), est.stable_dt) {
        (Interval::Bounded(y), Some(dt)) => format!(
            "stable for ω_max·Δt_s ≤ {y:.3}, Δt_s ≤ {dt:.3e} s, n_s ≥ {}",
            est.n_s
        ),
        (Interval::Empty, _) => "gains energy at every step".to_string(),
        _ => "unconditionally stable".to_string(),
    };
    println!(
        "  stability ω_max = {omega_max:.4e} rad/s (dissertation eq. 3.7): {name} {limit}; the dissertation's ω_max·Δt_s < 0.1 needs n_s ≥ {}",
        est.n_s_seed
    );
    if let Some(w) = stability::warning(&est, c.window, c.structure_substeps, name) {
        eprintln!("warning: {}: {w}", checked.path.display());
    }
}

/// Run `program --omega-max scenario` and read `omega_max <value>` from it.
fn ask_omega_max(program: &Path, scenario: &Path) -> Result<f64, String> {
    let mut child = Command::new(program)
        .arg(OMEGA_MAX_FLAG)
        .arg(scenario)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start {}: {e}", program.display()))?;
    // Drain both pipes while waiting, so a talkative program cannot block on them.
    let drain = |pipe: Option<Box<dyn Read + Send>>| {
        std::thread::spawn(move || {
            let mut text = String::new();
            if let Some(mut p) = pipe {
                let _ = p.read_to_string(&mut text);
            }
            text
        })
    };
    let stdout = drain(
        child
            .stdout
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let stderr = drain(
        child
            .stderr
            .take()
            .map(|p| Box::new(p) as Box<dyn Read + Send>),
    );
    let started = Instant::now();
    while child.try_wait().map_err(|e| e.to_string())?.is_none() {
        if started.elapsed() > ANSWER_WITHIN {
            let _ = child.kill();
            let _ = child.wait();
            return Err(format!(
                "{} did not answer {OMEGA_MAX_FLAG} within {} s",
                program.display(),
                ANSWER_WITHIN.as_secs()
            ));
        }
        std::thread::sleep(Duration::from_millis(20));
    }
    let (out, err) = (
        stdout.join().unwrap_or_default(),
        stderr.join().unwrap_or_default(),
    );
    out.lines()
        .find_map(|l| l.strip_prefix("omega_max ")?.trim().parse::<f64>().ok())
        .filter(|w| w.is_finite() && *w >= 0.0)
        .ok_or_else(|| {
            format!(
                "{} does not report ω_max ({OMEGA_MAX_FLAG}): {}",
                program.display(),
                err.lines().next().unwrap_or("no answer")
            )
        })
}
