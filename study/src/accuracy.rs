//! The accuracy sweep: every chosen integrator over a ladder of time steps on
//! a reference system, with the error against the exact solution and the CPU
//! time of each run; then each integrator's measured order of convergence and
//! the CPU time it needs to reach a chosen error.

use crate::cpu;
use crate::reference::Reference;
use structure_proc::integrators::theoretical_order;
use structure_section::{Integrator, Scheme};

/// A run whose relative error grows past this has left the solution for good.
pub const DIVERGED_ERROR: f64 = 1e3;
/// Errors that may enter the order fit: below, round-off and solver
/// tolerances dominate; above, the steps are far outside the asymptotic range.
pub const FIT_RANGE: (f64, f64) = (1e-10, 1e-1);
/// The order is fitted to this many runs in [`FIT_RANGE`], those of the
/// smallest steps: the ones deepest in the asymptotic range.
pub const FIT_POINTS: usize = 3;
/// Each run is repeated until it has used this much CPU time, so that runs of
/// microseconds are timed as reliably as runs of seconds.
pub const MIN_CPU_SECONDS: f64 = 0.02;

#[derive(Debug, Clone, PartialEq)]
pub enum Status {
    Ok,
    /// A non-finite value, or an error beyond [`DIVERGED_ERROR`], at the time given.
    Diverged(f64),
    /// The step itself failed (Newton iterations that did not converge).
    Failed(String),
}

impl Status {
    pub fn label(&self) -> String {
        match self {
            Status::Ok => "ok".into(),
            Status::Diverged(t) => format!("diverged at t = {t} s"),
            Status::Failed(why) => format!("failed: {why}"),
        }
    }
}

#[derive(Debug, Clone)]
pub struct Run {
    pub integrator: Integrator,
    /// Time step [s]; for an adaptive scheme, its mean internal step.
    pub dt: f64,
    /// An adaptive scheme's error tolerance; None for fixed steps.
    pub tolerance: Option<f64>,
    /// Largest sampled error (see [`Reference::error_measure`]); NaN if none was sampled.
    pub error: f64,
    pub cpu_seconds: f64,
    pub steps: u64,
    pub status: Status,
}

/// The scheme an integrator name stands for, with the default parameters.
pub fn scheme(i: Integrator) -> Scheme {
    Scheme::resolve(
        i,
        Default::default(),
        Default::default(),
        Default::default(),
        Default::default(),
    )
}

/// The step ladder dt_max, dt_max/2, … (`levels` values).
pub fn ladder(dt_max: f64, levels: u32) -> Vec<f64> {
    (0..levels).map(|l| dt_max / 2f64.powi(l as i32)).collect()
}

/// Tolerances an adaptive scheme runs with, one per ladder level: from
/// [`ADAPTIVE_TOLERANCES`].0 down to .1, log-spaced.
pub const ADAPTIVE_TOLERANCES: (f64, f64) = (1e-2, 1e-12);

/// What one level of the ladder runs: the scheme and the step it is given.
/// A fixed-step scheme runs at `dt`; an adaptive one is handed the whole
/// sampling interval and the level's tolerance, and chooses its own steps.
fn level(r: &dyn Reference, i: Integrator, dt: f64, l: usize, levels: usize) -> (Scheme, f64) {
    if !i.is_adaptive() {
        return (scheme(i), dt);
    }
    let tolerance = adaptive_tolerance(l, levels);
    (Scheme::DormandPrince { tolerance }, r.sample_interval())
}

/// The tolerance of level `l` of `levels`: [`ADAPTIVE_TOLERANCES`], log-spaced.
pub fn adaptive_tolerance(l: usize, levels: usize) -> f64 {
    let (hi, lo) = ADAPTIVE_TOLERANCES;
    let s = if levels > 1 {
        l as f64 / (levels - 1) as f64
    } else {
        0.0
    };
    hi * (lo / hi).powf(s)
}

/// One run of `integrator` as `scheme` with step `dt` on `r`, without timing.
/// An adaptive scheme's `dt` and `steps` are its mean internal step and count.
fn run_once(r: &dyn Reference, integrator: Integrator, scheme: Scheme, dt: f64) -> Run {
    let (sys, mut x, mut v) = r.start();
    let mut stepper = structure_proc::integrator(scheme);
    let per_sample = (r.sample_interval() / dt).round().max(1.0) as u64;
    let samples = (r.end_time() / r.sample_interval()).round() as u64;
    let mut run = Run {
        integrator,
        dt,
        tolerance: match scheme {
            Scheme::DormandPrince { tolerance } => Some(tolerance),
            _ => None,
        },
        error: f64::NAN,
        cpu_seconds: 0.0,
        steps: 0,
        status: Status::Ok,
    };
    let mut worst: f64 = 0.0;
    let mut covered = 0.0;
    'samples: for s in 1..=samples {
        for _ in 0..per_sample {
            if let Err(e) = stepper.step(sys.as_ref(), dt, &mut x, &mut v) {
                run.status = Status::Failed(e.to_string());
                break 'samples;
            }
            run.steps += 1;
            covered += dt;
        }
        let t = s as f64 * per_sample as f64 * dt;
        let e = r.error(t, &x, &v);
        if !e.is_finite() || e > DIVERGED_ERROR {
            run.status = Status::Diverged(t);
            break;
        }
        worst = worst.max(e);
        run.error = worst;
    }
    if let Some(n) = stepper.internal_steps() {
        // The mean internal step over the time actually covered.
        run.steps = n;
        run.dt = covered / n.max(1) as f64;
    }
    run
}

/// Every integrator of `integrators` at every step of `steps` (an adaptive
/// one at the matching tolerance of its ladder), timed. `progress` hears of
/// each run as it ends.
pub fn sweep(
    r: &dyn Reference,
    integrators: &[Integrator],
    steps: &[f64],
    mut progress: impl FnMut(&Run),
) -> Vec<Run> {
    let mut runs = Vec::new();
    for &i in integrators {
        for (l, &dt) in steps.iter().enumerate() {
            let (scheme, dt) = level(r, i, dt, l, steps.len());
            let (mut run, cpu) = cpu::timed(MIN_CPU_SECONDS, 1000, || run_once(r, i, scheme, dt));
            run.cpu_seconds = cpu;
            progress(&run);
            runs.push(run);
        }
    }
    runs
}

/// What the sweep says about one integrator.
#[derive(Debug, Clone)]
pub struct Summary {
    pub integrator: Integrator,
    pub theoretical_order: u32,
    /// Least-squares slope of ln(error) against ln(dt) over the
    /// [`FIT_POINTS`] smallest steps whose error lies in [`FIT_RANGE`]; None
    /// with fewer than two such runs.
    pub order: Option<f64>,
    /// How many runs the fit used.
    pub fitted: usize,
    /// CPU seconds to reach the target error, interpolated in log–log
    /// between the runs that bracket it; None if no run reached it.
    pub cpu_to_target: Option<f64>,
    /// Largest step that stayed finite and bounded.
    pub largest_stable_dt: Option<f64>,
}

pub fn summarise(runs: &[Run], target_error: f64) -> Vec<Summary> {
    let mut out: Vec<Summary> = Vec::new();
    for r in runs {
        if out.iter().any(|s| s.integrator == r.integrator) {
            continue;
        }
        let mine: Vec<&Run> = runs
            .iter()
            .filter(|q| q.integrator == r.integrator)
            .collect();
        let ok: Vec<&Run> = mine
            .iter()
            .copied()
            .filter(|q| q.status == Status::Ok)
            .collect();
        let mut fit: Vec<(f64, f64)> = ok
            .iter()
            .filter(|q| q.error >= FIT_RANGE.0 && q.error <= FIT_RANGE.1)
            .map(|q| (q.dt.ln(), q.error.ln()))
            .collect();
        fit.sort_by(|a, b| a.0.total_cmp(&b.0));
        fit.truncate(FIT_POINTS);
        out.push(Summary {
            integrator: r.integrator,
            theoretical_order: theoretical_order(scheme(r.integrator)),
            order: slope(&fit),
            fitted: fit.len(),
            cpu_to_target: cpu_to_reach(&ok, target_error),
            largest_stable_dt: ok.iter().map(|q| q.dt).reduce(f64::max),
        });
    }
    out
}

/// Least-squares slope of the points (x, y); None with fewer than two.
pub fn slope(points: &[(f64, f64)]) -> Option<f64> {
    let n = points.len() as f64;
    if points.len() < 2 {
        return None;
    }
    let (mx, my) = points
        .iter()
        .fold((0.0, 0.0), |(a, b), (x, y)| (a + x / n, b + y / n));
    let sxy: f64 = points.iter().map(|(x, y)| (x - mx) * (y - my)).sum();
    let sxx: f64 = points.iter().map(|(x, _)| (x - mx).powi(2)).sum();
    (sxx > 0.0).then(|| sxy / sxx)
}

/// CPU seconds at which the error first falls to `target`, going from large
/// steps to small; log–log interpolation between the bracketing runs.
fn cpu_to_reach(ok: &[&Run], target: f64) -> Option<f64> {
    let mut by_dt: Vec<&&Run> = ok.iter().collect();
    by_dt.sort_by(|a, b| b.dt.total_cmp(&a.dt));
    let first = by_dt.iter().position(|r| r.error <= target)?;
    let hit = by_dt[first];
    if first == 0 {
        return Some(hit.cpu_seconds);
    }
    let miss = by_dt[first - 1];
    let s = (target.ln() - miss.error.ln()) / (hit.error.ln() - miss.error.ln());
    Some((miss.cpu_seconds.ln() + s * (hit.cpu_seconds.ln() - miss.cpu_seconds.ln())).exp())
}
