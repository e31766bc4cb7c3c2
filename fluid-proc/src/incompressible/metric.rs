//! The lengths one velocity component's stencils read along each axis of
//! its padded array (`padded.rs`), from the cells' widths and the faces'
//! gaps (`axis.rs`). Along its own axis c a component sits on faces: its
//! control length is the face's gap and its neighbours are a cell's width
//! away; along the others it sits at cell centres: its control length is
//! the cell's width and its neighbours are a gap away. So the flux form's
//! difference divides by the control length, and the Laplacian's term of
//! a neighbour is 1/(control length · distance to it).
//!
//! A uniform axis keeps 1/h and 1/h² (and the uniform stencil's own
//! operations in `viscosity.rs`), so a uniform grid's results stay the
//! same to the bit.

use crate::incompressible::grid::Grid;
use crate::layout::Layout;

/// Along one axis, per padded index (−g .. m + g).
#[derive(Debug, Clone)]
pub struct AlongAxis {
    /// 1/(control length) [1/m].
    pub inv_len: Vec<f64>,
    /// The control length [m].
    pub len: Vec<f64>,
    /// The Laplacian's weights of the neighbours below and above [1/m²]:
    /// None on a uniform axis, whose one weight is `uniform`.
    pub weights: Option<[Vec<f64>; 2]>,
    /// 1/h² on a uniform axis [1/m²].
    pub uniform: f64,
}

/// One component's lengths along the three axes.
#[derive(Debug, Clone)]
pub struct Metric {
    pub axes: [AlongAxis; 3],
    /// Whether any axis is graded: the viscous solve then weighs its dot
    /// products by the faces' control volumes.
    pub graded: bool,
}

impl Metric {
    /// Component `c` on the rank's cells `grid`, laid out as `lay`.
    pub fn of(grid: &Grid, c: usize, lay: &Layout) -> Metric {
        let axes = [0, 1, 2].map(|a| {
            let axis = &grid.axes[a];
            let g = lay.g[a] as isize;
            let coords = (-g..lay.m[a] as isize + g).collect::<Vec<_>>();
            // Control length and the distances to the neighbours below and above.
            let lengths = |i: isize| match a == c {
                true => (axis.gap(i), axis.width(i - 1), axis.width(i)),
                false => (axis.width(i), axis.gap(i), axis.gap(i + 1)),
            };
            let len: Vec<f64> = coords.iter().map(|&i| lengths(i).0).collect();
            let weights = (!axis.is_uniform()).then(|| {
                [1, 2].map(|t| {
                    let weight = |i: isize| {
                        let l = lengths(i);
                        1.0 / (l.0 * if t == 1 { l.1 } else { l.2 })
                    };
                    coords.iter().map(|&i| weight(i)).collect()
                })
            });
            AlongAxis {
                inv_len: len.iter().map(|l| 1.0 / l).collect(),
                len,
                weights,
                uniform: 1.0 / (axis.width(0) * axis.width(0)),
            }
        });
        Metric {
            graded: grid.is_graded(),
            axes,
        }
    }

    /// The control volume of the entry at padded coordinates `f` [m³].
    #[inline(always)]
    pub fn volume(&self, lay: &Layout, f: [isize; 3]) -> f64 {
        (0..3)
            .map(|a| self.axes[a].len[(f[a] + lay.g[a] as isize) as usize])
            .product()
    }
}
