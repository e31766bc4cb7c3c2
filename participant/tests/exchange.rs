//! The participant library end to end, its participants as threads of this
//! test and the test itself as their coupler: fields arrive bit for bit,
//! every declared monitor reaches the coupler whenever it is reported, and
//! a participant that waits in vain names the one it waited for.

mod common;

use common::{run, timing};
use participant::supervisor::{Report, SuperviseError};
use participant::{Cadence, Command, Declaration, ExchangeError, Joining, Monitor};
use std::time::Duration;

/// xorshift64*: random bit patterns, NaN payloads and subnormals included.
fn random_bits(n: usize, seed: u64) -> Vec<f64> {
    let mut s = seed | 1;
    (0..n)
        .map(|_| {
            s ^= s >> 12;
            s ^= s << 25;
            s ^= s >> 27;
            f64::from_bits(s.wrapping_mul(0x2545_f491_4f6c_dd1d))
        })
        .collect()
}

const SIZES: [usize; 8] = [1, 2, 3, 10, 1000, 4097, 100_000, 1_000_000];

/// `ping` sends random bits of each size, `pong` sends them back from its
/// view of them; `ping` counts the values that changed on the way, as its
/// monitor `changed`.
fn echo(name: &str, joining: Joining) {
    let ping = name == "ping";
    let (me, other) = if ping {
        ("ping", "pong")
    } else {
        ("pong", "ping")
    };
    let d = Declaration::new(Cadence::PerWindow { substeps: 1 })
        .writes_items_of(me, 1)
        .reads(other)
        .monitors(if ping { vec!["changed"] } else { vec![] });
    let mut p = joining.declare(d).unwrap();
    loop {
        let mut monitors = Vec::new();
        match p.next_command().unwrap() {
            Command::Initialize if ping => {
                let mut changed = 0;
                for (k, n) in SIZES.into_iter().enumerate() {
                    let mut data = random_bits(n, 0x9e37_79b9 + k as u64);
                    data[0] = if n > 1 { -0.0 } else { data[0] };
                    p.write_field(me, n, |out| out.copy_from_slice(&data))
                        .unwrap();
                    let back = p.read_field(other).unwrap();
                    assert_eq!(back.len(), n);
                    changed += back
                        .iter()
                        .zip(&data)
                        .filter(|(a, b)| a.to_bits() != b.to_bits())
                        .count();
                }
                monitors.push(Monitor::new("changed", changed as f64));
            }
            Command::Initialize => {
                for _ in SIZES {
                    let v = p.read_field(other).unwrap();
                    p.write_field(me, v.len(), |out| out.copy_from_slice(&v))
                        .unwrap();
                }
            }
            Command::Stop => break,
            _ => {}
        }
        p.done(monitors).unwrap();
    }
    p.finish(0).unwrap();
}

#[test]
fn fields_arrive_bit_exact_from_1_to_a_million_values() {
    let reports = run(&["ping", "pong"], timing(1, 30.0), echo).unwrap();
    let first = reports.iter().find_map(|(p, r)| match r {
        Report::Monitors {
            first_row: 0,
            values,
            ..
        } if *p == 0 => Some(values[0]),
        _ => None,
    });
    assert_eq!(first, Some(0.0), "values changed in transit");
}

/// Reports `late` only at window ends and `often` at every command.
fn reporter(_: &str, joining: Joining) {
    let d = Declaration::new(Cadence::PerWindow { substeps: 1 }).monitors(["late", "often"]);
    let mut p = joining.declare(d).unwrap();
    let mut windows = 0.0;
    loop {
        let monitors = match p.next_command().unwrap() {
            Command::Initialize => vec![Monitor::new("often", -1.0)],
            Command::Advance(_) => {
                windows += 1.0;
                vec![
                    Monitor::new("late", windows),
                    Monitor::new("often", windows),
                ]
            }
            Command::Stop => break,
            _ => vec![],
        };
        p.done(monitors).unwrap();
    }
    // There is no command after Stop.
    let e = p.next_command().unwrap_err();
    assert!(matches!(e, ExchangeError::Misuse(_)), "{e}");
    p.finish(0).unwrap();
}

#[test]
fn a_monitor_first_reported_at_a_window_end_gets_its_column() {
    let reports = run(&["solver"], timing(3, 30.0), reporter).unwrap();
    let mut rows = Vec::new();
    for (_, r) in reports {
        if let Report::Monitors { width, values, .. } = r {
            rows.extend(values.chunks(width as usize).map(<[f64]>::to_vec));
        }
    }
    // Row 0 at the start, then one per window: `late` from the first window on.
    assert_eq!(rows.len(), 4);
    assert!(rows[0][0].is_nan() && rows[0][1] == -1.0);
    assert_eq!(
        rows[1..].to_vec(),
        vec![vec![1.0, 1.0], vec![2.0, 2.0], vec![3.0, 3.0]]
    );
}

#[test]
fn an_undeclared_monitor_is_an_error() {
    let reports = run(&["solver"], timing(1, 30.0), |_, joining: Joining| {
        let d = Declaration::new(Cadence::PerWindow { substeps: 1 }).monitors(["a"]);
        let mut p = joining.declare(d).unwrap();
        assert_eq!(p.next_command().unwrap(), Command::Initialize);
        let e = p.done(vec![Monitor::new("b", 1.0)]).unwrap_err();
        assert!(
            matches!(&e, ExchangeError::UndeclaredMonitor(m) if m == "b"),
            "{e}"
        );
        p.fail(e.to_string()).unwrap();
    });
    match reports {
        Err(SuperviseError::Failed { reason, .. }) => {
            assert!(reason.contains("monitor `b` was not declared"), "{reason}")
        }
        other => panic!("{other:?}"),
    }
}

#[test]
fn a_reader_that_waits_in_vain_names_the_writer() {
    // `mute` declares a field and never writes it; `waiting` gives up after
    // the timeout and says whom it waited for.
    let reports = run(
        &["waiting", "mute"],
        timing(1, 0.2),
        |name: &str, joining: Joining| {
            let d = Declaration::new(Cadence::PerWindow { substeps: 1 });
            if name == "mute" {
                let _p = joining.declare(d.writes("x", 1, 1)).unwrap();
                std::thread::sleep(Duration::from_secs(5));
                return;
            }
            let mut p = joining.declare(d.reads("x")).unwrap();
            p.next_command().unwrap();
            let e = p.read_field("x").map(|_| ()).unwrap_err();
            assert!(matches!(e, ExchangeError::Stalled { .. }), "{e}");
        },
    );
    match reports {
        Err(e @ SuperviseError::Timeout { .. }) => {
            assert_eq!(e.culprit(), Some("mute"));
            assert!(
                e.to_string().contains("`waiting` waited for field `x`"),
                "{e}"
            );
        }
        other => panic!("{other:?}"),
    }
}
