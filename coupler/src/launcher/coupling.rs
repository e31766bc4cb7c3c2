//! The coupling thread of `coupler run`: take every participant through the
//! handshake, start them, then supervise while they follow the schedule by
//! themselves (docs/PROTOCOL.md, "The schedule"): gather their monitor rows into
//! `monitors.csv`, show progress, notice a failure or a stall, and collect
//! their statistics at the end. The coupler relays no step: a participant
//! starts a step when the fields it reads for it have arrived.

use super::monitors::{Monitors, MonitorsError};
use super::progress::Progress;
use participant::supervisor::{Report, Setup, Stats, Summary, SuperviseError, Supervisor};
use participant::Timing;
use scenario::Scenario;
use std::path::Path;
use std::sync::Mutex;
use std::time::{Duration, Instant};

/// How long a freshly started participant may take to connect: the
/// scenario's `coupling.timeout`, but not less than this, for a process
/// started on a loaded machine.
pub const CONNECT_FLOOR: Duration = Duration::from_secs(5);
/// How long the coupler sleeps between looks at its reports: participants
/// leave their monitor rows without waking it, every 50 ms.
const LOOK_EVERY: Duration = Duration::from_millis(20);
/// Rows reach the file at least this often.
const FLUSH_EVERY: Duration = Duration::from_millis(200);
/// A participant that waits for a field reports the stall itself after
/// `coupling.timeout`; the coupler's own watch, for a run where no one
/// waits, allows this much more.
const WATCH_GRACE: Duration = Duration::from_secs(2);

pub struct Outcome {
    /// Each participant's name and statistics, in the scenario's order.
    pub stats: Vec<(String, Stats)>,
    /// What participants said of the run ([`Summary`]), each with its
    /// participant's name, in the order they finished.
    pub summaries: Vec<(String, Summary)>,
    pub windows: u64,
    pub coupler_send_s: f64,
    /// Wall time from the start signal to the last participant's statistics.
    pub run_s: f64,
}

#[derive(Debug, thiserror::Error)]
pub enum CouplingError {
    #[error("{0}")]
    Supervise(#[from] SuperviseError),
    #[error("{0}")]
    Monitors(#[from] MonitorsError),
    #[error("no participant reported for {seconds:.1} s{who}")]
    Silent { seconds: f64, who: String },
}

impl CouplingError {
    /// The participant to blame, if one is.
    pub fn culprit(&self) -> Option<String> {
        match self {
            CouplingError::Supervise(e) => e.culprit().map(str::to_string),
            _ => None,
        }
    }
}

/// What the coupling thread shares with the launcher.
pub struct Shared<'a> {
    /// The participants that have sent their statistics: their exits are expected.
    pub finished: &'a Mutex<Vec<String>>,
}

/// Connect, set up, start and supervise every participant to the end time
/// (from the end of window `resume` on, in a restarted run, whose
/// `monitors.csv` holds the rows up to there).
pub fn run(
    sup: &mut Supervisor,
    scenario: &Scenario,
    setup: impl Fn(&str) -> Setup,
    (monitors_path, resume): (&Path, Option<u64>),
    progress: &mut Progress,
    shared: Shared,
) -> Result<Outcome, CouplingError> {
    let timing = super::timing(scenario);
    let timeout = Duration::from_secs_f64(timing.timeout);
    sup.join(setup, CONNECT_FLOOR.max(timeout), timeout)?;
    let names = sup.names().to_vec();
    let declarations = sup.declarations();
    let monitors = match resume {
        // A row at the start and one per window up to its end.
        Some(window) => Monitors::resume(monitors_path, &names, declarations, &timing, window + 2)?,
        None => Monitors::create(monitors_path, &names, declarations, &timing)?,
    };
    sup.start(timeout)?;
    let started = Instant::now();
    let mut watch = Watch {
        names: &names,
        shared: &shared,
        monitors,
        stats: vec![None; names.len()],
        summaries: Vec::new(),
        checkpoints: Vec::new(),
    };
    let watched = watch.run(sup, progress, &timing);
    let (mut monitors, stats, summaries) = (watch.monitors, watch.stats, watch.summaries);
    if let Err(e) = watched {
        // The others' last rows are on their way (a participant that waits
        // long sends its rows): the file keeps them.
        let _ = drain(sup, &mut monitors, &names, STOP_GRACE);
        let _ = monitors.flush();
        return Err(e);
    }
    monitors.complete_rows();
    monitors.flush()?;
    Ok(Outcome {
        stats: names
            .iter()
            .cloned()
            .zip(stats.into_iter().flatten())
            .collect(),
        summaries,
        windows: timing.windows(),
        coupler_send_s: sup.send_s,
        run_s: started.elapsed().as_secs_f64(),
    })
}

/// How long a failing run waits for the monitor rows still on their way.
const STOP_GRACE: Duration = Duration::from_millis(300);

/// The running part: reports in, rows out, until every participant finished.
struct Watch<'a> {
    names: &'a [String],
    shared: &'a Shared<'a>,
    monitors: Monitors,
    stats: Vec<Option<Stats>>,
    summaries: Vec<(String, Summary)>,
    /// Participants writing a run checkpoint, each with the rows it waits
    /// to see kept in the file.
    checkpoints: Vec<(usize, u64)>,
}

impl Watch<'_> {
    fn run(
        &mut self,
        sup: &mut Supervisor,
        progress: &mut Progress,
        timing: &Timing,
    ) -> Result<(), CouplingError> {
        let timeout = Duration::from_secs_f64(timing.timeout);
        let mut heard = Instant::now();
        let mut flushed = Instant::now();
        while self.stats.iter().any(Option::is_none) {
            let Some((p, report)) = sup.next_report(LOOK_EVERY)? else {
                if heard.elapsed() > timeout + WATCH_GRACE {
                    return Err(silent(timing, &self.monitors, heard.elapsed()));
                }
                continue;
            };
            heard = Instant::now();
            self.take(p, report, progress)?;
            if self.keep_checkpoint_rows(sup)? {
                flushed = Instant::now();
            }
            if flushed.elapsed() >= FLUSH_EVERY {
                self.monitors.flush()?;
                flushed = Instant::now();
            }
        }
        Ok(())
    }

    fn take(
        &mut self,
        p: usize,
        report: Report,
        progress: &mut Progress,
    ) -> Result<(), CouplingError> {
        match report {
            Report::Monitors {
                first_row,
                rows,
                width,
                values,
            } => {
                self.monitors
                    .add(p, &self.names[p], first_row, rows, width, values)?;
                if self.monitors.complete_rows() > 0 {
                    let r = self.monitors.written - 1;
                    if r > 0 && self.monitors.total_tries > 0.0 {
                        let m = &self.monitors;
                        progress.set_tries(m.last_tries, m.total_tries / r as f64);
                    }
                    progress.update(self.monitors.time_of(r), r);
                }
            }
            Report::Checkpoint { rows } => self.checkpoints.push((p, rows)),
            // Heard: the participant works through a long window.
            Report::Tried { .. } => {}
            Report::Summary(s) => self.summaries.push((self.names[p].clone(), s)),
            Report::Finished(s) => {
                self.stats[p] = Some(s);
                if let Ok(mut f) = self.shared.finished.lock() {
                    f.push(self.names[p].clone());
                }
            }
        }
        Ok(())
    }

    /// Answer the participants writing a run checkpoint whose rows are all
    /// in: the file written up to them and synced, then each told. Returns
    /// whether the file was flushed.
    fn keep_checkpoint_rows(&mut self, sup: &mut Supervisor) -> Result<bool, CouplingError> {
        let written = self.monitors.written;
        if !self.checkpoints.iter().any(|&(_, rows)| rows <= written) {
            return Ok(false);
        }
        self.monitors.flush()?;
        self.monitors.sync()?;
        let mut error = None;
        self.checkpoints.retain(|&(p, rows)| {
            let kept = rows <= written;
            if kept && error.is_none() {
                error = sup.rows_kept(p, written).err();
            }
            !kept
        });
        match error {
            Some(e) => Err(e.into()),
            None => Ok(true),
        }
    }
}

/// Take the monitor rows that arrive within `grace`, ignoring anything else.
fn drain(
    sup: &Supervisor,
    monitors: &mut Monitors,
    names: &[String],
    grace: Duration,
) -> Result<(), CouplingError> {
    let until = Instant::now() + grace;
    while Instant::now() < until {
        if let Ok(Some((
            p,
            Report::Monitors {
                first_row,
                rows,
                width,
                values,
            },
        ))) = sup.next_report(until - Instant::now())
        {
            monitors.add(p, &names[p], first_row, rows, width, values)?;
            monitors.complete_rows();
        }
    }
    Ok(())
}

/// Nobody reported for `quiet`: no participant waited long enough to
/// report a stall, so they all compute, or one hangs that nobody waits for.
fn silent(timing: &Timing, monitors: &Monitors, quiet: Duration) -> CouplingError {
    let t = monitors.time_of(monitors.written.saturating_sub(1));
    CouplingError::Silent {
        seconds: quiet.as_secs_f64(),
        who: format!(
            " (coupling.timeout = {} s; the monitors reached t = {t} s)",
            timing.timeout
        ),
    }
}
