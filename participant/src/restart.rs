//! Run checkpoints on disk (`[run] checkpoint_interval`) and the files a
//! restarted run reads back (`coupler run --restart`).
//!
//! At a due window end every participant writes its state into the
//! window's directory, `checkpoints/<window>/`: the solver its own file (or
//! one per rank), then the library its part (the monitors' newest values,
//! the implicit scheme's acceleration state). Every file is written whole
//! or not at all (a temporary file, synced and renamed), and the library's
//! part goes last, so a checkpoint is complete when every participant's
//! library file is there, whenever the run was killed. Each participant
//! then removes its files from all but its [`KEEP`] newest checkpoints.

use serde::de::DeserializeOwned;
use serde::{Deserialize, Serialize};
use std::io::{self, Write};
use std::path::{Path, PathBuf};

/// The run directory's folder of run checkpoints.
pub const DIR: &str = "checkpoints";

/// The directory of the run checkpoint at the end of `window`.
pub fn dir(run_dir: &Path, window: u64) -> PathBuf {
    run_dir.join(DIR).join(format!("{window:012}"))
}

/// The file participant `name` writes its state into; `part` numbers the
/// files of a participant that writes several (one per MPI rank).
pub fn state_file(run_dir: &Path, window: u64, name: &str, part: Option<usize>) -> PathBuf {
    dir(run_dir, window).join(match part {
        None => format!("{name}.state"),
        Some(k) => format!("{name}.{k}.state"),
    })
}

/// The library's part of participant `name`'s checkpoint, written last.
fn library_file(run_dir: &Path, window: u64, name: &str) -> PathBuf {
    dir(run_dir, window).join(format!("{name}.library"))
}

/// Write `value` to `path` whole or not at all: into a temporary file
/// beside it, synced, then renamed over it.
pub fn write<T: Serialize>(path: &Path, value: &T) -> io::Result<()> {
    let bytes = bincode::serde::encode_to_vec(value, bincode::config::standard())
        .map_err(|e| io::Error::other(format!("cannot encode {}: {e}", path.display())))?;
    let with_path = |e: io::Error| io::Error::new(e.kind(), format!("{}: {e}", path.display()));
    if let Some(parent) = path.parent() {
        std::fs::create_dir_all(parent).map_err(with_path)?;
    }
    let partial = crate::atomic::aside(path);
    let mut file = std::fs::File::create(&partial).map_err(with_path)?;
    file.write_all(&bytes).map_err(with_path)?;
    file.sync_all().map_err(with_path)?;
    std::fs::rename(&partial, path).map_err(with_path)
}

/// Read back what [`write`] wrote to `path`.
pub fn read<T: DeserializeOwned>(path: &Path) -> io::Result<T> {
    let bytes = std::fs::read(path)
        .map_err(|e| io::Error::new(e.kind(), format!("{}: {e}", path.display())))?;
    bincode::serde::decode_from_slice(&bytes, bincode::config::standard())
        .map(|(v, _)| v)
        .map_err(|e| {
            let msg = format!("{} is not a checkpoint of this build: {e}", path.display());
            io::Error::new(io::ErrorKind::InvalidData, msg)
        })
}

/// The windows of the complete run checkpoints in `run_dir`, every one of
/// `names` having written its part, oldest first.
pub fn complete(run_dir: &Path, names: &[String]) -> Vec<u64> {
    let Ok(entries) = std::fs::read_dir(run_dir.join(DIR)) else {
        return Vec::new();
    };
    let mut windows: Vec<u64> = entries
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse().ok())
        .filter(|&w| names.iter().all(|n| library_file(run_dir, w, n).is_file()))
        .collect();
    windows.sort_unstable();
    windows
}

/// Run checkpoints each participant keeps: its files in older ones are
/// removed as it writes a new one. Two, so that a run killed while it
/// writes one still has the one before.
pub const KEEP: usize = 2;

/// Remove participant `name`'s files from the run checkpoints it wrote
/// but the [`KEEP`] newest; a checkpoint's directory left empty goes too.
pub fn prune(run_dir: &Path, name: &str) -> io::Result<()> {
    let mut mine: Vec<u64> = std::fs::read_dir(run_dir.join(DIR))?
        .filter_map(|e| e.ok()?.file_name().to_str()?.parse().ok())
        .filter(|&w| library_file(run_dir, w, name).is_file())
        .collect();
    mine.sort_unstable();
    let prefix = format!("{name}.");
    for &w in mine.iter().rev().skip(KEEP) {
        let dir = dir(run_dir, w);
        for entry in std::fs::read_dir(&dir)?.flatten() {
            let own = entry
                .file_name()
                .to_str()
                .is_some_and(|n| n.starts_with(&prefix));
            if own {
                std::fs::remove_file(entry.path())?;
            }
        }
        // Others' files may still be there.
        let _ = std::fs::remove_dir(&dir);
    }
    Ok(())
}

/// The library's part of a participant's run checkpoint.
#[derive(Serialize, Deserialize)]
pub(crate) struct LibraryState {
    /// The newest value of each declared monitor, as the last row closed.
    pub monitors: Vec<f64>,
    /// The implicit scheme's acceleration state (IQN-ILS's columns of the
    /// windows before, what was sent last), when the run is implicit.
    pub accelerator: Option<crate::acceleration::Accelerator>,
}

impl LibraryState {
    pub fn write(&self, run_dir: &Path, window: u64, name: &str) -> io::Result<()> {
        write(&library_file(run_dir, window, name), self)
    }

    pub fn read(run_dir: &Path, window: u64, name: &str) -> io::Result<LibraryState> {
        read(&library_file(run_dir, window, name))
    }
}
