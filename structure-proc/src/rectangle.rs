//! A rectangular cloth: an nx × ny grid of nodes in the plane z = height,
//! each cell split into two triangles along alternating diagonals so the mesh
//! has no preferred shear direction.

pub struct RectangleMesh {
    /// xyz per node, row by row from y = 0.
    pub points: Vec<f64>,
    /// Counter-clockwise seen from +z.
    pub triangles: Vec<[usize; 3]>,
    pub nx: usize,
    pub ny: usize,
}

impl RectangleMesh {
    pub fn node(&self, i: usize, j: usize) -> usize {
        j * self.nx + i
    }

    /// Nodes on one edge: `x0` (x = 0), `x1`, `y0`, `y1`.
    pub fn edge(&self, which: Edge) -> Vec<usize> {
        match which {
            Edge::X0 => (0..self.ny).map(|j| self.node(0, j)).collect(),
            Edge::X1 => (0..self.ny).map(|j| self.node(self.nx - 1, j)).collect(),
            Edge::Y0 => (0..self.nx).map(|i| self.node(i, 0)).collect(),
            Edge::Y1 => (0..self.nx).map(|i| self.node(i, self.ny - 1)).collect(),
        }
    }
}

#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Edge {
    X0,
    X1,
    Y0,
    Y1,
}

/// A `width` × `depth` rectangle with `nx` × `ny` nodes (each at least 2), corner at `origin`.
pub fn rectangle(width: f64, depth: f64, nx: usize, ny: usize, origin: [f64; 3]) -> RectangleMesh {
    let mut points = Vec::with_capacity(3 * nx * ny);
    for j in 0..ny {
        for i in 0..nx {
            points.push(origin[0] + width * i as f64 / (nx - 1) as f64);
            points.push(origin[1] + depth * j as f64 / (ny - 1) as f64);
            points.push(origin[2]);
        }
    }
    let mut triangles = Vec::with_capacity(2 * (nx - 1) * (ny - 1));
    for j in 0..ny - 1 {
        for i in 0..nx - 1 {
            let a = j * nx + i;
            let (b, c, d) = (a + 1, a + nx, a + nx + 1);
            if (i + j) % 2 == 0 {
                triangles.push([a, b, d]);
                triangles.push([a, d, c]);
            } else {
                triangles.push([a, b, c]);
                triangles.push([b, d, c]);
            }
        }
    }
    RectangleMesh {
        points,
        triangles,
        nx,
        ny,
    }
}

impl RectangleMesh {
    /// The nodes folded along x like an accordion into pleats `cells` cells
    /// wide, stacked `gap` apart in z (the crumpled cloth of the collision
    /// tests and benchmark: every node has the pleats beside it `gap` away).
    pub fn pleated(&self, cells: usize, gap: f64) -> Vec<f64> {
        let h = self.points[3] - self.points[0];
        let mut x = self.points.clone();
        for k in 0..self.nx * self.ny {
            let u = k % self.nx;
            let (pleat, s) = (u / cells, (u % cells) as f64 * h);
            x[3 * k] = if pleat % 2 == 0 {
                s
            } else {
                cells as f64 * h - s
            };
            x[3 * k + 2] = pleat as f64 * gap;
        }
        x
    }
}
