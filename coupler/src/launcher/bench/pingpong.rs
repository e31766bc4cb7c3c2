//! The ping-pong every column of the round-trip table plays, whatever
//! carries the values: the pinging side sends a field of n values and
//! waits for the answer; the other side answers from what it received.

use super::{Times, SIZES};
use std::time::Instant;

/// One end of a way of moving a field between two processes.
pub trait Transport {
    /// Send `n` values that `fill` computes.
    fn send(&mut self, n: usize, fill: &mut dyn FnMut(&mut [f64])) -> Result<(), String>;
    /// Take the next field and hand it to `read`.
    fn receive(&mut self, read: &mut dyn FnMut(&[f64])) -> Result<(), String>;
    /// Take the next field and send back the same values.
    fn answer(&mut self, touch: Touch) -> Result<(), String>;
}

/// Whether every value is written and read, or only the first and last
/// (the exchange alone, possible only where nothing is copied).
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Touch {
    Ends,
    Every,
}

fn warm_up(rounds: usize) -> usize {
    (rounds / 10).max(1)
}

/// The pinging side: for each size, `rounds` timed round trips after a
/// warm-up; the answer's stamps are checked.
pub fn ping(t: &mut dyn Transport, rounds: usize, touch: Touch) -> Result<Vec<Times>, String> {
    let mut out = Vec::new();
    for n in SIZES {
        let mut times = Vec::with_capacity(rounds);
        for r in 0..warm_up(rounds) + rounds {
            let stamp = r as f64;
            let t0 = Instant::now();
            t.send(n, &mut |v| match touch {
                Touch::Every => v
                    .iter_mut()
                    .enumerate()
                    .for_each(|(i, x)| *x = stamp + i as f64),
                Touch::Ends => {
                    v[0] = stamp;
                    v[n - 1] = stamp + (n - 1) as f64;
                }
            })?;
            let mut ok = false;
            t.receive(&mut |v| {
                let sum = match touch {
                    Touch::Every => v.iter().sum::<f64>(),
                    Touch::Ends => 0.0,
                };
                ok = v.len() == n
                    && v[0] == stamp
                    && v[n - 1] == stamp + (n - 1) as f64
                    && sum.is_finite();
            })?;
            let dt = t0.elapsed().as_secs_f64();
            if !ok {
                return Err(format!("round {r} of {n} values came back wrong"));
            }
            if r >= warm_up(rounds) {
                times.push(dt);
            }
        }
        times.sort_by(f64::total_cmp);
        let at = |q: f64| times[((times.len() - 1) as f64 * q).round() as usize] * 1e6;
        out.push(Times {
            median_us: at(0.5),
            p99_us: at(0.99),
        });
    }
    Ok(out)
}

/// The answering side: as many rounds as [`ping`] sends.
pub fn pong(t: &mut dyn Transport, rounds: usize, touch: Touch) -> Result<(), String> {
    for _ in SIZES {
        for _ in 0..warm_up(rounds) + rounds {
            t.answer(touch)?;
        }
    }
    Ok(())
}

/// The answer of a transport that receives into a vector of its own
/// (`got`): the received values arrive copied out, and the answer is
/// computed from them into the next send.
pub fn answer_from_copy<T: Transport>(
    t: &mut T,
    got: fn(&mut T) -> &mut Vec<f64>,
) -> Result<(), String> {
    t.receive(&mut |_| {})?;
    let values = std::mem::take(got(t));
    let sent = t.send(values.len(), &mut |out| out.copy_from_slice(&values));
    *got(t) = values;
    sent
}
