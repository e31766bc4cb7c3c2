//! Child processes: start them, keep the tail of their stderr, notice when
//! they exit, stop them, and always reap them (iceoryx2 sees a process as dead
//! only once its parent has waited on it).

use std::collections::VecDeque;
use std::os::unix::process::ExitStatusExt;
use std::path::Path;
use std::process::{ExitStatus, Stdio};
use std::sync::{Arc, Mutex};
use std::time::Instant;
use tokio::io::{AsyncBufReadExt, AsyncWriteExt, BufReader};
use tokio::sync::mpsc;
use tokio::task::JoinHandle;

/// Lines of stderr kept to quote when a participant fails.
const TAIL_LINES: usize = 12;

pub struct Child {
    pub role: String,
    pub program: String,
    pub pid: u32,
    pub started: Instant,
    pub exited: Option<(ExitStatus, Instant)>,
    pub tail: Arc<Mutex<VecDeque<String>>>,
    readers: Vec<JoinHandle<()>>,
}

/// A child's exit, sent by its waiting task.
pub struct Exit {
    pub role: String,
    pub status: std::io::Result<ExitStatus>,
    pub at: Instant,
}

pub fn describe(status: &ExitStatus) -> String {
    match (status.code(), status.signal()) {
        (Some(c), _) => format!("exited with status {c}"),
        (None, Some(9)) => "was killed by signal 9 (SIGKILL)".into(),
        (None, Some(s)) => format!("was killed by signal {s}"),
        _ => "ended".into(),
    }
}

/// Start `program` for participant `role`; its stdout and stderr go to
/// `logs/<role>.log` in the run directory, and its exit is sent on `exits`.
pub fn spawn(
    role: &str,
    program: &Path,
    args: &[String],
    env: &[(&str, String)],
    run_dir: &Path,
    exits: mpsc::UnboundedSender<Exit>,
) -> std::io::Result<Child> {
    let mut cmd = tokio::process::Command::new(program);
    cmd.args(args)
        .stdin(Stdio::null())
        .stdout(Stdio::piped())
        .stderr(Stdio::piped())
        // Its own process group: Ctrl-C reaches only the coupler, which stops
        // the participants itself.
        .process_group(0)
        .kill_on_drop(true);
    // If the coupler itself dies (SIGKILL, a closed terminal), the participants
    // must not run on: the kernel kills them with it. A coupler that died
    // between the fork and the prctl is no longer the parent by then, and
    // the child gives up rather than run as an orphan.
    let coupler = std::process::id();
    // SAFETY: prctl, getppid and _exit are async-signal-safe and touch only
    // the child being started.
    unsafe {
        cmd.pre_exec(move || {
            if libc::prctl(libc::PR_SET_PDEATHSIG, libc::SIGKILL) != 0 {
                return Err(std::io::Error::last_os_error());
            }
            if libc::getppid() as u32 != coupler {
                libc::_exit(1);
            }
            Ok(())
        });
    }
    for (k, v) in env {
        cmd.env(k, v);
    }
    let mut child = cmd.spawn()?;
    let pid = child.id().unwrap_or(0);
    let logs = run_dir.join("logs");
    std::fs::create_dir_all(&logs)?;
    let log_path = logs.join(format!("{role}.log"));
    let tail = Arc::new(Mutex::new(VecDeque::new()));
    let mut readers = Vec::new();
    if let Some(err) = child.stderr.take() {
        readers.push(tokio::spawn(pump(
            err,
            log_path.clone(),
            Some(tail.clone()),
        )));
    }
    if let Some(out) = child.stdout.take() {
        readers.push(tokio::spawn(pump(out, log_path, None)));
    }
    let name = role.to_string();
    tokio::spawn(async move {
        let status = child.wait().await;
        let _ = exits.send(Exit {
            role: name,
            status,
            at: Instant::now(),
        });
    });
    Ok(Child {
        role: role.to_string(),
        program: program.display().to_string(),
        pid,
        started: Instant::now(),
        exited: None,
        tail,
        readers,
    })
}

/// Copy a child's output line by line into its log, keeping the last lines in `tail`.
async fn pump(
    from: impl tokio::io::AsyncRead + Unpin,
    log_path: std::path::PathBuf,
    tail: Option<Arc<Mutex<VecDeque<String>>>>,
) {
    let mut log = tokio::fs::OpenOptions::new()
        .create(true)
        .append(true)
        .open(&log_path)
        .await
        .ok();
    let mut lines = BufReader::new(from).lines();
    while let Ok(Some(line)) = lines.next_line().await {
        if let Some(f) = log.as_mut() {
            let _ = f.write_all(format!("{line}\n").as_bytes()).await;
        }
        if let Some(tail) = &tail {
            let mut t = tail.lock().unwrap_or_else(|e| e.into_inner());
            if t.len() == TAIL_LINES {
                t.pop_front();
            }
            t.push_back(line);
        }
    }
}

impl Child {
    /// SIGKILL the child's process group, unless it already exited.
    pub fn kill(&self) {
        if self.exited.is_none() && self.pid > 0 {
            // SAFETY: plain syscall; the group id equals the pid (process_group(0)),
            // and the pid is not reaped (so not reused) until its waiting task sees the exit.
            unsafe {
                libc::kill(-(self.pid as i32), libc::SIGKILL);
            }
        }
    }

    /// Wait until stderr and stdout are drained, so the tail is complete.
    pub async fn drain(&mut self) {
        for r in self.readers.drain(..) {
            let _ = tokio::time::timeout(std::time::Duration::from_secs(2), r).await;
        }
    }

    pub fn tail(&self) -> Vec<String> {
        self.tail
            .lock()
            .unwrap_or_else(|e| e.into_inner())
            .iter()
            .cloned()
            .collect()
    }

    pub fn wall_s(&self) -> Option<f64> {
        self.exited.map(|(_, at)| (at - self.started).as_secs_f64())
    }
}
