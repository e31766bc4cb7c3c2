//! The sweep as files: a CSV of every run and a Markdown table of what each
//! integrator achieved.

use crate::accuracy::{Run, Summary, FIT_POINTS, FIT_RANGE};
use crate::reference::Reference;
use std::fmt::Write;

/// One line per run: integrator, dt, error, CPU seconds, steps, status.
pub fn csv(runs: &[Run]) -> String {
    let mut s = String::from("integrator,dt,error,cpu_s,steps,status\n");
    for r in runs {
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{},{}",
            r.integrator.name(),
            r.dt,
            r.error,
            r.cpu_seconds,
            r.steps,
            r.status.label().replace(',', ";")
        );
    }
    s
}

/// `x` with three significant digits, or a dash.
fn or_dash(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map(f).unwrap_or_else(|| "—".into())
}

/// The Markdown report: the set-up, then one row per integrator.
pub fn markdown(r: &dyn Reference, summaries: &[Summary], steps: &[f64], target: f64) -> String {
    let mut s = format!("# Accuracy study: {}\n\n", r.name());
    let _ = writeln!(
        s,
        "- Error: {}.\n- {} s simulated, error sampled every {} s.\n- Steps: {:e} s down to {:e} s, halving.\n- Measured order: least-squares slope of ln(error) against ln(dt) over the {FIT_POINTS} smallest steps whose error lies in [{:e}, {:e}].\n- CPU time: seconds of process CPU time for one run, interpolated log–log to reach error ≤ {target:e}.\n",
        r.error_measure(),
        r.end_time(),
        r.sample_interval(),
        steps.iter().copied().fold(f64::MIN, f64::max),
        steps.iter().copied().fold(f64::MAX, f64::min),
        FIT_RANGE.0,
        FIT_RANGE.1,
    );
    let _ = writeln!(
        s,
        "| integrator | theoretical order | measured order (runs fitted) | CPU s to error ≤ {target:e} | largest stable step [s] |\n|---|---|---|---|---|"
    );
    for m in summaries {
        let _ = writeln!(
            s,
            "| {} | {} | {} ({}) | {} | {} |",
            m.integrator.name(),
            m.theoretical_order,
            or_dash(m.order, |o| format!("{o:.3}")),
            m.fitted,
            or_dash(m.cpu_to_target, |c| format!("{c:.3e}")),
            or_dash(m.largest_stable_dt, |d| format!("{d:e}")),
        );
    }
    s
}
