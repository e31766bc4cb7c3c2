//! A Unix stream socket carrying each field as a length-prefixed bincode
//! encoding of a vector: the common way to couple two processes without
//! shared memory.

use super::pingpong::{self, Touch, Transport};
use super::Times;
use std::io::{Read, Write};
use std::os::unix::net::{UnixListener, UnixStream};
use std::path::Path;

struct End {
    stream: UnixStream,
    mine: Vec<f64>,
    got: Vec<f64>,
    bytes: Vec<u8>,
}

fn config() -> bincode::config::Configuration {
    bincode::config::standard()
}

impl Transport for End {
    fn send(&mut self, n: usize, fill: &mut dyn FnMut(&mut [f64])) -> Result<(), String> {
        self.mine.resize(n, 0.0);
        fill(&mut self.mine);
        let bytes =
            bincode::serde::encode_to_vec(&self.mine, config()).map_err(|e| e.to_string())?;
        let len = (bytes.len() as u64).to_le_bytes();
        self.stream
            .write_all(&len)
            .and_then(|_| self.stream.write_all(&bytes))
            .map_err(|e| e.to_string())
    }

    fn receive(&mut self, read: &mut dyn FnMut(&[f64])) -> Result<(), String> {
        let mut len = [0u8; 8];
        self.stream
            .read_exact(&mut len)
            .map_err(|e| e.to_string())?;
        self.bytes.resize(u64::from_le_bytes(len) as usize, 0);
        self.stream
            .read_exact(&mut self.bytes)
            .map_err(|e| e.to_string())?;
        self.got = bincode::serde::decode_from_slice(&self.bytes, config())
            .map(|(v, _)| v)
            .map_err(|e| e.to_string())?;
        read(&self.got);
        Ok(())
    }

    fn answer(&mut self, _: Touch) -> Result<(), String> {
        pingpong::answer_from_copy(self, |e| &mut e.got)
    }
}

impl End {
    fn new(stream: UnixStream) -> End {
        End {
            stream,
            mine: Vec::new(),
            got: Vec::new(),
            bytes: Vec::new(),
        }
    }
}

/// `coupler bench-peer socket --path P --rounds N`: connect and answer.
pub fn peer(path: &Path, rounds: usize) -> i32 {
    let result = UnixStream::connect(path)
        .map_err(|e| format!("cannot connect to {}: {e}", path.display()))
        .and_then(|s| pingpong::pong(&mut End::new(s), rounds, Touch::Every));
    match result {
        Ok(()) => 0,
        Err(e) => {
            eprintln!("bench-peer: {e}");
            1
        }
    }
}

/// The column: every value encoded, sent, received and decoded.
pub fn rows(exe: &Path, rounds: usize) -> Result<Vec<Times>, String> {
    let path = std::env::temp_dir().join(format!(
        "canopy-bench-{}.sock",
        participant::supervisor::new_run_id()
    ));
    let listener = UnixListener::bind(&path).map_err(|e| e.to_string())?;
    let mut child = std::process::Command::new(exe)
        .args([
            "bench-peer",
            "socket",
            "--rounds",
            &rounds.to_string(),
            "--path",
        ])
        .arg(&path)
        .spawn()
        .map_err(|e| format!("cannot start the peer: {e}"))?;
    let result = listener
        .accept()
        .map_err(|e| e.to_string())
        .and_then(|(s, _)| pingpong::ping(&mut End::new(s), rounds, Touch::Every));
    if result.is_err() {
        let _ = child.kill();
    }
    let _ = child.wait();
    let _ = std::fs::remove_file(&path);
    result
}
