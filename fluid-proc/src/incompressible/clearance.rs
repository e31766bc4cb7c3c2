//! What an immersed surface must keep from the flow box's sides.

use crate::incompressible::grid::{Bc, Grid};
use crate::surface::Marker;

/// Cells markers must keep from a side that is not periodic: the δ kernel
/// reaches two cells, and the side's face is given, not forced.
pub const CLEARANCE_CELLS: f64 = 3.0;

/// An error naming `what` (a body, the canopy) if one of its `markers` (in
/// the box's frame) comes within [`CLEARANCE_CELLS`] of a side that is not
/// periodic, or, along a graded axis (`axis.rs`), of the end of the fine
/// core, where the δ kernel's cells would no longer be of one width;
/// `origin` is the box's low corner in the world [m].
pub fn keep_clear(
    grid: &Grid,
    markers: &[Marker],
    origin: [f64; 3],
    what: &str,
) -> Result<(), String> {
    for m in markers {
        for d in 0..3 {
            let axis = &grid.axes[d];
            let graded = !axis.is_uniform();
            if grid.bc[d][0] == Bc::Periodic && !graded {
                continue;
            }
            let room = CLEARANCE_CELLS * grid.h[d];
            let [lo, hi] = match graded {
                true => axis.core(),
                false => [0.0, grid.n[d] as f64 * grid.h[d]],
            };
            if !(lo + room..=hi - room).contains(&m.x[d]) {
                let side = ["low", "high"][(m.x[d] > 0.5 * (lo + hi)) as usize];
                let name = format!("{}_{side}", ["x", "y", "z"][d]);
                let (edge, cure) = match graded {
                    true => (
                        format!("the edge of the flow box's fine core at {name}"),
                        "widen [fluid.box.core]",
                    ),
                    false => (format!("the flow box's {name} side"), "enlarge [fluid.box]"),
                };
                return Err(format!(
                    "{what} comes within {CLEARANCE_CELLS} cells of {edge} (at {:.4} m): the \
                     immersed boundary needs fluid round it, so {cure} or move it",
                    m.x[d] + origin[d]
                ));
            }
        }
    }
    Ok(())
}
