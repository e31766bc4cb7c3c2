//! `monitors.csv`: one row at the start and one per coupling window, with
//! the total kinetic and potential energy and every monitor the
//! participants declared, as `participant.name`, in the scenario's order
//! of participants and each one's order of declaration.
//!
//! Participants send their rows in batches as they run; a row is written
//! once every participant has sent it. The file is created with its header
//! only once the columns are known, so it never exists without one, and
//! every row is written whole: a failed write leaves the rows before it.

use participant::{Declaration, Timing};
use std::collections::VecDeque;
use std::io::Write;
use std::path::{Path, PathBuf};

/// One participant's columns and the rows it sent that are not written yet.
struct Part {
    width: usize,
    pending: VecDeque<Vec<f64>>,
    /// Number of the next row expected from it.
    next: u64,
}

/// The file beside `monitors.csv` that gives each column's unit.
pub const UNITS: &str = "units.csv";

pub struct Monitors {
    path: PathBuf,
    file: std::fs::File,
    /// Whole lines not yet written, and the file's length up to the last
    /// whole line written.
    buffer: String,
    length: u64,
    parts: Vec<Part>,
    /// (participant, column) of every `kinetic_energy` and `potential_energy`.
    kinetic: Vec<(usize, usize)>,
    potential: Vec<(usize, usize)>,
    /// (participant, column) of the tries per window of an implicit run.
    tries: Option<(usize, usize)>,
    /// The last window's tries and their sum over the windows.
    pub last_tries: f64,
    pub total_tries: f64,
    timing: Timing,
    /// Rows written so far.
    pub written: u64,
}

/// Why a row could not be taken or written.
#[derive(Debug, thiserror::Error)]
pub enum MonitorsError {
    #[error("cannot write {path}: {source}")]
    Io {
        path: String,
        source: std::io::Error,
    },
    #[error("participant `{0}` sent monitor rows out of order or of the wrong width")]
    Malformed(String),
    #[error(
        "{0} has other columns than the participants now declare: the run cannot go on \
         in it"
    )]
    Columns(String),
}

fn io_error(path: &Path, source: std::io::Error) -> MonitorsError {
    MonitorsError::Io {
        path: path.display().to_string(),
        source,
    }
}

/// Cut `path` back to its header and first `rows` rows; false when it
/// has fewer whole rows than that (a partial last line never counts).
pub fn keep_rows(path: &Path, rows: u64) -> std::io::Result<bool> {
    let text = std::fs::read(path)?;
    let ends = text.iter().enumerate().filter(|(_, &b)| b == b'\n');
    // The header's newline, then one per row.
    let Some((end, _)) = ends.clone().nth(rows as usize) else {
        return Ok(false);
    };
    let file = std::fs::OpenOptions::new().write(true).open(path)?;
    file.set_len(end as u64 + 1)?;
    Ok(true)
}

/// The columns: the header, and where the energies and the tries are.
struct Layout {
    header: String,
    /// `units.csv`: each column of `monitors.csv` with its declared unit.
    units: String,
    widths: Vec<usize>,
    kinetic: Vec<(usize, usize)>,
    potential: Vec<(usize, usize)>,
    tries: Option<(usize, usize)>,
}

impl Layout {
    /// `units.csv` beside `monitors` (at `monitors`).
    fn write_units(&self, monitors: &Path) -> Result<(), MonitorsError> {
        let path = monitors.with_file_name(UNITS);
        participant::atomic::write_atomic(&path, &self.units).map_err(|e| io_error(&path, e))
    }

    /// `names[i]` declared `declarations[i]`.
    fn of(names: &[String], declarations: &[Declaration]) -> Layout {
        let mut header = String::from("time,kinetic_energy,potential_energy");
        let mut units = String::from("column,unit\ntime,s\nkinetic_energy,J\npotential_energy,J\n");
        let (mut kinetic, mut potential, mut tries) = (Vec::new(), Vec::new(), None);
        for (p, (name, d)) in names.iter().zip(declarations).enumerate() {
            for (c, m) in d.monitor_names().iter().enumerate() {
                header.push_str(&format!(",{name}.{m}"));
                units.push_str(&format!("{name}.{m},{}\n", d.unit_of(m)));
                match m.as_str() {
                    "kinetic_energy" => kinetic.push((p, c)),
                    "potential_energy" => potential.push((p, c)),
                    participant::scheme::TRIES => tries = Some((p, c)),
                    _ => {}
                }
            }
        }
        Layout {
            header,
            units,
            widths: declarations
                .iter()
                .map(|d| d.monitor_names().len())
                .collect(),
            kinetic,
            potential,
            tries,
        }
    }
}

impl Monitors {
    /// Create `path` with its header: `names[i]` declared `declarations[i]`.
    pub fn create(
        path: &Path,
        names: &[String],
        declarations: &[Declaration],
        timing: &Timing,
    ) -> Result<Monitors, MonitorsError> {
        let layout = Layout::of(names, declarations);
        layout.write_units(path)?;
        // Written aside and renamed, so the file appears with its header.
        let header = format!("{}\n", layout.header);
        participant::atomic::write_atomic(path, &header).map_err(|e| io_error(path, e))?;
        Monitors::open(path, layout, timing, 0)
    }

    /// A restarted run's: `path` holds the header and the first `rows`
    /// rows (`keep_rows`), and the participants send the rows after them.
    pub fn resume(
        path: &Path,
        names: &[String],
        declarations: &[Declaration],
        timing: &Timing,
        rows: u64,
    ) -> Result<Monitors, MonitorsError> {
        let layout = Layout::of(names, declarations);
        let text = std::fs::read_to_string(path).map_err(|e| io_error(path, e))?;
        if text.lines().next() != Some(layout.header.as_str()) {
            return Err(MonitorsError::Columns(path.display().to_string()));
        }
        layout.write_units(path)?;
        let tries = layout
            .tries
            .map(|(p, c)| 3 + layout.widths[..p].iter().sum::<usize>() + c);
        let mut m = Monitors::open(path, layout, timing, rows)?;
        // The tries of the windows before, for the progress line's mean.
        let column = tries.into_iter().flat_map(|i| {
            let rows = text.lines().skip(2);
            rows.filter_map(move |l| l.split(',').nth(i)?.parse::<f64>().ok())
        });
        for t in column {
            (m.last_tries, m.total_tries) = (t, m.total_tries + t);
        }
        Ok(m)
    }

    /// Rows go on in `path` after its first `rows`.
    fn open(
        path: &Path,
        layout: Layout,
        timing: &Timing,
        rows: u64,
    ) -> Result<Monitors, MonitorsError> {
        let file = std::fs::OpenOptions::new()
            .append(true)
            .open(path)
            .map_err(|e| io_error(path, e))?;
        let length = file.metadata().map_err(|e| io_error(path, e))?.len();
        Ok(Monitors {
            path: path.to_path_buf(),
            file,
            buffer: String::new(),
            length,
            parts: layout
                .widths
                .iter()
                .map(|&width| Part {
                    width,
                    pending: VecDeque::new(),
                    next: rows,
                })
                .collect(),
            kinetic: layout.kinetic,
            potential: layout.potential,
            tries: layout.tries,
            last_tries: f64::NAN,
            total_tries: 0.0,
            timing: *timing,
            written: rows,
        })
    }

    /// Take `rows` rows from participant `p` (named `name`), starting at `first_row`.
    pub fn add(
        &mut self,
        p: usize,
        name: &str,
        first_row: u64,
        rows: u64,
        width: u32,
        values: Vec<f64>,
    ) -> Result<(), MonitorsError> {
        let part = &mut self.parts[p];
        let ok = first_row == part.next
            && width as usize == part.width
            && values.len() as u64 == rows * width as u64;
        if !ok {
            return Err(MonitorsError::Malformed(name.to_string()));
        }
        part.next += rows;
        for r in 0..rows as usize {
            let row = match part.width {
                0 => Vec::new(),
                w => values[r * w..(r + 1) * w].to_vec(),
            };
            part.pending.push_back(row);
        }
        Ok(())
    }

    /// Simulated time of row `r`: the start, then each window's end.
    pub fn time_of(&self, r: u64) -> f64 {
        match r {
            0 => self.timing.start_time,
            _ => {
                let (t, dt) = self.timing.window_span(r - 1);
                t + dt
            }
        }
    }

    /// Take every row all participants have sent into the file's buffer;
    /// returns how many.
    pub fn complete_rows(&mut self) -> u64 {
        let mut n = 0;
        while self.parts.iter().all(|p| !p.pending.is_empty()) {
            let line = self.line();
            if let (Some((p, c)), true) = (self.tries, self.written > 0) {
                self.last_tries = self.parts[p].pending[0][c];
                self.total_tries += self.last_tries;
            }
            for p in &mut self.parts {
                p.pending.pop_front();
            }
            self.buffer.push_str(&line);
            self.buffer.push('\n');
            self.written += 1;
            n += 1;
        }
        n
    }

    /// The next row, from the front of every participant's queue.
    fn line(&self) -> String {
        let value = |&(p, c): &(usize, usize)| self.parts[p].pending[0][c];
        let kinetic: f64 = self.kinetic.iter().map(value).sum();
        let potential: f64 = self.potential.iter().map(value).sum();
        let mut line = format!("{},{kinetic},{potential}", self.time_of(self.written));
        for p in &self.parts {
            for v in &p.pending[0] {
                line.push_str(&format!(",{v}"));
            }
        }
        line
    }

    fn io(&self, source: std::io::Error) -> MonitorsError {
        io_error(&self.path, source)
    }

    /// Write the buffered rows, in pieces of whole rows. If a write fails
    /// (a full disk), the file is cut back to its last whole row, so it
    /// stays readable and keeps every row that fitted, however many were
    /// buffered at once.
    pub fn flush(&mut self) -> Result<(), MonitorsError> {
        while !self.buffer.is_empty() {
            let piece = whole_rows(&self.buffer, FLUSH_PIECE);
            match self.file.write_all(&self.buffer.as_bytes()[..piece]) {
                Ok(()) => {
                    self.length += piece as u64;
                    self.buffer.drain(..piece);
                }
                Err(e) => {
                    let _ = self.file.set_len(self.length);
                    return Err(self.io(e));
                }
            }
        }
        Ok(())
    }

    /// Make the rows written so far durable: a run checkpoint that goes
    /// with them is complete only after this.
    pub fn sync(&self) -> Result<(), MonitorsError> {
        self.file.sync_data().map_err(|e| self.io(e))
    }
}

/// Bytes of rows written at once (at least one whole row).
const FLUSH_PIECE: usize = 64 << 10;

/// The length of the longest run of whole rows of `buffer` within `most`
/// bytes, or of its first row if that is longer.
fn whole_rows(buffer: &str, most: usize) -> usize {
    if buffer.len() <= most {
        return buffer.len();
    }
    let bytes = buffer.as_bytes();
    let within = bytes[..most].iter().rposition(|&b| b == b'\n');
    let first = bytes.iter().position(|&b| b == b'\n');
    within.or(first).map_or(buffer.len(), |i| i + 1)
}

#[cfg(test)]
mod tests {
    use super::whole_rows;

    /// A piece ends after a row's newline, within the limit, or after the
    /// first row if even that is longer.
    #[test]
    fn pieces_are_whole_rows() {
        let buffer = "0.1,2\n0.2,3\n0.3,4\n";
        assert_eq!(whole_rows(buffer, 100), buffer.len());
        assert_eq!(whole_rows(buffer, 13), 12);
        assert_eq!(whole_rows(buffer, 11), 6);
        assert_eq!(whole_rows(buffer, 3), 6);
    }
}
