//! `.vtu` output of the canopy and the strings.

use crate::model::Model;
use participant::vtu::{CellKind, Piece, Series};

pub struct Output {
    canopy: Option<Series>,
    strings: Option<Series>,
}

impl Output {
    pub fn new(run_dir: &std::path::Path, m: &Model) -> Output {
        Output {
            canopy: (m.canopy_nodes > 0).then(|| Series::new(run_dir, "canopy")),
            strings: (m.nodes() > m.canopy_nodes).then(|| Series::new(run_dir, "strings")),
        }
    }

    /// The outputs written so far, canopy's and strings', for a run checkpoint.
    pub fn entries(&self) -> [Option<Vec<(f64, String)>>; 2] {
        [&self.canopy, &self.strings].map(|s| s.as_ref().map(|s| s.entries().to_vec()))
    }

    /// A restarted run: the outputs [`Output::entries`] gave.
    pub fn resume(&mut self, entries: [Option<Vec<(f64, String)>>; 2]) -> std::io::Result<()> {
        let [canopy, strings] = entries;
        for (series, entries) in [(&mut self.canopy, canopy), (&mut self.strings, strings)] {
            if let (Some(series), Some(entries)) = (series, entries) {
                series.resume(entries)?;
            }
        }
        Ok(())
    }

    pub fn write(&mut self, m: &Model, index: u64, time: f64) -> std::io::Result<()> {
        if let Some(series) = &mut self.canopy {
            let n = m.canopy_nodes;
            let conn: Vec<usize> = m.triangles.iter().flatten().copied().collect();
            series.write(
                index,
                time,
                &Piece {
                    points: &m.x[..3 * n],
                    kind: CellKind::Triangle,
                    connectivity: &conn,
                    point_data: vec![("velocity", 3, &m.v[..3 * n])],
                },
            )?;
        }
        if let Some(series) = &mut self.strings {
            // All nodes: lines start on the canopy's skirt.
            let base = 0;
            let conn: Vec<usize> = m
                .springs
                .iter()
                .filter(|s| s.tension_only)
                .flat_map(|s| [s.i, s.j])
                .collect();
            series.write(
                index,
                time,
                &Piece {
                    points: &m.x[3 * base..],
                    kind: CellKind::Line,
                    connectivity: &conn,
                    point_data: vec![("velocity", 3, &m.v[3 * base..])],
                },
            )?;
        }
        Ok(())
    }
}
