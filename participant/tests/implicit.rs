//! Implicit coupling end to end, on the added-mass problem in one unknown
//! (Causin, Gerbeau & Nobile 2005): a wall of mass m in a fluid of added
//! mass M under a load F(t). The fluid answers the wall's acceleration a
//! with the load F − M·a; the wall answers a load p with a = p/m. The exact
//! acceleration is a* = F/(m + M). Explicit staggered coupling iterates
//! a_w = (F − M·a_{w−1})/m once per window and grows like (−M/m)^w; implicit
//! coupling takes each window again from its checkpoint until a converges,
//! and the wall's velocity, integrated only in the try that counts, is the
//! exact ∫a* dt.

mod common;

use common::{run_with, timing};
use participant::scheme::{Acceleration, Implicit, Measured, Scheme};
use participant::supervisor::{Report, SuperviseError};
use participant::{Cadence, Command, Declaration, Joining, Monitor};

const MASS: f64 = 1.0;
const ADDED: f64 = 4.0;
const WINDOWS: u32 = 8;
const WINDOW: f64 = 0.1;

/// The load [N] at time t: F₀(1 + t/1 s), F₀ = 10 N.
fn load(t: f64) -> f64 {
    10.0 * (1.0 + t)
}

fn exact(t: f64) -> f64 {
    load(t) / (MASS + ADDED)
}

/// The fluid: no state of its own, but it counts its checkpoints.
fn fluid(joining: Joining, with_checkpoints: bool) {
    let mut d = Declaration::new(Cadence::PerWindow { substeps: 1 })
        .reads("wall.acceleration")
        .writes("fluid.load", 1, 1);
    if with_checkpoints {
        d = d.checkpoints();
    }
    let Ok(mut p) = joining.declare(d) else {
        return;
    };
    loop {
        match p.next_command() {
            Ok(Command::Advance(a)) => {
                let Ok(acc) = p.read_field("wall.acceleration").map(|v| v[0]) else {
                    return;
                };
                let f = load(a.time) - ADDED * acc;
                if p.write_field("fluid.load", 1, |out| out[0] = f).is_err() {
                    return;
                }
            }
            Ok(Command::Stop) => break,
            Ok(_) => {}
            Err(e) => {
                let _ = p.fail(e.to_string());
                return;
            }
        }
        p.done(Vec::new()).unwrap();
    }
    p.finish(0).unwrap();
}

/// The wall: its velocity is its state, saved and restored.
fn wall(joining: Joining) {
    let d = Declaration::new(Cadence::PerWindow { substeps: 1 })
        .reads("fluid.load")
        .writes("wall.acceleration", 1, 1)
        .monitors(["acceleration", "velocity"])
        .checkpoints();
    let mut p = joining.declare(d).unwrap();
    let (mut v, mut saved) = (0.0, 0.0);
    loop {
        let mut monitors = Vec::new();
        match p.next_command() {
            Ok(Command::Initialize) => {
                p.write_field("wall.acceleration", 1, |out| out[0] = 0.0)
                    .unwrap();
            }
            Ok(Command::SaveCheckpoint) => saved = v,
            Ok(Command::RestoreCheckpoint) => v = saved,
            Ok(Command::Advance(step)) => {
                let a = p.read_field("fluid.load").unwrap()[0] / MASS;
                v += a * step.dt;
                p.write_field("wall.acceleration", 1, |out| out[0] = a)
                    .unwrap();
                monitors = vec![Monitor::new("acceleration", a), Monitor::new("velocity", v)];
            }
            Ok(Command::Stop) => break,
            Ok(_) => {}
            Err(e) => {
                let _ = p.fail(e.to_string());
                return;
            }
        }
        p.done(monitors).unwrap();
    }
    p.finish(0).unwrap();
}

fn play(name: &str, joining: Joining) {
    match name {
        "fluid" => fluid(joining, true),
        _ => wall(joining),
    }
}

fn implicit(acceleration: Acceleration, max_iterations: u32) -> Scheme {
    Scheme::Implicit(Implicit {
        fields: vec![Measured {
            field: "wall.acceleration".into(),
            relative: Some(1e-10),
            absolute: None,
        }],
        acceleration,
        min_iterations: 1,
        max_iterations,
        go_on_at_max: false,
        parallel: false,
        complement: 1.0,
    })
}

/// The monitor rows at the start and each window's end: the wall's
/// acceleration and velocity, and in an implicit run the tries (the
/// library's monitor on the first participant) and the wall's relative
/// residual and IQN-ILS columns (its monitors on the accelerated field's
/// writer).
fn rows(reports: &[(usize, Report)]) -> Vec<Vec<f64>> {
    let mut rows: Vec<Vec<f64>> = Vec::new();
    let mut tries = Vec::new();
    for (p, r) in reports {
        if let Report::Monitors { values, width, .. } = r {
            if *width == 0 {
                continue;
            }
            let chunks = values.chunks_exact(*width as usize);
            match p {
                0 => tries.extend(chunks.map(|c| c[0])),
                _ => rows.extend(chunks.map(|c| c.to_vec())),
            }
        }
    }
    for (row, t) in rows.iter_mut().zip(tries) {
        row.push(t);
    }
    rows
}

#[test]
fn explicit_coupling_diverges_on_the_added_mass_problem() {
    let reports = run_with(
        &["fluid", "wall"],
        timing(WINDOWS, 30.0),
        Scheme::Explicit,
        play,
    )
    .unwrap();
    let rows = rows(&reports);
    let last = rows.last().unwrap()[0];
    // |a_w| grows like 4^w: past 10³ a* within 8 windows.
    assert!(last.abs() > 1e3 * exact(0.7), "a = {last}");
}

/// Runs the added-mass problem implicitly with `acceleration`; checks
/// every window's acceleration and the velocity against the exact ones to
/// round-off, and returns the tries per window and the last relative
/// residual and columns used.
fn exact_motion(acceleration: Acceleration) -> (Vec<f64>, Vec<[f64; 2]>) {
    let scheme = implicit(acceleration, 20);
    let reports = run_with(&["fluid", "wall"], timing(WINDOWS, 30.0), scheme, play).unwrap();
    let rows = rows(&reports);
    assert_eq!(rows.len(), WINDOWS as usize + 1, "a row per window end");
    let mut v = 0.0;
    for (w, row) in rows[1..].iter().enumerate() {
        let t = w as f64 * WINDOW;
        let a = exact(t);
        v += a * WINDOW;
        assert!(
            (row[0] / a - 1.0).abs() < 1e-12,
            "window {w}: a = {}",
            row[0]
        );
        assert!(
            (row[1] / v - 1.0).abs() < 1e-12,
            "window {w}: v = {}",
            row[1]
        );
        assert!(row[2] <= 1e-10, "window {w}: residual {}", row[2]);
    }
    let tries = rows[1..].iter().map(|r| r[4]).collect();
    let last = rows[1..].iter().map(|r| [r[2], r[3]]).collect();
    (tries, last)
}

/// Aitken's secant step is exact on this linear problem: each window takes
/// three tries (a relaxed first step, the exact second, a third that
/// confirms it).
#[test]
fn implicit_coupling_with_aitken_reaches_the_exact_motion() {
    let (tries, _) = exact_motion(Acceleration::Aitken { initial: 0.1 });
    assert!(tries.iter().all(|&t| t == 3.0), "tries {tries:?}");
}

/// IQN-ILS keeps the secant of earlier windows: the first window takes
/// three tries like Aitken, every later one two, as the reused column
/// already holds the exact inverse Jacobian (H's slope −M/m does not change
/// with the load).
#[test]
fn iqn_ils_reuses_earlier_windows_and_needs_fewer_tries_than_aitken() {
    let (tries, _) = exact_motion(Acceleration::IqnIls {
        initial: 0.1,
        reused_windows: 8,
        max_columns: 50,
        filter: 1e-2,
    });
    assert_eq!(tries[0], 3.0, "tries {tries:?}");
    assert!(tries[1..].iter().all(|&t| t == 2.0), "tries {tries:?}");
}

/// ω = 1 is plain iteration: the window cannot converge, and the run stops
/// at the most tries allowed, naming the window, the field and its residual.
#[test]
fn an_unconverged_window_stops_the_run_naming_window_and_field() {
    let scheme = implicit(Acceleration::Constant { omega: 1.0 }, 4);
    let err = run_with(&["fluid", "wall"], timing(WINDOWS, 30.0), scheme, play).unwrap_err();
    let msg = err.to_string();
    assert!(
        msg.contains("window 0 did not converge in 4 tries")
            && msg.contains("wall.acceleration")
            && msg.contains("residual"),
        "{msg}"
    );
}

/// A participant that cannot take a window again is refused before the
/// run starts.
#[test]
fn implicit_coupling_is_refused_to_a_participant_without_checkpoints() {
    let scheme = implicit(Acceleration::Aitken { initial: 0.1 }, 20);
    let play = |name: &str, joining: Joining| match name {
        "fluid" => fluid(joining, false),
        _ => wall(joining),
    };
    let err = run_with(&["fluid", "wall"], timing(2, 5.0), scheme, play).unwrap_err();
    assert!(matches!(err, SuperviseError::Mismatch(_)), "{err}");
    assert!(err.to_string().contains("`fluid`"), "{err}");
}

/// Run checkpoints are refused the same way to participants whose
/// declarations lack `restarts()`.
#[test]
fn run_checkpoints_are_refused_to_participants_that_cannot_write_them() {
    let mut t = timing(2, 5.0);
    t.checkpoint_interval = 0.1;
    let play = |name: &str, joining: Joining| match name {
        "fluid" => fluid(joining, true),
        _ => wall(joining),
    };
    let err = run_with(&["fluid", "wall"], t, Scheme::Explicit, play).unwrap_err();
    assert!(matches!(err, SuperviseError::Mismatch(_)), "{err}");
    assert!(err.to_string().contains("`fluid`, `wall`"), "{err}");
    assert!(err.to_string().contains("restarts()"), "{err}");
}
