//! Where each value of a field sits in an array padded with ghost layers
//! on every side: the incompressible flow's face velocities (`padded.rs`)
//! and the Euler gas's cells (`euler/`) both carry three, so that WENO5's
//! stencils read the same way at a side as inside.

/// Ghost layers per side: WENO5 reads three values beyond a face.
pub const GHOSTS: usize = 3;

/// Where each face of one component sits in its padded array.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Layout {
    /// Faces along each axis without ghosts: n + 1 along c, n elsewhere.
    pub m: [usize; 3],
    /// Ghost layers per axis (GHOSTS, or 0 on an axis one cell thick).
    pub g: [usize; 3],
    pub stride: [usize; 3],
    /// The faces the momentum equation updates, as [low, high) per axis: a
    /// face on a side with a given velocity is not one of them, nor is the
    /// periodic repeat (face n) of face 0.
    pub unknown: [[usize; 2]; 3],
}

impl Layout {
    /// Index of face `f` (ghosts at negative or ≥ m coordinates).
    #[inline(always)]
    pub fn at(&self, f: [isize; 3]) -> usize {
        (0..3)
            .map(|a| (f[a] + self.g[a] as isize) as usize * self.stride[a])
            .sum()
    }

    pub fn dims(&self) -> [usize; 3] {
        [0, 1, 2].map(|a| self.m[a] + 2 * self.g[a])
    }

    /// Calls `f` with the index of every face in the box `range` (face
    /// coordinates, ghosts included when the range reaches into them).
    #[inline(always)]
    pub fn for_box(&self, range: [[isize; 2]; 3], mut f: impl FnMut([isize; 3], usize)) {
        for k in range[2][0]..range[2][1] {
            for j in range[1][0]..range[1][1] {
                let mut p = self.at([range[0][0], j, k]);
                for i in range[0][0]..range[0][1] {
                    f([i, j, k], p);
                    p += 1;
                }
            }
        }
    }

    /// A layout of cell-centred values: n cells, ghosts on each axis more
    /// than one cell thick, every cell an unknown.
    pub fn cells(n: [usize; 3]) -> Layout {
        Layout::cells_with(n, n.map(|n| if n > 1 { GHOSTS } else { 0 }))
    }

    /// A layout of cell-centred values with `g` ghost layers per axis.
    pub fn cells_with(n: [usize; 3], g: [usize; 3]) -> Layout {
        let dims = [0, 1, 2].map(|a| n[a] + 2 * g[a]);
        Layout {
            m: n,
            g,
            stride: [1, dims[0], dims[0] * dims[1]],
            unknown: n.map(|n| [0, n]),
        }
    }

    /// Calls `f` with the index of entry 0 along axis `a` of every line
    /// along a, over the whole padded range of the other two axes.
    pub fn for_each_line(&self, a: usize, mut f: impl FnMut(usize)) {
        let dims = self.dims();
        let (b, e) = ((a + 1) % 3, (a + 2) % 3);
        for ie in 0..dims[e] {
            for ib in 0..dims[b] {
                let mut at = [0isize; 3];
                at[b] = ib as isize - self.g[b] as isize;
                at[e] = ie as isize - self.g[e] as isize;
                f(self.at(at));
            }
        }
    }

    /// The box of unknown faces.
    pub fn unknown_box(&self) -> [[isize; 2]; 3] {
        self.unknown.map(|[lo, hi]| [lo as isize, hi as isize])
    }
}
