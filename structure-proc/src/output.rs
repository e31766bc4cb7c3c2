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
