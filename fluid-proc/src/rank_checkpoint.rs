//! Run checkpoints of a model on one rank or several (`[run]
//! checkpoint_interval`; part of the binary): every rank writes its own
//! part of the state into its own file and reads it back, and rank 0 its
//! outputs besides. Rank 0 alone speaks to the coupler and knows the run
//! directory: it tells the others at each checkpoint.

use crate::comm::Comm;
use participant::restart;
use participant::vtu::Series;
use participant::Participant;
use serde::de::DeserializeOwned;
use serde::Serialize;
use std::path::Path;

/// Where the run checkpoints go, as rank 0 tells the others: the run
/// directory and the participant's name, a line each (empty elsewhere).
#[derive(Debug, Clone, Default)]
pub struct Place(String);

impl Place {
    pub fn of(p: &Participant) -> Place {
        Place(format!("{}\n{}", p.run_dir().display(), p.name()))
    }
}

/// This rank's file of the run checkpoint of `window`, as rank 0 tells
/// every rank where it goes.
fn own_file(comm: &dyn Comm, place: &Place, window: u64) -> std::path::PathBuf {
    let mut at = place.0.clone();
    comm.broadcast_text(&mut at);
    let (run_dir, name) = at.split_once('\n').unwrap_or_default();
    restart::state_file(Path::new(run_dir), window, name, Some(comm.rank()))
}

/// Whether every rank managed its part: agreed on together, so that none
/// goes on alone.
fn agree(comm: &dyn Comm, done: Result<(), String>) -> Result<(), String> {
    let everyone = comm.min(if done.is_ok() { 1.0 } else { 0.0 }) == 1.0;
    match (done, everyone) {
        (Err(e), _) => Err(e),
        (Ok(()), false) => Err("another rank could not take its part of the run checkpoint".into()),
        (Ok(()), true) => Ok(()),
    }
}

/// Write this rank's `state` as its part of the run checkpoint of
/// `window`. Every rank calls it together.
pub fn write_part<T: Serialize>(
    comm: &dyn Comm,
    place: &Place,
    window: u64,
    state: &T,
) -> Result<(), String> {
    let path = own_file(comm, place, window);
    agree(
        comm,
        restart::write(&path, state).map_err(|e| e.to_string()),
    )
}

/// Read this rank's part of the run checkpoint of `window` back and hand
/// it to `take`, which says why it cannot take it. Every rank calls it
/// together.
pub fn read_part<T: DeserializeOwned>(
    comm: &dyn Comm,
    place: &Place,
    window: u64,
    take: impl FnOnce(T) -> Result<(), String>,
) -> Result<(), String> {
    let path = own_file(comm, place, window);
    let done = (restart::read(&path).map_err(|e| e.to_string())).and_then(|state| {
        take(state).map_err(|why| format!("{}: {why} (rank {})", path.display(), comm.rank()))
    });
    agree(comm, done)
}

/// What rank 0 keeps in a run checkpoint besides its part of the state:
/// the outputs written so far and the steps taken (for the statistics).
#[derive(serde::Serialize, serde::Deserialize)]
struct Lead {
    outputs: Vec<(f64, String)>,
    steps: u64,
}

/// Rank 0's own part of the run checkpoint of `window`.
pub fn write_lead(
    p: &Participant,
    window: u64,
    series: &Series,
    steps: u64,
) -> std::io::Result<()> {
    let lead = Lead {
        outputs: series.entries().to_vec(),
        steps,
    };
    restart::write(&p.state_file(window), &lead)
}

/// Rank 0's own part read back: `series` goes on from its outputs; the
/// steps taken.
pub fn read_lead(p: &Participant, window: u64, series: &mut Series) -> std::io::Result<u64> {
    let lead: Lead = restart::read(&p.state_file(window))?;
    series.resume(lead.outputs)?;
    Ok(lead.steps)
}
