//! What an immersed surface must keep from the flow box's sides.

use crate::incompressible::grid::{Bc, Grid};
use crate::surface::Marker;

/// Cells markers must keep from a side that is not periodic: the δ kernel
/// reaches two cells, and the side's face is given, not forced.
pub const CLEARANCE_CELLS: f64 = 3.0;

/// An error naming `what` (a body, the canopy) if one of its `markers` (in
/// the box's frame) comes within [`CLEARANCE_CELLS`] of a side that is not
/// periodic; `origin` is the box's low corner in the world [m].
pub fn keep_clear(
    grid: &Grid,
    markers: &[Marker],
    origin: [f64; 3],
    what: &str,
) -> Result<(), String> {
    for m in markers {
        for d in (0..3).filter(|&d| grid.bc[d][0] != Bc::Periodic) {
            let room = CLEARANCE_CELLS * grid.h[d];
            let length = grid.n[d] as f64 * grid.h[d];
            if !(room..=length - room).contains(&m.x[d]) {
                let side = ["low", "high"][(m.x[d] > length / 2.0) as usize];
                return Err(format!(
                    "{what} comes within {CLEARANCE_CELLS} cells of the flow box's {}_{side} side \
                     (at {:.4} m): the immersed boundary needs fluid round it, so enlarge \
                     [fluid.box] or move it",
                    ["x", "y", "z"][d],
                    m.x[d] + origin[d]
                ));
            }
        }
    }
    Ok(())
}
