//! iceoryx2 used as a message queue, with a copy at each end: the sender
//! computes its values into a vector and copies them into the loan, the
//! receiver copies the sample out before reading it. Both ends poll
//! without sleeping, as a two-process bench on two cores can afford.

use super::pingpong::{self, Touch, Transport};
use super::Times;
use iceoryx2::port::publisher::Publisher;
use iceoryx2::port::subscriber::Subscriber;
use iceoryx2::prelude::*;
use std::io::Read;
use std::path::Path;
use std::time::{Duration, Instant};

type Ipc = ipc::Service;

struct End {
    out: Publisher<Ipc, [f64], ()>,
    inp: Subscriber<Ipc, [f64], ()>,
    /// The sender's own values, computed before they are copied.
    mine: Vec<f64>,
    got: Vec<f64>,
    _node: Node<Ipc>,
}

fn err<E: std::fmt::Debug>(what: &'static str) -> impl Fn(E) -> String {
    move |e| format!("{what}: {e:?}")
}

impl End {
    fn open(run: &str, first: bool) -> Result<End, String> {
        set_log_level(LogLevel::Error);
        let node = NodeBuilder::new()
            .signal_handling_mode(SignalHandlingMode::Disabled)
            .create::<Ipc>()
            .map_err(err("node"))?;
        let (tx, rx) = if first { ("a", "b") } else { ("b", "a") };
        let service = |name: &str| {
            let name: ServiceName = format!("canopy/{run}/bench-copy/{name}")
                .as_str()
                .try_into()
                .map_err(err("name"))?;
            node.service_builder(&name)
                .publish_subscribe::<[f64]>()
                .subscriber_max_buffer_size(2)
                .open_or_create()
                .map_err(err("service"))
        };
        let out = service(tx)?
            .publisher_builder()
            .initial_max_slice_len(*super::SIZES.last().unwrap_or(&1))
            .create()
            .map_err(err("publisher"))?;
        let inp = service(rx)?
            .subscriber_builder()
            .create()
            .map_err(err("subscriber"))?;
        Ok(End {
            out,
            inp,
            mine: Vec::new(),
            got: Vec::new(),
            _node: node,
        })
    }
}

impl Transport for End {
    fn send(&mut self, n: usize, fill: &mut dyn FnMut(&mut [f64])) -> Result<(), String> {
        self.mine.resize(n, 0.0);
        fill(&mut self.mine);
        let sample = self.out.loan_slice_uninit(n).map_err(err("loan"))?;
        sample
            .write_from_slice(&self.mine)
            .send()
            .map_err(err("send"))?;
        Ok(())
    }

    fn receive(&mut self, read: &mut dyn FnMut(&[f64])) -> Result<(), String> {
        let started = Instant::now();
        loop {
            if let Some(s) = self.inp.receive().map_err(err("receive"))? {
                self.got.clear();
                self.got.extend_from_slice(s.payload());
                break;
            }
            if started.elapsed() > Duration::from_secs(30) {
                return Err("the peer stopped answering".into());
            }
            std::hint::spin_loop();
        }
        read(&self.got);
        Ok(())
    }

    fn answer(&mut self, _: Touch) -> Result<(), String> {
        pingpong::answer_from_copy(self, |e| &mut e.got)
    }
}

/// `coupler bench-peer copy --run-id R --rounds N`: answer until done.
pub fn peer(run: &str, rounds: usize) -> i32 {
    let result = End::open(run, false).and_then(|mut end| {
        println!("ready");
        pingpong::pong(&mut end, rounds, Touch::Every)
    });
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("bench-peer: {e}");
            1
        }
    }
}

/// The column: every value copied in and out at both ends.
pub fn rows(exe: &Path, rounds: usize) -> Result<Vec<Times>, String> {
    let run = participant::supervisor::new_run_id();
    let mut end = End::open(&run, true)?;
    let mut child = std::process::Command::new(exe)
        .args([
            "bench-peer",
            "copy",
            "--run-id",
            &run,
            "--rounds",
            &rounds.to_string(),
        ])
        .stdout(std::process::Stdio::piped())
        .spawn()
        .map_err(|e| format!("cannot start the peer: {e}"))?;
    // "ready": its ports exist before the first value is sent.
    let mut ready = [0u8; 6];
    if let Some(out) = child.stdout.as_mut() {
        out.read_exact(&mut ready).map_err(|e| e.to_string())?;
    }
    let result = pingpong::ping(&mut end, rounds, Touch::Every);
    if result.is_err() {
        let _ = child.kill();
    }
    let _ = child.wait();
    result
}
