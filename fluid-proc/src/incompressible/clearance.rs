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
    // Per axis held to the box or to the core: its span and whether graded.
    let spans = [0, 1, 2].map(|d| {
        let axis = &grid.axes[d];
        let graded = !axis.is_uniform();
        let held = graded || grid.bc[d][0] != Bc::Periodic;
        let span = match graded {
            true => axis.core(),
            false => [0.0, grid.n[d] as f64 * grid.h[d]],
        };
        held.then_some((span, graded))
    });
    for m in markers {
        for (d, span) in spans.iter().enumerate() {
            let Some(([lo, hi], graded)) = *span else {
                continue;
            };
            let room = CLEARANCE_CELLS * grid.h[d];
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

#[cfg(test)]
mod tests {
    use super::*;
    use crate::incompressible::axis::Axis;

    /// On a graded box a marker must keep three core cells from the core's
    /// edge, even where the box's side is periodic and far.
    #[test]
    fn a_marker_near_the_edge_of_a_graded_core_is_refused() {
        let a = Axis::graded(10.0, [4.0, 6.0], 0.25, 1.2, true).unwrap();
        let u = Axis::uniform(4, 2.5);
        let grid = Grid::of_axes([a, u.clone(), u], [[Bc::Periodic; 2]; 3]);
        let marker = |x: f64| Marker {
            x: [x, 5.0, 5.0],
            normal: [1.0, 0.0, 0.0],
            area: 0.01,
        };
        // The core spans 4..6 m: 4.8 m is more than three cells in, 4.7 m is not.
        assert!(keep_clear(&grid, &[marker(4.8), marker(5.2)], [0.0; 3], "the body").is_ok());
        let err = keep_clear(&grid, &[marker(4.7)], [0.0; 3], "the body").unwrap_err();
        assert!(err.contains("fine core at x_low"), "{err}");
    }
}
