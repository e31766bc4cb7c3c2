//! The sweep as files: a CSV of every run and a Markdown table of what each
//! integrator achieved.

use crate::accuracy::{scheme, Run, Summary, ADAPTIVE_TOLERANCES, FIT_POINTS, FIT_RANGE};
use crate::reference::Reference;
use crate::stability::{predicted_omega_h, Cell, Chain, Limit, Outcome, BISECTIONS, GROWTH, STEPS};
use std::fmt::Write;
use structure_proc::stability::{self, Interval};

/// One line per run: integrator, dt, error, CPU seconds, steps, status, and
/// an adaptive scheme's tolerance.
pub fn csv(runs: &[Run]) -> String {
    let mut s = String::from("integrator,dt,error,cpu_s,steps,status,tolerance\n");
    for r in runs {
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{},{},{}",
            r.integrator.name(),
            r.dt,
            r.error,
            r.cpu_seconds,
            r.steps,
            r.status.label().replace(',', ";"),
            r.tolerance.map(|t| format!("{t:e}")).unwrap_or_default()
        );
    }
    s
}

/// `x` with three significant digits, or a dash.
fn or_dash(x: Option<f64>, f: impl Fn(f64) -> String) -> String {
    x.map(f).unwrap_or_else(|| "—".into())
}

/// The set-up lines of a study on a reference system.
pub fn reference_setup(r: &dyn Reference, steps: &[f64]) -> String {
    format!(
        "- Error: {}.\n- {} s simulated, error sampled every {} s.\n- Steps: {:e} s down to {:e} s, halving. An adaptive scheme (dormand-prince) instead runs one level per tolerance, from {:e} down to {:e}, log-spaced, handed the whole sampling interval; its dt is its mean internal step.\n",
        r.error_measure(),
        r.end_time(),
        r.sample_interval(),
        steps.iter().copied().fold(f64::MIN, f64::max),
        steps.iter().copied().fold(f64::MAX, f64::min),
        ADAPTIVE_TOLERANCES.0,
        ADAPTIVE_TOLERANCES.1,
    )
}

/// The Markdown report: the title, the set-up, how orders and costs are
/// measured, then one row per integrator.
pub fn markdown(title: &str, setup: &str, summaries: &[Summary], target: f64) -> String {
    let mut s = format!("# Accuracy study: {title}\n\n{setup}");
    let _ = writeln!(
        s,
        "- Measured order: least-squares slope of ln(error) against ln(dt) over the {FIT_POINTS} smallest steps whose error lies in [{:e}, {:e}].\n- CPU time: seconds of process CPU time for one run, interpolated log–log to reach error ≤ {target:e}.\n",
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

/// One line per cell of the stability map.
pub fn stability_csv(cells: &[Cell]) -> String {
    let mut s = String::from("integrator,k,dt,omega_max_h,outcome,energy_ratio\n");
    for c in cells {
        let ratio = match c.outcome {
            Outcome::Stable(r) | Outcome::Unstable { ratio: r, .. } => format!("{r:e}"),
            Outcome::Failed(_) => String::new(),
        };
        let _ = writeln!(
            s,
            "{},{:e},{:e},{:e},{},{}",
            c.integrator.name(),
            c.k,
            c.dt,
            c.omega_h,
            c.outcome.label().replace(',', ";"),
            ratio
        );
    }
    s
}

/// The Markdown report of the stability sweep: the rule, then per integrator
/// its interval, the predicted and measured ω_max·h at the limit, and the
/// largest deviation of the measured step from the predicted one.
pub fn stability_markdown(chain: &Chain, limits: &[Limit], ks: &[f64], dts: &[f64]) -> String {
    let mut s = String::from("# Stability study: linear spring chain\n\n");
    let _ = writeln!(
        s,
        "- Network: a fixed–fixed chain of {} free nodes of {} kg on springs of rest length {} m, started in its highest mode (axial motion, so the forces are linear).\n- ω_max: the bound of dissertation eq. (3.7), √(2Mk/m) with M = 2 neighbours; the chain's exact highest frequency is {:.4} of it.\n- Rule: unstable when a value turns non-finite, or the energy after {STEPS} steps exceeds {GROWTH} × E₀.\n- Grid: k from {:e} to {:e} N/m ({} values), h from {:e} to {:e} s ({} values); the limit is refined by {BISECTIONS} bisections.\n- Prediction: h* = y*/ω_max with y* the end of the scheme's stability interval; schemes with an empty interval (energy grows at every h) are predicted where their amplification |R(iy)|^(2·{STEPS}) reaches {GROWTH}.\n",
        chain.free,
        chain.mass,
        chain.spacing,
        chain.exact_omega_max(1.0) / chain.omega_max(1.0),
        ks[0],
        ks[ks.len() - 1],
        ks.len(),
        dts[0],
        dts[dts.len() - 1],
        dts.len(),
    );
    let _ = writeln!(
        s,
        "| integrator | stability interval | predicted ω_max·h | measured ω_max·h (over k) | largest deviation |\n|---|---|---|---|---|"
    );
    for integrator in crate::integrators_in(limits.iter().map(|l| l.integrator)) {
        let mine: Vec<&Limit> = limits
            .iter()
            .filter(|m| m.integrator == integrator)
            .collect();
        let interval = match stability::interval(scheme(integrator)) {
            Interval::Unconditional => "unconditional".to_string(),
            Interval::Bounded(y) => format!("ω·h ≤ {y:.4}"),
            Interval::Empty => "empty".to_string(),
        };
        let y: Vec<f64> = mine
            .iter()
            .filter_map(|m| m.measured.map(|h| h * m.omega_max))
            .collect();
        let range = format!(
            "{:.4}–{:.4}",
            y.iter().copied().fold(f64::MAX, f64::min),
            y.iter().copied().fold(f64::MIN, f64::max)
        );
        let measured = if y.is_empty() {
            "stable on the whole grid".to_string()
        } else if y.len() < mine.len() {
            let stable = mine.len() - y.len();
            format!(
                "{range}, stable on the whole grid at {stable} of {} k",
                mine.len()
            )
        } else {
            range
        };
        let deviation = mine
            .iter()
            .filter_map(|m| Some((m.measured? / m.predicted? - 1.0).abs()))
            .reduce(f64::max);
        let _ = writeln!(
            s,
            "| {} | {} | {} | {} | {} |",
            integrator.name(),
            interval,
            or_dash(predicted_omega_h(integrator), |y| format!("{y:.4}")),
            measured,
            or_dash(deviation, |d| format!("{:.1} %", 100.0 * d)),
        );
    }
    s
}
