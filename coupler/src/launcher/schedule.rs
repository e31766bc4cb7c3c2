//! Explicit staggered coupling (DESIGN.md, "Time stepping"): per window the
//! fluid, then the structure and rigid solvers, with n_s structure sub-steps
//! and an impulse exchange every impulse sub-step. A participant is sent a
//! command only after the participants whose fields it reads have answered
//! `Done`, so no one starts a window or sub-step before its inputs arrived.

use super::control::{Control, ControlError};
use super::monitors::Monitors;
use super::progress::Progress;
use crate::protocol::{Advance, Command, Monitor, Role, Setup, Stats};
use crate::scenario::stability::{self, Estimate};
use crate::scenario::Scenario;
use std::collections::BTreeMap;
use std::sync::Mutex;
use std::time::Duration;

/// How long a freshly started participant may take to connect.
pub const CONNECT_TIMEOUT: Duration = Duration::from_secs(30);

pub struct Outcome {
    pub stats: BTreeMap<Role, Stats>,
    pub windows: u64,
    pub coupler_send_s: f64,
}

/// Connect, set up and run every participant to the end time. `estimate`
/// receives the structure's sub-step estimate once it reports its ω_max.
pub fn run(
    ctl: &mut Control,
    scenario: &Scenario,
    setup: &Setup,
    monitors: &mut Monitors,
    progress: &mut Progress,
    stopping: &std::sync::atomic::AtomicBool,
    estimate: &Mutex<Option<Estimate>>,
) -> Result<Outcome, ControlError> {
    let roles = scenario.participants.roles();
    let timeout = Duration::from_secs_f64(scenario.coupling.timeout);
    for &r in &roles {
        ctl.expect_connected(r, CONNECT_TIMEOUT)?;
    }
    for &r in &roles {
        ctl.send(r, &Command::Setup(setup.clone()))?;
    }
    for &r in &roles {
        ctl.expect_ready(r, timeout)?;
    }
    // Every field port exists now: initial values can be published.
    for &r in &roles {
        let m = ctl.call(r, &Command::Initialize, timeout)?;
        if r == Role::Structure {
            if let Ok(mut e) = estimate.lock() {
                *e = structure_estimate(scenario, &m);
            }
        }
        monitors.update(r, m);
    }
    let t0 = scenario.run.start_time;
    monitors.row(t0).map_err(monitors_error)?;
    let mut outputs = Outputs::new(scenario);
    outputs.write(ctl, &roles, t0, true, timeout)?;

    let windows = scenario.windows();
    let c = &scenario.coupling;
    let has = |r: Role| roles.contains(&r);
    for w in 0..windows {
        let (t, dt) = scenario.window_span(w);
        if has(Role::Fluid) {
            let step = Advance {
                window: w,
                time: t,
                dt,
                substeps: 1,
                window_end: true,
            };
            let m = ctl.call(Role::Fluid, &Command::Advance(step), timeout)?;
            monitors.update(Role::Fluid, m);
        }
        if has(Role::Rigid) {
            // Impulse sub-steps: the structure integrates the strings with the
            // attachment points the rigid bodies sent, then the bodies take the impulses.
            let n_i = c.impulse_substeps;
            let dt_i = dt / n_i as f64;
            for k in 0..n_i {
                let step = Advance {
                    window: w,
                    time: t + k as f64 * dt_i,
                    dt: dt_i,
                    substeps: c.structure_substeps / n_i,
                    window_end: k + 1 == n_i,
                };
                if has(Role::Structure) {
                    let m = ctl.call(Role::Structure, &Command::Advance(step), timeout)?;
                    monitors.update(Role::Structure, m);
                }
                let m = ctl.call(
                    Role::Rigid,
                    &Command::Advance(Advance {
                        substeps: 1,
                        ..step
                    }),
                    timeout,
                )?;
                monitors.update(Role::Rigid, m);
            }
        } else if has(Role::Structure) {
            let step = Advance {
                window: w,
                time: t,
                dt,
                substeps: c.structure_substeps,
                window_end: true,
            };
            let m = ctl.call(Role::Structure, &Command::Advance(step), timeout)?;
            monitors.update(Role::Structure, m);
        }
        let t_next = t + dt;
        monitors.row(t_next).map_err(monitors_error)?;
        outputs.write(ctl, &roles, t_next, w + 1 == windows, timeout)?;
        if outputs.written_now {
            monitors.flush().map_err(monitors_error)?;
        }
        progress.update(t_next, w + 1);
    }
    monitors.flush().map_err(monitors_error)?;
    stopping.store(true, std::sync::atomic::Ordering::SeqCst);
    for &r in &roles {
        ctl.send(r, &Command::Stop)?;
    }
    let mut stats = BTreeMap::new();
    for &r in &roles {
        stats.insert(r, ctl.expect_finished(r, timeout)?);
    }
    Ok(Outcome {
        stats,
        windows,
        coupler_send_s: ctl.send_s,
    })
}

/// The sub-step estimate from the ω_max the structure reported, if it did;
/// a warning on stderr when the scenario's sub-steps are too few.
fn structure_estimate(scenario: &Scenario, reported: &[Monitor]) -> Option<Estimate> {
    let section = scenario.structure.as_ref()?;
    let omega_max = reported
        .iter()
        .find(|m| m.name == stability::OMEGA_MAX_MONITOR)?
        .value;
    let c = &scenario.coupling;
    let est = stability::estimate(omega_max, c.window, section.scheme());
    if let Some(w) = stability::warning(
        &est,
        c.window,
        c.structure_substeps,
        section.integrator.name(),
    ) {
        eprintln!("warning: {w}");
    }
    Some(est)
}

fn monitors_error(e: std::io::Error) -> ControlError {
    ControlError::Output(format!("cannot write monitors.csv: {e}"))
}

/// When to ask the participants for `.vtu` output.
struct Outputs {
    interval: f64,
    next_time: f64,
    index: u64,
    written_now: bool,
}

impl Outputs {
    fn new(s: &Scenario) -> Outputs {
        Outputs {
            interval: s.run.output_interval,
            next_time: s.run.start_time,
            index: 0,
            written_now: false,
        }
    }

    fn write(
        &mut self,
        ctl: &mut Control,
        roles: &[Role],
        t: f64,
        last: bool,
        timeout: Duration,
    ) -> Result<(), ControlError> {
        // A small tolerance keeps round-off in t from skipping an output.
        let due = t >= self.next_time - 1e-9 * self.interval;
        self.written_now = (self.interval > 0.0 && due) || last || self.index == 0;
        if !self.written_now {
            return Ok(());
        }
        for &r in roles {
            ctl.call(
                r,
                &Command::Output {
                    index: self.index,
                    time: t,
                },
                timeout,
            )?;
        }
        self.index += 1;
        if self.interval > 0.0 {
            while self.next_time <= t + 1e-9 * self.interval {
                self.next_time += self.interval;
            }
        }
        Ok(())
    }
}
