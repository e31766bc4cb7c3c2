//! Velocities on the faces of the staggered (MAC) grid and their
//! divergence in each cell (the projection that makes it vanish:
//! `projection.rs`).
//!
//! The x-velocities sit on the n_x + 1 faces normal to x of every row of
//! cells, and so on. On a periodic axis faces 0 and n are one face, kept
//! equal. On a rank's slab (`part.rs`) the grid is the slab's.

use crate::incompressible::grid::Grid;
use crate::incompressible::rows;

/// Face velocities [m/s]: `u[d]` on the faces normal to axis d.
#[derive(Debug, Clone, PartialEq, serde::Serialize, serde::Deserialize)]
pub struct Faces {
    pub n: [usize; 3],
    pub u: [Vec<f64>; 3],
}

impl Faces {
    pub fn zeros(g: &Grid) -> Faces {
        let n = g.n;
        let count = |d: usize| {
            let mut m = n;
            m[d] += 1;
            m[0] * m[1] * m[2]
        };
        Faces {
            n,
            u: [
                vec![0.0; count(0)],
                vec![0.0; count(1)],
                vec![0.0; count(2)],
            ],
        }
    }

    /// Index of face `f` (face f[d] along d, cell rows elsewhere) normal to d.
    pub fn index(&self, d: usize, f: [usize; 3]) -> usize {
        let mut m = self.n;
        m[d] += 1;
        f[0] + m[0] * (f[1] + m[1] * f[2])
    }

    /// Largest difference of a face velocity from `other`'s [m/s].
    pub fn max_difference(&self, other: &Faces) -> f64 {
        self.u
            .iter()
            .zip(&other.u)
            .flat_map(|(a, b)| a.iter().zip(b))
            .fold(0.0, |m, (a, b)| m.max((a - b).abs()))
    }

    /// Largest face speed [m/s].
    pub fn max_abs(&self) -> f64 {
        self.u.iter().flatten().fold(0.0, |m, v| m.max(v.abs()))
    }
}

/// Calls `f(cell, below, up)` for every cell in index order: `below[d]` is
/// the index of the cell's face normal to d on its low side, and
/// `below[d] + up[d]` the one on its high side.
pub fn for_each_cell_faces(n: [usize; 3], mut f: impl FnMut(usize, [usize; 3], [usize; 3])) {
    let m = [0, 1, 2].map(|d| face_counts(n, d));
    let up = [0, 1, 2].map(|d| [1, m[d][0], m[d][0] * m[d][1]][d]);
    let mut cell = 0;
    for k in 0..n[2] {
        for j in 0..n[1] {
            let row = [0, 1, 2].map(|d| m[d][0] * (j + m[d][1] * k));
            for i in 0..n[0] {
                f(cell, row.map(|r| r + i), up);
                cell += 1;
            }
        }
    }
}

/// div[c] = Σ_d (u_d above − u_d below)/w_d, w_d the cell's width along d
/// (h_d on a uniform axis) [1/s].
pub fn divergence(g: &Grid, u: &Faces, div: &mut [f64]) {
    let n = g.n;
    let inv_w: [Vec<f64>; 3] = [0, 1, 2].map(|d| {
        (0..n[d])
            .map(|i| 1.0 / g.axes[d].width(i as isize))
            .collect()
    });
    // Faces normal to d: their counts, and the step from the face below a
    // cell to the one above it.
    let m = [0, 1, 2].map(|d| face_counts(n, d));
    let up = [0, 1, 2].map(|d| [1, m[d][0], m[d][0] * m[d][1]][d]);
    rows::each_plain(div, n, |j, k, row| {
        let first = m.map(|m| m[0] * (j + m[1] * k));
        let inv = [0, j, k];
        for (i, out) in row.iter_mut().enumerate() {
            *out = (0..3)
                .map(|d| {
                    let below = first[d] + i;
                    let at = if d == 0 { i } else { inv[d] };
                    (u.u[d][below + up[d]] - u.u[d][below]) * inv_w[d][at]
                })
                .sum();
        }
    });
}

/// Faces along each axis of the faces normal to d: n + 1 along d.
pub fn face_counts(n: [usize; 3], d: usize) -> [usize; 3] {
    let mut m = n;
    m[d] += 1;
    m
}
