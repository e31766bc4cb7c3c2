//! A participant's monitor rows: the newest value of every declared monitor
//! at the start and at each window end, sent to the coupler in batches so
//! that reporting costs no wake-up per window.

use std::collections::HashMap;
use std::time::{Duration, Instant};

/// Rows wait at most this long before they go to the coupler (which looks
/// every 20 ms).
const FLUSH_EVERY: Duration = Duration::from_millis(50);
/// And at most this many values (32 KiB).
const FLUSH_VALUES: usize = 4096;

/// A named scalar the coupler writes to `monitors.csv` as `participant.name`.
#[derive(Debug, Clone, PartialEq)]
pub struct Monitor {
    pub name: String,
    pub value: f64,
}

impl Monitor {
    pub fn new(name: impl Into<String>, value: f64) -> Self {
        Monitor {
            name: name.into(),
            value,
        }
    }
}

pub struct Rows {
    column: HashMap<String, usize>,
    /// Newest value per column; NaN until first reported.
    latest: Vec<f64>,
    /// Rows not yet sent, flat, the first of them numbered `first_row`.
    batch: Vec<f64>,
    first_row: u64,
    /// Rows closed so far (a participant without monitors closes rows too).
    closed: u64,
    last_flush: Instant,
}

/// A batch of rows to send: the number of the first, how many, the width, the values.
pub struct Batch {
    pub first_row: u64,
    pub rows: u64,
    pub width: u32,
    pub values: Vec<f64>,
}

impl Rows {
    pub fn new(names: &[String]) -> Rows {
        Rows {
            column: names
                .iter()
                .enumerate()
                .map(|(i, n)| (n.clone(), i))
                .collect(),
            latest: vec![f64::NAN; names.len()],
            batch: Vec::new(),
            first_row: 0,
            closed: 0,
            last_flush: Instant::now(),
        }
    }

    /// Keep the newest values; a name that was not declared is returned.
    pub fn update(&mut self, monitors: &[Monitor]) -> Result<(), String> {
        for m in monitors {
            match self.column.get(&m.name) {
                Some(&i) => self.latest[i] = m.value,
                None => return Err(m.name.clone()),
            }
        }
        Ok(())
    }

    /// The newest value of each column.
    pub fn latest(&self) -> &[f64] {
        &self.latest
    }

    /// A restarted run: `closed` rows were closed before, the last with
    /// the values `latest`. Returns false when their count does not match
    /// the declared monitors.
    pub fn resume(&mut self, latest: &[f64], closed: u64) -> bool {
        if latest.len() != self.latest.len() {
            return false;
        }
        self.latest.copy_from_slice(latest);
        self.batch.clear();
        (self.first_row, self.closed) = (closed, closed);
        true
    }

    /// Close a row with the newest values.
    pub fn push_row(&mut self) {
        self.batch.extend_from_slice(&self.latest);
        self.closed += 1;
    }

    /// The rows to send now, if any: all of them when `force`, otherwise
    /// when the last batch left long enough ago or this one is large.
    pub fn take(&mut self, force: bool) -> Option<Batch> {
        let due =
            force || self.batch.len() >= FLUSH_VALUES || self.last_flush.elapsed() >= FLUSH_EVERY;
        let rows = self.closed - self.first_row;
        if !due || rows == 0 {
            return None;
        }
        self.last_flush = Instant::now();
        let first_row = self.first_row;
        self.first_row = self.closed;
        Some(Batch {
            first_row,
            rows,
            width: self.latest.len() as u32,
            values: std::mem::take(&mut self.batch),
        })
    }
}
