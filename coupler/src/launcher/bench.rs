//! `coupler bench exchange`: round-trip time of a field between two processes,
//! and the share of wall time spent in exchange in a real scene.
//!
//! The peer is this same executable (`coupler bench-peer`). Neither side
//! copies: the sender computes straight into the loaned sample (here it only
//! stamps the first and last value, as a solver would write its results) and
//! the receiver reads the received sample in place. With `--echo` the peer
//! copies every value back instead, which the bit-exactness test uses.

use crate::channel::{self, ChannelError, FieldIn, FieldOut, Ipc};
use iceoryx2::node::Node;
use iceoryx2::port::listener::Listener;
use iceoryx2::port::notifier::Notifier;
use std::io::Read;
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::Arc;
use std::time::{Duration, Instant};

/// One end of a ping-pong pair of fields.
pub struct End {
    out: FieldOut,
    inp: FieldIn,
    wake_peer: Notifier<Ipc>,
    wake_me: Listener<Ipc>,
    _node: Node<Ipc>,
}

fn name(run: &str, what: &str) -> String {
    format!("{}/{run}/bench/{what}", crate::names::PREFIX)
}

impl End {
    /// `first` is the side that sends pings.
    pub fn open(run: &str, first: bool, len_hint: usize) -> Result<End, ChannelError> {
        let node = channel::node(if first { "bench-a" } else { "bench-b" })?;
        let (tx, rx, me, peer) = if first {
            ("ping", "pong", "wake-a", "wake-b")
        } else {
            ("pong", "ping", "wake-b", "wake-a")
        };
        Ok(End {
            out: channel::field_out(&node, &name(run, tx), len_hint)?,
            inp: channel::field_in(&node, &name(run, rx))?,
            wake_peer: channel::notifier(&node, &name(run, peer))?,
            wake_me: channel::listener(&node, &name(run, me))?,
            _node: node,
        })
    }

    /// Send `len` values computed in place by `fill`.
    pub fn send(&self, len: usize, fill: impl FnOnce(&mut [f64])) -> Result<(), ChannelError> {
        let sample = self
            .out
            .loan_slice_uninit(len)
            .map_err(channel::ipc_err("loan"))?;
        // SAFETY: shared memory is zero-filled by the OS and holds only f64s; `fill` writes every value.
        let mut sample = unsafe { sample.assume_init() };
        fill(sample.payload_mut());
        sample.send().map_err(channel::ipc_err("send"))?;
        self.wake_peer
            .notify()
            .map_err(channel::ipc_err("notify"))?;
        Ok(())
    }

    /// Wait for the next field and read it in place.
    pub fn receive<R>(
        &self,
        timeout: Duration,
        abort: &dyn Fn() -> bool,
        read: impl FnOnce(&[f64]) -> R,
    ) -> Result<R, ChannelError> {
        let sample = channel::wait_until(&self.wake_me, Some(timeout), abort, || {
            self.inp.receive().map_err(channel::ipc_err("receive"))
        })?;
        Ok(read(sample.payload()))
    }
}

/// `coupler bench-peer`: answer every ping until stdin closes.
pub fn peer(run: &str, echo: bool) -> i32 {
    let end = match End::open(run, false, 1 << 20) {
        Ok(e) => e,
        Err(e) => {
            eprintln!("bench-peer: {e}");
            return 1;
        }
    };
    let closed = Arc::new(AtomicBool::new(false));
    {
        let closed = closed.clone();
        std::thread::spawn(move || {
            let _ = std::io::stdin().read_to_end(&mut Vec::new());
            closed.store(true, Ordering::SeqCst);
        });
    }
    println!("ready");
    let abort = || closed.load(Ordering::SeqCst);
    loop {
        // Read the ping in place and answer straight from it.
        let result = channel::wait_until(&end.wake_me, None, &abort, || {
            end.inp.receive().map_err(channel::ipc_err("receive"))
        })
        .and_then(|ping| {
            let ping = ping.payload();
            end.send(ping.len(), |pong| {
                if echo {
                    pong.copy_from_slice(ping);
                } else {
                    pong[0] = ping[0];
                    let n = pong.len();
                    pong[n - 1] = ping[n - 1];
                }
            })
        });
        match result {
            Ok(()) => {}
            Err(ChannelError::Aborted) => return 0,
            Err(e) => {
                eprintln!("bench-peer: {e}");
                return 1;
            }
        }
    }
}

/// A running `coupler bench-peer` child; dropping it closes its stdin and reaps it.
pub struct Peer {
    child: std::process::Child,
}

impl Peer {
    pub fn start(coupler: &std::path::Path, run: &str, echo: bool) -> std::io::Result<Peer> {
        let mut cmd = std::process::Command::new(coupler);
        cmd.args(["bench-peer", "--run-id", run]);
        if echo {
            cmd.arg("--echo");
        }
        let mut child = cmd
            .stdin(std::process::Stdio::piped())
            .stdout(std::process::Stdio::piped())
            .spawn()?;
        // Wait for "ready" so its ports exist before the first ping.
        let mut buf = [0u8; 6];
        if let Some(out) = child.stdout.as_mut() {
            out.read_exact(&mut buf)?;
        }
        Ok(Peer { child })
    }
}

impl Drop for Peer {
    fn drop(&mut self) {
        drop(self.child.stdin.take());
        let _ = self.child.wait();
    }
}

fn percentile(sorted: &[f64], q: f64) -> f64 {
    sorted[((sorted.len() - 1) as f64 * q).round() as usize]
}

/// `coupler bench exchange`: prints a table; returns the exit code.
pub fn exchange(rounds: usize, scene: Option<&std::path::Path>) -> i32 {
    let run = crate::names::new_run_id();
    let exe = match std::env::current_exe() {
        Ok(e) => e,
        Err(e) => {
            eprintln!("error: cannot find the coupler executable: {e}");
            return 1;
        }
    };
    let end = End::open(&run, true, 1 << 20);
    let peer = Peer::start(&exe, &run, false);
    let (end, _peer) = match (end, peer) {
        (Ok(e), Ok(p)) => (e, p),
        (Err(e), _) => {
            eprintln!("error: {e}");
            return 1;
        }
        (_, Err(e)) => {
            eprintln!("error: cannot start the peer: {e}");
            return 1;
        }
    };
    println!("field round trip between two processes, zero-copy ({rounds} rounds each)");
    println!(
        "{:>10} {:>12} {:>12} {:>12}",
        "values", "median µs", "p99 µs", "GB/s (med)"
    );
    let never = || false;
    for &n in &[1_000usize, 10_000, 100_000, 1_000_000] {
        let mut times = Vec::with_capacity(rounds);
        for r in 0..rounds + rounds / 10 {
            let stamp = r as f64;
            let t0 = Instant::now();
            let sent = end.send(n, |out| {
                out[0] = stamp;
                out[n - 1] = stamp;
            });
            let back = sent.and_then(|_| {
                end.receive(Duration::from_secs(10), &never, |pong| {
                    pong[0] == stamp && pong[n - 1] == stamp
                })
            });
            let dt = t0.elapsed().as_secs_f64();
            match back {
                Ok(true) => {}
                Ok(false) => {
                    eprintln!("error: the peer answered with the wrong values");
                    return 1;
                }
                Err(e) => {
                    eprintln!("error: {e}");
                    return 1;
                }
            }
            if r >= rounds / 10 {
                times.push(dt); // the first tenth warms up
            }
        }
        times.sort_by(f64::total_cmp);
        let med = percentile(&times, 0.5);
        println!(
            "{n:>10} {:>12.1} {:>12.1} {:>12.1}",
            med * 1e6,
            percentile(&times, 0.99) * 1e6,
            2.0 * 8.0 * n as f64 / med / 1e9
        );
    }
    if let Some(scene) = scene {
        let dir = std::env::temp_dir().join(format!("canopy-bench-{run}"));
        let status = std::process::Command::new(&exe)
            .arg("run")
            .arg(scene)
            .arg("--out")
            .arg(&dir)
            .stderr(std::process::Stdio::null())
            .status();
        let manifest = std::fs::read_to_string(dir.join("manifest.json"))
            .ok()
            .and_then(|t| serde_json::from_str::<serde_json::Value>(&t).ok());
        let _ = std::fs::remove_dir_all(&dir);
        match (status, manifest) {
            (Ok(s), Some(m)) if s.success() => {
                let wall = m["coupler"]["wall_s"].as_f64().unwrap_or(f64::NAN);
                let ex = m["exchange_total_s"].as_f64().unwrap_or(f64::NAN);
                println!();
                println!("{}: wall {wall:.3} s, exchange {ex:.3} s summed over processes, {:.1}% of wall time", scene.display(), 100.0 * ex / wall);
            }
            _ => {
                eprintln!("error: running {} failed", scene.display());
                return 1;
            }
        }
    }
    0
}
