//! The round trip through the participant library itself: the bench is
//! the coupler of a two-participant run, `ping` and `pong`, each a
//! `coupler bench-peer library` process that declares one field it writes
//! and one it reads. `ping` times the round trips during `Initialize` and
//! reports them as its monitors.

use super::pingpong::{self, Touch, Transport};
use super::{Times, SIZES};
use participant::supervisor::{self, Report, Setup, Supervisor};
use participant::{Cadence, Command, Declaration, Monitor, Participant, Timing};
use std::path::Path;
use std::sync::atomic::AtomicBool;
use std::sync::Arc;
use std::time::Duration;

impl Transport for (&mut Participant, &str, &str) {
    fn send(&mut self, n: usize, fill: &mut dyn FnMut(&mut [f64])) -> Result<(), String> {
        self.0
            .write_field(self.1, n, fill)
            .map_err(|e| e.to_string())
    }

    fn receive(&mut self, read: &mut dyn FnMut(&[f64])) -> Result<(), String> {
        let v = self.0.read_field(self.2).map_err(|e| e.to_string())?;
        read(&v);
        Ok(())
    }

    /// In place: the answer is computed from the received values straight
    /// into the loan, with nothing copied out first.
    fn answer(&mut self, touch: Touch) -> Result<(), String> {
        let v = self.0.read_field(self.2).map_err(|e| e.to_string())?;
        let n = v.len();
        self.0
            .write_field(self.1, n, |out| match touch {
                Touch::Every => out.copy_from_slice(&v),
                Touch::Ends => {
                    out[0] = v[0];
                    out[n - 1] = v[n - 1];
                }
            })
            .map_err(|e| e.to_string())
    }
}

fn monitor(touch: Touch, n: usize, what: &str) -> String {
    let t = match touch {
        Touch::Ends => "ends",
        Touch::Every => "every",
    };
    format!("{t}.{n}.{what}")
}

const TOUCHES: [Touch; 2] = [Touch::Ends, Touch::Every];

/// `coupler bench-peer library --rounds R`, started by the bench with the
/// launcher's environment: plays `ping` or `pong`.
pub fn peer(rounds: usize) -> i32 {
    match play(rounds) {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("bench-peer: {e}");
            1
        }
    }
}

fn play(rounds: usize) -> Result<(), String> {
    let joining = participant::connect().map_err(|e| e.to_string())?;
    let ping = joining.name() == "ping";
    let (me, other) = if ping {
        ("ping", "pong")
    } else {
        ("pong", "ping")
    };
    let mut declaration = Declaration::new(Cadence::PerWindow { substeps: 1 })
        .writes_items_of(me, 1)
        .reads(other);
    if ping {
        for touch in TOUCHES {
            for n in SIZES {
                declaration = declaration
                    .monitors([monitor(touch, n, "median_us"), monitor(touch, n, "p99_us")]);
            }
        }
    }
    let mut p = joining.declare(declaration).map_err(|e| e.to_string())?;
    loop {
        let done = match p.next_command().map_err(|e| e.to_string())? {
            Command::Initialize => round_trips(&mut p, me, other, ping, rounds)?,
            Command::Stop => break,
            _ => Vec::new(),
        };
        p.done(done).map_err(|e| e.to_string())?;
    }
    p.finish(0).map_err(|e| e.to_string())
}

fn round_trips(
    p: &mut Participant,
    me: &str,
    other: &str,
    ping: bool,
    rounds: usize,
) -> Result<Vec<Monitor>, String> {
    let mut monitors = Vec::new();
    for touch in TOUCHES {
        let mut t = (&mut *p, me, other);
        if !ping {
            pingpong::pong(&mut t, rounds, touch)?;
            continue;
        }
        for (n, times) in SIZES.iter().zip(pingpong::ping(&mut t, rounds, touch)?) {
            monitors.push(Monitor::new(
                monitor(touch, *n, "median_us"),
                times.median_us,
            ));
            monitors.push(Monitor::new(monitor(touch, *n, "p99_us"), times.p99_us));
        }
    }
    Ok(monitors)
}

/// Both library columns, measured in one run of the two peers.
fn measure(exe: &Path, rounds: usize) -> Result<Vec<f64>, String> {
    let run = supervisor::new_run_id();
    let dir = std::env::temp_dir().join(format!("canopy-bench-{run}"));
    std::fs::create_dir_all(&dir).map_err(|e| e.to_string())?;
    let names = ["ping".to_string(), "pong".to_string()];
    let abort = Arc::new(AtomicBool::new(false));
    let mut sup = Supervisor::open(&run, &names, abort).map_err(|e| e.to_string())?;
    let mut peers = Vec::new();
    for name in &names {
        let child = std::process::Command::new(exe)
            .args(["bench-peer", "library", "--rounds", &rounds.to_string()])
            .env(supervisor::ENV_RUN_ID, &run)
            .env(supervisor::ENV_PARTICIPANT, name)
            .spawn()
            .map_err(|e| format!("cannot start the peer: {e}"))?;
        peers.push(child);
    }
    let result = supervise(&mut sup, &run, &dir);
    for mut c in peers {
        if result.is_err() {
            let _ = c.kill();
        }
        let _ = c.wait();
    }
    let _ = std::fs::remove_dir_all(&dir);
    result
}

/// The handshake, then ping's one row of monitors.
fn supervise(sup: &mut Supervisor, run: &str, dir: &Path) -> Result<Vec<f64>, String> {
    let timing = Timing {
        start_time: 0.0,
        end_time: 1.0,
        window: 1.0,
        output_interval: 0.0,
        impulse_substeps: 1,
        timeout: 600.0,
        checkpoint_interval: 0.0,
    };
    let setup = |_: &str| Setup {
        run_id: run.to_string(),
        run_dir: dir.to_path_buf(),
        scenario_path: dir.join("bench.toml"),
        scenario: String::new(),
        participants: vec!["ping".into(), "pong".into()],
        timing,
        scheme: Default::default(),
        resume: None,
        coupler_pid: 0,
    };
    let limit = Duration::from_secs(60);
    sup.join(setup, limit, limit).map_err(|e| e.to_string())?;
    sup.start(limit).map_err(|e| e.to_string())?;
    let (mut row, mut finished) = (None, 0);
    while finished < 2 {
        match sup.next_report(limit).map_err(|e| e.to_string())? {
            Some((
                0,
                Report::Monitors {
                    first_row: 0,
                    width,
                    values,
                    ..
                },
            )) => row = Some(values[..width as usize].to_vec()),
            Some((_, Report::Finished(_))) => finished += 1,
            Some(_) => {}
            None => return Err("the peers stopped answering".into()),
        }
    }
    row.ok_or_else(|| "ping reported no times".into())
}

/// The library's two columns: only the first and last values stamped (the
/// exchange itself), and every value written and read at both ends.
pub fn columns(exe: &Path, rounds: usize) -> Result<[Vec<Times>; 2], String> {
    let row = measure(exe, rounds)?;
    let column = |t: usize| {
        let first = t * 2 * SIZES.len();
        (0..SIZES.len())
            .map(|i| Times {
                median_us: row[first + 2 * i],
                p99_us: row[first + 2 * i + 1],
            })
            .collect()
    };
    Ok([column(0), column(1)])
}
